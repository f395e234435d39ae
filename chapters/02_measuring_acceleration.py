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
# To learn friction from experiments we need it as a signal.  The rigid joint of paper
# Eq. (2), $I\,\ddot q = T_m - T_{at}$, gives it as
#
# <a id="eq-experimental-friction"></a>
#
# $$ T_{at} = T_m - I\,\hat\alpha, $$
#
# with $T_m$ the motor torque [N m] (known: it is what the controller commands), $I$ the
# inertia [kg m²] (known), and $\hat\alpha$ [rad/s²] our estimate of the acceleration
# $\ddot q$: friction is as good as that estimate.  But the only sensor is an encoder: a
# position on a grid of counts, sampled at 500 Hz.  Differentiating a staircase twice is
# the problem of this chapter.
#
# The virtual bench gives what a real bench never does: the true velocity,
# acceleration and friction next to the measured encoder signal, so every
# estimator can be scored.

# %% [markdown]
# ## What you will learn
#
# * **Explain** why one encoder count per sample, $\Delta/T_s$, limits what a
#   differentiated encoder can say about the Stribeck region of friction.
# * **Derive** the quantisation error of the backward-difference acceleration,
#   $\Delta/(\sqrt{2}\,T_s^2)$ in RMS, and **measure** it on the simulated record.
# * **Explain** the paper's polynomial-segment estimator as a linear least-squares problem,
#   and check it against an independent fit.
# * **Measure** four velocity and acceleration estimators against the simulator's truth,
#   as velocity, acceleration and friction errors.
# * **Judge** the bias/noise trade-off of an estimator's settings (polynomial degree,
#   filter cut-off).
#
# Symbols and units are collected on the [notation page](../notation).

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
# The encoder sits on the rotor; with $N_e$ counts per rotor revolution [counts/rev] and
# the gear ratio $n$ [-], one count on the load side is $\Delta = 2\pi/(N_e\,n)$ [rad], and
# the reading at $t_k = k\,T_s$ (sample time $T_s$ [s]) is the position rounded down to
# the grid, $y_k = \Delta\lfloor q(t_k)/\Delta \rfloor$.  The controller's velocity is the
# backward difference
#
# <a id="eq-backward-difference"></a>
#
# $$ \hat\omega_k = \frac{y_k - y_{k-1}}{T_s}, $$
#
# so its smallest non-zero value is one count per sample, $\Delta/T_s$ [rad/s].  Compare it
# with the Stribeck velocity $v_s$ [rad/s], the speed range over which friction changes most.

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
# [`fricctl.estimation`](#fricctl.estimation):
#
# * **backward difference** ([`backward_difference`](#fricctl.estimation.backward_difference)),
#   twice: what the controller has, noisy and lagging,
#   $\hat\alpha_k = (\hat\omega_k - \hat\omega_{k-1})/T_s = (y_k - 2y_{k-1} + y_{k-2})/T_s^2$;
# * **polynomial segments** ([`polynomial_segments`](#fricctl.estimation.polynomial_segments)),
#   the paper's method: cut the record where the raw
#   velocity is non-zero, fit each moving segment with a 6th-order least-squares
#   polynomial in time, differentiate the polynomial analytically (written out below);
# * **Savitzky-Golay** ([`savitzky_golay`](#fricctl.estimation.savitzky_golay)): a local
#   polynomial in a sliding window;
# * **Butterworth + central differences**
#   ([`butterworth_central`](#fricctl.estimation.butterworth_central)): zero-phase low-pass,
#   then differences (the recipe of the EMPS benchmark used in
#   [Chapter 3](03_identifying_friction)).
#
# The last three are non-causal: they use future samples.  That is fine for
# building a training set offline, not inside the control loop.
#
# **The paper's fit.**  On a moving segment, take a window $W$ of at most 200 samples
# (0.4 s); longer segments are covered by windows overlapping by 100 samples, blended with
# triangular weights that trust each window's centre most.  In each window, fit the
# backward differences (each one the mean velocity over its interval, so it belongs to the
# interval's middle $\tau_k = t_k - T_s/2$) by a polynomial of degree 6:
#
# $$ \hat c = \arg\min_{c \in \mathbb{R}^7} \sum_{k \in W}
#    \Big(\hat\omega_k - \sum_{j=0}^{6} c_j\,\tau_k^{\,j}\Big)^2, \qquad
#    p(t) = \sum_{j=0}^{6} \hat c_j\,t^j, $$
#
# a linear least-squares problem in the seven coefficients.  Then $\hat\omega(t_k) =
# p(t_k)$ and $\hat\alpha(t_k) = p'(t_k)$: the fit's velocity and, equivalently, the
# second derivative of the position polynomial $y_0 + \int p\,dt$.  (The mid-interval
# times are fricctl's choice; the paper does not say.)  The check below refits one whole
# segment with numpy's own polynomial least squares.

# %%
def all_four(tt, yy):
    """The four estimators, in this order."""
    return [estimation.backward_difference(tt, yy),
            estimation.polynomial_segments(tt, yy, order=6, window=200, overlap=100),
            estimation.savitzky_golay(tt, yy, window_length=31, polyorder=3),
            estimation.butterworth_central(tt, yy, cutoff=20.0)]


t, y = sim.t, sim.q_meas
estimates = all_four(t, y)
# one whole segment as one window (window longer than any segment), refitted independently
assert np.isclose(200 * p.sample_time, 0.4)  # the paper's window: 200 samples = 0.4 s
one = estimation.polynomial_segments(t, y, order=6, window=t.size, overlap=0)
raw = np.diff(y) / p.sample_time  # backward differences of samples 1..N-1
seg_start, seg_stop = (int(i) for i in np.flatnonzero(np.diff(np.r_[False, raw != 0.0, False]))[2:4])
k = np.arange(seg_start, seg_stop) + 1  # sample indices of that segment's differences
tau = t[k] - p.sample_time / 2
c = np.polynomial.polynomial.polyfit(tau - tau.mean(), raw[k - 1], 6)  # centred: well conditioned
p_vel = np.polynomial.polynomial.polyval(t[k] - tau.mean(), c)
p_acc = np.polynomial.polynomial.polyval(t[k] - tau.mean(), np.polynomial.polynomial.polyder(c))
print(f"segment of {k.size} samples refitted by numpy: largest difference "
      f"{np.abs(one.velocity[k] - p_vel).max():.1e} rad/s, {np.abs(one.acceleration[k] - p_acc).max():.1e} rad/s^2")
assert np.allclose(one.velocity[k], p_vel, rtol=0, atol=1e-9 * np.abs(p_vel).max())
assert np.allclose(one.acceleration[k], p_acc, rtol=0, atol=1e-7 * np.abs(p_acc).max())

# %% [markdown]
# ## 4. Evaluate against the truth
#
# Score each estimator on the samples where the joint moves (at rest the friction
# is a reaction, not a function of velocity, and carries no information), leaving
# out a few samples at each end.  The friction error is that of the inverse model
# `Tm - I a_hat` against the simulator's true friction.

# %%
def score(p_run, sim_run, est):
    """RMS errors of one estimate on the moving samples: [velocity, acceleration, friction]."""
    keep = np.zeros(sim_run.t.size, dtype=bool)
    keep[BORDER:-BORDER] = True
    keep &= ~sim_run.stuck
    e_w = est.velocity[keep] - sim_run.omega[keep]
    e_a = est.acceleration[keep] - sim_run.accel[keep]
    e_f = sim_run.torque_motor[keep] - p_run.total_inertia * est.acceleration[keep] - sim_run.friction[keep]
    return np.array([np.sqrt(np.mean(e ** 2)) for e in (e_w, e_a, e_f)])


inner = np.zeros(t.size, dtype=bool)
inner[BORDER:-BORDER] = True
moving = inner & ~sim.stuck
friction_true = sim.friction[moving]
print(f"{'estimator':22s} {'velocity':>14s} {'acceleration':>16s} {'friction':>12s}")
print(f"{'(RMS error)':22s} {'[rad/s]':>14s} {'[rad/s^2]':>16s} {'[N*m]':>12s}")
scores = {}
for est in estimates:
    scores[est.method] = score(p, sim, est)
    print(f"{est.method:22s} {scores[est.method][0]:14.5f} {scores[est.method][1]:16.4f} "
          f"{scores[est.method][2]:12.5f}")
print(f"RMS of the true friction itself: {np.sqrt(np.mean(friction_true ** 2)):.4f} N*m")
best = {k: min(scores, key=lambda m: scores[m][k]) for k in range(3)}
print(f"most accurate: velocity {best[0]}, acceleration {best[1]}, friction {best[2]}")
assert set(best.values()) == {"polynomial_segments"}  # the paper's method wins all three here

# %% [markdown]
# Why the raw acceleration is so poor: the reading is $y_k = q(t_k) - e_k$ with a
# quantisation error $0 \le e_k < \Delta$, so the backward-difference acceleration carries
# $(e_k - 2e_{k-1} + e_{k-2})/T_s^2$.  While the joint crosses several counts per sample the
# $e_k$ behave like independent uniform errors (standard deviation $\Delta/\sqrt{12}$), and
# this term has the RMS value
#
# <a id="eq-quantisation-noise"></a>
#
# $$ \sqrt{1 + 4 + 1}\;\frac{\Delta}{\sqrt{12}\,T_s^2} = \frac{\Delta}{\sqrt{2}\,T_s^2}, $$
#
# of the order of $\Delta/T_s^2$: a single count divided by a very small $T_s^2$.  The
# prediction of [the RMS value](#eq-quantisation-noise), against the table's first row (within 25 %):

# %%
quant = res / (np.sqrt(2) * p.sample_time ** 2)
print(f"Delta/(sqrt(2) Ts^2) = {quant:.2f} rad/s^2 (Delta/Ts^2 = {res / p.sample_time ** 2:.2f}); "
      f"backward difference: {scores['backward_difference'][1]:.2f} rad/s^2; as friction "
      f"I * {quant:.2f} = {p.total_inertia * quant:.4f} N*m against {scores['backward_difference'][2]:.4f} N*m")
assert 0.8 < scores["backward_difference"][1] / quant < 1.25
assert 0.8 < scores["backward_difference"][2] / (p.total_inertia * quant) < 1.25

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

# %% mystnb={"figure": {"caption": "The paper's Fig. 4 on the load side, zoomed on the first reversal: the raw backward-difference velocity $\\hat\\omega$ (grey steps) moves in whole counts per sample, $\\Delta/T_s$, against the true velocity $\\omega$ (dashed) and the three smooth, non-causal filtered estimates."}}
ax = figures.plot_velocity_estimates(estimates[1:], raw=estimates[0], truth=(t, sim.omega))
t_stop = sim.stuck_intervals(min_duration=0.01)[1][0]  # first reversal after the start
ax.set_xlim(t_stop - 0.05, t_stop + 0.15)
ax.set_ylim(-0.6, 0.6)
plt.show()

# %% [markdown]
# And the "experimental friction" `Tm - I a_hat` of the paper's estimator against
# velocity, with the true friction law: this cloud is what Chapters 3 and
# [4](04_neural_network) learn from.

# %% mystnb={"figure": {"caption": "The experimental friction $T_m - I \\hat\\alpha$ of the polynomial segments against their velocity estimate, on the moving samples, with the true friction law $T_{at}(\\omega)$: the cloud that Chapters 3 and 4 learn from."}}
poly = estimates[1]
fig, ax = plt.subplots(figsize=(6.4, 3.6), layout="constrained")
ax.plot(poly.velocity[moving], sim.torque_motor[moving] - p.total_inertia * poly.acceleration[moving],
        ".", ms=2, label=r"$T_m - I\hat\alpha$ (polynomial segments)")
w = np.linspace(-np.abs(sim.omega).max(), np.abs(sim.omega).max(), 400)
w = w[w != 0.0]
ax.plot(w, p.friction_model().torque(w), "k", lw=1, label="true friction law")
ax.set_xlabel(r"velocity $\omega$ [rad/s]")
ax.set_ylabel(r"friction $T_{at}$ [N*m]")
ax.legend(fontsize="small")
plt.show()

# %% [markdown]
# ## Summary
#
# * One encoder count per sample, $\Delta/T_s$, is of the same order as the Stribeck
#   velocity: the raw velocity cannot resolve the region where friction drops from its
#   static to its Coulomb level.
# * The backward-difference acceleration carries the encoder's quantisation divided by
#   $T_s^2$; its RMS error is predicted by $\Delta/(\sqrt{2}\,T_s^2)$ (and, as friction,
#   $I$ times that), which the simulated record confirmed.
# * The paper's estimator fits a degree-6 polynomial by linear least squares to the
#   backward differences of each moving segment, in overlapping windows; an independent
#   numpy fit of one segment gave the same velocity and acceleration.
# * Scored against the simulator's truth on the moving samples, the polynomial segments
#   were the most accurate on velocity, acceleration and friction: each segment runs from
#   one stop to the next, where the other filters smear the stop over their window.
# * Savitzky-Golay, Butterworth and the polynomial segments are non-causal: they build a
#   training set offline, not a velocity for the control loop.
# * The exercises show the backward difference degrading with a coarser encoder roughly in
#   proportion to $\Delta$, a flat optimum of the polynomial degree against a sharp one of the
#   Butterworth cut-off, and torque noise that reaches the joint but not the record.

# %% [markdown]
# ## Exercises
#
# 1. Change the encoder to 500 counts per rotor revolution
#    (`p = `[`paper_actuator`](#fricctl.params.paper_actuator)`(encoder_counts=500)`) and rerun the table.  Which
#    estimator degrades most, and why does the backward-difference acceleration
#    get so much worse?
# 2. Vary `order` of `polynomial_segments` (2, 4, 6, 8) and the `cutoff` of
#    `butterworth_central` (5 to 100 Hz).  Plot the friction RMS error against
#    each setting: where is the bias/noise trade-off?
# 3. Add white torque noise to the experiment
#    ([`simulate`](#fricctl.simulate.simulate)`(..., noise_std=0.005, rng=np.random.default_rng(0))`).  Note that
#    `torque_motor` is the *commanded* torque: the noise reaches the joint but not
#    the record.  How does that show up in the friction error?


# %% tags=["solution"]
# Exercise 1.  Four times coarser counts: Delta x4.  The quantisation term of the raw
# acceleration scales with Delta (Delta/(sqrt(2) Ts^2)), so the backward difference should
# get about 4 times worse; the filters average the quantisation out and barely move.
p500 = paper_actuator(encoder_counts=500)
sim500 = simulate(p500, ctl.open_loop(ctl.sinusoid(TORQUE_AMPLITUDE, TORQUE_FREQUENCY)),
                  duration=DURATION)
ratio = {}
print(f"{'estimator':22s} {'friction RMS, 2000 counts':>26s} {'500 counts':>11s} {'ratio':>6s}")
for est2000, est500 in zip(estimates, all_four(sim500.t, sim500.q_meas)):
    s500 = score(p500, sim500, est500)
    ratio[est2000.method] = s500[2] / scores[est2000.method][2]
    print(f"{est2000.method:22s} {scores[est2000.method][2]:26.5f} {s500[2]:11.5f} "
          f"{ratio[est2000.method]:6.2f}")
    if est500.method == "backward_difference":
        quant500 = p500.encoder_resolution / (np.sqrt(2) * p500.sample_time ** 2)
        print(f"  raw acceleration error {s500[1]:.2f} rad/s^2, Delta/(sqrt(2) Ts^2) = {quant500:.2f}")
        assert 0.8 < s500[1] / quant500 < 1.25
assert max(ratio, key=ratio.get) == "backward_difference" and 3.0 < ratio["backward_difference"] < 4.5
assert ratio["savitzky_golay"] < 1.1 and ratio["butterworth_central"] < 1.1

# %% tags=["solution"] mystnb={"figure": {"caption": "Exercise 2: the friction RMS error against the polynomial degree (left) and the Butterworth cut-off (right).  Too low a setting cannot follow the motion, too high a one follows the encoder's staircase; the degree's optimum is flat, and the best cut-off stays above the best polynomial."}}
# Exercise 2.  Friction RMS error against the polynomial degree and the Butterworth cut-off.
# Too low a degree or cut-off cannot follow the motion (bias); too high a one follows the
# encoder's staircase (quantisation noise).  The sweep goes past 100 Hz to show the noise side.
orders = (2, 4, 6, 8, 10, 12)
cutoffs = (5.0, 10.0, 20.0, 50.0, 100.0, 150.0, 200.0)
e_order = np.array([score(p, sim, estimation.polynomial_segments(t, y, order=o))[2] for o in orders])
e_cut = np.array([score(p, sim, estimation.butterworth_central(t, y, cutoff=fc))[2] for fc in cutoffs])
for o, e in zip(orders, e_order):
    print(f"polynomial degree {o:2d}: friction RMS {e:.5f} N*m")
for fc, e in zip(cutoffs, e_cut):
    print(f"Butterworth {fc:5.0f} Hz:  friction RMS {e:.5f} N*m")
fig, (ax1, ax2) = plt.subplots(1, 2, sharey=True, figsize=(8.0, 3.2), layout="constrained")
ax1.semilogy(orders, e_order, "o-")
ax1.set_xlabel("polynomial degree [-]")
ax1.set_ylabel("friction RMS error [N*m]")
ax2.loglog(cutoffs, e_cut, "o-")
ax2.set_xlabel("Butterworth cut-off [Hz]")
plt.show()
i_o, i_c = int(np.argmin(e_order)), int(np.argmin(e_cut))
print(f"best: degree {orders[i_o]}, cut-off {cutoffs[i_c]:.0f} Hz")
assert e_order[0] > 10 * e_order.min() and e_order[-1] > e_order.min()  # bias at 2, noise at 12
assert 0 < i_c < len(cutoffs) - 1 and e_cut[0] > 3 * e_cut.min()        # a minimum inside the sweep
assert e_order[1:4].max() < 1.05 * e_order.min() and 50.0 <= cutoffs[i_c] <= 150.0
assert e_order.min() < e_cut.min()  # the best cut-off still loses to the paper's polynomials
# The polynomial's optimum is flat (degrees 4-8 within a few per cent): one polynomial per
# stop-to-stop segment is already the right shape.  The Butterworth filter's optimum is sharp
# and sits near 100 Hz; below it the filter rounds off the stops (bias), above it lets the
# counts through (noise) -- and even there it stays above the polynomial fit.

# %% tags=["solution"]
# Exercise 3.  The noise reaches the joint but not the record: the true acceleration gets a
# part n/I that the recorded Tm does not explain.  An estimator that saw the true acceleration
# would be off by exactly the noise, Tm - I*accel - Tat = -n.  The encoder barely sees it
# (n*Ts/I per sample is below one count per sample), so the estimators miss it -- and by
# missing it they keep Tm - I*alpha_hat close to the friction.
NOISE = 0.005  # [N*m]
print(f"velocity change per sample from the noise, NOISE*Ts/I = "
      f"{NOISE * p.sample_time / p.total_inertia:.4f} rad/s; one count per sample: "
      f"{res / p.sample_time:.4f} rad/s")
for seed in (0, 1, 2):
    noisy = simulate(p, ctl.open_loop(ctl.sinusoid(TORQUE_AMPLITUDE, TORQUE_FREQUENCY)),
                     duration=DURATION, noise_std=NOISE, rng=np.random.default_rng(seed))
    keep = np.zeros(noisy.t.size, dtype=bool)
    keep[BORDER:-BORDER] = True
    keep &= ~noisy.stuck
    perfect = noisy.torque_motor[keep] - p.total_inertia * noisy.accel[keep] - noisy.friction[keep]
    s_poly = score(p, noisy, estimation.polynomial_segments(noisy.t, noisy.q_meas))
    print(f"seed {seed}: with the TRUE acceleration the friction error is {np.sqrt(np.mean(perfect ** 2)):.4f} "
          f"N*m (the noise); polynomial segments: acceleration {s_poly[1]:.3f} rad/s^2 "
          f"(noise-free {scores['polynomial_segments'][1]:.3f}), friction {s_poly[2]:.5f} N*m "
          f"(noise-free {scores['polynomial_segments'][2]:.5f})")
    assert 0.8 * NOISE < np.sqrt(np.mean(perfect ** 2)) < 1.2 * NOISE
    assert s_poly[1] > 2 * scores["polynomial_segments"][1]  # further from the true acceleration
    assert s_poly[2] < 0.5 * NOISE                               # ...but not from the friction

# %% [markdown]
# ## References
#
# * [Gervini, Gomes & da Rosa 2003](#gervini2003): Section 4 and Fig. 4, the polynomial
#   velocity estimate.
# * [Savitzky & Golay 1964](#savitzky1964): the Savitzky-Golay filter.
# * [Janot, Gautier & Brunot 2019 (EMPS)](#janot2019emps): the Butterworth and
#   central-difference recipe.
#
# In fricctl: [`backward_difference`](#fricctl.estimation.backward_difference),
# [`polynomial_segments`](#fricctl.estimation.polynomial_segments),
# [`savitzky_golay`](#fricctl.estimation.savitzky_golay),
# [`butterworth_central`](#fricctl.estimation.butterworth_central) and their
# [`DerivativeEstimate`](#fricctl.estimation.DerivativeEstimate),
# [`paper_actuator`](#fricctl.params.paper_actuator), [`simulate`](#fricctl.simulate.simulate),
# [`open_loop`](#fricctl.controllers.open_loop), [`sinusoid`](#fricctl.controllers.sinusoid),
# [`plot_velocity_estimates`](#fricctl.figures.plot_velocity_estimates).
