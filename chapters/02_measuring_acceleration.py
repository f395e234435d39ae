# ---
# jupyter:
#   jupytext:
#     formats: py:percent
#     text_representation:
#       extension: .py
#       format_name: percent
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # Chapter 2 -- Measuring velocity and acceleration
#
# *Gervini, Gomes & da Rosa (2003), Section 4 and Fig. 4.*
#
# To learn friction from experiments we need it as a signal.  The joint's equation
# `I q'' = Tm - Tat` gives it as `Tat = Tm - I q''`: the motor torque is known (it is
# what the controller commands), the inertia is known, so friction is as good as
# our estimate of the **acceleration**.  But the only sensor is an encoder: a
# position on a grid of counts, sampled at 500 Hz.  Differentiating a staircase
# twice is the problem of this chapter.
#
# The virtual bench gives what a real bench never does: the true velocity,
# acceleration and friction next to the measured encoder signal, so every
# estimator can be scored.

# %%
import os

import matplotlib.pyplot as plt
import numpy as np

from fricctl import controllers as ctl
from fricctl import estimation, figures
from fricctl.params import paper_actuator
from fricctl.simulate import simulate

FAST = os.environ.get("FRICCTL_FAST") == "1"
DURATION = 2.0 if FAST else 4.0   # length of the experiment [s]
TORQUE_AMPLITUDE = 0.3            # open-loop sinusoidal torque [N*m]
TORQUE_FREQUENCY = 1.0            # [Hz]
BORDER = 25                       # samples ignored at each end when scoring [-]

# %% [markdown]
# ## 1. The model: what one encoder count means
#
# The encoder sits on the rotor; one count on the load side is `2 pi / (counts * n)`.
# The controller's velocity is the backward difference `(y_k - y_(k-1)) / Ts`, so
# its smallest non-zero value is one count per sample.  Compare it with the
# Stribeck velocity, the speed range over which friction changes most.

# %%
p = paper_actuator()
res = p.encoder_resolution
print(f"one encoder count on the load side: {res:.3e} rad")
print(f"velocity resolution of the backward difference: {res / p.sample_time:.4f} rad/s")
print(f"Stribeck velocity of the friction model:        {p.stribeck_velocity:.4f} rad/s")
assert res / p.sample_time > 0.5 * p.stribeck_velocity  # same order of magnitude

# %% [markdown]
# The raw velocity cannot resolve the Stribeck region: one count per sample is of
# the same order as the whole velocity range where friction drops from static to
# Coulomb.

# %% [markdown]
# ## 2. Experiment: open-loop sinusoidal torque
#
# A sinusoidal torque whose amplitude is above the breakaway level moves the joint
# back and forth; near each reversal the torque falls below breakaway and the joint
# sticks for a while.  The simulation records the encoder reading `q_meas`
# together with the truth (`omega`, `accel`, `friction`).

# %%
sim = simulate(p, ctl.open_loop(ctl.sinusoid(TORQUE_AMPLITUDE, TORQUE_FREQUENCY)),
               duration=DURATION)
print(f"{sim.t.size} samples; joint moving {100 * (1 - sim.stuck.mean()):.1f} % of the time; "
      f"peak speed {np.abs(sim.omega).max():.3f} rad/s")
raw_levels = np.unique(np.round(np.diff(sim.q_meas) / res))
print(f"backward differences take {raw_levels.size} distinct values, all whole counts per sample")
assert np.allclose(np.diff(sim.q_meas) / res, np.round(np.diff(sim.q_meas) / res), atol=1e-6)

# %% [markdown]
# ## 3. Estimators
#
# Four ways to get velocity and acceleration from `(t, q_meas)`, all in
# `fricctl.estimation`:
#
# * **backward difference**, twice: what the controller has, noisy and lagging;
# * **polynomial segments**, the paper's method: cut the record where the raw
#   velocity is non-zero, fit each moving segment with a 6th-order least-squares
#   polynomial in time, differentiate the polynomial analytically;
# * **Savitzky-Golay**: a local polynomial in a sliding window;
# * **Butterworth + central differences**: zero-phase low-pass, then differences
#   (the recipe of the EMPS benchmark used in Chapter 3).
#
# The last three are non-causal: they use future samples.  That is fine for
# building a training set offline, not inside the control loop.

# %%
t, y = sim.t, sim.q_meas
estimates = [
    estimation.backward_difference(t, y),
    estimation.polynomial_segments(t, y, order=6),
    estimation.savitzky_golay(t, y, window_length=31, polyorder=3),
    estimation.butterworth_central(t, y, cutoff=20.0),
]

# %% [markdown]
# ## 4. Evaluate against the truth
#
# Score each estimator on the samples where the joint moves (at rest the friction
# is a reaction, not a function of velocity, and carries no information), leaving
# out a few samples at each end.  The friction error is that of the inverse model
# `Tm - I a_hat` against the simulator's true friction.

# %%
inner = np.zeros(t.size, dtype=bool)
inner[BORDER:-BORDER] = True
moving = inner & ~sim.stuck
friction_true = sim.friction[moving]
print(f"{'estimator':22s} {'velocity':>14s} {'acceleration':>16s} {'friction':>12s}")
print(f"{'(RMS error)':22s} {'[rad/s]':>14s} {'[rad/s^2]':>16s} {'[N*m]':>12s}")
scores = {}
for est in estimates:
    e_w = est.velocity[moving] - sim.omega[moving]
    e_a = est.acceleration[moving] - sim.accel[moving]
    e_f = (sim.torque_motor[moving] - p.total_inertia * est.acceleration[moving]) - friction_true
    scores[est.method] = [float(np.sqrt(np.mean(e ** 2))) for e in (e_w, e_a, e_f)]
    print(f"{est.method:22s} {scores[est.method][0]:14.5f} {scores[est.method][1]:16.4f} "
          f"{scores[est.method][2]:12.5f}")
print(f"RMS of the true friction itself: {np.sqrt(np.mean(friction_true ** 2)):.4f} N*m")
best = {k: min(scores, key=lambda m: scores[m][k]) for k in range(3)}
print(f"most accurate: velocity {best[0]}, acceleration {best[1]}, friction {best[2]}")
assert set(best.values()) == {"polynomial_segments"}  # the paper's method wins all three here

# %% [markdown]
# On this record the paper's polynomial segments are the most accurate on all
# three counts: each moving segment is a smooth motion between two stops, which a
# low-order polynomial describes well, and the segment boundaries are exactly where
# the other filters smear the stop over their window.
#
# ## 5. Figure 4: raw versus filtered velocity
#
# The paper's Fig. 4 shows the raw rotor velocity against the filtered one.  Here
# on the load side (the rotor velocity is `n` times larger), zoomed on one reversal.

# %%
ax = figures.plot_velocity_estimates(estimates[1:], raw=estimates[0], truth=(t, sim.omega))
t_stop = sim.stuck_intervals(min_duration=0.01)[1][0]  # first reversal after the start
ax.set_xlim(t_stop - 0.05, t_stop + 0.15)
ax.set_ylim(-0.6, 0.6)
plt.show()

# %% [markdown]
# And the "experimental friction" `Tm - I a_hat` of the paper's estimator against
# velocity, with the true friction law: this cloud is what Chapters 3 and 4 learn
# from.

# %%
poly = estimates[1]
fig, ax = plt.subplots(figsize=(6.4, 3.6), layout="constrained")
ax.plot(poly.velocity[moving], sim.torque_motor[moving] - p.total_inertia * poly.acceleration[moving],
        ".", ms=2, label=r"$T_m - I\hat{a}$ (polynomial segments)")
w = np.linspace(-np.abs(sim.omega).max(), np.abs(sim.omega).max(), 400)
w = w[w != 0.0]
ax.plot(w, p.friction_model().torque(w), "k", lw=1, label="true friction law")
ax.set_xlabel(r"velocity $\omega$ [rad/s]")
ax.set_ylabel(r"friction $T_{at}$ [N*m]")
ax.legend(fontsize="small")
plt.show()

# %% [markdown]
# ## Exercises
#
# 1. Change the encoder to 500 counts per rotor revolution
#    (`p = paper_actuator(encoder_counts=500)`) and rerun the table.  Which
#    estimator degrades most, and why does the backward-difference acceleration
#    get so much worse?
# 2. Vary `order` of `polynomial_segments` (2, 4, 6, 8) and the `cutoff` of
#    `butterworth_central` (5 to 100 Hz).  Plot the friction RMS error against
#    each setting: where is the bias/noise trade-off?
# 3. Add white torque noise to the experiment
#    (`simulate(..., noise_std=0.005, rng=np.random.default_rng(0))`).  Note that
#    `torque_motor` is the *commanded* torque: the noise reaches the joint but not
#    the record.  How does that show up in the friction error?
