"""Plots of simulated runs, friction laws and the dead zone."""

from __future__ import annotations

import numpy as np

from ._common import get_ax

__all__ = ["plot_response", "plot_torques", "plot_friction_law", "plot_stuck", "plot_dead_zone"]

_UNITS = {"rad": 1.0, "deg": 180.0 / np.pi}


def _scale(unit):
    if unit not in _UNITS:
        raise ValueError(f"unit must be 'rad' or 'deg', got {unit!r}")
    return _UNITS[unit]


def plot_response(result, *, ax=None, label=None, unit: str = "deg", measured: bool = False,
                  reference: bool = True, **style):
    """Position against time, with the (held) reference.

    Parameters
    ----------
    result : fricctl.simulate.SimResult
    unit : {"deg", "rad"}
        Unit of the position axis.
    measured : bool
        Plot the encoder reading instead of the true position.
    reference : bool
        Also draw the reference (steps-post, dashed grey).
    **style
        Passed to ``ax.plot`` for the position line.
    """
    ax = get_ax(ax)
    k = _scale(unit)
    q = result.q_meas if measured else result.q
    sym = "y" if measured else "q"
    if reference and np.any(result.reference != 0):
        ax.plot(result.t, k * result.reference, drawstyle="steps-post", color="0.5", ls="--", lw=1,
                label="reference r")
    ax.plot(result.t, k * q, label=label or ("encoder y" if measured else "position q"), **style)
    ax.set_xlabel("time t [s]")
    ax.set_ylabel(f"position {sym} [{unit}]")
    ax.legend(loc="best", fontsize="small")
    return ax


def plot_torques(result, *, ax=None, estimate: bool = True):
    """Control torque Tc, motor torque Tm (held: steps-post) and the friction estimate."""
    ax = get_ax(ax)
    ax.plot(result.t, result.torque_cmd, drawstyle="steps-post", label="control torque $T_c$")
    ax.plot(result.t, result.torque_motor, drawstyle="steps-post", label="motor torque $T_m$")
    if estimate and np.any(result.friction_est != 0):
        ax.plot(result.t, result.friction_est, drawstyle="steps-post", lw=1, label=r"friction estimate $\hat T_{at}$")
    ax.set_xlabel("time t [s]")
    ax.set_ylabel("torque [N·m]")
    ax.legend(loc="best", fontsize="small")
    return ax


def plot_friction_law(model, *, ax=None, omega_max: float = 1.0, n: int = 801, label=None, **style):
    """Sliding friction torque against velocity, with the breakaway band at rest."""
    ax = get_ax(ax)
    w = np.linspace(-omega_max, omega_max, n)
    w = w[w != 0]
    neg, pos = w[w < 0], w[w > 0]
    line, = ax.plot(pos, model.torque(pos), label=label or r"sliding friction $T_{at}(\omega)$", **style)
    ax.plot(neg, model.torque(neg), color=line.get_color(), **{k: v for k, v in style.items() if k != "color"})
    ax.plot([0, 0], [-model.breakaway(-1), model.breakaway(1)], color=line.get_color(), lw=3, alpha=0.5,
            label="at rest: any $T_{at}$ in the breakaway band")
    ax.axhline(0, color="0.8", lw=0.8)
    ax.axvline(0, color="0.8", lw=0.8)
    ax.set_xlabel("velocity ω [rad/s]")
    ax.set_ylabel("friction torque $T_{at}$ [N·m]")
    ax.legend(loc="best", fontsize="small")
    return ax


def plot_stuck(result, *, ax=None, color="tab:red", alpha=0.12, label: str = "stuck (ω = 0)",
               band: tuple[float, float] = (0.0, 1.0)):
    """Shade the intervals where the joint is at rest.

    The first interval carries ``label``; an existing legend of ``ax`` (e.g. drawn by
    :func:`plot_response`) is redrawn so that the shading has its entry in it.  ``band``
    is the vertical extent as fractions of the axes' height (a strip per run when several
    runs share the axes, where full-height shades would mix their colours).
    """
    ax = get_ax(ax)
    first = True
    for a, b in result.stuck_intervals():
        ax.axvspan(a, b + result.sample_time, ymin=band[0], ymax=band[1], color=color,
                   alpha=alpha, lw=0, label=label if first else None)
        first = False
    if ax.get_xlabel() == "":
        ax.set_xlabel("time t [s]")
    if ax.get_legend() is not None:
        ax.legend(loc="best", fontsize="small")
    return ax


def plot_dead_zone(dead_zones, *, ax=None):
    """Encoder motion against sinusoid amplitude (fraction of Tmax) for each compensation.

    Parameters
    ----------
    dead_zones : DeadZone or list of DeadZone
        From :func:`fricctl.bench.experiments.dead_zone`.
    """
    ax = get_ax(ax)
    if not isinstance(dead_zones, (list, tuple)):
        dead_zones = [dead_zones]
    for dz in dead_zones:
        x = 100 * dz.amplitudes / dz.max_torque
        line, = ax.plot(x, np.maximum(dz.counts, 0.5), label=f"{dz.compensator}: dead zone "
                        f"{100 * dz.fraction:.2f} % of Tmax")
        ax.axvline(100 * dz.fraction, color=line.get_color(), ls=":", lw=1)
    if dead_zones:
        ax.axhline(dead_zones[0].threshold_counts, color="0.5", ls="--", lw=1, label="'moves' threshold")
    ax.set_yscale("log")
    ax.set_xlabel("control torque amplitude [% of Tmax]")
    ax.set_ylabel("encoder motion, peak to peak [counts]")
    ax.legend(loc="best", fontsize="small")
    return ax
