"""Fit a friction law to (velocity, acceleration, torque) samples: :func:`fit_friction`."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace

import numpy as np

from .. import _validate as v
from ..units import units as units_of
from .least_squares import IdentificationResult, fit_least_squares, linear_prediction
from .models import LINEAR_MODELS, MODELS, implausible, lower_bounds, model_names, regressor

__all__ = ["fit_friction"]


def _stribeck_prediction(theta, x):
    import casadi as ca

    inertia, viscous, coulomb, static, vs = theta[0], theta[1], theta[2], theta[3], theta[4]
    a, w = x[0], x[1]
    out = inertia * a + viscous * w + ca.sign(w) * (coulomb + (static - coulomb) * ca.exp(-(w / vs) ** 2))
    if theta.numel() > 5:
        out = out + theta[5]
    return out


def fit_friction(velocity, acceleration, torque, *, model: str = "coulomb_viscous",
                 offset: bool | None = None, initial: dict | None = None, units: str = "rotary",
                 solver_options: dict | None = None) -> IdentificationResult:
    """Fit a friction law to (velocity, acceleration, torque) samples by inverse dynamics.

    Parameters
    ----------
    velocity, acceleration : array_like, shape (N,)
        [rad/s], [rad/s^2] (or [m/s], [m/s^2]); samples at rest are used as given.
    torque : array_like, shape (N,)
        Applied torque [N*m] (or force [N]).
    model : {"coulomb_viscous", "asymmetric", "stribeck"}
        Friction law (see :mod:`fricctl.identify.models`).
    offset : bool, optional
        Include a constant offset (default: as in :data:`~fricctl.identify.MODELS`).
    initial : dict, optional
        Starting values by name.  Default: zeros for the linear models (the problem
        is convex); for ``"stribeck"`` the ``coulomb_viscous`` fit, ``static`` 1.5
        times its Coulomb level and ``stribeck_velocity`` a tenth of the 95th
        percentile of ``|velocity|``.
    units : {"rotary", "linear"}
        Labels only.
    solver_options : dict, optional
        Extra IPOPT options.

    Returns
    -------
    IdentificationResult

    Notes
    -----
    Linear models are scaled column-wise (``scale_j = ||y|| / ||X_j||``, the value
    that alone would explain the data), which needs no solution beforehand.  The
    Stribeck fit is non-convex in ``stribeck_velocity``; a poor start can end in a
    local minimum -- pass ``initial`` when you know better.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 2, 400); w = np.sin(3 * t) + 0.2; a = 3 * np.cos(3 * t)
    >>> tau = 0.01 * a + 0.02 * w + 0.1 * np.sign(w) + 0.005
    >>> res = fit_friction(w, a, tau)
    >>> np.round(res.estimates, 6).tolist()
    [0.01, 0.02, 0.1, 0.005]
    """
    v.choice("model", model, MODELS)
    units_of(units)
    w = v.array("velocity", velocity)
    a = v.array("acceleration", acceleration, size=w.size)
    y = v.array("torque", torque, size=w.size)
    names = model_names(model, offset)
    if initial is not None:
        v.instance("initial", initial, Mapping, "a mapping of parameter names to values")
        unknown = set(initial) - set(names)
        if unknown:
            raise ValueError(f"initial: unknown parameter(s) {sorted(unknown)} for model {model!r}")
        initial = {nm: v.real(f"initial[{nm!r}]", x) for nm, x in initial.items()}
    lower = lower_bounds(names)
    upper = np.full(len(names), np.inf)
    if model in LINEAR_MODELS:
        X = regressor(model, w, a, offset=offset)
        colnorm = np.linalg.norm(X, axis=0)
        if np.any(colnorm == 0):
            raise ValueError("data do not excite " + ", ".join(np.array(names)[colnorm == 0])
                             + " (an all-zero regressor column)")
        scale = (np.linalg.norm(y) or 1.0) / colnorm
        x0 = np.array([0.0 if initial is None or nm not in initial else initial[nm]
                       for nm in names])
        return fit_least_squares(linear_prediction, X, y, names=names, initial=x0,
                                 lower=lower, upper=upper, scale=scale, model=model, units=units,
                                 solver_options=solver_options)
    # Stribeck
    vmax = float(np.percentile(np.abs(w), 95))
    if vmax == 0:
        raise ValueError("velocity: no motion, a Stribeck curve cannot be identified")
    if initial is not None and set(initial) == set(names):
        start = dict(initial)
    else:
        base = fit_friction(w, a, y, model="coulomb_viscous", offset="offset" in names,
                            units=units, solver_options=solver_options).parameters
        start = dict(inertia=base["inertia"], viscous=base["viscous"], coulomb=base["coulomb"],
                     static=1.5 * base["coulomb"], stribeck_velocity=0.1 * vmax)
        if "offset" in names:
            start["offset"] = base["offset"]
        start.update(initial or {})
    x0 = np.array([float(start[nm]) for nm in names])
    lower[names.index("stribeck_velocity")] = 1e-6 * vmax
    scale = np.maximum(np.abs(x0), 1e-3 * np.max(np.abs(x0)))
    res = fit_least_squares(_stribeck_prediction, np.column_stack([a, w]), y, names=names,
                            initial=x0, lower=lower, upper=upper, scale=scale, model=model,
                            units=units, solver_options=solver_options)
    # a value the law cannot mean is said where the estimate is shown (a model file refuses it)
    bad = implausible(model, res.parameters)
    return replace(res, warnings=res.warnings + tuple(
        f"{n}: {why} (a Stribeck curve falls from breakaway to the Coulomb level); no model "
        f"file can be written from this fit" for n, why in bad.items()))
