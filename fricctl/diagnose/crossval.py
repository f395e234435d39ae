"""Blocked cross-validation of linear-in-the-coefficients candidates, and the final refits.

Every candidate is a set of :class:`Variant` s (one per value of its hyper-parameter:
extra regressor columns, their bounds and the target).  Several causes' variants
*compose* (:func:`compose`): their columns side by side, one target; that is how the
forward selection adds a cause to those already named.  The record is cut into
contiguous blocks (folds); :class:`Problem` holds the per-block sums of the normal
equations so that leaving a block out is a subtraction.  :func:`cross_validate` picks,
per block left out, the variant with the least training error and scores it on the
block; :func:`full_fit` does the same on all data; :func:`casadi_refit` refits the
chosen composition with CasADi/IPOPT (:func:`fricctl.identify.fit_least_squares`) for
standard errors.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable, Iterable, Sequence

import numpy as np

from .signals import Signals

if TYPE_CHECKING:  # identify imports CasADi: only when a fit is made
    from ..identify import IdentificationResult

__all__ = ["Variant", "Problem", "FoldFit", "BlockedCV", "FullFit", "solve", "compose", "settle",
           "advance", "cross_validate", "full_fit", "baseline_fit", "casadi_refit",
           "BASELINE_PARAMS", "empty_variant"]

#: Names of the rigid baseline's coefficients (fit mode), in column order.
BASELINE_PARAMS = ("inertia", "viscous", "coulomb")


def solve(G, g):
    """Normal equations of a (scaled) linear least-squares problem, with a tiny ridge.

    Thousands of these small systems (a few unknowns) are solved per diagnosis, so numpy
    solves them; the final refit of the named terms is CasADi's (:func:`casadi_refit`)."""
    p = G.shape[0]
    if p == 0:
        return np.zeros(0)
    ridge = 1e-12 * max(float(np.trace(G)) / max(p, 1), 1e-300)
    return np.linalg.solve(G + ridge * np.eye(p), g)


@dataclass(frozen=True, kw_only=True, eq=False)
class Variant:
    """One setting of a candidate's hyper-parameter: extra columns, their bounds, the target."""

    h: object
    """Hyper-parameter (period, delay, (wl, zeta), ...), or None; a tuple of the parts' for
    a composition."""
    extra: np.ndarray
    """(N, k) extra regressor columns."""
    y: np.ndarray
    """(N,) target (torque, or torque minus nominal prediction)."""
    signs: tuple
    """Per extra column: +1 (coefficient >= 0) or 0 (free)."""
    upper: tuple = ()
    """Per extra column: upper bound of the (unscaled) coefficient, or () for none."""
    shifts_target: bool = False
    """True when :attr:`y` is not the baseline's target (a delay moves it): in a composition
    this variant's target is the target."""

    @property
    def k(self) -> int:
        """Number of extra columns."""
        return self.extra.shape[1]

    def bounds(self) -> tuple:
        """Lower and upper bounds of the extra coefficients, two arrays of length :attr:`k`."""
        lo = np.array([0.0 if s > 0 else -np.inf for s in self.signs], dtype=float)
        hi = np.array(self.upper if self.upper else [np.inf] * self.k, dtype=float)
        return lo.reshape(self.k), hi.reshape(self.k)


def empty_variant(y: np.ndarray) -> Variant:
    """The variant that adds nothing (the model as it stands)."""
    return Variant(h=None, extra=np.zeros((y.size, 0)), y=y, signs=())


def advance(base, problem: "Problem", parts: Sequence[Variant], theta: np.ndarray):
    """``base`` (a :class:`~fricctl.diagnose.causes.Baseline`) moved on to the model of the
    composed ``parts`` with coefficients ``theta``
    (:meth:`~fricctl.diagnose.causes.Baseline.advanced`): its residual and its prediction,
    both of the composed target (the delayed one where a delay is among the parts)."""
    comp = compose(parts)
    prediction = problem.design(comp) @ theta
    return base.advanced(comp.y - prediction, prediction)


#: Most passes of :func:`settle` [-]: the column of a term read from the model's torque is a
#: contraction of ratio about its coefficient (at most 0.5 for a load dependence), so six
#: passes leave at most 0.5**6 = 1.6 % of the first change.
SETTLE_PASSES = 6

#: :func:`settle` stops once no remade column moves by more than this share of its norm [-].
SETTLE_TOLERANCE = 1e-3


def settle(problem: "Problem", base, causes: Sequence, parts: Sequence[Variant],
           theta: np.ndarray) -> tuple:
    """The named ``causes`` (their chosen ``parts``, fitted together as ``theta``) with the
    columns read from the model's own torque remade until they settle, and ``base`` moved on
    to that model (:func:`advance`).  Returns ``(parts, theta, base)``.

    A cause whose column is the torque of the model as it stands
    (:attr:`~fricctl.diagnose.causes.Cause.reads_model_torque`: a friction growing with the
    transmitted torque) was made before its own term and before any cause named after it;
    the simulation applies the term to the whole torque.  Left as made, a drag named after a
    load dependence ``mu`` is refitted beside a column that leaves the drag's torque out and
    comes back about ``(1 + mu)`` times itself (issue 21).  Each pass remakes such columns on
    the model of the last pass (same hyper-parameter) and refits every coefficient on all
    data, until no column moves by more than :data:`SETTLE_TOLERANCE` of its norm or after
    :data:`SETTLE_PASSES`.  Without such a cause, ``parts`` and ``theta`` are returned as
    given and ``base`` is moved on once, as :func:`advance` does.

    The result is a fixed point, not a least-squares minimum: the selection keeps it only
    where its held-out residual is no larger and its re-simulation no worse than the unsettled
    model's (:func:`fricctl.diagnose.selection.term_trial`; the twin, by its held-out residual
    alone: :func:`fricctl.diagnose.twin.chain_shares`).
    """
    parts = list(parts)
    base = advance(base, problem, parts, theta)
    which = [i for i, c in enumerate(causes) if c.reads_model_torque]
    for _ in range(SETTLE_PASSES if which else 0):
        moved = 0.0
        for i in which:
            new = next((v for v in base.variants(causes[i], None) if v.h == parts[i].h), None)
            if new is None:
                continue
            old = parts[i].extra
            norm = float(np.linalg.norm(old))
            moved = max(moved, float(np.linalg.norm(new.extra - old)) / norm if norm > 0 else
                        (math.inf if np.any(new.extra) else 0.0))
            parts[i] = new
        # one variant composed after the others: a fit always exists
        theta = full_fit(problem, [parts[-1]], tuple(parts[:-1])).theta
        base = advance(base, problem, parts, theta)
        if moved <= SETTLE_TOLERANCE:
            break
    return tuple(parts), theta, base


def compose(parts: Sequence[Variant]) -> Variant:
    """Several causes' variants as one: their columns side by side, the target of the one
    that shifts it (a delay), else the common one."""
    if len(parts) == 1:
        return parts[0]
    y = next((p.y for p in parts if p.shifts_target), parts[-1].y)
    lo, hi = zip(*(p.bounds() for p in parts))
    upper = tuple(np.concatenate(hi))
    return Variant(h=tuple(p.h for p in parts), extra=np.column_stack([p.extra for p in parts]),
                   y=y, signs=tuple(s for p in parts for s in p.signs),
                   upper=upper if any(math.isfinite(u) for u in upper) else (),
                   shifts_target=any(p.shifts_target for p in parts))


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
    """Block (fold) sums of the normal equations, shared by every candidate.

    The per-block cross products of every pair of column sets (the baseline's, each
    variant's extras, each target) are computed once and cached, so that composing a
    candidate with the causes already named costs only the products it adds.
    """

    def __init__(self, sig: Signals, base_cols: np.ndarray | None):
        self.sig = sig
        m = sig.moving
        self.rows = [np.flatnonzero(m & (sig.folds == f)) for f in range(sig.n_folds)]
        self.all_rows = np.flatnonzero(m)
        self.base = base_cols  # (N, 3) or None (nominal model)
        # the sliding samples of each block are a contiguous run of all_rows (blocks are
        # contiguous in time): block f is all_rows[_bounds[f]:_bounds[f + 1]]
        self._bounds = np.searchsorted(sig.folds[self.all_rows], np.arange(sig.n_folds + 1))
        self._restricted: dict = {}
        self._cross: dict = {}
        self._stats: dict = {}

    @property
    def n_base(self) -> int:
        """Number of baseline columns refitted with every candidate (3, or 0 with a nominal)."""
        return 0 if self.base is None else self.base.shape[1]

    def design(self, v: Variant):
        """The baseline's columns (fit mode) followed by the variant's extra columns."""
        return v.extra if self.base is None else np.column_stack([self.base, v.extra])

    def _rows_of(self, key, M) -> np.ndarray:
        """``M`` (N,) or (N, k) on the sliding samples, as (n, k); cached under ``key`` (the
        array is kept alive with the entry, so its identity stays unique)."""
        hit = self._restricted.get(key)
        if hit is None:
            M = np.asarray(M, dtype=float)
            # np.take, not M[rows]: the same copy, and 15 times faster on an (N, 2) array
            # (0.05 against 0.75 ms at 40 000 samples; about a thousand arrays per diagnosis)
            R = np.take(M[:, None] if M.ndim == 1 else M, self.all_rows, axis=0)
            hit = self._restricted[key] = (R, M)
        return hit[0]

    def _blockdot(self, ka, A, kb, B) -> np.ndarray:
        """Per-block ``A'B`` (F, a, b) over the sliding samples (cached by the pair of keys)."""
        key = (ka, kb)
        hit = self._cross.get(key)
        if hit is None:
            Ar, Br = self._rows_of(ka, A), self._rows_of(kb, B)
            b = self._bounds
            prod = np.stack([Ar[b[f]:b[f + 1]].T @ Br[b[f]:b[f + 1]]
                             for f in range(self.sig.n_folds)])
            hit = self._cross[key] = prod
            self._cross[(kb, ka)] = prod.transpose(0, 2, 1)
        return hit

    def stats(self, blocks, y) -> BlockStats:
        """Scaled per-block normal equations of the column sets ``blocks`` (``(key, array)``
        pairs, side by side) against the target ``y``."""
        ky = ("y", id(y))
        self._rows_of(ky, y)
        F = self.sig.n_folds
        sizes = [self._rows_of(k, M).shape[1] for k, M in blocks]
        p = sum(sizes)
        G = np.empty((F, p, p))
        g = np.empty((F, p))
        i = 0
        for (ka, A), na in zip(blocks, sizes):
            j = 0
            for (kb, B), nb in zip(blocks, sizes):
                G[:, i:i + na, j:j + nb] = self._blockdot(ka, A, kb, B)
                j += nb
            g[:, i:i + na] = self._blockdot(ka, A, ky, y)[:, :, 0]
            i += na
        s = self._blockdot(ky, y, ky, y)[:, 0, 0]
        n = max(self.all_rows.size, 1)
        scale = np.sqrt(np.einsum("fii->i", G) / n) if p else np.ones(0)
        scale[scale == 0] = 1.0
        return BlockStats(G=G / np.outer(scale, scale), g=g / scale, s=s.copy(), scale=scale)

    def stats_of(self, parts: Sequence[Variant]) -> tuple:
        """``(lower, upper, BlockStats)`` of the composition of ``parts``: bounds of its extra
        coefficients and its normal equations (cached by identity: a candidate's variants are
        built once per record; the parts are kept alive with the entry)."""
        key = tuple(id(p) for p in parts)
        hit = self._stats.get(key)
        if hit is None:
            bounds = [p.bounds() for p in parts]
            lo = np.concatenate([b[0] for b in bounds])
            hi = np.concatenate([b[1] for b in bounds])
            y = next((p.y for p in parts if p.shifts_target), parts[-1].y)
            blocks = [] if self.base is None else [("base", self.base)]
            blocks += [(("x", id(p)), p.extra) for p in parts if p.k]
            hit = self._stats[key] = (lo, hi, self.stats(blocks, y), tuple(parts))
        return hit[:3]

    def bounded(self, lo, hi, st: BlockStats, G, g) -> np.ndarray:
        """The least-squares coefficients (scaled) within the bounds ``lo, hi`` of the extras."""
        nb = self.n_base
        sc = st.scale[nb:]
        return solve_bounded(G, g, np.concatenate([np.full(nb, -np.inf), lo * sc]),
                             np.concatenate([np.full(nb, np.inf), hi * sc]))

    @staticmethod
    def sse(theta, G, g, s):
        # a column (nearly) zero on the training blocks gets a huge coefficient: its held-out
        # sum of squares overflows to inf, which is what it is (the variant fails held out),
        # not a numpy warning for the user (audit B).  Where both products overflow, inf - inf
        # is NaN: a sum of squares that large is inf too -- a NaN would read as "no variant
        # valid" (the record's own residual kept, no change) held out, and in training no later
        # variant compares below it (review R10)
        with np.errstate(over="ignore", invalid="ignore"):
            r = float(s - 2 * theta @ g + theta @ G @ theta)
        return math.inf if math.isnan(r) else r


def solve_bounded(G, g, lower, upper) -> np.ndarray:
    """:func:`solve`, then any coefficient outside its bounds is held at the bound it
    crossed (the worst first) and the others refitted: the bounded least-squares solution
    when the active set only grows (one or two bounds, as here)."""
    p = g.size
    fixed: dict = {}
    th = solve(G, g)
    for _ in range(p):
        viol = [(max(lower[i] - th[i], th[i] - upper[i]), i) for i in range(p)
                if i not in fixed and not lower[i] <= th[i] <= upper[i]]
        if not viol:
            break
        _, i = max(viol)
        fixed[i] = min(max(th[i], lower[i]), upper[i])
        fi = np.array(sorted(fixed), dtype=int)
        fv = np.array([fixed[j] for j in fi])
        free = np.array([j for j in range(p) if j not in fixed], dtype=int)
        th = np.empty(p)
        th[fi] = fv
        if free.size:
            th[free] = solve(G[np.ix_(free, free)], g[free] - G[np.ix_(free, fi)] @ fv)
    return th


@dataclass(frozen=True, kw_only=True, eq=False)
class FoldFit:
    """The variant chosen on the training blocks and its coefficients."""

    h: object
    """Hyper-parameter of the chosen variant."""
    theta: np.ndarray
    """Coefficients (unscaled): the baseline's (fit mode), the fixed parts', then the variant's."""
    variant: Variant
    """The chosen variant (the candidate's own, not the composition)."""


@dataclass(frozen=True, kw_only=True, eq=False)
class BlockedCV:
    """Held-out result of one candidate (:func:`cross_validate`)."""

    test: np.ndarray
    """Held-out sum of squared residuals per block (NaN where no variant was valid)."""
    fits: tuple
    """Per block, the :class:`FoldFit` fitted without it, or None."""


def cross_validate(problem: Problem, variants_for_fold: Callable[[int], Iterable[Variant]],
                   fixed_for_fold: Callable[[int], tuple] | None = None) -> BlockedCV:
    """Blocked CV: per fold the variant with the least training SSE, its held-out SSE.

    ``fixed_for_fold(f)`` gives the variants of the causes already in the model for the
    training blocks of fold ``f`` (their hyper-parameters chosen when they were added);
    the candidate's variants are composed after them.
    """
    F = problem.sig.n_folds
    test = np.empty(F)
    fits = []
    for f in range(F):
        fixed = () if fixed_for_fold is None else tuple(fixed_for_fold(f))
        best = None
        for v in variants_for_fold(f):
            lo, hi, st = problem.stats_of(fixed + (v,))
            G, g, s = st.G, st.g, st.s
            Gt, gt, stt = G.sum(0) - G[f], g.sum(0) - g[f], s.sum() - s[f]
            th = problem.bounded(lo, hi, st, Gt, gt)
            tr = Problem.sse(th, Gt, gt, stt)
            if best is None or tr < best[0]:
                with np.errstate(over="ignore"):  # a huge coefficient: inf, as its sse
                    best = (tr, Problem.sse(th, G[f], g[f], s[f]), v, th / st.scale)
        if best is None:
            test[f] = np.nan
            fits.append(None)
        else:
            test[f] = best[1]
            fits.append(FoldFit(h=best[2].h, theta=best[3], variant=best[2]))
    return BlockedCV(test=test, fits=tuple(fits))


@dataclass(frozen=True, kw_only=True, eq=False)
class FullFit:
    """The variant with the least error on all sliding samples (:func:`full_fit`)."""

    sse: float
    """Sum of squared residuals."""
    variant: Variant
    """The chosen variant (the candidate's own)."""
    theta: np.ndarray
    """Coefficients (unscaled): the baseline's (fit mode), the fixed parts', the variant's."""


def full_fit(problem: Problem, variants: Iterable[Variant], fixed: tuple = ()) -> FullFit | None:
    """All sliding samples: the variant with the least SSE, composed after ``fixed``
    (None when there is no variant)."""
    best = None
    for v in variants:
        lo, hi, st = problem.stats_of(tuple(fixed) + (v,))
        G, g = st.G.sum(0), st.g.sum(0)
        th = problem.bounded(lo, hi, st, G, g)
        sse = Problem.sse(th, G, g, st.s.sum())
        if best is None or sse < best.sse:
            best = FullFit(sse=sse, variant=v, theta=th / st.scale)
    return best


def baseline_fit(sig: Signals) -> "IdentificationResult":
    """The rigid baseline I, b, Fc by CasADi least squares on the sliding samples: the
    equation error of ``fricctl identify`` (:func:`fricctl.identify.equation_error`), the
    columns every candidate extends."""
    from ..identify import equation_error

    return equation_error(sig, "coulomb_viscous", offset=False)


def casadi_refit(problem: Problem, v: Variant, params: tuple) -> "IdentificationResult | None":
    """Refit the linear coefficients of the extended model by CasADi/IPOPT least squares.

    ``v`` is the (composed) variant, ``params`` names its extra coefficients; None when
    there is nothing to fit (a nominal model extended by a pure shift such as a delay).
    """
    from ..identify import fit_least_squares, linear_prediction

    X = problem.design(v)[problem.all_rows]
    y = v.y[problem.all_rows]
    p = X.shape[1]
    if p == 0:
        return None
    base_names = BASELINE_PARAMS if problem.base is not None else ()
    names = base_names + tuple(params)
    lo, hi = v.bounds()
    lower = [0.0] * len(base_names) + list(lo)
    upper = [np.inf] * len(base_names) + list(hi)
    scale = (np.linalg.norm(y) or 1.0) / np.maximum(np.linalg.norm(X, axis=0), 1e-300)
    return fit_least_squares(linear_prediction, X, y, names=names, initial=np.zeros(p), lower=lower,
                             upper=upper, scale=scale, units=problem.sig.units)
