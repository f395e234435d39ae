"""The paper's trainer: back-propagation with momentum (numba inner loop).

The update after each batch is the classical one (Rumelhart et al., 1986)::

    dtheta <- momentum*dtheta - learning_rate_k * mean_batch(grad 0.5*(yn - tn)^2)
    theta  <- theta + dtheta

on the scaled problem of :mod:`fricctl.nn.train.core`.  The pattern order is
shuffled each epoch.  By default ``learning_rate_k`` is constant (the paper's
method, bit for bit what this trainer always did); :data:`CONVERGING` is the set of
options that makes it reach the Levenberg-Marquardt loss on the paper's patterns
(a cosine learning-rate schedule, the velocity input re-scaled for the descent,
several starts).

Why each option, measured on the paper's patterns (``train_paper_network``; both
trainers on the same <= 4000 training patterns; "reaches" = final loss within 5 % of
LM's; the recipe's own numbers are in ``benchmarks/README.md``):

* **the schedule.**  With the constant default (0.05, momentum 0.9, one pattern per
  update: an effective step of 0.5) the loss over the last 1000 of 2000 epochs ranges
  from ~10x to ~230x LM's (medians over 20 seeds) and ends 9-85x above it: the steps
  throw hidden units into saturation and the net never settles.  A smaller constant
  rate (0.003) settles but rattles: its last epoch is 4-26 % above its best (4 seeds).
  Annealing the rate to zero with a cosine (``schedule="cosine"``) ends at the bottom
  of the basin it is in: started from the same weights as LM, it ended in LM's basin in
  17 of 24 starts, and there within 0-4 % of LM's loss.  Shuffling was there already;
  momentum 0 with a 10x rate, mini-batches of 16 with a 16x rate, or a 1000-epoch
  anneal did not change how often it reaches LM (62-67 % against 62 %, fast-mode
  patterns, 24 seeds, 5 starts).  No gradient clipping is needed below a rate of ~0.01.
* **the velocity scale.**  The seam scales each input to [-1, 1] over its range;
  70 % of the patterns are at rest (omega = 0) and the sliding ones have a median
  |omega| of 2.3 rad/s against a range of +-29 rad/s, so nearly all the data sit
  within 0.1 of the origin of the velocity input.  The deepest minima (those LM's best
  of three starts often finds) resolve that region; from range scaling the descent
  reached them in 0 and 1 of 20 starts on the two hardest seeds.  Training on
  ``omega / velocity_scale`` instead (the weights folded back to the seam's scaling
  afterwards, exactly) puts the initial tanh units and the step sizes where the data
  are.  Seeds reaching LM's loss with 3 starts (full mode, seeds 0-11, rate 0.003,
  300 epochs): range scaling 58 %, 14 rad/s 58 %, 10 rad/s 83 %, 7 rad/s 83 %,
  4.8 rad/s 67 %, 2.9 rad/s 17 %; 10 rad/s is about the RMS velocity of the sliding
  patterns (8.1 rad/s).  Standardising both inputs (mean, std) did not help (50 % with
  5 starts, 24 seeds): the torque input is best left as the seam scales it.
* **restarts.**  The loss surface has several basins (final losses 0.7-1.9x LM's
  from different initial weights, for LM as for back-prop), and LM's loss is the
  best of its three starts; back-prop keeps the best of ``restarts`` starts (each a
  full schedule).  The first three initial weight vectors are the ones LM draws
  from the same generator, so the comparison is start for start.  Five starts of 300
  epochs at 0.001 reached LM in 18 of 20 full-mode seeds (median 0.69 of LM's loss).
* **where it does not hold.**  The recipe is measured on the pipeline's 4000-pattern
  training sets: on 1000-pattern subsets LM goes deeper (down to half the loss) and
  1000 epochs from one start reached LM's one-start loss in 3 of 8 seeds.

The default stays the paper's constant rate: this trainer is the paper's method
wherever fricctl shows it (chapter 04 compares it with LM as the paper used it; the
"paper" pipeline of issue 11 is the literal recipe), and its results must not move
under anyone who relied on them.  :data:`CONVERGING` is one ``**`` away.

Numba caveat: the on-disk cache of these kernels is keyed on this file only, so
after editing ``forward_theta`` in ``layout.py``, delete ``__pycache__`` (or touch
this file).
"""

from __future__ import annotations

import functools
import math
import threading
import types

import numpy as np

from ..._jit import jit
from ... import _validate as v
from ..layout import forward_theta, pack, unpack
from .core import (MAX_RESTARTS, LoopResult, Recipe, Trainer, TrainerOption, TrainingProblem,
                   TrainingResult, check_work)

__all__ = ["train_backprop", "loop", "loss_gradient", "epoch", "learning_rates", "SCHEDULES",
           "CONVERGING", "compile_kernels", "TRAINER", "MAX_EPOCHS", "MAX_WORK"]

#: Most epochs per start (the paper's recipe runs 1000, :data:`CONVERGING` 300).
MAX_EPOCHS = 100_000
#: Most ``restarts * epochs * patterns * hidden`` one training may take: about 10 to 20
#: minutes at the ~5e-8 s per pattern, epoch and hidden unit measured on one core (the
#: paper's recipe on 4000 patterns is 1.6e7, a few seconds).
MAX_WORK = 2e10

#: The learning-rate schedules (:func:`learning_rates`).
SCHEDULES = ("constant", "cosine")

#: Options with which back-propagation reaches the Levenberg-Marquardt loss on the
#: paper's patterns (see the module docstring and ``benchmarks/README.md``):
#: ``train_backprop(tm, omega, friction, rng=rng, **CONVERGING)``.
CONVERGING = types.MappingProxyType(dict(
    schedule="cosine", learning_rate=0.001, momentum=0.9, epochs=300, batch_size=1,
    restarts=5, velocity_scale=10.0))


@jit
def _accumulate(theta, x0, x1, t, h, g, hid):
    # One pattern: loss 0.5*(yn - t)^2 on the scaled output; adds its gradient
    # to g and returns the loss.
    yn = forward_theta(theta, h, x0, x1, hid)
    e = yn - t
    for j in range(h):
        d = e * theta[3 * h + j] * (1.0 - hid[j] * hid[j])
        g[2 * j] += d * x0
        g[2 * j + 1] += d * x1
        g[2 * h + j] += d
        g[3 * h + j] += e * hid[j]
    g[4 * h] += e
    return 0.5 * e * e


@jit
def loss_gradient(theta, xn, tn, h, g):
    """Mean loss ``0.5*mean((yn - tn)^2)`` over all patterns; writes its gradient into ``g``."""
    g[:] = 0.0
    hid = np.empty(h)
    loss = 0.0
    n = tn.size
    for i in range(n):
        loss += _accumulate(theta, xn[0, i], xn[1, i], tn[i], h, g, hid)
    for p in range(g.size):
        g[p] = g[p] / n
    return loss / n


@jit
def epoch(theta, velocity, xn, tn, order, batch, lr, mom, h):
    """One pass over the patterns in ``order`` (updates ``theta`` and ``velocity`` in place);
    returns the mean loss over all patterns after the epoch."""
    n = order.size
    g = np.zeros(theta.size)
    hid = np.empty(h)
    for start in range(0, n, batch):
        stop = min(start + batch, n)
        g[:] = 0.0
        for k in range(start, stop):
            i = order[k]
            _accumulate(theta, xn[0, i], xn[1, i], tn[i], h, g, hid)
        m = stop - start
        for p in range(theta.size):
            velocity[p] = mom * velocity[p] - lr * g[p] / m
            theta[p] += velocity[p]
    loss = 0.0
    for i in range(n):
        yn = forward_theta(theta, h, xn[0, i], xn[1, i], hid)
        loss += 0.5 * (yn - tn[i]) ** 2
    return loss / n


# Thread executors: numba already serialises compilation under its global
# compiler lock; this lock and the cache make the first caller compile (or load
# from the on-disk cache) before any thread starts its clock, so no training
# history times the compiler, and later calls are a dictionary look-up.
_COMPILE_LOCK = threading.Lock()


@functools.lru_cache(maxsize=None)
def _compile_once() -> None:
    theta = np.zeros(5)
    xn = np.zeros((2, 2))
    tn = np.zeros(2)
    loss_gradient(theta, xn, tn, 1, np.zeros(5))
    epoch(theta, np.zeros(5), xn, tn, np.arange(2), 1, 0.1, 0.5, 1)


def compile_kernels() -> None:
    """Compile the kernels (or load them from numba's cache) now; safe from any thread."""
    with _COMPILE_LOCK:
        _compile_once()


def learning_rates(schedule: str, learning_rate: float, epochs: int) -> np.ndarray:
    """The learning rate of each epoch ``k = 0 .. epochs-1`` [-].

    ``"constant"``: ``learning_rate`` every epoch (the paper's method).
    ``"cosine"``: ``learning_rate * (1 + cos(pi*k/epochs)) / 2``, from ``learning_rate``
    down towards zero in the last epoch (Loshchilov & Hutter, 2017, without warm restarts).

    Examples
    --------
    >>> learning_rates("cosine", 0.01, 4)
    array([0.01      , 0.00853553, 0.005     , 0.00146447])
    """
    schedule = v.choice("schedule", schedule, SCHEDULES)
    lr = v.real("learning_rate", learning_rate, positive=True)
    epochs = v.integer("epochs", epochs, low=1)
    if schedule == "constant":
        return np.full(epochs, lr)
    return 0.5 * lr * (1.0 + np.cos(np.pi * np.arange(epochs) / epochs))


def _descent_velocity(problem: TrainingProblem, velocity_scale):
    """The velocity input the descent works on, ``a*xn[1] + b``, and ``(a, b)``.

    ``None``: the seam's scaled input itself (``a, b = 1, 0``).  A scale ``vs``
    [rad/s]: ``omega / vs`` (zero at rest), i.e. ``a = s/vs``, ``b = o/vs`` for the
    seam's ``omega = s*xn[1] + o``.
    """
    if velocity_scale is None:
        return problem.xn, 1.0, 0.0
    s = float(problem.scaling.input_scale[1])
    o = float(problem.scaling.input_offset[1])
    a, b = s / velocity_scale, o / velocity_scale
    xn = np.array(problem.xn)
    xn[1] = a * problem.xn[1] + b
    return xn, a, b


def _fold_velocity(theta: np.ndarray, hidden: int, a: float, b: float) -> np.ndarray:
    # w*(a*x + b) + c = (w*a)*x + (c + w*b): the same net on the seam's scaled input.
    if a == 1.0 and b == 0.0:
        return theta
    w = unpack(theta, hidden)
    return pack(np.column_stack([w.w1[:, 0], w.w1[:, 1] * a]), w.b1 + w.w1[:, 1] * b,
                w.w2, w.b2)


def loop(problem: TrainingProblem, *, learning_rate: float = 0.05, momentum: float = 0.9,
         epochs: int = 1000, batch_size: int = 1, schedule: str = "constant", restarts: int = 1,
         velocity_scale: float | None = None) -> LoopResult:
    """The inner loop: ``restarts`` starts of ``epochs`` passes of gradient descent with
    momentum, the start with the lowest final loss kept."""
    lr = v.real("learning_rate", learning_rate, positive=True)
    mom = v.real("momentum", momentum)
    if not 0 <= mom < 1:
        raise ValueError(f"momentum must lie in [0, 1), got {momentum!r}")
    epochs = v.integer("epochs", epochs, low=1)
    batch = min(v.integer("batch_size", batch_size, low=1), problem.n)
    schedule = v.choice("schedule", schedule, SCHEDULES)
    restarts = v.integer("restarts", restarts, low=1)
    if velocity_scale is not None:
        velocity_scale = v.real("velocity_scale", velocity_scale, positive=True, unit="rad/s")
    # bounded work: refused before anything the size of epochs is allocated
    if epochs > MAX_EPOCHS:
        raise ValueError(f"epochs={epochs} is more than the {MAX_EPOCHS} a start may run")
    if restarts > MAX_RESTARTS:
        raise ValueError(f"restarts={restarts} is more than the {MAX_RESTARTS} starts a training "
                         "may run")
    per_epoch = restarts * problem.n * problem.hidden
    check_work(f"restarts*epochs*patterns*hidden = {restarts}*{epochs}*{problem.n}*"
               f"{problem.hidden}", float(per_epoch) * epochs, MAX_WORK,
               f"at most {max(0, int(MAX_WORK // per_epoch))} epochs with these patterns, "
               "restarts and hidden units would finish")
    rates = learning_rates(schedule, lr, epochs)
    h, tn = problem.hidden, problem.tn
    xn, a, b = _descent_velocity(problem, velocity_scale)
    # All starting points first, then the pattern orders: with one start this is the
    # order of draws this trainer always made, and the first three starts are the
    # ones the Levenberg-Marquardt trainer draws from the same generator.
    thetas = [problem.initial_theta() for _ in range(restarts)]
    loss = np.empty(restarts * epochs + 1)
    elapsed = np.empty(restarts * epochs + 1)
    loss[0] = loss_gradient(thetas[0], xn, tn, h, np.empty_like(thetas[0]))
    elapsed[0] = problem.elapsed()
    best, best_loss, finals = 0, math.inf, []
    for r, theta in enumerate(thetas):
        velocity = np.zeros_like(theta)
        for k in range(epochs):
            order = problem.rng.permutation(problem.n)
            e = epoch(theta, velocity, xn, tn, order, batch, rates[k], mom, h)
            if not math.isfinite(e):
                raise ValueError(f"back-propagation diverged at epoch {k + 1} (loss is not "
                                 f"finite); lower learning_rate={lr}")
            # the loss of the best net so far: this start's, or a finished start's
            loss[r * epochs + k + 1] = min(e, best_loss)
            elapsed[r * epochs + k + 1] = problem.elapsed()
            problem.report(r * epochs + k + 1, restarts * epochs)
        finals.append(e)
        if e < best_loss:
            best, best_loss = r, e
    mse = [2.0 * f * problem.scaling.output_scale ** 2 for f in finals]
    return LoopResult(theta=_fold_velocity(thetas[best], h, a, b), loss=loss, elapsed=elapsed,
                      metadata={"epochs": epochs, "learning_rate": lr, "momentum": mom,
                                "batch_size": batch, "schedule": schedule, "restarts": restarts,
                                "velocity_scale": velocity_scale, "best_restart": best,
                                "restart_mse": mse})


TRAINER = Trainer(
    name="backprop", step="epoch", loop=loop, prepare=compile_kernels,
    description="back-propagation with momentum, the paper's trainer (numba inner loop)",
    flags=(TrainerOption(name="epochs", type=int, high=MAX_EPOCHS,
                         help="passes over the patterns per start"),
           TrainerOption(name="learning_rate", type=float,
                         help="step size (the first epoch's, for a schedule) [-]"),
           TrainerOption(name="momentum", type=float, help="momentum factor in [0, 1) [-]"),
           TrainerOption(name="batch_size", type=int,
                         help="patterns per update (1 = per pattern, as in the paper)"),
           TrainerOption(name="schedule", type=str, metavar="{" + ",".join(SCHEDULES) + "}",
                         help="learning rate per epoch (constant = the paper's; cosine = "
                              "annealed to zero over each start)"),
           TrainerOption(name="velocity_scale", type=float, metavar="RAD_PER_S",
                         help="the descent sees omega / this (none: the range scaling of "
                              "every trainer) [rad/s]"),
           TrainerOption(name="restarts", type=int, high=MAX_RESTARTS,
                         help="starting points, each a full schedule, the best kept")),
    # "paper" is what `fricctl train --trainer backprop` has always run (a constant rate of
    # 0.01, not the loop's 0.05: the command's own choice, kept so that its nets do not move)
    recipes=(Recipe(name="paper", options=dict(epochs=1000, learning_rate=0.01, momentum=0.9,
                                               batch_size=1, schedule="constant", restarts=1,
                                               velocity_scale=None),
                    description="constant rate as in the paper (epochs 1000, learning rate "
                                "0.01, one start)"),
             Recipe(name="converging", options=CONVERGING,
                    description="the options measured to reach the Levenberg-Marquardt loss on "
                                "the paper's patterns (fricctl.nn.train.backprop.CONVERGING)")),
    limits=(f"at most {MAX_EPOCHS:,} epochs per start".replace(",", " ")
            + f" and restarts*epochs*patterns*hidden <= {MAX_WORK:.0e}".replace("e+", "e")
            + " (~10-20 min on one core)"))


def train_backprop(tm, omega, target, *, hidden: int = 4, learning_rate: float = 0.05,
                   momentum: float = 0.9, epochs: int = 1000, batch_size: int = 1,
                   schedule: str = "constant", restarts: int = 1,
                   velocity_scale: float | None = None, rng: np.random.Generator,
                   metadata: dict | None = None) -> TrainingResult:
    """The paper's trainer: gradient descent with momentum (back-propagation).

    The update after each batch is the classical one (Rumelhart et al., 1986)::

        dtheta <- momentum*dtheta - learning_rate_k * mean_batch(grad 0.5*(yn - tn)^2)
        theta  <- theta + dtheta

    on scaled inputs (each to [-1, 1] over its range) and a scaled target (zero
    mean, unit standard deviation).  The pattern order is shuffled each epoch.

    Parameters
    ----------
    tm, omega, target : array_like
        1-D patterns: motor torque [N*m], velocity [rad/s], friction [N*m].
    hidden : int
        Hidden units H (4 in the paper).
    learning_rate : float
        Step size on the scaled problem (the first epoch's, for a schedule), > 0 [-].
    momentum : float
        Momentum factor in [0, 1) [-].
    epochs : int
        Passes over the patterns per start, >= 1.
    batch_size : int
        Patterns per update: 1 is per-pattern (on-line) training as in the
        paper; ``len(tm)`` is batch gradient descent.
    schedule : {"constant", "cosine"}
        Learning rate per epoch (:func:`learning_rates`): ``"constant"`` is the
        paper's method; ``"cosine"`` anneals it to zero over each start's epochs.
    restarts : int
        Independent starts (each its own initial weights and full schedule); the net
        with the lowest final training loss is kept, >= 1.
    velocity_scale : float or None
        ``None``: descend on the seam's scaled inputs.  A value: the descent sees the
        velocity input as ``omega / velocity_scale`` and the trained weights are folded
        back to the seam's scaling (the same net up to rounding); it changes the
        conditioning and where the initial tanh units fall, not the model [rad/s].
    rng : numpy.random.Generator
        Source of the initial weights and the pattern order.
    metadata : dict, optional
        Extra JSON-serialisable entries stored with the net (e.g. the seed).

    Returns
    -------
    TrainingResult
        ``.net`` and ``.history``; history entries are epochs (``restarts*epochs``
        of them after the initial loss), each the loss of the best net so far: the
        current start's, or the best finished start's if lower.

    Notes
    -----
    The defaults are the paper's plain method (constant rate, one start, no early
    stopping or weight decay) and reproduce this trainer's earlier results bit for
    bit; on the paper's patterns it does not converge (the loss oscillates far above
    the Levenberg-Marquardt loss).  :data:`CONVERGING` holds the options measured to
    reach that loss (module docstring; ``benchmarks/README.md``).  The inner loop is
    compiled with numba, so the comparison with
    :func:`~fricctl.nn.train.lm.train_casadi` is between algorithms, not interpreters.

    Examples
    --------
    >>> from fricctl.nn import smooth_friction_patterns
    >>> pats = smooth_friction_patterns(np.random.default_rng(0), n_sliding=200, n_stuck=0)
    >>> tm, om, f = pats.tm, pats.omega, pats.friction
    >>> res = train_backprop(tm, om, f, epochs=50, rng=np.random.default_rng(1))
    >>> bool(res.history.loss[-1] < res.history.loss[0])
    True
    >>> res = train_backprop(tm, om, f, rng=np.random.default_rng(1),
    ...                      **{**CONVERGING, "epochs": 50, "restarts": 2})
    >>> res.history.loss.size, res.net.metadata["schedule"]
    (101, 'cosine')
    """
    return TRAINER.train(tm, omega, target, hidden=hidden, rng=rng, metadata=metadata,
                         learning_rate=learning_rate, momentum=momentum, epochs=epochs,
                         batch_size=batch_size, schedule=schedule, restarts=restarts,
                         velocity_scale=velocity_scale)
