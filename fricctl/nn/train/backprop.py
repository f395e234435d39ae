"""The paper's trainer: back-propagation with momentum (numba inner loop).

The update after each batch is the classical one (Rumelhart et al., 1986)::

    dtheta <- momentum*dtheta - learning_rate * mean_batch(grad 0.5*(yn - tn)^2)
    theta  <- theta + dtheta

on the scaled problem of :mod:`fricctl.nn.train.core`.  The pattern order is
shuffled each epoch.
"""

from __future__ import annotations

import functools
import math
import threading

import numpy as np
from numba import njit

from ... import _validate as v
from ..layout import forward_theta
from .core import LoopResult, Trainer, TrainingProblem, TrainingResult

__all__ = ["train_backprop", "loop", "loss_gradient", "epoch", "compile_kernels", "TRAINER"]

# Numba caveat: the on-disk cache of these kernels is keyed on this file only, so
# after editing forward_theta in layout.py, delete __pycache__ (or touch this file).


@njit(cache=True)
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


@njit(cache=True)
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


@njit(cache=True)
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


def loop(problem: TrainingProblem, *, learning_rate: float = 0.05, momentum: float = 0.9,
         epochs: int = 1000, batch_size: int = 1) -> LoopResult:
    """The inner loop: ``epochs`` passes of gradient descent with momentum."""
    lr = v.real("learning_rate", learning_rate, positive=True)
    mom = v.real("momentum", momentum)
    if not 0 <= mom < 1:
        raise ValueError(f"momentum must lie in [0, 1), got {momentum!r}")
    epochs = v.integer("epochs", epochs, low=1)
    batch = min(v.integer("batch_size", batch_size, low=1), problem.n)
    h, xn, tn = problem.hidden, problem.xn, problem.tn
    theta = problem.initial_theta()
    velocity = np.zeros_like(theta)
    loss = np.empty(epochs + 1)
    elapsed = np.empty(epochs + 1)
    loss[0] = loss_gradient(theta, xn, tn, h, np.empty_like(theta))
    elapsed[0] = problem.elapsed()
    for k in range(epochs):
        order = problem.rng.permutation(problem.n)
        loss[k + 1] = epoch(theta, velocity, xn, tn, order, batch, lr, mom, h)
        elapsed[k + 1] = problem.elapsed()
        if not math.isfinite(loss[k + 1]):
            raise ValueError(f"back-propagation diverged at epoch {k + 1} (loss is not "
                             f"finite); lower learning_rate={lr}")
    return LoopResult(theta=theta, loss=loss, elapsed=elapsed,
                      metadata={"epochs": epochs, "learning_rate": lr, "momentum": mom,
                                "batch_size": batch})


TRAINER = Trainer(name="backprop", step="epoch", loop=loop, prepare=compile_kernels,
                  description="back-propagation with momentum, the paper's trainer "
                              "(numba inner loop)")


def train_backprop(tm, omega, target, *, hidden: int = 4, learning_rate: float = 0.05,
                   momentum: float = 0.9, epochs: int = 1000, batch_size: int = 1,
                   rng: np.random.Generator, metadata: dict | None = None) -> TrainingResult:
    """The paper's trainer: gradient descent with momentum (back-propagation).

    The update after each batch is the classical one (Rumelhart et al., 1986)::

        dtheta <- momentum*dtheta - learning_rate * mean_batch(grad 0.5*(yn - tn)^2)
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
        Step size on the scaled problem, > 0 [-].
    momentum : float
        Momentum factor in [0, 1) [-].
    epochs : int
        Passes over the patterns, >= 1.
    batch_size : int
        Patterns per update: 1 is per-pattern (on-line) training as in the
        paper; ``len(tm)`` is batch gradient descent.
    rng : numpy.random.Generator
        Source of the initial weights and the pattern order.
    metadata : dict, optional
        Extra JSON-serialisable entries stored with the net (e.g. the seed).

    Returns
    -------
    TrainingResult
        ``.net`` and ``.history``; history entries are epochs.

    Notes
    -----
    No early stopping, learning-rate schedule or weight decay: the paper's
    plain method.  The inner loop is compiled with numba, so the comparison
    with :func:`~fricctl.nn.train.lm.train_casadi` is between algorithms, not
    interpreters.

    Examples
    --------
    >>> from fricctl.nn import smooth_friction_patterns
    >>> pats = smooth_friction_patterns(np.random.default_rng(0), n_sliding=200, n_stuck=0)
    >>> tm, om, f = pats.tm, pats.omega, pats.friction
    >>> res = train_backprop(tm, om, f, epochs=50, rng=np.random.default_rng(1))
    >>> bool(res.history.loss[-1] < res.history.loss[0])
    True
    """
    return TRAINER.train(tm, omega, target, hidden=hidden, rng=rng, metadata=metadata,
                         learning_rate=learning_rate, momentum=momentum, epochs=epochs,
                         batch_size=batch_size)
