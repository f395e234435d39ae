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
# # Chapter 3 -- Identifying friction by least squares
#
# *Gervini, Gomes & da Rosa (2003), Section 4 (friction from measured torque and
# acceleration); the EMPS benchmark (Janot, Gautier & Brunot 2019) for real data.*
#
# Chapter 2 turned an encoder record into velocity and acceleration.  Here we fit a
# friction *model* to them.  The inverse dynamic identification model (IDIM) reads
# the joint's equation backwards,
#
# `Tm = I q'' + b w + Fc sign(w) + offset`,
#
# which is **linear in the parameters** `(I, b, Fc, offset)`: stacking one row per
# sample gives an over-determined linear system, solved by least squares.  In
# fricctl every least-squares problem is posed in CasADi and solved by IPOPT, so
# the same code also handles models that are nonlinear in their parameters (the
# Stribeck curve).  The result reports each estimate with its standard deviation,
# as the EMPS identification reports do.

# %%
import os

import matplotlib.pyplot as plt
import numpy as np

from fricctl import controllers as ctl
from fricctl import datasets, figures
from fricctl.identify import cross_validate, fit_friction, idim_ls, identify_run
from fricctl.params import paper_actuator
from fricctl.simulate import simulate

FAST = os.environ.get("FRICCTL_FAST") == "1"
DURATION = 2.0 if FAST else 4.0   # identification experiment [s]
RAMP_SLOPE = 0.1                  # torque ramp of the breakaway test [N*m/s]

# %% [markdown]
# ## 1. Experiment on the virtual bench
#
# The same open-loop experiment as in Chapter 2: a sinusoidal torque above the
# breakaway level.  `SimResult.to_run()` keeps only what a real bench would record
# (time, motor torque, encoder position): the identification does not see the truth.

# %%
p = paper_actuator()
sim = simulate(p, ctl.open_loop(ctl.sinusoid(0.3, 1.0)), duration=DURATION)
run = sim.to_run()
print(f"record: {run.n_samples} samples at {1 / run.sample_time:.0f} Hz, torque in "
      f"[{run.torque_unit}], position in [{run.position_unit}]")

# %% [markdown]
# ## 2. First check the solver, with the true derivatives
#
# Before blaming data, make sure the fit itself is right.  Feed the simulator's
# *true* velocity and acceleration (moving samples only) to a Stribeck fit: the
# friction law of the bench is exactly that model, so the parameters must come back.

# %%
moving = ~sim.stuck
check = fit_friction(sim.omega[moving], sim.accel[moving], sim.torque_motor[moving],
                     model="stribeck")
truth = {"inertia": p.total_inertia, "viscous": p.viscous, "coulomb": p.coulomb,
         "static": p.static, "stribeck_velocity": p.stribeck_velocity}
for name, true_value in truth.items():
    est = check.parameters[name]
    print(f"{name:18s} true {true_value:9.5f}   estimated {est:9.5f}")
    assert abs(est - true_value) <= 1e-3 * true_value  # noise-free recovery, 0.1 %

# %% [markdown]
# ## 3. Identify from the encoder alone
#
# Now the real situation: `identify_run` estimates velocity and acceleration with
# the paper's polynomial segments (Chapter 2), drops the samples at rest (an inverse
# model learns nothing there) and fits the Coulomb + viscous model.

# %%
cv_fit = identify_run(run, model="coulomb_viscous", estimator="polynomial_segments")
print(cv_fit.report())
print()
for name in ("inertia", "viscous", "coulomb"):
    est = cv_fit.parameters[name]
    print(f"{name:8s} true {truth[name]:.5f}, estimated {est:.5f} "
          f"({100 * (est - truth[name]) / truth[name]:+.1f} %)")
# the fitted Coulomb level lands below the true one, the viscous slope above (prose below)
assert cv_fit.parameters["coulomb"] < truth["coulomb"] and cv_fit.parameters["viscous"] > truth["viscous"]

# %%
ax = figures.plot_identification(cv_fit)
ax.set_xlim(0, min(400, cv_fit.n_samples))
plt.show()

# %% [markdown]
# The Coulomb + viscous model has no Stribeck term.  One might expect the fitted
# `Fc` to average the friction levels the data visit, and so to land above the true
# Coulomb level; the run above says otherwise (its sign is printed): least squares
# trades `Fc` against the viscous slope, and the line `b*w + Fc` that fits the
# visited speeds best need not pass through the true intercept.  Can the Stribeck
# model do better on the same data?

# %%
st_fit = identify_run(run, model="stribeck", estimator="polynomial_segments")
for name in ("coulomb", "static", "stribeck_velocity"):
    i = st_fit.names.index(name)
    print(f"{name:18s} true {truth[name]:.4f}, estimated {st_fit.estimates[i]:.4f} "
          f"+- {st_fit.std[i]:.4f} (std)")
i = st_fit.names.index("static")
miss_in_std = abs(st_fit.estimates[i] - p.static) / st_fit.std[i]
print(f"static level off by {miss_in_std:.0f} standard deviations")
assert miss_in_std > 3  # a confident but wrong estimate: bias, not noise

# %% [markdown]
# It cannot.  The Stribeck region is a narrow band of low velocities, visited only
# briefly around each stop, which is exactly where the estimated acceleration is
# worst.  The errors there are *systematic*, so the standard deviations, which
# assume independent noise, do not warn us: the static level misses by many of its
# own standard deviations.  A standard deviation measures noise, never bias.
#
# ## 4. Static friction needs its own experiment
#
# An inverse model only sees a joint that moves.  The breakaway level is a property
# of the joint at rest, so measure it directly: ramp the torque slowly from zero
# and record the torque at which the encoder shows its first count.

# %%
ramp = simulate(p, ctl.open_loop(ctl.sawtooth(RAMP_SLOPE * 10.0, 10.0)),
                duration=1.2 * p.static / RAMP_SLOPE)
k = int(np.flatnonzero(ramp.q_meas != 0.0)[0])
breakaway = ramp.torque_motor[k - 1]  # torque held over the interval of the first count
print(f"first encoder count at t = {ramp.t[k]:.3f} s with Tm = {breakaway:.4f} N*m "
      f"(true breakaway {p.static:.4f} N*m, {100 * (breakaway / p.static - 1):+.2f} %)")
assert p.static <= breakaway < 1.02 * p.static  # one count late, so slightly high

# %% [markdown]
# ## 5. Real data: the EMPS benchmark
#
# EMPS is a real prismatic axis (motor, ball screw, cart) with a published IDIM-LS
# identification.  `fricctl.identify.idim_ls` follows its recipe: zero-phase
# Butterworth at 100 Hz, central differences, decimation by 10, least squares (in
# CasADi here).  The data are not shipped with fricctl: set `FRICCTL_DATA` to the
# folder that holds `emps/DATA_EMPS.mat`; without it this part is skipped.  This is
# a linear axis: forces in N, mass in kg.

# %%
try:
    emps_est = datasets.emps(kind="estimation")
    emps_val = datasets.emps(kind="validation")
except FileNotFoundError as exc:
    emps_est = emps_val = None
    print(f"EMPS part skipped: {exc}")

# Published IDIM-LS results (EMPS_Description.pdf, Sections 3.4 and 4.2).
PUBLISHED = {"inertia": 95.1089, "viscous": 203.5034, "coulomb": 20.3935, "offset": -3.1648}
PUBLISHED_RELATIVE_ERROR = 4.0834       # [%]
PUBLISHED_CROSS_VALIDATION = 5.9824     # [%], on DATA_EMPS_PULSES.mat
PUBLISHED_ASYMMETRIC = {"inertia": 95.1540, "viscous_pos": 166.7061, "coulomb_pos": 20.1440,
                        "viscous_neg": 240.4236, "coulomb_neg": 20.6277}

# %%
if emps_est is not None:
    print(f"EMPS record: {emps_est.run.n_samples} samples at {1 / emps_est.run.sample_time:.0f} Hz")
    emps_fit = idim_ls(emps_est.run, model="coulomb_viscous")
    print(emps_fit.recipe)
    print(emps_fit.report())
    print(f"\n{'parameter':10s} {'here':>10s} {'published':>10s}")
    for name, pub in PUBLISHED.items():
        print(f"{name:10s} {emps_fit.parameters[name]:10.4f} {pub:10.4f}")
        assert abs(emps_fit.parameters[name] - pub) <= 0.5e-4 + 1e-9  # to the printed digits
    print(f"relative error {emps_fit.relative_error:.4f} % (published {PUBLISHED_RELATIVE_ERROR} %)")
    ctv = cross_validate(emps_fit, emps_val.run)
    print(f"cross-validation on the pulses record: relative error {ctv.relative_error:.4f} % "
          f"(published {PUBLISHED_CROSS_VALIDATION} %)")
    assert abs(emps_fit.relative_error - PUBLISHED_RELATIVE_ERROR) <= 0.5e-4 + 1e-9
    assert abs(ctv.relative_error - PUBLISHED_CROSS_VALIDATION) <= 0.5e-4 + 1e-9

# %% [markdown]
# The EMPS authors noticed that the friction is not the same in both directions and
# attribute it to mechanical fatigue of the screw.  The `asymmetric` model has one viscous and one
# Coulomb coefficient per direction (two positive magnitudes, no offset).

# %%
if emps_est is not None:
    asym = idim_ls(emps_est.run, model="asymmetric")
    print(f"{'parameter':12s} {'here':>10s} {'std':>8s} {'published':>10s}")
    for name, pub in PUBLISHED_ASYMMETRIC.items():
        i = asym.names.index(name)
        print(f"{name:12s} {asym.estimates[i]:10.4f} {asym.std[i]:8.4f} {pub:10.4f}")
        assert abs(asym.estimates[i] - pub) <= 0.5e-4 + 1e-9  # to the printed digits
    print(f"relative error: symmetric {emps_fit.relative_error:.4f} %, "
          f"asymmetric {asym.relative_error:.4f} %")
    gap = asym.parameters["viscous_neg"] - asym.parameters["viscous_pos"]
    gap_std = np.hypot(*asym.std[[asym.names.index("viscous_neg"), asym.names.index("viscous_pos")]])
    print(f"viscous asymmetry {gap:.1f} N*s/m = {gap / gap_std:.0f} standard deviations")
    assert asym.relative_error < emps_fit.relative_error

# %% [markdown]
# On EMPS the data are rich (long motions at several constant speeds in both
# directions, recorded at 1 kHz), and the published numbers are reproduced to their
# printed digits.
# Compare with Section 3: good identification is mostly about the experiment and
# the signal processing, not about the solver.
#
# ## Exercises
#
# 1. Replace `estimator="polynomial_segments"` by `"butterworth_central"` with
#    `estimator_options={"cutoff": 20.0}` in Section 3.  Which parameters move most,
#    and how does that match the error table of Chapter 2?
# 2. Design an experiment that identifies the Stribeck part: for example a torque
#    that keeps the joint at low speed for a long time (a small sinusoid just above
#    breakaway).  Does the static level come within its standard deviations?
# 3. Halve and double `RAMP_SLOPE` in Section 4.  How does the error of the
#    measured breakaway scale with the slope?  Explain it from the time one encoder
#    count takes to appear.
