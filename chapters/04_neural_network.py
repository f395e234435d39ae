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

# %%
import os
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from fricctl import figures
from fricctl import paper
from fricctl.bench.experiments import train_network
from fricctl.nn import c_source, fit_percent, fit_report, load_net, r_squared, save_net
from fricctl.params import paper_actuator

FAST = os.environ.get("FRICCTL_FAST") == "1"
SEED = 0                               # seed of the split and the trainers [-]
BACKPROP_EPOCHS = 200 if FAST else 2000  # epochs of the paper's back-propagation [-]

# %% [markdown]
# ## 1. The patterns (Fig. 5)
#
# `train_paper_network` runs the whole pipeline once: open-loop torque steps of
# growing amplitude up to the maximum torque, closed-loop P and PD step
# sequences, the paper's polynomial velocity/acceleration estimator on the encoder
# record, and an 80/20 split of the patterns into training and held-out sets.

# %%
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
# Notice the two kinds of pattern.  While the joint is stuck, `alpha_hat = 0` and
# the pattern says "friction equals the motor torque", for any torque up to the
# breakaway level -- a vertical line at `omega = 0`.  While it slides, friction is
# roughly `Fc + b*omega`.  A smooth net has to bridge the two at `omega = 0`.
#
# ## 2. Two trainers
#
# The paper trains with back-propagation and momentum.  fricctl also offers a
# second-order trainer, Levenberg-Marquardt on the least-squares problem, posed
# in CasADi (exact Jacobian by algorithmic differentiation).  Same patterns, same
# seed:

# %%
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
# ## 3. What does "98 % accuracy" mean?  (Fig. 8)
#
# The paper reports 98 % without a definition.  Two common ones:
#
# * the normalised **fit** `100 (1 - ||e|| / ||y - mean y||)` of system identification;
# * the coefficient of determination **R^2** `= 1 - ||e||^2 / ||y - mean y||^2`.
#
# They are tied by `fit = 100 (1 - sqrt(1 - R^2))`, so an R^2 of 0.98 is a much
# lower fit (printed below).  Measured on the held-out patterns, and against the
# simulator's *true* friction (which a lab never has):

# %%
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
# The paper's number is plausible for a good measuring chain; ours, from an encoder
# of 3.14e-5 rad at 500 Hz and torque steps, is not that good.
#
# ## 4. The envelope: where the net may be trusted
#
# A net extrapolates badly.  fricctl stores the box of the training inputs with
# the net; the compiled loop can clip its inputs to it (`NNCompensator(clip=True)`).
# The box is generous: it spans every torque at every velocity, though most of its
# area held no patterns.  Look at one corner, large torque at zero velocity: a
# joint at rest cannot hold more than the breakaway torque, yet a few patterns sit
# there, all with `Tat = Tm`.  They are artefacts of the measuring chain: the first
# samples of a torque step, taken before the encoder has counted the motion the step
# starts, so the estimator calls them "at rest" and the patterns claim a friction far
# above breakaway.

# %%
lo, hi = net.envelope_low, net.envelope_high
pats = net_run.patterns
odd = (pats.omega == 0) & (np.abs(pats.tm) > p.static)
print(f"patterns 'at rest' with |Tm| above the breakaway {p.static:.2f} N*m: {int(odd.sum())} of "
      f"{int((pats.omega == 0).sum())} at rest; largest |Tm| there {np.abs(pats.tm[odd]).max():.3f} N*m")
# the encoder counts within the next three samples of each of them: the start of a motion
soon = []
for e in net_run.experiments:
    moves = np.r_[np.diff(e.run.position), 0.0] != 0  # motion between sample k and k+1
    soon.append((moves | np.r_[moves[1:], False] | np.r_[moves[2:], False, False])[5:-5])
assert odd.any() and np.all(np.concatenate(soon)[odd])
print(f"envelope: Tm in [{lo[0]:.3f}, {hi[0]:.3f}] N*m, omega in [{lo[1]:.2f}, {hi[1]:.2f}] rad/s")
print(f"gain at rest g = dTat/dTm(0, 0) = {net.gain_at_rest():.3f} (Chapter 5: it sets the dead zone)")
w = np.linspace(2 * lo[1], 2 * hi[1], 201)
print(f"at Tm = 0: {np.count_nonzero(net.outside_envelope(0.0, w))} of {w.size} velocities on a "
      f"grid twice the envelope lie outside it")
figures.plot_friction_map(net)
plt.show()

# %% [markdown]
# ## 5. Exporting to C, saving and loading
#
# A 500 Hz controller evaluates the net 500 times a second; `c_source` writes a
# self-contained C function (with the same scaling and optional clipping).  The
# JSON file keeps weights, scaling, envelope and metadata -- no pickle.

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

# %% [markdown]
# ### Solution to exercise 2
#
# More epochs do not help the paper's constant rate.  With one pattern per update and
# momentum 0.9, a rate `lr` is an effective step of `lr / (1 - 0.9) = 10 lr` on the
# scaled problem: the steps keep throwing hidden units into saturation, so the loss never
# settles, however long it runs (below: twice the epochs of Section 2).  Three changes
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

# %%
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
    lm_s = train_network(net_run.train, rng=np.random.default_rng(seed))  # as the pipeline trains LM
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

# %% [markdown]
# A ratio under 1 above means back-prop's five starts found a deeper minimum than LM's
# three.  How often all this holds over seeds of the whole pipeline (the split, the
# subset and the starts), and how long each trainer takes, is measured in
# `benchmarks/README.md` ("Neural network"), with the seeds where back-prop ends in a
# different basin above LM's loss.  It is a statement about these patterns: on much
# smaller training sets LM goes deeper still and the recipe reaches it far less often.
