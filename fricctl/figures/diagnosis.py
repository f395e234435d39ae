"""Figures of the diagnosis: measured vs simulated, residual against velocity, position,
time and torque, residual spectrum, the forward selection's steps
(:func:`fricctl.diagnose.diagnose` results)."""

from __future__ import annotations

import numpy as np
from scipy import signal

from ..units import units
from ._common import get_ax

__all__ = ["plot_simulation", "plot_residual", "plot_residual_spectrum", "plot_steps",
           "plot_diagnosis"]

_AGAINST = ("velocity", "position", "time", "torque")
#: Most points a residual scatter draws (a longer record is thinned evenly: the cloud's shape
#: is what the eye reads, and drawing 10^5 markers per panel is slow).
MAX_POINTS = 20000


def _thin(mask: np.ndarray) -> np.ndarray:
    """Indices of the True samples of ``mask``, at most :data:`MAX_POINTS`, evenly spread."""
    idx = np.flatnonzero(mask)
    step = max(int(np.ceil(idx.size / MAX_POINTS)), 1)
    return idx[::step]


def _extended_label(result) -> str:
    """``+ a + b`` for the named causes (the extended model's label)."""
    return "+ " + " + ".join(result.causes)


def plot_simulation(result, *, ax=None, quantity: str = "position", span=None):
    """Measured motion and the windowed re-simulation of baseline and extended model.

    Parameters
    ----------
    result : fricctl.diagnose.Diagnosis
    ax : matplotlib.axes.Axes, optional
    quantity : {"position", "velocity"}
        Position [rad] (encoder) or velocity [rad/s] (estimate).
    span : tuple (t0, t1), optional
        Time range to show [s]; default the whole record.

    Returns
    -------
    matplotlib.axes.Axes
    """
    if quantity not in ("position", "velocity"):
        raise ValueError(f"quantity must be 'position' or 'velocity', got {quantity!r}")
    ax = get_ax(ax)
    u = units(result.units)
    t = result.t
    sel = np.ones(t.size, bool) if span is None else (t >= span[0]) & (t <= span[1])
    if quantity == "position":
        meas, b, a = result.position, result.sim_before.q, result.sim_after.q
        ax.plot(t[sel], meas[sel], drawstyle="steps-post", color="k", lw=1.0, label="measured (encoder)")
        ax.set_ylabel(f"position $q$ [{u.position}]")
    else:
        meas, b, a = result.velocity, result.sim_before.omega, result.sim_after.omega
        ax.plot(t[sel], meas[sel], color="k", lw=1.0, label="estimated")
        ax.set_ylabel(rf"velocity $\omega$ [{u.velocity}]")
    ax.plot(t[sel], b[sel], color="tab:red", lw=1.0, label="baseline, simulated")
    if result.cause != "none":
        ax.plot(t[sel], a[sel], color="tab:blue", lw=1.0, ls="--",
                label=f"{_extended_label(result)}, simulated")
    ax.set_xlabel("time $t$ [s]")
    ax.legend(loc="upper right", fontsize="small")
    return ax


def plot_residual(result, against: str = "velocity", *, ax=None, after: bool = False):
    """Equation-error torque residual against velocity, position, time or torque (at most
    :data:`MAX_POINTS` sliding samples, evenly thinned).

    Parameters
    ----------
    result : fricctl.diagnose.Diagnosis
    against : {"velocity", "position", "time", "torque"}
    ax : matplotlib.axes.Axes, optional
    after : bool
        Also draw the residual of the extended model.

    Returns
    -------
    matplotlib.axes.Axes
    """
    if against not in _AGAINST:
        raise ValueError(f"against must be one of {_AGAINST}, got {against!r}")
    ax = get_ax(ax)
    u = units(result.units)
    x = {"velocity": result.velocity, "position": result.position, "time": result.t,
         "torque": result.torque}[against]
    label = {"velocity": rf"velocity $\omega$ [{u.velocity}]",
             "position": f"position $q$ [{u.position}]", "time": "time $t$ [s]",
             "torque": f"recorded torque $T_m$ [{u.torque}]"}[against]
    ok = _thin(~np.isnan(result.residual_before))
    ax.plot(x[ok], result.residual_before[ok], ".", ms=1.5, color="tab:red", alpha=0.5,
            label="baseline")
    if after and result.cause != "none":
        ok2 = _thin(~np.isnan(result.residual_after))
        ax.plot(x[ok2], result.residual_after[ok2], ".", ms=1.5, color="tab:blue", alpha=0.5,
                label=_extended_label(result))
    ax.axhline(0.0, color="0.3", lw=0.8)
    ax.set_xlabel(label)
    ax.set_ylabel(f"torque residual [{u.torque}]")
    ax.legend(loc="upper right", fontsize="small", markerscale=6)
    return ax


def plot_residual_spectrum(result, *, ax=None):
    """Power spectral density (Welch) of the torque residual, baseline and extended.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = get_ax(ax)
    tu = units(result.units).torque
    fs = 1.0 / float(result.t[1] - result.t[0])
    for res, color, lab in ((result.residual_before, "tab:red", "baseline"),
                            (result.residual_after, "tab:blue", _extended_label(result))):
        if lab != "baseline" and result.cause == "none":
            continue
        r = np.nan_to_num(res, nan=0.0)
        f, p = signal.welch(r, fs=fs, nperseg=min(2048, r.size))
        ax.semilogy(f[1:], p[1:], color=color, lw=1.0, label=lab)
    ax.set_xlabel("frequency $f$ [Hz]")
    ax.set_ylabel(f"residual PSD [({tu})$^2$/Hz]")
    ax.legend(loc="upper right", fontsize="small")
    return ax


def plot_steps(result, *, ax=None):
    """The forward selection step by step: held-out torque residual RMS of the model before
    the first step and after each, each bar labelled with the cause and its net score.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = get_ax(ax)
    tu = units(result.units).torque
    names = ["baseline"] + [f"+ {s.cause}" for s in result.steps]
    values = [result.gain.torque_rms_before] + [s.torque_rms_after for s in result.steps]
    bars = ax.bar(range(len(values)), values, color=["tab:red"] + ["tab:blue"] * len(result.steps))
    for bar, step in zip(bars[1:], result.steps):
        ax.annotate(f"{100 * step.score:.0f} %", (bar.get_x() + bar.get_width() / 2,
                                                 bar.get_height()),
                    ha="center", va="bottom", fontsize="small")
    ax.set_xticks(range(len(values)), names, rotation=20)
    ax.set_ylabel(f"held-out torque residual RMS [{tu}]")
    ax.set_xlabel("step of the forward selection (net score above each bar)")
    return ax


def plot_diagnosis(result, *, fig=None):
    """Six panels: position and velocity simulation, residual vs velocity, position,
    time and torque, drawn on ``fig`` (an empty Figure; default: a new pyplot figure
    11 x 8.5 in).  Returns the Figure."""
    if fig is None:
        import matplotlib.pyplot as plt

        fig = plt.figure(figsize=(11, 8.5), layout="constrained")
    axes = fig.subplots(3, 2)
    plot_simulation(result, ax=axes[0, 0], quantity="position")
    plot_simulation(result, ax=axes[0, 1], quantity="velocity")
    for ax, against in zip(axes.ravel()[2:], _AGAINST):
        plot_residual(result, against, ax=ax, after=True)
    fig.suptitle(f"diagnosis: {' + '.join(result.causes)}")
    return fig
