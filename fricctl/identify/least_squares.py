r"""Least squares posed in CasADi, and its result with the IDIM-LS statistics.

Every fit is a CasADi NLP solved by IPOPT over *scaled* variables
``theta = scale * z`` with bounds.  :func:`fit_least_squares` is the generic
entry point: any per-sample prediction written in CasADi symbols.  Statistics
follow the IDIM-LS report of the EMPS benchmark (Janot, Gautier & Brunot 2019):
``std_j = sigma * sqrt(((J^T J)^-1)_jj)`` with ``sigma`` the sample standard
deviation of the residual, relative std in %, condition number of the
observation (Jacobian) matrix, relative error ``100*||y - yhat|| / ||y||``.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from .. import _validate as v
from .._json import finite_or_none
from ..units import units as units_of
from .models import implausible, inverse_dynamics, parameter_unit

__all__ = ["IdentificationResult", "fit_least_squares", "linear_prediction"]


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
    """``|diag(R)|`` of the QR factorisation of the observation matrix (EMPS prints it)."""
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
    recipe: "IdimRecipe | None" = None  # noqa: F821 (fricctl.identify.idim.IdimRecipe)
    """Signal recipe of :func:`~fricctl.identify.idim_ls`, or None."""
    at_bound: np.ndarray = None
    """Per parameter: the estimate sits on one of its bounds (e.g. a friction coefficient
    held at 0): the record pushes it beyond what is physical, so it is not identified by
    this record.  Default: none."""
    method: str = "IDIM-LS"
    """The estimator: ``"IDIM-LS"``, ``"IDIM-IV"`` or ``"DIDIM"`` (the report's title)."""
    warnings: tuple = ()
    """What the fit cannot vouch for, one sentence each (also in the JSON)."""

    def __post_init__(self):
        object.__setattr__(self, "method", v.text("method", self.method, empty=False))
        object.__setattr__(self, "warnings", tuple(v.text("warnings[]", w) for w in self.warnings))
        if self.at_bound is None:
            object.__setattr__(self, "at_bound", np.zeros(len(self.names), dtype=bool))
        ab = np.array(self.at_bound, dtype=bool)
        ab.setflags(write=False)
        object.__setattr__(self, "at_bound", ab)
        for name in ("estimates", "std", "abs_diag_r", "measured", "predicted"):
            x = np.array(getattr(self, name), dtype=float)
            x.setflags(write=False)
            object.__setattr__(self, name, x)
        object.__setattr__(self, "names", tuple(self.names))
        units_of(self.units)  # "rotary" or "linear", else ValueError naming `units`

    # statistics ---------------------------------------------------------------
    @property
    def parameters(self) -> dict[str, float]:
        """Name -> estimate."""
        return {n: float(x) for n, x in zip(self.names, self.estimates)}

    @property
    def relative_std(self) -> np.ndarray:
        """``100 * std / |estimate|`` [%] (inf for an estimate of 0 with a std, NaN for an
        estimate of 0 with none: undefined, which the report prints as ``-``)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return 100.0 * self.std / np.abs(self.estimates)

    @property
    def identified(self) -> np.ndarray:
        """Per parameter: not at a bound and its standard deviation below its magnitude.

        A parameter whose 1-sigma interval contains 0, or that sits on a bound, is not
        identified by this record (the record does not excite it, or contradicts the model);
        nor is one whose value the model cannot mean (:func:`~fricctl.identify.models.implausible`:
        a breakaway level below the Coulomb level).
        """
        bad = implausible(self.model, self.parameters)
        with np.errstate(invalid="ignore"):
            return ((~self.at_bound) & (self.std < np.abs(self.estimates))
                    & np.array([n not in bad for n in self.names], dtype=bool))

    def notes(self) -> tuple:
        """Per parameter: why it is not identified by this record, or ``""``."""
        out, bad = [], implausible(self.model, self.parameters)
        for n, ab, ok, s, x in zip(self.names, self.at_bound, self.identified, self.std,
                                   self.estimates):
            if ab:
                out.append("at its bound: not identified by this record")
            elif n in bad:
                out.append(f"{bad[n]}: not identified by this record")
            elif not ok:
                out.append(f"std {s:.3g} >= |value| {abs(x):.3g}: not identified by this record")
            else:
                out.append("")
        return tuple(out)

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
        """``100 * (1 - ||y - yhat|| / ||y - mean(y)||)`` [%] (normalised RMSE fit); NaN for a
        constant measurement (no variation to explain)."""
        spread = float(np.linalg.norm(self.measured - self.measured.mean()))
        if spread == 0.0:
            return math.nan
        return float(100.0 * (1.0 - self.error_norm / spread))

    # presentation -------------------------------------------------------------
    def report(self) -> str:
        """Text report laid out like the EMPS IDIM-LS script output."""
        w = max(len(n) for n in self.names)
        lines = [f"{self.method}: model {self.model or 'custom'}, {self.n_samples} samples",
                 f"{'':<10}{'':<{w}}   {'estimate':>12} {'std':>10} {'rel. std':>9}"]
        for n, x, s, r, note in zip(self.names, self.estimates, self.std, self.relative_std,
                                    self.notes()):
            unit = parameter_unit(n, self.units)
            tail = f"   ({note})" if note else ""
            rel = f"{r:8.4f} %" if not np.isnan(r) else f"{'-':>8}  "  # 0/0: undefined
            lines.append(f"Parameter {n:<{w}} : {x:12.4f} {s:10.4f} {rel}   [{unit}]{tail}")
        lines += ["", "Absolute value of the diagonal element of R"]
        lines += [f"Parameter {n:<{w}} : {d:12.4f}" for n, d in zip(self.names, self.abs_diag_r)]
        lines += [f"Condition number of the observation matrix: {self.condition_number:.4f}", "",
                  f"Error norm : {self.error_norm:.4f}",
                  f"Relative error (%): {self.relative_error:.4f}",
                  f"Deviation of error: {self.error_std:.4f}",
                  f"Fit (%): {self.fit_percent:.4f}"]
        lines += [f"Warning: {w}" for w in self.warnings]
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
            "parameters": {n: {"value": float(x), "std": finite_or_none(s),
                               "unit": parameter_unit(n, self.units), "at_bound": bool(ab),
                               "identified": bool(ok), "note": note}
                           for n, x, s, ab, ok, note in zip(self.names, self.estimates, self.std,
                                                            self.at_bound, self.identified,
                                                            self.notes())},
            "fit_percent": finite_or_none(self.fit_percent),
            "relative_error_percent": self.relative_error,
            "residual_rms": self.residual_rms,
            "condition_number": self.condition_number,
            "solver_status": self.solver_status,
            "method": self.method,
            "warnings": list(self.warnings),
        }

    def to_json(self) -> str:
        """:meth:`as_dict` as a JSON string (standard JSON: undefined values are null)."""
        return json.dumps(self.as_dict(), indent=2, allow_nan=False)


def linear_prediction(theta, rows):
    """Linear prediction ``sum_j theta_j * x_j`` over the data rows (CasADi symbols).

    The ``prediction`` of :func:`fit_least_squares` for a regressor matrix, one
    column per parameter.
    """
    out = theta[0] * rows[0]
    for j in range(1, len(rows)):
        out = out + theta[j] * rows[j]
    return out


def _bounds(name: str, x, p: int, default: float) -> np.ndarray:
    """Bounds: ``p`` real numbers, +-inf allowed (no bound), NaN refused."""
    if x is None:
        return np.full(p, default)
    b = v.array(name, x, size=p, finite=False)
    if np.any(np.isnan(b)):
        raise ValueError(f"{name} holds NaN at index {int(np.flatnonzero(np.isnan(b))[0])} "
                         "(use -inf/inf for no bound)")
    return b


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
        ``lambda th, x: th[0] * x[0] + th[1] * casadi.sign(x[1])``, or
        :func:`linear_prediction` for a regressor matrix.
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
    units_of(units)
    data = v.array("data", data, ndim=None)
    if data.ndim == 1:
        data = data[:, None]
    if data.ndim != 2:
        raise ValueError(f"data: expected shape (N, m), got {data.shape}")
    n, m = data.shape
    y = v.array("y", y, size=n)
    # a value whose square overflows makes the column norms (and the scaling) inf or 0
    for label, col in [(f"the regressor of {names[j]}" if m == p else f"data column {j}", data[:, j])
                       for j in range(m)] + [("y (the torque)", y)]:
        big = float(np.max(np.abs(col))) if col.size else 0.0
        if big > 1e150:
            raise ValueError(f"{label} reaches {big:.3g}: too large to fit (its square overflows "
                             "double precision); check the record's units and scale")
    if np.ptp(y) == 0:
        raise ValueError("y is constant over the record (e.g. a torque that is zero throughout): "
                         "nothing to identify")
    if n <= p:
        raise ValueError(f"need more samples ({n}) than parameters ({p})")
    x0 = v.array("initial", initial, size=p)
    lb = _bounds("lower", lower, p, -np.inf)
    ub = _bounds("upper", upper, p, np.inf)
    if np.any(lb > ub):
        raise ValueError("bounds: lower exceeds upper for " + ", ".join(np.array(names)[lb > ub]))
    if scale is None:
        sc = np.where(np.abs(x0) > 0, np.abs(x0), 1.0)
    else:
        sc = v.array("scale", scale, size=p)
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
    # IPOPT relaxes bounds by a factor 1e-8 of the *scaled* variable by default; with a large
    # scale that let inertia and viscous come out negative: the bounds are kept exactly
    opts = {"print_level": 0, "tol": 1e-12, "max_iter": 500, "sb": "yes",
            "bound_relax_factor": 0.0, "honor_original_bounds": "yes"}
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
    est = np.clip(np.asarray(sol["x"]).ravel() * sc, lb, ub)
    # on a bound to IPOPT's tolerance (1e-8 of the scaled variable): held exactly there
    at_lb = np.isfinite(lb) & (est - lb <= 1e-7 * sc)
    at_ub = np.isfinite(ub) & (ub - est <= 1e-7 * sc)
    est = np.where(at_lb, lb, np.where(at_ub, ub, est))
    at_bound = at_lb | at_ub
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
                                iterations=int(stats.get("iter_count", 0)), at_bound=at_bound)
