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
# [Chapter 2](02_measuring_acceleration) turned an encoder record into velocity and acceleration.  Here we fit a
# friction *model* to them.  The inverse dynamic identification model (IDIM) reads
# the joint's equation backwards: at each sample $k$,
#
# <a id="eq-idim"></a>
#
# $$ T_{m,k} = I\,\hat\alpha_k + b\,\hat\omega_k + F_c\operatorname{sign}(\hat\omega_k) + o
#    + \varepsilon_k, $$
#
# with the recorded motor torque $T_{m,k}$ [N m], the estimated velocity $\hat\omega_k$
# [rad/s] and acceleration $\hat\alpha_k$ [rad/s²], the inertia $I$ [kg m²], the viscous
# coefficient $b$ [N m s/rad], the Coulomb level $F_c$ [N m], a constant offset $o$ [N m]
# and an error $\varepsilon_k$ [N m].  The velocity enters nonlinearly (through the sign),
# but the model is **linear in the parameters** $\theta = (I, b, F_c, o)$: stacking one row
# per sample gives
#
# <a id="eq-linear-system"></a>
#
# $$ y = X\theta + \varepsilon, \qquad
#    y = \begin{bmatrix} T_{m,1} \\ \vdots \\ T_{m,N} \end{bmatrix}, \qquad
#    X = \begin{bmatrix} \hat\alpha_1 & \hat\omega_1 & \operatorname{sign}\hat\omega_1 & 1 \\
#        \vdots & \vdots & \vdots & \vdots \\
#        \hat\alpha_N & \hat\omega_N & \operatorname{sign}\hat\omega_N & 1 \end{bmatrix}, $$
#
# an over-determined linear system (the regressor $X$ has many more rows than columns),
# solved by bounded least squares:
#
# <a id="eq-least-squares"></a>
#
# $$ \hat\theta = \arg\min_{\theta} \lVert y - X\theta \rVert_2^2
#    \quad\text{subject to}\quad I \ge 0,\; b \ge 0,\; F_c \ge 0. $$
#
# The bounds are the sign convention (friction opposes motion, so its coefficients are
# positive magnitudes); $o$ is free.  In fricctl every least-squares problem is posed in
# CasADi over scaled variables and solved by IPOPT, so the same code also handles models
# that are nonlinear in their parameters (the Stribeck curve).  The result reports each
# estimate with its standard deviation, as the EMPS identification reports do:
#
# <a id="eq-standard-deviation"></a>
#
# $$ \sigma_j = \hat\sigma\,\sqrt{\big[(X^\top X)^{-1}\big]_{jj}}, $$
#
# with $\hat\sigma$ the sample standard deviation of the residual $y - X\hat\theta$.  This
# formula assumes independent, identically distributed errors; Section 3 shows what
# happens when they are not.

# %% [markdown]
# ## What you will learn
#
# * **Explain** why a friction model that is nonlinear in the velocity is linear in its
#   parameters, and pose its identification as a bounded least-squares problem.
# * **Derive** the standard deviations of the estimates from the residual, and **judge**
#   when they cannot be trusted (systematic errors, not noise).
# * **Design** a torque-ramp experiment that measures the breakaway level, and explain its
#   error from the time the first encoder count takes.
# * **Measure** the published IDIM-LS identification of a real axis (the EMPS benchmark) and
#   its cross-validation.
# * **Judge** estimators on a coarse encoder in closed loop -- equation error, instrumental
#   variables, DIDIM -- by their held-out validation.
#
# Symbols and units are collected on the [notation page](../notation).

# %%
import os

import matplotlib.pyplot as plt
import numpy as np

from fricctl import controllers as ctl
from fricctl import datasets, estimation, figures
from fricctl.design import design_pd
from fricctl.identify import cross_validate, fit_friction, idim_ls, identify_run, regressor
from fricctl.identify.uncertainty import block_covariance
from fricctl.params import paper_actuator
from fricctl.simulate import simulate

FAST = os.environ.get("FRICCTL_FAST") == "1"
DURATION = 2.0 if FAST else 4.0   # identification experiment [s]
RAMP_SLOPE = 0.1                  # torque ramp of the breakaway test [N*m/s]

# %% [markdown]
# ## 1. Experiment on the virtual bench
#
# The same open-loop experiment as in Chapter 2: a sinusoidal torque above the
# breakaway level.  [`SimResult.to_run()`](#fricctl.simulate.SimResult.to_run) keeps only what a real bench would record
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
# *true* velocity and acceleration (moving samples only) to a Stribeck fit
# ([`fit_friction`](#fricctl.identify.fit_friction)): the
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
# Now the real situation: [`identify_run`](#fricctl.identify.identify_run) estimates velocity and acceleration with
# the paper's polynomial segments (Chapter 2), drops the samples at rest (an inverse
# model learns nothing there) and fits the Coulomb + viscous model.  After it, the same
# problem is rebuilt by hand, the regressor $X$ from [`fricctl.identify.regressor`](#fricctl.identify.regressor) and
# the solution from numpy's unconstrained `lstsq` (none of the bounds is active here),
# to check that the CasADi fit is [the least squares](#eq-least-squares).  Its standard
# deviations are [the formula above](#eq-standard-deviation) where that is the larger; but
# the residual of filtered motion against the raw torque is coloured, not independent, and
# the formula is then optimistic, so `identify_run` reports for each parameter the larger of
# it and the spread of the residual summed over blocks of the record (its block
# covariance, `fricctl.identify.uncertainty.block_covariance`).

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
# the same fit by hand: identify_run's samples (border of 50, moving samples only)
est = estimation.polynomial_segments(run.t, run.position)
inner = slice(50, run.n_samples - 50)
keep = est.velocity[inner] != 0.0
X = regressor("coulomb_viscous", est.velocity[inner][keep], est.acceleration[inner][keep])
y = run.torque[inner][keep]
theta, *_ = np.linalg.lstsq(X, y, rcond=None)
sigma = np.std(y - X @ theta, ddof=1)
std = sigma * np.sqrt(np.diag(np.linalg.inv(X.T @ X)))          # the formula above
blocks = block_covariance(X, y - X @ theta).std                  # the residual over blocks
print(f"X: {X.shape[0]} rows x {X.shape[1]} columns {cv_fit.names}")
print("numpy lstsq:", np.array2string(theta, precision=6))
print("std, formula:", np.array2string(std, precision=6))
print("std, blocks: ", np.array2string(blocks, precision=6))
assert np.array_equal(y, cv_fit.measured) and not cv_fit.at_bound.any()
assert np.allclose(theta, cv_fit.estimates, rtol=1e-6, atol=1e-9)   # CasADi/IPOPT = lstsq
assert np.allclose(np.maximum(std, blocks), cv_fit.std, rtol=1e-4)  # the larger of the two

# %% mystnb={"figure": {"caption": "The Coulomb + viscous fit of Section 3 on its first samples: the recorded motor torque $T_m$ (measured), the model's prediction $X \\hat\\theta$ and their residual, against the sample index $k$; the title gives the relative error and the fit."}}
ax = figures.plot_identification(cv_fit)
ax.set_xlim(0, min(400, cv_fit.n_samples))
plt.show()

# %% [markdown]
# The Coulomb + viscous model has no Stribeck term.  One might expect the fitted
# `Fc` to average the friction levels the data visit, and so to land above the true
# Coulomb level; the run above says otherwise (its sign is printed): least squares
# trades `Fc` against the viscous slope, and the line `b*w + Fc` that fits the
# visited speeds best need not pass through the true intercept.  Can the Stribeck
# model do better on the same data?  Its friction,
#
# $$ T_{at}(\omega) = b\,\omega + \operatorname{sign}(\omega)\Big[F_c\big(1 - e^{-(\omega/v_s)^2}\big)
#    + F_s\,e^{-(\omega/v_s)^2}\Big], $$
#
# is still linear in $I$, $b$, $F_c$, the static level $F_s$ [N m] and $o$ for a fixed
# Stribeck velocity $v_s$ [rad/s]; only $v_s$ enters nonlinearly, so the fit is a
# nonlinear least-squares problem (non-convex in $v_s$, started from the Coulomb +
# viscous fit), with the bounds $F_s \ge 0$ and $v_s > 0$ added.

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
# linear for fixed v_s: with v_s at its estimate, lstsq on the five columns gives the rest
est_st = np.exp(-(est.velocity[inner][keep] / st_fit.parameters["stribeck_velocity"]) ** 2)
sgn = np.sign(est.velocity[inner][keep])
X5 = np.column_stack([X[:, 0], X[:, 1], sgn * (1 - est_st), sgn * est_st, X[:, 3]])
theta5, *_ = np.linalg.lstsq(X5, y, rcond=None)
print("with v_s fixed, lstsq gives (I, b, Fc, Fs, o) =", np.array2string(theta5, precision=5))
assert not st_fit.at_bound.any() and st_fit.parameters["static"] < st_fit.parameters["coulomb"]
# the fit says so itself: static is not identified, with a warning (a model file refuses it)
assert not st_fit.identified[i] and st_fit.warnings[0].startswith("static: breakaway level")
print(st_fit.warnings[0])
assert np.allclose(theta5, st_fit.estimates[[0, 1, 2, 3, 5]], rtol=1e-4, atol=1e-7)

# %% [markdown]
# It cannot.  The Stribeck region is a narrow band of low velocities, visited only
# briefly around each stop, which is exactly where the estimated acceleration is
# worst.  The errors there are *systematic*, so the standard deviations, which
# assume independent noise, do not warn us: the static level misses by many of its
# own standard deviations, and even lands below the Coulomb level (a Stribeck curve
# upside down, which the bounds $F_s \ge 0$, $v_s > 0$ do not forbid; the fit flags that
# one as non-physical, and a model file refuses it).  A standard deviation measures noise,
# never bias.
#
# ## 4. Static friction needs its own experiment
#
# An inverse model only sees a joint that moves.  The breakaway level is a property
# of the joint at rest, so measure it directly: ramp the torque slowly from zero,
# $T_m(t) = \dot T\,t$ with the slope $\dot T$ [N m/s] (held over each sample), and record
# the torque at which the encoder shows its first count.

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
# identification.  [`fricctl.identify.idim_ls`](#fricctl.identify.idim_ls) follows its recipe: zero-phase
# Butterworth at 100 Hz, central differences, decimation by 10, least squares (in
# CasADi here).  The data are not shipped with fricctl: set `FRICCTL_DATA` to the
# folder that holds `emps/DATA_EMPS.mat` ([`fricctl.datasets.emps`](#fricctl.datasets.emps));
# without it this part is skipped.  This is
# a linear axis: forces in N, mass in kg.  The quality figure of the EMPS reports is the
# relative error $100\,\lVert y - X\hat\theta \rVert / \lVert y \rVert$ [%].

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

# %% [markdown]
# ## 6. A coarse encoder: errors in variables, and the estimators of the field
#
# Every fit above regresses the torque on an acceleration computed from the encoder:
# a *filtered, twice differentiated, quantised* position.  When the encoder step is
# coarse against the motion per sample, that regressor carries an error correlated with
# the motion, and least squares pulls the inertia toward zero ("errors in variables").
# The EMPS authors answer it two ways: **IDIM-IV** ([`idim_iv`](#fricctl.identify.idim_iv); instrumental variables: the same
# regressors built from the motion the *model* simulates, Janot, Vandanjon & Gautier
# 2014) and **DIDIM** ([`didim`](#fricctl.identify.didim); the simulation error minimised
# over the parameters, Gautier, Janot & Vandanjon 2013).  `fricctl identify`'s default,
# [`identify_record`](#fricctl.identify.identify_record), starts with
# the equation error on the record's own signals (the low-pass at the band the motion
# reaches above the quantisation), refines it by DIDIM on the record's torque replayed
# (no derivative of the encoder, no model of the controller), takes its standard errors
# from the residual summed over blocks and from a delete-a-block jackknife, and
# validates on held-out blocks.  Below, a 1 kHz record with 500 counts per revolution, in
# closed loop -- the hardest case for an equation-error fit.

# %%
from dataclasses import replace  # noqa: E402

from fricctl import friction as fr  # noqa: E402
from fricctl.identify import didim, identify_record, idim_iv  # noqa: E402

coarse = replace(p, sample_time=0.001, encoder_counts=5)   # 500 counts per load revolution
coarse_law = fr.Viscous(p.viscous) + fr.Coulomb(p.coulomb)
coarse_run = simulate(coarse, ctl.pd_control(2.0, 0.05, ctl.sinusoid(1.0, 0.4)
                                             + ctl.sinusoid(0.3, 1.7)),
                      duration=10.0 if FAST else 20.0, friction=coarse_law, noise_std=0.005,
                      rng=np.random.default_rng(1500)).to_run()
coarse_truth = {"inertia": coarse.total_inertia, "viscous": p.viscous, "coulomb": p.coulomb}
ident = identify_record(coarse_run)
estimates = {"plain (Butterworth + LS)": identify_run(coarse_run),
             "idim_ls (EMPS recipe)": idim_ls(coarse_run)}
try:  # IV iterates on instruments simulated by its own estimate: it may leave physics
    estimates["idim_iv"] = idim_iv(coarse_run)
except ValueError as exc:
    print(f"idim_iv refused: {exc}")
estimates.update({"didim (closed loop)": didim(coarse_run),
                  "auto: equation error": ident.start,
                  "auto (default)": ident.result})
print(f"{'estimator':26s} " + " ".join(f"{k:>9s}" for k in coarse_truth) + "   (error, %)")
coarse_errors = {}
for label, res in estimates.items():
    coarse_errors[label] = {k: 100 * (res.parameters[k] / x - 1) for k, x in coarse_truth.items()}
    print(f"{label:26s} " + " ".join(f"{e:+9.1f}" for e in coarse_errors[label].values()))
print(ident.report())
# the equation error loses a third of the inertia or more; the default meets the issue's
# targets (inertia and Coulomb within 5 %, viscous 10 %), with the truth inside 4 std
assert coarse_errors["auto: equation error"]["inertia"] < -30
assert coarse_errors["plain (Butterworth + LS)"]["inertia"] < -30
e = coarse_errors["auto (default)"]
assert abs(e["inertia"]) < 5 and abs(e["coulomb"]) < 5 and abs(e["viscous"]) < 10
r = ident.result
assert all(abs(r.parameters[k] - x) < 4 * r.std[r.names.index(k)] for k, x in coarse_truth.items())
assert any("disagree beyond their standard errors" in w for w in r.warnings)

# %% [markdown]
# The report says which estimator it kept and why; the figure is the held-out
# validation ([`plot_held_out`](#fricctl.figures.plot_held_out)): each block of the record replayed with the estimate of the *other*
# blocks (top), and the equation error's torque on the same blocks (bottom).  A
# model that explains only the data it was fitted to fails here.

# %% mystnb={"figure": {"caption": "The held-out validation of fricctl's default estimate on the coarse-encoder record: each block's position replayed with the estimate of the other blocks, against the measured one (top), and the equation error's torque against the low-passed measured torque (bottom).  The replayed position follows the measured one."}}
fig = figures.plot_held_out(ident)
plt.show()
assert ident.held_out.simulation_fit > 95

# %% [markdown]
# And on EMPS: every estimator fitted on `DATA_EMPS.mat` and checked on
# `DATA_EMPS_PULSES.mat` (its torque replayed: position fit; and the force predicted
# by the EMPS recipe: relative error, published 5.9824 % for IDIM-LS).  With its fine
# encoder (one count is printed in [Chapter 9](09_your_own_actuator)), EMPS has no errors in
# variables to speak of: every estimator lands
# within a few standard errors of the published IDIM-LS.  The default reports DIDIM,
# whose mass is only known to a few per cent on this stiff closed loop (the replayed
# position carries little of it) -- and says so, pointing at the equation error, which
# agrees within the standard errors and is far more precise.

# %%
if emps_est is not None:
    from fricctl.identify.compare import compare_estimators, estimator_table  # noqa: E402

    pd_emps = ctl.pd_control(emps_est.gtau * emps_est.kp * emps_est.kv,
                             emps_est.gtau * emps_est.kv, ctl.constant(0.0))
    emps_rows = compare_estimators(emps_est.run, emps_val.run, controller=pd_emps)
    print(estimator_table(emps_rows))
    for row in emps_rows:
        res = row.result
        for name, pub in PUBLISHED.items():
            j = res.names.index(name)
            assert abs(res.estimates[j] - pub) < max(3 * res.std[j], 0.025 * abs(pub)), (row.name, name)
        assert row.validation.simulation_fit > 85 and row.cross_validation_error < 6.5
    default = emps_rows[-1].result
    assert default.method == "DIDIM" and any("take the equation error" in w for w in default.warnings)

# %% [markdown]
# Compare with Section 3: good identification is mostly about the experiment and
# the signal processing, not about the solver.

# %% [markdown]
# ## Summary
#
# * The inverse model $T_m = I\hat\alpha + b\hat\omega + F_c\operatorname{sign}\hat\omega + o$ is
#   linear in its parameters: a bounded least-squares problem, posed in CasADi and solved by
#   IPOPT.  Fed the true derivatives, the Stribeck fit recovered the bench's parameters; on
#   the encoder's estimates, the fit and its standard deviations equalled numpy's `lstsq`
#   and the formula $\sigma_j = \hat\sigma\sqrt{[(X^\top X)^{-1}]_{jj}}$.
# * Least squares trades the Coulomb level against the viscous slope: the fitted $F_c$ landed
#   below the true one and $b$ above.
# * The Stribeck level identified from sliding data was wrong by many of its own standard
#   deviations, even below the Coulomb level: a standard deviation measures noise, never
#   bias.
# * Static friction needs its own experiment: a slow torque ramp reads the breakaway level a
#   little high, by an error that grows as the ramp's slope to the power 2/3 (Exercise 3).
# * On the EMPS benchmark the IDIM-LS recipe reproduced the published estimates, relative
#   error and cross-validation to their printed digits, and the direction-dependent model
#   fitted better than the symmetric one.
# * With a coarse encoder in closed loop, equation-error fits lose a large part of the
#   inertia (errors in variables); `identify_record`, refined by DIDIM on the replayed torque,
#   came within 5 % of the true inertia and Coulomb level and 10 % of the viscous
#   coefficient, and passed the held-out validation.

# %% [markdown]
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

# %% tags=["solution"]
# Exercise 1.  Butterworth at 20 Hz instead of the polynomial segments, same record, same
# model.  Chapter 2's table predicts a worse fit: at 20 Hz the filter's friction error is
# several times the polynomial's, and most of it comes from the stops.  But identify_run
# drops the samples the *encoder* shows at rest (the same reading two samples before and
# after), whatever the estimator, so the stops hardly enter the fit:
bw_fit = identify_run(run, model="coulomb_viscous", estimator="butterworth_central",
                      estimator_options={"cutoff": 20.0})
for name in ("inertia", "viscous", "coulomb"):
    by_poly, by_bw = cv_fit.parameters[name], bw_fit.parameters[name]
    print(f"{name:8s} polynomial {by_poly:.5f}  Butterworth 20 Hz {by_bw:.5f}  (true {truth[name]:.5f})")
    assert abs(by_bw / truth[name] - 1) < 0.1       # within 10 % of the truth, like the polynomial's
print(f"relative error: polynomial {cv_fit.relative_error:.2f} %, Butterworth {bw_fit.relative_error:.2f} %; "
      f"samples in the fit: {cv_fit.n_samples} and {bw_fit.n_samples}")
# What the stops would do: a filtered velocity is never exactly 0, so with only the
# zero-velocity test (rest_guard=None) the samples at rest stay in.  There Tm is the
# reaction that holds the joint (anything below Fs), paired with a small velocity of
# either sign: the Coulomb column sign(w) sees torques far below Fc, and the fit lowers Fc
# and steepens b to reach them.
bw_kept = identify_run(run, model="coulomb_viscous", estimator="butterworth_central",
                       estimator_options={"cutoff": 20.0}, rest_guard=None)
rest = estimation.at_rest(run.position)[inner]
moved = {name: bw_kept.parameters[name] / bw_fit.parameters[name] - 1
         for name in ("inertia", "viscous", "coulomb")}
print(f"with the {bw_kept.n_samples - bw_fit.n_samples} samples at rest kept: "
      + ", ".join(f"{name} {100 * m:+.0f} %" for name, m in moved.items()))
assert bw_kept.n_samples - bw_fit.n_samples == rest.sum() > 0
assert moved["viscous"] > 0.3 and moved["coulomb"] < -0.3  # b up, Fc down
assert min(abs(moved["viscous"]), abs(moved["coulomb"])) > 3 * abs(moved["inertia"])
assert bw_kept.relative_error > bw_fit.relative_error

# %% tags=["solution"]
# Exercise 2.  The suggested experiment: a sinusoid just above breakaway (0.19 N*m, 1 Hz).
# Count how much of the moving time it spends inside the Stribeck band |w| < 2 vs, then
# fit the Stribeck model.
slow = simulate(p, ctl.open_loop(ctl.sinusoid(0.19, 1.0)), duration=DURATION)
slow_fit = identify_run(slow.to_run(), model="stribeck", estimator="polynomial_segments")
band = np.abs(slow.omega) < 2 * p.stribeck_velocity
i = slow_fit.names.index("static")
miss = abs(slow_fit.estimates[i] - p.static) / slow_fit.std[i]
print(f"0.19 N*m at 1 Hz: moving {100 * (~slow.stuck).mean():.0f} % of the time, inside |w| < 2 vs "
      f"{100 * (band & ~slow.stuck).sum() / (~slow.stuck).sum():.1f} % of that; static "
      f"{slow_fit.estimates[i]:.4f} +- {slow_fit.std[i]:.2g} N*m, off by {miss:.0f} std")
assert (band & ~slow.stuck).sum() < 0.1 * (~slow.stuck).sum() and miss > 3  # no: still biased
# Why no open-loop torque can do it: in the Stribeck band friction FALLS as speed rises.
# Its slope dTat/dw = b - 2 (Fs - Fc) x exp(-x^2) / vs (x = w/vs) is negative there, so a
# joint that starts to slide accelerates through the band within milliseconds.
x = np.linspace(0.0, 3.0, 301)
slope_min = (p.viscous - 2 * (p.static - p.coulomb) * x * np.exp(-x ** 2) / p.stribeck_velocity).min()
print(f"steepest friction slope in the band: {slope_min:.3f} N*m*s/rad (b = {p.viscous} N*m*s/rad)")
assert slope_min < 0
# A closed loop can hold a constant speed where that slope is beaten: with a stiff PD loop
# tracking slow ramps, steady sliding gives Tm = Tat(v) directly (no acceleration).  But
# the loop's own velocity is one count per sample ~ vs, and below about 2 vs it stick-slips
# (Chapter 1): the constant-speed test maps the curve only where the excess has decayed.
d_cv = design_pd(p, rise_time=0.05, damping=1.0)
for v_test in (0.01, 0.02, 0.04, 0.08, 0.16):
    r = simulate(p, ctl.pd_control(d_cv.kp, d_cv.kd, ctl.sawtooth(v_test * 100.0, 100.0)),
                 duration=2.0)
    late = r.t > 1.0
    tm_mean, tat_v = np.mean(r.torque_motor[late]), float(p.friction_model().torque(v_test))
    print(f"  speed {v_test:.2f} rad/s: stuck {100 * r.stuck[late].mean():3.0f} % of the last second, "
          f"mean Tm {tm_mean:.4f} N*m, Tat(v) {tat_v:.4f} N*m")
    if v_test >= 2 * p.stribeck_velocity:
        assert not r.stuck[late].any() and abs(tm_mean - tat_v) < 1e-3
    else:
        assert r.stuck[late].mean() > 0.3
# So: no, the static level does not come within its standard deviations from sliding data;
# it needs the breakaway test of Section 4, and the curve between needs a better sensor
# (or a velocity loop on a finer encoder) than one count per sample at 500 Hz.

# %% tags=["solution"]
# Exercise 3.  After breakaway the joint starts from rest under a net torque that grows
# with the ramp, about Tdot*tau after a time tau, so it covers Tdot*tau^3/(6 I).  The first
# count appears when that reaches one count Delta:
#     tau = (6 I Delta / Tdot)^(1/3),  torque error = Tdot*tau = (6 I Delta Tdot^2)^(1/3),
# which grows as the slope to the power 2/3 (doubling the slope: x 2^(2/3) = 1.59).  The
# Stribeck drop after breakaway adds net torque, so the joint reaches the count a bit sooner.
errors = {}
for slope_t in (RAMP_SLOPE / 2, RAMP_SLOPE, 2 * RAMP_SLOPE):
    r = simulate(p, ctl.open_loop(ctl.sawtooth(slope_t * 10.0, 10.0)), duration=1.2 * p.static / slope_t)
    k = int(np.flatnonzero(r.q_meas != 0.0)[0])
    errors[slope_t] = r.torque_motor[k - 1] - p.static
    predicted = (6 * p.total_inertia * p.encoder_resolution * slope_t ** 2) ** (1 / 3)
    print(f"slope {slope_t:.3f} N*m/s: error {1e3 * errors[slope_t]:.2f} mN*m, "
          f"(6 I Delta Tdot^2)^(1/3) = {1e3 * predicted:.2f} mN*m")
    assert 0.75 * predicted < errors[slope_t] <= predicted  # the Stribeck drop only shortens it
ratios = [errors[RAMP_SLOPE] / errors[RAMP_SLOPE / 2], errors[2 * RAMP_SLOPE] / errors[RAMP_SLOPE]]
print(f"doubling the slope multiplies the error by {ratios[0]:.2f} and {ratios[1]:.2f} "
      f"(2^(2/3) = {2 ** (2 / 3):.2f})")
assert all(1.3 < q < 1.9 for q in ratios)

# %% [markdown]
# ## References
#
# * [Gervini, Gomes & da Rosa 2003](#gervini2003): Section 4, friction from measured torque and
#   acceleration.
# * [Janot, Gautier & Brunot 2019 (EMPS)](#janot2019emps): the data, the IDIM-LS recipe and its
#   published results.
# * [Gautier, Janot & Vandanjon 2013](#gautier2013didim): DIDIM.
# * [Janot, Vandanjon & Gautier 2014](#janot2014idimiv): IDIM-IV.
# * [Armstrong-Hélouvry, Dupont & Canudas de Wit 1994](#armstrong1994survey): the Stribeck
#   friction model.
# * [Andersson et al. 2019 (CasADi)](#andersson2019casadi).
# * [Wächter & Biegler 2006](#wachter2006ipopt): IPOPT.
#
# In fricctl: [`fit_friction`](#fricctl.identify.fit_friction),
# [`identify_run`](#fricctl.identify.identify_run), [`regressor`](#fricctl.identify.regressor),
# [`IdentificationResult`](#fricctl.identify.IdentificationResult),
# [`idim_ls`](#fricctl.identify.idim_ls), [`cross_validate`](#fricctl.identify.cross_validate),
# [`idim_iv`](#fricctl.identify.idim_iv), [`didim`](#fricctl.identify.didim),
# [`identify_record`](#fricctl.identify.identify_record),
# [`polynomial_segments`](#fricctl.estimation.polynomial_segments),
# [`at_rest`](#fricctl.estimation.at_rest), [`emps`](#fricctl.datasets.emps),
# [`simulate`](#fricctl.simulate.simulate), [`design_pd`](#fricctl.design.design_pd),
# [`plot_identification`](#fricctl.figures.plot_identification),
# [`plot_held_out`](#fricctl.figures.plot_held_out).
