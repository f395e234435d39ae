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
# # Chapter 7 -- Wear, load and the Coulomb comparison
#
# *Gervini, Gomes & da Rosa (2003): the actuator with the SCARA link (Figs. 16-18).*
#
# The paper attaches a link (0.0046 kg*m^2) and runs the actuator for 30 hours.
# Friction changes with wear; instead of retraining, the paper lowers the
# compensation scale to `s = 0.95` and compares with the classic model-based
# compensator, `Fc * sign(omega_hat)`.  On the virtual bench the aged actuator is
# modelled as the true friction scaled by 0.95 -- an assumption, since the bench
# has no wear.  The chapter ends with a sweep over friction scale and link inertia:
# where does a net trained once keep the PD accuracy of 0.3 deg?

# %%
import os
from concurrent.futures import ThreadPoolExecutor

import matplotlib.pyplot as plt
import numpy as np

from fricctl import figures
from fricctl import paper
from fricctl.params import paper_actuator

FAST = os.environ.get("FRICCTL_FAST") == "1"
SCALES = (0.8, 1.0, 1.2) if FAST else (0.8, 0.9, 1.0, 1.1, 1.2)  # true / trained friction [-]
LINKS = (0.0, 0.0046) if FAST else (0.0, 0.0023, 0.0046, 0.0069, 0.0092)  # link inertia [kg*m^2]

# %%
p = paper_actuator()
net_run = paper.train_paper_network(p, fast=FAST, seed=0)

# %% [markdown]
# ## 1. The aged actuator: NN x 0.95, Coulomb, none (Fig. 16)
#
# PD designed for 0.4 s and damping 0.85 with the link, step of 30 deg.

# %%
r16 = paper.fig16.run(net_run)
print(f"Kp = {r16.design.kp:.4f} N*m/rad, Kd = {r16.design.kd:.4f} N*m*s/rad")
for name, run in r16.runs.items():
    print(f"{name:10s} e_ss {np.rad2deg(r16.steady_state_error[name]):7.3f} deg, "
          f"{r16.reference_crossings[name]} reference crossings, "
          f"{r16.torque_sign_changes[name]} Tm sign changes in the last 0.5 s")
figures.plot_fig16(r16)
plt.show()

# %% [markdown]
# The NN compensation, scaled without retraining, cuts the error against no
# compensation by the factor printed below, though not to the 0.3 deg of Fig. 14.  The Coulomb compensator on
# this bench does *not* chatter: `sign(omega_hat)` is zero while the encoder reads
# no motion, so the moment the joint sticks the compensation switches off.  While
# moving it cancels the braking Coulomb torque, so the joint overshoots, and then
# stays stuck wherever it stopped -- which, on this noise-free bench, is closer to
# the reference than the NN-compensated joint gets (compare the two errors printed
# below): the opposite of the paper's verdict, and a reminder that a compensator
# judged on one actuator, one step and one sensor is judged on very little.

# %%
coul = r16.runs["Coulomb"]
print(f"Coulomb run at the end: at rest {bool(coul.stuck[-1])}, compensation {coul.friction_est[-1]:.3f} N*m")
assert coul.stuck[-1] and coul.friction_est[-1] == 0.0
nn_name = next(k for k in r16.runs if k.startswith("NN"))
e_coul, e_nn = abs(r16.steady_state_error["Coulomb"]), abs(r16.steady_state_error[nn_name])
print(f"|e_ss|: Coulomb {np.rad2deg(e_coul):.3f} deg, {nn_name} {np.rad2deg(e_nn):.3f} deg")
assert r16.torque_sign_changes["Coulomb"] < 10  # no chatter
assert e_coul < e_nn  # what the prose above says
nn_key = next(k for k in r16.runs if k.startswith("NN"))
print(f"NN x 0.95 vs none: error {abs(r16.steady_state_error['none'] / r16.steady_state_error[nn_key]):.1f}x smaller")
assert abs(r16.steady_state_error[nn_key]) < abs(r16.steady_state_error["none"])

# %% [markdown]
# Chatter needs a velocity estimate that flickers at rest -- measurement noise, or a
# joint that never fully sticks; exercise 1 adds noise.
#
# ## 2. A small step (Fig. 17)
#
# 0.08 rad with the same gains: `Kp * 0.08 rad` is below the breakaway level, so
# without compensation nothing moves at all.

# %%
r17 = paper.fig17.run(net_run)
print(f"Kp * step = {r17.design.kp * r17.step:.4f} N*m vs breakaway {0.95 * p.static:.4f} N*m (aged)")
for name in r17.runs:
    print(f"{name:10s} peak |q| {r17.max_motion[name]:.4f} rad, e_ss "
          f"{np.rad2deg(r17.steady_state_error[name]):.3f} deg")
assert r17.max_motion["none"] == 0.0
figures.plot_fig17(r17)
plt.show()

# %% [markdown]
# ## 3. Tracking a sawtooth (Fig. 18)
#
# PD (0.22 s, 0.5) with the link, sawtooth of 0.1 rad.  Here too the uncompensated
# loop asks for less than the breakaway torque over the whole ramp; stick-slip
# appears only for a larger, slower ramp (right panel, an extra).

# %%
r18 = paper.fig18.run(net_run)
print(f"Kp * amplitude = {r18.design.kp * r18.amplitude:.4f} N*m (breakaway {p.static:.3f} N*m)")
print(f"without: peak |q| {r18.max_motion_without:.4f} rad, {r18.restarts_without} stick-slip cycles")
print(f"with NN: RMS deviation from the linear loop {r18.rms_deviation_with:.4f} rad, "
      f"{paper.restarts(r18.with_nn)} stick-slip cycles")
print(f"extra ({r18.extra_amplitude:g} rad over {r18.extra_period:g} s), without: "
      f"{r18.extra_restarts} stick-slip cycles")
assert r18.extra_restarts >= 2
figures.plot_fig18(r18)
plt.show()

# %% [markdown]
# ## 4. The claims of these figures

# %%
for c in paper.paper_claims({16: r16, 17: r17, 18: r18}, p):
    print(f"{'pass' if c.passed else 'FAIL'}  {c.id:14s} {c.measured}")

# %% [markdown]
# ## 5. Robustness: friction scale x link inertia
#
# One net, trained on the nominal actuator without link; the PD gains of Fig. 16
# (designed for the 0.0046 kg*m^2 link) kept fixed; the true friction scaled by
# 0.8-1.2 and the link changed.  Each link inertia is one job for an executor
# (here a thread pool; a `ProcessPoolExecutor` or a dask client's executor works
# the same), each job one batch simulation over the friction scales.

# %%
with ThreadPoolExecutor(max_workers=2) as pool:
    sweep = paper.robustness_sweep(net_run.net, p, friction_scales=SCALES, link_inertias=LINKS,
                                   executor=pool)
print(sweep.report())
print(f"without compensation: |e_ss| from {np.rad2deg(sweep.error_none.min()):.2f} to "
      f"{np.rad2deg(sweep.error_none.max()):.2f} deg")
assert np.all(sweep.error_nn < sweep.error_none)
figures.plot_sweep(sweep)
plt.show()

# %% [markdown]
# Read the table along a row: the error tends to grow with the friction scale --
# with more friction than the net learned, the compensation falls short and the
# joint stops further from the reference.  Where the error stays below 0.3 deg is
# printed above; the nominal point (scale 1) itself is not guaranteed to be
# inside (Chapter 5: the residual dead zone depends on `g`).  Everywhere, the
# compensated error is below the uncompensated one (checked above).
#
# ## Exercises
#
# 1. Rerun Fig. 16 with white torque noise (`simulate(..., noise_std=0.003,
#    rng=np.random.default_rng(0))`, using `r16.runs["Coulomb"].info` for the setup).
#    Does the Coulomb compensator chatter now?  And the NN?
# 2. Sweep the compensation scale `s` (`robustness_sweep(..., compensation_scale=s)`)
#    at friction scale 1.2.  Which `s` restores the 0.3 deg accuracy, and what does
#    it cost at scale 0.8?
# 3. Redesign the PD for each link inertia (`design=` per row) instead of keeping the
#    Fig. 16 gains.  Which part of the failure was the inertia mismatch?
