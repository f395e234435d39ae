r"""Second-order relations and step metrics.

The designed closed loop is the standard second-order system without a zero,

.. math::

    \frac{q(s)}{r(s)} = \frac{\omega_n^2}{s^2 + 2\zeta\omega_n s + \omega_n^2},

so its rise time is ``g(zeta) / wn`` with ``g`` the normalised rise time of
:func:`normalized_rise_time` (closed form for 0-100 % and for the time of the first
peak, root finding for 10-90 %).  Any loop, designed or not, is measured the same way: the damping of
its dominant pole pair (:func:`dominant_damping`) and the rise time, overshoot
and settling time of :func:`control.step_info` (:func:`metrics_from_response`,
:func:`step_metrics`), collected in :class:`StepMetrics`.

Dependencies: numpy, scipy, python-control.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import control
import numpy as np
from scipy.optimize import brentq

from .. import _validate as v
from .._json import finite_or_none

__all__ = [
    "RISE_TIME_DEFINITIONS",
    "SETTLING_THRESHOLD",
    "StepMetrics",
    "normalized_rise_time",
    "second_order_metrics",
    "resolve_rise_time_definition",
    "dominant_damping",
    "overshoot_of_damping",
    "second_order_holds",
    "metrics_from_response",
    "step_metrics",
]

#: Allowed rise-time definitions and their ``RiseTimeLimits`` for ``step_info``; ``"peak"`` (the
#: time of the first peak, ``step_info``'s ``PeakTime``) has no limits: None.
RISE_TIME_DEFINITIONS = {"0-100": (0.0, 1.0), "10-90": (0.1, 0.9), "peak": None}
#: The definitions that need an overshoot (a step that reaches, or peaks above, its final value):
#: they exist only for damping < 1.
_UNDERDAMPED_ONLY = ("0-100", "peak")
#: Unit of each :class:`StepMetrics` field.
METRIC_UNITS = {"rise_time": "s", "damping": "-", "overshoot_percent": "%", "settling_time": "s"}
#: Settling band used for the settling time (python-control's default) [-].
SETTLING_THRESHOLD = 0.02


@dataclass(frozen=True, kw_only=True)
class StepMetrics:
    """Step-response metrics of a closed loop (unit step of the reference).

    ``rise_time``, ``overshoot_percent`` and ``settling_time`` come from
    :func:`control.step_info`; ``damping`` is the damping ratio of the dominant
    closed-loop pole pair (for a sampled loop, of its poles mapped by
    ``s = ln(z)/Ts``).  NaN marks a metric that does not exist (e.g. the
    0-100 % rise time of a step that never reaches its final value, or any
    metric of an unstable loop).
    """

    rise_time: float
    """Rise time under the design's definition [s]."""
    damping: float
    """Damping ratio of the dominant closed-loop pole pair [-]."""
    overshoot_percent: float
    """Peak overshoot above the final value, in percent of it [%]."""
    settling_time: float
    """Time after which the step stays within +-2 % of its final value [s]."""

    @classmethod
    def undefined(cls, damping: float = math.nan) -> "StepMetrics":
        """Metrics of a response that has none (unstable or non-finite): all NaN but ``damping``."""
        return cls(rise_time=math.nan, damping=damping, overshoot_percent=math.nan,
                   settling_time=math.nan)

    @property
    def overshoot_damping(self) -> float:
        """Damping ratio of the second-order system with this overshoot [-].

        ``zeta = -ln(M)/sqrt(pi^2 + ln(M)^2)`` with ``M = overshoot/100``; NaN
        without overshoot.  Equals :attr:`damping` for a loop without zeros.
        """
        m = self.overshoot_percent / 100.0
        if not m > 0.0:
            return math.nan
        lm = math.log(m)
        return -lm / math.sqrt(math.pi**2 + lm**2)

    def as_dict(self) -> dict:
        """Each metric as ``{value, unit}`` (:func:`fricctl.units.quantity`); NaN becomes
        ``None`` (JSON has no NaN)."""
        from ..units import quantity

        return {f.name: quantity(finite_or_none(getattr(self, f.name)), METRIC_UNITS[f.name])
                for f in fields(self)}


def _settling_tau(zeta: float) -> float:
    """Normalised 2 % settling time ``wn*ts`` of the standard second-order step (exact)."""
    band = SETTLING_THRESHOLD

    def err(tau):
        return abs(_unit_step(tau, zeta) - 1.0) - band

    if zeta >= 1.0:                        # monotone: the one crossing of 1 - band
        hi = 1.0
        while _unit_step(hi, zeta) < 1.0 - band:
            hi *= 2.0
        return brentq(lambda tau: _unit_step(tau, zeta) - (1.0 - band), 0.0, hi,
                      xtol=1e-14, rtol=1e-13)
    wd = math.sqrt(1.0 - zeta * zeta)
    # |y - 1| <= exp(-zeta*tau)/wd: after tau_env the step stays in the band; the last exit
    # lies within the damped period before it (each period holds two peaks of |y - 1|)
    tau_env = -math.log(band * wd) / zeta
    if tau_env <= 0.0:
        return 0.0
    period = 2.0 * math.pi / wd
    hi = tau_env
    for _ in range(64):
        lo = max(0.0, hi - period)
        grid = np.linspace(lo, hi, 4001)
        e = np.array([err(x) for x in grid])
        above = np.flatnonzero(e >= 0.0)
        if above.size:
            k = above[-1]
            if k == grid.size - 1:
                return float(grid[k])
            return brentq(err, grid[k], grid[k + 1], xtol=1e-14, rtol=1e-13)
        if lo == 0.0:
            return 0.0
        hi = lo
    return tau_env  # pragma: no cover - 64 quiet periods before the envelope cannot happen


def second_order_metrics(wn: float, zeta: float, definition: str) -> StepMetrics:
    """Exact step metrics of ``wn^2/(s^2 + 2 zeta wn s + wn^2)`` from its closed form.

    The rise time is :func:`normalized_rise_time` (NaN for the 0-100 % and peak definitions
    at ``zeta >= 1``, where the step never reaches its final value and has no peak), the overshoot
    ``100*exp(-pi*zeta/sqrt(1 - zeta^2))``, the 2 % settling time the last exit from the
    band, found by root finding on the closed-form step.  No time grid: the cost does not
    depend on how slow or how lightly damped the loop is (a grid fine enough for
    :func:`control.step_info` can need 10^9 points, e.g. a P design with a 10 us rise time).

    Examples
    --------
    >>> m = second_order_metrics(10.0, 0.5, "0-100")
    >>> round(m.rise_time, 5), round(m.overshoot_percent, 4), round(m.settling_time, 4)
    (0.24184, 16.3034, 0.8076)
    """
    wn = v.real("wn", wn, positive=True, unit="rad/s")
    zeta = v.real("zeta", zeta, positive=True)
    v.choice("definition", definition, RISE_TIME_DEFINITIONS)
    if definition in _UNDERDAMPED_ONLY and zeta >= 1.0:
        rise = math.nan
    else:
        rise = normalized_rise_time(zeta, definition) / wn
    overshoot = 100.0 * math.exp(-math.pi * zeta / math.sqrt(1.0 - zeta * zeta)) if zeta < 1.0 else 0.0
    return StepMetrics(rise_time=rise, damping=zeta, overshoot_percent=overshoot,
                       settling_time=_settling_tau(zeta) / wn)


def resolve_rise_time_definition(definition: str | None, zeta: float | None) -> str:
    """The rise-time definition to use for a damping ratio.

    Parameters
    ----------
    definition : {"0-100", "10-90", "peak"} or None
        Requested definition; None picks ``"0-100"`` for ``zeta < 1`` (or no
        damping given) and ``"10-90"`` otherwise.
    zeta : float or None
        Damping ratio [-], or None when not specified.

    Returns
    -------
    str

    Raises
    ------
    ValueError
        An unknown definition, or ``"0-100"`` or ``"peak"`` with ``zeta >= 1`` (such a
        step never reaches its final value, and has no peak).

    Examples
    --------
    >>> resolve_rise_time_definition(None, 1.2)
    '10-90'
    """
    if definition is None:
        return "0-100" if (zeta is None or zeta < 1.0) else "10-90"
    v.choice("rise_time_definition", definition, RISE_TIME_DEFINITIONS)
    if definition in _UNDERDAMPED_ONLY and zeta is not None and zeta >= 1.0:
        what = "0-100 % rise time" if definition == "0-100" else "time of the first peak"
        raise ValueError(f"damping {zeta!r} >= 1 never reaches the final value, so the {what} "
                         "does not exist; use rise_time_definition='10-90'")
    return definition


def _unit_step(tau: float, zeta: float) -> float:
    """Closed-form unit step of wn^2/(s^2 + 2 zeta wn s + wn^2) at wn = 1."""
    if zeta < 1.0:
        wd = math.sqrt(1.0 - zeta * zeta)
        return 1.0 - math.exp(-zeta * tau) * (math.cos(wd * tau)
                                              + zeta / wd * math.sin(wd * tau))
    if zeta == 1.0:
        return 1.0 - math.exp(-tau) * (1.0 + tau)
    r = math.sqrt(zeta * zeta - 1.0)
    p1, p2 = -zeta + r, -zeta - r          # p1 slow, p2 fast
    return 1.0 + (p2 * math.exp(p1 * tau) - p1 * math.exp(p2 * tau)) / (p1 - p2)


def normalized_rise_time(zeta: float, definition: str) -> float:
    """Rise time of the second-order step at wn = 1 rad/s, i.e. ``wn * tr`` [-].

    Parameters
    ----------
    zeta : float
        Damping ratio, > 0 [-] (< 1 for ``"0-100"`` and ``"peak"``).
    definition : {"0-100", "10-90", "peak"}
        Rise-time definition: ``"peak"`` reads "rise time" as the time of the first
        peak (the rise to the top of the first overshoot), not a textbook definition
        but the one reading under which the paper's statements agree
        (``docs/paper_consistency.md``).

    Returns
    -------
    float
        ``wn * tr`` [rad].  Closed form for 0-100 % (Ogata):
        ``(pi - acos(zeta)) / sqrt(1 - zeta^2)``; for the first peak
        ``pi / sqrt(1 - zeta^2)`` (where the step's derivative first vanishes); for
        10-90 % the two crossing times of the closed-form step are found with
        :func:`scipy.optimize.brentq`.

    Examples
    --------
    >>> round(normalized_rise_time(0.5, "0-100"), 4)
    2.4184
    >>> round(normalized_rise_time(0.3, "peak"), 4)
    3.2933
    >>> round(normalized_rise_time(1.0, "10-90"), 4)
    3.3579
    """
    zeta = v.real("zeta", zeta, positive=True)
    definition = resolve_rise_time_definition(definition, zeta)
    if definition == "0-100":
        return (math.pi - math.acos(zeta)) / math.sqrt(1.0 - zeta * zeta)
    if definition == "peak":
        return math.pi / math.sqrt(1.0 - zeta * zeta)
    lo, hi = RISE_TIME_DEFINITIONS[definition]
    if zeta < 1.0:
        # the step rises monotonically up to its first peak at tau = pi/wd
        tau_max = math.pi / math.sqrt(1.0 - zeta * zeta)
    else:
        tau_max = 1.0
        while _unit_step(tau_max, zeta) < hi:
            tau_max *= 2.0
    t_lo = brentq(lambda s: _unit_step(s, zeta) - lo, 0.0, tau_max, xtol=1e-14, rtol=1e-13)
    t_hi = brentq(lambda s: _unit_step(s, zeta) - hi, 0.0, tau_max, xtol=1e-14, rtol=1e-13)
    return t_hi - t_lo


def dominant_damping(poles_s) -> float:
    """Damping ratio of the slowest-decaying pole pair (two reals or a conjugate pair) [-].

    The dominant poles are those whose modes decay slowest: the smallest decay rate
    ``-Re p`` (for a sampled loop mapped by ``s = ln(z)/Ts``, the poles closest to the unit
    circle), not the smallest ``|p|``: a fast-oscillating, lightly damped pair can have a larger
    ``|p|`` than a well-damped real pole and still ring long after that pole has died out.

    Parameters
    ----------
    poles_s : array_like of complex
        Continuous-time poles [rad/s] (non-finite ones are ignored).

    Returns
    -------
    float
        ``-Re p / |p|`` of a dominant complex pair; ``a1 / (2 sqrt(a0))`` of
        ``s^2 + a1 s + a0`` for two dominant real poles; 1 for a single slow real
        pole; negative for a growing complex pair; NaN for an unstable real pole or no pole.

    Notes
    -----
    The poles alone do not say whether the pair dominates the step: a slow pair with a small
    residue rings faintly under a larger, better damped response.  :func:`second_order_holds`
    checks the damping against the step's overshoot.

    Examples
    --------
    >>> round(dominant_damping([-1.0, -4.0]), 4)     # s^2 + 5 s + 4
    1.25
    >>> round(dominant_damping([-160.0, -27.5 + 280j, -27.5 - 280j]), 3)  # the pair decays slower
    0.098
    """
    p = np.asarray(poles_s, complex)
    p = p[np.isfinite(p)]
    if p.size == 0:
        return math.nan
    # slowest decay first (the largest real part); a conjugate pair shares its real part
    order = np.argsort(-p.real, kind="stable")
    p = p[order]
    if p.size == 1:
        return 1.0 if p[0].real < 0 else math.nan
    p1 = p[0]
    if abs(p1.imag) > 1e-9 * max(abs(p1), 1.0):
        # the conjugate of p1 is the other half of the pair
        return float(-p1.real / abs(p1))
    q = p[1]
    if abs(q.imag) <= 1e-9 * max(abs(q), 1.0):
        # two slowest poles real: the equivalent s^2 + a1 s + a0
        a1 = -(p1.real + q.real)
        a0 = p1.real * q.real
        return float(a1 / (2.0 * math.sqrt(a0))) if a0 > 0 else math.nan
    # a single slow real pole, then a complex pair: first-order dominated
    return 1.0 if p1.real < 0 else math.nan


#: Largest relative difference between a loop's dominant-pair damping and the damping its step's
#: overshoot implies for which the loop is called second-order [-].  The paper's designs and
#: their sampled loops agree within a few % (tests/test_design.py); 20 % leaves room for the
#: sampling's zero and delay while a pair that does not dominate misses by a factor (e.g. 0.098
#: against 0.37).
SECOND_ORDER_TOLERANCE = 0.2


def overshoot_of_damping(damping: float) -> float:
    """Overshoot of the standard second-order step with this damping (0 for damping >= 1) [%]."""
    z = v.real("damping", damping, nonneg=True)
    if z >= 1.0:
        return 0.0
    return 100.0 * math.exp(-math.pi * z / math.sqrt(1.0 - z * z))


def second_order_holds(damping: float, overshoot_percent: float) -> bool:
    """Whether a loop's dominant-pair damping and its step's overshoot tell the same story.

    The standard second-order step with damping ``zeta < 1`` overshoots by
    ``exp(-pi zeta / sqrt(1 - zeta^2))``; a loop with no overshoot counts as damping 1.  The loop
    is second-order when the damping its overshoot implies lies within
    :data:`SECOND_ORDER_TOLERANCE` of ``min(damping, 1)``.

    Parameters
    ----------
    damping : float
        Damping of the dominant pole pair (:func:`dominant_damping`) [-].
    overshoot_percent : float
        Measured overshoot of the loop's unit step [%].

    Returns
    -------
    bool
        False also when either is NaN.

    Examples
    --------
    >>> second_order_holds(0.5, 16.3), second_order_holds(0.098, 28.4)
    (True, False)
    """
    if not (math.isfinite(damping) and math.isfinite(overshoot_percent)) or damping <= 0:
        return False
    zp = min(damping, 1.0)
    m = overshoot_percent / 100.0
    if m > 0.0:
        lm = math.log(m)
        z_os = -lm / math.sqrt(math.pi**2 + lm**2)
    else:
        z_os = 1.0
    return abs(min(z_os, 1.0) - zp) <= SECOND_ORDER_TOLERANCE * zp


def metrics_from_response(t, y, *, final: float, definition: str, damping: float) -> StepMetrics:
    """:class:`StepMetrics` of a sampled step response.

    Parameters
    ----------
    t : array_like, shape (n,)
        Times of the samples [s]; :func:`control.step_info` does not interpolate,
        so the grid must be fine against the rise time.
    y : array_like, shape (n,)
        Output [rad] (NaN or inf anywhere gives :meth:`StepMetrics.undefined`).
    final : float
        Final value the metrics refer to [rad].
    definition : {"0-100", "10-90", "peak"}
        Rise-time definition (``"peak"``: ``step_info``'s ``PeakTime``, the time of the
        largest sample, which for a decaying oscillation is the first peak).
    damping : float
        Damping ratio to record (the loop's poles know it, the samples do not) [-].

    Returns
    -------
    StepMetrics
        The rise time is NaN when ``y`` never reaches the upper rise-time limit (for
        ``"peak"``: when it never rises above its final value, no peak).
    """
    limits = RISE_TIME_DEFINITIONS[v.choice("definition", definition, RISE_TIME_DEFINITIONS)]
    y = np.asarray(y, float)
    if not np.all(np.isfinite(y)):
        return StepMetrics.undefined(damping)
    if limits is None:
        # the time of the first peak: the step must overshoot (a monotone step's largest
        # sample is its last, no peak); the other metrics with step_info's default limits
        info = control.step_info(y, timepts=t, final_output=final,
                                 SettlingTimeThreshold=SETTLING_THRESHOLD)
        peaked = y.max() > final and int(np.argmax(y)) < y.size - 1
        return StepMetrics(rise_time=float(info["PeakTime"]) if peaked else math.nan,
                           damping=float(damping), overshoot_percent=float(info["Overshoot"]),
                           settling_time=float(info["SettlingTime"]))
    reached = y.max() >= limits[1] * final
    # a step that never reaches the upper rise-time limit has no rise time, and step_info
    # would index past the end of the record looking for it: ask it for the other metrics
    # with limits the record does reach
    lim = limits if reached else (0.0, 0.5 * max(float(y.max()) / final, 1e-12))
    info = control.step_info(y, timepts=t, final_output=final,
                             SettlingTimeThreshold=SETTLING_THRESHOLD, RiseTimeLimits=lim)
    rise = info["RiseTime"] if reached else math.nan
    return StepMetrics(rise_time=float(rise), damping=float(damping),
                       overshoot_percent=float(info["Overshoot"]),
                       settling_time=float(info["SettlingTime"]))


def step_metrics(sys, rise_time_definition: str = "0-100", *, t_end: float | None = None,
                 points: int = 40_000) -> StepMetrics:
    """Step metrics of any stable continuous SISO loop (e.g. the error-PD loop).

    Parameters
    ----------
    sys : control.TransferFunction or control.StateSpace
        Continuous SISO closed loop with a finite DC gain.
    rise_time_definition : {"0-100", "10-90", "peak"}
        Rise-time limits passed to :func:`control.step_info` (``"peak"``: its ``PeakTime``).
    t_end : float, optional
        End of the time grid [s]; default 12 time constants of the slowest pole.
    points : int
        Grid points (``step_info`` does not interpolate) [-].

    Returns
    -------
    StepMetrics

    Examples
    --------
    >>> import control
    >>> m = step_metrics(control.tf([1.0], [1.0, 1.0, 1.0]))
    >>> round(m.damping, 3), round(m.overshoot_percent, 2)
    (0.5, 16.3)
    """
    v.instance("sys", sys, (control.TransferFunction, control.StateSpace),
               "a SISO python-control TransferFunction or StateSpace")
    if not sys.issiso():
        raise ValueError("sys must be a SISO python-control TransferFunction or StateSpace")
    if sys.isdtime(strict=True):
        raise ValueError("sys must be continuous-time; use a Design's sampled metrics instead")
    v.choice("rise_time_definition", rise_time_definition, RISE_TIME_DEFINITIONS)
    points = v.integer("points", points, low=2)
    poles = np.asarray(control.poles(sys), complex)
    if poles.size == 0 or np.any(poles.real >= 0):
        raise ValueError("sys must be asymptotically stable (all poles in the left half-plane)")
    if t_end is None:
        t_end = 12.0 / np.min(-poles.real)
    else:
        t_end = v.real("t_end", t_end, positive=True, unit="s")
    t = np.linspace(0.0, float(t_end), points)
    resp = control.step_response(sys, t)
    return metrics_from_response(t, np.asarray(resp.outputs), final=float(np.real(sys.dcgain())),
                                 definition=rise_time_definition,
                                 damping=dominant_damping(poles))
