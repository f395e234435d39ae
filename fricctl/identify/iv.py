r"""IDIM-IV: inverse-dynamics identification with instruments simulated by the model.

Janot, Vandanjon & Gautier, "A generic instrumental variable approach for industrial
robot identification", IEEE Trans. Control Syst. Technol. 22(1), 2014.

Least squares on the inverse model (IDIM-LS) regresses the torque ``y`` on an
observation matrix ``X`` built from a *filtered, twice differentiated, quantised*
position: ``X`` carries noise, and the estimate is biased toward zero (errors in
variables), worst for the inertia when the encoder step is coarse against the motion
per sample.  IDIM-IV keeps ``X`` and ``y`` but correlates them with instruments
``Z``: the same observation matrix built from the position the *model* simulates
for the record (:mod:`~fricctl.identify.simulation`: closed loop through the
record's controller, or the recorded torque replayed), processed by the same recipe
(:func:`~fricctl.identify.idim_observations`).  ``Z`` follows the true motion but not
the measurement noise, so

.. math::

    \hat\theta = (Z^T X)^{-1} Z^T y

is consistent.  As ``Z`` depends on the parameters, the estimate is iterated from the
IDIM-LS one until it stops moving.  Covariance (same paper):
``sigma^2 (Z^T X)^-1 Z^T Z (X^T Z)^-1`` with ``sigma`` the standard deviation of the
residual ``y - X theta``.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from .. import _validate as v
from ..controllers import Controller
from ..datasets import Run
from .idim import IdimRecipe, check_length, filter_reach, idim_ls, idim_observations
from .least_squares import IdentificationResult
from .models import LINEAR_MODELS, MODELS, model_names
from .simulation import initial_velocity, record_loop, simulate_record

__all__ = ["idim_iv", "moving_rows"]


def idim_iv(run, *, model: str = "coulomb_viscous", offset: bool | None = None,
            recipe: IdimRecipe | None = None, controller: Controller | None = None,
            max_iterations: int = 10, tolerance: float = 1e-6) -> IdentificationResult:
    """IDIM-IV of a record: IDIM-LS refined with instruments from the simulated model.

    Parameters
    ----------
    run : fricctl.datasets.Run
        Measured record.
    model : {"coulomb_viscous", "asymmetric"}
        Linear friction model.
    offset : bool, optional
        Include the offset column (default: as in :data:`~fricctl.identify.MODELS`).
    recipe : IdimRecipe, optional
        Signal processing of the observations and of the instruments (default: the EMPS
        recipe, :class:`~fricctl.identify.IdimRecipe`).
    controller : fricctl.controllers.Controller, optional
        The record's controller (its gains, with the record's reference); default
        inferred, see :func:`~fricctl.identify.simulation.record_loop`.
    max_iterations : int
        Most instrument updates [-].
    tolerance : float
        Stop when the change of the estimate, each parameter in units of its column
        scale ``||y||/||X_j||``, is below ``tolerance`` times the estimate's norm in the
        same units [-].

    Returns
    -------
    IdentificationResult
        ``method="IDIM-IV"``; ``predicted`` is ``X theta`` (the equation error, as
        IDIM-LS), ``std`` from the IV covariance, ``warnings`` what the fit cannot vouch
        for (open-loop instruments for a closed-loop record, no convergence, a
        negative magnitude).

    Notes
    -----
    The instruments are noise-free but carry the model's own errors: a friction law
    the record contradicts (stiction, Stribeck, a delay) makes ``Z`` a poorer
    instrument, never a biased one, as long as it is uncorrelated with the noise.
    In closed loop the simulated loop is the package's (:mod:`fricctl.simulate`): a
    controller with other timing (EMPS: no computation delay, a two-sample mean
    velocity) gives slightly different instruments.  Standard errors assume white
    residuals (optimistic for coloured ones).

    Examples
    --------
    >>> from fricctl import controllers as ctl, friction as fr
    >>> from fricctl.params import paper_actuator
    >>> from fricctl.simulate import simulate
    >>> p = paper_actuator()
    >>> law = fr.Viscous(p.viscous) + fr.Coulomb(p.coulomb)
    >>> run = simulate(p, ctl.open_loop(ctl.sinusoid(0.4, 0.5)), duration=10.0,
    ...                friction=law, quantize=False).to_run()
    >>> res = idim_iv(run, recipe=IdimRecipe(decimation=5))
    >>> abs(res.parameters["inertia"] / p.total_inertia - 1) < 0.01
    True
    """
    v.instance("run", run, Run, "a fricctl.datasets.Run")
    if v.choice("model", model, MODELS) not in LINEAR_MODELS:
        raise ValueError(f"model: IDIM-IV needs a linear model ({', '.join(LINEAR_MODELS)}), "
                         f"not {model!r}")
    recipe = IdimRecipe() if recipe is None else v.instance("recipe", recipe, IdimRecipe)
    max_iterations = v.integer("max_iterations", max_iterations, low=1)
    tolerance = v.real("tolerance", tolerance, positive=True)
    loop = record_loop(run, controller)
    ls = idim_ls(run, model=model, offset=offset, recipe=recipe)
    names = model_names(model, offset)
    obs = idim_observations(run, model, offset, recipe)
    keep = moving_rows(run, recipe)
    if keep.sum() <= len(names):  # Z^T X would be singular: say what the record lacks
        raise ValueError(f"IDIM-IV: {int(keep.sum())} of the record's {keep.size} decimated "
                         f"rows lie clear of rest (no sample at rest within "
                         f"{filter_reach(run, recipe)} samples, the filters' reach), fewer than "
                         f"the {len(names) + 1} needed to identify {', '.join(names)}; record "
                         f"longer or with fewer stops")
    X, y = obs.decimated[keep], obs.torque[keep]
    colscale = (np.linalg.norm(y) or 1.0) / np.linalg.norm(X, axis=0)
    w0 = initial_velocity(run, recipe.cutoff, recipe.filter_order)
    theta = ls.estimates.copy()
    warnings = list(loop.warnings)
    converged = False
    for iteration in range(1, max_iterations + 1):
        bad = [f"{n} {x:.4g}" for n, x in zip(names, theta) if x < 0 and n != "offset"]
        if bad and iteration > 1:  # the next instruments cannot be simulated
            raise ValueError(f"IDIM-IV: iterate {iteration - 1} has a negative "
                             f"{', '.join(bad)}: the instruments of a non-physical joint "
                             f"cannot be simulated (the record's regressors are too noisy "
                             f"for IV); use --recipe didim or the default recipe")
        sim = simulate_record(run, dict(zip(names, theta)), loop, initial_velocity=w0)
        Z = idim_observations(Run(t=run.t, torque=sim.torque, position=sim.position,
                                  units=run.units), model, offset, recipe).decimated[keep]
        # a square p x p system, the IV estimate itself: numpy's LU solve is exact here,
        # there is nothing to optimise (no bounds: a negative magnitude is flagged below,
        # not clipped, as clipping would make the estimate inconsistent)
        try:
            new = np.linalg.solve(Z.T @ X, Z.T @ y)
        except np.linalg.LinAlgError:
            raise ValueError(f"IDIM-IV: the instruments of iterate {iteration} do not excite "
                             f"all of {', '.join(names)} (Z^T X is singular): the simulated "
                             f"motion lacks what the record shows; use --recipe didim or the "
                             f"default recipe") from None
        change = np.linalg.norm((new - theta) / colscale) / np.linalg.norm(new / colscale)
        previous, theta = theta, new
        if change < tolerance:
            converged = True
            break
    pred = X @ theta
    sigma = float(np.std(y - pred, ddof=1))
    ZX = np.linalg.inv(Z.T @ X)
    cov = sigma ** 2 * ZX @ (Z.T @ Z) @ ZX.T
    std = np.sqrt(np.diag(cov))
    # with noise the instruments (a stick-slip simulation) move the iterate by a tiny
    # fraction of its std at every update: not converged only where it still moves
    # by a tenth of a standard error
    if not converged and np.any(np.abs(theta - previous) > 0.1 * std):
        warnings.append(f"IDIM-IV did not converge in {max_iterations} iterations (last "
                        f"relative change {change:.2g}, above a tenth of a standard error): "
                        "the estimate is the last iterate")
    negative = [n for n, x in zip(names, theta) if x < 0 and n != "offset"]
    if negative:
        warnings.append(f"{', '.join(negative)} came out negative: the record or the model "
                        "is inconsistent, the values are not physical")
    return replace(ls, estimates=theta, std=std, measured=y, predicted=pred,
                   condition_number=float(np.linalg.cond(Z.T @ X)), method="IDIM-IV",
                   solver_status=f"{'converged' if converged else 'not converged'} after "
                                 f"{iteration} instrument updates, {loop.describe()}",
                   iterations=iteration, at_bound=np.zeros(len(names), dtype=bool),
                   warnings=tuple(warnings))


def moving_rows(run: Run, recipe: IdimRecipe) -> np.ndarray:
    """Rows of the recipe's decimated observations that no sample at rest reaches (bool).

    At rest the torque is the reaction that holds the joint, not the friction law, so a
    row the filters smear a rest into contradicts the model for the measurement and the
    instrument alike (the rest samples of the EMPS recipe are harmless only because EMPS
    never rests).  Reach: the Butterworth's ``2/cutoff`` and the decimation filter's
    ``4*factor`` samples, each side.
    """
    from ..estimation import at_rest

    check_length(run, recipe)  # else the window below outgrows the record (an IndexError)
    q = np.asarray(run.position)[recipe.border:]
    rest = at_rest(q).astype(float)
    reach = filter_reach(run, recipe)
    near = np.convolve(rest, np.ones(2 * reach + 1), mode="same") > 0
    n, f = q.size, recipe.decimation
    first = f - (f * -(-n // f) - n) - 1  # decimate's first kept sample (MATLAB's nbeg - 1)
    return ~near[first::f]
