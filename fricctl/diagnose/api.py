"""The diagnosis workflow (:func:`diagnose`) and the two checks of a model on another record
(:func:`torque_residual`, :func:`prediction_errors`)."""

from __future__ import annotations

import math
from concurrent import futures
import sys
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Callable

import numpy as np

from .. import _validate as v
from ..datasets import Run
from ..friction import FIELDS as FRICTION_FIELDS
from ..plant import JointModel
from ..plant.model import Provenance
from ..units import units as unit_labels
from . import causes
from .causes import Baseline, Term
from .crossval import Problem, baseline_fit, casadi_refit, compose, full_fit
from .below import PERIOD_PARAMETERS, _length, below_line
from .report import Diagnosis, Gain, evidence_text
from .selection import CHAIN_UNMEASURED, Selection, forward_selection, speed_curve
from .signals import Signals, estimate_signals, predict
from .stops import EndStops, end_stops
from .twin import chain_shares, effect_free_twin
from .verdict import verdict
from .windows import (WindowedSimulation, WindowGrid, clear_of_stops, signals_clear_of_stops,
                      simulate_windows, window_grid)

if TYPE_CHECKING:  # identify imports CasADi: only when a fit is made
    from ..identify import IdentificationResult, RecordIdentification

__all__ = ["diagnose", "judged_by_removal", "torque_residual", "prediction_errors",
           "TorqueResidual", "PredictionErrors", "MAX_SAMPLES", "BYTES_PER_SAMPLE", "MEMORY_BUDGET",
           "AGREEMENT", "check_model_agrees"]

#: Peak memory of ``fricctl diagnose`` per sample of the record, the whole process (CSV
#: reading, interpreter and compiled code included), measured at the former limits: 615 384
#: samples peaked at 4.32 GB (7.0 kB per sample; 6.4 kB per sample of marginal growth from
#: 60 000 to 240 000 samples: the candidates' columns on the record and on its effect-free
#: twins), and, after issue 21's settling and twins (2026-11-28, the tiled record of the test
#: below): 1.08, 2.37, 3.02, 3.63, 3.80 and 4.10 GB at 120 000, 300 000, 400 000, 480 000,
#: 500 000 and 533 333 samples -- 7.2-8.7 kB per sample of growth, over the budget at the former
#: limit (571 428 samples, 4.09-4.12 GB); 8 kB keeps the limit's measured peak 5 % under it
#: [bytes].
#: ``tests/test_cli_faults.py`` runs a record at :data:`MAX_SAMPLES` under
#: :data:`MEMORY_BUDGET` (slow).
BYTES_PER_SAMPLE = 8000
#: The memory a diagnosis may take [bytes].
MEMORY_BUDGET = 4e9
#: Longest record a diagnosis takes [samples]: :data:`MEMORY_BUDGET` at
#: :data:`BYTES_PER_SAMPLE` (500 000 samples, 8.3 min at 1 kHz); a longer one is refused
#: with the number, before any work (``fricctl diagnose``: before the file is parsed).
MAX_SAMPLES = int(MEMORY_BUDGET // BYTES_PER_SAMPLE)


def _check_run(run) -> Run:
    return v.instance("run", run, Run, "a fricctl.datasets.Run")


#: Relative difference beyond which a model's sample time or encoder count and the record's
#: disagree [-].
AGREEMENT = 1e-3


def check_model_agrees(model: JointModel, run: Run, name: str = "model") -> None:
    """Refuse a model whose sample time or encoder count (when it states them) disagree with
    the record's (beyond :data:`AGREEMENT`): a model of another sampling or another encoder.

    The encoder is compared with the grid the record's positions lie on
    (:meth:`~fricctl.datasets.Run.encoder_grid`; a filtered record has none: not checked).
    ``name`` is how the message calls the model (a file name on the command line).
    """
    v.instance("model", model, JointModel, "a fricctl.plant.JointModel")
    v.instance("run", run, Run, "a fricctl.datasets.Run")
    v.text("name", name)
    ts = run.sample_time
    where = run.source or "the record"
    if model.sample_time is not None and abs(model.sample_time - ts) > AGREEMENT * ts:
        raise ValueError(f"{name}: sample_time {model.sample_time:g} s differs from the record's "
                         f"{ts:g} s ({where}): a model of another sampling (resample the record, "
                         f"or correct the model's sample_time)")
    res = model.encoder_resolution
    grid = run.encoder_grid() if res is not None else None
    if res is not None and grid is not None and abs(grid - res) > AGREEMENT * res:
        raise ValueError(f"{name}: encoder_resolution {res:g} differs from the grid the record's "
                         f"positions lie on ({grid:g} {run.position_unit}, {where}): another "
                         f"encoder")


def diagnose(run: Run, model: JointModel | None = None, *, window: float = 0.5,
             folds: int = 8, progress: bool | None = None, on_baseline=None,
             motor_revolution: float | None = None) -> Diagnosis:
    """Show what the model gets wrong on ``run``, name every cause the data support, extend
    the model with them, measure the gain.

    Parameters
    ----------
    run : Run
        The measured record (uniform sampling, any rate; moving in most blocks).
    model : JointModel, optional
        A nominal model to diagnose as given; default: fit the rigid baseline
        ``I*q'' = Tm - b*w - Fc*sign(w)``.  Its sample time and encoder count, when it
        states them, must agree with the record's (:func:`check_model_agrees`).
    window : float
        Window of the re-simulation [s].
    folds : int
        Blocks of the blocked cross-validation (3 .. 20).
    progress : bool, optional
        Show a progress bar (tqdm) on stderr; default: when stderr is a terminal.
    on_baseline : callable, optional
        Called without arguments, in the baseline's thread, once the reported baseline's fit
        (fit mode: a thread beside the selection) has ended, or at once with a nominal model:
        from then on the diagnosis keeps one core busy (``fricctl diagnose --report`` starts
        its painters then, :mod:`fricctl.cli._painters`).
    motor_revolution : float, optional
        Travel of one motor revolution, in the record's position unit [rad] or [m]
        (positive, finite); default: the record's own
        (:attr:`~fricctl.datasets.Run.motor_revolution`, None when unknown).  A period in
        position the diagnosis reports is then also given in motor revolutions.

    Returns
    -------
    Diagnosis

    Notes
    -----
    With a nominal model every candidate fits only its own term on top of it (the
    nominal is trusted otherwise); without, the baseline's I, b and Fc are refitted
    with each candidate in the equation error, and the baseline the diagnosis *reports*
    is ``fricctl identify``'s fit of the record
    (:func:`fricctl.identify.identify_record` without offset or validation: the
    same numbers as ``fricctl identify RECORD --no-offset --no-validation``).  A record longer than :data:`MAX_SAMPLES` is refused (the
    diagnosis holds about :data:`BYTES_PER_SAMPLE` bytes per sample).  ``inertia`` and ``friction_scale`` only apply to a
    nominal model.  Causes are named one step at a time (:mod:`.selection`); a
    candidate's score is net of what its term removes on the record's effect-free twin
    (:mod:`.twin`).

    Examples
    --------
    >>> import numpy as np
    >>> from fricctl.bench.hidden_effects import hidden_effect_record
    >>> rec = hidden_effect_record(np.random.default_rng(3), cause="time_delay", duration=20.0)
    >>> diagnose(rec.run).causes
    ('time_delay',)
    """
    req = _request(run, model, window, folds, progress, motor_revolution)
    if on_baseline is not None and not callable(on_baseline):
        raise ValueError(f"on_baseline must be callable or None, got {on_baseline!r}")
    setup = _setup(run, model, req)  # the reported baseline is fitted in a thread meanwhile
    if on_baseline is not None:
        if setup.ident is None:
            on_baseline()
        else:  # called in its thread when done (at once if it is already)
            setup.ident.add_done_callback(lambda _: on_baseline())
    bar = _ProgressBar(req.show, run.n_samples)
    chain = _ChainShares(setup.base)
    simulate = _HeldOutSimulation.of(setup)
    try:
        candidates, vanished = causes.candidates(nominal=model is not None), {}
        while True:  # at most once per candidate: each pass drops what vanished
            sel = forward_selection(setup.problem, setup.base, candidates, chain, simulate,
                                    progress=bar.step if req.show else None)
            ext = _extension(setup, sel)
            gone = _vanished(sel, ext)
            if not gone:
                break
            vanished.update(gone)
            candidates = tuple(c for c in candidates if c.name not in gone)
        if vanished:
            sel = replace(sel, not_identifiable={**sel.not_identifiable, **vanished})
        below = below_line(setup.problem, sel, chain, simulate,
                           motor_revolution=req.motor_revolution)
    finally:
        bar.close()
    # waited for only here: a failed selection (or Ctrl-C) is not held up by the baseline's
    # fit, which cannot be cancelled once running (it ends in its thread, unused)
    if setup.ident is not None:
        setup = replace(setup, ident=setup.ident.result())
    d = _diagnosis(run, model, setup, sel, ext, chain.floor_rms(), req.motor_revolution)
    return replace(d, below_line=below, motor_revolution=req.motor_revolution,
                   notes={**d.notes, **_below_notes(below)})


@dataclass(frozen=True, kw_only=True)
class _Request:
    """The checked options of a diagnosis."""

    folds: int
    """Blocks of the blocked cross-validation."""
    window: float
    """Window of the re-simulation [s]."""
    show: bool
    """Whether a progress bar is shown."""
    motor_revolution: float | None = None
    """Travel of one motor revolution [rad] or [m], or None (unknown)."""


def _request(run: Run, model: JointModel | None, window, folds, progress,
             motor_revolution=None) -> _Request:
    """The arguments of :func:`diagnose` checked (in this order), before any work."""
    _check_run(run)
    if model is not None:
        v.instance("model", model, JointModel, "a JointModel (or None)")
        check_model_agrees(model, run)
    folds = v.integer("folds", folds, low=3, high=20)
    window = v.real("window", window, positive=True, unit="s")
    show = sys.stderr.isatty() if progress is None else v.flag("progress", progress)
    if motor_revolution is None:
        motor_revolution = run.motor_revolution
    else:
        motor_revolution = v.real("motor_revolution", motor_revolution, positive=True,
                                  unit=run.position_unit)
    if run.n_samples > MAX_SAMPLES:
        raise ValueError(
            f"run: {run.n_samples} samples; a diagnosis holds about {BYTES_PER_SAMPLE / 1e3:.1f} kB "
            f"per sample ({run.n_samples * BYTES_PER_SAMPLE / 1e9:.1f} GB here) and takes at most "
            f"{MAX_SAMPLES} samples (a {MEMORY_BUDGET / 1e9:g} GB budget): cut the record or "
            f"decimate it by "
            f"{math.ceil(run.n_samples / MAX_SAMPLES)}")
    return _Request(folds=folds, window=window, show=show, motor_revolution=motor_revolution)


@dataclass(frozen=True, kw_only=True, eq=False)
class _Setup:
    """The record as every candidate sees it."""

    sig: Signals
    """The record's signals, cut into :attr:`_Request.folds` blocks."""
    grid: WindowGrid
    """The windows of the re-simulation."""
    fit0: "IdentificationResult | None"
    """The CasADi equation-error fit of the rigid baseline the candidates extend (fit
    mode), or None with a nominal model."""
    ident: "RecordIdentification | futures.Future | None"
    """The record identified as ``fricctl identify`` does (fit mode): the baseline the
    diagnosis reports (a future while the selection runs), or None with a nominal model."""
    base: Baseline
    """The baseline every candidate extends."""
    problem: Problem
    """The record's normal equations."""
    stops: EndStops
    """The record's end stops: their contacts are out of the equation error, the windows,
    the twin and the verdict."""
    dropped: int
    """Re-simulation windows dropped for holding a contact with an end stop."""
    held: tuple = ()
    """The causes whose effect the supplied model held, removed to be judged
    (:func:`judged_by_removal`)."""


def _setup(run: Run, model: JointModel | None, req: _Request) -> _Setup:
    """Signals, windows and baseline of the record; a nominal model the record's sample
    time cannot re-simulate is refused here."""
    stops = end_stops(run)
    sig = estimate_signals(run, req.folds, exclude=stops.mask if stops.found else None)
    whole = window_grid(sig, req.window)
    grid = clear_of_stops(whole, stops, sig)
    if model is not None:
        try:
            simulate_windows(model, sig, grid.starts[:1], grid.length)
        except ValueError as err:
            raise ValueError(f"model: cannot be re-simulated at the record's sample time "
                             f"({sig.ts:g} s): {err}") from None
    fit0 = baseline_fit(sig) if model is None else None
    ident = None
    if model is None:  # the baseline reported: fricctl identify's own fit of the record
        from ..identify import identify_record

        # fitted in a thread while the selection runs (its replays release the GIL: the
        # second core of a small machine); diagnose() waits for it before reporting
        pool = futures.ThreadPoolExecutor(max_workers=1, thread_name_prefix="fricctl-baseline")
        ident = pool.submit(identify_record, run, model="coulomb_viscous", offset=False,
                            validate=False, stops=stops, start=fit0)  # its step 1 is fit0
        pool.shutdown(wait=False)
    core, held = (None, ()) if model is None else judged_by_removal(model)
    base = Baseline(sig, core, None if fit0 is None else fit0.estimates.copy())
    return _Setup(sig=sig, grid=grid, fit0=fit0, ident=ident, base=base,
                  problem=Problem(sig, base.columns), stops=stops,
                  dropped=whole.starts.size - grid.starts.size, held=held)


def judged_by_removal(model: JointModel) -> tuple:
    """``(core, held)``: ``model`` without every effect a cause can remove from it
    (:attr:`~fricctl.diagnose.causes.Cause.remove`), and the names of the causes whose
    effect it held, in candidate order.

    A supplied model's offset, asymmetric levels or Stribeck excess are claims about the
    record like any cause's: the diagnosis starts from the core and the selection names
    again, by the same held-out tests and in the order they earn it, what the record
    supports -- so that the causes do not depend on what a model happened to hold (on EMPS
    the IDIM-LS model's constant offset is a viscous asymmetry seen at the record's
    plateau speeds; fit mode names the asymmetry, and so does the diagnosis of that model).
    """
    core, held = model, []
    for cause in causes.candidates(nominal=True):
        if cause.held_by(core):
            core = cause.remove(core)
            held.append(cause.name)
    return core, tuple(held)


class _ChainShares:
    """``chain(floor, named, model)`` of :func:`~fricctl.diagnose.selection.forward_selection`:
    the measuring chain's shares on an effect-free twin of ``model`` (the model as it stands,
    with the causes ``named``) whose held-out residual is ``floor``.

    Twins are kept by the names of the causes named (within one diagnosis they say which
    model stands) and the floor to within 10 %; a step's twins are freed when the next step
    asks (they are never asked again).  The noise-free twin of the model as it stands, which
    starts every search for a floor's noise and is the twin itself where the chain alone
    leaves the floor, is made once per step (it was made again for each floor, and once
    more for the diagnosis's own floor, :meth:`floor_rms`); floors that end on one twin share
    its shares."""

    def __init__(self, base: Baseline):
        self.base = base
        self.twins: dict = {}
        #: ``(model, twin)``: the noise-free twin of the model asked last
        self.still: tuple | None = None
        #: the held-out residual RMS of the baseline's noise-free twin, once made [N*m]
        self.fitted_rms: float | None = None

    def __call__(self, floor: float, named: tuple, model: JointModel):
        names = tuple(c.name for c in named)
        key = (names, round(math.log(max(floor, 1e-300)) / math.log(1.1)))
        if key not in self.twins:
            self.twins = {k: t for k, t in self.twins.items() if k[0] == names}
            if self.still is None or self.still[0] is not model:
                self.still = (model, _twin(self.base, None, model))
                if model is self.base.fitted:
                    self.fitted_rms = self.still[1].rms
            twin = _twin(self.base, floor, model, still=self.still[1])
            # the same twin (the noise-free one, for floors the chain alone leaves): the
            # same shares
            same = next((share for t, share in self.twins.values() if t is twin), None)
            self.twins[key] = (twin, same or chain_shares(twin, named))
        return self.twins[key][1]

    def floor_rms(self) -> float:
        """The measuring chain's held-out residual RMS on the record: the baseline's
        noise-free twin's (:attr:`Twin.rms`; made here unless a step made it) [N*m]."""
        return _twin(self.base).rms if self.fitted_rms is None else self.fitted_rms


@dataclass(frozen=True, kw_only=True, eq=False)
class _HeldOutSimulation:
    """``simulate(fold_models)`` of :func:`~fricctl.diagnose.selection.forward_selection`:
    each block's windows re-simulated with the model fitted without that block (NaN errors
    and the reason when a fold's model cannot be re-simulated: too stiff for the sample
    time, or diverging)."""

    sig: Signals
    grid: WindowGrid
    starts: tuple
    """Per block, the starts of the windows that lie wholly inside it [samples]."""

    @classmethod
    def of(cls, setup: _Setup) -> "_HeldOutSimulation":
        sig, grid = setup.sig, setup.grid
        wfold = sig.folds[grid.starts]
        inside = sig.folds[np.minimum(grid.starts + grid.length - 1, sig.t.size - 1)] == wfold
        return cls(sig=sig, grid=grid, starts=tuple(grid.starts[(wfold == f) & inside]
                                                    for f in range(sig.n_folds)))

    def __call__(self, models) -> WindowedSimulation:
        sig, length = self.sig, self.grid.length
        try:
            parts = [simulate_windows(models[f], sig, self.starts[f], length)
                     for f in range(sig.n_folds)]
        except ValueError as err:
            return WindowedSimulation.failed(
                np.concatenate(self.starts), n=sig.t.size, length=length,
                reason=f"the model cannot be re-simulated on this record ({err})")
        return WindowedSimulation.merge(parts, n=sig.t.size, length=length)


@dataclass(frozen=True, kw_only=True, eq=False)
class _Extension:
    """The named terms refitted together on all data (the baseline itself for none)."""

    fit: "IdentificationResult | None"
    """The CasADi refit, or None (nothing named, nothing to fit, or IPOPT refused)."""
    theta: np.ndarray
    """The coefficients: the baseline's (fit mode), then each named term's."""
    model: JointModel
    """The extended model."""


def _extension(setup: _Setup, sel: Selection) -> _Extension:
    """The named terms refitted together on all data with CasADi (the bounded
    least-squares solution where IPOPT refuses: rank)."""
    base, problem = setup.base, setup.problem
    if not sel.selected:
        return _Extension(fit=None, theta=base.theta if base.fit_mode else np.zeros(0),
                          model=base.fitted)
    comp = compose([s.variant for s in sel.selected])
    params = tuple(p for s in sel.selected for p in s.cause.params)
    try:
        refit = casadi_refit(problem, comp, params)
    except ValueError:  # IPOPT refused (rank): keep the bounded least-squares solution
        refit = None
    theta = (refit.estimates.copy() if refit is not None
             else full_fit(problem, [sel.selected[-1].variant],
                           tuple(s.variant for s in sel.selected[:-1])).theta)
    parts = [(s.cause, s.variant.h) for s in sel.selected]
    return _Extension(fit=refit, theta=theta, model=base.model(parts, theta))


def _vanished(sel: Selection, ext: _Extension) -> dict:
    """The named causes whose term vanishes from the extended model (``name -> reason``):
    every coefficient of the cause held at a bound of 0 when the named terms are refitted
    together on all data.  A cause named at one step can be taken over by one named later
    (a spring at the grid's lowest frequency decouples the load and reads as less inertia:
    a nominal inertia error was named ``compliance`` + ``inertia``, the spring refitted to 0
    beside the inertia, and the record called explained); the final model then lacks what
    the cause names, so the selection is run again without it."""
    if ext.fit is None:  # no refit (IPOPT refused: rank): the bounded fit keeps every term
        return {}
    at, est = dict(zip(ext.fit.names, ext.fit.at_bound)), dict(zip(ext.fit.names,
                                                                    ext.fit.estimates))
    out = {}
    for k, s in enumerate(sel.selected):
        params = s.cause.params
        if params and all(at.get(p, False) and est.get(p) == 0.0 for p in params):
            later = [x.cause.name for x in sel.selected[k + 1:]] or ["the baseline"]
            out[s.cause.name] = (
                f"tried, rejected: named at step {k + 1}, its term vanished when the causes "
                f"named were refitted together on all data ({', '.join(params)} at the bound "
                f"0): {', '.join(later)} take{'s' if len(later) == 1 else ''} what it "
                f"removed, so the selection was run again without it")
    return out


def _other_shape(setup: _Setup, sel: Selection) -> float:
    """Held-out share of the final model's residual that a friction law of another shape
    removes (:func:`~fricctl.diagnose.selection.speed_curve` after the causes named) [-]."""
    curve = speed_curve(setup.problem, setup.base, sel.selected)
    before = float(np.sum(sel.test))
    if curve.test is None or not (before > 0 and np.all(np.isfinite(curve.test))):
        return math.nan
    return max(0.0, 1.0 - float(np.sum(curve.test)) / before)


def _diagnosis(run: Run, model: JointModel | None, setup: _Setup, sel: Selection,
               ext: _Extension, chain_rms: float,
               motor_revolution: float | None = None) -> Diagnosis:
    """The result: models with their provenance, held-out gain, evidence and report data;
    ``chain_rms`` is the measuring chain's floor (:meth:`_ChainShares.floor_rms`)."""
    sig, base = setup.sig, setup.base
    gain = _gain(sig, sel)
    bodies = _evidence_bodies(base, sel.selected, ext.theta, ext.model, motor_revolution)
    named = tuple(s.cause.name for s in sel.selected) or (causes.NONE,)
    baseline_model = _record_fields(base.fitted if setup.ident is None
                                    else _identified(setup.ident.result, run), run, sig, model)
    # with terms removed to be judged, what changed is told against the model as supplied
    # (a removed offset the record does not support is marked "diagnosed" at 0, not left
    # with the supplied value's provenance)
    supplied = None if not setup.held else _record_fields(model, run, sig, model)
    unmeasured = tuple(c for c in setup.held if c not in named and _unmeasured(c, sel))
    unsupported = tuple(c for c in setup.held if c not in named and c not in unmeasured)
    extended = (baseline_model if not sel.selected and not setup.held else
                _diagnosed(_record_fields(ext.model, run, sig, model),
                           supplied or baseline_model, named, unsupported, unmeasured))
    residual_after = _sliding_residual(extended, sig)
    no_floor = "" if math.isfinite(chain_rms) else NO_FLOOR
    said = verdict(gain.torque_rms_after, chain_rms, residual_after,
                   {"position": sig.q, "velocity": sig.w, "time": sig.t, "torque": sig.tm},
                   other_shape=lambda: _other_shape(setup, sel),
                   no_floor=no_floor,
                   caution=_simulation_caution(setup, sel, baseline_model, extended,
                                               lambda r: _record_fields(_identified(r, run),
                                                                        run, sig, model)))
    stops = setup.stops
    if stops.found:  # what the diagnosis left out, said with the stops
        stops = replace(stops, description=(
            f"{stops.description}; {setup.dropped} of {setup.dropped + setup.grid.starts.size} "
            f"re-simulation windows held or followed a contact and were dropped, and the "
            f"measuring chain's floor is "
            f"measured without the contacts too"))
    held = _held_text(setup.held, model, named, sel)
    return Diagnosis(cause=named[0], causes=named, steps=sel.steps, ranking=sel.first_ranking,
                     evidence=evidence_text(sel.steps, bodies, sel.first_ranking, gain,
                                            sel.not_identifiable, sig.units, said,
                                            stops.description if stops.found else "") + held,
                     held=setup.held, supplied=model,
                     baseline=baseline_model, extended=extended, gain=gain,
                     simulation_scores=sel.simulation_scores,
                     fit=ext.fit or (setup.ident.result if setup.ident else setup.fit0), t=sig.t,
                     torque=sig.tm, position=sig.q, velocity=sig.w,
                     residual_before=_sliding_residual(baseline_model, sig),
                     residual_after=residual_after, sim_before=sel.sim_before,
                     sim_after=sel.sim_after, nominal=model is not None, units=sig.units,
                     not_identifiable=dict(sel.not_identifiable), last_ranking=sel.last_ranking,
                     chain_rms=chain_rms, verdict=said,
                     cutoff=sig.cutoff, end_stops=stops,
                     notes={**_notes(sel), **_ranking_notes(sel), **(dict.fromkeys(
                         ("chain_rms", "verdict", "residual_over_floor"), no_floor)
                         if no_floor else {})})


def _below_notes(below: tuple) -> dict:
    """Why a number of a below-line entry is undefined (``notes``, by its JSON path)."""
    notes = {}
    for i, e in enumerate(below):
        if e.reason == CHAIN_UNMEASURED:  # the twin ran away: no net share, no test
            for key in ("chain", "score", "p_value"):
                notes[f"below_line[{i}].{key}"] = CHAIN_UNMEASURED
        elif not math.isfinite(e.chain):
            notes[f"below_line[{i}].chain"] = ("not measured: the gross share fails the test "
                                               "already (the net share can only be smaller)")
        if not math.isfinite(e.simulation_score):
            notes[f"below_line[{i}].simulation_score"] = (
                "not computed: the term is not supported" if not e.supported else
                "the held-out windows cannot be re-simulated with the term")
    return notes


def _ranking_notes(sel: Selection) -> dict:
    """Why a ranking's net score is undefined (``notes``, by its JSON path): the candidate's
    chain share could not be measured (NaN in the ranking, :data:`CHAIN_UNMEASURED`)."""
    rankings = [("ranking", sel.first_ranking), ("last_ranking", sel.last_ranking)]
    rankings += [(f"steps[{k}].ranking", st.ranking) for k, st in enumerate(sel.steps)]
    return {f"{where}[{i}].score": CHAIN_UNMEASURED for where, ranking in rankings
            for i, (_, score) in enumerate(ranking) if not math.isfinite(score)}


def _unmeasured(name: str, sel: Selection) -> bool:
    """Whether the candidate ``name`` was last scored with no net share: its chain share
    could not be measured (:data:`CHAIN_UNMEASURED`), so the record is not said to support
    it or not."""
    scored = sel.last_scored.get(name)
    return ((scored is not None and scored.unmeasured)
            or sel.not_identifiable.get(name) == CHAIN_UNMEASURED)


def _held_text(held: tuple, model: JointModel | None, named: tuple, sel: Selection) -> str:
    """What became of each effect the supplied model held: named again by the record (held
    and supported), or not (held, not supported: with the score it reached), or with no net
    share to judge it by (its chain share could not be measured: :data:`CHAIN_UNMEASURED`)."""
    if not held:
        return ""
    pm = model.parameters()
    last = dict(sel.last_ranking)
    out = []
    for name in held:
        core = causes.get(name).remove(model).parameters()
        what = ", ".join(f"{k} {pm.get(k, 0.0):.4g}" for k in sorted(set(pm) | set(core))
                         if pm.get(k, 0.0) != core.get(k, 0.0))
        if name in named:
            out.append(f" {name}: held by the supplied model ({what}); removed to be judged, "
                       f"the record supports it (named above, its term refitted)")
        elif _unmeasured(name, sel):  # no net share: neither supported nor not, as measured
            why = ("its measuring chain's share cannot be measured, above"  # said once
                   if sel.not_identifiable.get(name) == CHAIN_UNMEASURED else CHAIN_UNMEASURED)
            out.append(f" {name}: held by the supplied model ({what}); removed to be judged, "
                       f"it has no net share ({why}); whether the record supports it is not "
                       f"known, and it is left out of the extended model")
        else:
            score = last.get(name)
            at = "" if score is None else f" (it removes {100 * score:.1f} % of what is left, net)"
            out.append(f" {name}: held by the supplied model ({what}); removed to be judged, "
                       f"the record does not support it{at}: left out of the extended model")
    return "".join(s + "." for s in out)


def _gain(sig: Signals, sel: Selection) -> Gain:
    """Held-out torque and simulation RMS errors of the baseline and the extended model."""
    nmov = int(sig.moving.sum())
    before, after = sel.sim_before.rms(), sel.sim_after.rms()
    return Gain(torque_rms_before=math.sqrt(float(np.sum(sel.baseline_test)) / nmov),
                torque_rms_after=math.sqrt(float(np.sum(sel.test)) / nmov),
                simulation_rms_before=before.position, velocity_rms_before=before.velocity,
                simulation_rms_after=after.position, velocity_rms_after=after.velocity)


def _provenance_key(name: str) -> str:
    return f"friction.{name}" if name in FRICTION_FIELDS else name


def _record_fields(m: JointModel, run: Run, sig: Signals, nominal: JointModel | None) -> JointModel:
    """``m`` with the sample time and encoder count of the nominal model, else of the record
    (provenance "measured"), and in fit mode the baseline's values marked "identified"."""
    prov = dict(m.provenance)
    where = run.source or f"the record ({run.n_samples} samples)"
    ts, res = m.sample_time, m.encoder_resolution
    if ts is None:
        ts = sig.ts
        prov["sample_time"] = Provenance(source="measured", note=f"sample time of {where}")
    if res is None:
        res = run.encoder_grid()
        if res is not None:
            prov["encoder_resolution"] = Provenance(
                source="measured", note=f"the grid the positions of {where} lie on")
    if nominal is None:
        for name in m.parameters():
            key = _provenance_key(name)
            if key not in prov:
                prov[key] = Provenance(source="identified",
                                       note="rigid baseline fitted by fricctl diagnose "
                                            "(inverse-dynamics least squares)")
    return replace(m, sample_time=ts, encoder_resolution=res, provenance=prov)


def _simulation_caution(setup: _Setup, sel: Selection, baseline: JointModel,
                        extended: JointModel, rigid: Callable) -> str:
    """Why the causes named are not confirmed, or ``""``: where ``fricctl identify``'s rigid
    fit of the record refined by simulation error (DIDIM) re-simulates the record's windows
    better than the extended model, both fitted on all data.  That fit is the baseline
    reported (``baseline``), or, where DIDIM does not identify a parameter the equation error
    does and the equation error is reported, DIDIM's own fit (``rigid`` of its result makes
    the model): a rigid model that follows the record better by simulation still says so
    (without it, audit B's false backlash below would be "explained" again).

    The selection starts from the least-squares (equation error) baseline, fits every term on
    the equation error and names what re-simulates the held-out windows better than *that*
    baseline.  Where the equation error is biased (errors in variables: a coarse encoder on a
    record at nearly one speed), a term can take up the bias: audit B's rigid Coulomb-viscous
    joint tracking a triangle (4096 counts) was named ``backlash`` at 0.70 times the floor while
    the simulation-error baseline re-simulated its windows 6.6 times better than the extended
    model.  The comparison does not tell that case from a true cause whose equation-error fit
    re-simulates worse than a rigid simulation-error fit: review R10 found it on every true
    backlash of the package's generator (31 of 31, 1.3-5.5 times worse) and on 11 of 28 true
    compliances (1.01-1.4), all of them above twice the floor (not explained either way); a
    time delay, a ripple, a Stribeck hump, a drag re-simulated 3-80 times better than that
    baseline.  So it is said, as what was measured, and keeps the record from being called
    explained; it never rejects a cause."""
    if not sel.selected or setup.ident is None or setup.ident.refined is None:
        return ""  # no simulation-error fit to compare with (the record was not replayed)
    grid = setup.grid
    if grid.starts.size == 0:
        return ""
    ident, lost = setup.ident, ""
    if ident.result.method != "DIDIM":  # the equation error reported: DIDIM lost a parameter
        gone = [n for n, a, b in zip(ident.start.names, ident.start.identified,
                                     ident.refined.identified) if a and not b]
        which = ", ".join(gone) or "a parameter the equation error identifies"
        lost = (f"; it does not identify {which} on this record, so the equation error is the "
                f"baseline reported")
    try:
        if lost:
            baseline = rigid(ident.refined)
        b = simulate_windows(baseline, setup.sig, grid.starts, grid.length).rms().position
        e = simulate_windows(extended, setup.sig, grid.starts, grid.length).rms().position
    except ValueError:  # a model that cannot be made or re-simulated: the gain's numbers
        return ""       # say it
    if not (math.isfinite(b) and math.isfinite(e) and e > b):
        return ""
    one = len(sel.selected) == 1
    what = (f"the cause named ({sel.selected[0].cause.name}) is" if one else
            f"the causes named ({', '.join(x.cause.name for x in sel.selected)}) are")
    verb, they = ("is", "it") if one else ("are", "they")
    return (f"the rigid {'fit' if lost else 'baseline'} fricctl identify fits to the record "
            f"by simulation error (DIDIM{lost}) re-simulates its windows better than the "
            f"extended model (position RMS "
            f"{b:.3g} against {e:.3g} {unit_labels(setup.sig.units).position}, all windows, both "
            f"fitted on all data): {what} fitted on the equation error and {verb} not "
            f"confirmed by the simulation error; {they} may be the joint's and simulate poorly "
            f"as fitted, or take up a bias of the equation error (errors in variables: a coarse "
            f"encoder, a record at nearly one speed)")


def _identified(r, run: Run) -> JointModel:
    """The rigid model of one of ``fricctl identify``'s fits of the record (its result: the
    reported baseline, or DIDIM's)."""
    return JointModel.from_estimates(
        r.parameters, std=dict(zip(r.names, map(float, r.std))), units=run.units,
        source=f"fricctl diagnose: rigid baseline of {run.source or 'the record'}",
        note=f"rigid baseline fitted by fricctl diagnose as fricctl identify fits it "
             f"({r.method}: the record's torque replayed, from the equation error on its "
             f"signals)")


def _diagnosed(extended: JointModel, baseline: JointModel, named: tuple,
               removed: tuple = (), unmeasured: tuple = ()) -> JointModel:
    """``extended`` with provenance "diagnosed" on every value the diagnosis added or changed
    (the other values keep the baseline's provenance); ``removed``: the supplied model's
    effects removed to be judged that the record does not support; ``unmeasured``: those
    removed whose net share could not be measured (the twin ran away: not known to be
    supported or not)."""
    pb, pe = baseline.parameters(), extended.parameters()
    prov = dict(baseline.provenance)
    prov.update({k: extended.provenance[k] for k in ("sample_time", "encoder_resolution")
                 if k in extended.provenance})
    note = "fricctl diagnose: " + " + ".join(named) + (
        f" ({', '.join(removed)} of the supplied model removed: not supported by the record)"
        if removed else "") + (
        f" ({', '.join(unmeasured)} of the supplied model removed: no net share, the "
        f"effect-free twin that measures the chain's share ran away)" if unmeasured else "")
    for name in set(pb) | set(pe):
        if pb.get(name, 0.0) != pe.get(name, 0.0):
            prov[_provenance_key(name)] = Provenance(source="diagnosed", note=note)
    source = (extended.source + "; " if extended.source else "") + note
    return replace(extended, provenance=prov,
                   source=(source if named != (causes.NONE,) or removed or unmeasured
                           else extended.source))


def _twin(base: Baseline, floor: float | None = None, model: JointModel | None = None, *,
          still=None):
    """The record's effect-free twin; a model that cannot make one (it does not move on the
    recorded torque, or cannot be simulated) is refused naming the model."""
    try:
        return effect_free_twin(base, floor, model=model, still=still)
    except ValueError as err:
        what = "model" if base.nominal is not None else "the fitted baseline"
        raise ValueError(f"{what}: its effect-free twin (the model driven by the recorded "
                         f"torque) cannot be made: {err}") from None


#: Why a diagnosis has no floor (its text, its verdict's reason, the JSON's ``undefined``).
NO_FLOOR = ("the effect-free twin that measures the floor ran away (its torque reached the bound "
            "of its simulation): it does not follow the record, so no floor")


def _notes(sel) -> dict:
    """Why numbers of the result are undefined: a model that could not be re-simulated."""
    notes = {}
    if sel.sim_before.failure or sel.sim_after.failure:
        notes["gain"] = sel.sim_after.failure or sel.sim_before.failure
    for i, st in enumerate(sel.steps):
        for key in ("simulation_rms_before", "simulation_rms_after"):
            if not math.isfinite(getattr(st, key)):
                notes[f"steps[{i}].{key}"] = (sel.sim_after.failure or "the model of this step cannot be "
                                              "re-simulated on this record")
    return notes


class _ProgressBar:
    """A tqdm bar on stderr over the candidates of each step (nothing when not shown)."""

    def __init__(self, show: bool, n_samples: int):
        self.bar = None
        if show:
            from tqdm import tqdm

            self.bar = tqdm(total=None, file=sys.stderr, unit="candidate", leave=False,
                            desc=f"diagnose ({n_samples} samples)")

    def step(self, step: int, done: int, total: int) -> None:
        """Candidate ``done`` of ``total`` of selection step ``step`` (1, 2, ...) is scored."""
        if self.bar is None:
            return
        if done == 0:
            self.bar.reset(total=total)
            self.bar.set_description(f"diagnose: step {step}, scoring the candidates")
        else:
            self.bar.update(1)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def _evidence_bodies(base: Baseline, selected: tuple, theta: np.ndarray,
                     extended: JointModel, motor_revolution: float | None = None) -> tuple:
    """Each named cause's evidence clause, from its slice of the joint fit; a period in
    position it fits also in motor revolutions where ``motor_revolution`` is known."""
    out = []
    k = 3 if base.fit_mode else 0
    values = extended.parameters()
    for s in selected:
        coef = theta[k:k + s.cause.n_extra]
        k += s.cause.n_extra
        body = s.cause.evidence(base, Term(h=s.variant.h, coef=coef), extended)
        if motor_revolution is not None:
            body += "".join(f"; its period is {values[c] / motor_revolution:#.3g} motor "
                            f"revolutions (one revolution: "
                            f"{_length(motor_revolution, base.labels.position)})"
                            for c in PERIOD_PARAMETERS if c in s.cause.changes and c in values)
        out.append(body)
    return tuple(out)


def _sliding_residual(model: JointModel, sig: Signals) -> np.ndarray:
    return np.where(sig.moving, predict(model, sig).residual, np.nan)


# ============================================================================ transfer
@dataclass(frozen=True, kw_only=True, eq=False)
class TorqueResidual:
    """Equation-error residual of a model on a record (:func:`torque_residual`)."""

    residual: np.ndarray
    """``LP(Tm received) - LP(model torque along the measured motion)`` per sample [N*m]."""
    mask: np.ndarray
    """True where the joint slides (where the residual is meaningful)."""

    def rms(self) -> float:
        """RMS of the residual over the sliding samples [N*m]."""
        return float(np.sqrt(np.mean(self.residual[self.mask] ** 2)))


def torque_residual(model: JointModel, run: Run) -> TorqueResidual:
    """Equation-error residual of ``model`` on ``run`` and the mask of sliding samples.

    ``residual = LP(Tm received) - LP(model torque along the measured motion)`` [N*m];
    meaningful where ``mask`` is true (the joint slides, clear of any contact with an end
    stop, as :func:`diagnose` reads the record).
    """
    v.instance("model", model, JointModel)
    sig, _ = signals_clear_of_stops(_check_run(run))
    return TorqueResidual(residual=predict(model, sig).residual, mask=sig.moving)


@dataclass(frozen=True, kw_only=True)
class PredictionErrors:
    """How well a model predicts a record it was not fitted on (:func:`prediction_errors`)."""

    torque_rms: float
    """Equation error on the sliding samples [N*m]."""
    simulation_rms: float
    """Windowed re-simulation, position error [rad]."""
    velocity_rms: float
    """Windowed re-simulation, velocity error [rad/s]."""
    windows: int = 0
    """Re-simulation windows the two simulation errors are measured over [-]."""
    windows_dropped: int = 0
    """Windows left out for holding (or following within the filter's reach) a contact with an
    end stop [-]; 0 on a record without stops."""


def prediction_errors(model: JointModel, run: Run, *, window: float = 0.5) -> PredictionErrors:
    """How well ``model`` predicts another record (no refit): RMS errors (contacts with end
    stops left out, as :func:`diagnose` leaves them out).

    Returns
    -------
    PredictionErrors
    """
    _check_run(run)
    v.instance("model", model, JointModel)
    window = v.real("window", window, positive=True, unit="s")
    sig, stops = signals_clear_of_stops(run)
    r = predict(model, sig).residual[sig.moving]
    whole = window_grid(sig, window)
    grid = clear_of_stops(whole, stops, sig)
    rms = simulate_windows(model, sig, grid.starts, grid.length).rms()
    return PredictionErrors(torque_rms=float(np.sqrt(np.mean(r ** 2))),
                            simulation_rms=rms.position, velocity_rms=rms.velocity,
                            windows=int(grid.starts.size),
                            windows_dropped=int(whole.starts.size - grid.starts.size))
