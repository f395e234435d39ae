"""Figures for :mod:`fricctl.nn`: friction map, training history, fit (paper Fig. 8)."""

from __future__ import annotations

import numpy as np

from .. import _validate as v
from ..nn.metrics import fit_percent, r_squared
from ..nn.net import FrictionNet
from ..nn.train.core import TrainingHistory
from ._common import get_ax

__all__ = ["plot_friction_map", "plot_training_history", "plot_fit"]


def plot_friction_map(net: FrictionNet, *, ax=None, tm_values=None, omega_margin: float = 0.25,
                      points: int = 401):
    """Estimated friction ``Tat_hat`` against velocity for several motor torques.

    Each curve is ``net(Tm, omega)`` for one ``Tm``; it is solid inside the
    training envelope and dotted outside, where the paper finds the net does not
    generalise.  The envelope's velocity range is shaded.

    Parameters
    ----------
    net : FrictionNet
        The trained network.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; a new figure otherwise.
    tm_values : array_like, optional
        Motor torques of the curves [N*m]; default five values spanning the
        envelope's torque range.
    omega_margin : float
        Velocity range drawn beyond the envelope on each side, as a fraction of
        the envelope's width [-].
    points : int
        Velocities per curve [-].

    Returns
    -------
    matplotlib.axes.Axes
    """
    v.instance("net", net, FrictionNet)
    omega_margin = v.real("omega_margin", omega_margin, nonneg=True)
    points = v.integer("points", points, low=2)
    lo, hi = net.envelope_low, net.envelope_high
    if tm_values is None:
        tm_values = np.linspace(lo[0], hi[0], 5)
    tm_values = np.atleast_1d(v.array("tm_values", tm_values, ndim=None))
    if tm_values.ndim != 1:
        raise ValueError(f"tm_values must be a 1-D array [N*m], got shape {tm_values.shape}")
    ax = get_ax(ax)
    width = hi[1] - lo[1]
    omega = np.linspace(lo[1] - omega_margin * width, hi[1] + omega_margin * width, points)
    ax.axvspan(lo[1], hi[1], color="0.9", zorder=0, label=r"training envelope ($\omega$)")
    for k, tm in enumerate(tm_values):
        y = net(tm, omega)
        out = net.outside_envelope(tm, omega)
        color = f"C{k % 10}"
        y_in = np.where(out, np.nan, y)
        ax.plot(omega, y_in, color=color, label=f"$T_m$ = {tm:.3g} N·m"
                + (" (outside envelope)" if tm < lo[0] or tm > hi[0] else ""))
        ax.plot(omega, np.where(out, y, np.nan), color=color, ls=":")
    ax.set_xlabel(r"velocity $\omega$ [rad/s]")
    ax.set_ylabel(r"estimated friction $\hat T_{at}$ [N*m]")
    ax.set_title(f"2-{net.hidden}-1 friction network (dotted: outside the envelope)")
    ax.axhline(0.0, color="k", lw=0.5)
    ax.legend(fontsize="small")
    return ax


def plot_training_history(history: TrainingHistory, *, ax=None, against: str = "step"):
    """Training loss (mean squared error) on a log scale.

    Parameters
    ----------
    history : TrainingHistory
        From any trainer of :mod:`fricctl.nn.train` (``result.history``).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; calling again on the same axes overlays another run.
    against : {'step', 'time'}
        Horizontal axis: epochs / iterations, or wall time [s] (to compare trainers).

    Returns
    -------
    matplotlib.axes.Axes
    """
    v.instance("history", history, TrainingHistory)
    v.choice("against", against, ("step", "time"))
    ax = get_ax(ax)
    if against == "step":
        x = np.arange(history.loss.size)
        ax.set_xlabel(f"{history.step} [-]")
    else:
        x = history.elapsed
        ax.set_xlabel("wall time [s]")
    ax.semilogy(x, history.loss, label=f"{history.trainer} (final {history.loss[-1]:.3g})")
    ax.set_ylabel(r"training MSE [(N*m)$^2$]")
    ax.legend(fontsize="small")
    return ax


def plot_fit(target, predicted, *, ax=None, time=None):
    """Measured versus network friction over the patterns (the paper's Fig. 8).

    Parameters
    ----------
    target : array_like
        Friction from the patterns ("experimental") [N*m].
    predicted : array_like
        Network estimate at the same patterns [N*m].
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; a new figure otherwise.
    time : array_like, optional
        Time of each pattern [s]; the pattern index otherwise.

    Returns
    -------
    matplotlib.axes.Axes
        The title states the fit and R^2 (definitions in :mod:`fricctl.nn`).
    """
    y = v.array("target", target, ndim=None, finite=False)  # fit_percent names NaN and inf
    yhat = v.array("predicted", predicted, ndim=None, finite=False)
    if y.ndim != 1 or yhat.shape != y.shape:
        raise ValueError(f"target and predicted must be 1-D of the same length, got "
                         f"{y.shape} and {yhat.shape}")
    fit = fit_percent(y, yhat)  # also rejects NaN and constant targets
    r2 = r_squared(y, yhat)
    ax = get_ax(ax)
    if time is None:
        x = np.arange(y.size)
        ax.set_xlabel("pattern index [-]")
    else:
        x = v.array("time", time, ndim=1, size=y.size)
        ax.set_xlabel("time t [s]")
    ax.plot(x, y, color="k", lw=1.0, label=r"patterns $T_{at}$")
    ax.plot(x, yhat, color="C3", lw=1.0, ls="--", label=r"network $\hat T_{at}$")
    ax.set_ylabel("friction torque [N*m]")
    ax.set_title(f"fit {fit:.1f} %, R$^2$ = {r2:.4f}")
    ax.legend(fontsize="small")
    return ax
