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
# <a id="eq-motion"></a>
#
# $$ I\,\ddot q = T_m - T_{at}, \qquad \dot q\,T_{at} \ge 0, $$
#
# with $q$ the joint position [rad], $I$ the inertia of motor, gear and link
# [kg m²], $T_m$ the motor torque [N m] and $T_{at}$ the friction torque [N m]:
# friction only ever takes energy out of the joint.

# %% [markdown]
# ## What you will learn
#
# * **Explain** the elastic joint of paper Eq. (1) and the rigid joint of Eq. (2), and
#   say which of the actuator's parameters the paper gives and which are derived or assumed.
# * **Explain** the friction law (viscous, Coulomb, Stribeck) and why, at rest, friction is
#   a reaction anywhere between $-F_s$ and $F_s$ rather than a function of velocity.
# * **Derive** the dead band $|e| \le F_s/K_p$ of a proportional position loop and
#   **measure** it on the simulated joint.
# * **Explain** stick-slip under a slow ramp, and predict how long each stuck interval lasts.
# * **Judge** when the rigid model is enough, from the flexible joint's resonance against
#   the loop's bandwidth and the Nyquist frequency.
#
# Symbols and units are collected on the [notation page](../notation).

# %%
import os
import sys

import matplotlib.pyplot as plt
import numpy as np

from fricctl import controllers as ctl
from fricctl.design import design_p, design_pd
from fricctl.figures import plot_response
from fricctl.friction import Coulomb, Stribeck, Viscous
from fricctl.params import PAPER_LINK_INERTIA, PAPER_STATIC_FRACTION, paper_actuator
from fricctl.plant import FlexibleJoint, RigidJoint
from fricctl.simulate import simulate
from fricctl.units import to_rotor_side

FAST = os.environ.get("FRICCTL_FAST") == "1"
RAMP_DURATION = 6.0 if FAST else 12.0  # length of the stick-slip experiment [s]

# %% [markdown]
# ## 1. The model: the paper's actuator
#
# [`paper_actuator()`](#fricctl.params.paper_actuator) collects the actuator's parameters.  Each field records its
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
# ### Paper Eq. (1): the elastic joint
#
# Between the rotor and the link sits the flexspline, an elastic cup.  On the rotor side
# of the gear are the rotor inertia $I_r$ [kg m²], the rotor angle $\theta_r$ [rad] and
# the motor torque $T_r$ [N m]; the gear ratio $n$ [-] divides angles
# ($\theta_r = n\,q$) and multiplies torques ($T_m = n\,T_r$) and inertias
# ($n^2 I_r$) on their way to the load side.  There, with the link inertia $I_s$
# [kg m²], the flexspline stiffness $K$ [N m/rad] and the friction $T_{at}$ [N m] acting on
# the motor side of the spring (where the encoder also sits), the simulator integrates
#
# <a id="eq-elastic"></a>
#
# $$
# \begin{aligned}
# n^2 I_r\,\ddot q &= T_m - T_{at} - K\,(q - q_s) - d\,(\dot q - \dot q_s),\\
# I_s\,\ddot q_s &= K\,(q - q_s) + d\,(\dot q - \dot q_s),
# \end{aligned}
# $$
#
# with $q$ the motor position seen from the load side [rad] (what the encoder measures),
# $q_s$ the link position [rad] and $d$ a small damping across the spring [N m s/rad].
#
# ### Paper Eq. (2): the rigid joint
#
# A stiff enough spring keeps $q_s = q$; adding the two equations removes the spring and
# leaves one inertia,
#
# <a id="eq-rigid"></a>
#
# $$ I\,\ddot q = T_m - T_{at}, \qquad I = n^2 I_r + I_s, $$
#
# the total inertia reflected to the load side.  Which of these numbers the paper gives:
# of the mechanical parameters only the link inertia $I_s$ (0.0046 kg m², the SCARA link of
# Figs. 16-18); its friction values are the subject of Section 2.  The actuator's inertia
# $n^2 I_r$ is *derived* (the one value that makes the paper's P design self-consistent,
# [Chapter 6](06_gain_design_and_closed_loop)); the gear ratio $n = 100$, the stiffness $K$ and the damping $d$ are
# *assumptions*, so $I_r$ itself is known only through the assumed $n$.  The cell below
# reads all of them from the simulator's own joint objects and checks that their
# accelerations are the right-hand sides of [the two equations of the elastic joint](#eq-elastic).

# %%
n = p.gear_ratio
i_r = to_rotor_side(gear_ratio=n, inertia=p.inertia)["inertia"]  # rotor (and flange) inertia
p_link = p.with_link()
flex = FlexibleJoint.from_params(p_link)
rigid = RigidJoint.from_params(p_link)
for name, symbol in (("gear_ratio", "n"), ("inertia", "n^2 Ir"), ("link_inertia", "Is"),
                     ("stiffness", "K"), ("joint_damping", "d")):
    print(f"{symbol:7s} = {getattr(p_link, name):10.6g} [{p.unit(name)}]  ({p.source(name)})")
print(f"Ir      = {i_r:10.4g} [kg*m^2] on the rotor side (with the assumed n)")
print(f"I = n^2 Ir + Is = {rigid.inertia:.6g} kg*m^2 (rigid joint, with the link)")
assert p.source("link_inertia") == "paper" and p.source("inertia") == "derived" and n == 100
assert all(p.source(k) == "assumption" for k in ("gear_ratio", "stiffness", "joint_damping"))
assert np.isclose(flex.motor_inertia, n**2 * i_r, rtol=1e-12) and flex.load_inertia == PAPER_LINK_INERTIA == 0.0046
assert np.isclose(rigid.inertia, n**2 * i_r + p_link.link_inertia, rtol=1e-12)
# the right-hand sides above, against the kernels: a sliding state with the spring twisted
q, w, q_s, w_s, tm = 0.01, 0.3, 0.009, 0.25, 0.5  # [rad], [rad/s], [rad], [rad/s], [N*m]
t_at = p.friction_model().torque(w)
spring = flex.stiffness * (q - q_s) + flex.damping * (w - w_s)
acc = flex.resistive_torque([q, w, q_s, w_s, 0.0], tm).acceleration
assert np.isclose(acc, (tm - t_at - spring) / (n**2 * i_r), rtol=1e-12)
acc = rigid.resistive_torque([q, w, q, w, 0.0], tm).acceleration
assert np.isclose(acc, (tm - t_at) / (n**2 * i_r + p_link.link_inertia), rtol=1e-12)

# %% [markdown]
# ## 2. Friction laws
#
# The nominal friction is the sum of three laws from [`fricctl.friction`](#fricctl.friction):
#
# * viscous $b\,\omega$, proportional to the velocity $\omega = \dot q$ [rad/s], with
#   $b$ [N m s/rad];
# * Coulomb $F_c\operatorname{sign}(\omega)$, a constant level $F_c$ [N m] whenever the
#   joint slides;
# * Stribeck: extra friction near zero speed that decays to the Coulomb level over the
#   Stribeck velocity $v_s$ [rad/s], so breaking loose takes more torque (the static level
#   $F_s$ [N m]) than keeping moving ($F_c$).
#
# Together, while the joint slides,
#
# <a id="eq-friction"></a>
#
# $$
# T_{at}(\omega) = b\,\omega + \operatorname{sign}(\omega)\Big[F_c + (F_s - F_c)\,
# e^{-(|\omega|/v_s)^2}\Big], \qquad \omega \ne 0.
# $$
#
# At $\omega = 0$ friction is *not* a function of velocity: it is whatever reaction
# keeps the joint at rest, anywhere in $-F_s \le T_{at} \le F_s$; the joint breaks loose
# when $|T_m|$ exceeds $F_s$.  [The friction curve below](#fig-friction) therefore leaves out the point
# $\omega = 0$.  Of the four coefficients the paper gives $b$ and $F_s$; $F_c$ (80 % of
# $F_s$) and $v_s$ are assumptions (the table above).

# %% mystnb={"figure": {"caption": "The nominal friction $T_{at}(\\omega)$ built up term by term: viscous, plus Coulomb, plus the Stribeck excess that lifts it toward $F_s$ near zero speed.  The point $\\omega = 0$ is left out: at rest, friction is a reaction anywhere between $-F_s$ and $F_s$.", "name": "fig-friction"}}
law = p.friction_model()
print(law)
print(f"breakaway +{law.breakaway(+1):.4f} / -{law.breakaway(-1):.4f} N*m, "
      f"sliding level at high speed {law.sliding_level(+1):.4f} N*m")
# the formula above, written out independently of fricctl.friction, at 1e-12
w_check = np.array([-0.5, -0.02, -1e-4, 1e-4, 0.003, 0.02, 0.5])  # [rad/s]
by_hand = p.viscous * w_check + np.sign(w_check) * (
    p.coulomb + (p.static - p.coulomb) * np.exp(-(np.abs(w_check) / p.stribeck_velocity) ** 2))
assert np.allclose(law.torque(w_check), by_hand, rtol=1e-12, atol=0.0)
assert law.breakaway(+1) == law.breakaway(-1) == p.static
assert np.isclose(p.coulomb, 0.8 * p.static, rtol=1e-12) and p.source("stribeck_velocity") == "assumption"

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
# time 0.2 s, damping 0.3, designed on the linear viscous model by
# [`design_p`](#fricctl.design.design_p); Chapter 6 explains the design).  Once the joint stops, it stays stuck as long as the controller's
# torque $K_p\,|r - q|$ is below the breakaway level $F_s$ [N m].  Every error
# inside the band
#
# <a id="eq-dead-band"></a>
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
# In [the two steps below](#fig-dead-band) the smaller step never starts: its initial torque `Kp * r` is already below the
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


# %% tags=["widget"] mystnb={"figure": {"caption": "The P loop's step at the gain $K_p$ set by the slider, with its dead band (within $F_s/K_p$ of $r$) shaded: the larger $K_p$, the narrower the band the joint stops in."}}
if "ipykernel" in sys.modules:  # in Jupyter: a slider; the book shows the figure below instead
    from ipywidgets import FloatSlider, interact

    def show_dead_band(kp):
        dead_band_step(kp)
        plt.show()

    interact(show_dead_band, kp=FloatSlider(value=d_p.kp, min=0.1, max=1.5, step=0.05,
                                            description="Kp [N*m/rad]"))

# %% mystnb={"figure": {"caption": "The 60 deg step at the paper's gain $K_p$ and at three times that gain: each run stops inside its own dead band, within $F_s/K_p$ of $r$ (shaded).", "name": "fig-dead-band"}}
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

# %% mystnb={"figure": {"caption": "Stick-slip under a slow ramp: the position $q$ (top) advances in jumps behind the reference $r$, at rest in the shaded intervals until $K_p e$ reaches $F_s$; the friction $T_{at}$ (bottom) equals the motor torque $T_m$ while the joint sticks and falls below it when the joint breaks loose."}}
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
ax2.plot(ramp.t, ramp.torque_motor, drawstyle="steps-post", label="motor torque $T_m$")
ax2.plot(ramp.t, ramp.friction, lw=1, label="friction Tat")
ax2.set_xlabel("time t [s]")
ax2.set_ylabel("torque [N*m]")
ax2.legend(fontsize="small")
plt.show()

# %% [markdown]
# ## 6. Rigid or flexible joint?
#
# Paper Eq. (1) (Section 1) models the flexspline as a spring $K$ (with a little
# damping $d$) between the actuator inertia $n^2 I_r$ and the link $I_s$; the rigid joint
# ([its equation](#eq-rigid), paper Eq. (2)) lumps both into one rigid inertia $I$.  The simulator,
# [`simulate`](#fricctl.simulate.simulate), has both (`plant="rigid"` or `plant="flexible"`).  Run the same PD step with the SCARA link attached, on both plants,
# and compare.  The two-mass system ([its equations](#eq-elastic), paper
# Eq. (1)) has, with the motor free, the resonance
#
# $$ \omega_r = \sqrt{K\left(\frac{1}{n^2 I_r} + \frac{1}{I_s}\right)} \quad \text{[rad/s]}, $$
#
# and the sampled loop sees frequencies up to the Nyquist frequency $\pi/T_s$ [rad/s],
# with $T_s$ the sample time [s].

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
assert np.isclose(flex.resonance, np.sqrt(flex.stiffness * (1 / p_link.inertia + 1 / p_link.link_inertia)),
                  rtol=1e-12)
print(f"Nyquist frequency pi/Ts = {np.pi / p.sample_time:.0f} rad/s")
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
# ## Summary
#
# * The simulator integrates the elastic joint of paper Eq. (1) and the rigid joint of
#   Eq. (2); their accelerations were checked against the right-hand sides.  Of the
#   mechanical parameters the paper gives only the link inertia: the actuator's inertia is
#   derived, and the gear ratio, stiffness and damping are assumptions.
# * Friction is viscous plus Coulomb plus a Stribeck excess near zero speed; at rest it is a
#   reaction between $-F_s$ and $F_s$.  Below the breakaway torque the simulated joint does
#   not move at all, not even by a fraction of a count; just above it, it breaks loose.
# * A proportional loop stops anywhere inside its dead band $|e| \le F_s/K_p$
#   ([the dead band](#eq-dead-band)): a step whose
#   first torque $K_p r$ is below $F_s$ never starts, a larger one freezes short of the
#   reference, and the band shrinks as $1/K_p$.
# * Under a slow ramp the same loop stick-slips: each stuck interval lasts until $K_p e$ has
#   grown back to $F_s$, the start-up $F_s/(K_p v)$ for a ramp speed $v$ (Exercise 2).
# * With the assumed stiffness the flexspline's twist is far smaller than the error friction
#   leaves and its resonance far above the loop's bandwidth, so the rigid joint ([its
#   equation](#eq-rigid)) is enough
#   for these controllers -- a conclusion that holds only as far as the assumed stiffness.

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
#    ([`FlexibleJoint`](#fricctl.plant.FlexibleJoint)`.from_params(...).resonance`) with the Nyquist frequency
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

# %% tags=["solution"]
# Exercise 2.  Three ramp speeds on the same P loop, as in Section 5.  While the joint is
# stuck q is constant and the error grows at the ramp speed v, so a stuck interval that
# starts with error e_a ends when Kp e reaches Fs: it lasts (Fs/Kp - e_a)/v (+ a sample or
# two of the loop's delay).  The start-up (e_a = 0) lasts Fs/(Kp v): at 0.05 rad/s that is
# longer than the whole experiment, and the joint never moves.
for v_ramp in (0.05, slope, 0.5):
    r = simulate(p, ctl.p_control(d_p.kp, ctl.sawtooth(v_ramp * 100.0, 100.0)),
                 duration=RAMP_DURATION)
    st = r.stuck_intervals(min_duration=0.01)
    t_up = band / v_ramp  # predicted start-up [s]
    print(f"ramp {v_ramp} rad/s: start-up predicted {t_up:.3f} s; {len(st)} stuck intervals, "
          f"lengths {np.round([b - a for a, b in st], 3).tolist()} s")
    if t_up > RAMP_DURATION:
        assert len(st) == 1 and np.all(r.q == 0.0)  # never breaks loose
        continue
    assert abs((st[0][1] - st[0][0]) - t_up) <= 3 * p.sample_time
    for t_a, t_b in st[1:]:  # each later stop: the ramp rebuilds the error from e_a to Fs/Kp
        e_a = r.error[np.searchsorted(r.t, t_a)]
        assert abs((t_b - t_a) - (band - e_a) / v_ramp) <= 3 * p.sample_time
    k_up = np.searchsorted(r.t, st[0][1])
    k_up += int(np.argmax(r.omega[k_up:] > v_ramp))  # first time the joint outruns the ramp
    w_after = r.omega[k_up:]
    print(f"  after it first outruns the ramp: velocity swings from {w_after.max():.3f} down to "
          f"{w_after.min():.3f} rad/s")
    if v_ramp == 0.5:
        assert len(st) == 1 and w_after.min() > 0.0  # no stick-slip after the start-up
    else:
        assert len(st) >= 3 and w_after.min() == 0.0
# Why a fast ramp slides on: the joint breaks loose with the error Fs/Kp but slides in
# equilibrium at the smaller (Fc + b v)/Kp.  The excess, released at once, sets the lightly
# damped loop (zeta = 0.3) swinging about the ramp, and the size of that swing is set by
# Fs - Fc, not by v.  When v is small against the swing, the velocity swings down to zero
# and the joint sticks again; a fast ramp keeps it positive throughout (0.5 rad/s here).

# %% tags=["solution"] mystnb={"figure": {"caption": "Exercise 3: the PD step's motor position $q$ on the rigid joint of paper Eq. (2) and on the flexible joint of Eq. (1), at the first stiffness $K$ of the sweep for which the two runs part by more than 1 % of the step."}}
# Exercise 3.  Lower K until the two plants visibly differ (here: the motor positions more
# than 1 % of the 30 deg step apart).  The resonance falls as sqrt(K).
nyquist = np.pi / p.sample_time  # [rad/s]
print(f"Nyquist pi/Ts = {nyquist:.0f} rad/s; PD natural frequency {d_pd.wn:.1f} rad/s")
ctrl_pd = ctl.pd_control(d_pd.kp, d_pd.kd, ctl.step(np.deg2rad(30.0)))
for k_soft in (2000.0, 500.0, 200.0, 100.0, 50.0, 20.0, 10.0):
    soft = p_link.replace(stiffness=k_soft)
    w_r = FlexibleJoint.from_params(soft).resonance
    r_flex = simulate(soft, ctrl_pd, duration=2.0, plant="flexible")
    gap_k = np.abs(runs["rigid"].q - r_flex.q).max()
    print(f"K = {k_soft:6.0f} N*m/rad: resonance {w_r:6.0f} rad/s ({w_r / nyquist:.2f} x Nyquist, "
          f"{w_r / d_pd.wn:5.1f} x wn), largest gap to the rigid run {np.rad2deg(gap_k):.3f} deg")
    if gap_k > 0.01 * np.deg2rad(30.0):
        break
assert gap_k > 0.01 * np.deg2rad(30.0)  # found a stiffness where they differ
assert w_r < 10 * d_pd.wn and w_r < 0.1 * nyquist
assert flex.resonance < nyquist  # the nominal resonance too lies below Nyquist
fig, ax = plt.subplots(figsize=(6.4, 3.2), layout="constrained")
ax.plot(runs["rigid"].t, np.rad2deg(runs["rigid"].q), label="rigid (Eq. 2)")
ax.plot(r_flex.t, np.rad2deg(r_flex.q), label=f"flexible (Eq. 1), K = {k_soft:g} N*m/rad")
ax.set_xlabel("time t [s]")
ax.set_ylabel("motor position q [deg]")
ax.legend(fontsize="small")
plt.show()
# The runs part only once the resonance has come down to within about ten times the loop's
# natural frequency -- far below the Nyquist frequency.  Even the nominal resonance
# (K = 2000) lies below pi/Ts, so the 500 Hz loop samples it rather than aliasing it; with
# a much stiffer joint (or a slower loop) the resonance would fold back below Nyquist.

# %% [markdown]
# ## References
#
# * [Gervini, Gomes & da Rosa 2003](#gervini2003): the actuator, Eqs. (1)-(2), the P design.
# * [Armstrong-Hélouvry, Dupont & Canudas de Wit 1994](#armstrong1994survey): the friction laws
#   (Coulomb, viscous, Stribeck), stick and stick-slip.
#
# In fricctl: [`paper_actuator`](#fricctl.params.paper_actuator) and
# [`ActuatorParams`](#fricctl.params.ActuatorParams),
# [`to_rotor_side`](#fricctl.units.to_rotor_side), [`Viscous`](#fricctl.friction.Viscous),
# [`Coulomb`](#fricctl.friction.Coulomb), [`Stribeck`](#fricctl.friction.Stribeck),
# [`RigidJoint`](#fricctl.plant.RigidJoint), [`FlexibleJoint`](#fricctl.plant.FlexibleJoint),
# [`simulate`](#fricctl.simulate.simulate) and its [`SimResult`](#fricctl.simulate.SimResult),
# the controllers [`open_loop`](#fricctl.controllers.open_loop),
# [`p_control`](#fricctl.controllers.p_control) and [`pd_control`](#fricctl.controllers.pd_control),
# [`design_p`](#fricctl.design.design_p), [`design_pd`](#fricctl.design.design_pd),
# [`plot_response`](#fricctl.figures.plot_response).
