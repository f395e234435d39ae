"""Figures of the measuring chain: velocity estimates (paper Fig. 4 style) and identification fits."""

from __future__ import annotations

import numpy as np

from .. import _validate as v
from ..estimation import DerivativeEstimate
from ..identify import IdentificationResult
from ..units import units as units_of
from ._common import get_ax

__all__ = ["plot_velocity_estimates", "plot_identification"]


def plot_velocity_estimates(estimates, *, raw=None, truth=None, ax=None, units: str = "rotary"):
    """Raw (backward-difference) velocity against filtered estimates, as in the paper's Fig. 4.

    Parameters
    ----------
    estimates : DerivativeEstimate or sequence of DerivativeEstimate
        Filtered estimates (one line each, labelled by ``method``).
    raw : DerivativeEstimate, optional
        The raw estimate, drawn as held samples (``steps-post``) in grey.
    truth : tuple (t, velocity), optional
        True velocity [s], [rad/s] (virtual bench only), drawn dashed.
    ax : matplotlib.axes.Axes, optional
    units : {"rotary", "linear"}
        Axis label unit (rad/s or m/s).

    Returns
    -------
    matplotlib.axes.Axes
    """
    labels = units_of(units)
    ax = get_ax(ax)
    if not isinstance(estimates, (list, tuple)):
        estimates = [estimates]
    for i, est in enumerate(estimates):
        v.instance(f"estimates[{i}]", est, DerivativeEstimate)
    if raw is not None:
        v.instance("raw", raw, DerivativeEstimate)
    if raw is not None:
        ax.plot(raw.t, raw.velocity, drawstyle="steps-post", color="0.6", lw=0.8,
                label=f"raw ({raw.method})")
    for est in estimates:
        ax.plot(est.t, est.velocity, lw=1.2, label=est.method)
    if truth is not None:
        t_true, w_true = truth
        ax.plot(np.asarray(t_true), np.asarray(w_true), "k--", lw=1.0, label="true")
    ax.set_xlabel("time $t$ [s]")
    ax.set_ylabel(rf"velocity $\omega$ [{labels.velocity}]")
    ax.legend(loc="best", fontsize="small")
    return ax


def plot_identification(result, *, t=None, ax=None):
    """Measured and predicted torque (or force) of a fit, with the residual.

    Parameters
    ----------
    result : fricctl.identify.IdentificationResult
    t : array_like, optional
        Times of the fitted samples [s]; default the sample index.
    ax : matplotlib.axes.Axes, optional

    Returns
    -------
    matplotlib.axes.Axes
    """
    v.instance("result", result, IdentificationResult)
    x = np.arange(result.n_samples) if t is None else v.array("t", t, size=result.n_samples)
    ax = get_ax(ax)
    # the regressed quantity is the motor torque T_m (docs/notation.md), a force on a prismatic axis
    name = "motor torque $T_m$" if result.units == "rotary" else "motor force $T_m$"
    unit = units_of(result.units).torque
    ax.plot(x, result.measured, lw=1.2, label="measured")
    ax.plot(x, result.predicted, "--", lw=1.2, label=f"predicted ({result.model or 'custom'})")
    ax.plot(x, result.residual, lw=0.8, color="k", label="residual")
    ax.set_xlabel("time $t$ [s]" if t is not None else "sample $k$ [-]")
    ax.set_ylabel(f"{name} [{unit}]")
    ax.set_title(f"relative error {result.relative_error:.2f} %, fit {result.fit_percent:.1f} %",
                 fontsize="medium")
    ax.legend(loc="best", fontsize="small")
    return ax
