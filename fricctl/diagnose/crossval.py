"""Blocked cross-validation of linear-in-the-coefficients candidates, and the final refits.

Every candidate is a set of :class:`Variant` s (one per value of its hyper-parameter:
extra regressor columns and the target).  The record is cut into contiguous
blocks (folds); :class:`Problem` holds the per-block sums of the normal equations
so that leaving a block out is a subtraction.  :func:`cross_validate` picks, per
block left out, the variant with the least training error and scores it on the
block; :func:`full_fit` does the same on all data; :func:`casadi_refit` refits the
chosen variant with CasADi/IPOPT (:func:`fricctl.identify.fit_least_squares`) for
standard errors.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable, Iterable

import numpy as np

from .signals import Signals

if TYPE_CHECKING:  # identify imports CasADi: only when a fit is made
    from ..identify import IdentificationResult

__all__ = ["Variant", "Problem", "FoldFit", "BlockedCV", "FullFit", "solve", "cross_validate",
           "full_fit", "baseline_fit", "casadi_refit", "BASELINE_PARAMS"]

#: Names of the rigid baseline's coefficients (fit mode), in column order.
BASELINE_PARAMS = ("inertia", "viscous", "coulomb")


def solve(G, g):
    """Normal equations of a (scaled) linear least-squares problem, solved by CasADi."""
    import casadi as ca

    p = G.shape[0]
    if p == 0:
        return np.zeros(0)
    ridge = 1e-12 * max(float(np.trace(G)) / max(p, 1), 1e-300)
    return np.asarray(ca.solve(ca.DM(G + ridge * np.eye(p)), ca.DM(g))).ravel()


@dataclass(frozen=True, kw_only=True, eq=False)
class Variant:
    """One setting of a candidate's hyper-parameter: extra columns and target."""

    h: object
    """Hyper-parameter (period, delay, (wl, zeta), ...), or None."""
    extra: np.ndarray
    """(N, k) extra regressor columns."""
    y: np.ndarray
    """(N,) target (torque, or torque minus nominal prediction)."""
    signs: tuple
    """Per extra column: +1 (coefficient >= 0) or 0 (free)."""
    upper: tuple = ()
    """Per extra column: upper bound of the (unscaled) coefficient, or ()."""


@dataclass(frozen=True, kw_only=True, eq=False)
class BlockStats:
    """Per-block normal equations of a scaled design (:meth:`Problem.stats`)."""

    G: np.ndarray
    """(F, p, p) Gram matrices."""
    g: np.ndarray
    """(F, p) right-hand sides."""
    s: np.ndarray
    """(F,) target sums of squares."""
    scale: np.ndarray
    """(p,) column scales (RMS over the sliding samples)."""


class Problem:
    """Block (fold) sums of the normal equations, shared by every candidate."""

    def __init__(self, sig: Signals, base_cols: np.ndarray | None):
        self.sig = sig
        m = sig.moving
        self.rows = [np.flatnonzero(m & (sig.folds == f)) for f in range(sig.n_folds)]
        self.all_rows = np.flatnonzero(m)
        self.base = base_cols  # (N, 3) or None (nominal model)

    def design(self, v: Variant):
        """The baseline's columns (fit mode) followed by the variant's extra columns."""
        return v.extra if self.base is None else np.column_stack([self.base, v.extra])

    def stats(self, X, y) -> BlockStats:
        rows = self.all_rows
        scale = np.sqrt(np.mean(X[rows] ** 2, axis=0))
        scale[scale == 0] = 1.0
        Xs = X / scale
        F = self.sig.n_folds
        p = X.shape[1]
        G = np.empty((F, p, p))
        g = np.empty((F, p))
        s = np.empty(F)
        for f, r in enumerate(self.rows):
            Xf = Xs[r]
            yf = y[r]
            G[f] = Xf.T @ Xf
            g[f] = Xf.T @ yf
            s[f] = yf @ yf
        return BlockStats(G=G, g=g, s=s, scale=scale)

    @staticmethod
    def sse(theta, G, g, s):
        return float(s - 2 * theta @ g + theta @ G @ theta)


def _solve_bounded(G, g, scale, upper, n_extra):
    """:func:`solve`, then any extra coefficient above its upper bound is held at the bound
    and the others refitted (the bounded least-squares solution when one bound is active)."""
    th = solve(G, g)
    if not upper:
        return th
    p = th.size
    fixed = {}
    for j, ub in enumerate(upper):
        i = p - n_extra + j
        if math.isfinite(ub) and th[i] / scale[i] > ub:
            fixed[i] = ub * scale[i]
    if not fixed:
        return th
    fi = np.array(sorted(fixed))
    fv = np.array([fixed[i] for i in fi])
    free = np.array([i for i in range(p) if i not in fixed], dtype=int)
    out = np.empty(p)
    out[fi] = fv
    out[free] = solve(G[np.ix_(free, free)], g[free] - G[np.ix_(free, fi)] @ fv)
    return out


def _valid(theta, signs, n_extra):
    if n_extra == 0:
        return True
    ex = theta[-n_extra:]
    return all(sg == 0 or c >= 0 for c, sg in zip(ex, signs))


@dataclass(frozen=True, kw_only=True, eq=False)
class FoldFit:
    """The variant chosen on the training blocks and its coefficients."""

    h: object
    """Hyper-parameter of the chosen variant."""
    theta: np.ndarray
    """Coefficients (unscaled): the baseline's (fit mode), then the extra columns'."""


@dataclass(frozen=True, kw_only=True, eq=False)
class BlockedCV:
    """Held-out result of one candidate (:func:`cross_validate`)."""

    test: np.ndarray
    """Held-out sum of squared residuals per block (NaN where no variant was valid)."""
    fits: tuple
    """Per block, the :class:`FoldFit` fitted without it, or None."""


def cross_validate(problem: Problem, variants_for_fold: Callable[[int], Iterable[Variant]],
                   n_extra: int) -> BlockedCV:
    """Blocked CV: per fold the variant with the least training SSE, its held-out SSE."""
    F = problem.sig.n_folds
    cache = {}
    test = np.empty(F)
    fits = []
    for f in range(F):
        best = None
        for v in variants_for_fold(f):
            key = id(v)
            if key not in cache:
                cache[key] = problem.stats(problem.design(v), v.y)
            st = cache[key]
            G, g, s = st.G, st.g, st.s
            Gt, gt, stt = G.sum(0) - G[f], g.sum(0) - g[f], s.sum() - s[f]
            th = _solve_bounded(Gt, gt, st.scale, v.upper, n_extra)
            if not _valid(th, v.signs, n_extra):
                continue
            tr = Problem.sse(th, Gt, gt, stt)
            if best is None or tr < best[0]:
                best = (tr, Problem.sse(th, G[f], g[f], s[f]), v.h, th / st.scale)
        if best is None:
            test[f] = np.nan
            fits.append(None)
        else:
            test[f] = best[1]
            fits.append(FoldFit(h=best[2], theta=best[3]))
    return BlockedCV(test=test, fits=tuple(fits))


@dataclass(frozen=True, kw_only=True, eq=False)
class FullFit:
    """The variant with the least error on all sliding samples (:func:`full_fit`)."""

    sse: float
    """Sum of squared residuals."""
    variant: Variant
    theta: np.ndarray
    """Coefficients (unscaled)."""


def full_fit(problem: Problem, variants: Iterable[Variant], n_extra: int) -> FullFit | None:
    """All sliding samples: the variant with the least SSE (None if no variant is valid)."""
    best = None
    for v in variants:
        st = problem.stats(problem.design(v), v.y)
        G, g = st.G.sum(0), st.g.sum(0)
        th = _solve_bounded(G, g, st.scale, v.upper, n_extra)
        if not _valid(th, v.signs, n_extra):
            continue
        sse = Problem.sse(th, G, g, st.s.sum())
        if best is None or sse < best.sse:
            best = FullFit(sse=sse, variant=v, theta=th / st.scale)
    return best


def baseline_fit(sig: Signals) -> "IdentificationResult":
    """The rigid baseline I, b, Fc by CasADi least squares on the sliding samples."""
    from ..identify import fit_least_squares, linear_prediction

    m = sig.moving
    X = np.column_stack([sig.a, sig.filt(sig.w), sig.filt(sig.seff)])[m]
    y = sig.torque_target(0)[m]
    scale = (np.linalg.norm(y) or 1.0) / np.maximum(np.linalg.norm(X, axis=0), 1e-300)
    return fit_least_squares(linear_prediction, X, y, names=BASELINE_PARAMS, initial=np.zeros(3),
                             lower=[0.0, 0.0, 0.0], scale=scale, units=sig.units)


def casadi_refit(problem: Problem, v: Variant, params: tuple) -> "IdentificationResult | None":
    """Refit the linear coefficients of the extended model by CasADi/IPOPT least squares.

    ``params`` names the variant's extra coefficients; None when there is nothing to fit
    (a nominal model extended by a pure shift such as a delay).
    """
    from ..identify import fit_least_squares, linear_prediction

    X = problem.design(v)[problem.all_rows]
    y = v.y[problem.all_rows]
    p = X.shape[1]
    if p == 0:
        return None
    nx = len(params)
    base_names = BASELINE_PARAMS if problem.base is not None else ()
    names = base_names + tuple(params)
    lower = [0.0] * len(base_names) + [0.0 if s > 0 else -np.inf for s in v.signs]
    upper = [np.inf] * len(base_names) + (list(v.upper) if v.upper else [np.inf] * nx)
    scale = (np.linalg.norm(y) or 1.0) / np.maximum(np.linalg.norm(X, axis=0), 1e-300)
    return fit_least_squares(linear_prediction, X, y, names=names, initial=np.zeros(p), lower=lower,
                             upper=upper, scale=scale, units=problem.sig.units)
