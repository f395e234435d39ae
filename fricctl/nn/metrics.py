"""Accuracy of a friction estimate, with the definitions stated: fit [%], R^2, RMSE.

The paper's "98 % accuracy" has no definition; :func:`fit_percent` and
:func:`r_squared` are the common candidates and differ a lot (R^2 = 0.98 is a
fit of 85.9 %).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _validate as v
from .net import FrictionNet

__all__ = ["fit_percent", "r_squared", "FitReport", "fit_report"]


def _pair(y, yhat):
    y = v.array("y", y, ndim=None).ravel()
    yhat = v.array("yhat", yhat, ndim=None).ravel()
    if y.shape != yhat.shape:
        raise ValueError(f"y and yhat must have the same length, got {y.size} and {yhat.size}")
    if y.size < 2:
        raise ValueError("need at least 2 samples to measure a fit")
    spread = np.linalg.norm(y - y.mean())
    if spread == 0:
        raise ValueError("y is constant: the normalised fit and R^2 are undefined")
    return y, yhat, spread


def fit_percent(y, yhat) -> float:
    """Normalised fit ``100*(1 - ||y - yhat|| / ||y - mean(y)||)`` [%].

    100 % is a perfect fit, 0 % is no better than the mean; it is negative for
    worse.  This is the "fit" of system-identification tools (MATLAB
    ``compare``).  It relates to R^2 by ``fit = 100*(1 - sqrt(1 - R^2))``, so
    R^2 = 0.98 is only a fit of 85.9 %.

    Examples
    --------
    >>> fit_percent([0.0, 1.0, 2.0, 3.0], [0.0, 1.0, 2.0, 3.0])
    100.0
    >>> round(fit_percent([0.0, 1.0, 2.0, 3.0], [1.5, 1.5, 1.5, 1.5]), 6)
    0.0
    """
    y, yhat, spread = _pair(y, yhat)
    return float(100.0 * (1.0 - np.linalg.norm(y - yhat) / spread))


def r_squared(y, yhat) -> float:
    """Coefficient of determination ``1 - ||y - yhat||^2 / ||y - mean(y)||^2`` [-].

    Examples
    --------
    >>> round(r_squared([0.0, 1.0, 2.0, 3.0], [0.0, 1.0, 2.0, 4.0]), 3)
    0.8
    """
    y, yhat, spread = _pair(y, yhat)
    return float(1.0 - np.sum((y - yhat) ** 2) / spread**2)


@dataclass(frozen=True, kw_only=True)
class FitReport:
    """Accuracy of a friction estimate on one set of patterns.

    Notes
    -----
    The paper's "98 % accuracy" has no definition; the two measures here are
    the common candidates and differ a lot (R^2 = 0.98 is a fit of 85.9 %).
    """

    fit_percent: float
    """Normalised fit, 100*(1 - ||e|| / ||y - mean(y)||) [%]."""
    r_squared: float
    """Coefficient of determination [-]."""
    rmse: float
    """Root-mean-square error [N*m]."""
    max_abs_error: float
    """Largest absolute error [N*m]."""
    n: int
    """Number of patterns."""
    outside_envelope: int = 0
    """Patterns outside the net's training box (when computed from a net)."""

    def report(self, units: str = "rotary") -> str:
        """A few readable lines; ``units`` (``"rotary"``/``"linear"``) labels the torque or force."""
        from ..units import units as units_of

        tu = units_of(units).torque
        lines = [f"patterns      {self.n}",
                 f"fit           {self.fit_percent:.2f} %  (100*(1 - ||e||/||y - mean y||))",
                 f"R^2           {self.r_squared:.5f}",
                 f"RMSE          {self.rmse:.4g} {tu}",
                 f"max |error|   {self.max_abs_error:.4g} {tu}"]
        if self.outside_envelope:
            lines.append(f"outside envelope: {self.outside_envelope} patterns")
        return "\n".join(lines)

    def as_dict(self) -> dict:
        """Plain dict (JSON-ready)."""
        return {"fit_percent": self.fit_percent, "r_squared": self.r_squared,
                "rmse": self.rmse, "max_abs_error": self.max_abs_error, "n": self.n,
                "outside_envelope": self.outside_envelope}


def fit_report(y, yhat=None, *, net: FrictionNet | None = None, tm=None, omega=None) -> FitReport:
    """Accuracy of ``yhat`` against ``y``, or of ``net(tm, omega)`` against ``y``.

    Parameters
    ----------
    y : array_like
        Reference friction torque [N*m].
    yhat : array_like, optional
        Estimate [N*m]; give this or ``net``, ``tm`` and ``omega``.
    net : FrictionNet, optional
        Network evaluated (without clipping) at ``tm``, ``omega``.
    tm, omega : array_like, optional
        Inputs of the patterns [N*m], [rad/s].

    Examples
    --------
    >>> rep = fit_report([1.0, 2.0, 3.0, 4.0], [1.0, 2.0, 3.0, 5.0])
    >>> rep.rmse, rep.max_abs_error
    (0.5, 1.0)
    """
    outside = 0
    if net is not None:
        if yhat is not None or tm is None or omega is None:
            raise ValueError("give either yhat, or net with tm and omega")
        v.instance("net", net, FrictionNet)
        yhat = net(tm, omega)
        outside = int(np.count_nonzero(net.outside_envelope(tm, omega)))
    elif yhat is None:
        raise ValueError("give either yhat, or net with tm and omega")
    y, yhat, _ = _pair(y, yhat)
    e = y - yhat
    return FitReport(fit_percent=fit_percent(y, yhat), r_squared=r_squared(y, yhat),
                     rmse=float(np.sqrt(np.mean(e * e))), max_abs_error=float(np.max(np.abs(e))),
                     n=int(y.size), outside_envelope=outside)
