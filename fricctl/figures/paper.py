"""The paper's figures (4-18) from the results of :mod:`fricctl.paper`.

One ``plot_figN(result, ax=None)`` per figure; single-panel ones return the
Axes, multi-panel ones (``ax`` then a sequence of Axes, or None) return the
Figure.  Held torques are drawn with ``drawstyle="steps-post"``; every axis
carries symbol and unit; nothing is shown or saved here.

Each plot registers itself for its figure with ``@paper_plot(N)``: the decorator
checks that Fig. N is in the paper's registry (:func:`fricctl.paper.paper_figures`),
makes the plot refuse any result but that figure's ``result_type``, and adds it to
:data:`PAPER_PLOTS` (figure number -> plot, read-only), which ``fricctl reproduce``
reads.  Adding a figure's plot is one decorated function here.
"""

from __future__ import annotations

import functools
from types import MappingProxyType
from typing import Callable

import matplotlib.pyplot as plt
import numpy as np

from ..paper import SweepResult, paper_figures
from ..paper.coast import CoastResult
from ..paper.runaway import LINEAR_TOLERANCE
from ..paper.fig04 import Fig4Result
from ..paper.fig05 import Fig5Result
from ..paper.fig08 import Fig8Result
from ..paper.fig09 import Fig9Result
from ..paper.fig10 import Fig10Result
from ..paper.fig11 import Fig11Result
from ..paper.fig12 import Fig12Result
from ..paper.fig13 import Fig13Result
from ..paper.fig14 import Fig14Result
from ..paper.fig16 import Fig16Result
from ..paper.fig17 import Fig17Result
from ..paper.fig18 import Fig18Result
from ._common import get_ax, legend_beside
from .core import plot_dead_zone
from .measure import plot_velocity_estimates
from .network import plot_fit

__all__ = ["plot_fig4", "plot_fig5", "plot_fig8", "plot_fig9", "plot_fig10", "plot_fig11",
           "plot_fig12", "plot_fig13", "plot_fig14", "plot_fig16", "plot_fig17", "plot_fig18",
           "plot_sweep", "plot_coast", "PAPER_PLOTS", "paper_plot"]

_DEG = 180.0 / np.pi

_PLOTS: dict[int, Callable] = {}
#: Figure number -> plot function, filled by :func:`paper_plot` (read-only view).
PAPER_PLOTS = MappingProxyType(_PLOTS)


def _check(result, cls):
    if not isinstance(result, cls):
        raise ValueError(f"expected a {cls.__name__}, got {type(result).__name__}")


def paper_plot(number: int) -> Callable[[Callable], Callable]:
    """Register the decorated ``plot(result, ax=None)`` as the plot of paper figure ``number``.

    The returned plot refuses (``ValueError``) a result that is not the figure's
    registered ``result_type``.

    Raises
    ------
    ValueError
        Fig. ``number`` is not in :func:`fricctl.paper.paper_figures`, or already has a plot.
    """
    figure = paper_figures().get(number)
    if figure is None:
        raise ValueError(f"Fig. {number} is not registered in fricctl.paper (no module fig{number:02d})")

    def register(plot: Callable) -> Callable:
        if number in _PLOTS:
            raise ValueError(f"Fig. {number} already has a plot: {_PLOTS[number].__name__}")

        @functools.wraps(plot)
        def checked(result, *args, **kwargs):
            _check(result, figure.result_type)
            return plot(result, *args, **kwargs)

        _PLOTS[number] = checked
        return checked

    return register


def _axes(ax, n, width=9.6, height=3.6):
    if ax is None:
        fig, axes = plt.subplots(1, n, figsize=(width, height), layout="constrained")
        return fig, list(np.atleast_1d(axes))
    axes = list(ax)
    if len(axes) != n:
        raise ValueError(f"ax must be a sequence of {n} Axes, got {len(axes)}")
    return axes[0].figure, axes


def _position(ax, run, label, *, reference=True, **style):
    if reference:
        ax.plot(run.t, _DEG * run.reference, drawstyle="steps-post", color="0.5", ls="--", lw=1,
                label="reference r")
    ax.plot(run.t, _DEG * run.q, label=label, **style)
    ax.set_xlabel("time t [s]")
    ax.set_ylabel("position q [deg]")


@paper_plot(4)
def plot_fig4(result: Fig4Result, ax=None):
    """Raw (backward-difference) and filtered velocity, with the true one (Fig. 4)."""
    ax = plot_velocity_estimates(result.filtered, raw=result.raw,
                                 truth=(result.filtered.t, result.truth_velocity), ax=get_ax(ax))
    ax.set_title(f"Fig. 4: velocity, {result.experiment} (RMS error raw {result.raw_rms:.3g}, "
                 f"filtered {result.filtered_rms:.3g} rad/s)", fontsize="small")
    return ax


@paper_plot(5)
def plot_fig5(result: Fig5Result, ax=None):
    """Training torque sequence and the friction patterns it gives (Fig. 5)."""
    ax = get_ax(ax)
    ax.plot(result.t, result.torque, drawstyle="steps-post", lw=1, label="motor torque $T_m$")
    ax.plot(result.t, result.friction, ".", ms=1.5, label=r"patterns $T_{at} = T_m - I\hat\alpha$")
    ax.plot(result.t, result.friction_true, "k", lw=0.6, alpha=0.6, label="true friction (bench)")
    ax.set_xlabel("time t [s]")
    ax.set_ylabel("torque [N·m]")
    ax.set_title("Fig. 5: open-loop training sequence and experimental friction", fontsize="small")
    ax.legend(loc="best", fontsize="small")
    return ax


@paper_plot(8)
def plot_fig8(result: Fig8Result, ax=None):
    """Experimental against network friction on the held-out patterns (Fig. 8)."""
    ax = plot_fit(result.target, result.predicted, ax=get_ax(ax))
    ax.set_title(f"Fig. 8 (held out): {ax.get_title()}, g = {result.gain_at_rest:.2f}", fontsize="small")
    return ax


def _torques(ax, run, *, which=("cmd", "motor")):
    if "cmd" in which:
        ax.plot(run.t, run.torque_cmd, drawstyle="steps-post", label="control torque $T_c$")
    if "motor" in which:
        ax.plot(run.t, run.torque_motor, drawstyle="steps-post", label="motor torque $T_m$")
    ax.set_xlabel("time t [s]")
    ax.set_ylabel("torque [N·m]")


@paper_plot(9)
def plot_fig9(result: Fig9Result, ax=None):
    """Velocity under an open-loop sinusoid near breakaway, without and with compensation (Fig. 9)."""
    fig, (a0, a1) = _axes(ax, 2)
    for a, run, name, sticks in ((a0, result.without, "without compensation", result.sticks_without),
                                 (a1, result.with_nn, "with NN compensation", result.sticks_with)):
        a.plot(run.t, run.omega, label="velocity ω")
        if run is result.with_nn:
            a.plot(result.linear.t, result.linear.omega, "k--", lw=1, label="linear viscous actuator")
        for i, (s, e) in enumerate(sticks):
            a.axvspan(s, e, color="tab:red", alpha=0.15, lw=0, label="stuck" if i == 0 else None)
        a.set_xlabel("time t [s]")
        a.set_ylabel("velocity ω [rad/s]")
        a.set_title(f"{name}: {len(sticks)} stick intervals", fontsize="small")
        a.legend(loc="best", fontsize="small")
    fig.suptitle(f"Fig. 9: open-loop $T_c$ = {result.amplitude:.3f} N·m · sin(2π·{result.frequency:g} Hz·t)",
                 fontsize="medium")
    return fig


@paper_plot(10)
def plot_fig10(result: Fig10Result, ax=None):
    """Control and motor torque at 10 % of Tmax with compensation, and the dead zones (Fig. 10)."""
    fig, (a0, a1) = _axes(ax, 2)
    _torques(a0, result.with_nn)
    a0.set_title(f"with NN compensation: {result.with_nn.displacement_counts()} counts of motion "
                 f"(without: {result.without.displacement_counts()})", fontsize="small")
    a0.legend(loc="best", fontsize="small")
    plot_dead_zone([result.dead_zone_without, result.dead_zone_with], ax=a1)
    a1.set_title(f"dead zone reduced {result.factor:.1f}x (g = {result.gain_at_rest:.2f})",
                 fontsize="small")
    fig.suptitle("Fig. 10: inside the dead zone", fontsize="medium")
    return fig


@paper_plot(11)
def plot_fig11(result: Fig11Result, ax=None):
    """P step without compensation, with the linear viscous prediction (Fig. 11)."""
    ax = get_ax(ax)
    ax.plot(result.run.t, _DEG * result.linear, "--", label="linear viscous simulation")
    _position(ax, result.run, "joint, no compensation")
    ax.set_title(f"Fig. 11: P step, $e_{{ss}}$ = {_DEG * result.steady_state_error:.2f} deg", fontsize="small")
    ax.legend(loc="best", fontsize="small")
    return ax


@paper_plot(12)
def plot_fig12(result: Fig12Result, ax=None):
    """P step with NN compensation against the linear viscous simulation, dashed (Fig. 12)."""
    ax = get_ax(ax)
    ax.plot(result.run.t, _DEG * result.linear, "k--", label="linear viscous simulation")
    _position(ax, result.run, "NN compensation")
    ax.plot(result.variant.t, _DEG * result.variant.q, lw=1, label=r"estimate $-\,b\,\omega$ (extra)")
    ax.plot(result.ideal.t, _DEG * result.ideal.q, lw=0.8, ls="-.", color="0.4",
            label="ideal estimate (extra)")
    ax.plot(result.ideal_no_viscous.t, _DEG * result.ideal_no_viscous.q, lw=0.8, ls=":", color="C2",
            label=r"ideal $-\,b\,\omega$ (extra)")
    ax.set_title(f"Fig. 12: max $|q - q_{{lin}}|$ = {_DEG * result.max_deviation:.1f} deg",
                 fontsize="small")
    legend_beside(ax)  # six lines that oscillate over the whole plot: no corner is free
    return ax


def _pd_figure(result, ax, title, extra=None):
    fig, (a0, a1) = _axes(ax, 2)
    a0.plot(result.run.t, _DEG * result.linear, "k--", label="linear viscous simulation")
    _position(a0, result.run, "joint")
    a0.legend(loc="best", fontsize="small")
    _torques(a1, result.run)
    if extra is not None:
        extra(a1)
    a1.legend(loc="best", fontsize="small")
    fig.suptitle(title, fontsize="medium")
    return fig


@paper_plot(13)
def plot_fig13(result: Fig13Result, ax=None):
    """PD step without compensation; the residual motor torque and the NN estimate (Fig. 13)."""
    def extra(a):
        a.axhline(result.nn_at_rest, color="C3", ls=":", label=f"NN estimate at rest {result.nn_at_rest:.3f} N·m")
    return _pd_figure(result, ax, f"Fig. 13: PD step, no compensation, $e_{{ss}}$ = "
                      f"{_DEG * result.steady_state_error:.2f} deg", extra)


@paper_plot(14)
def plot_fig14(result: Fig14Result, ax=None):
    """PD step with NN compensation (Fig. 14)."""
    return _pd_figure(result, ax, f"Fig. 14: PD step with NN compensation, $e_{{ss}}$ = "
                      f"{_DEG * result.steady_state_error:.3f} deg")


def _link_figure(result, ax, title):
    fig, (a0, a1) = _axes(ax, 2)
    first = True
    for name, run in result.runs.items():
        _position(a0, run, f"{name}: $e_{{ss}}$ {_DEG * result.steady_state_error[name]:.2f} deg", reference=first)
        a1.plot(run.t, run.torque_motor, drawstyle="steps-post", lw=1, label=f"$T_m$, {name}")
        first = False
    a1.set_xlabel("time t [s]")
    a1.set_ylabel("motor torque $T_m$ [N·m]")
    a0.legend(loc="best", fontsize="small")
    a1.legend(loc="best", fontsize="small")
    fig.suptitle(title, fontsize="medium")
    return fig


@paper_plot(16)
def plot_fig16(result: Fig16Result, ax=None):
    """Aged actuator with link: NN x 0.95, Coulomb and no compensation (Fig. 16)."""
    return _link_figure(result, ax, f"Fig. 16: aged actuator (friction x {result.friction_scale:g}), "
                        f"step {_DEG * result.step:.0f} deg")


@paper_plot(17)
def plot_fig17(result: Fig17Result, ax=None):
    """Step of 0.08 rad with the link (Fig. 17)."""
    return _link_figure(result, ax, f"Fig. 17: step {result.step:g} rad")


@paper_plot(18)
def plot_fig18(result: Fig18Result, ax=None):
    """Sawtooth without and with compensation, plus the stick-slip extra (Fig. 18)."""
    fig, (a0, a1) = _axes(ax, 2)
    a0.plot(result.with_nn.t, _DEG * result.linear, "k--", lw=1, label="linear viscous simulation")
    _position(a0, result.without, "no compensation")
    _position(a0, result.with_nn, "NN compensation", reference=False)
    a0.set_title(f"sawtooth {result.amplitude:g} rad, period {result.period:g} s", fontsize="small")
    a0.legend(loc="best", fontsize="small")
    _position(a1, result.extra_without, "no compensation")
    a1.set_title(f"extra: {result.extra_amplitude:g} rad over {result.extra_period:g} s, "
                 f"{result.extra_restarts} stick-slip cycles", fontsize="small")
    a1.legend(loc="best", fontsize="small")
    fig.suptitle("Fig. 18: sawtooth tracking", fontsize="medium")
    return fig


def plot_sweep(result: SweepResult, ax=None):
    """``|e_ss|`` with NN compensation over friction scale x link inertia; hatched where >= tolerance."""
    _check(result, SweepResult)
    ax = get_ax(ax)
    e = _DEG * result.error_nn
    im = ax.imshow(e, origin="lower", aspect="auto", cmap="viridis",
                   extent=(-0.5, e.shape[1] - 0.5, -0.5, e.shape[0] - 0.5))
    for i in range(e.shape[0]):
        for j in range(e.shape[1]):
            ok = result.within[i, j]
            ax.text(j, i, f"{e[i, j]:.2f}" + ("" if ok else "*"), ha="center", va="center",
                    fontsize="x-small", color="w" if e[i, j] < 0.5 * e.max() else "k")
    ax.set_xticks(range(e.shape[1]), [f"{s:.2f}" for s in result.friction_scales])
    ax.set_yticks(range(e.shape[0]), [f"{j:.4f}" for j in result.link_inertias])
    ax.set_xlabel("friction scale (true / trained) [-]")
    ax.set_ylabel(r"link inertia $I_s$ [kg·m²]")
    ax.figure.colorbar(im, ax=ax, label=r"$|e_{ss}|$ with NN compensation [deg]")
    ax.set_title(f"PD step {_DEG * result.step:.0f} deg: * = $|e_{{ss}}| \\geq$ {_DEG * result.tolerance:.2f} deg",
                 fontsize="small")
    return ax


def plot_coast(result: CoastResult, ax=None):
    """The coast test: velocity after a torque pulse, against the viscous decay it must stay under."""
    _check(result, CoastResult)
    ax = get_ax(ax)
    r = result.run
    ax.plot(r.t, r.omega, label="velocity ω, compensated")
    ax.plot(result.linear.t, result.linear.omega, "k--", lw=1, label="linear viscous actuator")
    after = r.t >= result.t_end - 1e-12
    w0 = abs(result.omega_end)
    fm = r.info.friction_model
    b = min(fm.viscous_pos, fm.viscous_neg) * fm.scale
    decay = np.exp(-(b / r.info.params.total_inertia) * (r.t[after] - result.t_end))
    env = w0 * decay + LINEAR_TOLERANCE * w0
    sign = 1.0 if result.omega_end >= 0 else -1.0
    ax.plot(r.t[after], sign * env, color="C3", ls=":",
            label=f"allowed: viscous decay + {100 * LINEAR_TOLERANCE:.0f} %")
    ax.axvline(result.t_end, color="0.5", lw=0.8, ls="-.", label="pulse ends")
    ax.set_xlabel("time t [s]")
    ax.set_ylabel("velocity ω [rad/s]")
    ax.set_title(f"coast test (extra): {result.pulse_torque:.2f} N·m for {result.pulse_duration:g} s, then "
                 f"Tc = 0: {'decays' if result.passed else 'RUNS AWAY'}", fontsize="small")
    ax.legend(loc="best", fontsize="small")
    return ax
