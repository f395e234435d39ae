"""Identification from a measured record: the plain route and the EMPS IDIM-LS recipe.

:func:`identify_run` estimates velocity and acceleration with any estimator of
:mod:`fricctl.estimation`, drops the border and the samples at rest, and fits a
friction law (:func:`~fricctl.identify.fit_friction`).  :func:`idim_ls` is the
IDIM-LS method of the EMPS benchmark (Janot, Gautier & Brunot 2019):
Butterworth + central differences, observation matrix, parallel decimation,
least squares; :func:`cross_validate` predicts another record with its result.

Notes
-----
Left out here: instrumental-variable and output-error methods (they are
:mod:`~fricctl.identify.iv` and :mod:`~fricctl.identify.didim`), weighted least squares, and any static
(breakaway) information -- samples at rest carry none in an inverse model and
are dropped by :func:`identify_run`.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from .. import _validate as v
from ..datasets import Run
from ..estimation import at_rest, butterworth_central, decimate, estimate
from .fit import fit_friction
from .least_squares import IdentificationResult, fit_least_squares, linear_prediction
from .models import (LINEAR_MODELS, MODELS, check_directions, lower_bounds, model_names,
                     regressor)
from .uncertainty import block_covariance

__all__ = ["identify_run", "IdimRecipe", "IdimObservations", "idim_observations", "idim_ls",
           "CrossValidation", "cross_validate"]


def _run(run) -> Run:
    return v.instance("run", run, Run, "a fricctl.datasets.Run")


def identify_run(run, *, model: str = "coulomb_viscous", estimator: str = "butterworth_central",
                 estimator_options: dict | None = None, offset: bool | None = None,
                 border: int = 50, initial: dict | None = None,
                 rest_guard: int | None = 2) -> IdentificationResult:
    """Estimate velocity/acceleration from a :class:`~fricctl.datasets.Run` and fit ``model``.

    Parameters
    ----------
    run : fricctl.datasets.Run
        Measured record.
    model : str
        Friction law, see :data:`~fricctl.identify.MODELS`.
    estimator : str
        Name in :data:`fricctl.estimation.ESTIMATORS`.
    estimator_options : dict, optional
        Keyword options of the estimator.
    offset : bool, optional
        Include a constant offset (default: as in :data:`~fricctl.identify.MODELS`).
    border : int
        Samples dropped at each end (estimator end effects) [samples].
    initial : dict, optional
        Starting values, see :func:`~fricctl.identify.fit_friction`.
    rest_guard : int or None
        Samples the *encoder* shows at rest -- the same reading ``rest_guard`` samples
        before and after (:func:`fricctl.estimation.at_rest`) -- are dropped [samples];
        ``None`` drops only the samples whose estimated velocity is exactly zero.

    Notes
    -----
    Samples at rest carry no friction information in an inverse model (the torque there
    is the reaction that holds the axis, anything below breakaway), so they are dropped:
    those whose estimated velocity is exactly zero (as the encoder-based estimators
    report rest) and those where the encoder stood still.  The second test matters for
    filtering estimators: a Butterworth velocity is never exactly zero, and the rest
    samples left in pair holding torques with small velocities of either sign, which
    pulls the Coulomb level down (by half on the paper's bench, chapter 3).  No
    decimation (plain least squares); see :func:`idim_ls` for the full EMPS recipe.  The
    standard errors of a linear model are the block covariance's
    (:func:`~fricctl.identify.uncertainty.block_covariance`) where larger than the white
    formula's: the filtered motion against the raw torque leaves a coloured residual.  They
    do not hold the estimator's own bias (``fricctl identify --recipe plain`` checks it).
    """
    _run(run)
    border = v.integer("border", border, low=0)
    if rest_guard is not None:
        rest_guard = v.integer("rest_guard", rest_guard, low=1)
    if 2 * border >= run.n_samples - 10:
        raise ValueError(f"border: {border} leaves too few of the {run.n_samples} samples")
    est = estimate(run.t, run.position, estimator, **(estimator_options or {}))
    sl = slice(border, run.n_samples - border)
    w, a, y = est.velocity[sl], est.acceleration[sl], run.torque[sl]
    keep = w != 0.0
    if rest_guard is not None:
        keep &= ~at_rest(run.position, guard=rest_guard)[sl]
    if keep.sum() < 10:
        raise ValueError("no motion: fewer than 10 samples that move (non-zero estimated velocity, "
                         "encoder not at rest)")
    res = fit_friction(w[keep], a[keep], y[keep], model=model, offset=offset, initial=initial,
                       units=run.units)
    if model not in LINEAR_MODELS:
        return res
    # the filtered motion against the raw torque leaves a coloured residual, for which the
    # textbook std is optimistic: the block covariance's where it is the larger (audit C 6)
    X = regressor(model, w[keep], a[keep], offset=offset)
    return replace(res, std=np.maximum(res.std, block_covariance(X, res.residual).std))


@dataclass(frozen=True, kw_only=True)
class IdimRecipe:
    """Signal processing of the IDIM-LS recipe (EMPS script ``Script_IDIM_LS.m``).

    Defaults are the EMPS ones at 1 kHz: 4th-order zero-phase Butterworth at
    100 Hz (5x the 20 Hz position-loop bandwidth), central differences twice,
    first 49 samples dropped, every column decimated by 10 (MATLAB ``decimate``).
    """

    cutoff: float = field(default=100.0, metadata={"unit": "Hz"})
    """Butterworth cut-off [Hz]."""
    filter_order: int = field(default=4, metadata={"unit": "-"})
    """Butterworth order [-]."""
    decimation: int = field(default=10, metadata={"unit": "-"})
    """Decimation factor of the parallel filtering [-]."""
    border: int = field(default=49, metadata={"unit": "samples"})
    """Samples dropped at the start (filter and difference end effects) [samples]."""

    def __post_init__(self):
        object.__setattr__(self, "cutoff", v.real("cutoff", self.cutoff, positive=True, unit="Hz"))
        object.__setattr__(self, "filter_order", v.integer("filter_order", self.filter_order, low=1))
        object.__setattr__(self, "decimation", v.integer("decimation", self.decimation, low=1))
        object.__setattr__(self, "border", v.integer("border", self.border, low=0))


@dataclass(frozen=True, kw_only=True)
class IdimObservations:
    """The observation matrix of a record by an :class:`IdimRecipe`, and its torque."""

    full: np.ndarray
    """Observation matrix before decimation, one column per parameter."""
    decimated: np.ndarray
    """Every column decimated (parallel filtering)."""
    torque: np.ndarray
    """The torque (force) decimated the same way [N*m] or [N]."""
    velocity: np.ndarray
    """The filtered velocity after the border, not decimated (the rows of :attr:`full`)
    [rad/s] or [m/s]."""


def filter_reach(run: Run, recipe: IdimRecipe) -> int:
    """Samples each side of a sample over which the recipe's filters spread it: the
    Butterworth's ``2/cutoff`` and the decimation filter's ``4*factor`` [samples]."""
    return int(np.ceil(2.0 / (recipe.cutoff * run.sample_time))) + 4 * recipe.decimation


def check_length(run: Run, recipe: IdimRecipe) -> None:
    """Refuse a record shorter than the recipe's window: its start border and the filters'
    reach (:func:`filter_reach`) each side of one row, naming the minimum."""
    reach = filter_reach(run, recipe)
    need = recipe.border + 2 * reach + 1
    if run.n_samples < need:
        raise ValueError(f"the record is too short for the IDIM recipe's filters: "
                         f"{run.n_samples} samples, at least {need} needed "
                         f"({need * run.sample_time:.3g} s at this sample rate: {recipe.border} "
                         f"dropped at the start, and the filters reach {reach} samples each side "
                         f"of a row, the {recipe.cutoff:g} Hz Butterworth's 2/cutoff and the "
                         f"decimation by {recipe.decimation}'s 4*{recipe.decimation})")


def idim_observations(run, model, offset, recipe: IdimRecipe) -> IdimObservations:
    """The IDIM-LS observations of ``run``: Butterworth + central differences, border
    dropped, regressor columns and torque decimated (the EMPS recipe)."""
    if v.choice("model", model, MODELS) not in LINEAR_MODELS:
        raise ValueError(f"model: the IDIM-LS recipe decimates regressor columns, so it needs a "
                         f"linear model ({', '.join(LINEAR_MODELS)}), not {model!r}")
    check_length(run, recipe)
    est = butterworth_central(run.t, run.position, cutoff=recipe.cutoff, order=recipe.filter_order)
    sl = slice(recipe.border, None)
    X0 = regressor(model, est.velocity[sl], est.acceleration[sl], offset=offset)
    y0 = np.asarray(run.torque[sl])
    X = np.column_stack([decimate(X0[:, j], recipe.decimation) for j in range(X0.shape[1])])
    return IdimObservations(full=X0, decimated=X, torque=decimate(y0, recipe.decimation),
                            velocity=est.velocity[sl])


def idim_ls(run, *, model: str = "coulomb_viscous", offset: bool | None = None,
            recipe: IdimRecipe | None = None) -> IdentificationResult:
    """The IDIM-LS method of the EMPS benchmark, with the least squares in CasADi.

    Butterworth + central differences (:func:`fricctl.estimation.butterworth_central`),
    drop ``recipe.border`` samples, build the observation matrix, decimate each
    column and the torque (:func:`fricctl.estimation.decimate`), least squares.

    Parameters
    ----------
    run : fricctl.datasets.Run
        Measured record (closed-loop, moving all the time for EMPS).
    model : {"coulomb_viscous", "asymmetric"}
        Linear friction model.
    offset : bool, optional
        Include the offset column (default: as in :data:`~fricctl.identify.MODELS`).
    recipe : IdimRecipe, optional
        Signal processing; default the EMPS one.

    Notes
    -----
    As in the EMPS script, ``abs_diag_r`` comes from the QR factorisation of the
    observation matrix *before* decimation, the condition number after.  Samples
    at rest are kept (``sign(0) = 0``), as in the script.
    """
    _run(run)
    recipe = IdimRecipe() if recipe is None else v.instance("recipe", recipe, IdimRecipe)
    obs = idim_observations(run, model, offset, recipe)
    X, y = obs.decimated, obs.torque
    names = model_names(model, offset)
    # a direction the record barely slides in gives a column that differs from a constant
    # (or from zero) only by the filters' smear: refused by name, before the fit reads it
    w = obs.velocity
    sliding = ~at_rest(run.position)[recipe.border:]
    check_directions(names, np.sum(sliding & (w > 0)), np.sum(sliding & (w < 0)),
                     filter_reach(run, recipe), f"the reach of its {recipe.cutoff:g} Hz "
                     f"Butterworth and its decimation by {recipe.decimation}")
    res = fit_least_squares(linear_prediction, X, y, names=names,
                            initial=np.zeros(len(names)), lower=lower_bounds(names),
                            scale=(np.linalg.norm(y) or 1.0) / np.linalg.norm(X, axis=0),
                            model=model, units=run.units)
    rdiag = np.abs(np.diag(np.linalg.qr(obs.full, mode="r")))
    return replace(res, abs_diag_r=rdiag, recipe=recipe)


@dataclass(frozen=True, kw_only=True)
class CrossValidation:
    """Prediction of a fitted IDIM model on another record (EMPS cross-test validation)."""

    measured: np.ndarray
    """Decimated measured torque/force [N*m] or [N]."""
    predicted: np.ndarray
    """Decimated prediction [N*m] or [N]."""
    condition_number: float
    """Condition number of the validation observation matrix [-]."""

    def __post_init__(self):
        for name in ("measured", "predicted"):
            x = np.array(getattr(self, name), dtype=float)
            x.setflags(write=False)
            object.__setattr__(self, name, x)

    @property
    def error_norm(self) -> float:
        """``||y - yhat||`` [N*m] or [N]."""
        return float(np.linalg.norm(self.measured - self.predicted))

    @property
    def relative_error(self) -> float:
        """``100 ||y - yhat|| / ||y||`` [%]."""
        return float(100.0 * self.error_norm / np.linalg.norm(self.measured))

    @property
    def error_std(self) -> float:
        """Sample standard deviation of the error [N*m] or [N]."""
        return float(np.std(self.measured - self.predicted, ddof=1))


def cross_validate(result: IdentificationResult, run, *,
                   recipe: IdimRecipe | None = None) -> CrossValidation:
    """Rebuild the observation matrix on ``run`` with the same recipe and predict.

    This is ``Script_IDIM_LS_CTV.m`` of the EMPS benchmark: no refit, only
    ``y_hat = X_ctv @ theta``; its relative error is the published 5.9824 % on the
    PULSES file.
    """
    v.instance("result", result, IdentificationResult)
    _run(run)
    if result.model not in LINEAR_MODELS:
        raise ValueError("cross_validate: needs a result of idim_ls (a linear model)")
    if recipe is not None:
        v.instance("recipe", recipe, IdimRecipe)
    recipe = recipe or result.recipe or IdimRecipe()
    offset = "offset" in result.names
    obs = idim_observations(run, result.model, offset, recipe)
    return CrossValidation(measured=obs.torque, predicted=obs.decimated @ result.estimates,
                           condition_number=float(np.linalg.cond(obs.decimated)))
