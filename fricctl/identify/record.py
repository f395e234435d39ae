r"""One identification of a record, for ``fricctl identify`` and every diagnosis.

:func:`identify_record` is the default of ``fricctl identify`` and the baseline of
:func:`fricctl.diagnose.diagnose`: the same code, the same numbers.  Every choice it makes
is read off the record, never off a bench's magnitudes:

1. **Equation error on the record's own signals** (:func:`equation_error`): the low-pass
   cut-off is the band the motion reaches above the encoder's quantisation
   (:func:`~fricctl.identify.signals.motion_band`), the torque and every column filtered
   alike, samples at rest left out, the sign of the motion from the encoder (fractional
   at reversals).  This is IDIM-LS with a record-driven filter.  It regresses on a twice
   differentiated, quantised position, so where the encoder step is coarse against the
   motion per sample its inertia is biased toward zero (errors in variables: -46 % on a
   seeded 1 kHz, 500-count closed-loop record of the package's generator).
2. **DIDIM refinement** (:func:`~fricctl.identify.didim`, Gautier, Janot & Vandanjon
   2013) from that start: the record's torque replayed on the rigid joint with the
   parameters and the position error minimised.  No derivative of the encoder enters, so
   the bias of step 1 cannot arise; and the record's controller is not needed (a closed
   loop's torque is what the joint received: the replay needs no model of the controller's
   timing, which a closed-loop simulation would -- 2 % on the EMPS mass).
3. **Honest uncertainty**: every std from the residual summed over blocks longer than its
   correlation (:mod:`~fricctl.identify.uncertainty`), and, with the validation, the
   delete-a-block jackknife's where it is larger (a replayed position error can be
   correlated over a good part of the record, and the block covariance then underestimates).
4. **Validation on held-out blocks**: the record is cut into :data:`JACKKNIFE_BLOCKS`
   blocks; each is deleted in turn, the rest identified (steps 1-2, the pieces replayed
   together) and the deleted block replayed with that estimate (:func:`validate`); the
   held-out simulation fit and the held-out equation-error fit are reported (the EMPS
   authors validate the same way on a second record), and the spread of the four
   estimates is the jackknife's std.
5. **The reported estimate** is DIDIM's (consistent) whenever the record can be replayed,
   else the equation error's.  The two are compared: when they disagree beyond
   :data:`DISAGREEMENT_SIGMAS` combined standard errors the user is told (the equation
   error is biased by the encoder's quantisation, or the record holds an effect the model
   lacks).  A Hausman-style choice -- the equation error when the two agree, being the more
   precise -- was tried and dropped: on 500 Hz / 2000-count records the equation error's
   inertia was 5 of its stds off while the test, dominated by DIDIM's larger std, passed it.
6. **Warnings** (one sentence each, also in the JSON and marked in a model file's
   provenance): the estimators disagree, a parameter not identified (std above its value,
   or held at a bound), the inertia poorly excited, a poor held-out simulation fit, the
   refinement impossible (a record that cannot be replayed keeps the equation error),
   standard errors that are lower bounds (a residual correlated over more than a
   twentieth of the record, when no jackknife was run).

Notes
-----
Linear models only (:data:`~fricctl.identify.LINEAR_MODELS`); the Stribeck curve is
``fricctl identify --recipe plain --model stribeck``.
"""

from __future__ import annotations

import math
import os
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field, replace

import numpy as np

from .. import _validate as v
from ..datasets import Run
from .didim import didim
from .idim import IdimRecipe
from .least_squares import IdentificationResult, fit_least_squares, linear_prediction
from .models import LINEAR_MODELS, MODELS, check_directions, lower_bounds, model_names
from .signals import Signals, estimate_signals
from .simulation import RecordLoop, initial_velocity, simulate_record
from .stops import EndStops, end_stops
from .uncertainty import block_covariance

__all__ = ["identify_record", "equation_error", "record_columns", "validate", "held_out_halves",
           "held_out_warnings",
           "RecordIdentification", "Validation", "DISAGREEMENT_SIGMAS", "POOR_FIT_PERCENT",
           "POOR_INERTIA_RELATIVE_STD", "JACKKNIFE_BLOCKS"]

#: Two estimates of one parameter disagree when they differ by more than this many combined
#: standard errors [-].
DISAGREEMENT_SIGMAS = 3.0
#: A held-out simulation fit below this is reported as poor [%].
POOR_FIT_PERCENT = 80.0
#: An inertia whose relative standard error exceeds this is poorly excited [%].
POOR_INERTIA_RELATIVE_STD = 5.0


def record_columns(sig: Signals, model: str, offset: bool | None = None) -> np.ndarray:
    """The equation error's observation matrix on the record's signals (every sample; the
    fit keeps ``sig.moving``), columns in :func:`~fricctl.identify.model_names` order.

    ``inertia``: the acceleration of the filtered position; every friction column the
    low-pass of its term with samples at rest zeroed (:meth:`Signals.filt`), the sign of
    the motion the encoder's (fractional at reversals)."""
    if v.choice("model", model, MODELS) not in LINEAR_MODELS:
        raise ValueError(f"model: the record's equation error needs a linear model "
                         f"({', '.join(LINEAR_MODELS)}), not {model!r}")
    s, w = sig.seff, sig.w
    raw = {"viscous": w, "coulomb": s,
           "viscous_pos": np.where(s > 0, w, 0.0), "viscous_neg": np.where(s < 0, w, 0.0),
           "coulomb_pos": np.maximum(s, 0.0), "coulomb_neg": np.minimum(s, 0.0),
           "offset": np.ones_like(w)}
    cols = [sig.a if nm == "inertia" else sig.filt(raw[nm]) for nm in model_names(model, offset)]
    return np.column_stack(cols)


def equation_error(sig: Signals, model: str = "coulomb_viscous",
                   offset: bool | None = None) -> IdentificationResult:
    """The equation-error (IDIM-LS) fit on the record's own signals, CasADi least squares.

    ``LP(Tm) = X theta`` on the sliding samples (``sig.moving``), magnitudes bounded below
    by 0, standard errors by :func:`~fricctl.identify.uncertainty.block_covariance` (the
    filtered residual is coloured).  ``sig`` may be a sequence of :class:`Signals` (the
    segments of a record with gaps): their rows are fitted together.
    """
    sigs = [sig] if isinstance(sig, Signals) else list(sig)
    for i, s_ in enumerate(sigs):
        v.instance(f"sig[{i}]", s_, Signals, "the record's Signals (fricctl.identify.signals)")
    names = model_names(model, offset)
    # the columns are low-passed with the samples at rest zeroed, so on a one-way record the
    # sign's column differs from the constant's only by the filter's smear at the record's
    # edges (1e-6): far from the rank test, and the fit "separates" Coulomb and offset
    need = int(math.ceil(2.0 / (sigs[0].cutoff * sigs[0].ts)))
    check_directions(names, sum(int(np.sum(s_.moving & (s_.seff > 0))) for s_ in sigs),
                     sum(int(np.sum(s_.moving & (s_.seff < 0))) for s_ in sigs), need,
                     f"two periods of its {sigs[0].cutoff:.3g} Hz low-pass, the filter's reach")
    X = np.vstack([record_columns(s_, model, offset)[s_.moving] for s_ in sigs])
    y = np.concatenate([s_.torque_target(0)[s_.moving] for s_ in sigs])
    scale = (np.linalg.norm(y) or 1.0) / np.maximum(np.linalg.norm(X, axis=0), 1e-300)
    res = fit_least_squares(linear_prediction, X, y, names=names, initial=np.zeros(len(names)),
                            lower=lower_bounds(names), scale=scale, model=model,
                            units=sigs[0].units)
    free = ~res.at_bound
    std = np.zeros(len(names))
    if np.any(free):  # a parameter held at a bound has no std of its own
        std[free] = block_covariance(X[:, free], res.residual).std
    return replace(res, std=std, method="IDIM-LS")


@dataclass(frozen=True, kw_only=True, eq=False)
class Validation:
    """An estimate checked on a record it was not fitted to (:func:`validate`): the record's
    torque replayed (position) and its equation error (torque).  The held-out validation of
    :func:`identify_record` is two of them, each half with the other half's estimate."""

    simulation_fit: float
    """Simulation fit of the position (the record's torque replayed) [%]
    (``100 (1 - ||y - y_sim|| / ||y - mean y||)``, each half's mean removed)."""
    equation_fit: float
    """Equation-error fit of the low-passed torque on the sliding samples [%]."""
    t: np.ndarray
    """Instants of the compared position [s] (NaN-separated halves)."""
    measured: np.ndarray
    """The measured position, its mean removed per half [rad] (or [m])."""
    simulated: np.ndarray
    """The position replayed with the estimate, mean removed [rad] (or [m])."""
    torque_t: np.ndarray
    """Instants of the equation-error comparison (sliding samples) [s]."""
    torque_measured: np.ndarray
    """Low-passed measured torque [N*m] or [N]."""
    torque_predicted: np.ndarray
    """Low-passed torque the estimate predicts."""
    failure: str = ""
    """Why the validation could not be run, or ``""``."""

    def as_dict(self) -> dict:
        """``{simulation_fit_percent, equation_fit_percent, failure}``."""
        def num(x):
            return None if not math.isfinite(x) else float(x)
        return {"simulation_fit_percent": num(self.simulation_fit),
                "equation_fit_percent": num(self.equation_fit), "failure": self.failure or None}


@dataclass(frozen=True, kw_only=True, eq=False)
class RecordIdentification:
    """What :func:`identify_record` found: the estimate, how, and how far to trust it."""

    result: IdentificationResult
    """The reported estimate (step 5's choice); its ``warnings`` are :attr:`warnings`."""
    start: IdentificationResult
    """The equation-error fit on the record's signals (step 1)."""
    refined: IdentificationResult | None
    """The DIDIM refinement, or None (the record cannot be replayed, or none was asked)."""
    cutoff: float = field(metadata={"unit": "Hz"})
    """The record's low-pass cut-off [Hz]."""
    held_out: Validation | None
    """Validation on held-out blocks (each with the estimate of the other blocks), or None
    when not asked."""
    notes: tuple = ()
    """How the reported standard errors were obtained, beyond the block covariance, and
    what of the record was left out (an end stop's contacts)."""
    end_stops: EndStops | None = None
    """The record's end stops (:func:`~fricctl.identify.stops.end_stops`): their contacts
    are out of the equation error, and the replay runs only the segments clear of them."""

    @property
    def warnings(self) -> tuple:
        """What the identification cannot vouch for, one sentence each."""
        return self.result.warnings

    @property
    def parameters(self) -> dict:
        """Name -> reported estimate."""
        return self.result.parameters

    def as_dict(self) -> dict:
        """The reported result's JSON (:meth:`IdentificationResult.as_dict`) with
        ``equation_error`` and ``didim`` (each estimator's values and stds, ``didim`` null
        when not run), ``cutoff_hz`` and ``held_out``."""
        out = self.result.as_dict()
        out["equation_error"] = {n: {"value": float(x), "std": float(s)} for n, x, s in
                                 zip(self.start.names, self.start.estimates, self.start.std)}
        out["didim"] = None if self.refined is None else {
            n: {"value": float(x), "std": float(s)} for n, x, s in
            zip(self.refined.names, self.refined.estimates, self.refined.std)}
        out["cutoff_hz"] = self.cutoff
        out["std_notes"] = list(self.notes)
        out["end_stops"] = None if self.end_stops is None else self.end_stops.as_dict()
        out["held_out"] = None if self.held_out is None else self.held_out.as_dict()
        return out

    def report(self) -> str:
        """The reported estimate's table, the equation error beside it, the held-out fits."""
        lines = [self.result.report()]
        for label, r in (("Equation error (IDIM-LS)", self.start), ("Simulation error (DIDIM)",
                                                                     self.refined)):
            if r is not None:
                lines.append(f"{label}: " + ", ".join(
                    f"{n} {x:.6g} +- {s:.2g}" for n, x, s in zip(r.names, r.estimates, r.std)))
        lines += [f"Note: {n}" for n in self.notes]
        if self.held_out is not None:
            h = self.held_out
            lines.append(h.failure and f"Held-out validation: {h.failure}" or
                         f"Held-out blocks: simulation fit (position) {h.simulation_fit:.2f} %, "
                         f"equation-error fit {h.equation_fit:.2f} %")
        return "\n".join(lines)


def _didim_recipe(sig: Signals) -> IdimRecipe:
    """The start-up velocity estimate of the replay at the record's cut-off."""
    border = max(int(math.ceil(2.0 / (sig.cutoff * sig.ts))), 10)
    return IdimRecipe(cutoff=sig.cutoff, border=border)


@dataclass(frozen=True, kw_only=True, eq=False)
class _Fit:
    cutoff: float
    start: IdentificationResult
    refined: IdentificationResult | None
    why_not: str
    """Why there is no refinement (``""`` when there is, or none was asked)."""

    @property
    def lost(self) -> tuple:
        """The parameters the equation error identifies and DIDIM does not (at a bound, or a
        std as large as the value): a replay the model cannot follow (an effect it lacks,
        a stop the detector missed) drove the refinement off."""
        if self.refined is None:
            return ()
        return tuple(n for n, a, b in zip(self.start.names, self.start.identified,
                                          self.refined.identified) if a and not b)

    @property
    def chosen(self) -> IdentificationResult:
        """DIDIM when it ran (consistent) and identified what the equation error does, else
        the equation error."""
        return self.start if self.refined is None or self.lost else self.refined

    @property
    def apart(self) -> tuple:
        """Per parameter on which the two estimators disagree: (name, equation error,
        DIDIM, combined standard errors)."""
        if self.refined is None:
            return ()
        return tuple((n, a, b, math.hypot(sa, sb)) for n, a, sa, b, sb in zip(
            self.start.names, self.start.estimates, self.start.std, self.refined.estimates,
            self.refined.std) if abs(a - b) > DISAGREEMENT_SIGMAS * math.hypot(sa, sb))


def _fit(segments, model: str, offset, refine: bool, cutoff: float | None = None,
         masks=None, start: IdentificationResult | None = None) -> _Fit:
    """Steps 1 and 2 on the segments of one record (one segment, or the pieces left by a
    deleted block, read through the whole record's filter ``cutoff``).  A jackknife fit
    starts from its own equation error, never from the whole record's optimum: started
    there, the stick-slip roughness of the simulation error keeps it close by and the
    jackknife's spread shrinks (the truth 5 stds off on a 500 Hz / 2000-count record).

    ``masks`` (per segment, bool per sample, or None) are an end stop's contacts: left out
    of the equation error (with the filter's reach) and of the replay, which runs the
    stretches between them (a rigid replay cannot pass a stop).  ``start``: the equation
    error of the one segment, when the caller has fitted it (checked against its signals'
    sliding samples)."""
    masks = [None] * len(segments) if masks is None else list(masks)
    sigs = [estimate_signals(r, 1, cutoff=cutoff, exclude=m) for r, m in zip(segments, masks)]
    cutoff = sigs[0].cutoff
    if start is None:
        start = equation_error(sigs, model, offset)
    else:
        _check_start(start, sigs, model, offset)
    refined, why = None, ""
    if refine:
        recipe = _didim_recipe(sigs[0])
        replayed = [p for r, m in zip(segments, masks) for p in _clear_pieces(r, m, recipe)]
        try:
            if not replayed:
                raise ValueError(f"no stretch of {_min_piece(recipe)} samples clear of the end "
                                 f"stops' contacts to replay")
            refined = didim(replayed[0], model=model, offset=offset, loop=_REPLAY,
                            output="position", recipe=recipe,
                            start=start, also=tuple(replayed[1:]))
        except ValueError as err:
            why = str(err)
    return _Fit(cutoff=cutoff, start=start, refined=refined, why_not=why)


def _check_start(start, sigs, model: str, offset) -> None:
    """Refuse a given equation error that is not of this model on these signals' sliding
    samples (another model, another record, or another exclusion of its contacts)."""
    v.instance("start", start, IdentificationResult, "the record's equation error "
               "(fricctl.identify.equation_error) or None")
    names = model_names(model, offset)
    if tuple(start.names) != names or start.method != "IDIM-LS":
        raise ValueError(f"start: a {start.method} fit of {tuple(start.names)}, not the equation "
                         f"error of {names}")
    n = sum(int(s_.moving.sum()) for s_ in sigs)
    if start.measured.size != n:
        raise ValueError(f"start: fitted on {start.measured.size} sliding samples, the record "
                         f"has {n}: the equation error of another record")


def _min_piece(recipe: IdimRecipe) -> int:
    """Fewest samples of a stretch between contacts that is replayed: four of the replay's
    start-up borders (its first velocity is a filtered estimate) [samples]."""
    return 4 * recipe.border


def _clear_pieces(run: Run, mask, recipe: IdimRecipe) -> list:
    """``run`` cut at the contacts of ``mask`` (None: ``run`` whole): the stretches clear of
    them, those of at least :func:`_min_piece` samples."""
    if mask is None or not np.any(mask):
        return [run]
    clear = np.concatenate([[False], ~np.asarray(mask, bool), [False]])
    edges = np.flatnonzero(np.diff(clear.astype(int)))
    return [_piece(run, int(a), int(b)) for a, b in zip(edges[::2], edges[1::2])
            if b - a >= _min_piece(recipe)]


#: The DIDIM of the default: the record's torque replayed (no controller model).
_REPLAY = RecordLoop(closed=False)
#: Blocks of the delete-a-block jackknife and of the held-out validation [-].
JACKKNIFE_BLOCKS = 4


def identify_record(run, *, model: str = "coulomb_viscous", offset: bool | None = None,
                    refine: bool = True, validate: bool = True,
                    stops: EndStops | None = None,
                    start: IdentificationResult | None = None) -> RecordIdentification:
    """Identify a record's rigid-joint model: equation error, DIDIM, validation, jackknife.

    Parameters
    ----------
    run : fricctl.datasets.Run
        Measured record (open or closed loop: its torque is replayed).
    model : {"coulomb_viscous", "asymmetric"}
        Linear friction model (:data:`~fricctl.identify.MODELS`).
    offset : bool, optional
        Include the constant offset (default: as in :data:`~fricctl.identify.MODELS`).
    refine : bool
        Refine the equation error by DIDIM (step 2; without, the equation error is reported).
    validate : bool
        Step 4: validate on held-out blocks and take the jackknife's std where it is the
        larger (:data:`JACKKNIFE_BLOCKS` more fits of three quarters of the record).
        Without, the estimates are the same and the std is the block covariance's alone
        (the diagnosis's baseline).
    stops : EndStops, optional
        The record's end stops, when already found (default:
        :func:`~fricctl.identify.stops.end_stops` of ``run``).  Their contacts are left out
        of the equation error, the replay (DIDIM and the validation) runs the stretches
        clear of them, and :attr:`RecordIdentification.notes` says so.
    start : IdentificationResult, optional
        The record's equation error (:func:`equation_error` of ``model`` and ``offset`` on
        its signals, the stops' contacts left out), when already fitted (``fricctl
        diagnose`` fits it for its own baseline): step 1 is not fitted again.  One of another
        model or with another number of sliding samples is refused.

    Returns
    -------
    RecordIdentification

    Examples
    --------
    >>> from fricctl import controllers as ctl, friction as fr
    >>> from fricctl.params import paper_actuator
    >>> from fricctl.simulate import simulate
    >>> p = paper_actuator()
    >>> run = simulate(p, ctl.open_loop(ctl.sinusoid(0.4, 0.5)), duration=10.0,
    ...                friction=fr.Viscous(p.viscous) + fr.Coulomb(p.coulomb)).to_run()
    >>> ident = identify_record(run, offset=False, validate=False)
    >>> abs(ident.parameters["inertia"] / p.total_inertia - 1) < 0.02
    True
    """
    v.instance("run", run, Run, "a fricctl.datasets.Run")
    v.choice("model", model, MODELS)
    refine = v.flag("refine", refine)
    validate = v.flag("validate", validate)
    if stops is None:
        stops = end_stops(run)
    else:
        v.instance("stops", stops, EndStops, "the record's EndStops (fricctl.identify.stops)")
        if stops.mask.shape != (run.n_samples,):
            raise ValueError(f"stops: a mask of {stops.mask.size} samples for a record of "
                             f"{run.n_samples}: the end stops of another record")
    mask = stops.mask if stops.found else None
    fit = _fit([run], model, offset, refine, masks=[mask], start=start)
    chosen = fit.chosen
    held, std, extra = None, chosen.std, []
    if stops.found:
        extra.append(f"{stops.description}; the replay runs the stretches between the "
                     f"contacts")
    if validate:
        held, jack = _folds(run, model, offset, refine, fit, mask)
        if jack is not None:
            std = np.maximum(chosen.std, jack)
            grown = [n for n, a, b in zip(chosen.names, chosen.std, jack) if b > a]
            if grown:
                extra.append("std from the delete-a-block jackknife (larger than the block "
                             "covariance's) for " + ", ".join(grown))
    warnings = [w for w in chosen.warnings if not ("lower bounds" in w and validate
                                                   and held is not None and not held.failure)]
    result = replace(chosen, std=std)
    warnings += _judge(fit, result, held)
    result = replace(result, warnings=tuple(dict.fromkeys(warnings)))
    return RecordIdentification(result=result, start=fit.start, refined=fit.refined,
                                cutoff=fit.cutoff, held_out=held, notes=tuple(extra),
                                end_stops=stops)


def _apart_text(name: str, equation: float, didim: float, std: float) -> str:
    """One parameter on which the two estimators disagree, for the warning: the gap in
    combined standard errors, or that neither estimator gave one (a parameter at a bound)."""
    gap = (f"{abs(equation - didim) / std:.1f} std" if std > 0
           else "neither estimator gives it a standard error")
    return f"{name} {equation:.4g} vs {didim:.4g} ({gap})"


def _judge(fit: _Fit, result: IdentificationResult, held) -> list:
    """The warnings of step 6."""
    out = []
    if fit.why_not:
        out.append(f"the record could not be replayed ({fit.why_not}): the equation error is "
                   f"reported, and it is biased toward zero inertia where the encoder step is "
                   f"coarse against the motion per sample")
    if fit.lost:
        out.append("the simulation error (DIDIM) does not identify " + ", ".join(fit.lost)
                   + " (at a bound, or a std as large as the value), which the equation error "
                     "identifies: the equation error is reported; the replay cannot follow the "
                     "record with this model (an effect it lacks: fricctl diagnose)")
    elif fit.apart:
        out.append("the equation error and the simulation error disagree beyond their standard "
                   "errors on " + ", ".join(_apart_text(*row) for row in fit.apart)
                   + ": the simulation error (DIDIM) is reported; the encoder's quantisation "
                     "biases the equation error (errors in variables), or the record holds an "
                     "effect the model lacks (fricctl diagnose)")
    for n, note in zip(result.names, result.notes()):
        if note:
            out.append(f"{n}: {note}")
    i = result.names.index("inertia")
    rel = float(result.relative_std[i])
    if result.identified[i] and rel > POOR_INERTIA_RELATIVE_STD:
        msg = (f"inertia known to {rel:.3g} % only (relative std > "
               f"{POOR_INERTIA_RELATIVE_STD:g} %): the record's accelerations move the "
               f"replayed position little; excite the joint harder")
        s = fit.start
        if fit.refined is not None and not any(a[0] == "inertia" for a in fit.apart):
            msg += (f", or take the equation error's {s.estimates[i]:.5g} +- {s.std[i]:.2g} "
                    f"if the encoder is fine enough (it agrees within the standard errors)")
        out.append(msg)
    # the default reports the equation error where DIDIM lost a parameter, could not replay the
    # record, or was not asked: the sentence then names the estimate's bias too (review R13)
    return out + held_out_warnings(held, refined=fit.refined is not None
                                   and fit.chosen is fit.refined)


def held_out_warnings(held, *, refined: bool = False) -> list:
    """What a held-out :class:`Validation` (or None: not asked) cannot vouch for: that it was
    not run, or a simulation fit below :data:`POOR_FIT_PERCENT` -- the same sentence for
    every recipe of ``fricctl identify``; ``refined``: the estimate minimises the simulation
    error already (the default recipe, DIDIM), so the sentence does not send the user there."""
    if held is None:
        return []
    if held.failure:
        return [f"held-out validation not run: {held.failure}"]
    if not held.simulation_fit >= POOR_FIT_PERCENT:
        return [f"poor held-out simulation fit: {held.simulation_fit:.3g} % of the position "
                f"(< {POOR_FIT_PERCENT:g} %); the model misses what drives this record "
                f"(fricctl diagnose names causes)"
                + ("" if refined else ", or the estimate is biased (an equation-error fit: "
                                      "the encoder's errors in variables, which a "
                                      "simulation-error fit such as DIDIM avoids)")]
    return []


def _piece(run: Run, lo: int, hi: int) -> Run:
    ref = None if run.reference is None else run.reference[lo:hi]
    return Run(t=run.t[lo:hi], torque=run.torque[lo:hi], position=run.position[lo:hi],
               reference=ref, source=f"{run.source} [{lo}:{hi}]", units=run.units)


def validate(result: IdentificationResult, run, *, exclude=None) -> Validation:
    """Check an estimate on a record: replay the record's torque with it (position fit) and
    predict its low-passed torque along the measured motion (equation-error fit).

    Parameters
    ----------
    result : IdentificationResult
        A linear model's estimate (any recipe).
    run : fricctl.datasets.Run
        The record to check it on (EMPS: ``DATA_EMPS_PULSES.mat`` for an estimate of
        ``DATA_EMPS.mat``).
    exclude : ndarray of bool, optional
        Samples left out (an end stop's contacts, :attr:`~fricctl.identify.stops.EndStops.mask`):
        out of the equation error with the filter's reach, and the replay run on each
        stretch clear of them (NaN between them in the curves).

    Raises
    ------
    ValueError
        A record that cannot be replayed (no motion, a diverging replay), a non-linear model.
    """
    v.instance("result", result, IdentificationResult)
    v.instance("run", run, Run, "a fricctl.datasets.Run")
    model, offset = result.model, "offset" in result.names
    if model not in LINEAR_MODELS or tuple(result.names) != model_names(model, offset):
        raise ValueError(f"result: a fit of a linear model ({', '.join(LINEAR_MODELS)}) is "
                         f"needed, not {model!r} over {result.names}")
    sig = estimate_signals(run, 1, exclude=exclude)
    if exclude is None or not np.any(exclude):
        sim = simulate_record(run, result.parameters, _REPLAY, initial_velocity=float(sig.w[0]))
        y = run.position - run.position.mean()
        yhat = sim.position - sim.position.mean()
        tt = run.t.copy()
    else:  # each stretch clear of the contacts replayed from its own start
        recipe = _didim_recipe(sig)
        pieces = _clear_pieces(run, exclude, recipe)
        if not pieces:
            raise ValueError(f"no stretch of {_min_piece(recipe)} samples clear of the end "
                             f"stops' contacts to replay")
        sims = [simulate_record(p, result.parameters, _REPLAY, initial_velocity=initial_velocity(
            p, recipe.cutoff, recipe.filter_order)).position for p in pieces]
        y = np.concatenate([x for p in pieces for x in (p.position - p.position.mean(), [np.nan])])
        yhat = np.concatenate([x for q in sims for x in (q - q.mean(), [np.nan])])
        tt = np.concatenate([x for p in pieces for x in (p.t, [np.nan])])
    m = sig.moving
    tm = sig.torque_target(0)[m]
    tp = record_columns(sig, model, offset)[m] @ result.estimates
    return Validation(simulation_fit=_fit_percent(y, yhat), equation_fit=_fit_percent(tm, tp),
                      t=tt, measured=y, simulated=yhat, torque_t=sig.t[m],
                      torque_measured=tm, torque_predicted=tp)


def held_out_halves(fit, run) -> Validation:
    """Any recipe validated on held-out halves: ``fit(half)`` (a linear model's
    :class:`IdentificationResult`) on each half, :func:`validate` on the other; both halves
    together (NaN between them in the curves).  What ``fricctl identify`` reports for the
    recipes other than the default (which uses :data:`JACKKNIFE_BLOCKS` blocks)."""
    v.instance("run", run, Run, "a fricctl.datasets.Run")
    n = run.n_samples
    halves = ((0, n // 2), (n // 2, n))
    try:
        parts = [validate(fit(_piece(run, *halves[1 - k])), _piece(run, lo, hi))
                 for k, (lo, hi) in enumerate(halves)]
    except ValueError as err:
        return _failed(str(err))
    return _merged(parts)


def _failed(reason: str) -> Validation:
    e = np.zeros(0)
    return Validation(simulation_fit=math.nan, equation_fit=math.nan, t=e, measured=e,
                      simulated=e, torque_t=e, torque_measured=e, torque_predicted=e,
                      failure=reason)


def _merged(parts) -> Validation:
    def cat(name):
        return np.concatenate([x for p in parts for x in (getattr(p, name), [np.nan])])

    return Validation(simulation_fit=_fit_percent(cat("measured"), cat("simulated")),
                      equation_fit=_fit_percent(cat("torque_measured"), cat("torque_predicted")),
                      t=cat("t"), measured=cat("measured"), simulated=cat("simulated"),
                      torque_t=cat("torque_t"), torque_measured=cat("torque_measured"),
                      torque_predicted=cat("torque_predicted"))


def _folds(run: Run, model, offset, refine: bool, full: _Fit, mask=None) -> tuple:
    """Delete each of :data:`JACKKNIFE_BLOCKS` blocks in turn: fit the rest (its pieces
    replayed together) and validate on the deleted block.  Returns the merged
    :class:`Validation` (NaN between blocks in the curves) and the jackknife's standard
    errors of the full fit's estimator, ``sqrt((K-1)/K sum_k (theta_k - mean)^2)`` (None when
    a block cannot be fitted)."""
    n, k = run.n_samples, JACKKNIFE_BLOCKS
    edges = [round(i * n / k) for i in range(k + 1)]

    def cut(a, b):
        return None if mask is None else mask[a:b]

    def fold(i):
        lo, hi = edges[i], edges[i + 1]
        spans = [(a, b) for a, b in ((0, lo), (hi, n)) if b - a > 0]
        # the whole record's estimator in every fold: DIDIM only where it was reported (a
        # record that fell back to the equation error is not replayed four more times)
        f = _fit([_piece(run, a, b) for a, b in spans], model, offset,
                 refine and full.chosen is full.refined, full.cutoff,
                 masks=[cut(a, b) for a, b in spans])
        est = f.chosen
        if est.method != full.chosen.method:
            why = (f"the simulation error does not identify {', '.join(f.lost)} without it"
                   if f.lost else f.why_not or "no refinement")
            raise ValueError(f"block {i + 1} of {k}: {why}")
        return est.estimates, validate(est, _piece(run, lo, hi), exclude=cut(lo, hi))

    try:
        # the replays release the GIL: two threads use both cores of a small machine
        with ThreadPoolExecutor(max_workers=min(k, os.cpu_count() or 1)) as pool:
            done = list(pool.map(fold, range(k)))
        thetas = [d[0] for d in done]
        parts = [d[1] for d in done]
    except ValueError as err:
        return _failed(str(err)), None
    th = np.array(thetas)
    jack = np.sqrt((k - 1) / k * np.sum((th - th.mean(axis=0)) ** 2, axis=0))
    return _merged(parts), jack


def _fit_percent(y, yhat) -> float:
    ok = np.isfinite(y) & np.isfinite(yhat)
    y, yhat = y[ok], yhat[ok]
    spread = float(np.linalg.norm(y - y.mean()))
    return math.nan if spread == 0.0 else float(100.0 * (1.0 - np.linalg.norm(y - yhat) / spread))
