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
# # Chapter 4 -- The neural network
#
# *Gervini, Gomes & da Rosa (2003): the friction patterns (Fig. 5), the 2-4-1
# network and its training, and the comparison of measured and learned friction
# (Fig. 8).*
#
# The paper does not write down a friction law.  It *measures* friction torque
# samples on the bench -- `Tat = Tm - I*alpha_hat`, motor torque minus inertia
# times the estimated acceleration -- and lets a small network learn the map
# `(Tm, omega) -> Tat`: two inputs, four tanh hidden units, one linear output.
# This chapter builds those patterns on the virtual bench, trains the network with
# two trainers, asks what "98 % accuracy" can mean, and looks at where the net may
# be trusted (its envelope), how it is exported to C for a 500 Hz controller, and
# how it is saved.

# %% [markdown]
# ## What you will learn
#
# * **Explain** how friction patterns are measured on a bench, $T_{at} = T_m - I\hat\alpha$,
#   and why the patterns of a stuck joint are a vertical line at $\omega = 0$.
# * **Explain** the paper's 2-4-1 network and how the two pipelines scale its inputs and
#   choose its target.
# * **Measure** two trainers on the same patterns: back-propagation with momentum and
#   Levenberg-Marquardt in CasADi.
# * **Judge** what an accuracy figure means (the fit of system identification against
#   $R^2$) and whether the network or the measuring chain limits it.
# * **Explain** the network's gain at rest $g$, why the paper's recipe gives $g > 1$, and how
#   a trainer can certify it inside a band.
#
# Symbols and units are collected on the [notation page](../notation).

# %%
import os
import sys
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from fricctl import figures
from fricctl import paper
from fricctl.bench.experiments import train_network
from fricctl.nn import c_source, fit_percent, fit_report, load_net, r_squared, save_net
from fricctl.nn.pipelines import DEFAULT_GAIN_BAND
from fricctl.nn.train.certified import CERTIFY_POINTS
from fricctl.params import paper_actuator

FAST = os.environ.get("FRICCTL_FAST") == "1"
SEED = 0                               # seed of the split and the trainers [-]
BACKPROP_EPOCHS = 200 if FAST else 2000  # epochs of the paper's back-propagation [-]
SEEDS = range(2 if FAST else 4)        # training seeds of each pipeline (Section 5) [-]
PIPELINES = ("paper", "fricctl")       # fricctl.nn.pipelines.PIPELINES

# %% [markdown]
# ## 1. The patterns (Fig. 5)
#
# [`train_paper_network`](#fricctl.paper.train_paper_network) runs the whole pipeline once: open-loop torque steps of
# growing amplitude up to the maximum torque, closed-loop P and PD step
# sequences, the paper's polynomial velocity/acceleration estimator on the encoder
# record, and an 80/20 split of the patterns into training and held-out sets.

# %% mystnb={"figure": {"caption": "The paper's Fig. 5 on the virtual bench: the open-loop training torque $T_m$ and the friction patterns $T_{at} = T_m - I \\hat\\alpha$ it gives, with the bench's true friction.  While the joint sticks, the patterns equal $T_m$."}}
p = paper_actuator()
net_run = paper.train_paper_network(p, fast=FAST, seed=SEED)
for ex in net_run.experiments:
    print(f"{ex.name:16s} {ex.run.t[-1]:5.1f} s, {ex.run.n_samples} samples")
print(f"patterns: {len(net_run.patterns)} ({len(net_run.train)} training, {len(net_run.held_out)} held out)")
stuck = net_run.patterns.omega == 0
print(f"{np.mean(stuck) * 100:.0f} % of the patterns are at rest, where Tat = Tm exactly")
figures.plot_fig5(paper.fig05.run(net_run))
plt.show()

# %% [markdown]
# Each pattern is a measured friction torque [N m] from paper Eq. (2),
#
# <a id="eq-patterns"></a>
#
# $$ T_{at}(k) = T_m(k) - I\,\hat\alpha(k), $$
#
# with $I$ the inertia [kg m²] and $\hat\alpha$ the estimated acceleration [rad/s²].
# Notice the two kinds of pattern.  While the joint is stuck, $\hat\alpha = 0$ and
# the pattern says "friction equals the motor torque", $T_{at} = T_m$, for any torque up
# to the breakaway level -- a vertical line at $\omega = 0$.  While it slides, friction is
# roughly $F_c + b\,\omega$.  A smooth net has to bridge the two at $\omega = 0$.
#
# ## 2. The network and its inputs
#
# The paper's 2-4-1 network maps the scaled inputs through four tanh units to one
# linear output:
#
# <a id="eq-network"></a>
#
# $$ \hat T = W_2 \tanh(W_1 x + b_1) + b_2, \qquad
#    x = \left(\frac{T_m - c_T}{s_T},\ \frac{\omega - c_\omega}{s_\omega}\right), $$
#
# with $W_1$ (4x2), $b_1$ (4), $W_2$ (1x4), $b_2$ the weights [-] (the output's own scale
# and offset [N m] folded into $W_2$ and $b_2$) and $c$, $s$ the centre and scale of each
# input [N m, rad/s].  The two pipelines differ in the scaling and the target:
#
# * **paper** (the literal recipe): $c$ and $s$ the centre and half-width of the
#   training data's range, and the target the whole friction, $\hat T_{at} = \hat T$.
#   The velocity range is tens of rad/s, so every velocity below a few tenths of a rad/s
#   is "zero" to the net.
# * **fricctl**: $c = 0$, $s_T$ the largest torque held at rest, $s_\omega = \Delta/T_s$,
#   one encoder count $\Delta$ [rad] per sample [s] -- the smallest non-zero velocity the
#   loop measures is one unit of input; the target is the nonlinear part,
#   $\hat T_{at} = \hat b\,\omega + \hat T$, with $\hat b$ [N m s/rad] fitted by least
#   squares on the sliding patterns; and at-rest patterns kept only where the encoder
#   stood still two samples either side.

# %%
# ("paper", SEED) is net_run of Section 1: the same call, so it is not run again
nets = {(pipe, k): net_run if (pipe, k) == ("paper", SEED)
        else paper.train_paper_network(p, fast=FAST, seed=k, pipeline=pipe)
        for pipe in PIPELINES for k in SEEDS}
quantum = p.encoder_resolution / p.sample_time  # one count per sample [rad/s]
for pipe in PIPELINES:
    n = nets[(pipe, SEEDS[0])]
    print(f"{pipe:8s} c = ({n.net.input_offset[0]:+.3f} N*m, {n.net.input_offset[1]:+.3f} rad/s), "
          f"s = ({n.net.input_scale[0]:.3f} N*m, {n.net.input_scale[1]:.4g} rad/s), "
          f"b_hat = {n.trained.viscous_removed:.4f} N*m*s/rad")
fr, pa = nets[("fricctl", SEEDS[0])], nets[("paper", SEEDS[0])]
assert np.array_equal(fr.net.input_offset, [0.0, 0.0]) and np.isclose(fr.net.input_scale[1], quantum)
assert pa.net.input_scale[1] > 10 and pa.trained.viscous_removed == 0.0  # the data's range: > 10 rad/s
print(f"one count per sample = {quantum:.4f} rad/s; the paper's s_omega is {pa.net.input_scale[1] / quantum:.0f} of them")

# %% [markdown]
# ## 3. Two trainers
#
# The paper trains with back-propagation and momentum.  fricctl also offers a
# second-order trainer, Levenberg-Marquardt on the least-squares problem, posed
# in CasADi (exact Jacobian by algorithmic differentiation).  Same patterns, same
# seed:

# %% mystnb={"figure": {"caption": "Training loss (mean squared error) of the CasADi Levenberg-Marquardt trainer and of the paper's back-propagation on the same patterns and seed, against the iteration or epoch (log axes): the second-order trainer ends lower."}}
lm = net_run.trained
bp = train_network(net_run.train, trainer="backprop", epochs=BACKPROP_EPOCHS, max_patterns=2000,
                   rng=np.random.default_rng(SEED))
for name, res in (("CasADi LM", lm), ("back-prop", bp)):
    h = res.history
    print(f"{name:10s} final training MSE {h.loss[-1]:.3e} (N*m)^2 after {h.loss.size - 1} "
          f"{h.step}s, {h.elapsed[-1]:.2f} s")
assert lm.history.loss[-1] < bp.history.loss[-1]  # the second-order trainer ends lower
ax = figures.plot_training_history(lm.history, against="step")
figures.plot_training_history(bp.history, ax=ax, against="step")
ax.set_xscale("log")
plt.show()

# %% [markdown]
# ## 4. What does "98 % accuracy" mean?  (Fig. 8)
#
# The paper reports 98 % without a definition.  Two common ones:
#
# * the normalised **fit** `100 (1 - ||e|| / ||y - mean y||)` of system identification;
# * the coefficient of determination **R^2** `= 1 - ||e||^2 / ||y - mean y||^2`.
#
# They are tied by `fit = 100 (1 - sqrt(1 - R^2))`, so an R^2 of 0.98 is a much
# lower fit (printed below).  Measured on the held-out patterns, and against the
# simulator's *true* friction (which a lab never has):

# %% mystnb={"figure": {"caption": "The paper's Fig. 8 on the held-out patterns: the measured friction $T_{at}$ and the network's estimate $\\hat T_{at}$, pattern by pattern; the title gives the fit, $R^2$ and the gain at rest $g$.  The fit stays below the paper's 98 %."}}
print(f"R^2 = 0.98 is a fit of {100 * (1 - np.sqrt(1 - 0.98)):.1f} %")
ho = net_run.held_out
net = net_run.net
for name, fr in (("held-out, measured", net_run.fit_held_out), ("training, measured", net_run.fit_train),
                 ("held-out, true friction", net_run.fit_true)):
    print(f"{name:24s} fit {fr.fit_percent:6.2f} %   R^2 {fr.r_squared:.4f}   RMSE {fr.rmse:.4f} N*m")
yhat = net(ho.tm, ho.omega)
assert abs(fit_percent(ho.friction, yhat)
           - 100 * (1 - np.sqrt(1 - r_squared(ho.friction, yhat)))) < 1e-9
moving = ho.omega != 0
print(f"fit on the sliding patterns only: {fit_report(ho.friction[moving], yhat[moving]).fit_percent:.1f} %; "
      f"at rest only: {fit_report(ho.friction[~moving], yhat[~moving]).fit_percent:.1f} %")
assert net_run.fit_held_out.fit_percent < 98 and net_run.fit_held_out.r_squared < 0.98
r8 = paper.fig08.run(net_run)
figures.plot_fig8(r8)
plt.show()

# %% [markdown]
# The claims table reads the paper's number as the normalised fit, on every seed: an
# accuracy in percent is a relative size of the error, as the fit is; it is the "fit %"
# the identification tools of the paper's time print; and it is the stricter reading (a
# fit of 98 % implies $R^2 \ge 0.98$).  $R^2$ is reported beside it for every seed.
#
# Neither definition gets to 98 % here (checked above).  The patterns carry the
# estimator's error wherever the acceleration jumps (each torque step, each
# stick/slip transition), and the static map cannot be sharp at `omega = 0`.
# Which of the two limits the fit?  Train the same network, with the same split and
# seed, on *exact* patterns -- the simulator's true velocity and friction at the
# same samples, what a perfect measuring chain would give:

# %%
print(f"held-out fit, measured patterns: {r8.fit_held_out.fit_percent:.1f} %; "
      f"exact patterns: {r8.fit_exact.fit_percent:.1f} % (R^2 {r8.fit_exact.r_squared:.4f})")
assert r8.fit_exact.fit_percent > r8.fit_held_out.fit_percent + 10

# %% [markdown]
# With exact patterns the four tanh units come close to (or reach) the paper's
# 98 %: the architecture is not the bottleneck, the acceleration estimate is.
# The paper's number is plausible for a good measuring chain; ours, the paper's encoder
# sampled at 500 Hz under torque steps, is not that good.
#
# ## 5. The gain at rest: why the paper's recipe gives g > 1, and the certified band
#
# [Chapter 5](05_open_loop_compensation_and_dead_zone) shows that one number of the net decides what the compensator does while the
# joint is stuck: the at-rest gain
#
# <a id="eq-gain-at-rest"></a>
#
# $$ g = \left.\frac{\partial \hat T_{at}}{\partial T_m}\right|_{\omega = 0}, $$
#
# the slope of $\hat T_{at}(T_m, 0)$ [-].  Below one the stuck loop settles; above one it
# winds the motor torque up by itself.  Nothing in the paper's recipe asks for a slope.
# Over several training seeds of each pipeline:

# %% mystnb={"figure": {"caption": "The estimate at rest $\\hat T_{at}(T_m, 0)$ of every training seed, paper pipeline (left) and fricctl pipeline (right), with the patterns at rest ($T_{at} = T_m$, grey dots), the identity (dotted) and $-F_s$, $F_s$ (grey lines): the paper's curves leave the origin steeper than the identity ($g > 1$), the fricctl curves with a slope just below one."}}
g = {key: n.net.gain_at_rest() for key, n in nets.items()}
rest_share = np.mean(pats_all := nets[("paper", SEEDS[0])].patterns.omega == 0)
for pipe in PIPELINES:
    gs = np.array([g[(pipe, k)] for k in SEEDS])
    print(f"{pipe:8s} {len(gs)} seeds: g median {np.median(gs):.3f} (min {gs.min():.3f}, max {gs.max():.3f})")
print(f"patterns with omega_hat = 0: {100 * rest_share:.0f} % (Tat = Tm there)")
assert all(g[("paper", k)] > 1 for k in SEEDS)
assert all(DEFAULT_GAIN_BAND[0] <= g[("fricctl", k)] <= DEFAULT_GAIN_BAND[1] for k in SEEDS)
assert 0.6 < rest_share < 0.8

fig, axes = plt.subplots(1, 2, figsize=(9, 3.6), sharey=True, layout="constrained")
tm = np.linspace(-1.5 * p.static, 1.5 * p.static, 301)
for ax, pipe in zip(axes, PIPELINES):
    n0 = nets[(pipe, SEEDS[0])]
    at0 = n0.train.omega == 0
    ax.plot(n0.train.tm[at0], n0.train.friction[at0], ".", color="0.75", ms=3,
            label="patterns at rest ($T_{at} = T_m$)")
    for k in SEEDS:
        ax.plot(tm, nets[(pipe, k)].estimate(tm, np.zeros_like(tm)), lw=1.5,
                label=f"seed {k}: g = {g[(pipe, k)]:.3f}")
    ax.plot(tm, tm, "k:", lw=1, label="identity")
    for sign in (-1, 1):
        ax.axvline(sign * p.static, color="0.5", lw=0.8)
    ax.set(title=f"{pipe} pipeline: $\\hat T_{{at}}(T_m, 0)$", xlabel="$T_m$ [N m]",
           xlim=(tm[0], tm[-1]), ylim=(tm[0], tm[-1]))
    ax.legend(fontsize="x-small")
axes[0].set_ylabel("friction estimate at rest [N m]")
plt.show()

# %% [markdown]
# The paper pipeline's curve lies above the identity near the origin ($g > 1$ in every
# seed): the blending at rest.  Its velocity input is scaled by the data's range, so at
# $\omega = 0$ the net sees the stuck patterns (most of all patterns, printed above; the
# grey dots, piled up at small torques and at the holding torques) together with sliding patterns of
# nearby velocities, whose friction is about $F_c$.  The least-squares fit bends the
# curve at rest down towards $F_c$ at the largest torques, and a concave curve through
# the origin and the holding torques has a slope above one at the origin.  A better
# acceleration estimate does not remove it (exercise 1): it is the target, not the
# measurement.
#
# The fricctl pipeline removes the cause (at-rest patterns only where the encoder stood
# still, the nonlinear part as target, the velocity scaled to one count per sample) and
# then *certifies* the result.  Its trainer (`fricctl.nn.train.certified`) imposes the
# slope on grids while it trains and checks the trained net afterwards on a dense grid:
#
# * at rest, $g_{\min} \le \partial\hat T/\partial T_m \le g_{\max}$ inside the band
#   $0.98 \le g \le 0.99$ on 2001 torques over $|T_m| \le$ the largest torque held at rest;
# * at rest over the whole torque range (201 torques), the slope at most 0.99;
# * while sliding, at $\omega = \pm k\,\Delta/T_s$ ($k = 1, 2, \dots$, the velocities a
#   quantised loop measures), $|\partial\hat T/\partial T_m| \le 0.3$;
# * no offset at rest: $\hat T(0, 0) = 0$.
#
# A net that fails is retrained from another start.  The certificate is stored with the net:

# %%
cert = nets[("fricctl", SEEDS[0])].trained.certificate
print(cert)
assert cert.passed and cert.gain_band == DEFAULT_GAIN_BAND and CERTIFY_POINTS == 2001
for k in SEEDS:  # every seed certified; checked again here by central differences of the net
    n = nets[("fricctl", k)]
    c = n.trained.certificate
    t = np.linspace(-c.rest_torque, c.rest_torque, 401)
    h = 1e-6
    slope = (n.net(t + h, np.zeros_like(t)) - n.net(t - h, np.zeros_like(t))) / (2 * h)
    assert c.passed and np.all((slope > DEFAULT_GAIN_BAND[0] - 1e-4) & (slope < DEFAULT_GAIN_BAND[1] + 1e-4))
    assert c.sliding_slope_max <= c.sliding_slope + 1e-6 and abs(c.offset) < 1e-6
print(f"certified in {len(SEEDS)} of {len(SEEDS)} seeds; paper pipeline: certificate {pa.trained.certificate}")

# %% [markdown]
# ## 6. The envelope: where the net may be trusted
#
# A net extrapolates badly.  fricctl stores the box of the training inputs with
# the net; the compiled loop can clip its inputs to it
# ([`NNCompensator`](#fricctl.compensators.NNCompensator)`(clip=True)`).
# The box is generous: it spans every torque at every velocity, though most of its
# area held no patterns.  Look at one corner, torque above breakaway at zero velocity: a
# joint at rest cannot hold more than the breakaway torque $F_s$, yet a few patterns sit
# there, all with $T_{at} = T_m$.  They are the start of a motion the encoder has not
# counted yet.  After a torque step to $T_m > F_s$ the joint breaks loose at once, but
# its position grows as $\tfrac12 a t^2$ with $a = (|T_m| - F_s)/I$ at most at first, so
# the first count $\Delta$ comes up to $\sqrt{2\,\Delta\, I/(|T_m| - F_s)}$ later: one or
# two samples after a step to twice $F_s$ or more, but several after a step just above
# $F_s$.  Each such pattern is off by $|T_m|$ minus the true friction.  The check below
# finds the count within the bound for every one of them:

# %%
def samples_to_next_count(position):
    """Samples from each reading until the encoder reading next changes (inf if never) [-]."""
    change = np.flatnonzero(np.diff(position) != 0)  # the reading changes between j and j+1
    k = np.arange(position.size)
    i = np.searchsorted(change, k)
    return np.where(i < change.size, change[np.minimum(i, change.size - 1)] - k + 1, np.inf)


pats = net_run.patterns
odd = (pats.omega == 0) & (np.abs(pats.tm) > p.static)
print(f"patterns 'at rest' with |Tm| above the breakaway {p.static:.2f} N*m: {int(odd.sum())} of "
      f"{int((pats.omega == 0).sum())} at rest; largest |Tm| there {np.abs(pats.tm[odd]).max():.3f} N*m")
# the patterns are the experiments' samples without the estimator's 5 edge samples each side
wait = np.concatenate([samples_to_next_count(e.run.position)[5:-5] for e in net_run.experiments])[odd]
bound = np.ceil(np.sqrt(2 * p.encoder_resolution * p.total_inertia / (np.abs(pats.tm[odd]) - p.static))
                / p.sample_time) + 1  # samples until the first count, + the sample the torque needs
print(f"the encoder counts {int(wait.min())}-{int(wait.max())} samples after them "
      f"(the bound allows {int(bound.min())}-{int(bound.max())})")
assert odd.any() and np.all(wait <= bound) and np.all(wait[np.abs(pats.tm[odd]) >= 2 * p.static] <= 2)
error = np.abs(pats.tm[odd]) - np.abs(pats.friction_true[odd])
kept = pats.at_rest[odd]  # what the fricctl pipeline keeps: the encoder still 2 samples either side
print(f"their error |Tm| - |true friction|: up to {error.max():.3f} N*m; the fricctl pipeline's at-rest "
      f"test keeps {int(kept.sum())} of them" + (f", off by at most {1e3 * error[kept].max():.1f} mN*m"
                                                   if kept.any() else ""))
assert np.all(error[kept] < 0.002)

# %% [markdown]
# The paper pipeline trains on all of them.  The fricctl pipeline's at-rest test (no count
# two samples before or after) drops every one that is more than 2 mN m off; the few it
# keeps (if any, printed) sit just above $F_s$ where the joint creeps, and their error is
# below 2 mN m, about 1 % of $F_s$.

# %% mystnb={"figure": {"caption": "The paper pipeline's net of Sections 1-4: its estimate $\\hat T_{at}$ against the velocity $\\omega$ for several motor torques $T_m$, solid inside the training envelope (its velocity range shaded) and dotted outside it, where the net extrapolates."}}
lo, hi = net.envelope_low, net.envelope_high
print(f"envelope: Tm in [{lo[0]:.3f}, {hi[0]:.3f}] N*m, omega in [{lo[1]:.2f}, {hi[1]:.2f}] rad/s")
print(f"gain at rest g = dTat/dTm(0, 0) = {net.gain_at_rest():.3f} (Chapter 5: it sets the dead zone)")
w = np.linspace(2 * lo[1], 2 * hi[1], 201)
print(f"at Tm = 0: {np.count_nonzero(net.outside_envelope(0.0, w))} of {w.size} velocities on a "
      f"grid twice the envelope lie outside it")
figures.plot_friction_map(net)
plt.show()

# %% [markdown]
# ## 7. Exporting to C, saving and loading
#
# A 500 Hz controller evaluates the net 500 times a second; [`c_source`](#fricctl.nn.c_source) writes a
# self-contained C function (with the same scaling and optional clipping).  The
# JSON file ([`save_net`](#fricctl.nn.save_net), [`load_net`](#fricctl.nn.load_net)) keeps
# weights, scaling, envelope and metadata -- no pickle.

# %%
src = c_source(net)
print("\n".join(src.splitlines()[:6]))
print(f"... {len(src.splitlines())} lines of C")
assert "double fricctl_friction_net(double tm, double omega, int clip)" in src
with tempfile.TemporaryDirectory() as tmp:
    path = save_net(net, Path(tmp) / "net.json")
    again = load_net(path)
    print(f"saved {path.stat().st_size} bytes; metadata keys: {sorted(again.metadata)}")
tm_grid, w_grid = np.meshgrid(np.linspace(lo[0], hi[0], 21), np.linspace(lo[1], hi[1], 21))
assert np.array_equal(again(tm_grid, w_grid), net(tm_grid, w_grid))  # round trip is exact

# %% [markdown]
# ## Summary
#
# * The patterns are measured friction, $T_{at} = T_m - I\hat\alpha$: while the joint is
#   stuck they say $T_{at} = T_m$ for any torque up to breakaway, while it slides roughly
#   $F_c + b\,\omega$, and a smooth network has to bridge the two at $\omega = 0$.
# * On the same patterns, Levenberg-Marquardt in CasADi ended at a lower training loss than
#   the paper's back-propagation; with a schedule, a velocity scale and several starts,
#   back-propagation reaches it in most seeds (Exercise 2).
# * The fit and $R^2$ are tied by $\text{fit} = 100\,(1 - \sqrt{1 - R^2})$; on measured
#   patterns neither reached the paper's 98 %, while the same network trained on exact
#   patterns fitted far better: the acceleration estimate, not the four tanh units, limits
#   the accuracy.
# * The gain at rest $g$ came out above one in every seed of the paper's recipe -- the
#   stuck and the sliding patterns blended at $\omega = 0$, a property of the target, not of
#   the estimator (Exercise 1) -- and inside the certified band in every seed of the fricctl
#   pipeline, checked again by central differences.
# * Patterns recorded "at rest" above the breakaway level are the start of a motion the
#   encoder has not counted yet; the fricctl pipeline's at-rest test drops the ones that are
#   far off.
# * The network is exported as a self-contained C function and saved as JSON; the round
#   trip is exact.

# %% [markdown]
# ## Exercises
#
# 1. Train with `estimator="savitzky_golay"` (pass `window_length=51`) instead of
#    the paper's polynomial segments: how do the fit, R^2 and the gain at rest move?
# 2. Increase `BACKPROP_EPOCHS`: does the paper's back-propagation reach the CasADi
#    trainer's final loss?  Then train it with the options
#    `fricctl.nn.train.backprop.CONVERGING` (a learning-rate schedule, the velocity
#    input re-scaled for the descent, several starts) on LM's own patterns: does it reach
#    LM's loss now, after how many epochs, and how long does that take next to LM?
# 3. Fit only the sliding patterns (`net_run.train.subset(net_run.train.omega != 0)`).
#    What does the resulting net predict at rest, and why is that dangerous for the
#    compensator of Chapter 5?

# %% tags=["solution"]
# Exercise 1.  The Savitzky-Golay estimate moves the fit (printed) and the gain at rest
# not at all in kind: g stays above one in every seed.  The cause is the target (stuck
# patterns blended with sliding ones at omega = 0, Section 5), not the estimator.
for k in SEEDS:
    sg = paper.train_paper_network(p, fast=FAST, seed=k, estimator="savitzky_golay", window_length=51)
    poly = nets[("paper", k)]
    print(f"seed {k}: Savitzky-Golay fit {sg.fit_held_out.fit_percent:.1f} % (R^2 {sg.fit_held_out.r_squared:.3f}), "
          f"g = {sg.net.gain_at_rest():.3f}; polynomial segments fit {poly.fit_held_out.fit_percent:.1f} % "
          f"(R^2 {poly.fit_held_out.r_squared:.3f}), g = {g[('paper', k)]:.3f}")
    assert sg.net.gain_at_rest() > 1 and sg.fit_held_out.fit_percent < 98

# %% tags=["solution"] mystnb={"figure": {"caption": "Exercise 2, first seed: training loss against wall time of CasADi LM, of back-propagation at a constant rate for twice the epochs (it keeps jumping, far above LM's loss) and of back-propagation with `CONVERGING`; dotted: LM's final loss + 5 %."}}
# Exercise 2.  More epochs do not help the paper's constant rate.
# With one pattern per update and
# momentum 0.9, a rate `lr` is an effective step of `lr / (1 - 0.9) = 10 lr` on the
# scaled problem: the steps keep throwing hidden units into saturation, so the loss never
# settles, however long it runs (below: twice the epochs of Section 3).  Three changes
# make the same back-propagation converge (`CONVERGING`; the module docstring of
# `fricctl.nn.train.backprop` gives the measurement behind each):
#
# * a **cosine schedule**: the rate falls to zero over each start, so the descent ends
#   at the bottom of its basin instead of rattling around it;
# * a **velocity scale** for the descent: the net is trained on `omega / velocity_scale`
#   (10 rad/s) instead of the velocity scaled over its whole range, where most patterns
#   sit at `omega = 0` and most sliding ones close to it; the weights are folded back
#   afterwards, so the stored net is scaled like every other;
# * **five starts**, the best kept -- LM keeps the best of three, and the loss surface
#   has several basins.
#
# "Reached" below means a final training loss within 5 % of LM's, on the same patterns
# (the <= 4000 that the pipeline trained LM on); the times are first-hitting times of
# that loss in each trainer's own history, in this run.
from fricctl.nn.train.backprop import CONVERGING

print({k: CONVERGING[k] for k in ("schedule", "learning_rate", "epochs", "restarts", "velocity_scale")})
assert (CONVERGING["schedule"], CONVERGING["restarts"], CONVERGING["velocity_scale"]) == ("cosine", 5, 10.0)
assert lm.net.metadata["restarts"] == 3  # LM's starts
lm_loss = lm.history.loss[-1]
longer = train_network(net_run.train, trainer="backprop", epochs=2 * BACKPROP_EPOCHS,
                       max_patterns=2000, rng=np.random.default_rng(SEED))
tail = longer.history.loss[BACKPROP_EPOCHS:]
print(f"constant rate, {2 * BACKPROP_EPOCHS} epochs: final loss {longer.history.loss[-1] / lm_loss:.1f}x "
      f"LM's; over the last {BACKPROP_EPOCHS} epochs between {tail.min() / lm_loss:.1f}x and "
      f"{tail.max() / lm_loss:.0f}x")
assert tail.min() > 3 * lm_loss and tail.max() > 10 * tail.min()  # far above LM, not settling

ratios = []
for seed in (SEED, SEED + 1, SEED + 2):
    # LM as the pipeline trains it (the same subset and starts from the same generator): for
    # SEED that is the pipeline's own net of Section 3, not trained again
    lm_s = lm if seed == SEED else train_network(net_run.train, rng=np.random.default_rng(seed))
    bp_s = train_network(net_run.train, trainer="backprop", rng=np.random.default_rng(seed),
                         **CONVERGING)
    target = 1.05 * lm_s.history.loss[-1]
    ratios.append(bp_s.history.loss[-1] / lm_s.history.loss[-1])
    hit = np.flatnonzero(bp_s.history.loss <= target)
    when = (f"reached after {hit[0]} epochs, {bp_s.history.time_to_reach(target):.2f} s "
            f"(LM: {lm_s.history.time_to_reach(target):.2f} s)" if hit.size else "not reached")
    print(f"seed {seed}: back-prop's final loss {ratios[-1]:.2f}x LM's; {when}; whole run "
          f"{bp_s.history.elapsed[-1]:.2f} s (LM {lm_s.history.elapsed[-1]:.2f} s)")
    if seed == SEED:
        ax = figures.plot_training_history(lm_s.history, against="time")
        figures.plot_training_history(longer.history, ax=ax, against="time")
        figures.plot_training_history(bp_s.history, ax=ax, against="time")
        ax.axhline(target, color="0.5", lw=0.8, ls=":")
        ax.legend(["CasADi LM", "back-prop, constant rate", "back-prop, CONVERGING",
                   "LM's loss + 5 %"], fontsize="small")
reached = int(np.sum(np.array(ratios) <= 1.05))
print(f"reached LM's loss in {reached} of {len(ratios)} seeds")
assert reached >= 2  # a rate over seeds, not one seed's luck
plt.show()
# A ratio under 1 above means back-prop's five starts found a deeper minimum than LM's
# three.  How often all this holds over seeds of the whole pipeline (the split, the
# subset and the starts), and how long each trainer takes, is measured in
# `benchmarks/README.md` ("Neural network"), with the seeds where back-prop ends in a
# different basin above LM's loss.  It is a statement about these patterns: on much
# smaller training sets LM goes deeper still and the recipe reaches it far less often.


# %% tags=["solution"]
# Exercise 3.  A net that never saw a stuck pattern has learnt nothing about Tm at rest:
# at omega = 0 it returns whatever its tanh units extrapolate to, and its slope there is
# not tied to one at all -- above one in every seed here, so the stuck loop of Chapter 5,
# Tm <- Tc + T^at(Tm, 0), winds the motor torque up by itself.
sliding_g = []
for k in SEEDS:
    tr = nets[("paper", k)].train
    sl = train_network(tr.subset(tr.omega != 0), rng=np.random.default_rng(k))
    sliding_g.append(sl.net.gain_at_rest())
    at = sl.net(np.array([-0.1, 0.0, 0.1]), np.zeros(3))
    print(f"seed {k}: net(Tm, 0) at Tm = -0.1, 0, 0.1 N*m: {np.round(at, 3)} N*m; g = {sliding_g[-1]:.2f}")
assert min(sliding_g) > 1

# %% [markdown]
# ## References
#
# * [Gervini, Gomes & da Rosa 2003](#gervini2003): the friction patterns (Fig. 5), the 2-4-1
#   network, Fig. 8.
# * [Rumelhart, Hinton & Williams 1986](#rumelhart1986): back-propagation.
# * [Levenberg 1944](#levenberg1944) and [Marquardt 1963](#marquardt1963): the
#   Levenberg-Marquardt trainer.
# * [Ljung 1999](#ljung1999): the normalised fit.
# * [Andersson et al. 2019 (CasADi)](#andersson2019casadi).
#
# In fricctl: [`train_paper_network`](#fricctl.paper.train_paper_network),
# [`train_network`](#fricctl.bench.experiments.train_network),
# [`FrictionNet`](#fricctl.nn.FrictionNet), [`fit_percent`](#fricctl.nn.fit_percent),
# [`r_squared`](#fricctl.nn.r_squared), [`fit_report`](#fricctl.nn.fit_report),
# [`c_source`](#fricctl.nn.c_source), [`save_net`](#fricctl.nn.save_net),
# [`load_net`](#fricctl.nn.load_net), [`plot_fig5`](#fricctl.figures.plot_fig5),
# [`plot_fig8`](#fricctl.figures.plot_fig8),
# [`plot_training_history`](#fricctl.figures.plot_training_history),
# [`plot_friction_map`](#fricctl.figures.plot_friction_map).
