"""Forward selection of causes with the blocked cross-validation: every effect the record supports.

Starting from the baseline, each step scores every remaining candidate by the fraction of
the *remaining* held-out torque residual its term removes when added to the causes
already named (their hyper-parameters as chosen on each fold's training blocks), less
the fraction the same term removes on the record's effect-free twin
(:mod:`fricctl.diagnose.twin`: the measuring chain's share).  The best candidate whose net score reaches
:data:`~fricctl.diagnose.report.MIN_SCORE` and which can be told on this record
(:func:`collinearity`, then the cause's own ``identifiable``) is named -- preferring one
whose extended model does not simulate the held-out windows worse -- and the search
repeats until no candidate reaches it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..plant import JointModel
from .causes import Baseline, Cause, Term
from .crossval import BlockedCV, Problem, compose, cross_validate, full_fit
from .windows import WindowedSimulation

__all__ = ["Step", "Selected", "Selection", "forward_selection", "collinearity", "not_applicable",
           "COLLINEAR_SHARE", "MIN_SCORE"]

#: Smallest held-out fraction of the remaining torque residual (sum of squares) a candidate
#: must remove, net of the measuring chain's share, to be named: 1 - 0.9**2, i.e. the
#: held-out torque RMS must drop by 10 %, the issue's definition of an effect that matters.
MIN_SCORE = 1.0 - 0.9 ** 2

#: A candidate's column is collinear with the model's when less than this share of its
#: energy (sliding samples) lies outside their span (a variance inflation above 1000) [-].
COLLINEAR_SHARE = 1e-3


@dataclass(frozen=True, kw_only=True)
class Step:
    """One step of the forward selection: the cause named and its held-out gain."""

    cause: str
    """The cause named at this step."""
    score: float
    """Net score: held-out fraction of the remaining torque residual (sum of squares) the
    term removes, less the measuring chain's share [-]."""
    gross: float
    """The same fraction before the chain's share is taken off [-]."""
    chain: float
    """The measuring chain's share: the held-out fraction of the residual the same term
    removes on the record's effect-free twin [-]."""
    torque_rms_before: float
    """Held-out torque residual RMS of the model before this step [N*m]."""
    torque_rms_after: float
    """Held-out torque residual RMS with the term added [N*m]."""
    simulation_rms_before: float
    """Windowed re-simulation, position error before this step [rad]."""
    simulation_rms_after: float
    """Windowed re-simulation, position error with the term added [rad]."""
    ranking: tuple = ()
    """Every candidate of this step with its net score, best first."""

    def as_dict(self) -> dict:
        """The step's JSON object (``ranking`` as ``[{cause, score}]``)."""
        out = {k: getattr(self, k) for k in ("cause", "score", "gross", "chain",
                                             "torque_rms_before", "torque_rms_after",
                                             "simulation_rms_before", "simulation_rms_after")}
        out["ranking"] = [{"cause": c, "score": s} for c, s in self.ranking]
        return out


@dataclass(frozen=True, kw_only=True, eq=False)
class Selected:
    """A named cause: its fits per fold and on all data."""

    cause: Cause
    fold_variants: tuple
    """Per fold, the variant chosen on the training blocks."""
    variant: object
    """The variant chosen on all data."""


@dataclass(frozen=True, kw_only=True, eq=False)
class Selection:
    """What :func:`forward_selection` found."""

    selected: tuple
    """The :class:`Selected` causes, in the order named."""
    steps: tuple
    """One :class:`Step` per named cause."""
    first_ranking: tuple
    """The first step's candidates with their net scores, best first."""
    last_ranking: tuple
    """The candidates of the step that named nothing, with their net scores, best first
    (why the selection stopped; empty when every candidate was named or dropped)."""
    simulation_scores: dict
    """First step: per candidate, the held-out fraction of the windowed simulation error
    (position, sum of squares) its term removes [-] (computed for the supported ones)."""
    not_identifiable: dict = field(default_factory=dict)
    """Candidates that reached the score but cannot be told on this record, and those whose
    term cannot be added to the model (:func:`not_applicable`), with the reason."""
    test: np.ndarray = field(default_factory=lambda: np.zeros(0))
    """Held-out SSE per block of the final model."""
    baseline_test: np.ndarray = field(default_factory=lambda: np.zeros(0))
    """Held-out SSE per block of the baseline."""
    sim_before: WindowedSimulation | None = None
    sim_after: WindowedSimulation | None = None


def collinearity(problem: Problem, fixed: tuple, variant) -> float:
    """Share of the candidate's column energy outside the span of the model's columns (the
    baseline's and the named causes'), the smallest over its columns [-] (1 with nothing to
    compare with)."""
    rows = problem.all_rows
    k = variant.extra.shape[1]
    cols = [problem.base] if problem.base is not None else []
    cols += [v.extra for v in fixed if v.extra.shape[1]]
    if k == 0 or not cols:
        return 1.0
    B = np.column_stack(cols)[rows]
    E = variant.extra[rows]
    scale = np.sqrt(np.mean(B ** 2, axis=0))
    scale[scale == 0] = 1.0
    coef = np.linalg.lstsq(B / scale, E, rcond=None)[0]
    out = E - (B / scale) @ coef
    energy = np.sum(E ** 2, axis=0)
    share = np.where(energy > 0, np.sum(out ** 2, axis=0) / np.where(energy > 0, energy, 1), 0.0)
    return float(np.min(share))


def forward_selection(problem: Problem, base: Baseline, candidates: tuple,
                      chain: Callable[[float, tuple, JointModel], Callable[[Cause], float]],
                      simulate: Callable[[list], WindowedSimulation], *,
                      progress: Callable[[int, int, int], None] | None = None) -> Selection:
    """Name every cause the record supports, one step at a time (see the module notes).

    Parameters
    ----------
    problem, base : Problem, Baseline
        The record's normal equations and the baseline every candidate extends.
    candidates : tuple of Cause
    chain : callable
        ``chain(floor, named, model)`` gives, for a twin of ``model`` (the model as it
        stands, fitted on all data) whose held-out residual is ``floor`` [N^2*m^2],
        ``share(cause)``: the held-out fraction of its residual the cause's term removes
        after the causes ``named`` [-].  Asked for each candidate whose gross score
        reaches :data:`MIN_SCORE`, with the residual the record keeps once that
        candidate's term is in.
    simulate : callable
        ``simulate(fold_models)``: the held-out windowed simulation of one model per fold.
    progress : callable, optional
        ``progress(step, done, total)``: called before the candidates of a step are scored
        (``done`` 0) and after each (for a progress bar).
    """
    F = problem.sig.n_folds
    nmov = max(int(problem.sig.moving.sum()), 1)
    empty = base.variant(None, np.zeros((base.target.size, 0)), ())
    cv0 = cross_validate(problem, lambda f: [empty])
    cur_test = cv0.test.copy()
    cur_fits = [(f.theta if f is not None else None) for f in cv0.fits]
    base_models = [base.model((), th) if th is not None else base.fitted for th in cur_fits]
    cur_models = list(base_models)
    cur_model = base.fitted  # the model as it stands, fitted on all data
    sim_base = cur_sim = simulate(cur_models)
    selected: list = []
    steps: list = []
    not_told: dict = {}
    sim_scores0: dict = {}
    first_ranking: tuple = ()
    last_ranking: tuple = ()
    # a cause whose term cannot sit in one model with the baseline (or, later, with the
    # causes named) is not tried: a limit of the models, not of the record
    not_told.update(not_applicable(base, [], base.theta if base.fit_mode else np.zeros(0),
                                   candidates))
    remaining = [c for c in candidates if c.name not in not_told]
    while remaining:
        sse_prev = float(np.sum(cur_test))
        if not sse_prev > 0:
            break

        def fixed_for(f, sel=tuple(selected)):
            return tuple(s.fold_variants[f] if s.fold_variants[f] is not None else s.variant
                         for s in sel)

        cvs = {}
        if progress is not None:
            progress(len(steps) + 1, 0, len(remaining))
        for c in remaining:
            cv = cross_validate(problem, lambda f, c=c: base.variants(c, f), fixed_for)
            if progress is not None:
                progress(len(steps) + 1, len(cvs) + 1, len(remaining))
            test = np.where(np.isnan(cv.test), cur_test, cv.test)
            cvs[c.name] = (1.0 - float(np.sum(test)) / sse_prev, cv, test)
        named = tuple(s.cause for s in selected)
        scored = {}
        for c in remaining:
            gross, cv, test = cvs[c.name]
            share = 0.0
            if gross >= MIN_SCORE:  # the twin keeps what the record keeps with the term in
                share = max(chain(sse_prev * (1.0 - gross), named, cur_model)(c), 0.0)
            scored[c.name] = (gross - share, gross, share, cv, test)
        ranking = tuple(sorted(((n, s[0]) for n, s in scored.items()), key=lambda kv: -kv[1]))
        last_ranking = ranking
        if not steps:
            first_ranking = ranking
        supported = [n for n, s in ranking if s >= MIN_SCORE]
        told = []
        all_fixed = tuple(s.variant for s in selected)
        for name in supported:
            cause = next(c for c in remaining if c.name == name)
            best = full_fit(problem, base.variants(cause, None), all_fixed)
            if best is None:
                not_told[name] = "no variant of the term can be fitted to all the data"
                continue
            share = collinearity(problem, all_fixed, best.variant)
            if share < COLLINEAR_SHARE:
                reason = (f"its column is collinear with the model's on this record (only "
                          f"{100 * share:.2g} % of it lies outside their span)")
            else:
                coef = best.theta[best.theta.size - cause.n_extra:]
                parts = [(s.cause, s.variant.h) for s in selected] + [(cause, best.variant.h)]
                reason = cause.identifiable(base, Term(h=best.variant.h, coef=coef,
                                                       extended=base.model(parts, best.theta)))
            if reason is None:
                told.append((cause, best))
            else:
                not_told[name] = reason
        # a cause that cannot be told on this record is not tried again
        remaining = [c for c in remaining if c.name not in not_told]
        if not told:
            break
        sims = {}
        for cause, _ in told:
            cv = scored[cause.name][3]
            models = [_fold_model(base, selected, cause, cv, f, cur_models[f]) for f in range(F)]
            sims[cause.name] = simulate(models)
        pb = float(np.sum(cur_sim.position_error ** 2))
        sim_score = {n: (1.0 - float(np.sum(s.position_error ** 2)) / pb if pb > 0 else 0.0)
                     for n, s in sims.items()}
        if not steps:
            sim_scores0 = dict(sim_score)
        credible = [t for t in told if sim_score[t[0].name] > 0.0] or told
        cause, best = credible[0]
        net, gross, share, cv, test = scored[cause.name]
        fold_variants = tuple(fit.variant if fit is not None else None for fit in cv.fits)
        cur_models = [_fold_model(base, selected, cause, cv, f, cur_models[f]) for f in range(F)]
        selected.append(Selected(cause=cause, fold_variants=fold_variants, variant=best.variant))
        cur_model = base.model([(s.cause, s.variant.h) for s in selected], best.theta)
        base.advance(_residual(problem, all_fixed + (best.variant,), best.theta))
        new_sim = sims[cause.name]
        steps.append(Step(cause=cause.name, score=net, gross=gross, chain=share,
                          torque_rms_before=math.sqrt(sse_prev / nmov),
                          torque_rms_after=math.sqrt(float(np.sum(test)) / nmov),
                          simulation_rms_before=cur_sim.rms().position,
                          simulation_rms_after=new_sim.rms().position, ranking=ranking))
        cur_test, cur_sim = test, new_sim
        remaining = [c for c in remaining if c is not cause]
        last_ranking = ()
        gone = not_applicable(base, [(s.cause, s.variant.h) for s in selected], best.theta,
                              remaining)
        not_told.update(gone)
        remaining = [c for c in remaining if c.name not in gone]
    return Selection(selected=tuple(selected), steps=tuple(steps), first_ranking=first_ranking,
                     last_ranking=last_ranking,
                     simulation_scores=sim_scores0, not_identifiable=not_told, test=cur_test,
                     baseline_test=cv0.test, sim_before=sim_base, sim_after=cur_sim)


def not_applicable(base: Baseline, parts: list, theta: np.ndarray, candidates) -> dict:
    """The candidates whose term cannot be added to the model of ``parts`` (coefficients
    ``theta``), with the reason: e.g. a resonance on a model with LuGre friction (the elastic
    joint has no bristle state).  Such a candidate is never named, whatever the record."""
    out = {}
    for c in candidates:
        probe = base.variants(c, None)
        if not probe:
            continue
        try:
            base.model(list(parts) + [(c, probe[0].h)],
                       np.concatenate([theta, np.full(c.n_extra, 1e-6)]))
        except ValueError as err:
            out[c.name] = f"its term cannot be added to this model ({err})"
    return out


def _residual(problem: Problem, parts: tuple, theta: np.ndarray) -> np.ndarray:
    """The residual on all samples of a composition of variants with coefficients ``theta``."""
    v = compose(parts)
    return v.y - problem.design(v) @ theta


def _fold_model(base: Baseline, selected: list, cause: Cause, cv: BlockedCV, f: int,
                fallback: JointModel) -> JointModel:
    """The model fitted without block ``f``: the named causes and ``cause`` on top."""
    fit = cv.fits[f]
    if fit is None:
        return fallback
    parts = [(s.cause, (s.fold_variants[f] or s.variant).h) for s in selected]
    return base.model(parts + [(cause, fit.h)], fit.theta)
