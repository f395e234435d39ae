r"""P and PD gains from rise time and damping: :func:`design_p`, :func:`design_pd`.

Both design on the linear viscous plant ``1/(s (I s + b))`` and verify the
result twice, on the continuous loop and on the sampled-data loop of the core
simulator (:class:`~fricctl.design.loops.LinearLoop`).  A
:class:`~fricctl.design.DesignWarning` is issued when the sampled loop's rise
time or damping differs from the continuous design by more than 10 %, or when a
P design misses its non-priority specification by more than 10 %.

The plant is an :class:`~fricctl.params.ActuatorParams` (``total_inertia``,
``viscous``, ``sample_time``; rotary) or a :class:`~fricctl.plant.JointModel` (your
own actuator: ``inertia``, :attr:`~fricctl.plant.JointModel.viscous`, ``sample_time``,
and its units: a linear axis gives Kp [N/m] and Kd [N*s/m]).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import control
from scipy.optimize import brentq

from .. import _validate as v
from ..params import ActuatorParams
from ..plant.model import JointModel
from ..units import units as units_of
from .loops import LinearLoop
from .result import Design, DesignWarning
from .second_order import (normalized_rise_time, overshoot_of_damping,
                           resolve_rise_time_definition)

__all__ = ["WARN_TOLERANCE", "design_p", "design_pd"]

#: Relative tolerance beyond which a missed spec or a sampled-loop change warns [-].
WARN_TOLERANCE = 0.10
_PRIORITIES = ("rise_time", "damping")
#: Below this overshoot the 0-100 % rise time is ill-conditioned (warning hint) [%].
_ILL_CONDITIONED_OVERSHOOT = 2.0


@dataclass(frozen=True, kw_only=True)
class _Plant:
    """What a design reads of its plant."""

    total_inertia: float
    viscous: float
    sample_time: float
    units: str


def _plant(params) -> _Plant:
    v.instance("params", params, (ActuatorParams, JointModel), "an ActuatorParams or a JointModel")
    if isinstance(params, ActuatorParams):
        return _Plant(total_inertia=params.total_inertia, viscous=params.viscous,
                      sample_time=params.sample_time, units="rotary")
    if params.sample_time is None:
        raise ValueError("sample_time: the model has none (null); the design's sampled-loop "
                         "check needs the controller's sample time")
    return _Plant(total_inertia=params.inertia, viscous=params.viscous,
                  sample_time=params.sample_time, units=params.units)


def _specs(params, rise_time, damping) -> tuple:
    """Checked (plant, rise_time, damping); a spec may be None (not given)."""
    plant = _plant(params)
    if rise_time is not None:
        rise_time = v.real("rise_time", rise_time, positive=True, unit="s")
    if damping is not None:
        damping = v.real("damping", damping, positive=True)
    return plant, rise_time, damping


def _rel(a, b):
    return abs(a - b) / abs(b) if b else math.inf


def _finish(*, law, kp, kd, params, rise_time, damping, priority, definition, extra_warnings):
    loop = LinearLoop(kp=kp, kd=kd, inertia=params.total_inertia, viscous=params.viscous,
                      sample_time=params.sample_time)
    inertia, viscous, ts = loop.inertia, loop.viscous, loop.sample_time
    wn, zeta = loop.wn, loop.zeta
    achieved = loop.continuous_metrics(definition)
    # horizon of the sampled check: three settling times, or three rise times when the step
    # rises slower than it settles (an overdamped 10-90 % rise); a 0-100 % rise time far
    # beyond the settling time (zeta -> 1, overshoot -> 0) is ill-conditioned and not waited for
    rise = achieved.rise_time if math.isfinite(achieved.rise_time) else 0.0
    t_end = 3.0 * max(achieved.settling_time, rise if rise <= 5.0 * achieved.settling_time else 0.0)
    sampled = loop.sampled_metrics(definition, t_end)
    msgs = list(extra_warnings)
    if not loop.sampled_stable():
        u = units_of(params.units)
        msgs.append(f"the sampled loop at Ts = {ts:g} s is unstable (Kp = {kp:.4g} {u.stiffness}, "
                    f"Kd = {kd:.4g} {u.viscous}); slow the design down")
    else:
        if not math.isfinite(sampled.damping):
            # stable, but its slowest pair does not shape the step (sampled_metrics)
            zp = loop.sampled_pole_damping()
            msgs.append(
                f"sampled loop (Ts = {ts:g} s) is not second-order: its slowest-decaying pole "
                f"pair has damping {zp:.3g} (alone it would overshoot "
                f"{overshoot_of_damping(max(zp, 0.0)):.3g} %) but the step overshoots "
                f"{sampled.overshoot_percent:.3g} %; no single pair dominates, so no damping is "
                f"given for it: judge it by its rise time, overshoot and settling time")
        for name, unit in (("rise_time", " s"), ("damping", "")):
            c, s = getattr(achieved, name), getattr(sampled, name)
            if name == "damping" and not math.isfinite(s):
                continue                       # said above: not second-order
            if name == "rise_time" and not math.isfinite(s):
                # no number to compare: say what the sampled step lacks
                what = ("has no peak: its step never rises above its final value"
                        if definition == "peak" else
                        f"never reaches the top of its {definition} % rise")
                msgs.append(f"sampled loop (Ts = {ts:g} s) {what}, so it has no {definition} "
                            f"rise time (the continuous design's is {c:.4g} s)")
                continue
            if not math.isfinite(s) or _rel(s, c) > WARN_TOLERANCE:
                msg = (f"sampled loop (Ts = {ts:g} s) {name.replace('_', ' ')} {s:.4g}{unit} "
                       f"differs from the continuous design's {c:.4g}{unit} by more than "
                       f"{WARN_TOLERANCE:.0%}")
                if name == "rise_time" and definition == "0-100" \
                        and achieved.overshoot_percent < _ILL_CONDITIONED_OVERSHOOT:
                    # near zeta = 1 the step creeps up to its final value, so the first
                    # crossing of 100 % moves a lot for a tiny change; say so, with the
                    # 10-90 % comparison that is not ill-conditioned
                    c9 = loop.continuous_metrics("10-90")
                    s9 = loop.sampled_metrics("10-90", t_end)
                    msg += (f" (overshoot {achieved.overshoot_percent:.2g} % < "
                            f"{_ILL_CONDITIONED_OVERSHOOT:g} %: the 0-100 % rise time is "
                            f"ill-conditioned here; the 10-90 % rise times are "
                            f"{c9.rise_time:.4g} s and {s9.rise_time:.4g} s)")
                msgs.append(msg)
    for msg in msgs:
        # stacklevel 3: the caller of design_p / design_pd
        warnings.warn(msg, DesignWarning, stacklevel=3)
    cl = control.tf([kp], [inertia, viscous + kd, kp])
    return Design(law=law, kp=float(kp), kd=float(kd), inertia=inertia, viscous=viscous,
                  units=params.units,
                  sample_time=ts, requested_rise_time=rise_time, requested_damping=damping,
                  priority=priority, rise_time_definition=definition, wn=wn, zeta=zeta,
                  closed_loop=cl, sampled_closed_loop=loop.sampled(),
                  achieved=achieved, sampled=sampled, warnings=tuple(msgs))


def design_pd(params: ActuatorParams | JointModel, *, rise_time: float, damping: float,
              rise_time_definition: str | None = None) -> Design:
    """PD (rate feedback) gains for a rise time and a damping ratio.

    ``Tc = Kp (r - q) - Kd omega_hat`` on ``G = 1/(s (I s + b))`` gives the
    closed loop ``wn^2 / (s^2 + 2 zeta wn s + wn^2)`` with
    ``Kp = I wn^2`` and ``Kd = 2 zeta wn I - b``; ``wn`` follows from the rise
    time (:func:`~fricctl.design.normalized_rise_time`).

    Parameters
    ----------
    params : ActuatorParams or JointModel
        Plant: ``total_inertia`` (actuator + link), ``viscous``; ``sample_time``
        for the sampled-data check (a model: ``inertia``, the mean viscous
        coefficient of both directions, ``sample_time``; its units).
    rise_time : float
        Requested rise time, > 0 [s].
    damping : float
        Requested damping ratio, > 0 [-].
    rise_time_definition : {"0-100", "10-90", "peak"}, optional
        Default ``"0-100"`` for damping < 1, ``"10-90"`` otherwise (required
        for damping >= 1); ``"peak"``: the time of the first peak.

    Returns
    -------
    Design

    Raises
    ------
    ValueError
        For a non-positive or non-finite spec, an impossible definition, or a
        design that needs Kd < 0 (the viscous friction alone already damps
        more than requested).

    Warns
    -----
    DesignWarning
        When the sampled loop's rise time or damping differs by more than 10 %.

    Notes
    -----
    Linear viscous model only (see :class:`~fricctl.design.Design`).

    Examples
    --------
    >>> from fricctl.params import paper_actuator
    >>> d = design_pd(paper_actuator().with_link(), rise_time=0.22, damping=0.5)
    >>> round(d.kp, 4), round(d.kd, 4)
    (0.9021, 0.0652)
    """
    params, rise_time, damping = _specs(params, rise_time, damping)
    if rise_time is None or damping is None:
        raise ValueError("a PD design needs both rise_time and damping")
    definition = resolve_rise_time_definition(rise_time_definition, damping)
    inertia, viscous = params.total_inertia, params.viscous
    wn = normalized_rise_time(damping, definition) / rise_time
    kp = inertia * wn * wn
    kd = 2.0 * damping * wn * inertia - viscous
    if kd < 0.0:
        raise ValueError(
            f"this PD needs a negative Kd = {kd:.4g} {units_of(params.units).viscous}: the viscous "
            f"friction b = {viscous:g} {units_of(params.units).viscous} alone gives damping "
            f"{viscous / (2.0 * wn * inertia):.3g} > {damping:g} at wn = {wn:.4g} rad/s; "
            "ask for more damping or a faster rise, or use P")
    return _finish(law="pd", kp=kp, kd=kd, params=params, rise_time=rise_time, damping=damping,
                   priority=None, definition=definition, extra_warnings=())


def design_p(params: ActuatorParams | JointModel, *, rise_time: float | None = None,
             damping: float | None = None, priority: str = "rise_time",
             rise_time_definition: str | None = None) -> Design:
    """P gain for a rise time, a damping ratio, or both with a priority.

    With one gain, ``Kp/(I s^2 + b s + Kp)`` has ``2 zeta wn = b/I`` fixed:
    the damping alone gives ``Kp = b^2 / (4 I zeta^2)``; the rise time alone
    is met by solving ``tr = 2 I zeta g(zeta) / b`` for zeta
    (:func:`scipy.optimize.brentq`, g = :func:`~fricctl.design.normalized_rise_time`).

    Parameters
    ----------
    params : ActuatorParams or JointModel
        Plant and sample time (see :func:`design_pd`).
    rise_time : float, optional
        Requested rise time, > 0 [s].
    damping : float, optional
        Requested damping ratio, > 0 [-].
    priority : {"rise_time", "damping"}
        With both specs: the one that is met exactly; the other is reported as
        achieved (``Design.achieved``) and warns when it misses by > 10 %.
    rise_time_definition : {"0-100", "10-90", "peak"}, optional
        Default ``"0-100"`` when the (requested) damping is < 1, else ``"10-90"``;
        ``"peak"``: the time of the first peak.

    Returns
    -------
    Design

    Warns
    -----
    DesignWarning
        Missed non-priority spec (> 10 %) or sampled loop off by > 10 %.

    Examples
    --------
    >>> from fricctl.params import paper_actuator
    >>> d = design_p(paper_actuator(), rise_time=0.2, damping=0.3)
    >>> round(d.kp, 4), round(d.zeta, 4)
    (0.2769, 0.3)
    """
    params, rise_time, damping = _specs(params, rise_time, damping)
    if rise_time is None and damping is None:
        raise ValueError("a P design needs rise_time, damping, or both")
    v.choice("priority", priority, _PRIORITIES)
    inertia, viscous = params.total_inertia, params.viscous
    if viscous <= 0.0:
        raise ValueError("a P design on G = 1/(s (I s + b)) needs viscous b > 0: with b = 0 "
                         "the loop is undamped for every Kp")
    both = rise_time is not None and damping is not None
    use_rise = rise_time is not None and (priority == "rise_time" or damping is None)
    definition = resolve_rise_time_definition(rise_time_definition, damping)
    if use_rise:
        # 0-100 % and the first peak exist only below zeta = 1
        zeta_cap = 1.0 - 1e-12 if definition in ("0-100", "peak") else 1e3

        def f(z):
            return 2.0 * inertia * z * normalized_rise_time(z, definition) / viscous - rise_time

        lo = 1e-9
        if f(zeta_cap) < 0.0:
            raise ValueError(f"rise_time {rise_time:g} s is too slow for a P loop on this plant")
        zeta = brentq(f, lo, zeta_cap, xtol=1e-15, rtol=1e-13)
    else:
        zeta = damping
    wn = viscous / (2.0 * inertia * zeta)
    kp = inertia * wn * wn
    extra = []
    if both:
        if priority == "rise_time":
            miss = _rel(zeta, damping)
            if miss > WARN_TOLERANCE:
                extra.append(f"P with rise-time priority: damping {zeta:.4g} misses the "
                             f"requested {damping:g} by {miss:.0%} (one gain, one spec)")
        else:
            tr = normalized_rise_time(zeta, definition) / wn
            miss = _rel(tr, rise_time)
            if miss > WARN_TOLERANCE:
                extra.append(f"P with damping priority: rise time {tr:.4g} s misses the "
                             f"requested {rise_time:g} s by {miss:.0%} (one gain, one spec)")
    return _finish(law="p", kp=kp, kd=0.0, params=params, rise_time=rise_time, damping=damping,
                   priority=priority if both else None, definition=definition,
                   extra_warnings=extra)
