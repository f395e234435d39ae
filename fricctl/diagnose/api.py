"""The diagnosis workflow (:func:`diagnose`) and the two checks of a model on another record
(:func:`torque_residual`, :func:`prediction_errors`)."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from .. import _validate as v
from ..datasets import Run
from ..plant import JointModel
from . import causes
from .causes import Baseline, Term
from .crossval import Problem, baseline_fit, casadi_refit, compose, full_fit
from .report import Diagnosis, Gain, evidence_text
from .selection import forward_selection
from .signals import Signals, estimate_signals, predict
from .twin import chain_shares, effect_free_twin
from .windows import WindowedSimulation, simulate_windows, window_grid

__all__ = ["diagnose", "torque_residual", "prediction_errors", "TorqueResidual", "PredictionErrors"]


def _check_run(run) -> Run:
    return v.instance("run", run, Run, "a fricctl.datasets.Run")


def diagnose(run: Run, model: JointModel | None = None, *, window: float = 0.5,
             folds: int = 8) -> Diagnosis:
    """Show what the model gets wrong on ``run``, name every cause the data support, extend
    the model with them, measure the gain.

    Parameters
    ----------
    run : Run
        The measured record (uniform sampling, any rate; moving in most blocks).
    model : JointModel, optional
        A nominal model to diagnose as given; default: fit the rigid baseline
        ``I*q'' = Tm - b*w - Fc*sign(w)``.
    window : float
        Window of the re-simulation [s].
    folds : int
        Blocks of the blocked cross-validation (3 .. 20).

    Returns
    -------
    Diagnosis

    Notes
    -----
    With a nominal model every candidate fits only its own term on top of it (the
    nominal is trusted otherwise); without, the baseline's I, b and Fc are refitted
    with each candidate.  ``inertia`` and ``friction_scale`` only apply to a
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
    _check_run(run)
    if model is not None:
        v.instance("model", model, JointModel, "a JointModel (or None)")
    folds = v.integer("folds", folds, low=3, high=20)
    window = v.real("window", window, positive=True, unit="s")
    sig = estimate_signals(run, folds)
    fit0 = baseline_fit(sig) if model is None else None
    base = Baseline(sig, model, None if fit0 is None else fit0.estimates.copy())
    problem = Problem(sig, base.columns)
    candidates = causes.candidates(nominal=model is not None)
    grid = window_grid(sig, window)
    twins: dict = {}

    def chain(floor: float, named: tuple, current: JointModel):
        """The chain's shares on a twin of ``current`` with the residual ``floor``, after
        ``named`` (twins within 10 % of a residual are shared)."""
        key = (named, id(current), round(math.log(max(floor, 1e-300)) / math.log(1.1)))
        if key not in twins:
            twins[key] = chain_shares(effect_free_twin(base, floor, model=current), named)
        return twins[key]

    wfold = sig.folds[grid.starts]
    inside = sig.folds[np.minimum(grid.starts + grid.length - 1, sig.t.size - 1)] == wfold

    def heldout_sim(models) -> WindowedSimulation:
        """Each block's windows re-simulated with the model fitted without that block."""
        parts = [simulate_windows(models[f], sig, grid.starts[(wfold == f) & inside], grid.length)
                 for f in range(sig.n_folds)]
        return WindowedSimulation.merge(parts, n=sig.t.size, length=grid.length)

    sel = forward_selection(problem, base, candidates, chain, heldout_sim)

    # ---- the named terms refitted together on all data with CasADi --------------
    refit = None
    if sel.selected:
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
        extended = base.model(parts, theta)
    else:
        theta = base.theta if base.fit_mode else np.zeros(0)
        parts = []
        extended = base.fitted
    nmov = int(sig.moving.sum())
    before, after = sel.sim_before.rms(), sel.sim_after.rms()
    gain = Gain(torque_rms_before=math.sqrt(float(np.sum(sel.baseline_test)) / nmov),
                torque_rms_after=math.sqrt(float(np.sum(sel.test)) / nmov),
                simulation_rms_before=before.position, velocity_rms_before=before.velocity,
                simulation_rms_after=after.position, velocity_rms_after=after.velocity)
    bodies = _evidence_bodies(base, sel.selected, theta, extended)
    named = tuple(s.cause.name for s in sel.selected) or (causes.NONE,)
    baseline_model = base.fitted
    return Diagnosis(cause=named[0], causes=named, steps=sel.steps, ranking=sel.first_ranking,
                     evidence=evidence_text(sel.steps, bodies, sel.first_ranking, gain,
                                            sel.not_identifiable, sig.units),
                     baseline=baseline_model, extended=extended, gain=gain,
                     simulation_scores=sel.simulation_scores, fit=refit or fit0, t=sig.t,
                     torque=sig.tm, position=sig.q, velocity=sig.w,
                     residual_before=_sliding_residual(baseline_model, sig),
                     residual_after=_sliding_residual(extended, sig), sim_before=sel.sim_before,
                     sim_after=sel.sim_after, nominal=model is not None, units=sig.units,
                     not_identifiable=dict(sel.not_identifiable), last_ranking=sel.last_ranking,
                     chain_rms=effect_free_twin(base).rms,
                     cutoff=sig.cutoff)


def _evidence_bodies(base: Baseline, selected: tuple, theta: np.ndarray,
                     extended: JointModel) -> tuple:
    """Each named cause's evidence clause, from its slice of the joint fit."""
    out = []
    k = 3 if base.fit_mode else 0
    for s in selected:
        coef = theta[k:k + s.cause.n_extra]
        k += s.cause.n_extra
        out.append(s.cause.evidence(base, Term(h=s.variant.h, coef=coef), extended))
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
    meaningful where ``mask`` is true (the joint slides).
    """
    v.instance("model", model, JointModel)
    sig = estimate_signals(_check_run(run), 1)
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


def prediction_errors(model: JointModel, run: Run, *, window: float = 0.5) -> PredictionErrors:
    """How well ``model`` predicts another record (no refit): RMS errors.

    Returns
    -------
    PredictionErrors
    """
    _check_run(run)
    v.instance("model", model, JointModel)
    window = v.real("window", window, positive=True, unit="s")
    sig = estimate_signals(run, 1)
    r = predict(model, sig).residual[sig.moving]
    grid = window_grid(sig, window)
    rms = simulate_windows(model, sig, grid.starts, grid.length).rms()
    return PredictionErrors(torque_rms=float(np.sqrt(np.mean(r ** 2))),
                            simulation_rms=rms.position, velocity_rms=rms.velocity)
