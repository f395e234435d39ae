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
# # Chapter 5 -- Open-loop compensation and the dead zone
#
# *Gervini, Gomes & da Rosa (2003): the compensation law (Eq. 3) and the open-loop
# experiments of Figs. 9 and 10.*
#
# The compensator adds the network's friction estimate to the control torque.  Before
# closing a position loop, the paper tests it open loop: a sinusoidal control torque near
# the breakaway level (Fig. 9), and one *inside* the dead zone, at 10 % of the maximum
# torque (Fig. 10).  This chapter first works out what the compensated loop does while the
# joint is stuck -- a fixed point that sets the dead zone and decides between a joint that
# follows its control torque and one that runs away -- and then repeats both experiments
# with the two training pipelines of [Chapter 4](04_neural_network), over several training seeds.

# %% [markdown]
# ## What you will learn
#
# * **Explain** the compensation law of paper Eq. (3) and the inner loop it closes: the net
#   reads the motor torque the compensator commanded one sample earlier.
# * **Derive** the fixed point of the stuck loop, $T_m^\star = T_c/(1 - s g)$, the
#   compensated dead zone $D = F_s\,(1 - s g)$, and why $s g \ge 1$ runs away.
# * **Measure** the dead zone of both training pipelines open loop (Figs. 9 and 10) over
#   training seeds, and compare it with the fixed point's prediction from the net alone.
# * **Judge** a compensator by runaway checks (wind-up, reversal, coast) as well as by its
#   dead zone.
# * **Design** the pair $(s, g)$ against the band a stuck position loop may stop in.
#
# Symbols and units are collected on the [notation page](../notation).

# %%
import os
import sys

import matplotlib.pyplot as plt
import numpy as np

from fricctl import figures
from fricctl import paper
from fricctl.bench.experiments import dead_zone, paper_gains, predicted_dead_zone
from fricctl.nn.pipelines import DEFAULT_GAIN_BAND
from fricctl.paper.runaway import LINEAR_TOLERANCE
from fricctl.params import paper_actuator

FAST = os.environ.get("FRICCTL_FAST") == "1"
SEEDS = range(2 if FAST else 4)   # training seeds of each pipeline [-]
PIPELINES = ("paper", "fricctl")  # fricctl.nn.pipelines.PIPELINES

# %%
p = paper_actuator()
Fs = p.static
nets = {(pipe, k): paper.train_paper_network(p, fast=FAST, seed=k, pipeline=pipe)
        for pipe in PIPELINES for k in SEEDS}
g = {key: n.net.gain_at_rest() for key, n in nets.items()}
print(f"breakaway Fs = {Fs:.3f} N*m = {100 * Fs / p.max_torque:.1f} % of Tmax = {p.max_torque:.3f} N*m")
for pipe in PIPELINES:
    gs = [g[(pipe, k)] for k in SEEDS]
    print(f"{pipe:8s} pipeline, {len(gs)} seeds: at-rest gain g = {np.median(gs):.3f} "
          f"(min {min(gs):.3f}, max {max(gs):.3f})")
assert all(g[("paper", k)] > 1 for k in SEEDS)
assert all(DEFAULT_GAIN_BAND[0] <= g[("fricctl", k)] <= DEFAULT_GAIN_BAND[1] for k in SEEDS)

# %% [markdown]
#
# **Which bench, which sensing, which velocity.**  This chapter runs on the `literal` bench:
# the paper's numbers with fricctl's first readings (0-100 % rise time), noise-free -- an
# encoder that reads exactly, no current-loop noise -- so that every difference below is the
# compensation's.  `fricctl reproduce` judges the paper on the `consistent` bench by default,
# with the sensing a real bench has; both benches' counts are on the
# [reproduction page](../reproduction).  The paper's pipeline feeds its network the
# backward-difference velocity; the fricctl pipeline the direction-confirmed one
# ([`nn_confirmed`](#fricctl.compensators.ConfirmedNNCompensator)), which reads an encoder count
# that goes against the last one as rest (a flicker goes back and forth; motion, however slow,
# goes on the way it went) -- on this noise-free bench it differs from the backward difference
# only on the first count after a reversal.

# %%
for pipe in PIPELINES:
    n0 = nets[(pipe, SEEDS[0])]
    print(f"{pipe:8s}: bench {n0.bench.name}, sensing {'noise-free' if n0.bench.sensing.noise_free else 'on'}, "
          f"velocity {n0.velocity}, compensator {type(n0.compensator()).__name__}")
    assert n0.bench.name == "literal" and n0.bench.sensing.noise_free
assert {pipe: nets[(pipe, SEEDS[0])].velocity for pipe in PIPELINES} == {
    "paper": "backward-difference", "fricctl": "confirmed"}

# %% [markdown]
# ## 1. The compensated loop (paper Eq. 3)
#
# At sample $k$ the controller computes a control torque $T_c(k)$ [N m]; the compensator
# adds a fraction $s$ [-] of the net's friction estimate $\hat T_{at}$ [N m] and commands,
# for the next sample,
#
# <a id="eq-compensation"></a>
#
# $$ T_m(k+1) = T_c(k) + s\,\hat T_{at}(k), \qquad
#    \hat T_{at}(k) = \operatorname{net}\big(T_m(k),\ \hat\omega(k)\big), $$
#
# with $T_m$ the motor torque [N m] (held by the ZOH for one sampling period $T_s$ [s])
# and $\hat\omega$ the velocity estimated from the encoder [rad/s].  The net reads the
# motor torque the compensator itself commanded one sample earlier: the loop of
# [the block diagram below](#fig-compensation-loop) has an inner feedback, $T_m \to z^{-1} \to$ net $\to s \to T_m$, that no
# friction law has.  At rest it is the only loop left.
#
# The at-rest gain $g = \partial\hat T_{at}/\partial T_m$ at $\omega = 0$ [-] of the two
# pipelines is printed above: above one in every seed of the paper's literal recipe,
# inside the certified band $0.98 \le g \le 0.99$ in every seed of fricctl's
# (Chapter 4 explains both).

# %% tags=["hide-input"] mystnb={"figure": {"caption": "The compensated loop of paper Eq. (3), open loop: the commanded motor torque $T_m$ feeds back into the net through a one-sample delay.", "name": "fig-compensation-loop"}}
fig, ax = plt.subplots(figsize=(8, 2.9), layout="constrained")
figures.plot_compensation_loop(ax)
plt.show()

# %% [markdown]
# ## 2. The stuck loop and its fixed point
#
# While the joint is stuck the encoder does not move, $\hat\omega = 0$, and
# [the compensation law](#eq-compensation) becomes an iteration in $T_m$ alone:
#
# <a id="eq-stuck-loop"></a>
#
# $$ T_m(k+1) = T_c + s\,\hat T_{at}(T_m(k), 0). $$
#
# For a linear estimate $\hat T_{at} = g\,T_m$ it converges (for $|s g| < 1$) to the fixed point
#
# <a id="eq-fixed-point"></a>
#
# $$ T_m^\star = \frac{T_c}{1 - s g}, $$
#
# and the joint stays stuck as long as $T_m^\star < F_s$, the breakaway torque [N m].  The
# compensated dead zone and its reduction are therefore
#
# <a id="eq-dead-zone"></a>
#
# $$ D = F_s\,(1 - s g), \qquad \frac{F_s}{D} = \frac{1}{1 - s g}. $$
#
# For $s g \ge 1$ there is no stable fixed point at small torque: the loop is an
# integrator (or worse) and winds $T_m$ up by itself.  For the real, curved net the
# fixed points are where $s\,\hat T_{at}(T_m, 0)$ crosses the line $T_m - T_c$; the
# iteration climbs from $T_m = 0$ to the first stable crossing, and the joint breaks loose
# once none lies below $F_s$: $D = \max_{0 \le T_m \le F_s} \big(T_m - s\,\hat T_{at}(T_m, 0)\big)$
# ([`fricctl.bench.experiments.predicted_dead_zone`](#fricctl.bench.experiments.predicted_dead_zone)).

# %% mystnb={"figure": {"caption": "Fixed points of the stuck loop, first seed of each pipeline: where the estimate at rest $\\hat T_{at}(T_m, 0)$ crosses the lines $T_m - T_c$ for three control torques $T_c$ (filled dots stable, open dots unstable; grey line: $F_s$).  The paper pipeline's curve leaves the origin above the identity ($g > 1$) and latches a torque at $T_c = 0$; the fricctl pipeline's stays just below it.", "name": "fig-fixed-points"}}
def fixed_points(net, tc, s=1.0, n=4001):
    """Torques 0 <= Tm <= Fs where s*net(Tm, 0) = Tm - tc, and whether each is stable [N*m]."""
    tm = np.linspace(-0.01 * Fs, Fs, n)  # from just below 0: a root at Tm = 0 is a sign change
    gap = s * net(tm, np.zeros(n)) - (tm - tc)
    i = np.flatnonzero(np.sign(gap[:-1]) != np.sign(gap[1:]))
    roots = tm[i] - gap[i] * (tm[i + 1] - tm[i]) / (gap[i + 1] - gap[i])
    return roots, gap[i] > gap[i + 1]  # stable where the curve crosses the line from above


def stuck_iteration(net, tc, s=1.0, steps=3000):
    """Tm after ``steps`` samples of the stuck loop Tm <- tc + s*net(Tm, 0) from Tm = 0 [N*m]."""
    tm = 0.0
    for _ in range(steps):
        tm = tc + s * float(net(tm, 0.0))
    return tm


# The torque each net latches with Tc = 0, the joint at rest (stuck as long as |Tm| < Fs).
lat = np.array([stuck_iteration(nets[("paper", k)].net, 0.0) for k in SEEDS])
print(f"paper pipeline, Tc = 0: the stuck loop latches |Tm| = {np.median(np.abs(lat)):.3f} N*m "
      f"(min {np.abs(lat).min():.3f}, max {np.abs(lat).max():.3f}) over {len(SEEDS)} seeds")
assert np.all((np.abs(lat) > 0.05) & (np.abs(lat) < Fs))  # a latched torque in every seed
lat_f = np.array([stuck_iteration(nets[("fricctl", k)].net, 0.0) for k in SEEDS])
print(f"fricctl pipeline, Tc = 0: largest |Tm| {np.abs(lat_f).max():.1e} N*m")
assert np.all(np.abs(lat_f) < 1e-6)
for k in SEEDS:  # fricctl: the only fixed point at Tc = 0 is Tm = 0, and it is stable
    roots, stable = fixed_points(nets[("fricctl", k)].net, 0.0)
    assert roots.size == 1 and abs(roots[0]) < 1e-3 and stable[0]

fig, axes = plt.subplots(1, 2, figsize=(9, 3.6), sharey=True, layout="constrained")
tm = np.linspace(0.0, Fs, 400)
for ax, pipe in zip(axes, PIPELINES):
    net = nets[(pipe, SEEDS[0])].net
    ax.plot(tm, net(tm, np.zeros_like(tm)), lw=2, label=r"$\hat T_{at}(T_m, 0)$")
    for tc in (0.0, 0.001, 0.01):
        ax.plot(tm, tm - tc, lw=0.9, ls="--", label=rf"$T_m - T_c$, $T_c$ = {1e3 * tc:g} mN m")
        roots, stable = fixed_points(net, tc)
        ax.plot(roots[stable], roots[stable] - tc, "ko", ms=5)
        ax.plot(roots[~stable], roots[~stable] - tc, "o", mfc="white", mec="k", ms=5)
    ax.axvline(Fs, color="0.5", lw=0.8)
    ax.set_title(f"{pipe} pipeline, seed {SEEDS[0]}: g = {g[(pipe, SEEDS[0])]:.3f}", fontsize="small")
    ax.set_xlabel(r"$T_m$ [N m]")
axes[0].set_ylabel("torque [N m]")
axes[1].legend(fontsize="x-small", loc="upper left")
plt.show()

# %% [markdown]
# In [the fixed points' figure](#fig-fixed-points), filled dots are stable fixed points, open dots unstable ones, the grey line is $F_s$; a
# line with no dot below $F_s$ is a control torque that breaks the joint loose.
# The paper pipeline's curve leaves the origin above the identity ($g > 1$): near
# $T_m = 0$ any offset grows, and with $T_c = 0$ the loop climbs by itself to the stable
# crossing further up (or down) -- a latched motor torque (printed above, iterating the
# stuck loop from $T_m = 0$) with no control torque at all.  The fricctl pipeline's curve stays just below the identity: the fixed point
# sits at $T_c/(1 - g)$, about a hundred times $T_c$, and the joint breaks loose at a
# $T_c$ a hundred times smaller than $F_s$ -- but only once $T_c$ is there.
#
# ## 3. Near the breakaway level (Fig. 9), both pipelines
#
# An open-loop sinusoid of $1.1 F_s$ at 0.5 Hz.  Without compensation the joint moves only
# while the torque exceeds breakaway and sticks around every velocity reversal.  A
# compensated joint must not stick -- and must still follow its control torque.  Three
# checks decide the second (`fricctl.paper.runaway`; [`wind_up`](#fricctl.paper.wind_up),
# [`reversal`](#fricctl.paper.reversal), [`coast_decay`](#fricctl.paper.coast_decay)): no **wind-up** ($|T_m|$ never exceeds
# $|T_c| + F_s + b|\omega|$ for more than 5 samples), the velocity **reverses** in every
# period, and a **coast** test (a torque pulse, then $T_c = 0$) decays at least like the
# linear viscous actuator.

# %%
r9 = {key: paper.fig09.run(n) for key, n in nets.items()}
r10 = {key: paper.fig10.run(n) for key, n in nets.items()}
print(f"{'pipeline':8s} seed  sticks (without/with)  peak speed with [rad/s] (linear)  "
      "wind-up reversal coast")
for (pipe, k), r in r9.items():
    print(f"{pipe:8s} {k:4d} {len(r.sticks_without):8d} / {len(r.sticks_with):<10d} "
          f"{r.peak_speed_with:10.2f} ({r.peak_speed_linear:.2f})           "
          + "  ".join(f"{'pass' if c.passed else 'FAIL':7s}" for c in r.checks))
lin = r9[("paper", SEEDS[0])].peak_speed_linear
print("paper pipeline, seed", SEEDS[0], "--", "\n  ".join(c.reason for c in r9[("paper", SEEDS[0])].checks))
assert all(len(r.sticks_without) >= 2 and len(r.sticks_with) == 0 for r in r9.values())
assert all(not r9[("paper", k)].coast.passed for k in SEEDS)      # every paper seed runs away
assert all(all(c.passed for c in r9[("fricctl", k)].checks) for k in SEEDS)
assert all(abs(r9[("fricctl", k)].peak_speed_with / lin - 1) <= LINEAR_TOLERANCE for k in SEEDS)
paper_speed = [r9[("paper", k)].peak_speed_with / lin for k in SEEDS]
print(f"paper pipeline's peak speed: {min(paper_speed):.1f}-{max(paper_speed):.1f} x the linear actuator's")
assert min(paper_speed) > 2

# %% [markdown]
# Neither pipeline's compensated joint sticks: that is all the paper's Fig. 9 asks, and
# the paper pipeline would pass it.  It passes by running away.  Its coast test fails in
# every seed (the joint speeds up by itself after the pulse), and its peak speed is
# several times the linear actuator's (printed).  The fricctl pipeline passes all three
# checks in every seed and its peak speed is within 10 % of the linear viscous actuator:
# compensation has removed the Coulomb and Stribeck part and left the viscous term, as
# intended.  The paper pipeline's seed first, then the fricctl pipeline's:

# %% mystnb={"figure": {"caption": "The paper's Fig. 9 for the first seed of the paper pipeline (first figure) and of the fricctl pipeline (second): the velocity $\\omega$ under an open-loop sinusoid near breakaway, without compensation (left, stuck intervals shaded) and with it (right), against the linear viscous actuator (dashed).  Neither compensated joint sticks, but the paper pipeline's reaches several times the linear actuator's peak speed."}}
for pipe in PIPELINES:
    fig = figures.plot_fig9(r9[(pipe, SEEDS[0])])
    fig.suptitle(f"Fig. 9, {pipe} pipeline, seed {SEEDS[0]}", fontsize="medium")
    plt.show()

# %% mystnb={"figure": {"caption": "The coast test, first seed of each pipeline: the velocity $\\omega$ after a torque pulse, then $T_c = 0$, against the viscous decay it must stay under (dotted).  The paper pipeline's joint (left) runs away; the fricctl pipeline's (right) decays like the linear actuator."}}
fig, axes = plt.subplots(1, 2, figsize=(9, 3.2), layout="constrained")
for ax, pipe in zip(axes, PIPELINES):
    figures.plot_coast(r9[(pipe, SEEDS[0])].coast, ax=ax)
    ax.set_title(f"coast test, {pipe} pipeline: {'decays' if r9[(pipe, SEEDS[0])].coast.passed else 'runs away'}",
                 fontsize="small")
plt.show()

# %% [markdown]
# ## 4. Inside the dead zone (Fig. 10), both pipelines
#
# At 10 % of Tmax the control torque alone never breaks the joint loose.  With
# compensation the motor torque is the control torque through the stuck loop:

# %% mystnb={"figure": {"caption": "The paper's Fig. 10 for the first seed of the paper pipeline (first figure) and of the fricctl pipeline (second): the control and motor torques $T_c$ and $T_m$ of the compensated joint inside the dead zone (left), and the encoder motion against the sinusoid's amplitude, without and with compensation, each dead zone dotted (right).  Both compensated joints move where the uncompensated one does not."}}
print(f"{'pipeline':8s} seed  peak |Tc|  peak |Tm|  motion [counts]  wind-up reversal coast")
for (pipe, k), r in r10.items():
    tc = np.abs(r.with_nn.torque_cmd).max()
    tmx = np.abs(r.with_nn.torque_motor).max()
    print(f"{pipe:8s} {k:4d} {tc:9.3f} {tmx:9.3f} {r.with_nn.displacement_counts():12d}     "
          + "  ".join(f"{'pass' if c.passed else 'FAIL':7s}" for c in r.checks))
assert all(r.without.displacement_counts() == 0 < r.with_nn.displacement_counts() for r in r10.values())
assert all(all(c.passed for c in r10[("fricctl", k)].checks) for k in SEEDS)
assert all(not r10[("paper", k)].coast.passed for k in SEEDS)
for pipe in PIPELINES:
    fig = figures.plot_fig10(r10[(pipe, SEEDS[0])])
    fig.suptitle(f"Fig. 10, {pipe} pipeline, seed {SEEDS[0]}", fontsize="medium")
    plt.show()

# %% [markdown]
# Both compensated joints move where the uncompensated one does not.  The fricctl
# pipeline's does so following $T_c$ (all three checks pass in every seed); the paper
# pipeline's fails its coast test in every seed, and where its wind-up check fails the
# motor torque is latched far above the control torque (the table).
#
# ## 5. The dead zone over seeds
#
# [`dead_zone`](#fricctl.bench.experiments.dead_zone) runs open-loop sinusoids of growing amplitude (0.25 % to 20 % of Tmax) and
# finds the smallest amplitude that moves the encoder by more than 3 counts.  Without
# compensation it is close to the paper's 12.7 % of Tmax.  With compensation, per
# pipeline over the seeds, measured and predicted by the fixed point:

# %%
dz0 = r10[("paper", SEEDS[0])].dead_zone_without
print(f"dead zone without compensation: {dz0.dead_zone:.4f} N*m = {100 * dz0.fraction:.2f} % of Tmax "
      f"(paper: 12.7 %)")
assert abs(100 * dz0.fraction - 12.7) < 0.5
factor, pred_factor = {}, {}
for pipe in PIPELINES:
    factor[pipe] = np.array([r10[(pipe, k)].factor for k in SEEDS])
    pred_factor[pipe] = np.array([r10[(pipe, k)].predicted_factor for k in SEEDS])
    floor = sum(r10[(pipe, k)].dead_zone_with.at_grid_floor for k in SEEDS)
    print(f"{pipe:8s}: factor measured median {np.median(factor[pipe]):5.1f} (min {factor[pipe].min():5.1f}, "
          f"max {factor[pipe].max():5.1f}); predicted median {np.median(pred_factor[pipe]):5.1f} "
          f"(min {pred_factor[pipe].min():5.1f}, max {pred_factor[pipe].max():5.1f})"
          + (f"; {floor} of {len(SEEDS)} at the grid floor (a lower bound)" if floor else ""))
assert all(r10[("fricctl", k)].dead_zone_with.at_grid_floor for k in SEEDS)
assert factor["fricctl"].min() > 2 * factor["paper"].max() and factor["paper"].min() > 2
# The paper's claims on Figs. 9 and 10, each gated by the runaway checks (fricctl.paper.claims)
claim_fns = ((paper.fig09.claim_fig9, r9), (paper.fig09.claim_coast, r9),
             (paper.fig10.claim_dead_zone, r10), (paper.fig10.claim_fig10_motion, r10))
passes = {}
for pipe in PIPELINES:
    for fn, results in claim_fns:
        res = [fn(results[(pipe, k)], p) for k in SEEDS]
        passes[(pipe, res[0].id)] = sum(c.passed for c in res)
print("claims passed (of", len(SEEDS), "seeds):", ", ".join(f"{pipe} {cid} {n}" for (pipe, cid), n in passes.items()))
assert all(passes[key] == len(SEEDS) for key in passes if key[0] == "fricctl")
assert all(passes[key] == 0 for key in passes if key[0] == "paper")

# %% [markdown]
# The paper pipeline's dead zone does shrink (by the factor printed, comparable to the
# paper's "about 6") -- but that is the gap between its latched torque and $F_s$, and a
# joint that breaks loose there runs away (Section 3): a dead-zone factor is no success
# without the runaway checks.  Gated by them, the paper pipeline passes none of the four
# claims of Figs. 9 and 10 in any seed, the fricctl pipeline all four in every seed (the
# pass counts printed).  The fricctl pipeline's compensated dead zone lies below the
# grid's smallest amplitude in every seed.  A finer grid resolves it; with $g$ inside the
# certified band the prediction $F_s(1 - g)$ lies between 1.8 and 3.6 mN m:

# %%
assert (round(1e3 * Fs * (1 - DEFAULT_GAIN_BAND[1]), 1), round(1e3 * Fs * (1 - DEFAULT_GAIN_BAND[0]), 1)) == (1.8, 3.6)
fine = np.linspace(0.0005, 0.05, 100)  # amplitudes [N*m], steps of 0.5 mN*m
meas, pred = [], []
for k in SEEDS:
    n = nets[("fricctl", k)]
    meas.append(dead_zone(p, n.compensator(), amplitudes=fine).dead_zone)
    pred.append(predicted_dead_zone(n.net, Fs).largest)
meas, pred = np.array(meas), np.array(pred)
print(f"fricctl pipeline, fine grid: measured dead zone {1e3 * np.median(meas):.1f} mN*m "
      f"(min {1e3 * meas.min():.1f}, max {1e3 * meas.max():.1f}); predicted {1e3 * np.median(pred):.1f} "
      f"(min {1e3 * pred.min():.1f}, max {1e3 * pred.max():.1f}); reduction measured "
      f"{np.median(Fs / meas):.0f}x, predicted {np.median(Fs / pred):.0f}x")
assert np.all(meas >= pred - 0.0005) and np.all(meas - pred <= 0.0015)  # within 3 grid steps above

# %% [markdown]
# The measured dead zone lies at most 1.5 mN m (three grid steps) above the fixed point's
# prediction: the joint needs the fixed point to pass $F_s$, and then a few encoder counts
# of motion to be seen.
#
# ## 6. The price in a position loop
#
# A stuck joint under a position controller $T_c = K_p(r - \hat q) - K_d\hat\omega$ sees
# $T_c = K_p e$ at rest ($e$ the position error [rad]); it stays stuck while
# $K_p|e| < D$ ([the dead zone](#eq-dead-zone)), so it may stop anywhere within
#
# <a id="eq-band"></a>
#
# $$ |e| \le \frac{F_s\,(1 - s g)}{K_p} $$
#
# of its reference.  A small dead zone is a narrow band; $g$ close to one buys it, and
# $s g \ge 1$ loses the band altogether (the joint runs away instead of stopping).  With
# the paper's P and PD gains ([Chapter 6](06_gain_design_and_closed_loop)), at the ends of the certified band and at $s = 1$:

# %%
gains = paper_gains(p)
band = {}
for name, kp in (("P", gains.p_kp), ("PD", gains.pd_kp)):
    for gg in (0.0,) + DEFAULT_GAIN_BAND:
        band[(name, gg)] = np.degrees(Fs * (1 - gg) / kp)
    print(f"{name:2s} Kp = {kp:.3f} N*m/rad: band +-{band[(name, 0.0)]:.1f} deg without compensation, "
          f"+-{band[(name, DEFAULT_GAIN_BAND[1])]:.2f} to +-{band[(name, DEFAULT_GAIN_BAND[0])]:.2f} deg "
          f"for g in {DEFAULT_GAIN_BAND}")
assert band[("P", DEFAULT_GAIN_BAND[1])] > 0.3 > band[("PD", DEFAULT_GAIN_BAND[0])]

# %% [markdown]
# With the PD gains the whole certified band keeps a stuck joint within 0.3 degrees of
# its reference (the paper's accuracy claim); with the softer P gain it does not, even at
# $g = 0.99$.  Moving $s$ and $g$ shows the trade-off: the dead zone (and with it the
# band) shrinks as $s g \to 1$ and vanishes -- into a runaway -- beyond.

# %%
def stuck_loop(s, g_rest, ax=None):
    """The stuck loop with a linear estimate g*Tm: Tm* = Tc/(1 - s*g) against Tc, and D [N*m]."""
    ax = ax if ax is not None else plt.subplots(figsize=(4.5, 3.2), layout="constrained")[1]
    sg = s * g_rest
    tc = np.linspace(0.0, Fs, 200)
    ax.axhline(Fs, color="0.5", lw=0.8)
    ax.text(0.002, Fs, r" $F_s$", va="bottom", fontsize="small")
    if sg >= 1:
        ax.text(0.5, 0.5, f"s g = {sg:.2f} >= 1:\nno stable fixed point,\nTm winds up (runaway)",
                transform=ax.transAxes, ha="center", va="center")
        dz = 0.0
    else:
        dz = Fs * (1 - sg)
        ax.plot(tc, np.minimum(tc / (1 - sg), 1.5 * Fs), lw=2, label=r"$T_m^\star = T_c/(1 - s g)$")
        ax.axvline(dz, color="C3", ls="--", lw=1, label=rf"$D$ = {1e3 * dz:.1f} mN m ($\times${1 / (1 - sg):.1f})")
        ax.legend(fontsize="x-small", loc="lower right")
    ax.plot(tc, tc, color="0.6", lw=0.8, ls=":")
    ax.set(xlim=(0, Fs), ylim=(0, 1.5 * Fs), xlabel=r"$T_c$ [N m]", ylabel=r"$T_m$ [N m]",
           title=f"s = {s:.2f}, g = {g_rest:.3f}")
    return dz


# %% tags=["widget"] mystnb={"figure": {"caption": "The stuck loop with a linear estimate $g T_m$ at the sliders' $s$ and $g$: the fixed point $T_c/(1 - s g)$ against $T_c$, and the dead zone $D$ (dashed), which narrows as $s g$ nears one; from $s g = 1$ on there is no stable fixed point."}}
if "ipykernel" in sys.modules:  # in Jupyter: sliders; the book shows the figure below instead
    from ipywidgets import FloatSlider, interact

    def show_stuck_loop(s, g_rest):
        stuck_loop(s, g_rest)
        plt.show()

    interact(show_stuck_loop, s=FloatSlider(value=1.0, min=0.5, max=1.2, step=0.01),
             g_rest=FloatSlider(value=0.9, min=0.5, max=1.5, step=0.005))

# %% mystnb={"figure": {"caption": "The stuck loop with a linear estimate $g T_m$ at $s = 1$: the fixed point $T_c/(1 - s g)$ and the dead zone $D$ (dashed) for the $g$ of the paper's dead-zone factor of 6 (left), the fricctl pipeline's median $g$ (middle) and the paper pipeline's (right), where $g > 1$ leaves no stable fixed point."}}
cases = ((1.0, 1 - 1 / 6), (1.0, float(np.median([g[("fricctl", k)] for k in SEEDS]))),
         (1.0, float(np.median([g[("paper", k)] for k in SEEDS]))))
fig, axes = plt.subplots(1, 3, figsize=(11, 3.3), layout="constrained")
dz = [stuck_loop(s, gg, ax=ax) for (s, gg), ax in zip(cases, axes)]
plt.show()
print(f"paper's factor 6 <=> g = {cases[0][1]:.3f}: D = {1e3 * dz[0]:.1f} mN*m, band with P "
      f"+-{np.degrees(dz[0] / gains.p_kp):.2f} deg, with PD +-{np.degrees(dz[0] / gains.pd_kp):.2f} deg")
assert abs(Fs / dz[0] - 6) < 1e-9                 # the closed form: 1/(1 - g) = 6
assert dz[1] < dz[0] / 10 and dz[2] == 0.0        # certified g: 10x narrower; paper's g: no band
assert np.degrees(dz[0] / gains.pd_kp) > 0.3      # the paper's 6x and its 0.3 deg do not meet

# %% [markdown]
# The paper's factor of about 6 needs $g = 1 - 1/6$: a dead zone of $F_s/6$, which leaves a
# stuck joint further than 0.3 degrees from its reference even with the PD gain (printed)
# -- the paper's 6x dead-zone reduction and its 0.3-degree accuracy cannot both hold with
# one smooth net.
# The certified band's $g \approx 0.99$ narrows the dead zone more than tenfold further,
# and the paper pipeline's $g > 1$ has no band at all.

# %% [markdown]
# ## Summary
#
# * The compensated loop of Eq. (3) feeds the commanded motor torque back into the net
#   through a one-sample delay; while the joint is stuck, that inner loop is the only one
#   left.
# * For a linear estimate of gain $g$ the stuck loop settles at $T_m^\star = T_c/(1 - s g)$:
#   the dead zone shrinks by the factor $1/(1 - s g)$, and for $s g \ge 1$ there is no stable
#   fixed point near rest -- the loop winds the torque up.  For the real, curved net the
#   fixed points predict the dead zone from the net alone.
# * The paper's recipe ($g > 1$ in every seed) latches a motor torque with no control torque
#   at all.  Its compensated joint never sticks in Fig. 9, but by running away: the coast
#   test fails in every seed and the peak speed is several times the linear actuator's.  The
#   fricctl pipeline passes every runaway check and moves like the linear viscous actuator.
# * Gated by the runaway checks, the paper pipeline passes none of the four claims of
#   Figs. 9 and 10 and the fricctl pipeline all four, in every seed; its dead zone, measured on
#   a fine grid, lies within three grid steps above the fixed point's prediction.
# * A stuck position loop stops within $F_s(1 - s g)/K_p$ of its reference: the paper's
#   dead-zone factor and its 0.3-degree accuracy cannot both hold with one smooth net, and
#   $s g \ge 1$ loses the band altogether.

# %% [markdown]
# ## Exercises
#
# 1. For the paper pipeline's net of each seed, find the fixed points with $T_c = 0$ and
#    $T_c = D$ (the predicted dead zone).  Where does the joint break loose, and does
#    the measured dead zone of Fig. 10 agree?
# 2. Repeat the fine-grid dead-zone measurement with the fricctl net and
#    `n.compensator(s)` for `s = 0.8, 0.9, 1.0`.  Does the dead zone follow
#    $F_s(1 - s g)$?
# 3. Add white torque noise (`noise_std=0.005`, with an `rng`) to the Fig. 9
#    experiment without compensation.  Do the stick intervals survive?

# %% tags=["solution"]
# Exercise 1.  With Tc = 0 the stable crossing is the latched torque of Section 2.  At
# Tc = D the stable crossing below Fs disappears: the joint breaks loose there.  A sinusoid
# pushes both ways, so Fig. 10's measured dead zone is the easier direction's D (the smaller
# of the two), rounded up to its amplitude grid (within two steps).
for k in SEEDS:
    net = nets[("paper", k)].net
    pred_k = predicted_dead_zone(net, Fs)
    d = pred_k.positive  # the fixed points below are those of the positive direction
    roots0, stable0 = fixed_points(net, 0.0)
    tm_latched = stuck_iteration(net, 0.0)
    rootsd, stabled = fixed_points(net, 0.999 * d)
    print(f"seed {k}: Tc = 0 -> fixed points {np.round(roots0, 3)} (stable {stable0}); D = {d:.4f} N*m, "
          f"Tc = 0.999 D -> stable ones {np.round(rootsd[stabled], 3)}; measured "
          f"{r10[('paper', k)].dead_zone_with.dead_zone:.4f} N*m")
    # the latched torque of Section 2 is a stable fixed point (or its mirror image below 0)
    roots_m, stable_m = fixed_points(lambda tm, w: -net(-tm, w), 0.0)
    assert np.min(np.abs(np.r_[roots0[stable0], -roots_m[stable_m]] - tm_latched)) < 1e-3
    assert stabled.any() and rootsd[stabled][0] <= Fs  # just below D, still a stable point below Fs
    roots_up, stable_up = fixed_points(net, 1.001 * d)
    assert not np.any(stable_up & (roots_up < Fs - 1e-3))  # just above D: none left below Fs
    step = np.diff(r10[("paper", k)].dead_zone_with.amplitudes)[0]
    easier = min(pred_k.positive, pred_k.negative)
    assert easier <= r10[("paper", k)].dead_zone_with.dead_zone <= easier + 2 * step

# %% tags=["solution"]
# Exercise 2.  The dead zone follows Fs(1 - s*g) from above, by at most 2 mN*m (compare
# Section 5); the smaller s, the wider it is, and the reduction follows 1/(1 - s*g).
n = nets[("fricctl", SEEDS[0])]
for s in (0.8, 0.9, 1.0):
    d_meas = dead_zone(p, n.compensator(s), amplitudes=fine).dead_zone
    d_lin = Fs * (1 - s * g[("fricctl", SEEDS[0])])
    print(f"s = {s:.1f}: measured {1e3 * d_meas:.1f} mN*m, Fs(1 - s g) = {1e3 * d_lin:.1f} mN*m, "
          f"reduction {Fs / d_meas:.1f}x (1/(1 - s g) = {1 / (1 - s * g[('fricctl', SEEDS[0])]):.1f}x)")
    assert d_lin - 0.0005 <= d_meas <= d_lin + 0.002

# %% tags=["solution"]
# Exercise 3.  Noise of 5 mN*m is under 3 % of Fs: near each velocity reversal the torque
# is still far below breakaway, and the stick intervals survive.
from fricctl import controllers as ctl
from fricctl.paper.common import stick_intervals_after_motion
from fricctl.simulate import simulate

c = ctl.open_loop(ctl.sinusoid(1.1 * Fs, 0.5))
quiet = simulate(p, c, duration=4.0)
noisy = simulate(p, c, duration=4.0, noise_std=0.005, rng=np.random.default_rng(1))
n_quiet, n_noisy = len(stick_intervals_after_motion(quiet)), len(stick_intervals_after_motion(noisy))
print(f"stick intervals: {n_quiet} without noise, {n_noisy} with noise_std = 0.005 N*m")
assert n_noisy == n_quiet >= 2

# %% [markdown]
# ## References
#
# * [Gervini, Gomes & da Rosa 2003](#gervini2003): the compensation law (Eq. 3), Figs. 9 and
#   10, the dead-zone and accuracy claims.
# * [Armstrong-Hélouvry, Dupont & Canudas de Wit 1994](#armstrong1994survey): friction
#   compensation and its hazards.
#
# In fricctl: [`train_paper_network`](#fricctl.paper.train_paper_network),
# [`FrictionNet.gain_at_rest`](#fricctl.nn.FrictionNet.gain_at_rest),
# [`dead_zone`](#fricctl.bench.experiments.dead_zone),
# [`predicted_dead_zone`](#fricctl.bench.experiments.predicted_dead_zone),
# [`paper_gains`](#fricctl.bench.experiments.paper_gains),
# the runaway checks [`wind_up`](#fricctl.paper.wind_up), [`reversal`](#fricctl.paper.reversal)
# and [`coast_decay`](#fricctl.paper.coast_decay),
# [`stick_intervals_after_motion`](#fricctl.paper.stick_intervals_after_motion),
# [`plot_compensation_loop`](#fricctl.figures.plot_compensation_loop),
# [`plot_fig9`](#fricctl.figures.plot_fig9), [`plot_fig10`](#fricctl.figures.plot_fig10),
# [`plot_coast`](#fricctl.figures.plot_coast), [`simulate`](#fricctl.simulate.simulate).
