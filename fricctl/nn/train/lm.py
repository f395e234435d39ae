"""Second-order trainer: Levenberg-Marquardt with CasADi derivatives (registered as ``"casadi"``).

Minimises ``0.5*sum_i (yn_i - tn_i)^2`` over the 4H+1 weights of the scaled
problem of :mod:`fricctl.nn.train.core`.  The residuals and their exact Jacobian
are a CasADi expression graph (algorithmic differentiation over all patterns);
each iteration solves ``(J'J + mu*I) d = -J'r`` and updates the damping ``mu``
with Nielsen's gain-ratio rule (Madsen, Nielsen & Tingleff, 2004).  Several
seeded starting points are run and the best net is kept.

The registry name stays ``"casadi"`` (the name saved in every net's metadata and
taken by ``fricctl train --trainer``); the module is named after the method.
"""

from __future__ import annotations

import functools
import math
import threading
from dataclasses import dataclass

import numpy as np

from ... import _validate as v
from .core import (MAX_RESTARTS, LoopResult, Trainer, TrainerOption, TrainingProblem,
                   TrainingResult, check_work)

__all__ = ["train_casadi", "loop", "ResidualFunctions", "residual_functions", "clear_cache",
           "TRAINER", "MAX_ITERATIONS", "MAX_WORK"]

#: Most Levenberg-Marquardt iterations per start (the default is 200).
MAX_ITERATIONS = 10_000
#: Most ``restarts * max_iterations * patterns * (4*hidden + 1)**2`` one training may take
#: (the cost of the normal equations J'J, the bulk of an iteration for larger nets: ~2e-9 s
#: per unit measured at H = 64; the defaults on 4000 patterns at H = 4 are 6.9e8).
MAX_WORK = 1e12


@dataclass(frozen=True, kw_only=True, eq=False)
class ResidualFunctions:
    """CasADi Functions of ``(theta, xn 2xN, tn 1xN)`` for one (H, N)."""

    residuals: object
    """``casadi.Function``: ``r = yn - tn``, shape (N, 1)."""
    residuals_jacobian: object
    """``casadi.Function``: ``r`` and the exact Jacobian ``dr/dtheta``, shape (N, 4H+1)."""


# Thread executors (robustness_sweep): building a CasADi graph is not
# thread-safe, and two threads missing the cache together would both build.  The
# lock covers look-up and build, so each (H, N) is built once; look-ups cost
# microseconds.  Evaluation is per call (each train_casadi call checks out its
# own buffers), so no lock is held while training.
_BUILD_LOCK = threading.Lock()


@functools.lru_cache(maxsize=16)
def _build(hidden: int, n: int) -> ResidualFunctions:
    import casadi as ca  # lazily: `import fricctl.nn` does not load CasADi

    theta = ca.MX.sym("theta", 4 * hidden + 1)
    x = ca.MX.sym("xn", 2, n)
    t = ca.MX.sym("tn", 1, n)
    w1 = ca.reshape(theta[:2 * hidden], 2, hidden).T  # row-major (H, 2): fricctl.nn.layout
    b1 = theta[2 * hidden:3 * hidden]
    w2 = theta[3 * hidden:4 * hidden]
    r = (w2.T @ ca.tanh(w1 @ x + ca.repmat(b1, 1, n)) + theta[4 * hidden] - t).T
    return ResidualFunctions(
        residuals=ca.Function("residuals", [theta, x, t], [r]),
        residuals_jacobian=ca.Function("residuals_jacobian", [theta, x, t],
                                       [r, ca.jacobian(r, theta)]))


def residual_functions(hidden: int, n: int) -> ResidualFunctions:
    """The CasADi graph of the net's residuals over ``n`` patterns, cached per (H, N).

    The network is written with MX matrix operations over all patterns at once
    (one ``tanh`` node on an H x N matrix), which CasADi's virtual machine
    evaluates as dense loops: for 1000 patterns the Jacobian takes ~0.2 ms,
    against ~0.35-0.6 ms for a per-pattern SX function mapped over the patterns
    (building either takes ~10 ms).
    """
    hidden = v.integer("hidden", hidden, low=1)
    n = v.integer("n", n, low=1)
    with _BUILD_LOCK:
        return _build(hidden, n)


def clear_cache() -> None:
    """Forget the built CasADi Functions (benchmarks time a cold start with it)."""
    with _BUILD_LOCK:
        _build.cache_clear()


def loop(problem: TrainingProblem, *, restarts: int = 3, max_iterations: int = 200,
         tolerance: float = 1e-10) -> LoopResult:
    """The inner loop: ``restarts`` Levenberg-Marquardt runs, the best kept."""
    restarts = v.integer("restarts", restarts, low=1)
    max_iterations = v.integer("max_iterations", max_iterations, low=1)
    tol = v.real("tolerance", tolerance, positive=True)
    hidden, n = problem.hidden, problem.n
    p = 4 * hidden + 1
    if restarts > MAX_RESTARTS:
        raise ValueError(f"restarts={restarts} is more than the {MAX_RESTARTS} starts a training "
                         "may run")
    if max_iterations > MAX_ITERATIONS:
        raise ValueError(f"max_iterations={max_iterations} is more than the {MAX_ITERATIONS} a "
                         "start may run")
    per_iteration = restarts * n * p * p
    check_work(f"restarts*max_iterations*patterns*(4*hidden+1)^2 = {restarts}*{max_iterations}*"
               f"{n}*{p}^2", float(per_iteration) * max_iterations, MAX_WORK,
               f"at most {max(0, int(MAX_WORK // (n * p * p * max_iterations)))} restarts (or "
               "fewer patterns or hidden units) would finish")
    funs = residual_functions(hidden, n)
    # CasADi's copy-free buffer interface: the Functions read and write these
    # numpy arrays in place (CasADi is column-major: the 2xN input is the
    # row-major (N, 2) array, the N x p Jacobian the row-major (p, N) array J').
    theta_buf = np.zeros(p)
    x_buf = np.ascontiguousarray(problem.xn.T)
    t_buf = np.ascontiguousarray(problem.tn)
    r_buf = np.zeros(n)
    jt_buf = np.zeros((p, n))
    runs = []
    for fun, outs in ((funs.residuals, (r_buf,)), (funs.residuals_jacobian, (r_buf, jt_buf))):
        buf, run = fun.buffer()
        for i, a in enumerate((theta_buf, x_buf, t_buf)):
            buf.set_arg(i, memoryview(a.reshape(-1)))
        for i, a in enumerate(outs):
            buf.set_res(i, memoryview(a.reshape(-1)))
        runs.append((buf, run))  # keep buf alive with its run
    run_r, run_rj = runs[0][1], runs[1][1]

    loss_hist = []
    elapsed = []
    best_cost, best_theta = math.inf, None
    iterations = []
    for _ in range(restarts):
        theta = problem.initial_theta()
        theta_buf[:] = theta
        run_rj()
        r, jt = r_buf.copy(), jt_buf.copy()
        cost = 0.5 * float(r @ r)
        a = jt @ jt.T
        g = jt @ r
        mu = 1e-3 * float(np.max(np.diag(a)))
        nu = 2.0
        if cost < best_cost:
            best_cost, best_theta = cost, theta.copy()
        loss_hist.append(best_cost)
        elapsed.append(problem.elapsed())
        it = 0
        while it < max_iterations:
            if np.linalg.norm(g, np.inf) <= tol * max(cost, 1e-300):
                break
            it += 1
            try:
                d = np.linalg.solve(a + mu * np.eye(p), -g)
            except np.linalg.LinAlgError:
                d = None
            accepted = False
            if d is not None and np.all(np.isfinite(d)):
                theta_buf[:] = theta + d
                run_r()
                cost_new = 0.5 * float(r_buf @ r_buf)
                predicted = 0.5 * float(d @ (mu * d - g))  # model decrease, > 0
                rho = (cost - cost_new) / predicted if predicted > 0 else -1.0
                if rho > 0:
                    accepted = True
                    decrease = (cost - cost_new) / max(cost, 1e-300)
                    theta = theta + d
                    run_rj()  # Jacobian only at accepted points
                    r, jt = r_buf.copy(), jt_buf.copy()
                    cost = cost_new
                    a = jt @ jt.T
                    g = jt @ r
                    mu *= max(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3)
                    nu = 2.0
            if not accepted:
                mu *= nu
                nu *= 2.0
            if cost < best_cost:
                best_cost, best_theta = cost, theta.copy()
            loss_hist.append(best_cost)
            elapsed.append(problem.elapsed())
            problem.report(len(iterations) * max_iterations + it, restarts * max_iterations)
            if mu > 1e15 or (accepted and decrease < tol):
                break
        iterations.append(it)
        problem.report(len(iterations) * max_iterations, restarts * max_iterations)
    return LoopResult(theta=best_theta, loss=np.asarray(loss_hist) / n,
                      elapsed=np.asarray(elapsed),
                      metadata={"method": "levenberg-marquardt", "restarts": restarts,
                                "iterations": iterations})


TRAINER = Trainer(
    name="casadi", step="iteration", loop=loop,
    description="Levenberg-Marquardt on the least-squares objective, exact Jacobian by CasADi's "
                "algorithmic differentiation",
    flags=(TrainerOption(name="restarts", type=int, high=MAX_RESTARTS,
                         help="independent starting points, the best kept"),),
    limits=(f"restarts*{loop.__kwdefaults__['max_iterations']}*patterns*(4*hidden+1)^2 <= "
            f"{MAX_WORK:.0e}".replace("e+", "e") + " (its iterations stop by themselves)"))


def train_casadi(tm, omega, target, *, hidden: int = 4, restarts: int = 3,
                 max_iterations: int = 200, tolerance: float = 1e-10,
                 rng: np.random.Generator, metadata: dict | None = None) -> TrainingResult:
    """Second-order trainer: Levenberg-Marquardt on the least-squares objective.

    Minimises ``0.5*sum_i (yn_i - tn_i)^2`` over the 4H+1 weights (same scaling
    as :func:`~fricctl.nn.train.backprop.train_backprop`).  The residuals and
    their exact Jacobian are a CasADi expression graph (algorithmic
    differentiation over all patterns); each iteration solves
    ``(J'J + mu*I) d = -J'r`` and updates the damping ``mu`` with Nielsen's
    gain-ratio rule (Madsen, Nielsen & Tingleff, 2004).  Several seeded starting
    points are run and the best net is kept.

    Parameters
    ----------
    tm, omega, target : array_like
        1-D patterns: motor torque [N*m], velocity [rad/s], friction [N*m].
    hidden : int
        Hidden units H.
    restarts : int
        Number of independent starting points, >= 1.
    max_iterations : int
        Iteration limit per start.
    tolerance : float
        Stop a start when the relative decrease of the loss over an accepted
        step, or the gradient's infinity norm relative to the loss, falls below
        this [-].
    rng : numpy.random.Generator
        Source of the initial weights.
    metadata : dict, optional
        Extra JSON-serialisable entries stored with the net.

    Returns
    -------
    TrainingResult
        ``.net`` and ``.history``; history entries are LM iterations (accepted
        or rejected steps), the loss being the best so far over all starts.

    Notes
    -----
    Why LM and not IPOPT: with 17 unknowns the normal equations cost nothing,
    LM needs no line search or barrier, and it is the standard trainer for small
    networks (Hagan & Menhaj, 1994).  No regularisation, so with few patterns the
    net can over-fit; check held-out patterns with :func:`fricctl.nn.fit_report`.

    Examples
    --------
    >>> from fricctl.nn import fit_percent, smooth_friction_patterns
    >>> pats = smooth_friction_patterns(np.random.default_rng(0), n_sliding=200, n_stuck=0)
    >>> tm, om, f = pats.tm, pats.omega, pats.friction
    >>> net = train_casadi(tm, om, f, restarts=1, rng=np.random.default_rng(1)).net
    >>> fit_percent(f, net(tm, om)) > 99
    True
    """
    return TRAINER.train(tm, omega, target, hidden=hidden, rng=rng, metadata=metadata,
                         restarts=restarts, max_iterations=max_iterations, tolerance=tolerance)
