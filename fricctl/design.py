r"""P and PD gains from rise time and damping, on the linear viscous model.

The paper designs every controller "as if the system was linear (only viscous
friction)".  The plant is the rigid joint with viscous friction only, load side:

.. math::

    G(s) = \frac{q(s)}{T_m(s)} = \frac{1}{s\,(I s + b)},

with ``I = params.total_inertia`` (actuator + link) and ``b = params.viscous``.

Control laws
------------
* P: ``Tc = Kp*(r - q)``.  Closed loop ``Kp / (I s^2 + b s + Kp)``.  One gain, so
  only one of the two specifications can be imposed (``priority``).
* PD: ``Tc = Kp*(r - q) - Kd*omega_hat``, the derivative acts on the *measured
  velocity* (rate feedback), not on the error.  The closed loop
  ``Kp / (I s^2 + (b + Kd) s + Kp)`` is the standard second-order system with
  no zero, so the closed-form relations hold exactly:
  ``Kp = I*wn^2`` and ``Kd = 2*zeta*wn*I - b``.
* For teaching, :meth:`Design.error_pd_closed_loop` gives the loop of a PD
  acting on the error, ``(Kp + Kd s)(r - q)``: the same poles, plus a zero at
  ``-Kp/Kd`` that adds overshoot.

Rise time
---------
The rise-time definition is always explicit: ``"0-100"`` (Ogata's definition
for underdamped systems, first time the step reaches its final value; the
default when zeta < 1) or ``"10-90"`` (required when zeta >= 1, where the step
never reaches its final value).  For 0-100 the closed form is
``wn = (pi - acos(zeta)) / (tr*sqrt(1 - zeta^2))``; for 10-90 the normalised
rise time ``wn*tr`` is found with :func:`scipy.optimize.brentq` on the
closed-form step response.

Verification
------------
Every :class:`Design` carries the *achieved* step metrics, measured with
:func:`control.step_info` (with ``RiseTimeLimits`` set from the definition) on a
time grid of at least 2000 points per rise time, because ``step_info`` does not
interpolate between samples; and the same metrics of the *sampled-data loop*
of the core simulator (zero-order hold at ``Ts``, backward-difference velocity,
one sample of computation delay; see :func:`sampled_loop`).  A
:class:`DesignWarning` is issued when the sampled loop's rise time or damping
differs from the continuous design by more than 10 %, or when a P design misses
its non-priority specification by more than 10 %.

Dependencies: :mod:`fricctl.params`, numpy, scipy, python-control (which imports
matplotlib on import: this module is the one non-plotting module that loads it).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, fields

import control
import numpy as np
from scipy.optimize import brentq

from .params import ActuatorParams, paper_actuator

__all__ = [
    "DesignWarning",
    "StepMetrics",
    "Design",
    "RISE_TIME_DEFINITIONS",
    "design_p",
    "design_pd",
    "normalized_rise_time",
    "plant_tf",
    "sampled_loop",
    "step_metrics",
    "linear_response",
    "paper_designs",
    "design_table",
]

#: Allowed rise-time definitions and their ``RiseTimeLimits`` for ``step_info``.
RISE_TIME_DEFINITIONS = {"0-100": (0.0, 1.0), "10-90": (0.1, 0.9)}
#: Relative tolerance beyond which a missed spec or a sampled-loop change warns [-].
WARN_TOLERANCE = 0.10
#: Settling band used for the settling time (python-control's default) [-].
SETTLING_THRESHOLD = 0.02
#: Time-grid points per rise time for the continuous step metrics [-].
_POINTS_PER_RISE = 2000
#: Sub-steps per sample used to evaluate the sampled loop between samples [-].
_SUBSTEPS = 20
_PRIORITIES = ("rise_time", "damping")
#: Below this overshoot the 0-100 % rise time is ill-conditioned (warning hint) [%].
_ILL_CONDITIONED_OVERSHOOT = 2.0


class DesignWarning(UserWarning):
    """A design that is valid but misses a specification by more than 10 %."""


# ---------------------------------------------------------------------------
# results
# ---------------------------------------------------------------------------
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
        """Metrics as a plain dict; NaN becomes ``None`` (JSON has no NaN)."""
        return {f.name: _json_float(getattr(self, f.name)) for f in fields(self)}


@dataclass(frozen=True, kw_only=True, eq=False)
class Design:
    """A P or PD position controller designed on the linear viscous model.

    Build it with :func:`design_p` or :func:`design_pd`.

    Notes
    -----
    The design and both verifications use the linear viscous model only:
    Coulomb and static friction, torque saturation (+-Tmax), encoder
    quantisation and joint flexibility are left out.  That is the paper's
    method; the nonlinear simulation shows what those omissions cost.
    """

    law: str
    """``"p"`` or ``"pd"`` (PD with the derivative on the measured velocity)."""
    kp: float
    """Proportional gain Kp [N*m/rad]."""
    kd: float
    """Velocity-feedback gain Kd [N*m*s/rad]; 0 for P."""
    inertia: float
    """Total inertia I of the design model (actuator + link) [kg*m^2]."""
    viscous: float
    """Viscous coefficient b of the design model [N*m*s/rad]."""
    sample_time: float
    """Sample time Ts of the sampled-data check [s]."""
    requested_rise_time: float | None
    """Requested rise time, or None when not given (P only) [s]."""
    requested_damping: float | None
    """Requested damping ratio, or None when not given (P only) [-]."""
    priority: str | None
    """P with both specs: the one imposed (``"rise_time"``/``"damping"``); else None."""
    rise_time_definition: str
    """``"0-100"`` or ``"10-90"``."""
    wn: float
    """Natural frequency of the continuous closed loop [rad/s]."""
    zeta: float
    """Damping ratio of the continuous closed loop [-]."""
    closed_loop: control.TransferFunction
    """Continuous closed loop q/r (python-control, no zero)."""
    sampled_closed_loop: control.StateSpace
    """Sampled-data closed loop q_k/r_k at Ts (see :func:`sampled_loop`)."""
    achieved: StepMetrics
    """Step metrics of the continuous closed loop."""
    sampled: StepMetrics
    """Step metrics of the sampled-data loop (evaluated between samples too)."""
    warnings: tuple[str, ...] = ()
    """Messages of the :class:`DesignWarning` issued while designing."""

    @property
    def rise_time_limits(self) -> tuple[float, float]:
        """``RiseTimeLimits`` for :func:`control.step_info` [-]."""
        return RISE_TIME_DEFINITIONS[self.rise_time_definition]

    def error_pd_closed_loop(self) -> control.TransferFunction:
        """Closed loop of a PD acting on the error, ``(Kp + Kd s)(r - q)``.

        ``(Kd s + Kp) / (I s^2 + (b + Kd) s + Kp)``: the poles of this design
        plus a zero at ``-Kp/Kd`` that makes the step faster and adds
        overshoot.  For teaching only; the paper's PD (and :attr:`closed_loop`)
        uses rate feedback.
        """
        return control.tf([self.kd, self.kp],
                          [self.inertia, self.viscous + self.kd, self.kp])

    def report(self) -> str:
        """A readable multi-line summary with units."""
        def spec(v, unit):
            return "-" if v is None else f"{v:.4g} {unit}".rstrip()

        law = {"p": "P: Tc = Kp (r - q)",
               "pd": "PD (rate feedback): Tc = Kp (r - q) - Kd omega_hat"}[self.law]
        lines = [
            f"{law}",
            f"  plant        I = {self.inertia:.6g} kg*m^2, b = {self.viscous:.6g} N*m*s/rad",
            f"  requested    rise time {spec(self.requested_rise_time, 's')} "
            f"({self.rise_time_definition}), damping {spec(self.requested_damping, '')}"
            + (f", priority {self.priority}" if self.priority else ""),
            f"  gains        Kp = {self.kp:.6g} N*m/rad, Kd = {self.kd:.6g} N*m*s/rad",
            f"  closed loop  wn = {self.wn:.6g} rad/s, zeta = {self.zeta:.4g}",
            f"  {'':12} {'rise [s]':>10} {'damping':>9} {'OS [%]':>9} {'settle [s]':>11}",
        ]
        for name, m in (("continuous", self.achieved),
                        (f"Ts={self.sample_time:g} s", self.sampled)):
            lines.append(f"  {name:12} {m.rise_time:10.4f} {m.damping:9.4f} "
                         f"{m.overshoot_percent:9.3f} {m.settling_time:11.4f}")
        for w in self.warnings:
            lines.append(f"  warning: {w}")
        return "\n".join(lines)

    def as_dict(self) -> dict:
        """JSON-ready dict (the CLI's ``--json`` object)."""
        return {
            "law": self.law,
            "kp": self.kp,
            "kd": self.kd,
            "inertia": self.inertia,
            "viscous": self.viscous,
            "sample_time": self.sample_time,
            "requested": {"rise_time": self.requested_rise_time,
                          "damping": self.requested_damping,
                          "priority": self.priority},
            "rise_time_definition": self.rise_time_definition,
            "wn": self.wn,
            "zeta": self.zeta,
            "achieved": self.achieved.as_dict(),
            "sampled": self.sampled.as_dict(),
            "warnings": list(self.warnings),
        }


def _json_float(v):
    if v is None:
        return None
    v = float(v)
    return v if math.isfinite(v) else None


# ---------------------------------------------------------------------------
# argument checks
# ---------------------------------------------------------------------------
def _check_params(params) -> None:
    if not isinstance(params, ActuatorParams):
        raise ValueError(f"params must be an ActuatorParams, got {type(params).__name__}")


def _check_spec(name: str, value, unit: str):
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
        raise ValueError(f"{name} must be a real number, got {value!r}")
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"{name} must be finite, got {value!r}")
    if not value > 0.0:
        what = "a damping ratio <= 0 gives an unstable or undamped loop" if name == "damping" \
            else "a rise time must be positive"
        raise ValueError(f"{name} must be > 0{unit}, got {value!r}: {what}")
    return value


def _resolve_definition(definition, zeta):
    if definition is None:
        return "0-100" if (zeta is None or zeta < 1.0) else "10-90"
    if definition not in RISE_TIME_DEFINITIONS:
        raise ValueError(f"rise_time_definition must be one of "
                         f"{', '.join(map(repr, RISE_TIME_DEFINITIONS))}, got {definition!r}")
    if definition == "0-100" and zeta is not None and zeta >= 1.0:
        raise ValueError(f"damping {zeta!r} >= 1 never reaches the final value, so the 0-100 % "
                         "rise time does not exist; use rise_time_definition='10-90'")
    return definition


# ---------------------------------------------------------------------------
# second-order relations
# ---------------------------------------------------------------------------
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
        Damping ratio, > 0 [-] (< 1 for ``"0-100"``).
    definition : {"0-100", "10-90"}
        Rise-time definition.

    Returns
    -------
    float
        ``wn * tr`` [rad].  Closed form for 0-100 % (Ogata):
        ``(pi - acos(zeta)) / sqrt(1 - zeta^2)``; for 10-90 % the two crossing
        times of the closed-form step are found with :func:`scipy.optimize.brentq`.

    Examples
    --------
    >>> round(normalized_rise_time(0.5, "0-100"), 4)
    2.4184
    >>> round(normalized_rise_time(1.0, "10-90"), 4)
    3.3579
    """
    zeta = _check_spec("damping", zeta, "")
    definition = _resolve_definition(definition, zeta)
    if definition == "0-100":
        return (math.pi - math.acos(zeta)) / math.sqrt(1.0 - zeta * zeta)
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


def plant_tf(params: ActuatorParams) -> control.TransferFunction:
    """The design plant ``1 / (s (I s + b))``, I = actuator + link, load side.

    Examples
    --------
    >>> from fricctl.params import paper_actuator
    >>> g = plant_tf(paper_actuator())
    >>> [round(float(c), 7) for c in g.den[0][0]]
    [0.0028653, 0.0169, 0.0]
    """
    _check_params(params)
    return control.tf([1.0], [params.total_inertia, params.viscous, 0.0])


def _closed_loop_ss(kp, kd, inertia, viscous) -> control.StateSpace:
    """Continuous rate-feedback loop, state (q, omega), input r, output q."""
    a = [[0.0, 1.0], [-kp / inertia, -(viscous + kd) / inertia]]
    return control.ss(a, [[0.0], [kp / inertia]], [[1.0, 0.0]], [[0.0]])


# ---------------------------------------------------------------------------
# sampled-data loop of the core simulator
# ---------------------------------------------------------------------------
def _sampled_loop_matrices(kp, kd, inertia, viscous, ts):
    """(A, B, C) of the sampled loop; state (q, omega, Tm, y_prev); outputs (q, Tm)."""
    plant = control.ss([[0.0, 1.0], [0.0, -viscous / inertia]], [[0.0], [1.0 / inertia]],
                       [[1.0, 0.0]], [[0.0]])
    pd_ = control.c2d(plant, ts, method="zoh")
    ad, bd = np.asarray(pd_.A), np.asarray(pd_.B)
    c = np.array([[1.0, 0.0]])
    # Tc_k = Kp (r_k - y_k) - Kd (y_k - y_{k-1})/Ts ; Tm_{k+1} = Tc_k ; yprev_{k+1} = y_k
    k_y = -(kp + kd / ts)
    k_prev = kd / ts
    a = np.zeros((4, 4))
    a[:2, :2] = ad
    a[:2, 2:3] = bd
    a[2, :2] = k_y * c[0]
    a[2, 3] = k_prev
    a[3, :2] = c[0]
    b = np.array([[0.0], [0.0], [kp], [0.0]])
    cout = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]])
    return a, b, cout


def sampled_loop(design: Design | None = None, *, kp: float | None = None,
                 kd: float = 0.0, params: ActuatorParams | None = None,
                 torque_output: bool = False) -> control.StateSpace:
    """Discrete closed loop of the core simulator's sampled-data controller.

    Timing (the core loop's): at ``t_k = k*Ts`` the encoder reads
    ``y_k = q(t_k)``; ``omega_hat_k = (y_k - y_{k-1})/Ts`` with
    ``y_{-1} = y_0``; ``Tc_k = Kp (r_k - y_k) - Kd omega_hat_k``; the torque
    computed at ``t_k`` is held over ``[t_{k+1}, t_{k+2})`` (one sample of
    computation delay) and the torque over ``[t_0, t_1)`` is 0.  The plant is
    discretised with :func:`control.c2d` (``'zoh'``), which is exact for a
    held input.

    Parameters
    ----------
    design : Design, optional
        Take gains, inertia, viscous and Ts from it; otherwise give ``kp``,
        ``kd`` and ``params``.
    kp, kd : float, optional
        Gains [N*m/rad], [N*m*s/rad].
    params : ActuatorParams, optional
        Plant (``total_inertia``, ``viscous``) and ``sample_time``.
    torque_output : bool
        Also output the held motor torque Tm_k (second output) [N*m].

    Returns
    -------
    control.StateSpace
        ``dt = Ts``; input r_k [rad]; output q_k [rad] (and Tm_k); state
        ``(q, omega, Tm, y_prev)``, so the initial state of a loop at rest at
        ``q0`` is ``(q0, 0, 0, q0)``.

    Notes
    -----
    Linear viscous plant only: no saturation, no quantisation, no Coulomb or
    static friction.
    """
    if design is not None:
        if not isinstance(design, Design):
            raise ValueError(f"design must be a Design, got {type(design).__name__}")
        if kp is not None or params is not None:
            raise ValueError("give either design or (kp, kd, params), not both")
        kp_, kd_, i_, b_, ts = design.kp, design.kd, design.inertia, design.viscous, \
            design.sample_time
    else:
        _check_params(params)
        if kp is None:
            raise ValueError("kp is required without a design")
        for name, v in (("kp", kp), ("kd", kd)):
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise ValueError(f"{name} must be a finite real number, got {v!r}")
        kp_, kd_ = float(kp), float(kd)
        i_, b_, ts = params.total_inertia, params.viscous, params.sample_time
    a, b, c = _sampled_loop_matrices(kp_, kd_, i_, b_, ts)
    if not torque_output:
        c = c[:1]
    return control.ss(a, b, c, np.zeros((c.shape[0], 1)), ts)


def _hybrid_response(kp, kd, inertia, viscous, ts, r_samples, q0, substeps):
    """Sampled loop driven by r_k; q on the grid t_k + j*Ts/substeps (exact ZOH)."""
    a, b, c = _sampled_loop_matrices(kp, kd, inertia, viscous, ts)
    n = len(r_samples)
    x0 = np.array([q0, 0.0, 0.0, q0])
    loop = control.ss(a, b, c, np.zeros((2, 1)), ts)
    resp = control.forced_response(loop, np.arange(n) * ts, np.asarray(r_samples, float),
                                   initial_state=x0)
    tm = np.asarray(resp.outputs)[1]
    # the plant between samples: exact ZOH discretisation at h = Ts/substeps
    h = ts / substeps
    plant = control.ss([[0.0, 1.0], [0.0, -viscous / inertia]], [[0.0], [1.0 / inertia]],
                       [[1.0, 0.0]], [[0.0]])
    fine = control.c2d(plant, h, method="zoh")
    u_fine = np.repeat(tm, substeps)
    resp_f = control.forced_response(fine, np.arange(n * substeps) * h, u_fine,
                                     initial_state=[q0, 0.0])
    return np.arange(n * substeps) * h, np.asarray(resp_f.outputs)


# ---------------------------------------------------------------------------
# step metrics
# ---------------------------------------------------------------------------
def _dominant_damping(poles_s: np.ndarray) -> float:
    """Damping of the slowest pole pair (two reals or a conjugate pair)."""
    p = np.asarray(poles_s, complex)
    p = p[np.isfinite(p)]
    if p.size == 0:
        return math.nan
    order = np.argsort(np.abs(p), kind="stable")
    p = p[order]
    if p.size == 1:
        return 1.0 if p[0].real < 0 else math.nan
    p1 = p[0]
    if abs(p1.imag) > 1e-9 * max(abs(p1), 1.0):
        # the conjugate of p1 is the other half of the pair
        wn = abs(p1)
        return float(-p1.real / wn) if wn > 0 else math.nan
    reals = [q for q in p if abs(q.imag) <= 1e-9 * max(abs(q), 1.0)]
    if len(reals) >= 2 and abs(reals[1]) <= abs(p[1]) + 1e-12:
        a1 = -(reals[0].real + reals[1].real)
        a0 = reals[0].real * reals[1].real
        return float(a1 / (2.0 * math.sqrt(a0))) if a0 > 0 else math.nan
    # a single slow real pole, then a complex pair: first-order dominated
    return 1.0 if p1.real < 0 else math.nan


def _metrics_from_response(t, y, final, definition, damping) -> StepMetrics:
    limits = RISE_TIME_DEFINITIONS[definition]
    y = np.asarray(y, float)
    if not np.all(np.isfinite(y)):
        return StepMetrics(rise_time=math.nan, damping=damping, overshoot_percent=math.nan,
                           settling_time=math.nan)
    info = control.step_info(y, timepts=t, final_output=final,
                             SettlingTimeThreshold=SETTLING_THRESHOLD, RiseTimeLimits=limits)
    rise = info["RiseTime"]
    if y.max() < limits[1] * final:  # step_info would index past the end
        rise = math.nan
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
    rise_time_definition : {"0-100", "10-90"}
        Rise-time limits passed to :func:`control.step_info`.
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
    if not isinstance(sys, (control.TransferFunction, control.StateSpace)) or not sys.issiso():
        raise ValueError("sys must be a SISO python-control TransferFunction or StateSpace")
    if sys.isdtime(strict=True):
        raise ValueError("sys must be continuous-time; use a Design's sampled metrics instead")
    if rise_time_definition not in RISE_TIME_DEFINITIONS:
        raise ValueError(f"rise_time_definition must be one of "
                         f"{', '.join(map(repr, RISE_TIME_DEFINITIONS))}, "
                         f"got {rise_time_definition!r}")
    poles = np.asarray(control.poles(sys), complex)
    if poles.size == 0 or np.any(poles.real >= 0):
        raise ValueError("sys must be asymptotically stable (all poles in the left half-plane)")
    if t_end is None:
        t_end = 12.0 / np.min(-poles.real)
    t = np.linspace(0.0, float(t_end), int(points))
    resp = control.step_response(sys, t)
    return _metrics_from_response(t, np.asarray(resp.outputs), float(np.real(sys.dcgain())),
                                  rise_time_definition, _dominant_damping(poles))


def _continuous_metrics(kp, kd, inertia, viscous, wn, zeta, definition) -> StepMetrics:
    tr = normalized_rise_time(zeta, definition) / wn
    sys = _closed_loop_ss(kp, kd, inertia, viscous)
    slow = wn * (zeta - math.sqrt(zeta * zeta - 1.0)) if zeta > 1.0 else zeta * wn
    t_end = max(3.0 * tr, 10.0 / slow)
    dt = tr / _POINTS_PER_RISE
    for _ in range(4):
        t = np.arange(0.0, t_end + dt, dt)
        y = np.asarray(control.step_response(sys, t).outputs)
        m = _metrics_from_response(t, y, 1.0, definition, zeta)
        if math.isfinite(m.settling_time):
            return m
        t_end *= 2.0
    return m


def _sampled_metrics(kp, kd, inertia, viscous, ts, definition, t_end) -> StepMetrics:
    a, _, _ = _sampled_loop_matrices(kp, kd, inertia, viscous, ts)
    z = np.linalg.eigvals(a)
    if np.any(np.abs(z) >= 1.0):
        return StepMetrics(rise_time=math.nan, damping=math.nan, overshoot_percent=math.nan,
                           settling_time=math.nan)
    nz = z[np.abs(z) > 1e-12]           # poles at z = 0 are infinitely fast
    damping = _dominant_damping(np.log(nz.astype(complex)) / ts)
    for _ in range(4):
        n = int(math.ceil(t_end / ts)) + 1
        t, y = _hybrid_response(kp, kd, inertia, viscous, ts, np.ones(n), 0.0, _SUBSTEPS)
        m = _metrics_from_response(t, y, 1.0, definition, damping)
        if math.isfinite(m.settling_time):
            return m
        t_end *= 2.0
    return m


def _rel(a, b):
    return abs(a - b) / abs(b) if b else math.inf


# ---------------------------------------------------------------------------
# design functions
# ---------------------------------------------------------------------------
def _finish(*, law, kp, kd, params, rise_time, damping, priority, definition, extra_warnings):
    inertia, viscous, ts = params.total_inertia, params.viscous, params.sample_time
    wn = math.sqrt(kp / inertia)
    zeta = (viscous + kd) / (2.0 * math.sqrt(kp * inertia))
    achieved = _continuous_metrics(kp, kd, inertia, viscous, wn, zeta, definition)
    t_end = max(3.0 * achieved.settling_time, 3.0 * achieved.rise_time)
    sampled = _sampled_metrics(kp, kd, inertia, viscous, ts, definition, t_end)
    msgs = list(extra_warnings)
    if not math.isfinite(sampled.damping):
        msgs.append(f"the sampled loop at Ts = {ts:g} s is unstable (Kp = {kp:.4g} N*m/rad, "
                    f"Kd = {kd:.4g} N*m*s/rad); slow the design down")
    else:
        for name, unit in (("rise_time", " s"), ("damping", "")):
            c, s = getattr(achieved, name), getattr(sampled, name)
            if not math.isfinite(s) or _rel(s, c) > WARN_TOLERANCE:
                msg = (f"sampled loop (Ts = {ts:g} s) {name.replace('_', ' ')} {s:.4g}{unit} "
                       f"differs from the continuous design's {c:.4g}{unit} by more than "
                       f"{WARN_TOLERANCE:.0%}")
                if name == "rise_time" and definition == "0-100" \
                        and achieved.overshoot_percent < _ILL_CONDITIONED_OVERSHOOT:
                    # near zeta = 1 the step creeps up to its final value, so the first
                    # crossing of 100 % moves a lot for a tiny change; say so, with the
                    # 10-90 % comparison that is not ill-conditioned
                    c9 = _continuous_metrics(kp, kd, inertia, viscous, wn, zeta, "10-90")
                    s9 = _sampled_metrics(kp, kd, inertia, viscous, ts, "10-90", t_end)
                    msg += (f" (overshoot {achieved.overshoot_percent:.2g} % < "
                            f"{_ILL_CONDITIONED_OVERSHOOT:g} %: the 0-100 % rise time is "
                            f"ill-conditioned here; the 10-90 % rise times are "
                            f"{c9.rise_time:.4g} s and {s9.rise_time:.4g} s)")
                msgs.append(msg)
    for msg in msgs:
        warnings.warn(msg, DesignWarning, stacklevel=3)
    cl = control.tf([kp], [inertia, viscous + kd, kp])
    return Design(law=law, kp=float(kp), kd=float(kd), inertia=inertia, viscous=viscous,
                  sample_time=ts, requested_rise_time=rise_time, requested_damping=damping,
                  priority=priority, rise_time_definition=definition, wn=wn, zeta=zeta,
                  closed_loop=cl,
                  sampled_closed_loop=control.ss(*_sampled_loop_matrices(
                      kp, kd, inertia, viscous, ts)[:2],
                      [[1.0, 0.0, 0.0, 0.0]], [[0.0]], ts),
                  achieved=achieved, sampled=sampled, warnings=tuple(msgs))


def design_pd(params: ActuatorParams, *, rise_time: float, damping: float,
              rise_time_definition: str | None = None) -> Design:
    """PD (rate feedback) gains for a rise time and a damping ratio.

    ``Tc = Kp (r - q) - Kd omega_hat`` on ``G = 1/(s (I s + b))`` gives the
    closed loop ``wn^2 / (s^2 + 2 zeta wn s + wn^2)`` with
    ``Kp = I wn^2`` and ``Kd = 2 zeta wn I - b``; ``wn`` follows from the rise
    time (:func:`normalized_rise_time`).

    Parameters
    ----------
    params : ActuatorParams
        Plant: ``total_inertia`` (actuator + link), ``viscous``; ``sample_time``
        for the sampled-data check.
    rise_time : float
        Requested rise time, > 0 [s].
    damping : float
        Requested damping ratio, > 0 [-].
    rise_time_definition : {"0-100", "10-90"}, optional
        Default ``"0-100"`` for damping < 1, ``"10-90"`` otherwise (required
        for damping >= 1).

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
    Linear viscous model only (see :class:`Design`).

    Examples
    --------
    >>> from fricctl.params import paper_actuator
    >>> d = design_pd(paper_actuator().with_link(), rise_time=0.22, damping=0.5)
    >>> round(d.kp, 4), round(d.kd, 4)
    (0.9021, 0.0652)
    """
    _check_params(params)
    rise_time = _check_spec("rise_time", rise_time, " s")
    damping = _check_spec("damping", damping, "")
    if rise_time is None or damping is None:
        raise ValueError("a PD design needs both rise_time and damping")
    definition = _resolve_definition(rise_time_definition, damping)
    inertia, viscous = params.total_inertia, params.viscous
    wn = normalized_rise_time(damping, definition) / rise_time
    kp = inertia * wn * wn
    kd = 2.0 * damping * wn * inertia - viscous
    if kd < 0.0:
        raise ValueError(
            f"this PD needs a negative Kd = {kd:.4g} N*m*s/rad: the viscous friction "
            f"b = {viscous:g} N*m*s/rad alone gives damping "
            f"{viscous / (2.0 * wn * inertia):.3g} > {damping:g} at wn = {wn:.4g} rad/s; "
            "ask for more damping or a faster rise, or use P")
    return _finish(law="pd", kp=kp, kd=kd, params=params, rise_time=rise_time, damping=damping,
                   priority=None, definition=definition, extra_warnings=())


def design_p(params: ActuatorParams, *, rise_time: float | None = None,
             damping: float | None = None, priority: str = "rise_time",
             rise_time_definition: str | None = None) -> Design:
    """P gain for a rise time, a damping ratio, or both with a priority.

    With one gain, ``Kp/(I s^2 + b s + Kp)`` has ``2 zeta wn = b/I`` fixed:
    the damping alone gives ``Kp = b^2 / (4 I zeta^2)``; the rise time alone
    is met by solving ``tr = 2 I zeta g(zeta) / b`` for zeta
    (:func:`scipy.optimize.brentq`, g = :func:`normalized_rise_time`).

    Parameters
    ----------
    params : ActuatorParams
        Plant and sample time.
    rise_time : float, optional
        Requested rise time, > 0 [s].
    damping : float, optional
        Requested damping ratio, > 0 [-].
    priority : {"rise_time", "damping"}
        With both specs: the one that is met exactly; the other is reported as
        achieved (``Design.achieved``) and warns when it misses by > 10 %.
    rise_time_definition : {"0-100", "10-90"}, optional
        Default ``"0-100"`` when the (requested) damping is < 1, else ``"10-90"``.

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
    _check_params(params)
    rise_time = _check_spec("rise_time", rise_time, " s")
    damping = _check_spec("damping", damping, "")
    if rise_time is None and damping is None:
        raise ValueError("a P design needs rise_time, damping, or both")
    if priority not in _PRIORITIES:
        raise ValueError(f"priority must be 'rise_time' or 'damping', got {priority!r}")
    inertia, viscous = params.total_inertia, params.viscous
    if viscous <= 0.0:
        raise ValueError("a P design on G = 1/(s (I s + b)) needs viscous b > 0: with b = 0 "
                         "the loop is undamped for every Kp")
    both = rise_time is not None and damping is not None
    use_rise = rise_time is not None and (priority == "rise_time" or damping is None)
    definition = _resolve_definition(rise_time_definition, damping)
    if use_rise:
        zeta_cap = 1.0 - 1e-12 if definition == "0-100" else 1e3

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


# ---------------------------------------------------------------------------
# linear prediction on a simulation's grid
# ---------------------------------------------------------------------------
def linear_response(design: Design, t, reference, q0: float = 0.0, *,
                    sampled: bool = False) -> np.ndarray:
    """Linear viscous closed-loop response on a given time grid (Fig. 12's dashed line).

    Parameters
    ----------
    design : Design
        The controller.
    t : array_like, shape (n,)
        Uniform, increasing time grid, e.g. a nonlinear ``SimResult.t`` [s].
    reference : array_like, shape (n,)
        Reference r on that grid, e.g. ``SimResult.reference`` [rad].
    q0 : float
        Initial position, at rest [rad].
    sampled : bool
        False: continuous loop (:func:`control.forced_response`, input linear
        between grid points).  True: the sampled-data loop of the core
        simulator (:func:`sampled_loop`), which reads r at the samples
        ``t[0] + k*Ts``; the grid spacing must then be ``Ts/m`` for an integer
        m >= 1, and q is returned between samples too (exact ZOH).

    Returns
    -------
    numpy.ndarray, shape (n,)
        Predicted position q [rad].

    Notes
    -----
    Viscous friction only: no Coulomb/static friction, saturation or
    quantisation; the point of the overlay is to show what they change.

    Examples
    --------
    >>> import numpy as np
    >>> from fricctl.params import paper_actuator
    >>> d = design_pd(paper_actuator().with_link(), rise_time=0.22, damping=0.5)
    >>> t = np.arange(0, 2.0, 0.002)
    >>> q = linear_response(d, t, np.ones_like(t), sampled=True)
    >>> round(float(q[-1]), 3)
    1.0
    """
    if not isinstance(design, Design):
        raise ValueError(f"design must be a Design, got {type(design).__name__}")
    t = np.asarray(t, dtype=float)
    r = np.asarray(reference, dtype=float)
    if t.ndim != 1 or t.size < 2:
        raise ValueError(f"t must be a 1-D array of at least 2 times, got shape {t.shape}")
    if r.shape != t.shape:
        raise ValueError(f"reference shape {r.shape} does not match t shape {t.shape}")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(r))):
        raise ValueError("t and reference must be finite (no NaN or inf)")
    if isinstance(q0, bool) or not isinstance(q0, (int, float)) or not math.isfinite(q0):
        raise ValueError(f"q0 must be a finite real number, got {q0!r}")
    dt = np.diff(t)
    h = float(dt.mean())
    if not h > 0 or np.max(np.abs(dt - h)) > 1e-6 * h:
        raise ValueError("t must be uniform and increasing")
    if not sampled:
        sys = _closed_loop_ss(design.kp, design.kd, design.inertia, design.viscous)
        resp = control.forced_response(sys, t - t[0], r, initial_state=[float(q0), 0.0])
        return np.asarray(resp.outputs, dtype=float)
    ts = design.sample_time
    m = ts / h
    if abs(m - round(m)) > 1e-6 * m or round(m) < 1:
        raise ValueError(f"for the sampled loop the grid spacing {h:g} s must be Ts/m "
                         f"(Ts = {ts:g} s, m a positive integer)")
    m = int(round(m))
    n_samples = (t.size + m - 1) // m
    _, q = _hybrid_response(design.kp, design.kd, design.inertia, design.viscous, ts,
                            r[::m][:n_samples], float(q0), m)
    return np.asarray(q[: t.size], dtype=float)


# ---------------------------------------------------------------------------
# the paper's designs
# ---------------------------------------------------------------------------
#: The paper's four designs: key -> (law, rise time [s], damping [-], with link).
PAPER_DESIGN_SPECS = {
    "fig11-12": ("p", 0.2, 0.3, False),
    "fig13-14": ("pd", 0.3, 0.9, False),
    "fig16-17": ("pd", 0.4, 0.85, True),
    "fig18": ("pd", 0.22, 0.5, True),
}


def paper_designs(params: ActuatorParams | None = None) -> dict[str, Design]:
    """The paper's four controllers (Figs. 11-12, 13-14, 16-17, 18).

    ========  ====  =========  =======  =========================
    key       law   rise time  damping  plant
    ========  ====  =========  =======  =========================
    fig11-12  P     0.2 s      0.3      actuator
    fig13-14  PD    0.3 s      0.9      actuator
    fig16-17  PD    0.4 s      0.85     actuator + link 0.0046
    fig18     PD    0.22 s     0.5      actuator + link 0.0046
    ========  ====  =========  =======  =========================

    The P design uses ``priority="rise_time"``; with the paper actuator the
    damping is met too, since the inertia was derived from this design.
    Rise times are 0-100 % (all dampings < 1).

    Parameters
    ----------
    params : ActuatorParams, optional
        The actuator without link (default :func:`fricctl.params.paper_actuator`);
        the link designs use ``params.with_link()``.

    Returns
    -------
    dict of str to Design
    """
    if params is None:
        params = paper_actuator()
    _check_params(params)
    out = {}
    for key, (law, tr, zeta, link) in PAPER_DESIGN_SPECS.items():
        p = params.with_link() if link else params
        if law == "p":
            out[key] = design_p(p, rise_time=tr, damping=zeta, priority="rise_time")
        else:
            out[key] = design_pd(p, rise_time=tr, damping=zeta)
    return out


def design_table(designs: Mapping[str, Design]) -> str:
    """Markdown table of designs: specs, gains, continuous and sampled metrics.

    Parameters
    ----------
    designs : mapping of str to Design
        E.g. :func:`paper_designs`.

    Returns
    -------
    str
        One row per design; times in s, overshoot in %.
    """
    def f(v, fmt):
        return "-" if v is None or not math.isfinite(v) else format(v, fmt)

    head = ("| design | law | I [kg*m^2] | tr req [s] | zeta req | Kp [N*m/rad] | "
            "Kd [N*m*s/rad] | tr [s] | zeta | OS [%] | ts [s] | tr Ts [s] | zeta Ts | "
            "OS Ts [%] | ts Ts [s] |")
    rows = [head, "|" + "|".join(["---"] * (head.count("|") - 1)) + "|"]
    for key, d in designs.items():
        if not isinstance(d, Design):
            raise ValueError(f"designs[{key!r}] must be a Design, got {type(d).__name__}")
        a, s = d.achieved, d.sampled
        rows.append("| " + " | ".join([
            str(key), d.law.upper(), f(d.inertia, ".4g"), f(d.requested_rise_time, ".3g"),
            f(d.requested_damping, ".3g"), f(d.kp, ".4g"), f(d.kd, ".4g"),
            f(a.rise_time, ".4f"), f(a.damping, ".3f"), f(a.overshoot_percent, ".2f"),
            f(a.settling_time, ".3f"), f(s.rise_time, ".4f"), f(s.damping, ".3f"),
            f(s.overshoot_percent, ".2f"), f(s.settling_time, ".3f")]) + " |")
    return "\n".join(rows)
