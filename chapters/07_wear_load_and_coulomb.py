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
# The paper attaches a link (0.0046 kg m²) and runs the actuator for 30 hours.
# Friction changes with wear; instead of retraining, the paper lowers the
# compensation scale to $s = 0.95$ and compares with the classic model-based
# compensator, $F_c\,\operatorname{sign}(\hat\omega)$.  On the virtual bench the aged
# actuator is modelled as the true friction scaled by $\varphi = 0.95$ -- an
# *assumption*, since the bench has no wear.  As in [Chapter 6](06_gain_design_and_closed_loop), a claim about a
# trained network is checked on several training seeds of both pipelines.  The
# chapter ends with a sweep over friction scale and link inertia: where does a net
# trained once keep the PD accuracy of 0.3 deg?

# %% [markdown]
# ## What you will learn
#
# * **Derive** the band a stuck joint stops in when both the compensation ($s$) and the
#   true friction ($\varphi$) are scaled, and **judge** whether lowering $s$ keeps the paper's
#   accuracy.
# * **Measure** the aged actuator with the link under scaled NN, Coulomb and no
#   compensation (Figs. 16-18), over training seeds.
# * **Explain** with a describing function when over-compensating Coulomb friction sustains
#   a limit cycle and when the joint simply sticks.
# * **Explain** why Fig. 18's stick-slip cannot appear with the paper's gains and amplitude.
# * **Judge** a net's robustness to wear and load as a share of seeds over a grid of
#   friction scales and link inertias.
#
# Symbols and units are collected on the [notation page](../notation).

# %%
import os
from concurrent.futures import ThreadPoolExecutor

import matplotlib.pyplot as plt
import numpy as np

from fricctl import controllers as ctl
from fricctl import figures
from fricctl import paper
from fricctl.bench.experiments import predicted_dead_zone
from fricctl.compensators import CoulombCompensator
from fricctl.design import design_pd
from fricctl.paper.common import (AGED_SCALE, COULOMB_AT_FC, COULOMB_AT_FS, last_window, sign_changes,
                                  uncompensated_dead_zone)
from fricctl.paper.table import aggregate_claims
from fricctl.params import PAPER_LINK_INERTIA, paper_actuator
from fricctl.simulate import simulate

FAST = os.environ.get("FRICCTL_FAST") == "1"
SEEDS = range(2 if FAST else 4)   # training seeds of each pipeline [-]
PIPELINES = ("fricctl", "paper")  # fricctl.nn.pipelines.PIPELINES
SCALES = (0.8, 1.0, 1.2) if FAST else (0.8, 0.9, 1.0, 1.1, 1.2)  # true / trained friction [-]
LINKS = (0.0, 0.0046) if FAST else (0.0, 0.0023, 0.0046, 0.0069, 0.0092)  # link inertia [kg*m^2]
LIMIT = np.deg2rad(paper.ACCURACY_DEG)  # the paper's 0.3 deg accuracy [rad]

# %%
p = paper_actuator()
nets = {(pipe, k): paper.train_paper_network(p, fast=FAST, seed=k, pipeline=pipe)
        for pipe in PIPELINES for k in SEEDS}
results = {key: {n: paper.FIGURES[n](net_run) for n in (16, 17, 18)} for key, net_run in nets.items()}
g = {key: n.trained.net.gain_at_rest() for key, n in nets.items()}
r16 = results[("fricctl", SEEDS[0])][16]
kp = r16.design.kp
# the paper's numbers the prose quotes: link, aged scale, the steps of Figs. 16-18
assert PAPER_LINK_INERTIA == 0.0046 and AGED_SCALE == 0.95 and r16.friction_scale == AGED_SCALE
assert np.isclose(r16.step, np.deg2rad(30.0))
assert results[("fricctl", SEEDS[0])][17].step == 0.08 and results[("fricctl", SEEDS[0])][18].amplitude == 0.1
print(f"PD of Figs. 16-17 (0.4 s, 0.85, with the link): Kp = {kp:.4f} N*m/rad, Kd = {r16.design.kd:.4f} N*m*s/rad")

# %% [markdown]
# ## 1. The aged actuator and its band
#
# Chapter 6 showed that a stuck compensated joint stops anywhere inside a band set by
# the loop's gain at rest ([Chapter 6's band](#eq-stuck-band)).  With the compensation scaled by $s$ and the true friction
# by $\varphi$ (breakaway $\varphi F_s$), the fixed point $T_m^\ast = K_p e/(1 - s g)$
# stays below the breakaway for
#
# <a id="eq-aged-band"></a>
#
# $$ |e_{ss}| \le \frac{\varphi F_s\,(1 - s g)}{K_p}, $$
#
# with $g$ the network's at-rest gain [-], $F_s$ the nominal breakaway torque [N m]
# and $K_p$ the gain of Figs. 16-17 [N m/rad].  Lowering $s$ to 0.95 widens the band:
# over the fricctl pipeline's certified range $0.98 \le g \le 0.99$,

# %%
phi = s = AGED_SCALE


def band_deg(gain, scale=s, friction=phi):
    """The stuck band phi Fs (1 - s g)/Kp of the Figs. 16-17 loop [deg]."""
    return np.rad2deg(friction * p.static * (1.0 - scale * gain) / kp)


print(f"s = {s}: band +-{band_deg(0.99):.2f} deg (g = 0.99) to +-{band_deg(0.98):.2f} deg (g = 0.98); "
      f"with s = 1: +-{band_deg(0.99, 1.0):.2f} to +-{band_deg(0.98, 1.0):.2f} deg")
assert band_deg(0.99) > paper.ACCURACY_DEG  # s = 0.95 no longer guarantees 0.3 deg
for key, net_run in nets.items():
    dz = predicted_dead_zone(net_run.trained.net, phi * p.static, scale=s).largest
    band_text = (f"predicted band +-{np.rad2deg(dz / kp):.2f} deg" if s * g[key] < 1.0 else
                 "no fixed point near rest: the torque winds up")
    print(f"{key[0]:8s} seed {key[1]}: g = {g[key]:.3f}, s*g = {s * g[key]:.3f}, {band_text}")
assert all(s * g[("paper", k)] > 1.0 for k in SEEDS)  # no fixed point: the torque winds up

# %% [markdown]
# Even at the certified gain, $s = 0.95$ makes the band wider than 0.3 deg: a small
# step of Fig. 17 ends inside 0.3 deg only if the joint happens to stop there, which
# depends on how it arrives -- on the seed and on the step.  The paper pipeline's
# $s g$ is above one in every seed: no fixed point, the torque winds up (a runaway).
#
# ## 2. The aged actuator: NN x 0.95, Coulomb at two levels, none (Fig. 16)
#
# PD designed for 0.4 s and damping 0.85 with the link, step of 30 deg.  The paper
# compensates Coulomb friction "at the dry friction identified experimentally" -- the
# breakaway level -- and at a smaller level.  Both are read here off the bench's records,
# as the paper would have, never from the bench's true parameters
# (`fricctl.paper.common.CoulombLevels`): the breakaway level $\hat F_s$ is
# the dead zone of the uncompensated dead-zone experiment (Chapter 5), the smaller one the
# Coulomb level $\hat F_c$ of a least-squares fit of $F_c\operatorname{sign}(\omega) + b\,\omega$
# on the pipeline's sliding friction patterns.  Both are scaled by $s$ like the network.
# The uncompensated and the Coulomb runs do not depend on the network's weights.

# %%
lv = r16.coulomb_levels
fs_true = uncompensated_dead_zone(p).dead_zone
print(f"breakaway read off the dead-zone experiment: {lv.breakaway:.4f} N*m (step {lv.breakaway_step:.4f}; "
      f"the bench's true Fs {p.static:.3f})")
print(f"Coulomb level of the fit on {lv.patterns} sliding patterns: {lv.coulomb:.4f} N*m (true {p.coulomb:.3f}), "
      f"b {lv.viscous:.4f} N*m*s/rad")
print(f"compensated: s*Fs^ = {r16.coulomb_level(COULOMB_AT_FS):.4f} N*m, s*Fc^ = "
      f"{r16.coulomb_level(COULOMB_AT_FC):.4f} N*m; aged breakaway phi*Fs = {phi * p.static:.4f} N*m")
assert lv.breakaway == fs_true and p.static < lv.breakaway <= p.static + lv.breakaway_step
assert abs(lv.coulomb / p.coulomb - 1) < 0.05  # the measuring chain's bias: a few %
assert r16.coulomb_level(COULOMB_AT_FS) > phi * p.static  # above the aged breakaway torque

# %% mystnb={"figure": {"caption": "The paper's Fig. 16 for the first fricctl seed: the aged actuator with the link, a PD step with the network scaled by $s$, with Coulomb compensation at the identified breakaway and Coulomb levels and without; positions (left) and motor torques $T_m$ (right).  Both Coulomb runs stick where they stop instead of oscillating."}}
print(f"{'pipeline':8s} seed {'NN x 0.95':>10s} {'Coul. Fs':>9s} {'Coul. Fc':>9s} {'none':>7s}  (|e_ss| [deg])")
for (pipe, k), res in results.items():
    e = {name: abs(np.rad2deg(x)) for name, x in res[16].steady_state_error.items()}
    print(f"{pipe:8s} {k:4d} {e[f'NN x {s:g}']:10.3f} {e[COULOMB_AT_FS]:9.3f} {e[COULOMB_AT_FC]:9.3f} "
          f"{e['none']:7.3f}")
e_coul = abs(r16.steady_state_error[COULOMB_AT_FC])
nn_closer = sum(abs(results[("fricctl", k)][16].steady_state_error[f"NN x {s:g}"]) < e_coul for k in SEEDS)
for key in (COULOMB_AT_FS, COULOMB_AT_FC):
    coul, cyc = r16.runs[key], r16.cycles[key]
    print(f"{key}: at rest at the end {bool(coul.stuck[-1])}, compensation {coul.friction_est[-1]:.3f} N*m, "
          f"{r16.reference_crossings[key]} reference crossing(s), {r16.torque_sign_changes[key]} Tm sign "
          f"changes in the last 0.5 s, last 1 s: {np.rad2deg(2 * cyc.amplitude):.4f} deg peak to peak")
    assert coul.stuck[-1] and coul.friction_est[-1] == 0.0 and r16.torque_sign_changes[key] == 0
    assert not cyc.sustained and r16.reference_crossings[key] < 2
print(f"in this run the fricctl NN ends closer than Coulomb at Fc^ in {nn_closer} of {len(SEEDS)} seeds")
for k in SEEDS:
    res16 = results[("fricctl", k)][16]
    assert abs(res16.steady_state_error[f"NN x {s:g}"]) < abs(res16.steady_state_error["none"])
figures.plot_fig16(r16)
plt.gcf().suptitle(f"fricctl pipeline, seed {SEEDS[0]}", fontsize="medium")
plt.show()

# %% [markdown]
# The paper's Coulomb compensator at the breakaway level oscillates around the reference
# (a limit cycle: the compensation switches sign with every reversal of $\hat\omega$).  On
# this bench it does *not*, at either level: $\operatorname{sign}(\hat\omega)$ is zero
# while the encoder reads no motion, so the moment the joint sticks the compensation
# switches off, and nothing drives a limit cycle -- at $s\hat F_s$ the joint overshoots
# (the compensation pushes along the motion while it slides) and stays wherever it
# stopped.  Chatter needs a velocity estimate that flickers at rest: encoder edge
# jitter, which this bench leaves out (exercise 1 shows that torque noise at the joint
# is not enough).  A flicker toward the reference would add the compensation to the
# loop's pull where the joint stopped:

# %%
for key in (COULOMB_AT_FS, COULOMB_AT_FC):
    push = r16.coulomb_level(key) + kp * abs(r16.steady_state_error[key])
    print(f"{key}: s*F^ + Kp*|e_ss| = {push:.4f} N*m against the aged breakaway {phi * p.static:.4f} N*m -> "
          + ("breaks loose again" if push > phi * p.static else "stays stuck"))
assert r16.coulomb_level(COULOMB_AT_FS) + kp * abs(r16.steady_state_error[COULOMB_AT_FS]) > phi * p.static
assert r16.coulomb_level(COULOMB_AT_FC) + kp * abs(r16.steady_state_error[COULOMB_AT_FC]) < phi * p.static

# %% [markdown]
# At the breakaway level one flicker breaks the joint loose again; at the identified
# Coulomb level it stays stuck: the paper's observation, *if* the velocity estimate
# flickers at rest.  On this noise-free bench nothing flickers, so the claim that the
# breakaway level oscillates fails and the claim that the smaller level does not passes
# with nothing to disappear (Section 5).  The scaled NN ends closer to the reference than
# no compensation in every fricctl seed (checked); whether it beats Coulomb on this
# noise-free bench depends on the seed (the count above).
#
# **What a describing function predicts.**  The paper compensated at the dry friction it
# identified, the breakaway level $\hat F_s$.  While the joint slides, compensation and
# friction add up to a relay $-(F_c - F_{comp})\,\operatorname{sign}(\hat\omega)$: above
# $F_c$ it *pushes* along the motion, a negative damping.  Its describing function
# $N(A) = 4(F_c - F_{comp})/(\pi A)$ against the sampled PD loop $H(z)$ from the
# compensation's torque to $\hat\omega$
# ([`fricctl.design.coulomb_limit_cycle`](#fricctl.design.coulomb_limit_cycle), python-control)
# predicts a cycle near $\sqrt{K_p/I}$ -- and whether the loop can keep it going: at each
# turning point $\hat\omega = 0$ switches the compensation off and static friction holds
# the joint unless the spring of the loop pulls harder, $K_p A_q > F_s$.

# %%
from fricctl.design import LinearLoop, coulomb_limit_cycle  # noqa: E402
from fricctl.friction import Coulomb, Viscous  # noqa: E402

loop16 = LinearLoop.of(r16.design)
for key in (COULOMB_AT_FC, COULOMB_AT_FS):
    level = r16.coulomb_level(key)
    cyc = coulomb_limit_cycle(loop16, compensation=level, coulomb=phi * p.coulomb, static=phi * p.static)
    assert cyc == r16.predicted[key]  # what the claims table reports
    print(f"{key} ({level:.4f} N*m): " + ("no cycle (the compensation does not exceed friction)" if cyc is None
          else f"A = {np.rad2deg(cyc.amplitude):.2f} deg at {cyc.frequency:.2f} Hz, pull Kp*A = {cyc.pull:.3f} "
          f"N*m vs Fs {cyc.static:.3f} N*m -> {'sustained' if cyc.sustained else 'sticks'}; simulated: "
          f"{r16.cycles[key].crossings} crossings in the last 1 s"))
cyc16 = r16.predicted[COULOMB_AT_FS]
assert r16.predicted[COULOMB_AT_FC] is None  # s*Fc^ is below the aged Fc: no pushing relay
assert not cyc16.sustained and cyc16.pull < 0.5 * phi * p.static
# the same prediction where it can hold: a P loop (no Kd) twice as stiff, simulated
loop_p = LinearLoop(kp=2.0, kd=0.0, inertia=p.inertia, viscous=p.viscous, sample_time=p.sample_time)
cyc_p = coulomb_limit_cycle(loop_p, compensation=p.static, coulomb=p.coulomb)
run_p = simulate(p, ctl.pd_control(2.0, 0.0, ctl.step(0.2)), CoulombCompensator.symmetric(p.static),
                 duration=8.0, friction=Viscous(p.viscous) + Coulomb(p.coulomb))
late = run_p.t > 4.0
amp_p = (run_p.q[late].max() - run_p.q[late].min()) / 2
print(f"P loop, Kp = 2: predicted {np.rad2deg(cyc_p.amplitude):.2f} deg at {cyc_p.frequency:.2f} Hz, "
      f"simulated {np.rad2deg(amp_p):.2f} deg")
assert cyc_p.sustained and abs(amp_p / cyc_p.amplitude - 1) < 0.03

# %% [markdown]
# On the paper's PD the predicted cycle is small and its pull is far below the breakaway
# level: the joint sticks at the first turning point, so over-compensating at $F_s$ gives an
# overshoot and a stop, not an oscillation -- *on a noise-free bench*.  Where the loop is
# stiff and undamped enough (the P loop above) the cycle is sustained, with the amplitude
# the describing function predicts (within 3 %).  The paper's oscillation thus needs what
# this bench leaves out: a velocity estimate that flickers at rest, or gains that keep
# $K_p A_q$ above $F_s$.
#
# **The sensing a real bench has: encoder edge jitter.**  A real encoder does not read a
# resting joint exactly: near a count's edge the reading flickers between two counts (the
# edge's position is uncertain by a fraction of a count: the quadrature state-width tolerance
# of an optical encoder, the rotor's vibration under the current loop).  A bench states its
# sensing as data (`fricctl.paper.benches`, its `sensing`): this
# chapter's bench is noise-free; the consistent bench has an edge jitter of
# $\sigma = 0.25$ count (white position noise added before quantisation) and a current-loop
# noise of 0.1 % of $T_{max}$.  Switch the jitter alone on here, over $\sigma$, on the first
# fricctl network (`PaperNetwork.sensed_on`): the Coulomb runs do not depend on the
# network's weights, so the seeds below are seeds of the noise.

# %%
JITTERS = (0.0, 0.1, 0.25, 0.5) if FAST else (0.0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5)  # [counts]
NOISE_SEEDS = range(3 if FAST else 5)  # seeds of the sensing noise [-]
net0 = nets[("fricctl", SEEDS[0])]
pair, cycles, rest = {}, {}, {}
for sigma in JITTERS:
    b = net0.bench.with_sensing("chapter 7: edge jitter alone", encoder_jitter=sigma)
    rs = [paper.fig16.run(net0.sensed_on(b, k)) for k in NOISE_SEEDS]
    pair[sigma] = (sum(paper.fig16.claim_fig16_coulomb_fs(r, b).passed for r in rs),
                   sum(paper.fig16.claim_fig16_coulomb_fc(r, b).passed for r in rs))
    cycles[sigma] = [r.cycles[COULOMB_AT_FS] for r in rs]
    rest[sigma] = [r.cycles[COULOMB_AT_FC].counts for r in rs]  # the smaller level's reading
    print(f"sigma {sigma:4.2f} count: breakaway level oscillates in {pair[sigma][0]}/{len(NOISE_SEEDS)} seeds, "
          f"the pair (oscillates, then disappears at s*Fc^) holds in {pair[sigma][1]}/{len(NOISE_SEEDS)}")
held = [sig for sig in JITTERS if pair[sig] == (len(NOISE_SEEDS),) * 2]
creep = [c.counts for c in cycles[0.25]]
print(f"the pair holds in every seed for sigma in [{min(held)}, {max(held)}] count; at 0.25 count the joint "
      f"at the breakaway level moves {min(creep)}-{max(creep)} counts peak to peak over the last second "
      f"({np.rad2deg(max(creep) * p.encoder_resolution):.3f} deg at most)")
assert pair[0.0] == (0, 0)  # noise-free: neither level oscillates, nothing to disappear
assert pair[0.1][0] < len(NOISE_SEEDS)  # a tenth of a count: too rare a flicker on this bench
assert 0.25 in held and 0.0 not in held and 0.1 not in held  # the consistent bench's jitter holds the pair
assert FAST or {0.2, 0.25, 0.3} <= set(held)  # the full grid: more than one sigma, not a knife edge
assert pair[0.5][0] == len(NOISE_SEEDS)  # half a count: the breakaway level still oscillates
rest_fc = rest[0.5]
print(f"sigma 0.50 count: at the smaller level the resting joint reads {min(rest_fc)}-{max(rest_fc)} counts peak "
      f"to peak over the last second (the claims read more than {paper.runaway.MOTION_COUNTS} as motion); "
      f"the pair holds in {pair[0.5][1]}/{len(NOISE_SEEDS)} seeds")
# where the pair fails at half a count, the resting joint's reading is past the criterion
assert pair[0.5][1] == len(NOISE_SEEDS) or max(rest_fc) > paper.runaway.MOTION_COUNTS
assert all(10 <= c < 100 for c in creep)  # tens of counts: hundredths of a degree

# %% [markdown]
# Noise-free, neither level oscillates.  With the consistent bench's edge jitter, 0.25 count,
# the joint at the breakaway level $s\hat F_s$ never comes to rest in any seed while at the
# smaller level $s\hat F_c$ it stays within the jitter's count or two: the paper's pair.  The
# range printed above is where it holds in every seed of the noise; the full run's finer grid
# finds it at 0.2, 0.25 and 0.3 count at least (asserted): not a knife edge.  The
# flicker does what the sums above said: at the breakaway level a flicker toward the
# reference adds the compensation to the loop's pull and breaks the joint loose, at the
# Coulomb level it does not.  On this bench the motion is a chatter of tens of counts
# (hundredths of a degree, one reference crossing): each flicker breaks the joint loose for
# a step and it sticks again.  On the consistent bench (Fc/Fs 0.6, the peak-time gains) the
# same jitter sustains a cycle of degrees across the reference (`benchmarks/README.md`).
# At a tenth of a count the flicker is too rare here.  At half a count the jitter itself nears
# the claims' own criterion (a resting joint may show 3 counts peak to peak): where a seed's
# resting reading exceeds it, the smaller level "oscillates", which says more about the
# criterion than about the joint -- in some seeds of the fast run's network; how many in this
# run is printed above, with the resting joint's reading (checked: where the pair fails at half a
# count, that reading exceeds the criterion).  Torque noise alone at the consistent bench's level
# moves no edge: it leaves both claims as they are (`tests/test_paper_sensing.py`).
#
# **The drive's torque ripple.**  A harmonic drive does not transmit a constant torque: its
# wave generator adds a torque periodic in the position, twice per motor revolution, so with
# the gear ratio $n = 100$ a period of $2\pi/(2n) = \pi/100$ rad at the joint.  The consistent
# bench gives its plant $A \sin(2\pi q/P)$ with $A$ = 1 % of $T_{max}$ (an assumed order of
# magnitude; the bench file says why) and $P = \pi/100$ rad.  Switch it on alone, and with
# the jitter, on this chapter's bench.  At rest the joint holds while
# $|T_m - A\sin(2\pi q/P)| \le \varphi F_s$, so the ripple moves the stuck band's edges by at
# most $A$ in torque: the band of Section 1 with $\varphi F_s + A$ in place of $\varphi F_s$
# bounds where a compensated joint can stop.

# %%
ripple = paper.benches.bench("consistent").sensing
A, P = ripple.torque_ripple, ripple.torque_ripple_period


def with_ripple(jitter=0.0, phase=ripple.torque_ripple_phase):
    """This chapter's bench with the consistent bench's ripple (and ``jitter`` [counts]); its
    phase [rad] the consistent bench's ("random": drawn for each run) unless given."""
    return net0.bench.with_sensing("chapter 7: the drive's ripple", encoder_jitter=jitter,
                                   torque_ripple=A, torque_ripple_period=P, torque_ripple_phase=phase)


pair_ripple = {}
for jitter in (0.0, 0.25):
    b = with_ripple(jitter)
    rs = [paper.fig16.run(net0.sensed_on(b, k)) for k in NOISE_SEEDS]
    pair_ripple[jitter] = (sum(paper.fig16.claim_fig16_coulomb_fs(r, b).passed for r in rs),
                           sum(paper.fig16.claim_fig16_coulomb_fc(r, b).passed for r in rs))
print(f"ripple A = {A:.4f} N*m ({100 * A / p.max_torque:.1f} % of Tmax, {100 * A / p.static:.1f} % of Fs), "
      f"period {P:.5f} rad = {P / p.encoder_resolution:.0f} counts")
print(f"Fig. 16's Coulomb pair (fs passes, fc passes) over {len(NOISE_SEEDS)} seeds: ripple alone "
      f"{pair_ripple[0.0]}, ripple and 0.25 count of jitter {pair_ripple[0.25]}")
# the ripple is deterministic: without the jitter nothing flickers at rest, the pair stays absent;
# with the jitter it holds as it did without the ripple
assert pair_ripple[0.0] == pair[0.0] == (0, 0)
assert pair_ripple[0.25] == pair[0.25] == (len(NOISE_SEEDS),) * 2
PHASES = (0.0, 0.5 * np.pi, np.pi, 1.5 * np.pi)  # where the ripple's period starts, at q = 0 [rad]
e17_ripple = {}
for k in SEEDS:
    n_k = nets[("fricctl", k)]
    dz_a = predicted_dead_zone(n_k.trained.net, phi * p.static + A, scale=s).largest
    for ph in PHASES:
        r = paper.fig17.run(n_k.sensed_on(with_ripple(phase=ph)))
        e17_ripple[(k, ph)] = abs(r.steady_state_error[f"NN x {s:g}"])
        assert e17_ripple[(k, ph)] <= dz_a / kp + p.encoder_resolution  # inside the band widened by A
        assert r.max_motion["none"] == 0.0  # Kp*0.08 + A is still below the aged breakaway
e17_none = {k: abs(results[("fricctl", k)][17].steady_state_error[f"NN x {s:g}"]) for k in SEEDS}
for k in SEEDS:
    print(f"Fig. 17, fricctl seed {k}: |e_ss| {np.rad2deg(e17_none[k]):.3f} deg without the ripple; with it, "
          "at phase 0, pi/2, pi, 3pi/2: " + ", ".join(f"{np.rad2deg(e17_ripple[(k, ph)]):.3f}" for ph in PHASES)
          + " deg")
r18_ripple = paper.fig18.run(net0.sensed_on(with_ripple()))
kp18 = r18_ripple.design.kp
print(f"Fig. 18 without compensation: Kp * 0.1 rad + A = {kp18 * r18_ripple.amplitude + A:.4f} N*m < Fs = "
      f"{p.static:.3f} N*m: peak |q| {r18_ripple.max_motion_without:.4f} rad")
shift = max(np.rad2deg(A * (1.0 - s * g[("fricctl", k)]) / kp) for k in SEEDS)
print(f"the ripple's share of the band, A (1 - s g)/Kp: at most {shift:.3f} deg over the fricctl seeds")
assert 0.01 <= shift < 0.1  # hundredths of a degree (the prose below)
# where the joint stops moves with the phase by more than the band widens: the ripple acts on the approach
spread = {k: np.ptp([e17_ripple[(k, ph)] for ph in PHASES]) for k in SEEDS}
print("spread of |e_ss| over the phases: " + ", ".join(f"{np.rad2deg(x):.3f}" for x in spread.values()) + " deg")
assert all(x > np.deg2rad(shift) for x in spread.values())
assert kp * results[("fricctl", SEEDS[0])][17].step + A < phi * p.static
assert kp18 * r18_ripple.amplitude + A < p.static and r18_ripple.max_motion_without == 0.0

# %% [markdown]
# The ripple changes neither Coulomb claim: it is a torque the joint receives, the same at
# the same position every time, so it cannot make the velocity estimate flicker at rest --
# the pair still needs the jitter, and holds with it as before.  A compensated joint still
# stops inside its band, widened by the ripple (checked): the network's fixed point
# $T_m^\ast = K_p e/(1 - s g)$ turns $A$ into at most $A(1 - s g)/K_p$ of band, hundredths
# of a degree at $s g \approx 0.94$ (printed).  But *where* in the band the approach ends
# moves with the ripple's phase by more than that, in every seed (checked; Fig. 17's
# $|e_{ss}|$ per seed and phase printed): the ripple pushes and holds the joint along its
# slow approach, and the band of $s = 0.95$ is wider than the paper's 0.3 deg (Section 1),
# so a claim judged on where the joint stops (`fig17-nn`, `fig16-nn`) changes with the
# phase, either way.  Where the drive's period starts is not kept from one experiment to
# the next, so the consistent bench draws the phase for each run (its `torque_ripple_phase`
# is `"random"`) and rates those claims over seeds: a fixed phase would decide them.
# Where nothing moves without compensation (Figs. 17 and 18 on this bench) the ripple's
# 0.014 N·m does not make the loop's request reach the breakaway torque (checked).  Its
# effect on every claim of the consistent bench, over seeds, is in `benchmarks/README.md`
# ("ripple alone").
#
# ## 3. A small step (Fig. 17)
#
# 0.08 rad with the same gains.  Without compensation $K_p \cdot 0.08$ rad is below the
# aged breakaway level, so nothing moves at all.  With compensation the error is
# bounded by the band of Section 1:

# %% mystnb={"figure": {"caption": "The small step of Fig. 17 for every seed, fricctl pipeline left and paper pipeline right (crosses: runaways): the steady-state error $|e_{ss}|$ with the network scaled by $s$, each net's predicted band (bar) and the paper's 0.3 deg (dashed).  Every fricctl seed stops inside its predicted band."}}
r17 = results[("fricctl", SEEDS[0])][17]
print(f"Kp * step = {kp * r17.step:.4f} N*m vs aged breakaway {phi * p.static:.4f} N*m")
assert kp * r17.step < phi * p.static
fig, ax = plt.subplots(figsize=(6.4, 3.2), layout="constrained")
for j, pipe in enumerate(PIPELINES):
    e17 = np.array([abs(np.rad2deg(results[(pipe, k)][17].steady_state_error[f"NN x {s:g}"])) for k in SEEDS])
    run_ok = np.array([results[(pipe, k)][17].wind_up.passed for k in SEEDS])
    passed = np.count_nonzero((e17 < paper.ACCURACY_DEG) & run_ok)
    print(f"{pipe:8s}: |e_ss| {np.round(e17, 3)} deg; < 0.3 deg without runaway in {passed} of {len(SEEDS)} seeds")
    x = 3 * j + np.arange(len(SEEDS))
    ax.plot(x[run_ok], e17[run_ok], "o", color=f"C{j}", label=pipe)
    ax.plot(x[~run_ok], e17[~run_ok], "x", color=f"C{j}", ms=8, label=f"{pipe}, runaway")
    for xi, k in zip(x, SEEDS):
        if s * g[(pipe, k)] >= 1.0:
            continue  # no band
        dz = predicted_dead_zone(nets[(pipe, k)].trained.net, phi * p.static, scale=s).largest
        ax.plot([xi - 0.3, xi + 0.3], [np.rad2deg(dz / kp)] * 2, "k-", lw=1)
    for k in SEEDS:
        assert results[(pipe, k)][17].max_motion["none"] == 0.0  # no compensation: never moves
ax.axhline(paper.ACCURACY_DEG, color="tab:red", ls="--", lw=1, label="0.3 deg")
ax.set_xticks([])
ax.set_xlabel("seeds (fricctl left, paper right); bar: predicted band")
ax.set_ylabel("|e_ss| [deg]")
ax.legend(fontsize="small")
plt.show()
for k in SEEDS:
    dz = predicted_dead_zone(nets[("fricctl", k)].trained.net, phi * p.static, scale=s).largest
    assert abs(results[("fricctl", k)][17].steady_state_error[f"NN x {s:g}"]) <= dz / kp + p.encoder_resolution

# %% mystnb={"figure": {"caption": "The paper's Fig. 17 for the first fricctl seed: the small step with the link under the network scaled by $s$, Coulomb compensation and none; positions (left) and motor torques $T_m$ (right).  Without compensation the joint never moves."}}
figures.plot_fig17(r17)
plt.show()

# %% [markdown]
# Every fricctl seed stops inside its predicted band (checked); whether that is also
# inside 0.3 deg is a matter of where, because the band is wider (Section 1).  The
# paper pipeline's runs wind up.
#
# ## 4. Tracking a sawtooth (Fig. 18)
#
# PD (0.22 s, 0.5) with the link, sawtooth of 0.1 rad.  The paper shows stick-slip
# without compensation.  **Not reproduced here, for a reason that needs no
# simulation:** the loop's largest torque request over the whole ramp is
# $K_p \cdot 0.1$ rad, below the breakaway torque, so the joint never moves.

# %% mystnb={"figure": {"caption": "The paper's Fig. 18 for the first fricctl seed: the sawtooth without compensation, where the joint never moves, and with the network, against the linear viscous simulation (left); the extra, a larger and slower ramp, stick-slips without compensation (right)."}}
r18 = results[("fricctl", SEEDS[0])][18]
kp18 = r18.design.kp
print(f"Kp = {kp18:.4f} N*m/rad: Kp * 0.1 rad = {kp18 * r18.amplitude:.4f} N*m < Fs = {p.static:.3f} N*m; "
      f"moving needs an amplitude above Fs/Kp = {p.static / kp18:.3f} rad")
print(f"without: peak |q| {r18.max_motion_without:.4f} rad, {r18.restarts_without} stick-slip cycles")
print(f"extra ({r18.extra_amplitude:g} rad over {r18.extra_period:g} s), without: "
      f"{r18.extra_restarts} stick-slip cycles")
assert kp18 * r18.amplitude < p.static and r18.max_motion_without == 0.0
assert 1.9 * r18.amplitude < p.static / kp18 < 2.1 * r18.amplitude and r18.extra_restarts >= 2
for pipe in PIPELINES:
    rms = [np.rad2deg(results[(pipe, k)][18].rms_deviation_with) for k in SEEDS]
    share = [results[(pipe, k)][18].slow_share for k in SEEDS]
    print(f"{pipe:8s} with NN: RMS deviation from the linear loop {np.round(rms, 2)} deg; share of the "
          f"slow sliding friction cancelled {np.round(share, 2)}")
figures.plot_fig18(r18)
plt.show()

# %% [markdown]
# Stick-slip needs an amplitude above $F_s/K_p$, about twice the paper's 0.1 rad
# (printed); the extra (right panel) shows it for a larger, slower ramp.  The
# [paper-consistency study](../paper_consistency) found no bench on which Fig. 18's
# stick-slip and the P design's rise time hold together under the usual reading of
# "rise time".  With compensation, the sawtooth is followed as closely as the
# compensation cancels the friction at the ramp's low speed: both the deviation and
# that share are printed per seed, and the claims table below gives the pass rate.
# The paper pipeline's runs wind up.
#
# ## 5. The claims of these figures, over seeds

# %%
per_seed = {key: paper.paper_claims(res, p) for key, res in results.items()}
stats = aggregate_claims(per_seed, {pipe: SEEDS[0] for pipe in PIPELINES})
by = {(st.id, st.pipeline): st for st in stats}
print(f"{'claim':14s} {'pipeline':8s} {'pass':>5s} {'median':>9s} {'min':>9s} {'max':>9s} unit   runaways")
for st in stats:
    print(f"{st.id:14s} {st.pipeline:8s} {st.n_passed:>2d}/{st.n_seeds:<2d} {st.median:9.3g} {st.minimum:9.3g} "
          f"{st.maximum:9.3g} {st.unit:6s} {st.runaway_failures}")
for cid in ("fig16-nn", "fig17-nn", "fig18-with"):
    assert by[(cid, "paper")].n_passed == 0 and by[(cid, "paper")].runaway_failures == len(SEEDS)
    assert by[(cid, "fricctl")].runaway_failures == 0
assert by[("fig16-coulomb-fs", "fricctl")].n_passed == 0 and by[("fig18-without", "fricctl")].n_passed == 0
for pipe in PIPELINES:  # the Coulomb claims do not involve the network: the same in every seed, no runaway
    assert by[("fig16-coulomb-fs", pipe)].n_passed == 0 and by[("fig16-coulomb-fc", pipe)].n_passed == 0
    assert by[("fig16-coulomb-fs", pipe)].runaway_failures == by[("fig16-coulomb-fc", pipe)].runaway_failures == 0

# %% [markdown]
# The paper pipeline fails every network-compensated claim by runaway ($s g > 1$).  The
# fricctl pipeline has no runaway; its pass rates are the table's.  Two claims fail
# for every network, for the reasons of Sections 2 and 4: the Coulomb limit cycle at the
# breakaway level (`fig16-coulomb-fs`) and Fig. 18's stick-slip without compensation
# (`fig18-without`).  The Coulomb claims carry the wind-up check of their own run: a
# limit cycle would not fail it (the compensation never exceeds the friction it
# estimates), a runaway would; here neither happens.  `fig16-coulomb-fc` ("at a smaller
# level the oscillation disappears") fails in every seed too: with no oscillation at the
# breakaway level there is nothing to disappear, and a claim that cannot fail reproduces nothing.
# Both are judged on the joint's position (two reference crossings after the step, or more
# than three counts of motion over the last second), not on the sign changes of $T_m$:
# a velocity estimate that flickers at rest makes $T_m$ change sign at any level while the
# joint stays still, and the oscillation the paper saw disappear is the joint's.
#
# ## 6. Robustness: friction scale x link inertia
#
# One net per seed, trained on the nominal actuator without link; the PD gains of
# Fig. 16 (designed for the 0.0046 kg m² link) kept fixed; the true friction scaled by
# 0.8-1.2 and the link changed ([`robustness_sweep`](#fricctl.paper.robustness_sweep)).
# Each link inertia is one job for an executor (here a
# thread pool; a `ProcessPoolExecutor` or a dask client's executor works the same),
# each job one batch simulation over the friction scales.  The sweep's error is the
# mean over the run's last 0.5 s: where the compensation does not match the friction
# the joint may still be hunting there (exercise 2 looks at that).

# %% mystnb={"figure": {"caption": "Share of the fricctl pipeline's seeds whose PD step ends within 0.3 deg, over the ratio of true to trained friction and the link inertia, with the Fig. 16 gains kept fixed: the robustness of a net trained once is this share at each point, not one seed's result."}}
sweeps = {}
with ThreadPoolExecutor(max_workers=2) as pool:
    for k in SEEDS:
        sweeps[k] = paper.robustness_sweep(nets[("fricctl", k)].trained.net, p, friction_scales=SCALES,
                                           link_inertias=LINKS, executor=pool,
                                           velocity=nets[("fricctl", k)].velocity)
print(sweeps[SEEDS[0]].report())
within = np.mean([sw.within for sw in sweeps.values()], axis=0)  # share of seeds < 0.3 deg
err = np.array([sw.error_nn for sw in sweeps.values()])            # (seed, link, scale) [rad]
print(f"share of seeds within 0.3 deg (rows: link inertia, columns: friction scale):\n{within}")
nominal = within[list(LINKS).index(PAPER_LINK_INERTIA), list(SCALES).index(1.0)]
print(f"at the nominal point (link 0.0046, scale 1): {nominal:.2f}; everywhere: {within.mean():.2f}")
med = {sc: np.rad2deg(np.median(err[:, :, j])) for j, sc in enumerate(SCALES)}
print("median |e_ss| over seeds and links by friction scale [deg]: "
      + ", ".join(f"{sc:g}: {m:.3f}" for sc, m in med.items()))
assert all(np.all(sw.error_nn < sw.error_none) for sw in sweeps.values())
assert med[max(SCALES)] > med[1.0]

fig, ax = plt.subplots(figsize=(5.4, 3.6), layout="constrained")
im = ax.imshow(within, origin="lower", cmap="RdYlGn", vmin=0, vmax=1, aspect="auto")
ax.set_xticks(range(len(SCALES)), [f"{x:g}" for x in SCALES])
ax.set_yticks(range(len(LINKS)), [f"{x:g}" for x in LINKS])
ax.set_xlabel("true / trained friction [-]")
ax.set_ylabel("link inertia [kg m²]")
fig.colorbar(im, ax=ax, label="share of seeds with |e_ss| < 0.3 deg")
plt.show()

# %% [markdown]
# Everywhere, for every seed, the compensated error is below the uncompensated one
# (checked).  The error grows with the friction scale (the median at the largest
# scale is above the nominal one, checked): with more friction than the net learned
# the compensation falls short and the joint stops further from the reference.  The
# map gives, per grid point, the share of seeds within 0.3 deg: a claim about the
# trained network is a claim about that share, not about one seed's table (printed
# above for the first seed).

# %% [markdown]
# ## Summary
#
# * With the compensation scaled by $s$ and the friction by $\varphi$, a stuck joint stops
#   within $\varphi F_s(1 - s g)/K_p$ of its reference.  Lowering $s$ widens the band: even at
#   the certified gain, $s = 0.95$ no longer guarantees the paper's accuracy, and the paper
#   pipeline's $s g$ stays above one (a runaway) in every seed.
# * The Coulomb compensator runs at the levels the bench's records give: the breakaway level
#   of the dead-zone experiment (the paper's) and the Coulomb level of a fit on the sliding
#   patterns.  On this noise-free bench $\operatorname{sign}(\hat\omega)$ switches the
#   compensation off when the joint sticks, so no limit cycle appears at either level; one
#   flicker of $\hat\omega$ at rest would break the joint loose again at the breakaway level
#   and not at the smaller one -- the paper's observation needs a velocity estimate that
#   flickers at rest.  The scaled NN ends closer to the reference than no compensation in
#   every fricctl seed.
# * Encoder edge jitter -- position noise before quantisation, the sensing a real bench has --
#   supplies that flicker: at 0.25 count (and, in the full run, at 0.2 and 0.3) the breakaway
#   level never rests and the smaller level does, in every seed of the noise; a tenth of a
#   count is too little, and at half a count
#   the claims' criterion starts to read the jitter itself as motion.
# * The harmonic drive's torque ripple (1 % of $T_{max}$, period $\pi/100$ rad) makes nothing
#   flicker -- the Coulomb pair still needs the jitter -- but moves where a slowly approaching
#   joint stops inside its band, with the ripple's phase, by far more than it widens the band:
#   a claim read on where the joint stops is then a rate over phases, which the consistent
#   bench draws for each run.
# * The describing function of an over-compensating relay predicts, on the paper's PD, a
#   cycle whose pull is far below the breakaway level -- an overshoot and a stop; on a stiff
#   P loop it predicts a sustained cycle, and the simulation matched its amplitude.
# * The small step of Fig. 17 never moves without compensation; with it, every fricctl seed
#   stops inside its predicted band.  Fig. 18's sawtooth never asks the loop for the
#   breakaway torque, so stick-slip without compensation needs a larger amplitude than the
#   paper's.
# * Over friction scale and link inertia the compensated error stays below the
#   uncompensated one everywhere and grows with the friction scale; robustness is reported
#   as the share of seeds within the accuracy at each grid point.

# %% [markdown]
# ## Exercises
#
# 1. Rerun Fig. 16 with white torque noise ([`simulate`](#fricctl.simulate.simulate)`(..., noise_std=0.003,
#    rng=np.random.default_rng(0))`, using `r16.runs["Coulomb at Fs"].info` for the setup).
#    Does the Coulomb compensator chatter now?  And the NN?
# 2. Sweep the compensation scale `s` (`robustness_sweep(..., compensation_scale=s)`)
#    at friction scale 1.2.  Which `s` restores the 0.3 deg accuracy, and what does
#    it cost at scale 0.8?
# 3. Redesign the PD for each link inertia (`design=` per row) instead of keeping the
#    Fig. 16 gains.  Which part of the failure was the inertia mismatch?

# %% tags=["solution"]
# Exercise 1.  White torque noise of 0.003 N*m at the joint, two noise seeds, the Fig. 16
# setup (link, friction x 0.95, the same PD).  Neither compensator chatters: once the joint
# sticks the noise is far below the margin to the breakaway torque, the encoder does not
# move, omega_hat stays 0 -- so sign(omega_hat) stays 0 and the net sees "at rest".  Chatter
# needs noise in the *measurement* (a flickering omega_hat), not at the joint.
info = r16.runs[COULOMB_AT_FS].info
net0 = nets[("fricctl", SEEDS[0])]
step30 = ctl.pd_control(info.kp, info.kd, ctl.step(r16.step))
for name, comp in (("Coulomb at Fs", CoulombCompensator.symmetric(lv.breakaway, scale=s)),
                   (f"NN x {s:g}", net0.compensator(s))):
    for noise_seed in (0, 1):
        run = simulate(info.params, step30, comp, duration=3.0, friction=info.friction_model,
                       noise_std=0.003, rng=np.random.default_rng(noise_seed))
        w = last_window(run)
        changes = sign_changes(run.torque_motor[w])
        print(f"{name:9s} noise seed {noise_seed}: {changes} Tm sign changes in the last 0.5 s, at rest "
              f"{run.stuck[w].mean():.0%} of it, e_ss {np.rad2deg(run.steady_state_error()):.3f} deg")
        assert changes == 0 and run.stuck[w].all()
assert 0.003 < 0.1 * phi * p.static  # the noise is a small fraction of the breakaway torque

# %% tags=["solution"]
# Exercise 2.  s at friction scales 0.8 and 1.2 (link 0.0046, the Fig. 16 gains), for every
# fricctl seed.  s above 1/g (about 1.01) is excluded: s*g >= 1 has no fixed point and winds
# the torque up.  Where the joint ends at rest, its error is inside the predicted band
# phi Fs (1 - s g)/Kp (checked); where the compensation does not match the friction the
# joint hunts (stick-slip in the last 0.5 s) and the "steady-state" error is a mean over
# that motion.  The band grows with the friction (phi Fs) and shrinks as s approaches 1/g
# (checked, seed by seed), so the largest s is the one that can keep 0.3 deg at friction
# x 1.2 -- whether its widest band over the seeds is inside 0.3 deg, and the errors measured,
# are printed below -- and s cannot go past 1/g to make up for more wear.  The same s at
# friction x 0.8 over-compensates: read the "at rest" count there (a joint that is not at rest
# hunts).  Retraining, not rescaling, is the answer to wear that s cannot reach.
S_VALUES = (0.9, 0.95, 1.0)
pl = p.with_link()
table, bands = {}, {}
for k in SEEDS:
    net_k = nets[("fricctl", k)]
    assert max(S_VALUES) < 1.0 / g[("fricctl", k)] < 1.025  # "about 1.01"
    for scale in S_VALUES:
        for fr in (0.8, 1.2):
            run = simulate(pl, step30, net_k.compensator(scale), duration=3.0,
                           friction=pl.friction_model().scaled(fr))
            w = last_window(run)
            e = abs(run.steady_state_error())
            dz = predicted_dead_zone(net_k.trained.net, fr * p.static, scale=scale).largest / kp
            at_rest = bool(run.stuck[w].all())
            table[(k, scale, fr)] = (e, at_rest)
            bands[(k, scale, fr)] = dz
            if at_rest:
                assert e <= dz + p.encoder_resolution  # a joint at rest is inside its band
for k in SEEDS:
    for fr in (0.8, 1.2):
        assert bands[(k, 0.9, fr)] > bands[(k, 0.95, fr)] > bands[(k, 1.0, fr)]  # shrinks with s
    for scale in S_VALUES:
        assert bands[(k, scale, 1.2)] > bands[(k, scale, 0.8)]  # grows with the friction
for scale in S_VALUES:
    for fr in (0.8, 1.2):
        es = [table[(k, scale, fr)][0] for k in SEEDS]
        rest = sum(table[(k, scale, fr)][1] for k in SEEDS)
        ok = sum(e < LIMIT for e in es)
        band = max(bands[(k, scale, fr)] for k in SEEDS)
        print(f"s = {scale:4.2f}, friction x {fr}: |e_ss| {np.round(np.rad2deg(es), 3)} deg, at rest in "
              f"{rest}/{len(SEEDS)} seeds, < 0.3 deg in {ok}/{len(SEEDS)}; widest predicted band "
              f"+-{np.rad2deg(band):.2f} deg")

# %% tags=["solution"]
# Exercise 3.  Redesign the PD (0.4 s, 0.85) for each link inertia and sweep again.  At the
# 0.0046 kg*m^2 link the redesign is the Fig. 16 design itself, so that row cannot change
# (checked, to rounding).  For a lighter link the same specs give a smaller Kp, hence a
# wider band phi Fs (1 - s g)/Kp, so the redesign does *not* help: the inertia mismatch
# was not the cause of the misses; in this run (both modes) the redesigned grid is within
# 0.3 deg less often than the fixed one (checked).  The share of grid points within
# 0.3 deg per seed:
shares = {"fixed gains": [], "redesigned": []}
for k in SEEDS:
    net_k = nets[("fricctl", k)].trained.net
    rows = []
    for link in LINKS:
        d_link = design_pd(p.with_link(link), rise_time=0.4, damping=0.85)
        rows.append(paper.robustness_sweep(net_k, p, friction_scales=SCALES, link_inertias=(link,),
                                           design=d_link, velocity=nets[("fricctl", k)].velocity).error_nn[0])
    redesigned = np.array(rows)
    i_nom = list(LINKS).index(PAPER_LINK_INERTIA)
    np.testing.assert_allclose(redesigned[i_nom], sweeps[k].error_nn[i_nom], atol=1e-9)
    shares["fixed gains"].append(np.mean(sweeps[k].error_nn < LIMIT))
    shares["redesigned"].append(np.mean(redesigned < LIMIT))
for name, sh in shares.items():
    print(f"{name:12s}: share of the grid within 0.3 deg per seed {np.round(sh, 2)}, mean {np.mean(sh):.2f}")
kp_light = design_pd(p.with_link(0.0), rise_time=0.4, damping=0.85).kp
print(f"Kp without link {kp_light:.4f} N*m/rad vs Fig. 16's {kp:.4f} N*m/rad")
assert kp_light < kp and np.mean(shares["redesigned"]) < np.mean(shares["fixed gains"])

# %% [markdown]
# ## References
#
# * [Gervini, Gomes & da Rosa 2003](#gervini2003): the actuator with the SCARA link, Figs.
#   16-18.
# * [Armstrong-Hélouvry, Dupont & Canudas de Wit 1994](#armstrong1994survey): Coulomb
#   compensation, hunting and limit cycles.
# * [Gelb & Vander Velde 1968](#gelb1968): the describing function of a relay.
# * [Fuller et al. 2021 (python-control)](#fuller2021control).
#
# In fricctl: [`train_paper_network`](#fricctl.paper.train_paper_network),
# [`paper_claims`](#fricctl.paper.paper_claims),
# [`aggregate_claims`](#fricctl.paper.aggregate_claims),
# [`robustness_sweep`](#fricctl.paper.robustness_sweep),
# [`predicted_dead_zone`](#fricctl.bench.experiments.predicted_dead_zone),
# [`CoulombCompensator`](#fricctl.compensators.CoulombCompensator),
# [`design_pd`](#fricctl.design.design_pd), [`LinearLoop`](#fricctl.design.LinearLoop),
# [`coulomb_limit_cycle`](#fricctl.design.coulomb_limit_cycle),
# [`simulate`](#fricctl.simulate.simulate), [`plot_fig16`](#fricctl.figures.plot_fig16),
# [`plot_fig17`](#fricctl.figures.plot_fig17), [`plot_fig18`](#fricctl.figures.plot_fig18).
