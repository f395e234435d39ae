"""Figures of the measuring chain: velocity estimates (paper Fig. 4 style) and identification fits."""

from __future__ import annotations

import numpy as np

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
    ax = get_ax(ax)
    if not isinstance(estimates, (list, tuple)):
        estimates = [estimates]
    if raw is not None:
        ax.plot(raw.t, raw.velocity, drawstyle="steps-post", color="0.6", lw=0.8,
                label=f"raw ({raw.method})")
    for est in estimates:
        ax.plot(est.t, est.velocity, lw=1.2, label=est.method)
    if truth is not None:
        t, v = truth
        ax.plot(np.asarray(t), np.asarray(v), "k--", lw=1.0, label="true")
    unit = "rad/s" if units == "rotary" else "m/s"
    ax.set_xlabel("time $t$ [s]")
    ax.set_ylabel(rf"velocity $\omega$ [{unit}]")
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
    ax = get_ax(ax)
    x = np.arange(result.n_samples) if t is None else np.asarray(t, dtype=float)
    if x.size != result.n_samples:
        raise ValueError(f"t: length {x.size} differs from the fit's {result.n_samples} samples")
    unit, name = ("N*m", r"torque $\tau$") if result.units == "rotary" else ("N", "force $F$")
    ax.plot(x, result.measured, lw=1.2, label="measured")
    ax.plot(x, result.predicted, "--", lw=1.2, label=f"predicted ({result.model or 'custom'})")
    ax.plot(x, result.residual, lw=0.8, color="k", label="residual")
    ax.set_xlabel("time $t$ [s]" if t is not None else "sample $k$ [-]")
    ax.set_ylabel(f"{name} [{unit}]")
    ax.set_title(f"relative error {result.relative_error:.2f} %, fit {result.fit_percent:.1f} %",
                 fontsize="medium")
    ax.legend(loc="best", fontsize="small")
    return ax
