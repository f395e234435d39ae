r"""Friction identification by inverse-dynamics least squares, posed in CasADi.

The inverse dynamic identification model (IDIM) of one axis, rotary convention
(for a linear axis read force [N], mass [kg], [m], [m/s]):

.. math::

    \tau = I\,\ddot q + F_f(\dot q) + \text{offset},

with the friction laws (``w`` = velocity, friction has the sign of ``w``)

* ``"coulomb_viscous"``: ``F_f = b*w + Fc*sign(w)``;
  parameters ``inertia, viscous, coulomb, offset``;
* ``"asymmetric"`` (EMPS eq. 12): ``b+ * w + Fc+`` for ``w > 0`` and
  ``b- * w - Fc-`` for ``w < 0``, two positive magnitudes per direction;
  parameters ``inertia, viscous_pos, coulomb_pos, viscous_neg, coulomb_neg``
  (``offset`` only on request: without rest samples it is collinear with the two
  Coulomb columns);
* ``"stribeck"``: ``b*w + sign(w)*(Fc + (Fs - Fc)*exp(-(w/vs)^2))``;
  parameters ``inertia, viscous, coulomb, static, stribeck_velocity, offset``.

Every fit is a CasADi NLP solved by IPOPT over *scaled* variables
``theta = scale * z`` with bounds (inertia, viscous, Coulomb and static levels
non-negative, Stribeck velocity positive).  :func:`fit_least_squares` is the
generic entry point: any per-sample prediction written in CasADi symbols.
Statistics follow the IDIM-LS report of the EMPS benchmark (Janot, Gautier &
Brunot 2019): ``std_j = sigma * sqrt(((J^T J)^-1)_jj)`` with ``sigma`` the sample
standard deviation of the residual, relative std in %, condition number of the
observation (Jacobian) matrix, relative error ``100*||y - yhat|| / ||y||``.

Notes
-----
Left out: instrumental-variable and output-error methods (closed-loop bias of
least squares is not corrected), weighted least squares, LuGre (its internal
state makes it an output-error problem), and any static (breakaway) information
-- samples at rest carry none in an inverse model and are dropped by
:func:`identify_run`.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field, replace
from typing import Callable

import numpy as np

__all__ = [
    "MODELS",
    "model_names",
    "regressor",
    "inverse_dynamics",
    "IdentificationResult",
    "fit_least_squares",
    "fit_friction",
    "identify_run",
    "IdimRecipe",
    "idim_ls",
    "CrossValidation",
    "cross_validate",
]

#: Parameter names of each model (``offset`` included where it is the default).
MODELS = {
    "coulomb_viscous": ("inertia", "viscous", "coulomb", "offset"),
    "asymmetric": ("inertia", "viscous_pos", "coulomb_pos", "viscous_neg", "coulomb_neg"),
    "stribeck": ("inertia", "viscous", "coulomb", "static", "stribeck_velocity", "offset"),
}
_LINEAR = ("coulomb_viscous", "asymmetric")
_NONNEGATIVE = {"inertia", "viscous", "coulomb", "viscous_pos", "coulomb_pos",
                "viscous_neg", "coulomb_neg", "static"}
_UNITS_ROTARY = {"inertia": "kg*m^2", "viscous": "N*m*s/rad", "coulomb": "N*m",
                 "offset": "N*m", "static": "N*m", "stribeck_velocity": "rad/s"}


def _unit(name: str, units: str) -> str:
    base = name.replace("_pos", "").replace("_neg", "")
    if units == "linear":
        return {"inertia": "kg", "viscous": "N*s/m", "coulomb": "N", "offset": "N",
                "static": "N", "stribeck_velocity": "m/s"}.get(base, "")
    return _UNITS_ROTARY.get(base, "")


def _check_model(model: str) -> None:
    if model not in MODELS:
        raise ValueError(f"model: unknown friction model {model!r}; choose from {sorted(MODELS)}")


def model_names(model: str, offset: bool | None = None) -> tuple[str, ...]:
    """Parameter names of ``model``, with or without ``offset``.

    Examples
    --------
    >>> model_names("asymmetric", offset=True)
    ('inertia', 'viscous_pos', 'coulomb_pos', 'viscous_neg', 'coulomb_neg', 'offset')
    """
    _check_model(model)
    names = MODELS[model]
    has = "offset" in names
    if offset is None or offset == has:
        return names
    return names + ("offset",) if offset else tuple(n for n in names if n != "offset")


def _as_1d(name, x, n=None):
    x = np.asarray(x, dtype=float)
    if x.ndim != 1:
        raise ValueError(f"{name}: expected a 1-D array, got shape {x.shape}")
    if n is not None and x.size != n:
        raise ValueError(f"{name}: length {x.size} differs from {n}")
    bad = np.flatnonzero(~np.isfinite(x))
    if bad.size:
        raise ValueError(f"{name}: non-finite value at row {int(bad[0])}")
    return x


def regressor(model: str, velocity, acceleration, *, offset: bool | None = None) -> np.ndarray:
    """Observation matrix of a linear-in-parameters model, columns in :func:`model_names` order.

    Parameters
    ----------
    model : {"coulomb_viscous", "asymmetric"}
        Linear model.
    velocity, acceleration : array_like, shape (N,)
        Joint velocity [rad/s] and acceleration [rad/s^2] (or [m/s], [m/s^2]).
    offset : bool, optional
        Include the constant column (default: as in :data:`MODELS`).

    Examples
    --------
    >>> regressor("coulomb_viscous", [2.0, -1.0], [0.5, 0.0]).tolist()
    [[0.5, 2.0, 1.0, 1.0], [0.0, -1.0, -1.0, 1.0]]
    """
    _check_model(model)
    if model not in _LINEAR:
        raise ValueError(f"model: {model!r} is not linear in its parameters; no regressor matrix")
    w = _as_1d("velocity", velocity)
    a = _as_1d("acceleration", acceleration, w.size)
    s = np.sign(w)
    cols = {"inertia": a, "offset": np.ones_like(w)}
    if model == "coulomb_viscous":
        cols.update(viscous=w, coulomb=s)
    else:
        pos, neg = (1.0 + s) / 2.0, (1.0 - s) / 2.0  # EMPS's O+ and O- operators
        cols.update(viscous_pos=w * pos, coulomb_pos=s * pos, viscous_neg=w * neg,
                    coulomb_neg=s * neg)
    return np.column_stack([cols[n] for n in model_names(model, offset)])


def inverse_dynamics(model: str, parameters: dict, velocity, acceleration) -> np.ndarray:
    """Torque [N*m] (or force [N]) the model predicts for given motion.

    Parameters
    ----------
    model : str
        One of :data:`MODELS`.
    parameters : dict
        Name -> value; exactly the names of the model, ``offset`` optional.
    velocity, acceleration : array_like, shape (N,)
        [rad/s], [rad/s^2] (or [m/s], [m/s^2]).

    Examples
    --------
    >>> p = dict(inertia=2.0, viscous=0.5, coulomb=1.0, offset=0.0)
    >>> inverse_dynamics("coulomb_viscous", p, [2.0, -2.0], [1.0, 1.0]).tolist()
    [4.0, 0.0]
    """
    _check_model(model)
    names = set(MODELS[model]) - {"offset"}
    given = set(parameters)
    if not names <= given or not given <= names | {"offset"}:
        raise ValueError(f"parameters: expected {sorted(names)} (+ optional offset), got {sorted(given)}")
    p = {k: float(v) for k, v in parameters.items()}
    w = _as_1d("velocity", velocity)
    a = _as_1d("acceleration", acceleration, w.size)
    s = np.sign(w)
    tau = p["inertia"] * a + p.get("offset", 0.0)
    if model == "coulomb_viscous":
        return tau + p["viscous"] * w + p["coulomb"] * s
    if model == "asymmetric":
        pos, neg = w > 0, w < 0
        return tau + np.where(pos, p["viscous_pos"] * w + p["coulomb_pos"], 0.0) \
                   + np.where(neg, p["viscous_neg"] * w - p["coulomb_neg"], 0.0)
    excess = (p["static"] - p["coulomb"]) * np.exp(-(w / p["stribeck_velocity"]) ** 2)
    return tau + p["viscous"] * w + s * (p["coulomb"] + excess)


# --------------------------------------------------------------------------- result
@dataclass(frozen=True, kw_only=True)
class IdentificationResult:
    """Estimates of a least-squares fit and the IDIM-LS statistics.

    Notes
    -----
    Standard deviations assume independent, identically distributed residuals
    (they are optimistic for coloured, closed-loop residuals), and are linearised
    at the solution for nonlinear models.
    """

    names: tuple[str, ...]
    """Parameter names."""
    estimates: np.ndarray
    """Estimated values, SI units of each parameter."""
    std: np.ndarray
    """Standard deviations ``sigma*sqrt(diag((J^T J)^-1))``, same units."""
    condition_number: float
    """2-norm condition number of the observation (Jacobian) matrix [-]."""
    abs_diag_r: np.ndarray
    """|diag(R)| of the QR factorisation of the observation matrix (EMPS prints it)."""
    measured: np.ndarray
    """Measured torque/force the fit used [N*m] or [N]."""
    predicted: np.ndarray
    """Model prediction at the estimates [N*m] or [N]."""
    model: str | None = None
    """Friction model name, or None for a generic fit (then :meth:`predict` is unavailable)."""
    units: str = "rotary"
    """``"rotary"`` or ``"linear"`` (labels in the report)."""
    solver_status: str = ""
    """IPOPT's return status."""
    iterations: int = 0
    """IPOPT iterations."""
    recipe: "IdimRecipe | None" = None
    """Signal recipe of :func:`idim_ls`, or None."""

    def __post_init__(self):
        for name in ("estimates", "std", "abs_diag_r", "measured", "predicted"):
            x = np.array(getattr(self, name), dtype=float)
            x.setflags(write=False)
            object.__setattr__(self, name, x)
        object.__setattr__(self, "names", tuple(self.names))

    # statistics ---------------------------------------------------------------
    @property
    def parameters(self) -> dict[str, float]:
        """Name -> estimate."""
        return {n: float(v) for n, v in zip(self.names, self.estimates)}

    @property
    def relative_std(self) -> np.ndarray:
        """``100 * std / |estimate|`` [%]."""
        with np.errstate(divide="ignore"):
            return 100.0 * self.std / np.abs(self.estimates)

    @property
    def residual(self) -> np.ndarray:
        """``measured - predicted`` [N*m] or [N]."""
        return self.measured - self.predicted

    @property
    def n_samples(self) -> int:
        """Samples in the fit [-]."""
        return int(self.measured.size)

    @property
    def error_norm(self) -> float:
        """``||y - yhat||`` [N*m] or [N]."""
        return float(np.linalg.norm(self.residual))

    @property
    def error_std(self) -> float:
        """Sample standard deviation of the residual (``sigma``) [N*m] or [N]."""
        return float(np.std(self.residual, ddof=1))

    @property
    def residual_rms(self) -> float:
        """Root-mean-square residual [N*m] or [N]."""
        return float(np.sqrt(np.mean(self.residual ** 2)))

    @property
    def relative_error(self) -> float:
        """``100 * ||y - yhat|| / ||y||`` [%] (EMPS eq. 11)."""
        return float(100.0 * self.error_norm / np.linalg.norm(self.measured))

    @property
    def fit_percent(self) -> float:
        """``100 * (1 - ||y - yhat|| / ||y - mean(y)||)`` [%] (normalised RMSE fit)."""
        return float(100.0 * (1.0 - self.error_norm / np.linalg.norm(self.measured - self.measured.mean())))

    # presentation -------------------------------------------------------------
    def report(self) -> str:
        """Text report laid out like the EMPS IDIM-LS script output."""
        w = max(len(n) for n in self.names)
        lines = [f"IDIM-LS: model {self.model or 'custom'}, {self.n_samples} samples",
                 f"{'':<10}{'':<{w}}   {'estimate':>12} {'std':>10} {'rel. std':>9}"]
        for n, v, s, r in zip(self.names, self.estimates, self.std, self.relative_std):
            unit = _unit(n, self.units)
            lines.append(f"Parameter {n:<{w}} : {v:12.4f} {s:10.4f} {r:8.4f} %   [{unit}]")
        lines += ["", "Absolute value of the diagonal element of R"]
        lines += [f"Parameter {n:<{w}} : {d:12.4f}" for n, d in zip(self.names, self.abs_diag_r)]
        lines += [f"Condition number of the observation matrix: {self.condition_number:.4f}", "",
                  f"Error norm : {self.error_norm:.4f}",
                  f"Relative error (%): {self.relative_error:.4f}",
                  f"Deviation of error: {self.error_std:.4f}",
                  f"Fit (%): {self.fit_percent:.4f}"]
        return "\n".join(lines)

    def predict(self, velocity, acceleration) -> np.ndarray:
        """Torque [N*m] (or force [N]) the fitted friction model predicts."""
        if self.model is None:
            raise ValueError("predict: a generic fit has no friction model; evaluate your own prediction")
        return inverse_dynamics(self.model, self.parameters, velocity, acceleration)

    def as_dict(self) -> dict:
        """JSON-ready summary: parameters (value, std, unit), fit %, condition number, ..."""
        return {
            "model": self.model,
            "units": self.units,
            "n_samples": self.n_samples,
            "parameters": {n: {"value": float(v), "std": float(s), "unit": _unit(n, self.units)}
                           for n, v, s in zip(self.names, self.estimates, self.std)},
            "fit_percent": self.fit_percent,
            "relative_error_percent": self.relative_error,
            "residual_rms": self.residual_rms,
            "condition_number": self.condition_number,
            "solver_status": self.solver_status,
        }

    def to_json(self) -> str:
        """:meth:`as_dict` as a JSON string."""
        return json.dumps(self.as_dict(), indent=2)


# --------------------------------------------------------------------------- generic fit
def fit_least_squares(prediction: Callable, data, y, *, names, initial, lower=None, upper=None,
                      scale=None, model: str | None = None, units: str = "rotary",
                      solver_options: dict | None = None) -> IdentificationResult:
    """Least squares ``min 1/2 sum_k (y_k - f(theta, x_k))^2`` with CasADi + IPOPT.

    Parameters
    ----------
    prediction : callable
        ``prediction(theta, x) -> casadi.MX`` of shape (1, N): the model output for
        all samples, written in CasADi symbols.  ``theta`` is an ``MX`` of length p
        (``theta[i]`` a scalar), ``x`` a list of m ``MX`` rows of shape (1, N), one
        per column of ``data``; write the model element-wise (``*``, ``/``, ``**``,
        ``casadi.exp``, ``casadi.sign``, ``casadi.tanh``...), e.g.
        ``lambda th, x: th[0] * x[0] + th[1] * casadi.sign(x[1])``.
    data : array_like, shape (N, m)
        Per-sample inputs (regressor rows, or e.g. ``[acceleration, velocity]``).
    y : array_like, shape (N,)
        Measurements.
    names : sequence of str
        Parameter names (length p).
    initial : array_like, shape (p,)
        Starting point, in the parameters' own units.
    lower, upper : array_like, shape (p,), optional
        Bounds (``-inf``/``inf`` for none).
    scale : array_like, shape (p,), optional
        Typical magnitudes; IPOPT works on ``z = theta/scale``.  Default:
        ``|initial|``, or 1 where that is zero.
    model : str, optional
        Friction model name, recorded so that :meth:`IdentificationResult.predict` works.
    units : {"rotary", "linear"}
        For the report's unit labels.
    solver_options : dict, optional
        Extra IPOPT options (``{"tol": 1e-10}``...), merged over the defaults.

    Returns
    -------
    IdentificationResult

    Raises
    ------
    ValueError
        Wrong shapes, non-finite data, lower bound above upper, a rank-deficient
        Jacobian (parameters not excited by the data), or IPOPT failure.

    Notes
    -----
    The data enter as NLP parameters, not constants, and the prediction is a few
    element-wise nodes over whole rows, so the graph does not grow with N.  IPOPT
    uses the exact Hessian; the objective is divided by ``||y||^2`` so its scale does not
    depend on the data's units.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.linspace(0, 1, 50)[:, None]
    >>> res = fit_least_squares(lambda th, r: th[0] + th[1] * r[0], x, 1 + 2 * x[:, 0],
    ...                         names=("a", "b"), initial=[0.5, 0.5])
    >>> np.round(res.estimates, 8).tolist()
    [1.0, 2.0]
    """
    import casadi as ca

    names = tuple(names)
    p = len(names)
    data = np.asarray(data, dtype=float)
    if data.ndim == 1:
        data = data[:, None]
    if data.ndim != 2:
        raise ValueError(f"data: expected shape (N, m), got {data.shape}")
    n, m = data.shape
    y = _as_1d("y", y, n)
    if not np.all(np.isfinite(data)):
        raise ValueError(f"data: non-finite value at row {int(np.flatnonzero(~np.isfinite(data).all(1))[0])}")
    if n <= p:
        raise ValueError(f"need more samples ({n}) than parameters ({p})")
    x0 = _as_1d("initial", initial, p)
    lb = np.full(p, -np.inf) if lower is None else _as_1d_inf("lower", lower, p)
    ub = np.full(p, np.inf) if upper is None else _as_1d_inf("upper", upper, p)
    if np.any(lb > ub):
        raise ValueError("bounds: lower exceeds upper for " + ", ".join(np.array(names)[lb > ub]))
    if scale is None:
        sc = np.where(np.abs(x0) > 0, np.abs(x0), 1.0)
    else:
        sc = _as_1d("scale", scale, p)
        if np.any(sc <= 0):
            raise ValueError("scale: must be positive")

    # Vectorised formulation: each data column is one 1 x N row symbol (an NLP
    # parameter, so the data are not baked into the graph) and the prediction is a
    # handful of element-wise MX nodes over all samples.  This evaluates like numpy
    # and its derivatives stay as small as the per-sample expression (a per-sample
    # Function mapped N times was 7x slower at N = 50 000).
    z = ca.MX.sym("z", p)
    rows = [ca.MX.sym(f"x{j}", 1, n) for j in range(m)]
    ysym = ca.MX.sym("y", 1, n)
    theta = z * ca.DM(sc)
    pred = prediction(theta, rows)
    if not isinstance(pred, (ca.MX, ca.DM)) or pred.shape not in ((1, n), (1, 1)):
        raise ValueError("prediction: must return a casadi expression of shape (1, N)")
    pred = pred * ca.DM.ones(1, n) if pred.shape == (1, 1) else pred
    ynorm2 = float(y @ y) or 1.0
    obj = 0.5 * ca.sumsqr(ysym - pred) / ynorm2
    opts = {"print_level": 0, "tol": 1e-12, "max_iter": 500, "sb": "yes"}
    opts.update(solver_options or {})
    psym = ca.vertcat(*[ca.vec(r) for r in rows], ca.vec(ysym))
    solver = ca.nlpsol("idim", "ipopt", {"x": z, "f": obj, "p": psym},
                       {"ipopt": opts, "print_time": False, "error_on_fail": False})
    pval = np.concatenate([data.T.ravel(), y])
    sol = solver(x0=x0 / sc, lbx=lb / sc, ubx=ub / sc, p=pval)
    stats = solver.stats()
    status = str(stats.get("return_status", ""))
    if not stats.get("success", False) and status not in ("Solved_To_Acceptable_Level",):
        raise ValueError(f"IPOPT did not converge: {status}")
    est = np.asarray(sol["x"]).ravel() * sc
    # Jacobian of the prediction w.r.t. theta (not z): d pred/d theta = d pred/d z / sc
    evaluate = ca.Function("pred_jac", [z, psym], [pred, ca.jacobian(ca.vec(pred), z)])
    yh, jac = evaluate(est / sc, pval)
    J = np.asarray(jac) / sc[None, :]
    yh = np.asarray(yh).ravel()
    cond = float(np.linalg.cond(J))
    if not np.isfinite(cond) or cond > 1e12:
        raise ValueError(f"observation matrix is rank deficient (condition number {cond:.3g}): "
                         f"the data do not excite all of {', '.join(names)}")
    r = y - yh
    sigma = float(np.std(r, ddof=1))
    cov = np.linalg.inv(J.T @ J)
    std = sigma * np.sqrt(np.diag(cov))
    rdiag = np.abs(np.diag(np.linalg.qr(J, mode="r")))
    return IdentificationResult(names=names, estimates=est, std=std, condition_number=cond,
                                abs_diag_r=rdiag, measured=y, predicted=yh, model=model,
                                units=units, solver_status=status,
                                iterations=int(stats.get("iter_count", 0)))


def _as_1d_inf(name, x, n):
    x = np.asarray(x, dtype=float)
    if x.shape != (n,) or np.any(np.isnan(x)):
        raise ValueError(f"{name}: expected {n} numbers (inf allowed), got {x!r}")
    return x


# --------------------------------------------------------------------------- friction fits
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
        Friction law (see the module docstring).
    offset : bool, optional
        Include a constant offset (default: as in :data:`MODELS`).
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
    _check_model(model)
    if units not in ("rotary", "linear"):
        raise ValueError(f"units: expected 'rotary' or 'linear', got {units!r}")
    w = _as_1d("velocity", velocity)
    a = _as_1d("acceleration", acceleration, w.size)
    y = _as_1d("torque", torque, w.size)
    names = model_names(model, offset)
    if initial is not None:
        unknown = set(initial) - set(names)
        if unknown:
            raise ValueError(f"initial: unknown parameter(s) {sorted(unknown)} for model {model!r}")
    lower = np.array([0.0 if nm in _NONNEGATIVE else -np.inf for nm in names])
    upper = np.full(len(names), np.inf)
    if model in _LINEAR:
        X = regressor(model, w, a, offset=offset)
        colnorm = np.linalg.norm(X, axis=0)
        if np.any(colnorm == 0):
            raise ValueError("data do not excite " + ", ".join(np.array(names)[colnorm == 0])
                             + " (an all-zero regressor column)")
        scale = (np.linalg.norm(y) or 1.0) / colnorm
        x0 = np.array([0.0 if initial is None or nm not in initial else float(initial[nm])
                       for nm in names])
        return fit_least_squares(lambda th, row: _dot(th, row), X, y, names=names, initial=x0,
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
    return fit_least_squares(_stribeck_prediction, np.column_stack([a, w]), y, names=names,
                             initial=x0, lower=lower, upper=upper, scale=scale, model=model,
                             units=units, solver_options=solver_options)


def _dot(theta, rows):
    """Linear prediction ``sum_j theta_j * x_j`` over the data rows."""
    out = theta[0] * rows[0]
    for j in range(1, len(rows)):
        out = out + theta[j] * rows[j]
    return out


def identify_run(run, *, model: str = "coulomb_viscous", estimator: str = "butterworth_central",
                 estimator_options: dict | None = None, offset: bool | None = None,
                 border: int = 50, initial: dict | None = None) -> IdentificationResult:
    """Estimate velocity/acceleration from a :class:`~fricctl.datasets.Run` and fit ``model``.

    Parameters
    ----------
    run : fricctl.datasets.Run
        Measured record.
    model : str
        Friction law, see :data:`MODELS`.
    estimator : str
        Name in :data:`fricctl.estimation.ESTIMATORS`.
    estimator_options : dict, optional
        Keyword options of the estimator.
    offset : bool, optional
        Include a constant offset (default: as in :data:`MODELS`).
    border : int
        Samples dropped at each end (estimator end effects) [samples].
    initial : dict, optional
        Starting values, see :func:`fit_friction`.

    Notes
    -----
    Samples whose estimated velocity is exactly zero (the axis at rest, as the
    encoder-based estimators report it) are dropped: an inverse model has no
    friction information there.  No decimation (plain least squares); see
    :func:`idim_ls` for the full EMPS recipe.
    """
    from .estimation import estimate

    if border < 0 or 2 * border >= run.n_samples - 10:
        raise ValueError(f"border: {border} leaves too few of the {run.n_samples} samples")
    est = estimate(run.t, run.position, estimator, **(estimator_options or {}))
    sl = slice(border, run.n_samples - border)
    w, a, y = est.velocity[sl], est.acceleration[sl], run.torque[sl]
    keep = w != 0.0
    if keep.sum() < 10:
        raise ValueError("no motion: fewer than 10 samples with non-zero estimated velocity")
    return fit_friction(w[keep], a[keep], y[keep], model=model, offset=offset, initial=initial,
                        units=run.units)


# --------------------------------------------------------------------------- EMPS recipe
@dataclass(frozen=True, kw_only=True)
class IdimRecipe:
    """Signal processing of the IDIM-LS recipe (EMPS script ``Script_IDIM_LS.m``).

    Defaults are the EMPS ones at 1 kHz: 4th-order zero-phase Butterworth at
    100 Hz (5x the 20 Hz position-loop bandwidth), central differences twice,
    first 49 samples dropped, every column decimated by 10 (MATLAB ``decimate``).
    """

    cutoff: float = field(default=100.0, metadata={"unit": "Hz"})
    """Butterworth cut-off [Hz]."""
    filter_order: int = 4
    """Butterworth order [-]."""
    decimation: int = 10
    """Decimation factor of the parallel filtering [-]."""
    border: int = 49
    """Samples dropped at the start (filter and difference end effects) [samples]."""

    def __post_init__(self):
        if not self.cutoff > 0:
            raise ValueError(f"cutoff: must be positive, got {self.cutoff}")
        if self.filter_order < 1 or self.decimation < 1 or self.border < 0:
            raise ValueError("filter_order and decimation must be >= 1, border >= 0")


def _idim_observations(run, model, offset, recipe: IdimRecipe):
    from .estimation import butterworth_central, decimate

    if model not in _LINEAR:
        raise ValueError(f"model: the IDIM-LS recipe decimates regressor columns, so it needs a "
                         f"linear model ({', '.join(_LINEAR)}), not {model!r}")
    est = butterworth_central(run.t, run.position, cutoff=recipe.cutoff, order=recipe.filter_order)
    sl = slice(recipe.border, None)
    X0 = regressor(model, est.velocity[sl], est.acceleration[sl], offset=offset)
    y0 = np.asarray(run.torque[sl])
    X = np.column_stack([decimate(X0[:, j], recipe.decimation) for j in range(X0.shape[1])])
    y = decimate(y0, recipe.decimation)
    return X0, X, y


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
        Include the offset column (default: as in :data:`MODELS`).
    recipe : IdimRecipe, optional
        Signal processing; default the EMPS one.

    Notes
    -----
    As in the EMPS script, ``abs_diag_r`` comes from the QR factorisation of the
    observation matrix *before* decimation, the condition number after.  Samples
    at rest are kept (``sign(0) = 0``), as in the script.
    """
    recipe = recipe or IdimRecipe()
    _check_model(model)
    X0, X, y = _idim_observations(run, model, offset, recipe)
    names = model_names(model, offset)
    res = fit_least_squares(lambda th, row: _dot(th, row), X, y, names=names,
                            initial=np.zeros(len(names)),
                            lower=[0.0 if nm in _NONNEGATIVE else -np.inf for nm in names],
                            scale=(np.linalg.norm(y) or 1.0) / np.linalg.norm(X, axis=0),
                            model=model, units=run.units)
    rdiag = np.abs(np.diag(np.linalg.qr(X0, mode="r")))
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


def cross_validate(result: IdentificationResult, run, *, recipe: IdimRecipe | None = None) -> CrossValidation:
    """Rebuild the observation matrix on ``run`` with the same recipe and predict.

    This is ``Script_IDIM_LS_CTV.m`` of the EMPS benchmark: no refit, only
    ``y_hat = X_ctv @ theta``; its relative error is the published 5.9824 % on the
    PULSES file.
    """
    if result.model not in _LINEAR:
        raise ValueError("cross_validate: needs a result of idim_ls (a linear model)")
    recipe = recipe or result.recipe or IdimRecipe()
    offset = "offset" in result.names
    _, X, y = _idim_observations(run, result.model, offset, recipe)
    return CrossValidation(measured=y, predicted=X @ result.estimates,
                           condition_number=float(np.linalg.cond(X)))
