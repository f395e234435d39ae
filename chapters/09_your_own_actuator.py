# %% [markdown]
# # Chapter 9 — Your own actuator: EMPS from record to compensator
#
# *Companion to Gervini, Gomes & da Rosa (2003), Secs. 3-5 (identify, design, learn the
# friction, compensate), applied to a machine that is not the paper's: the EMPS benchmark
# (Janot, Gautier & Brunot 2019).*
#
# The paper's chain starts from records of *its* harmonic drive.  This chapter runs it on
# the records of another drive -- a ball-screw axis, a prismatic joint: forces in N,
# positions in m, a mass in kg -- and asks at each step what the records can and cannot
# tell.  One file carries the actuator from step to step: the **model file**
# (`fricctl.joint_model`, version 2, read and written by
# [`JointModel`](#fricctl.plant.JointModel)).  The page
# [Your own actuator](../your_own_actuator) runs the same chain as seven `fricctl`
# commands.

# %% [markdown]
# ## What you will learn
#
# * **Explain** what a model file holds -- the joint equation, friction per direction, the
#   loop around it -- and why every value carries its unit and its provenance.
# * **Measure** a real axis: identify EMPS by IDIM-LS into a model file, and check the
#   estimates by hand.
# * **Design** a PD loop for the identified axis and compare it with the axis's own
#   controller.
# * **Judge** what a set of records fixes and what it leaves to the training seed: the
#   network's fit against its gain at rest.
# * **Judge** a compensator by simulated steps and held-out data before exporting it to C.
#
# Symbols and units are collected on the [notation page](../notation).

# %%
import hashlib
import os
import tempfile
import warnings
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from fricctl.compensators import CoulombCompensator, NNCompensator
from fricctl.controllers import pd_control, step
from fricctl.data import paper_actuator_file
from fricctl.datasets import emps, record_patterns
from fricctl.design import DesignWarning, design_pd, normalized_rise_time
from fricctl.estimation import at_rest, butterworth_central, decimate
from fricctl.identify import idim_ls, regressor
from fricctl.nn import TRAINERS, fit_report
from fricctl.nn.c_export import c_header, c_source
from fricctl.nn.cache import cached_pipeline_net
from fricctl.nn.pipelines import PipelineNet, pipeline
from fricctl.params import paper_actuator
from fricctl.plant import JointModel
from fricctl.simulate import simulate_model

FAST = os.environ.get("FRICCTL_FAST") == "1"
SEEDS = (0, 1, 2, 3)  # training seeds: what the data fix, the seeds agree on
MAX_PATTERNS = 4000 if FAST else None  # patterns per network (None: all of them)
RESTARTS = 1 if FAST else 3  # starting points of the Levenberg-Marquardt trainer
RISE_TIME, DAMPING = 0.05, 0.7  # PD specification [s], [-]
STEP = 0.0005  # step of the closed-loop test [m]
POLY = {"window": 50, "overlap": 25}  # the fricctl pipeline's polynomial windows [samples]
WORK = tempfile.TemporaryDirectory(prefix="fricctl-ch09-")  # files of this chapter (removed at exit)
warnings.simplefilter("ignore", DesignWarning)  # the designs' warnings are in Design.warnings

# %% [markdown]
# ## 1. The model file
# Everything a design or a simulation needs of an actuator, with units and, per value, where
# it comes from.  For a rigid joint (the file's `load_inertia` is 0) it is the joint
# equation of paper Eq. (2), a constant offset, and a friction law with one set of
# coefficients per direction:
#
# <a id="eq-joint-model"></a>
#
# $$ I\,\ddot q = T_m - o - T_{at}(\dot q), \qquad
#    T_{at}(\omega) = b^{\pm}\omega + \operatorname{sign}(\omega)\Big[F_c^{\pm}
#    + S^{\pm} e^{-(|\omega|/v_s)^{\delta}}\Big] \quad (\omega \ne 0), $$
#
# with the inertia $I$ (`inertia`) [kg m²], the offset $o$ (`offset`) [N m], the viscous
# coefficients $b^+$, $b^-$ (`friction.viscous_pos`, `_neg`) [N m s/rad], the Coulomb levels
# $F_c^+$, $F_c^-$ (`coulomb_pos`, `_neg`) [N m], the Stribeck excesses $S^\pm = F_s^\pm -
# F_c^\pm$ over the Stribeck velocity $v_s$ [rad/s] with exponent $\delta$ [-] (`stribeck_*`),
# $+$ for $\omega > 0$ and $-$ for $\omega < 0$, all positive magnitudes; at rest the joint
# holds while $|T_m - o|$ stays below the breakaway level $F_c^\pm + S^\pm$ (a file may add
# the excess of a plain static-friction law, `static_*`; 0 here).  Around it the
# file gives the loop: the sample time $T_s$ (`sample_time`) [s], one encoder count $\Delta$
# (`encoder_resolution`) [rad], the torque limit $T_{max}$ (`max_torque`) [N m].  A linear
# axis reads N, m, kg instead.  The paper's actuator ships as one (generated from
# [`fricctl.params`](#fricctl.params), the values of [Chapter 1](01_actuator_and_stick_slip)):

# %%
paper = JointModel.load(paper_actuator_file())
print(f"{paper.units} joint, I = {paper.inertia:.4g} kg m^2, Ts = {paper.sample_time} s, "
      f"Tmax = {paper.max_torque:.4g} N m, one count = {paper.encoder_resolution:.3g} rad")
for key, prov in paper.provenance.items():
    print(f"  {key:28s} {prov.source:10s} {prov.note}")
assert paper.provenance["friction.viscous_pos"].source == "paper"
assert paper.provenance["friction.coulomb_pos"].source == "assumption"
chapter1 = paper_actuator()  # the same numbers as Chapter 1's parameters
fr = paper.friction
assert (paper.inertia, paper.sample_time, paper.max_torque) == (
    chapter1.total_inertia, chapter1.sample_time, chapter1.max_torque)
assert (fr.viscous_pos, fr.coulomb_pos, fr.stribeck_velocity) == (
    chapter1.viscous, chapter1.coulomb, chapter1.stribeck_velocity)
assert np.isclose(fr.coulomb_pos + fr.stribeck_pos, chapter1.static, rtol=1e-12)
assert paper.offset == 0.0 and paper.load_inertia == 0.0  # rigid, no offset
assert fr.static_excess_pos == 0.0 and fr.breakaway(+1) == fr.coulomb_pos + fr.stribeck_pos

# %% [markdown]
# A model file is read strictly: a missing or unknown key, another version, NaN or a negative
# inertia is an error that names the key (the command line prints it on one line and exits
# with code 2), never a silently repaired model.

# %%
bad = Path(WORK.name) / "bad.json"
bad.write_text(paper_actuator_file().read_text().replace('"inertia": 0.00', '"inertia": -0.00'))
try:
    JointModel.load(bad)
except ValueError as exc:
    print("refused:", exc)
    assert "inertia must be > 0" in str(exc)

# %% [markdown]
# ## 2. The records
# EMPS (Janot, Gautier & Brunot 2019) is a real electro-mechanical positioning system: a DC
# motor driving a ball screw, in closed loop at 1 kHz.  `DATA_EMPS.mat` is for
# identification, `DATA_EMPS_PULSES.mat` (the same trajectory plus force pulses) for
# validation.  The data are not shipped: set `FRICCTL_DATA` (see
# [`fricctl.datasets.emps`](#fricctl.datasets.emps)).
# The motor force is `gtau * vir` (`vir` is the controller's output in volts).

# %%
try:
    est, val = emps(kind="estimation"), emps(kind="validation")
except FileNotFoundError as exc:
    est = val = None
    print("EMPS data not available, the rest of this chapter is skipped:",
          str(exc).splitlines()[0][:120])

if est is not None:
    run = est.run
    print(f"{run.source}: {run.n_samples} samples at {run.sample_time:g} s, force "
          f"{run.torque.min():.1f} .. {run.torque.max():.1f} N, one count = "
          f"{run.encoder_grid():.3g} m")
    n_rest = int(np.count_nonzero(at_rest(run.position)))
    print(f"samples at rest (encoder still for 2 samples each side): {n_rest}")
    assert run.units == "linear" and n_rest == 0 and abs(run.sample_time - 1e-3) < 1e-9

# %% [markdown]
# **The axis never rests.**  There is no breakaway in these records: nothing in them says
# what the friction does below the Coulomb level, where the paper's compensator does its
# most delicate work ([Chapter 5](05_open_loop_compensation_and_dead_zone)).  Keep this in
# mind; it decides step 5.
#
# ## 3. Identify, and write the model file
# The benchmark's IDIM-LS gives the published estimates with their standard deviations.
# Its model, per sample $k$, is the joint equation read backwards
# ([Chapter 3](03_identifying_friction), [its model](#eq-idim); [`idim_ls`](#fricctl.identify.idim_ls)):
#
# <a id="eq-emps-idim"></a>
#
# $$ F_{m,k} = M\,\ddot q_k + F_v\,\dot q_k + F_c\,\operatorname{sign}(\dot q_k) + o
#    + \varepsilon_k, $$
#
# with the motor force $F_{m,k}$ [N], the moving mass $M$ [kg], the viscous coefficient
# $F_v$ [N s/m], the Coulomb level $F_c$ and the offset $o$ [N].  Its recipe: the position
# through a zero-phase 4th-order Butterworth low-pass at 100 Hz, central differences for
# $\dot q$ [m/s] and $\ddot q$ [m/s²], the first 49 samples dropped; then each column of the
# regressor $X = [\ddot q \;\; \dot q \;\; \operatorname{sign}\dot q \;\; 1]$ and the force
# $y$ low-pass filtered and kept one sample in 10 (decimation $D$, "parallel filtering",
# which removes the noise above the dynamics without shifting any column against the
# others), and least squares on what remains:
#
# <a id="eq-emps-least-squares"></a>
#
# $$ \hat\theta = \arg\min_{\theta} \lVert D y - (D X)\,\theta \rVert_2^2, \qquad
#    \theta = (M, F_v, F_c, o), \qquad
#    \sigma_j = \hat\sigma\sqrt{\big[\big((DX)^\top DX\big)^{-1}\big]_{jj}}, $$
#
# $\hat\sigma$ the standard deviation of the residual.  The identified values become the
# model file's inertia, friction and offset, each with its standard deviation.

# %%
if est is not None:
    res = idim_ls(run)
    print(res.report())
    model = JointModel.from_estimates(
        res.parameters, std=dict(zip(res.names, res.std)), units="linear",
        source="IDIM-LS on DATA_EMPS.mat", note="IDIM-LS, EMPS recipe",
        sample_time=run.sample_time, encoder_resolution=run.encoder_grid())
    path = model.save(Path(WORK.name) / "emps.json")
    model = JointModel.load(path)
    # published IDIM-LS values (EMPS_Description.pdf sec. 3.4), 4 decimals
    published = {"inertia": 95.1089, "viscous": 203.5034, "coulomb": 20.3935, "offset": -3.1648}
    assert {k: round(x, 4) for k, x in res.parameters.items()} == published
    # the equation above by hand, with the public pieces and numpy's lstsq
    filt = butterworth_central(run.t, run.position, cutoff=100.0, order=4)
    X_full = regressor("coulomb_viscous", filt.velocity[49:], filt.acceleration[49:])
    X_dec = np.column_stack([decimate(col, 10) for col in X_full.T])
    y_dec = decimate(run.torque[49:], 10)
    theta, *_ = np.linalg.lstsq(X_dec, y_dec, rcond=None)
    sd = np.std(y_dec - X_dec @ theta, ddof=1) * np.sqrt(np.diag(np.linalg.inv(X_dec.T @ X_dec)))
    print(f"by hand: {X_full.shape[0]} rows decimated to {X_dec.shape[0]}; theta = "
          f"{np.array2string(theta, precision=4)}, std {np.array2string(sd, precision=4)}")
    assert np.allclose(y_dec, res.measured) and np.allclose(theta, res.estimates, rtol=1e-6)
    assert np.allclose(sd, res.std, rtol=1e-6)
    print(f"\n{path.name}: M = {model.inertia:.4f} kg +- {model.provenance['inertia'].std:.4f}, "
          f"max_torque {model.max_torque} (the records do not say where the drive saturates)")

# %% [markdown]
# ## 4. A PD loop for the axis
# The paper's design ([`design_pd`](#fricctl.design.design_pd)), on the model file's linear
# viscous plant $1/(s(Ms + F_v))$:
# rise time 0.05 s, damping 0.7, rate feedback, checked on the sampled loop at 1 kHz.
# With $T_c = K_p(r - q) - K_d\,\hat\omega$ the closed loop is
#
# <a id="eq-emps-loop"></a>
#
# $$ M s^2 + (F_v + K_d)\,s + K_p, \qquad \omega_n = \sqrt{K_p/M}, \qquad
#    \zeta = \frac{F_v + K_d}{2\sqrt{K_p M}}, $$
#
# with $K_p$ [N/m], $K_d$ [N s/m], $\omega_n$ [rad/s].  EMPS's own controller (a P
# position loop around a P velocity loop, gains $k_p$, $k_v$, drive gain $g_\tau$) is, in
# the same terms, $K_p = k_p k_v g_\tau$ and $K_d = k_v g_\tau$.

# %%
if est is not None:
    d = design_pd(model, rise_time=RISE_TIME, damping=DAMPING)
    print(d.report())
    assert np.isclose(np.sqrt(d.kp / model.inertia), d.wn, rtol=1e-9)
    assert np.isclose((model.viscous + d.kd) / (2 * np.sqrt(d.kp * model.inertia)), DAMPING, rtol=1e-9)
    kp_emps, kd_emps = est.kp * est.kv * est.gtau, est.kv * est.gtau
    wn_emps = np.sqrt(kp_emps / model.inertia)
    zeta_emps = (model.viscous + kd_emps) / (2 * np.sqrt(kp_emps * model.inertia))
    print(f"EMPS's own loop: Kp = {kp_emps:.4g} N/m, Kd = {kd_emps:.4g} N s/m "
          f"(wn = {wn_emps:.1f} rad/s, zeta = {zeta_emps:.2f})")
    assert kp_emps > 3 * d.kp and zeta_emps < 0.5  # "stiffer and less damped", below

# %% [markdown]
# EMPS's own loop is stiffer and less damped than our design (more than three times the
# stiffness, damping below 0.5): the benchmark tracks a fast trajectory.  Our slower design
# makes the friction's share of the error larger, which is what we want to look at.
#
# ## 5. Patterns and the network
# The paper's recipe, $T_{at} = F_m - M\hat{\alpha}$
# ([`record_patterns`](#fricctl.datasets.record_patterns)), with the model's mass and the
# polynomial-segment estimator (50-sample windows: a longer window fits across the
# bang-bang trajectory's acceleration steps).

# %% mystnb={"figure": {"caption": "The friction patterns $T_{at} = F_m - M \\hat\\alpha$ of the EMPS record against the velocity, with the law identified by IDIM-LS, offset included: the axis never rests, so every pattern lies on one of the two sliding branches."}}
if est is not None:
    pats = record_patterns(run, inertia=model.inertia, estimator_options=POLY,
                           velocity_quantum=model.velocity_quantum)
    law = model.friction.torque(pats.omega) + model.offset
    print(f"{len(pats)} patterns, {int(pats.at_rest.sum())} at rest; RMS distance to the "
          f"identified law {np.sqrt(np.mean((pats.friction - law) ** 2)):.2f} N")
    fig, ax = plt.subplots(figsize=(6.4, 3.6), layout="constrained")
    ax.plot(pats.omega, pats.friction, ".", ms=1, alpha=0.3, label="patterns $F_m - M\\hat\\alpha$")
    w = np.linspace(pats.omega.min(), pats.omega.max(), 400)
    ax.plot(w, model.friction.torque(w) + model.offset, "k", lw=1, label="identified law")
    ax.set_xlabel("velocity [m/s]")
    ax.set_ylabel("friction force [N]")
    ax.legend(loc="best", fontsize="small")
    plt.show()

# %% [markdown]
# Now the paper's network (2-4-1, trained on the full friction with Levenberg-Marquardt),
# once per seed.  Besides the fit, each net has a **gain at rest**
# $g = \partial \hat T_{at}/\partial T_m$ at $(T_m, \omega) = (0, 0)$: the compensated loop
# holds a torque at rest only for $s\,g < 1$ (Chapter 5).  Training is the slow step: each
# net is trained once and then read back from fricctl's disk cache of trained networks
# (`FRICCTL_CACHE`), keyed by the patterns, the settings and fricctl's own source code.

# %%
def paper_net(seed):
    """The paper's 2-4-1 net on the EMPS patterns for one seed (through the disk cache)."""
    rng = np.random.default_rng(seed)
    idx = (np.arange(len(pats)) if MAX_PATTERNS is None
           else np.sort(rng.choice(len(pats), MAX_PATTERNS, replace=False)))

    def train():
        res = TRAINERS["casadi"].train(pats.tm[idx], pats.omega[idx], pats.friction[idx],
                                       hidden=4, rng=rng, restarts=RESTARTS)
        return PipelineNet(net=res.net, history=res.history, pipeline="paper",
                           viscous_removed=0.0, certificate=None, used=idx)

    digest = hashlib.sha256(b"".join(x.tobytes() for x in (pats.tm, pats.omega, pats.friction)))
    key = {"what": "chapter 09: the paper's net on EMPS patterns", "seed": seed, "hidden": 4,
           "restarts": RESTARTS, "max_patterns": MAX_PATTERNS, "patterns": digest.hexdigest()}
    # trained on EMPS, a linear axis: the net says so (a compensator checks it against the model)
    net = cached_pipeline_net(key, train).net
    return net.replace(metadata={**net.metadata, "units": "linear"})


if est is not None:
    nets = {seed: paper_net(seed) for seed in SEEDS}
    fits = {s: fit_report(pats.friction, net=n, tm=pats.tm, omega=pats.omega).fit_percent
            for s, n in nets.items()}
    gains = {s: n.gain_at_rest() for s, n in nets.items()}
    for s in SEEDS:
        print(f"seed {s}: fit {fits[s]:.2f} % on all patterns, gain at rest {gains[s]:.3f}")
    spread_fit = max(fits.values()) - min(fits.values())
    print(f"fits within {spread_fit:.2f} points; gains at rest from {min(gains.values()):.2f} "
          f"to {max(gains.values()):.2f}")
    assert spread_fit < 1.0 and max(gains.values()) > 1.25 * min(gains.values())
    if not FAST:  # every pattern, three starts: all seeds put the gain at rest above 1
        assert min(gains.values()) > 1.0

# %% [markdown]
# **What the records fix, and what they do not.**  The seeds agree on the fit (within a
# point) and not on the gain at rest (the largest is more than a quarter above the
# smallest).  The patterns all lie on the two sliding branches, $\omega > 0$ and
# $\omega < 0$; at $\omega = 0$ there is none, and the net's slope in $T_m$ there is how it
# happens to bridge the jump between the branches.  With every pattern and three starts
# (the full run of this chapter) every seed puts it above 1 -- the compensated loop cannot
# hold a torque at rest (Chapter 5); with fewer patterns and one start (the fast run) it
# lands on either side of 1.  fricctl's own pipeline (`fricctl.nn.pipelines`, "fricctl") exists for
# exactly this number: it keeps the patterns at rest (where $T_{at} = T_m$ is the reaction),
# learns the nonlinear part, and *certifies* the gain at rest in a band below 1.  On EMPS it
# has nothing to learn it from:

# %%
if est is not None:
    try:
        pipeline("fricctl").train(pats, rng=np.random.default_rng(0))
        refused = ""
    except ValueError as exc:
        refused = str(exc)
    print("fricctl pipeline:", refused)
    assert "no pattern at rest" in refused
    fc, off = model.friction.coulomb_pos, model.offset
    print(f"at rest the axis holds forces from {off - fc:.1f} N to {off + fc:.1f} N "
          f"(Coulomb level {fc:.2f} N, offset {off:.2f} N)")
    assert (round(off + fc), round(fc - off)) == (17, 24)

# %% [markdown]
# To use it on your own axis, record what EMPS lacks: the axis held at rest under slow
# open-loop force steps below breakaway, both ways (here below $F_c \pm$ offset: about 17 N
# one way and 24 N the other), and add that record to the patterns
# (`fricctl patterns rest.csv DATA_EMPS.mat --model emps.json --out patterns.csv`).
#
# ## 6. Compensated and uncompensated steps of the identified axis
# A 0.5 mm step with the PD of Section 4, simulated on the model file (its mass, friction,
# offset, encoder and sample time; no saturation, since the model has no torque limit).
# Without compensation the axis stops wherever the PD force cannot overcome friction and
# offset: $\text{offset} - F_c < K_p e < \text{offset} + F_c$.

# %% mystnb={"figure": {"caption": "The step of Section 6 simulated on the model file without compensation, with Coulomb compensation and with the paper's net of each seed (dashed: the target): the first two stop in the same band, and each net stops the axis somewhere else."}}
if est is not None:
    ctrl = pd_control(d.kp, d.kd, step(STEP))
    band = (1e6 * (off - fc) / d.kp, 1e6 * (off + fc) / d.kp)
    runs = {"none": simulate_model(model, ctrl, duration=1.0),
            "Coulomb": simulate_model(model, ctrl, CoulombCompensator.symmetric(fc), duration=1.0)}
    for s in SEEDS:
        runs[f"NN seed {s}"] = simulate_model(model, ctrl, NNCompensator(nets[s], clip=True),
                                              duration=1.0)
    print(f"stopping band without compensation: {band[0]:.1f} .. {band[1]:.1f} um")
    for name, r in runs.items():
        e = 1e6 * (r.reference[-1] - r.q[-1])
        print(f"{name:>12}: final error {e:7.2f} um, force held {r.torque_motor[-1]:7.2f} N, "
              f"peak force {np.max(np.abs(r.torque_motor)):.0f} N")
    for name in ("none", "Coulomb"):
        e = 1e6 * (runs[name].reference[-1] - runs[name].q[-1])
        assert runs[name].stuck[-1] and band[0] <= e <= band[1]
    e_nn = [1e6 * (runs[f"NN seed {s}"].reference[-1] - runs[f"NN seed {s}"].q[-1]) for s in SEEDS]
    print(f"the nets stop the axis {min(e_nn):.1f} .. {max(e_nn):.1f} um from the target")
    assert max(e_nn) - min(e_nn) > 5.0
    held_at = [abs(runs[f"NN seed {s}"].torque_motor[-1] - off) / fc for s in SEEDS]
    print("force at the joint at rest / Coulomb level, per net:", np.round(held_at, 3))
    if not FAST:  # the full run's nets, gains above 1: at the edge of breakaway
        assert min(held_at) > 0.9
    fig, ax = plt.subplots(figsize=(6.4, 3.6), layout="constrained")
    for name, r in runs.items():
        ax.plot(r.t, 1e3 * r.q, lw=1, label=name)
    ax.axhline(1e3 * STEP, color="0.5", ls="--", lw=1)
    ax.set_xlabel("time t [s]")
    ax.set_ylabel("position q [mm]")
    ax.set_xlim(0, 0.4)
    ax.legend(loc="best", fontsize="small")
    plt.show()

# %% [markdown]
# The Coulomb compensator ($\hat F_c\,\mathrm{sign}(\hat\omega)$) changes nothing once the
# axis stops: at rest $\hat\omega = 0$ and its output is 0, so the axis stays in the
# uncompensated band.  The networks act at rest too, through the part of their map the
# records never constrained: where each one stops the axis, and the force it holds there,
# differ from seed to seed (by more than 5 um here) although their fits agreed within a
# point.  In the full run, where every gain at rest is above 1, every net holds the force
# at the joint within 10 % of the Coulomb level: at the edge of breakaway, one disturbance
# from slipping.  That behaviour was decided by the seed, not by the data -- on a real axis, record
# the axis at rest and certify the gain (Section 5) before you compensate.
#
# ## 7. Held out: the PULSES record
# Patterns from `DATA_EMPS_PULSES.mat`, which no net was trained on, and the identified
# four-parameter law on the same patterns.

# %%
if est is not None:
    held = record_patterns(val.run, inertia=model.inertia, estimator_options=POLY)
    law_fit = fit_report(held.friction, model.friction.torque(held.omega) + model.offset)
    law_train = fit_report(pats.friction, model.friction.torque(pats.omega) + model.offset)
    print(f"identified law: fit {law_fit.fit_percent:.2f} % (training record "
          f"{law_train.fit_percent:.2f} %), RMSE {law_fit.rmse:.2f} N")
    assert law_fit.fit_percent < law_train.fit_percent - 10
    held_fits = {}
    for s, net in nets.items():
        rep = fit_report(held.friction, net=net, tm=held.tm, omega=held.omega)
        held_fits[s] = rep.fit_percent
        print(f"net seed {s}: fit {rep.fit_percent:.2f} % (training record {fits[s]:.2f} %), "
              f"RMSE {rep.rmse:.2f} N, {rep.outside_envelope} outside the envelope")
    assert all(abs(f - law_fit.fit_percent) < 2.0 for f in held_fits.values())
    assert all(held_fits[s] < fits[s] - 10 for s in SEEDS)

# %% [markdown]
# On held-out data every net falls more than ten points below its training fit, to within
# two points of the four-parameter law: the net's extra accuracy on the training record
# does not transfer.  Part of the drop belongs to the record: its positions are low-pass
# filtered after acquisition (see the data README), which bends the acceleration estimate,
# and the law loses more than ten points too.
#
# ## 8. The compensator in C
# The controller calls one function per sample: `NAME_compensation(Tm, omega_hat, s, clip)`
# returns $s\,\hat T_{at}$ [N], with the envelope clip as an argument
# ([`c_source`](#fricctl.nn.c_source)); the header carries
# the units of the axis.  (`fricctl simulate --model ... --compensation nn --c-source
# NAME.c` writes both files for the net it simulated.)

# %%
if est is not None:
    header = c_header(nets[SEEDS[0]], name="emps_friction", units="linear")
    source = c_source(nets[SEEDS[0]], name="emps_friction", units="linear")
    print("\n".join(line for line in header.splitlines() if "(" in line and ";" in line))
    print(f"... emps_friction.c: {len(source.splitlines())} lines of C99 (only <math.h>)")
    assert "motor force tm [N], velocity omega [m/s]" in header

# %% [markdown]
# ## Summary
#
# * A model file holds the joint equation of paper Eq. (2), an offset, friction with one set
#   of coefficients per direction and the loop around it, each value with its unit and its
#   provenance; the paper's actuator ships as one, and a bad file is refused with the key
#   named.
# * On EMPS the IDIM-LS recipe reproduced the published estimates, rebuilt by hand from the
#   public pieces, and they became the model file's values with their standard deviations.
# * The PD designed for the identified axis is slower and better damped than the axis's own
#   loop; given that loop's rise time and damping, `design_pd` returns its gains
#   (Exercise 1).
# * The axis never rests, so the records fix the network's fit but not its gain at rest:
#   the seeds agree on the first and not on the second, and the fricctl pipeline refuses to
#   train without a pattern at rest.
# * In simulated steps Coulomb compensation changes nothing once the axis stops, while the
#   nets stop it at places and forces decided by the seed; on the held-out record every net
#   falls to within two points of the four-parameter law.
# * The compensator is exported as C99 with the axis's units in its header.

# %% [markdown]
# ## Exercises
#
# 1. Which rise time (0-100 %) and damping make `design_pd` return EMPS's own gains?
#    Compute them by hand from $K_p = M\omega_n^2$ and $K_d = 2\zeta\omega_n M - F_v$, then
#    check with `design_pd`.
# 2. Build the patterns with the paper's 200-sample polynomial windows
#    (`estimator_options={"window": 200, "overlap": 100}`) and with the identification's
#    Butterworth estimator (`estimator="butterworth_central"`).  How far does each lie from
#    the identified law, and why do long windows fail on this trajectory?
# 3. Compensate the step of Section 6 with the net whose gain at rest is largest, at a
#    scale $s < 1/g$.  Where does the axis stop now?

# %% tags=["solution"]
# Exercise 1.  wn from Kp, zeta from Kd (the formulas of Section 4); the 0-100 % rise time
# of that (wn, zeta), and design_pd with those specifications must return EMPS's gains.
if est is not None:
    tr_emps = normalized_rise_time(zeta_emps, "0-100") / wn_emps
    d_emps = design_pd(model, rise_time=tr_emps, damping=zeta_emps)
    print(f"rise time {1e3 * tr_emps:.2f} ms, damping {zeta_emps:.3f}: "
          f"Kp = {d_emps.kp:.6g} N/m (EMPS {kp_emps:.6g}), Kd = {d_emps.kd:.6g} N s/m (EMPS {kd_emps:.6g})")
    assert np.isclose(d_emps.kp, kp_emps, rtol=1e-9) and np.isclose(d_emps.kd, kd_emps, rtol=1e-9)

# %% tags=["solution"]
# Exercise 2.  Distance of each estimator's patterns to the identified law.
if est is not None:
    dist = {}
    for label, kw in (("polynomial, 50-sample windows", dict(estimator_options=POLY)),
                      ("polynomial, 200-sample windows",
                       dict(estimator_options={"window": 200, "overlap": 100})),
                      ("Butterworth + central differences", dict(estimator="butterworth_central"))):
        pp = record_patterns(run, inertia=model.inertia, **kw)
        dist[label] = np.sqrt(np.mean((pp.friction - model.friction.torque(pp.omega) - off) ** 2))
        print(f"{label:>34}: RMS distance to the law {dist[label]:.2f} N")
    assert dist["polynomial, 200-sample windows"] > 3 * dist["polynomial, 50-sample windows"]
# A 200-sample window (0.2 s) spans the bang-bang trajectory's acceleration steps: one
# polynomial cannot follow a step in acceleration, and the error lands in the patterns.

# %% tags=["solution"]
# Exercise 3.  The net with the largest gain at rest, scaled below 1/g.  Stuck at a measured
# error e (encoder reading y), the loop's force obeys Tm(k+1) = Kp e + s*T^(Tm(k), 0): with
# s*g < 1 that is a contraction, and it settles at the fixed point Tm = Kp e + s*T^(Tm, 0).
# The axis stays stuck while |Tm - o| <= Fc, so the edges of the stopping band are the
# errors whose fixed point is Tm = o -+ Fc:  e = (Tm - s*T^(Tm, 0)) / Kp  there.
if est is not None:
    s_max = max(SEEDS, key=lambda s: gains[s])
    scale = 0.8 / gains[s_max]
    comp = NNCompensator(nets[s_max], scale=scale, clip=True)
    r = simulate_model(model, ctrl, comp, duration=1.0)
    edges = np.array([off - fc, off + fc])  # force at the edges of breakaway [N]
    band_nn = 1e6 * (edges - scale * comp(edges, np.zeros(2))) / d.kp  # [um]
    e = 1e6 * (r.reference[-1] - r.q[-1])
    e_meas = 1e6 * (r.reference[-1] - r.q_meas[-1])
    held = r.torque_motor[-1]
    fixed = d.kp * 1e-6 * e_meas + scale * float(comp(held, 0.0))
    print(f"seed {s_max} (g = {gains[s_max]:.2f}) at s = {scale:.3f} (s*g = 0.8): stopping band "
          f"{band_nn[0]:.1f} .. {band_nn[1]:.1f} um (without compensation {band[0]:.1f} .. {band[1]:.1f} um)")
    print(f"final error {e:.2f} um (measured {e_meas:.2f} um), force held {held:.2f} N, "
          f"Kp e + s T^(Tm, 0) = {fixed:.2f} N, stuck {bool(r.stuck[-1])}")
    assert r.stuck[-1] and abs(fixed - held) < 1e-3 * fc  # at the fixed point of the stuck loop
    slack = 1e6 * model.encoder_resolution
    assert band_nn[0] - slack <= e_meas <= band_nn[1] + slack  # inside the predicted band
    g_mean = float(np.diff(comp(edges, np.zeros(2)))[0] / np.diff(edges)[0])
    print(f"the net's slope in Tm: {gains[s_max]:.2f} at Tm = 0, {g_mean:.2f} on average across "
          f"the band; band width {np.ptp(band_nn) / np.ptp(band):.2f} of the uncompensated one "
          f"(1 - s*mean slope = {1 - scale * g_mean:.2f})")
    assert g_mean < 0.5 * gains[s_max]  # far from linear: the slope at rest overstates it
# With s*g < 1 the loop holds a force at rest again (the fixed point above) and stops inside
# the band predicted from the net alone.  The band's width is set by the net's average slope
# across the band, not by its slope g at Tm = 0: the net is far from linear over +-Fc, so
# s < 1/g buys a fixed point at rest, not a chosen accuracy.  And the scale shrinks the
# sliding compensation by the same factor -- one number cannot fix both, which is why the
# fricctl pipeline certifies the gain at rest instead of scaling it.

# %% [markdown]
# ## References
#
# * [Gervini, Gomes & da Rosa 2003](#gervini2003): Sections 3-5, the chain identify, design,
#   learn, compensate.
# * [Janot, Gautier & Brunot 2019 (EMPS)](#janot2019emps): the records, the IDIM-LS recipe and
#   its published results, the axis's own controller.
# * [Fuller et al. 2021 (python-control)](#fuller2021control): the PD design.
# * [Andersson et al. 2019 (CasADi)](#andersson2019casadi): the least squares and the
#   Levenberg-Marquardt trainer.
#
# In fricctl: [`JointModel`](#fricctl.plant.JointModel), [`emps`](#fricctl.datasets.emps),
# [`record_patterns`](#fricctl.datasets.record_patterns), [`idim_ls`](#fricctl.identify.idim_ls),
# [`regressor`](#fricctl.identify.regressor), [`at_rest`](#fricctl.estimation.at_rest),
# [`butterworth_central`](#fricctl.estimation.butterworth_central),
# [`decimate`](#fricctl.estimation.decimate), [`design_pd`](#fricctl.design.design_pd),
# [`normalized_rise_time`](#fricctl.design.normalized_rise_time),
# [`fit_report`](#fricctl.nn.fit_report), [`c_source`](#fricctl.nn.c_source),
# [`NNCompensator`](#fricctl.compensators.NNCompensator),
# [`CoulombCompensator`](#fricctl.compensators.CoulombCompensator),
# [`simulate_model`](#fricctl.simulate.simulate_model).
