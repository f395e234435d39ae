"""Forward selection of causes with the blocked cross-validation: every effect the record supports.

Starting from the baseline, each step scores every remaining candidate by the fraction of
the *remaining* held-out torque residual its term removes when added to the causes
already named (their hyper-parameters as chosen on each fold's training blocks), less
what of it the measuring chain alone accounts for: the fraction the same term removes on
the record's effect-free twin (:mod:`fricctl.diagnose.twin`: the measuring chain's share),
taken as a fraction of the record's chain residual (:func:`net_of_chain`).  The best
candidate whose net score reaches :data:`~fricctl.diagnose.report.MIN_SCORE` and which can
be told on this record (:func:`collinearity`; a positive inertia refitted beside it; then
the cause's own ``identifiable``: e.g. a ripple period the record can resolve) and whose
extended model simulates the held-out windows better is named -- one that lowers the torque
residual but re-simulates worse is tried and rejected, with the reason -- and the search
repeats until no candidate reaches it.

With a nominal model, a supported candidate must also remove at least as much of the
held-out residual as a scale error of the recorded torque (:func:`torque_scale`: the model's torque times
``1 + e``, a torque-sensor gain or torque-constant error, which is not a cause of the list):
a record whose residual is the model's own torque scaled cannot tell a friction level, an
inertia or a load-dependent friction from it, and naming them would be a wrong cause (issue
21, item 5).  A candidate the scale beats is still told when, on top of the scale, it
removes :data:`MIN_SCORE` of what the scale leaves (an effect of its own beside a scale
error).  One the scale beats is set aside for the step, not dropped: once another
cause is named the scale may no longer match it.  Without a nominal model the refitted
baseline absorbs such a scale exactly.

In the same way, with or without a nominal model, a supported candidate must beat a friction
law of another shape (:func:`speed_curve`: a generic odd function of the velocity, piecewise
linear between knots at quantiles of the record's speeds; no cause of the list), unless its
term is itself a shape of that curve (:attr:`~fricctl.diagnose.causes.Cause.friction_curve`:
Stribeck, drag, a friction level's scale).  A load of position, a drift in time or a
presliding term fitted to a record whose friction has a shape no cause represents removes a
part of its residual that the generic curve removes with the rest (issue 21, item 5: a
Coulomb level reached smoothly with speed was read as each of the three); a candidate that
adds :data:`MIN_SCORE` on top of the curve is still told.

A term whose column is the torque of the model as it stands (a friction growing with the
transmitted torque: :attr:`~fricctl.diagnose.causes.base.Cause.reads_model_torque`) is made
before its own term and before the causes named after it.  Where the model holds one, a told
candidate is re-simulated, and named, with that column settled beside its term
(:func:`~.crossval.settle`: remade on the model's whole torque and refitted until it stops
moving), where the settled model's held-out torque residual is no larger and its windowed
re-simulation no worse than the unsettled one's (:func:`term_trial`); the step's score and its
errors "after" are then the settled model's.

A candidate whose chain share cannot be measured (the twin of the model as it stands ran away:
:attr:`fricctl.diagnose.twin.Twin.ran_away`) has no net score: it is set aside for the step
with :data:`CHAIN_UNMEASURED` and not named on its gross score (its ranking shows NaN, not
the 0 it is held at).

The causes named are then refitted together on all data (:func:`fricctl.diagnose.diagnose`):
one whose every coefficient goes to a bound of 0 there has been taken over by a cause named
after it (a spring at the grid's lowest frequency decouples the load and reads as less
inertia), so the extended model lacks it; it is reported tried and rejected, and the
selection is run again without it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Callable, Mapping, Sequence

import numpy as np

from ..plant import JointModel
from .causes import Baseline, Cause, Term
from .crossval import (BlockedCV, FullFit, Problem, advance, compose, cross_validate,
                       empty_variant, full_fit, settle)
from .windows import WindowedSimulation

__all__ = ["Step", "Selected", "Selection", "forward_selection", "collinearity", "not_applicable",
           "torque_scale", "position_scale", "sensor_scales", "SensorScale", "speed_curve",
           "COLLINEAR_SHARE", "MIN_SCORE", "CURVE_QUANTILES", "CHAIN_UNMEASURED", "net_of_chain"]

#: Smallest held-out fraction of the remaining torque residual (sum of squares) a candidate
#: must remove, net of the measuring chain's share, to be named: 1 - 0.9**2, i.e. the
#: held-out torque RMS must drop by 10 %, the issue's definition of an effect that matters.
MIN_SCORE = 1.0 - 0.9 ** 2


def net_of_chain(gross: float, chain: float) -> float:
    """The held-out fraction of the remaining residual a term removes beyond what the
    measuring chain alone lets it remove [-]: ``gross`` less the chain's estimated part of
    it, both as fractions of the residual before the term.

    ``chain`` is measured on the effect-free twin, whose noise is set so that it keeps the
    residual the record keeps once the term is in (:func:`~fricctl.diagnose.twin.
    effect_free_twin`): a fraction of *that* residual, not of the record's.  Taken to hold
    on the record's own chain residual ``C``, the term leaves ``(1 - chain) * C`` of it --
    all it leaves, ``1 - gross`` -- so it removed ``chain * C = chain * (1 - gross) / (1 -
    chain)`` of the chain's, and the net share is ``gross - chain * (1 - gross) / (1 - chain)
    = (gross - chain) / (1 - chain)``.  That is still conservative: ``C`` is larger than the
    twin's residual, more of it noise, of which the chain's terms remove less (on [33, 24]
    below, 73 % at the twin's level and 23 % at ``C``, review of this rule); and from the
    second step on the twin's noise is set against its baseline's residual, so the named
    causes leave less on it and the share is measured at less noise still (noted, not
    changed).  The earlier rule, ``gross - chain``, took the record's whole residual for the
    chain's and took off a share of a large effect's residual that the effect had already
    removed: a resonance removing 97 % of a 200 Hz record (second simulator, [33, 24]), 73 %
    of its twin's small residual, scored 24 % and lost to a delay.  Where ``chain >= gross``
    the term removes nothing of the record's own: ``gross - chain`` (<= 0, never named;
    a bounded number to print where ``chain`` nears 1)."""
    if not gross > chain:
        return gross - chain
    return (gross - chain) / (1.0 - chain)


#: Why a candidate is set aside when its measuring chain's share cannot be measured.
CHAIN_UNMEASURED = ("the measuring chain's share of it cannot be measured: the effect-free twin of "
                    "the model as it stands ran away (its torque reached the bound of its "
                    "simulation), so its score is not net of the chain's and it is not named")

#: Knots of the generic friction curve (:func:`speed_curve`): quantiles of the speed |w| over
#: the sliding samples, dense at low speed where friction laws differ most [-].
CURVE_QUANTILES = (0.02, 0.05, 0.1, 0.2, 0.4, 0.7)

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
    term removes, less the measuring chain's part of it (:func:`net_of_chain`) [-].  Where the
    step settled a column read from the model's torque (:func:`term_trial`), the settled
    model's, at least the :attr:`ranking`'s (which scores every candidate beside the columns as
    they were), net of the chain's share as measured for the unsettled term."""
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
    """Every candidate of this step with its net score, best first; NaN for one whose chain
    share could not be measured (:data:`CHAIN_UNMEASURED`), in the place a net 0 takes."""
    passed_over: tuple = ()
    """``(cause, gross)`` of each candidate of this step set aside with no net share
    (:data:`CHAIN_UNMEASURED`) whose gross share exceeds the named cause's, largest first: the
    named cause may stand in for one of them (a correlated term takes what the true cause's
    would), which the evidence and the report say."""

    def as_dict(self) -> dict:
        """The step's JSON object (``ranking`` as ``[{cause, score}]``, ``passed_over`` as
        ``[{cause, gross}]``)."""
        out = {k: getattr(self, k) for k in ("cause", "score", "gross", "chain",
                                             "torque_rms_before", "torque_rms_after",
                                             "simulation_rms_before", "simulation_rms_after")}
        out["ranking"] = [{"cause": c, "score": s} for c, s in self.ranking]
        out["passed_over"] = [{"cause": c, "gross": g} for c, g in self.passed_over]
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
    """The first step's candidates with their net scores, best first (NaN: no net share,
    as in :attr:`Step.ranking`)."""
    last_ranking: tuple
    """The candidates of the step that named nothing, with their net scores, best first
    (why the selection stopped; empty when every candidate was named or dropped; NaN: no net
    share, as in :attr:`Step.ranking`)."""
    simulation_scores: dict
    """First step: per candidate, the held-out fraction of the windowed simulation error
    (position, sum of squares) its term removes [-] (computed for the supported ones)."""
    not_identifiable: dict = field(default_factory=dict)
    """Candidates that reached the score but cannot be told on this record, those whose
    term cannot be added to the model (:func:`not_applicable`), and those a scale error of
    the recorded torque explained better when last scored (:func:`torque_scale`; never
    named), with the reason."""
    test: np.ndarray = field(default_factory=lambda: np.zeros(0))
    """Held-out SSE per block of the final model."""
    baseline_test: np.ndarray = field(default_factory=lambda: np.zeros(0))
    """Held-out SSE per block of the baseline."""
    sim_before: WindowedSimulation | None = None
    sim_after: WindowedSimulation | None = None
    final: "_State | None" = None
    """Where the selection stood when it stopped (the model as it stands, its held-out
    residual and simulation): what :mod:`.below` measures the last step's candidates on."""
    last_scored: Mapping = field(default_factory=dict)
    """The candidates of the step that named nothing, as scored there (``name ->``
    :class:`_Scored`); empty when the last step named a cause."""


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
                      simulate: Callable[[Sequence], WindowedSimulation], *,
                      progress: Callable[[int, int, int], None] | None = None) -> Selection:
    """Name every cause the record supports, one step at a time (see the module notes).

    Parameters
    ----------
    problem, base : Problem, Baseline
        The record's normal equations and the baseline every candidate extends (not
        changed: each step works on :meth:`Baseline.advanced`).
    candidates : tuple of Cause
    chain : callable
        ``chain(floor, named, model)`` gives, for a twin of ``model`` (the model as it
        stands, fitted on all data, with the causes ``named`` so far) whose held-out
        residual is ``floor`` [N^2*m^2], ``share(cause)``: the held-out fraction of its
        residual the cause's term removes after the causes ``named`` [-].  Asked for each
        candidate whose gross score reaches :data:`MIN_SCORE`, with the residual the record
        keeps once that candidate's term is in.
    simulate : callable
        ``simulate(fold_models)``: the held-out windowed simulation of one model per fold.
    progress : callable, optional
        ``progress(step, done, total)``: called before the candidates of a step are scored
        (``done`` 0) and after each (for a progress bar).
    """
    state = _start(problem, base, candidates, simulate)
    scored: dict = {}
    while state.remaining:
        sse_prev = float(np.sum(state.test))
        if not sse_prev > 0:
            break
        scored = _score(problem, state, chain, sse_prev, progress)
        # a candidate whose chain share could not be measured is set aside for the step
        # (and one measured now loses an earlier step's such reason)
        state = replace(state, aside={
            **{n: r for n, r in state.aside.items()
               if not (r == CHAIN_UNMEASURED and n in scored and not scored[n].unmeasured)},
            **{n: CHAIN_UNMEASURED for n, sc in scored.items() if sc.unmeasured}})
        # a candidate with no net share shows NaN, not the 0 it is held at (a number that
        # would read as measured), in the place a net 0 takes
        ranking = tuple((name, math.nan if scored[name].unmeasured else net)
                        for name, net in sorted(((name, s.net) for name, s in scored.items()),
                                                key=lambda kv: -kv[1]))
        state = replace(state, last_ranking=ranking,
                        first_ranking=state.first_ranking if state.steps else ranking)
        verdict = _tell(problem, state, scored, ranking, sse_prev)
        # a cause that cannot be told on this record is not tried again
        state = replace(state, not_told={**state.not_told, **verdict.reasons},
                        aside={**state.aside, **verdict.aside},
                        remaining=tuple(c for c in state.remaining
                                        if c.name not in verdict.reasons))
        if not verdict.told:
            break
        before = len(state.steps)
        named, rejected = _name(problem, state, verdict.told, scored, ranking, sse_prev,
                                simulate)
        state = replace(named, not_told={**named.not_told, **rejected},
                        remaining=tuple(c for c in named.remaining if c.name not in rejected))
        if len(state.steps) == before:  # every told candidate re-simulated worse
            break
        scored = {}  # a step that named a cause: its scores are not the last step's
    named = {s.cause.name for s in state.selected}
    aside = {k: r for k, r in state.aside.items() if k not in named and k not in state.not_told}
    return Selection(selected=state.selected, steps=state.steps,
                     first_ranking=state.first_ranking, last_ranking=state.last_ranking,
                     simulation_scores=state.simulation_scores,
                     not_identifiable={**state.not_told, **aside}, test=state.test,
                     baseline_test=state.baseline_test, sim_before=state.sim_before,
                     sim_after=state.sim, final=state,
                     last_scored=scored if state.last_ranking else {})


@dataclass(frozen=True, kw_only=True, eq=False)
class _State:
    """Where the forward selection stands after a step (each step returns a new one)."""

    base: Baseline
    """The baseline with the residual of the model as it stands (:meth:`Baseline.advanced`)."""
    test: np.ndarray
    """Held-out SSE per block of the model as it stands [N^2*m^2]."""
    fold_models: tuple
    """Per fold, the model as it stands fitted without that block."""
    model: JointModel
    """The model as it stands, fitted on all data."""
    sim: WindowedSimulation
    """Held-out windowed simulation of :attr:`fold_models`."""
    baseline_test: np.ndarray
    """Held-out SSE per block of the baseline [N^2*m^2]."""
    sim_before: WindowedSimulation
    """Held-out windowed simulation of the baseline."""
    remaining: tuple
    """The candidates still tried."""
    not_told: Mapping[str, str]
    """Candidates dropped, with the reason (:attr:`Selection.not_identifiable`)."""
    selected: tuple = ()
    """The :class:`Selected` causes, in the order named."""
    steps: tuple = ()
    """One :class:`Step` per named cause."""
    first_ranking: tuple = ()
    """The first step's ``(cause, net score)``, best first (NaN: no net share)."""
    last_ranking: tuple = ()
    """The ranking of the last step if it named nothing, else ()."""
    simulation_scores: Mapping[str, float] = field(default_factory=dict)
    """First step that named a cause: the simulation score of each candidate told."""
    aside: Mapping[str, str] = field(default_factory=dict)
    """Candidates a scale error of the recorded torque explained as well, at the latest step
    that scored them, with why (:func:`torque_scale`)."""


@dataclass(frozen=True, kw_only=True, eq=False)
class _Scored:
    """One candidate of a step, scored by the blocked cross-validation."""

    cause: Cause
    net: float
    """:attr:`gross` net of :attr:`chain` (:func:`net_of_chain`) [-]."""
    gross: float
    """Held-out fraction of the remaining torque residual the term removes [-]."""
    chain: float
    """The measuring chain's share (0 unless :attr:`gross` reaches :data:`MIN_SCORE`) [-]."""
    cv: BlockedCV
    """The candidate's blocked cross-validation after the causes named."""
    test: np.ndarray
    """Held-out SSE per block with the term in (the model's where no variant fits)."""
    unmeasured: bool = False
    """The measuring chain's share could not be measured (the twin ran away): the net score
    is set to 0, the chain's share to NaN."""


@dataclass(frozen=True, kw_only=True, eq=False)
class _Told:
    """A supported candidate that can be told on this record, fitted on all data."""

    cause: Cause
    fit: FullFit


@dataclass(frozen=True, kw_only=True, eq=False)
class _Verdict:
    """Which supported candidates of a step can be told on this record."""

    told: tuple
    """The :class:`_Told` ones, best score first."""
    reasons: Mapping[str, str]
    """The others that cannot be told on this record, with why not (not tried again)."""
    aside: Mapping[str, str] = field(default_factory=dict)
    """Those a scale error of the recorded torque explains as well, with why (tried again
    at the next step)."""


@dataclass(frozen=True, kw_only=True, eq=False)
class _Trial:
    """A told candidate added to each fold's model, and those models re-simulated."""

    fold_models: tuple
    sim: WindowedSimulation
    settled: tuple | None = None
    """Where a column read from the model's torque is in the model: ``(selected, theta, base,
    test)`` of the named causes with the term added, those columns settled beside it
    (:func:`~.crossval.settle`): what naming the term makes of the model.  None otherwise."""


def _start(problem: Problem, base: Baseline, candidates: tuple,
           simulate: Callable[[Sequence], WindowedSimulation]) -> _State:
    """The baseline held out block by block, simulated, and the candidates it can take."""
    empty = base.variant(None, np.zeros((base.target.size, 0)), ())
    cv0 = cross_validate(problem, lambda f: [empty])
    fold_models = tuple(base.model((), fit.theta) if fit is not None else base.fitted
                        for fit in cv0.fits)
    sim = simulate(fold_models)
    # a cause whose term cannot sit in one model with the baseline (or, later, with the
    # causes named) is not tried: a limit of the models, not of the record
    not_told = not_applicable(base, [], base.theta if base.fit_mode else np.zeros(0), candidates)
    return _State(base=base, test=cv0.test.copy(), fold_models=fold_models, model=base.fitted,
                  sim=sim, baseline_test=cv0.test, sim_before=sim,
                  remaining=tuple(c for c in candidates if c.name not in not_told),
                  not_told=not_told)


def _fixed_for(selected: tuple) -> Callable[[int], tuple]:
    """Per fold, the variants of the causes named (chosen on that fold's training blocks).

    A named cause with no variant for a fold (a block it cannot test, e.g. one reaching far
    beyond :mod:`.causes.position_load`'s training travel) stays out of that fold at every
    later step, as it was at the step that named it and as the twin leaves it out
    (:func:`fricctl.diagnose.twin.chain_shares`).  Filling it with the all-data variant put
    the term back on that block one step later: what it then removed there was credited to
    whichever candidate was scored (issue 21's review: seven causes above the line beside a
    named load on a drifting record)."""
    def fixed_for(f):
        return tuple(s.fold_variants[f] for s in selected if s.fold_variants[f] is not None)
    return fixed_for


@dataclass(frozen=True, kw_only=True, eq=False)
class SensorScale:
    """A scale error of a sensor, held out as the candidates are (:func:`torque_scale`,
    :func:`position_scale`)."""

    test: np.ndarray | None
    """Held-out SSE per block with the scale in the model (None without a nominal model)."""
    gain: float
    """The fitted scale of the sensor, recorded over true, on all data [-] (NaN: none)."""
    variant: object = None
    """Its column, as a :class:`~fricctl.diagnose.crossval.Variant`."""
    what: str = ""
    """The error in words, with the fitted gain (for the reason a candidate is set aside)."""


#: Relative step of the finite difference of the nominal friction along a scaled motion [-].
_MOTION_STEP = 1e-3


def _scale(problem: Problem, base: Baseline, selected: tuple, column: np.ndarray, name: str,
           gain_of: Callable[[float], float], what: Callable[[float], str]) -> SensorScale:
    variant = base.variant(name, column, (0,))
    cv = cross_validate(problem, lambda f: [variant], _fixed_for(selected))
    fit = full_fit(problem, [variant], tuple(s.variant for s in selected))
    gain = math.nan if fit is None else gain_of(float(fit.theta[-1]))
    return SensorScale(test=cv.test, gain=gain, variant=variant, what=what(gain))


def torque_scale(problem: Problem, base: Baseline, selected: tuple = ()) -> SensorScale:
    """A scale error of the recorded torque, held out as the candidates are, after the causes
    ``selected`` (they stay in the model with their own terms); without a nominal model
    nothing (the refitted baseline absorbs a scale exactly).

    The column is the nominal model's low-passed torque along the measured motion
    (:attr:`Baseline.model_torque`); a recorded torque ``(1 + e)`` times the applied one
    leaves the nominal residual ``e`` times it, plus noise.
    """
    if base.fit_mode:
        return SensorScale(test=None, gain=math.nan)
    return _scale(problem, base, selected, base.model_torque, "torque_scale",
                  lambda c: 1.0 + c,
                  lambda g: f"a scale error of the recorded torque (the model's torque x {g:.3f}: "
                            f"a torque-sensor gain or torque-constant error, not a cause of the "
                            f"list)")


def position_scale(problem: Problem, base: Baseline, selected: tuple = ()) -> SensorScale:
    """A scale error of the recorded position (an encoder count or a gear ratio), held out as
    the candidates are, after the causes ``selected``; without a nominal model nothing (the
    refitted inertia and viscous coefficient absorb it).

    A position recorded ``(1 + e)`` times the true one makes the nominal model's torque
    along the recorded motion ``pred((1 + e) q)``: the nominal residual is, to first order,
    ``-e/(1 + e)`` times the column ``d pred(s q)/ds`` at ``s = 1`` -- ``I*a`` plus the
    derivative of the nominal friction along the scaled motion (a finite difference; a
    Coulomb level does not change, a viscous term does).  An elastic nominal model's load
    term is left out of the column.
    """
    if base.fit_mode:
        return SensorScale(test=None, gain=math.nan)
    sig, nominal = base.sig, base.nominal
    f0 = nominal.friction.along_motion(sig.qf, sig.w, base.torque, sig.t)
    f1 = nominal.friction.along_motion(sig.qf * (1 + _MOTION_STEP), sig.w * (1 + _MOTION_STEP),
                                       base.torque, sig.t)
    column = nominal.inertia * sig.a + sig.filt((f1 - f0) / _MOTION_STEP)
    units = base.labels
    return _scale(problem, base, selected, column, "position_scale",
                  lambda c: 1.0 / (1.0 + c) if c > -1.0 else math.inf,
                  lambda g: f"a scale error of the recorded position (the motion x {g:.3f} of the "
                            f"true one: an encoder count or gear ratio error, in "
                            f"{units.position}, not a cause of the list)")


def sensor_scales(problem: Problem, base: Baseline, selected: tuple = ()) -> tuple:
    """The sensor scale errors a candidate must beat (nominal model only): the torque's and
    the position's."""
    if base.fit_mode:
        return ()
    return (torque_scale(problem, base, selected), position_scale(problem, base, selected))


def speed_curve(problem: Problem, base: Baseline, selected: tuple = ()) -> SensorScale:
    """A friction law of another shape, held out as the candidates are, after the causes
    ``selected``: a generic odd function of the velocity, piecewise linear in ``|w|`` between
    knots at the :data:`CURVE_QUANTILES` of the record's sliding speeds and constant beyond
    the last (columns ``clip(w/k, -1, 1)``, one per knot ``k``), on top of the baseline's
    viscous and Coulomb terms (fit mode) or with them (nominal model).

    It is not a cause: it stands for whatever shape the record's friction-speed curve has
    (a sub-linear viscous law, a smooth Coulomb transition) that the candidates' specific
    terms would otherwise absorb in part.
    """
    sig = base.sig
    speed = np.abs(sig.w[sig.moving])
    knots = np.unique(np.quantile(speed, CURVE_QUANTILES)) if speed.size else np.zeros(0)
    cols = [sig.filt(np.clip(sig.w / k, -1.0, 1.0)) for k in knots if k > 0]
    if not base.fit_mode:  # the nominal model's levels may be wrong too
        cols = [sig.filt(base.sign), sig.filt(sig.w)] + cols
    if not cols:
        return SensorScale(test=None, gain=math.nan)
    variant = base.variant("speed_curve", np.column_stack(cols), (0,) * len(cols))
    cv = cross_validate(problem, lambda f: [variant], _fixed_for(selected))
    return SensorScale(test=cv.test, gain=math.nan, variant=variant,
                       what=f"a friction law of another shape (a smooth odd function of the "
                            f"velocity, piecewise linear between {int(np.sum(knots > 0))} knots "
                            f"at the record's speeds, not a cause of the list)")


def _score(problem: Problem, state: _State, chain, sse_prev: float, progress) -> dict:
    """Every remaining candidate held out after the causes named (``name -> _Scored``); the
    chain's share is asked only once all are cross-validated."""
    step, total = len(state.steps) + 1, len(state.remaining)
    selected = state.selected
    fixed_for = _fixed_for(selected)

    if progress is not None:
        progress(step, 0, total)
    gross = {}
    for i, c in enumerate(state.remaining):
        cv = cross_validate(problem, lambda f, c=c: state.base.variants(c, f), fixed_for)
        if progress is not None:
            progress(step, i + 1, total)
        test = np.where(np.isnan(cv.test), state.test, cv.test)
        g = 1.0 - float(np.sum(test)) / sse_prev
        gross[c.name] = _Scored(cause=c, net=g, gross=g, chain=0.0, cv=cv, test=test)
    named = tuple(s.cause for s in selected)
    scored = {}
    for name, s in gross.items():
        share = 0.0
        if s.gross >= MIN_SCORE:  # the twin keeps what the record keeps with the term in
            share = chain(sse_prev * (1.0 - s.gross), named, state.model)(s.cause)
            if not math.isfinite(share):  # no twin to measure it on: no net score either
                scored[name] = replace(s, net=0.0, chain=math.nan, unmeasured=True)
                continue
            share = max(share, 0.0)
        scored[name] = replace(s, net=net_of_chain(s.gross, share), chain=share)
    return scored


def _tell(problem: Problem, state: _State, scored: dict, ranking: tuple,
          sse_prev: float) -> _Verdict:
    """The supported candidates, best first, fitted on all data and checked: one that a
    scale error of the recorded torque matches (nominal model: :func:`torque_scale`),
    collinear with the model, or not identifiable by the cause's own test, is not told."""
    told, reasons, aside = [], {}, {}
    fixed = tuple(s.variant for s in state.selected)
    scales = None
    for name, score in ranking:
        if not score >= MIN_SCORE:
            continue
        cause = scored[name].cause
        fit = full_fit(problem, state.base.variants(cause, None), fixed)
        reason = _why_not_told(problem, state, cause, fit, fixed)
        if reason is not None:
            reasons[name] = reason
            continue
        if scales is None:  # asked once per step, and only when a candidate can be told
            scales = sensor_scales(problem, state.base, state.selected)
            curve = speed_curve(problem, state.base, state.selected)
        # a shape of the friction curve is not judged against a generic curve, which spans it
        rivals = scales + (() if cause.friction_curve else (curve,))
        reason = next((r for r in (_scale_matches(problem, state, scored[name], sc, sse_prev)
                                   for sc in rivals) if r is not None), None)
        if reason is not None:  # set aside for this step only: once another cause is in,
            aside[name] = reason  # the scale may no longer match it
        else:
            told.append(_Told(cause=cause, fit=fit))
    return _Verdict(told=tuple(told), reasons=reasons, aside=aside)


def _scale_matches(problem: Problem, state: _State, s: "_Scored", scale: SensorScale,
                   sse_prev: float) -> str | None:
    """Why a sensor's scale error explains the record better than the candidate ``s`` and
    leaves it nothing to add (held out), or None: no nominal model, the candidate removes at
    least as much, or on top of the scale it still removes :data:`MIN_SCORE` of what the
    scale leaves (an effect of its own beside a scale error)."""
    on_top = rival_on_top(problem, state, s, scale, sse_prev)
    if on_top is None or on_top >= MIN_SCORE:
        return None
    sse_scale = float(np.sum(scale.test))
    return (f"tried, rejected: {scale.what} removes more of the held-out residual "
            f"({100 * (1 - sse_scale / sse_prev):.0f} % against {100 * s.gross:.0f} %) and the "
            f"term adds {100 * max(on_top, 0.0):.0f} % on top of it: the record cannot tell the "
            f"two apart")


def rival_on_top(problem: Problem, state: _State, s: "_Scored", rival: SensorScale,
                 sse_prev: float) -> float | None:
    """What the candidate ``s`` removes of the held-out residual ``rival`` leaves, the two
    cross-validated together [-]; None where the rival is not held out (no nominal model)
    or does not remove strictly more than the candidate alone (beyond round-off: once an
    inertia is named, a scale of the model's torque spans what a friction level does, the
    same fit, and the cause of the list is kept).  Read against the naming line by
    :func:`_scale_matches` and against the F test below it (:mod:`.below`)."""
    if rival.test is None or not np.all(np.isfinite(rival.test)):
        return None
    sse_rival, sse_cause = float(np.sum(rival.test)), float(np.sum(s.test))
    if sse_rival >= sse_cause - 1e-9 * sse_prev:
        return None
    fixed_for = _fixed_for(state.selected)
    cv = cross_validate(problem, lambda f: state.base.variants(s.cause, f),
                        lambda f: fixed_for(f) + (rival.variant,))
    both = float(np.sum(np.where(np.isnan(cv.test), rival.test, cv.test)))
    return 1.0 - both / sse_rival if sse_rival > 0 else 0.0


def _why_not_told(problem: Problem, state: _State, cause: Cause, fit: FullFit | None,
                  fixed: tuple) -> str | None:
    """Why the term of ``cause`` fitted on all data (``fit``) cannot be told on this record,
    or None."""
    if fit is None:
        return "no variant of the term can be fitted to all the data"
    share = collinearity(problem, fixed, fit.variant)
    if share < COLLINEAR_SHARE:
        return (f"its column is collinear with the model's on this record (only "
                f"{100 * share:.2g} % of it lies outside their span)")
    if state.base.fit_mode and not fit.theta[0] > 0:
        # the model would hold no inertia (Baseline.model clamps it to 1e-12): no joint moves
        # so, and its effect-free twin cannot even be simulated (independent bench, [31, 107]:
        # a delay of 11 samples at 200 Hz beside an inertia refitted to -0.0039 kg*m^2, and
        # the diagnosis stopped on "too stiff for this sample time")
        return (f"the joint's inertia refitted beside it is {fit.theta[0]:.3g} "
                f"{state.base.labels.inertia}: a model with no positive inertia is not a joint")
    coef = fit.theta[fit.theta.size - cause.n_extra:]
    parts = _parts(state.selected) + [(cause, fit.variant.h)]
    return cause.identifiable(state.base, Term(h=fit.variant.h, coef=coef,
                                               extended=state.base.model(parts, fit.theta)))


def _name(problem: Problem, state: _State, told: tuple, scored: dict, ranking: tuple,
          sse_prev: float, simulate, made: Mapping[str, "_Trial"] | None = None) -> tuple:
    """Name the best told candidate whose models simulate the held-out windows better and
    move the model on by its term.  Returns ``(state, rejected)``: the candidates whose
    extended models re-simulate the held-out windows worse are tried and rejected, with
    the reason (issue 21: a term that lowers the torque residual but makes the model
    simulate worse is not a physical cause); when every told one is rejected, the state is
    returned unchanged.  Where the windows cannot be re-simulated at all (NaN), the
    simulation does not judge.  ``made``: trials already made (:func:`term_trial`, by cause
    name), not made again."""
    trials = {t.cause.name: (made or {}).get(t.cause.name)
                           or term_trial(problem, state, t.cause, scored[t.cause.name].cv, simulate,
                                         t.fit)
              for t in told}
    sim_score = {n: simulation_score(state, tr) for n, tr in trials.items()}
    rejected = {}
    for t in told:
        sc = sim_score[t.cause.name]
        if math.isfinite(sc) and sc <= 0.0:
            before, after = state.sim.rms().position, trials[t.cause.name].sim.rms().position
            rejected[t.cause.name] = (
                f"tried, rejected: its extended model re-simulates the held-out windows worse "
                f"(position RMS {before:.3g} -> {after:.3g}) although it lowers the torque "
                f"residual")
    keep = [t for t in told if t.cause.name not in rejected]
    if not keep:
        return state, rejected
    pick = keep[0]
    cause, fit = pick.cause, pick.fit
    s, trial = scored[cause.name], trials[cause.name]
    net, gross = s.net, s.gross
    if trial.settled is not None:  # a column read from the model's torque, settled: the step
        selected, theta, base, test = trial.settled  # scores the model it names (no worse)
        gross = 1.0 - float(np.sum(test)) / sse_prev
        net = net_of_chain(gross, s.chain)  # a told candidate's chain share was measured
    else:
        selected = state.selected + (_named(cause, s.cv, fit),)
        theta, test = fit.theta, s.test
        base = advance(state.base, problem, tuple(x.variant for x in selected), theta)
    fold_models, sim = trial.fold_models, trial.sim
    model = state.base.model(_parts(selected), theta)  # the model as it now stands
    nmov = max(int(problem.sig.moving.sum()), 1)
    step = Step(cause=cause.name, score=net, gross=gross, chain=s.chain,
                torque_rms_before=math.sqrt(sse_prev / nmov),
                torque_rms_after=math.sqrt(float(np.sum(test)) / nmov),
                simulation_rms_before=state.sim.rms().position,
                simulation_rms_after=sim.rms().position, ranking=ranking,
                passed_over=tuple(sorted(((n, o.gross) for n, o in scored.items()
                                          if o.unmeasured and o.gross > gross),
                                         key=lambda kv: -kv[1])))
    remaining = tuple(c for c in state.remaining if c is not cause)
    gone = not_applicable(base, _parts(selected), theta, remaining)
    return replace(state, base=base, test=test, fold_models=fold_models,
                   model=model, sim=sim,
                   selected=selected, steps=state.steps + (step,), last_ranking=(),
                   remaining=tuple(c for c in remaining if c.name not in gone),
                   not_told={**state.not_told, **gone},
                   simulation_scores=state.simulation_scores if state.steps else sim_score), {}


def _resettled(selected: tuple, settled: tuple) -> tuple:
    """The named causes with the variants :func:`~.crossval.settle` remade (a column read
    from the model's torque is one column on all data: every fold that had the cause's
    variant takes the new one)."""
    out = []
    for x, v in zip(selected, settled):
        if v is not x.variant:
            x = replace(x, variant=v,
                        fold_variants=tuple(v if fv is not None else None
                                            for fv in x.fold_variants))
        out.append(x)
    return tuple(out)


def _held_out(problem: Problem, state: _State, selected: tuple) -> tuple:
    """``(test, fold_models)`` of the named causes ``selected`` as they are: held out block by
    block (each fold's variants, :func:`_fixed_for`) and the models fitted without each
    block."""
    empty = empty_variant(state.base.target)
    cv = cross_validate(problem, lambda f: [empty], _fixed_for(selected))
    models = []
    for f, fit in enumerate(cv.fits):
        parts = [(x.cause, x.fold_variants[f].h) for x in selected
                 if x.fold_variants[f] is not None]
        models.append(state.base.model(parts, fit.theta) if fit is not None
                      else state.fold_models[f])
    return np.where(np.isnan(cv.test), state.test, cv.test), tuple(models)


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


def _parts(selected: tuple) -> list:
    """``(cause, h)`` of each named cause (the hyper-parameter chosen on all data)."""
    return [(s.cause, s.variant.h) for s in selected]


def _named(cause: Cause, cv: BlockedCV, fit: FullFit) -> Selected:
    """``cause`` as named: its variant per fold (``cv``) and on all data (``fit``)."""
    return Selected(cause=cause, fold_variants=tuple(f.variant if f is not None else None
                                                     for f in cv.fits), variant=fit.variant)


def term_trial(problem: Problem, state: _State, cause: Cause, cv: BlockedCV,
               simulate: Callable[[Sequence], WindowedSimulation],
               fit: FullFit | None = None) -> _Trial:
    """The model as it stands with ``cause``'s term added in each fold (its blocked
    cross-validation ``cv``), and those models' held-out windowed simulation.

    Where the model then holds a column read from the model's torque
    (:attr:`~fricctl.diagnose.causes.base.Cause.reads_model_torque`, the term's own or a named
    cause's) and the term's fit on all data ``fit`` is given, the columns are also settled
    beside the term (:func:`~.crossval.settle`) and the folds refitted with them.  The settled
    model is kept only where it is no worse by both of the selection's tests -- the held-out
    torque residual and the windowed re-simulation (which must re-simulate it wherever it
    re-simulates the unsettled one) -- since a fixed point
    is not a least-squares minimum: on five records of a load dependence beside a delay, a
    ripple or a drag (review R8), settling left the held-out residual 7 % larger on one and the
    re-simulation 6-21 % worse on four whose held-out residual it lowered.  Where it is kept,
    the term is judged, and named, by the model naming it makes."""
    every = tuple(x.cause for x in state.selected) + (cause,)
    models = tuple(_fold_model(state, cause, cv, f) for f in range(problem.sig.n_folds))
    plain = _Trial(fold_models=models, sim=simulate(models))
    if fit is None or not any(c.reads_model_torque for c in every):
        return plain
    fixed = tuple(x.variant for x in state.selected) + (fit.variant,)
    parts, theta, base = settle(problem, state.base, every, fixed, fit.theta)
    selected = _resettled(state.selected + (_named(cause, cv, fit),), parts)
    test, models = _held_out(problem, state, selected)
    if float(np.sum(test)) > float(np.sum(np.where(np.isnan(cv.test), state.test, cv.test))):
        return plain
    sim = simulate(models)
    a, b = (float(np.sum(x.position_error ** 2)) for x in (sim, plain.sim))
    if math.isfinite(b) and not (math.isfinite(a) and a <= b):  # worse, or not re-simulated
        return plain  # where the plain trial is: the re-simulation's judgement is kept (R9)
    return _Trial(fold_models=models, sim=sim, settled=(selected, theta, base, test))


def simulation_score(state: _State, tried: _Trial) -> float:
    """Held-out share of the windowed simulation error (position, sum of squares) the trial's
    term removes [-]; NaN where the model as it stands has no simulated window (NaN) or none
    at all (0): the simulation does not judge."""
    pb = float(np.sum(state.sim.position_error ** 2))
    if not (math.isfinite(pb) and pb > 0):
        return math.nan
    return 1.0 - float(np.sum(tried.sim.position_error ** 2)) / pb


def _fold_model(state: _State, cause: Cause, cv: BlockedCV, f: int) -> JointModel:
    """The model fitted without block ``f``: the named causes that have a variant for that
    fold and ``cause`` on top (the model as it stands where ``cause`` has no fit for that
    block)."""
    fit = cv.fits[f]
    if fit is None:
        return state.fold_models[f]
    parts = [(s.cause, s.fold_variants[f].h) for s in state.selected
             if s.fold_variants[f] is not None]  # as :func:`_fixed_for` leaves them
    return state.base.model(parts + [(cause, fit.h)], fit.theta)
