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
# # Chapter 1 -- The actuator and stick-slip
#
# *Gervini, Gomes & da Rosa (2003), Sections 2-3, Eqs. (1)-(2).*
#
# A harmonic-drive joint is a motor, a gear with a very high ratio and a flexible
# cup (the flexspline) between them.  It is compact and has no backlash, but its
# friction is large: a sizeable part of the motor's torque is spent just getting
# the joint to move.  This chapter builds the model every later chapter uses and
# shows the two behaviours that make friction hard for a position controller:
#
# * **stick**: below the breakaway torque the joint does not move *at all*;
# * **stick-slip**: a loop that should track a slow ramp instead alternates
#   between sticking and jumping.
#
# All quantities are on the load side of the gear, in SI units.  Friction has the
# sign of the velocity and enters the rigid joint of paper Eq. (2) as
#
# $$ I\,\ddot q = T_m - T_{at}, \qquad \dot q\,T_{at} \ge 0, $$
#
# with $q$ the joint position [rad], $I$ the inertia of motor, gear and link
# [kg m²], $T_m$ the motor torque [N m] and $T_{at}$ the friction torque [N m]:
# friction only ever takes energy out of the joint.

# %%
import os
import sys

import matplotlib.pyplot as plt
import numpy as np

from fricctl import controllers as ctl
from fricctl.design import design_p, design_pd
from fricctl.figures import plot_response
from fricctl.friction import Coulomb, Stribeck, Viscous
from fricctl.params import PAPER_STATIC_FRACTION, paper_actuator
from fricctl.plant import FlexibleJoint, RigidJoint
from fricctl.simulate import simulate

FAST = os.environ.get("FRICCTL_FAST") == "1"
RAMP_DURATION = 6.0 if FAST else 12.0  # length of the stick-slip experiment [s]

# %% [markdown]
# ## 1. The model: the paper's actuator
#
# `paper_actuator()` collects the actuator's parameters.  Each field records its
# unit and its provenance: `paper` (a value the paper gives), `derived`
# (computed from paper values) or `assumption` (a plausible value the paper does
# not give).  Keep an eye on the provenance column: a conclusion that depends on an
# assumed value is only as good as that assumption.

# %%
p = paper_actuator()
for name, value in p.as_dict().items():
    print(f"{name:18s} {value:12.6g}  [{p.unit(name)}]  ({p.source(name)})")
print(f"\nmaximum torque {p.max_torque:.4f} N*m; static friction is "
      f"{100 * p.static / p.max_torque:.1f} % of it (paper: {100 * PAPER_STATIC_FRACTION:.1f} %)")

# %% [markdown]
# ## 2. Friction laws
#
# The nominal friction is the sum of three laws from `fricctl.friction`:
#
# * viscous `b*w`, proportional to velocity;
# * Coulomb `Fc*sign(w)`, a constant level whenever the joint slides;
# * Stribeck: extra friction near zero speed that decays to the Coulomb level, so
#   breaking loose takes more torque (`Fs`) than keeping moving (`Fc`).
#
# At `w = 0` friction is *not* a function of velocity: it is whatever reaction
# keeps the joint at rest, anywhere in `[-Fs, +Fs]`.  The curve below therefore
# leaves out the point `w = 0`.

# %%
law = p.friction_model()
print(law)
print(f"breakaway +{law.breakaway(+1):.4f} / -{law.breakaway(-1):.4f} N*m, "
      f"sliding level at high speed {law.sliding_level(+1):.4f} N*m")

w = np.linspace(-0.3, 0.3, 601)
w = w[w != 0.0]
fig, ax = plt.subplots(figsize=(6.4, 3.6), layout="constrained")
for name, part in (("viscous", Viscous(p.viscous).model()),
                   ("viscous + Coulomb", Viscous(p.viscous) + Coulomb(p.coulomb)),
                   ("viscous + Coulomb + Stribeck", law)):
    ax.plot(w, part.torque(w), label=name)
ax.set_xlabel(r"velocity $\omega$ [rad/s]")
ax.set_ylabel(r"friction $T_{at}$ [N*m]")
ax.legend(fontsize="small")
plt.show()

# %% [markdown]
# ## 3. Experiment: exact stick
#
# Apply a constant open-loop torque just below and just above the breakaway level
# and watch the position.  The simulator treats sticking as an event, not as a
# very steep friction curve, so below breakaway the joint is at rest *exactly*:
# not creeping slowly, not moving by a tiny amount.

# %%
below = simulate(p, ctl.open_loop(ctl.constant(0.999 * p.static)), duration=1.0)
above = simulate(p, ctl.open_loop(ctl.constant(1.01 * p.static)), duration=1.0)
print(f"0.1 % below breakaway: max |q| = {np.abs(below.q).max():.3g} rad, "
      f"stuck at every sample: {bool(below.stuck.all())}")
print(f"1 % above breakaway:   q(1 s) = {above.q[-1]:.4f} rad, "
      f"{above.displacement_counts()} encoder counts")
assert np.all(below.q == 0.0) and below.stuck.all()  # the joint does not move at all
assert above.q[-1] > 0.0 and not above.stuck[-1]      # ...and breaks loose just above

# %% [markdown]
# ## 4. Design and simulate: a P loop stuck inside its dead band
#
# Now close a proportional loop `Tc = Kp (r - q)` with the paper's P gain (rise
# time 0.2 s, damping 0.3, designed on the linear viscous model; Chapter 6 explains
# the design).  Once the joint stops, it stays stuck as long as the controller's
# torque $K_p\,|r - q|$ is below the breakaway level $F_s$ [N m].  Every error
# inside the band
#
# $$ |e| = |r - q| \le \frac{F_s}{K_p} $$
#
# is an equilibrium: a **dead band** of the position loop, and the smaller the
# gain $K_p$ [N m/rad], the wider it is.

# %%
d_p = design_p(p, rise_time=0.2, damping=0.3)
band = p.static / d_p.kp
print(f"Kp = {d_p.kp:.4f} N*m/rad -> dead band +-Fs/Kp = {band:.4f} rad "
      f"({np.rad2deg(band):.1f} deg)")
for step_deg in (25.0, 60.0):
    run = simulate(p, ctl.p_control(d_p.kp, ctl.step(np.deg2rad(step_deg))), duration=3.0)
    e_ss = run.steady_state_error()
    print(f"step {step_deg:4.0f} deg: final position {np.rad2deg(run.q[-1]):6.2f} deg, "
          f"steady-state error {np.rad2deg(e_ss):6.2f} deg, stuck at the end: {bool(run.stuck[-1])}")
    # stuck with the error inside the band (one encoder count of slack: the loop sees q_meas)
    assert run.stuck[-1] and abs(e_ss) <= band + p.encoder_resolution
    if step_deg * d_p.kp * np.pi / 180.0 < p.static:
        assert np.all(run.q == 0.0)  # Kp*r below breakaway: the joint never starts
    else:
        assert 0.0 < run.q.max() < run.reference[-1]  # moves, then freezes short of r

# %% [markdown]
# The smaller step never starts: its initial torque `Kp * r` is already below the
# breakaway level.  The larger one moves, but freezes short of the reference, where
# its velocity first reaches zero inside the band.  The linear model the gain was
# designed on predicts an overshoot instead (Chapter 6).
#
# The band shrinks as $1/K_p$, but where inside it the joint stops depends on how
# it arrives.  In Jupyter, move the gain with the slider below (it needs
# `ipywidgets`); the book, and a run as a script, show the paper's gain and three
# times that gain side by side instead.

# %%
def dead_band_step(kp, ax=None, step_deg=60.0):
    """The P loop's step of `step_deg` [deg] with gain `kp` [N*m/rad], its band r +- Fs/kp shaded."""
    run = simulate(p, ctl.p_control(kp, ctl.step(np.deg2rad(step_deg))), duration=3.0)
    ax = plot_response(run, ax=ax)
    half = np.rad2deg(p.static / kp)
    ax.axhspan(step_deg - half, step_deg + half, color="tab:orange", alpha=0.15, lw=0,
               label="dead band r +- Fs/Kp")
    ax.set_title(f"Kp = {kp:.3f} N*m/rad", fontsize="medium")
    ax.legend(fontsize="small")
    return run


# %% tags=["widget"]
if "ipykernel" in sys.modules:  # in Jupyter: a slider; the book shows the figure below instead
    from ipywidgets import FloatSlider, interact

    def show_dead_band(kp):
        dead_band_step(kp)
        plt.show()

    interact(show_dead_band, kp=FloatSlider(value=d_p.kp, min=0.1, max=1.5, step=0.05,
                                            description="Kp [N*m/rad]"))

# %% mystnb={"figure": {"caption": "The 60 deg step at the paper's gain and at three times that gain: each run stops inside its own band r +- Fs/Kp (shaded).", "name": "fig-dead-band"}}
fig, axes = plt.subplots(1, 2, sharey=True, figsize=(9.6, 3.6), layout="constrained")
for kp, ax in zip((d_p.kp, 3 * d_p.kp), axes):
    run = dead_band_step(kp, ax=ax)
    e_ss = run.steady_state_error()
    print(f"Kp = {kp:.4f} N*m/rad: band +-{np.rad2deg(p.static / kp):.2f} deg, "
          f"steady-state error {np.rad2deg(e_ss):.2f} deg")
    assert run.stuck[-1] and abs(e_ss) <= p.static / kp + p.encoder_resolution  # inside its band
plt.show()

# %% [markdown]
# ## 5. Stick-slip under a slow ramp
#
# Ask the same P loop to follow a slow ramp.  While the joint sticks, the error
# grows with the ramp until `Kp e` reaches the breakaway level; the joint breaks
# loose, friction drops to the lower sliding level (Stribeck), the joint jumps
# forward and closes part of the error, loses speed as `Kp e` falls, and sticks
# again.  The position advances in jumps rather than smoothly.

# %%
slope = 0.2  # ramp speed [rad/s]
ramp = simulate(p, ctl.p_control(d_p.kp, ctl.sawtooth(slope * 100.0, 100.0)),
                duration=RAMP_DURATION)
stuck = ramp.stuck_intervals(min_duration=0.01)
print(f"ramp {slope} rad/s for {RAMP_DURATION} s: {len(stuck)} stuck intervals "
      f"(the first one is the start-up)")
for t_a, t_b in stuck:
    e_a, e_b = ramp.error[np.searchsorted(ramp.t, [t_a, t_b])]
    print(f"  stuck from {t_a:6.3f} s to {t_b:6.3f} s ({t_b - t_a:.3f} s): "
          f"error {e_a:.4f} rad when it sticks, {e_b:.4f} rad (Kp e = {d_p.kp * e_b:.4f} N*m) "
          f"when it breaks loose")
print(f"fraction of the time at rest: {100 * ramp.stuck.mean():.1f} %")
assert len(stuck) >= 3  # start-up plus at least two stick phases while tracking

fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(6.4, 5.0), layout="constrained")
ax1.plot(ramp.t, ramp.reference, "k--", lw=1, label="reference r")
ax1.plot(ramp.t, ramp.q, label="position q")
for t_a, t_b in stuck:
    ax1.axvspan(t_a, t_b, color="0.9", lw=0)
ax1.set_ylabel("angle [rad]")
ax1.legend(fontsize="small")
ax2.plot(ramp.t, ramp.torque_motor, drawstyle="steps-post", label="motor torque Tm")
ax2.plot(ramp.t, ramp.friction, lw=1, label="friction Tat")
ax2.set_xlabel("time t [s]")
ax2.set_ylabel("torque [N*m]")
ax2.legend(fontsize="small")
plt.show()

# %% [markdown]
# ## 6. Rigid or flexible joint?
#
# Paper Eq. (1) models the flexspline as a spring `K` (with a little damping)
# between the motor inertia and the link; Eq. (2) lumps both into one rigid
# inertia.  The simulator has both (`plant="rigid"` or `plant="flexible"`).  Run the
# same PD step with the SCARA link attached, on both plants, and compare.

# %%
p_link = p.with_link()
d_pd = design_pd(p_link, rise_time=0.4, damping=0.85)
runs = {kind: simulate(p_link, ctl.pd_control(d_pd.kp, d_pd.kd, ctl.step(np.deg2rad(30.0))),
                       duration=2.0, plant=kind)
        for kind in ("rigid", "flexible")}
flex = FlexibleJoint.from_params(p_link)
print(f"flexible joint: K = {flex.stiffness:g} N*m/rad, resonance {flex.resonance:.0f} rad/s "
      f"({flex.resonance / (2 * np.pi):.0f} Hz); rigid inertia "
      f"{RigidJoint.from_params(p_link).inertia:.5f} kg*m^2")
for kind, run in runs.items():
    print(f"{kind:8s}: steady-state error {np.rad2deg(run.steady_state_error()):.3f} deg, "
          f"max twist |q - q_load| {np.rad2deg(np.abs(run.q - run.q_load).max()):.4f} deg")
gap = np.abs(runs["rigid"].q - runs["flexible"].q).max()
print(f"largest difference between the two motor positions: {np.rad2deg(gap):.4f} deg")
print(f"closed-loop natural frequency of the PD design: {d_pd.wn:.1f} rad/s")
twist = np.abs(runs["flexible"].q - runs["flexible"].q_load).max()
assert twist < 0.01 * abs(runs["flexible"].steady_state_error())  # twist << friction error
assert flex.resonance > 10 * d_pd.wn  # resonance well above the loop's bandwidth

# %% [markdown]
# With the assumed stiffness the twist stays far below the steady-state error that
# friction leaves, and the resonance lies far above the loop's bandwidth: for these
# controllers the rigid model of Eq. (2) is enough, which is also the paper's
# choice.  That conclusion rests on `stiffness`, an *assumption* (see the table
# in Section 1): Exercise 3 asks when it breaks down.

# %% [markdown]
# ## Exercises
#
# 1. Repeat the exact-stick experiment with `p.friction_model().scaled(1.1)`
#    passed as `friction=` to `simulate` (a worn, stiffer joint).  Which of the two
#    constant torques still moves the joint?  Predict first, then run it.
# 2. Replace the ramp slope by 0.05 and 0.5 rad/s.  How do the number and length
#    of the stuck intervals change, and why does a fast enough ramp remove
#    stick-slip after the start-up?
# 3. Lower the stiffness with `p_link.replace(stiffness=...)` until the flexible
#    and rigid runs visibly differ.  Compare the resonance
#    (`FlexibleJoint.from_params(...).resonance`) with the Nyquist frequency
#    `pi / p.sample_time` of the 500 Hz loop.

# %% tags=["solution"]
# Exercise 1.  Friction x1.1 raises the breakaway level to 1.1 Fs: both torques,
# 0.999 Fs and 1.01 Fs, are now below it, so neither moves the joint.
worn = p.friction_model().scaled(1.1)
print(f"breakaway of the worn joint: {worn.breakaway(+1):.4f} N*m (was {p.static:.4f} N*m)")
for frac in (0.999, 1.01):
    run = simulate(p, ctl.open_loop(ctl.constant(frac * p.static)), duration=1.0, friction=worn)
    print(f"{frac:.3f} Fs = {frac * p.static:.4f} N*m: max |q| = {np.abs(run.q).max():.3g} rad, "
          f"stuck at every sample: {bool(run.stuck.all())}")
    assert np.all(run.q == 0.0) and run.stuck.all()  # below the worn breakaway: no motion at all
