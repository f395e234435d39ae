"""Figures for :mod:`fricctl.design`: root locus and verified step response."""

from __future__ import annotations

import math

import control
import numpy as np

from .. import _validate as v
from ..design import Design, RISE_TIME_DEFINITIONS, SETTLING_THRESHOLD, linear_response
from ._common import get_ax, legend_beside

__all__ = ["plot_root_locus", "plot_step"]


def _check(design):
    v.instance("design", design, Design, "a fricctl.design.Design")


def plot_root_locus(design: Design, *, ax=None, gain_range: float = 4.0, points: int = 400):
    """Root locus in Kp with the design point marked.

    The locus is that of ``1 + Kp / (s (I s + b + Kd))``: Kp varies from 0 to
    ``gain_range`` times the design value while the velocity feedback Kd stays
    at its design value (for P, Kd = 0 and this is the classic locus of
    ``1/(s (I s + b))``).  The closed-loop poles of the design are marked, with
    the ray of constant damping zeta through them.

    Parameters
    ----------
    design : Design
        The controller.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; a new figure otherwise.
    gain_range : float
        Largest Kp on the locus, as a multiple of the design Kp [-].
    points : int
        Number of gains on the locus [-].

    Returns
    -------
    matplotlib.axes.Axes
    """
    _check(design)
    gain_range = v.real("gain_range", gain_range)
    if not gain_range > 1.0:
        raise ValueError(f"gain_range must be > 1, got {gain_range!r}")
    points = v.integer("points", points, low=2)
    ax = get_ax(ax)
    loop = control.tf([1.0], [design.inertia, design.viscous + design.kd, 0.0])
    gains = np.linspace(0.0, gain_range * design.kp, points)
    loci = np.asarray(control.root_locus_map(loop, gains).loci)
    for j in range(loci.shape[1]):
        ax.plot(loci[:, j].real, loci[:, j].imag, color="C0",
                label=r"locus, $K_p$ from 0" if j == 0 else None)
    ol = np.asarray(control.poles(loop))
    ax.plot(ol.real, ol.imag, "x", color="k", ms=8, label="open-loop poles")
    cl = np.asarray(control.poles(design.closed_loop))
    ax.plot(cl.real, cl.imag, "o", color="C3", ms=8, mfc="none", mew=2,
            label=f"design: $K_p$ = {design.kp:.3g} N·m/rad, $\\zeta$ = {design.zeta:.2f}")
    if design.zeta < 1.0:
        r = 1.3 * design.wn
        ang = math.acos(design.zeta)
        for sgn in (1, -1):
            ax.plot([0.0, -r * math.cos(ang)], [0.0, sgn * r * math.sin(ang)], ":",
                    color="C3", lw=1, label=f"$\\zeta$ = {design.zeta:.2f}" if sgn == 1 else None)
    ax.axhline(0.0, color="0.7", lw=0.5)
    ax.axvline(0.0, color="0.7", lw=0.5)
    ax.set_xlabel(r"Re $s$ [rad/s]")
    ax.set_ylabel(r"Im $s$ [rad/s]")
    ax.set_title(f"{design.law.upper()} root locus")
    legend_beside(ax)  # the locus climbs through every corner a "best" legend would pick
    return ax


def plot_step(design: Design, *, ax=None, t_end: float | None = None, sampled: bool = True):
    """Unit step of the designed loop with its spec markers.

    Draws the reference (held, ``steps-post``), the continuous closed loop,
    and (``sampled=True``) the sampled-data loop at Ts between samples, with
    markers for the achieved rise time (and the requested one), the overshoot
    peak and the settling time with its +-2 % band.

    Parameters
    ----------
    design : Design
        The controller.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; a new figure otherwise.
    t_end : float, optional
        End of the plot [s]; default 1.5 x the settling time.
    sampled : bool
        Also draw the sampled-data loop.

    Returns
    -------
    matplotlib.axes.Axes
    """
    _check(design)
    ax = get_ax(ax)
    a = design.achieved
    if t_end is None:
        t_end = 1.5 * max(a.settling_time, design.sampled.settling_time
                          if math.isfinite(design.sampled.settling_time) else 0.0,
                          a.rise_time)
    t_end = v.real("t_end", t_end, positive=True, unit="s")
    ts = design.sample_time
    n = int(math.ceil(t_end / ts)) * 20 + 1
    t = np.arange(n) * (ts / 20)
    r = np.ones_like(t)
    ax.plot(t, r, color="0.5", lw=1, drawstyle="steps-post", label="reference r")
    ax.plot(t, linear_response(design, t, r), color="C0", label="continuous")
    if v.flag("sampled", sampled):
        ax.plot(t, linear_response(design, t, r, sampled=True), color="C1", ls="--",
                label=f"sampled, Ts = {ts:g} s")
    limits = RISE_TIME_DEFINITIONS[design.rise_time_definition]
    # the requested rise time is marked at the level the definition reads: its upper limit, or
    # for the time of the first peak the peak itself
    hi = 1.0 + a.overshoot_percent / 100.0 if limits is None else limits[1]
    ax.axvline(a.rise_time, color="C2", lw=1, ls=":",
               label=f"rise time {a.rise_time:.3f} s ({design.rise_time_definition})")
    if design.requested_rise_time is not None:
        ax.plot([design.requested_rise_time], [hi], "v", color="C2",
                label=f"requested rise time {design.requested_rise_time:g} s")
    if a.overshoot_percent > 0:
        peak = 1.0 + a.overshoot_percent / 100.0
        ax.axhline(peak, color="C3", lw=1, ls=":",
                   label=f"overshoot {a.overshoot_percent:.2f} %")
    band = SETTLING_THRESHOLD
    ax.axhspan(1.0 - band, 1.0 + band, color="0.85", alpha=0.5, lw=0,
               label=f"+-{band:.0%} band")
    ax.axvline(a.settling_time, color="C4", lw=1, ls=":",
               label=f"settling time {a.settling_time:.3f} s")
    ax.set_xlabel(r"$t$ [s]")
    ax.set_ylabel(r"$q/r$ [-]")
    ax.set_title(f"{design.law.upper()} step: Kp = {design.kp:.3g} N*m/rad, "
                 f"Kd = {design.kd:.3g} N*m*s/rad")
    ax.legend(loc="lower right", fontsize="small")
    return ax
