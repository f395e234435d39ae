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
# # Chapter 6 -- Gain design and the closed loop without compensation
#
# *Gervini, Gomes & da Rosa (2003): the controller design and the closed-loop
# experiments of Figs. 11-14.*
#
# The paper designs its position controllers "as if the system was linear (only
# viscous friction)": the classic second-order design from a rise time and a
# damping ratio.  This chapter does that design with python-control, checks it on
# the sampled 500 Hz loop, and then runs the *nonlinear* joint of Chapter 1 with
# those gains and no friction compensation.  The gap between the two is what the
# neural compensator of the later chapters has to close: the dashed "linear"
# line of the paper's Fig. 12 is the target.

# %%
import os
import warnings

import control
import matplotlib.pyplot as plt
import numpy as np

from fricctl import controllers as ctl
from fricctl import figures
from fricctl import paper
from fricctl.design import (DesignWarning, design_p, design_pd, design_table, linear_response,
                            paper_designs, plant_tf)
from fricctl.params import paper_actuator
from fricctl.simulate import simulate

FAST = os.environ.get("FRICCTL_FAST") == "1"
DURATION = 2.0 if FAST else 3.0   # length of each closed-loop run [s]
P_STEP = np.deg2rad(25.0)         # the paper's P step (Figs. 11-12) [rad]
PD_STEP = np.deg2rad(30.0)        # the paper's PD step (Figs. 13-14) [rad]

# %% [markdown]
# ## 1. The design model
#
# Drop Coulomb and static friction, keep the viscous term: the joint becomes the
# linear plant `G(s) = q/Tm = 1 / (s (I s + b))`, a pole at the origin and one at
# `-b/I`.

# %%
p = paper_actuator()
G = plant_tf(p)
print(G)
print(f"open-loop poles: {np.round(np.sort(control.poles(G).real), 3)} rad/s")

# %% [markdown]
# ## 2. Design: P and PD from rise time and damping
#
# With `Tc = Kp (r - q)` the closed loop is `Kp / (I s^2 + b s + Kp)`: one gain, two
# specifications.  The viscous term fixes `2 zeta wn = b / I`, so the damping can
# only be chosen through `wn`, which also sets the rise time.  `design_p` imposes
# one specification (here the rise time) and reports how well the other is met.
# (The actuator's inertia is itself *derived* from this design, Chapter 1, so both
# come out right; that is a consistency choice of fricctl, not a measurement.)
#
# The PD uses *rate feedback*, `Tc = Kp (r - q) - Kd w_hat`: the closed loop
# `Kp / (I s^2 + (b + Kd) s + Kp)` has two free gains for two specifications and no
# zero.  Both designs are also verified on the sampled-data loop (500 Hz, zero-order
# hold, backward-difference velocity, one sample of computation delay).

# %%
d_p = design_p(p, rise_time=0.2, damping=0.3, priority="rise_time")
print(d_p.report())
print()
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always", DesignWarning)
    d_pd = design_pd(p, rise_time=0.3, damping=0.9)
print(d_pd.report())  # lists the DesignWarning messages caught here, if any
print(f"{len(caught)} DesignWarning(s) for the PD design")

# %% [markdown]
# The warning, if printed, is worth reading: for a well-damped loop the 0-100 % rise
# time is ill-conditioned (the response creeps up to its final value), so a small
# change in the loop moves it a lot while the 10-90 % rise time hardly changes.
#
# All four of the paper's designs in one table (the last two with the SCARA link):

# %%
with warnings.catch_warnings():
    warnings.simplefilter("ignore", DesignWarning)  # reported above for fig13-14
    designs = paper_designs(p)
print(design_table(designs))

# %% [markdown]
# ## 3. Root locus and step response
#
# The root locus of the P loop shows the trade-off: as `Kp` grows the poles leave
# the real axis and move up a vertical line `Re s = -b / (2 I)`, so the damping
# falls as the loop gets faster.  The step plot marks the achieved rise time,
# overshoot and settling time of the PD design.

# %%
cl_poles = control.poles(d_p.closed_loop)
print(f"P closed-loop poles {np.round(cl_poles, 3)} rad/s; -b/(2I) = "
      f"{-p.viscous / (2 * p.total_inertia):.3f} rad/s")
assert np.allclose(cl_poles.real, -p.viscous / (2 * p.total_inertia))
ax = figures.plot_root_locus(d_p)
plt.show()
ax = figures.plot_step(d_pd)
plt.show()

# %% [markdown]
# Why rate feedback?  A PD acting on the error, `(Kp + Kd s)(r - q)`, has the same
# poles but adds a zero at `-Kp/Kd`, which makes the step overshoot more than the
# damping ratio suggests.

# %%
zero_loop = d_pd.error_pd_closed_loop()
os_rate = d_pd.achieved.overshoot_percent
os_error = control.step_info(zero_loop)["Overshoot"]
print(f"overshoot: rate feedback {os_rate:.2f} %, PD on the error {os_error:.2f} % "
      f"(zero at {-d_pd.kp / d_pd.kd:.2f} rad/s)")
assert os_error > os_rate

# %% [markdown]
# ## 4. Simulate: the nonlinear joint with the P gain (Fig. 11)
#
# Now the real joint, with Coulomb and Stribeck friction, the encoder and the torque
# limit, against the linear prediction on the same time grid
# (`linear_response(..., sampled=True)` is the sampled loop with viscous friction
# only: the dashed line of the paper's Fig. 12).

# %%
run_p = simulate(p, ctl.p_control(d_p.kp, ctl.step(P_STEP)), duration=DURATION)
lin_p = linear_response(d_p, run_p.t, run_p.reference, sampled=True)
print(f"initial P torque Kp*r = {d_p.kp * P_STEP:.4f} N*m, breakaway {p.static:.4f} N*m")
print(f"linear model: peak {np.rad2deg(lin_p.max()):.2f} deg, "
      f"q({run_p.t[-1]:.1f} s) = {np.rad2deg(lin_p[-1]):.2f} deg")
print(f"nonlinear joint: max |q| = {np.rad2deg(np.abs(run_p.q).max()):.2f} deg, "
      f"steady-state error {np.rad2deg(run_p.steady_state_error()):.2f} deg")
assert np.all(run_p.q == 0.0) and run_p.stuck.all()  # the joint never moves

# %% [markdown]
# The linear design promises a fast, lightly damped step; the real joint does not
# move at all.  The P gain turns the whole step into a torque below the breakaway
# level, and the joint is stuck from the start: the steady-state error is the full
# step.
#
# ## 5. The PD loop (Fig. 13)

# %%
run_pd = simulate(p, ctl.pd_control(d_pd.kp, d_pd.kd, ctl.step(PD_STEP)), duration=DURATION)
lin_pd = linear_response(d_pd, run_pd.t, run_pd.reference, sampled=True)
e_ss = run_pd.steady_state_error()
band = p.static / d_pd.kp
stuck = run_pd.stuck_intervals(min_duration=0.01)
print(f"linear model: error at the end {np.rad2deg(run_pd.reference[-1] - lin_pd[-1]):.4f} deg")
print(f"nonlinear joint: stuck from t = {stuck[-1][0]:.3f} s, "
      f"steady-state error {np.rad2deg(e_ss):.3f} deg (dead band +-Fs/Kp = {np.rad2deg(band):.3f} deg)")
print(f"residual motor torque {run_pd.torque_motor[-1]:.4f} N*m = Kp*e = {d_pd.kp * e_ss:.4f} N*m, "
      f"held by static friction (breakaway {p.static:.4f} N*m)")
print(f"largest gap between linear and nonlinear: {np.rad2deg(np.abs(run_pd.q - lin_pd).max()):.3f} deg")
assert run_pd.stuck[-1] and abs(e_ss) <= band + p.encoder_resolution
assert abs(run_pd.torque_motor[-1]) <= p.static
# the loop sees the encoder, the error uses the true q: they differ by less than one count
assert abs(run_pd.torque_motor[-1] - d_pd.kp * e_ss) <= d_pd.kp * p.encoder_resolution

# %% [markdown]
# The PD joint does move, but stops early: once the velocity reaches zero, the
# remaining torque `Kp e` is smaller than the breakaway level and nothing in the loop
# grows to overcome it (there is no integral action).  The joint stays stuck with a
# constant error inside the dead band, and the motor keeps pushing against static
# friction with exactly the torque printed above.  Chapter 5's compensator adds the
# estimated friction to that torque.

# %%
fig, axes = plt.subplots(1, 2, figsize=(9.6, 3.6), layout="constrained", sharey=False)
for ax, run, lin, title in ((axes[0], run_p, lin_p, "P (Fig. 11)"),
                            (axes[1], run_pd, lin_pd, "PD (Fig. 13)")):
    ax.plot(run.t, np.rad2deg(run.reference), "k:", lw=1, drawstyle="steps-post", label="reference")
    ax.plot(run.t, np.rad2deg(lin), "--", label="linear viscous model")
    ax.plot(run.t, np.rad2deg(run.q), label="nonlinear joint")
    ax.set_xlabel("time t [s]")
    ax.set_ylabel("position q [deg]")
    ax.set_title(title)
    ax.legend(fontsize="small")
plt.show()

# %% [markdown]
# ## 6. Closing the loop with the network (Figs. 12 and 14)
#
# Now the paper's compensation, `Tm(k+1) = Tc(k) + T^at(Tm(k), omega_hat(k))`, with
# the network trained as in Chapter 4, on the same two designs.  The paper reports
# the P step "close to the linear viscous simulation" (Fig. 12) and a PD
# steady-state error below 0.3 deg (Fig. 14).

# %%
net_run = paper.train_paper_network(p, fast=FAST, seed=0)
r12 = paper.fig12.run(net_run)
r14 = paper.fig14.run(net_run)
print(f"P + NN: max |q - q_linear| {np.rad2deg(r12.max_deviation):.1f} deg, "
      f"error growth last/first second x{r12.growth:.2f}")
print(f"P + ideal estimate: max |q - q_linear| {np.rad2deg(r12.ideal_max_deviation):.1f} deg, "
      f"growth x{r12.ideal_growth:.2f}; ideal minus b*w: max |q - q_linear| "
      f"{np.rad2deg(r12.ideal_no_viscous_max_deviation):.2f} deg")
print(f"PD + NN: steady-state error {np.rad2deg(r14.steady_state_error):.3f} deg, "
      f"predicted stopping band +-{np.rad2deg(r14.predicted_band):.3f} deg")
assert r12.ideal_growth > 1 and r12.ideal_no_viscous_max_deviation < 0.1 * P_STEP
assert r12.max_deviation > 1.2 * r12.ideal_max_deviation  # the net's swing exceeds the ideal one
assert abs(r14.steady_state_error) <= r14.predicted_band + p.encoder_resolution
figures.plot_fig12(r12)
figures.plot_fig14(r14)
plt.show()

# %% [markdown]
# **The P loop.**  A P loop has no damping but the viscous friction `b`: the
# design's `zeta = b / (2 sqrt(Kp I))` *is* the friction.  A compensator that
# cancels all friction cancels that damping too, and with the one-sample delay of
# the sampled loop what is left is slightly negative: the step oscillates and grows.
# The printout separates the suspects.  An *ideal* estimate (the bench's exact
# friction while sliding, `Tat = Tm` at rest) oscillates too, so the scheme itself is
# at fault; the same ideal estimate minus `b*omega` follows the linear prediction.
# The network makes it worse: its swing is several times the ideal estimate's (the
# two deviations are printed), because its errors -- a gain at rest above one, its
# slope in `Tm` while sliding -- wind the torque up.  Compensate what the linear
# design did not model, not what it counts on, and expect a learned estimate to add
# its own errors to the loop.
#
# **The PD loop.**  Rate feedback supplies the damping, so full compensation is
# safe here, and the joint gets much closer than without compensation (Section 5).  But it
# still stops: the compensated loop keeps a residual dead zone (Chapter 5), and the
# joint may rest anywhere where `Kp*e` is inside it -- the band printed above.
# Whether a given step ends inside 0.3 deg depends on where in that band it stops.
#
# ## Exercises
#
# 1. Rerun the P design with `priority="damping"` on an actuator whose inertia you
#    change by +-30 % (`p.replace(inertia=...)`).  Which specification is missed,
#    and by how much?  Why can a single gain not fix both?
# 2. For the PD loop, find the smallest step for which the nonlinear joint moves at
#    all, first by hand from `Kp` and the breakaway level, then by simulation.
# 3. Double `Kp` and `Kd` of the PD design (faster loop) and compare the dead band
#    `Fs/Kp` with the simulated steady-state error.  What limits how far you can go
#    (look at `torque_motor` against `p.max_torque`, and at the sampled-loop damping)?
