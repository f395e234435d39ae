r"""The loop models of the design: plant, continuous loop, sampled-data loop, responses.

The design plant is the rigid joint with viscous friction only, load side,
``G(s) = 1 / (s (I s + b))`` (:func:`plant_tf`).  :class:`LinearLoop` closes it
with a P or rate-feedback PD controller, both as the continuous loop of the
design and as the sampled-data loop of the core simulator (zero-order hold at
``Ts``, backward-difference velocity, one sample of computation delay), and
measures the step metrics of each.  :func:`sampled_loop` and
:func:`linear_response` give the same models for a :class:`~fricctl.design.Design`.

Notes
-----
Linear viscous model only: no Coulomb or static friction, torque saturation,
encoder quantisation or joint flexibility.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cached_property

import control
import numpy as np

from .. import _validate as v
from ..params import ActuatorParams
from .result import Design
from .second_order import (StepMetrics, dominant_damping, metrics_from_response,
                           second_order_holds, second_order_metrics)

__all__ = ["plant_tf", "LinearLoop", "SampledResponse", "sampled_loop", "linear_response"]

#: Sub-steps per sample used to evaluate the sampled loop between samples [-].
SUBSTEPS = 20
#: Largest number of samples the sampled-loop check simulates (about 11 min at 500 Hz).
MAX_SAMPLED = 1_000_000
#: Largest number of evaluation points of the sampled-loop check (samples x sub-steps):
#: python-control's discrete forced_response costs ~10 us a point.
MAX_POINTS = 1_000_000


def _check_params(params) -> ActuatorParams:
    return v.instance("params", params, ActuatorParams, "an ActuatorParams")


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


@dataclass(frozen=True, kw_only=True)
class SampledResponse:
    """Position of the sampled-data loop, between samples too (exact zero-order hold)."""

    t: np.ndarray = field(metadata={"unit": "s"})
    """Times ``k*Ts + j*Ts/substeps`` from the first sample [s]."""
    q: np.ndarray = field(metadata={"unit": "rad"})
    """Joint position at those times [rad]."""

    def __post_init__(self):
        for name in ("t", "q"):
            x = np.array(getattr(self, name), dtype=float)
            x.setflags(write=False)
            object.__setattr__(self, name, x)


@dataclass(frozen=True, kw_only=True)
class LinearLoop:
    """A P or rate-feedback PD position loop on the linear viscous plant.

    ``Tc = Kp (r - q) - Kd omega_hat`` on ``G = 1/(s (I s + b))``.

    Notes
    -----
    Linear viscous plant only: no saturation, no quantisation, no Coulomb or
    static friction.

    Examples
    --------
    >>> loop = LinearLoop(kp=1.0, kd=0.0, inertia=0.01, viscous=0.1, sample_time=0.002)
    >>> round(loop.wn, 6), round(loop.zeta, 6)
    (10.0, 0.5)
    """

    kp: float = field(metadata={"unit": "N*m/rad"})
    """Proportional gain Kp [N*m/rad]."""
    kd: float = field(default=0.0, metadata={"unit": "N*m*s/rad"})
    """Velocity-feedback gain Kd [N*m*s/rad]; 0 for P."""
    inertia: float = field(metadata={"unit": "kg*m^2"})
    """Total inertia I (actuator + link), load side [kg*m^2]."""
    viscous: float = field(metadata={"unit": "N*m*s/rad"})
    """Viscous coefficient b [N*m*s/rad]."""
    sample_time: float = field(metadata={"unit": "s"})
    """Sample time Ts of the sampled-data loop [s]."""

    def __post_init__(self):
        for name, kw in (("kp", {}), ("kd", {}), ("inertia", {"positive": True}),
                         ("viscous", {"nonneg": True}), ("sample_time", {"positive": True})):
            object.__setattr__(self, name, v.real(name, getattr(self, name), **kw))

    @classmethod
    def of(cls, design: Design) -> "LinearLoop":
        """The loop of a :class:`~fricctl.design.Design` (its gains, plant and Ts)."""
        v.instance("design", design, Design)
        return cls(kp=design.kp, kd=design.kd, inertia=design.inertia, viscous=design.viscous,
                   sample_time=design.sample_time)

    @property
    def wn(self) -> float:
        """Natural frequency of the continuous loop ``sqrt(Kp/I)`` [rad/s]."""
        return math.sqrt(self.kp / self.inertia)

    @property
    def zeta(self) -> float:
        """Damping ratio of the continuous loop ``(b + Kd) / (2 sqrt(Kp I))`` [-]."""
        return (self.viscous + self.kd) / (2.0 * math.sqrt(self.kp * self.inertia))

    def _plant_ss(self) -> control.StateSpace:
        """Plant state (q, omega), input Tm, output q."""
        return control.ss([[0.0, 1.0], [0.0, -self.viscous / self.inertia]],
                          [[0.0], [1.0 / self.inertia]], [[1.0, 0.0]], [[0.0]])

    def continuous(self) -> control.StateSpace:
        """Continuous rate-feedback loop, state (q, omega), input r, output q."""
        kp, kd, inertia, viscous = self.kp, self.kd, self.inertia, self.viscous
        a = [[0.0, 1.0], [-kp / inertia, -(viscous + kd) / inertia]]
        return control.ss(a, [[0.0], [kp / inertia]], [[1.0, 0.0]], [[0.0]])

    def sampled(self, *, torque_output: bool = False,
                viscous_compensated: float = 0.0) -> control.StateSpace:
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
        torque_output : bool
            Also output the held motor torque Tm_k (second output) [N*m].
        viscous_compensated : float
            Fraction c of the viscous term a compensator cancels: it adds
            ``c*b*omega_hat_k`` to the torque computed at ``t_k`` (the paper's
            ``Tm(k+1) = Tc(k) + T^at(k)`` with a friction estimate whose viscous
            part is ``c*b*omega_hat``).  0 is the loop without compensation; 1 the
            full compensation of Chapter 6, which removes the only damping of a P
            loop [-].

        Returns
        -------
        control.StateSpace
            ``dt = Ts``; input r_k [rad]; output q_k [rad] (and Tm_k); state
            ``(q, omega, Tm, y_prev)``, so the initial state of a loop at rest at
            ``q0`` is ``(q0, 0, 0, q0)``.
        """
        ts = self.sample_time
        pd_ = control.c2d(self._plant_ss(), ts, method="zoh")
        ad, bd = np.asarray(pd_.A), np.asarray(pd_.B)
        c = np.array([[1.0, 0.0]])
        comp = v.real("viscous_compensated", viscous_compensated, nonneg=True) * self.viscous
        # Tc_k = Kp (r_k - y_k) - Kd (y_k - y_{k-1})/Ts ; yprev_{k+1} = y_k
        # Tm_{k+1} = Tc_k + c b (y_k - y_{k-1})/Ts : the compensation acts as a negative Kd
        k_y = -(self.kp + (self.kd - comp) / ts)
        k_prev = (self.kd - comp) / ts
        a = np.zeros((4, 4))
        a[:2, :2] = ad
        a[:2, 2:3] = bd
        a[2, :2] = k_y * c[0]
        a[2, 3] = k_prev
        a[3, :2] = c[0]
        b = np.array([[0.0], [0.0], [self.kp], [0.0]])
        cout = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]])
        if not v.flag("torque_output", torque_output):
            cout = cout[:1]
        return control.ss(a, b, cout, np.zeros((cout.shape[0], 1)), ts)

    def sampled_response(self, r_samples, *, q0: float = 0.0,
                         substeps: int = 1) -> SampledResponse:
        """The sampled loop driven by ``r_k``, with q between samples (exact ZOH).

        Parameters
        ----------
        r_samples : array_like, shape (n,)
            Reference at the samples ``k*Ts`` [rad].
        q0 : float
            Initial position, at rest [rad].
        substeps : int
            Points per sample interval of the returned grid [-].

        Returns
        -------
        SampledResponse
            ``n * substeps`` points on ``t = j * Ts/substeps``.
        """
        r = v.array("r_samples", r_samples, min_size=1)
        q0 = v.real("q0", q0)
        substeps = v.integer("substeps", substeps, low=1)
        ts = self.sample_time
        n = r.size
        resp = control.forced_response(self.sampled(torque_output=True), np.arange(n) * ts, r,
                                       initial_state=np.array([q0, 0.0, 0.0, q0]))
        tm = np.asarray(resp.outputs)[1]
        # the plant between samples: exact ZOH discretisation at h = Ts/substeps
        h = ts / substeps
        fine = control.c2d(self._plant_ss(), h, method="zoh")
        resp_f = control.forced_response(fine, np.arange(n * substeps) * h,
                                         np.repeat(tm, substeps), initial_state=[q0, 0.0])
        return SampledResponse(t=np.arange(n * substeps) * h, q=np.asarray(resp_f.outputs))

    def continuous_metrics(self, definition: str) -> StepMetrics:
        """Exact step metrics of :meth:`continuous` (:func:`second_order_metrics`).

        The continuous loop is the standard second-order system without a zero, so its
        metrics have closed forms; ``tests/test_design.py`` checks them against
        :func:`control.step_info` on fine grids.
        """
        return second_order_metrics(self.wn, self.zeta, definition)

    def sampled_pole_damping(self) -> float:
        """Damping of the sampled loop's slowest-decaying pole pair (:func:`dominant_damping`) [-].

        The poles of :meth:`sampled` (:func:`control.poles`) mapped by ``s = ln(z)/Ts``; poles at
        ``z = 0`` are infinitely fast and left out (``control.damp`` would take their log).
        """
        z = self._sampled_poles
        nz = z[np.abs(z) > 1e-12]
        return dominant_damping(np.log(nz) / self.sample_time)

    def sampled_metrics(self, definition: str, t_end: float) -> StepMetrics:
        """Step metrics of :meth:`sampled`, evaluated 20 times per sample interval.

        The damping is that of the slowest-decaying poles mapped by ``s = ln(z)/Ts``
        (:meth:`sampled_pole_damping`), kept only where the step's overshoot agrees with it
        (:func:`second_order_holds`); where no single pair dominates the step the loop is not
        second-order and the damping is NaN.  An unstable loop gives
        :meth:`StepMetrics.undefined`.  The horizon ``t_end`` [s] is extended (up to 8x) until
        the step settles.
        """
        ts = self.sample_time
        t_end = v.real("t_end", t_end, positive=True, unit="s")
        if not self.sampled_stable():
            return StepMetrics.undefined()
        damping = self.sampled_pole_damping()
        for _ in range(4):
            n = int(math.ceil(t_end / ts)) + 1
            if n > MAX_SAMPLED:
                raise ValueError(
                    f"sample_time: checking this design on the sampled loop needs {n} samples of "
                    f"Ts = {ts:g} s (it settles after about {t_end:.3g} s), more than "
                    f"{MAX_SAMPLED}: the loop is too slow for its sample time")
            # 20 evaluations per sample interval, fewer on long horizons (at most MAX_POINTS)
            resp = self.sampled_response(np.ones(n), substeps=max(1, min(SUBSTEPS, MAX_POINTS // n)))
            m = metrics_from_response(resp.t, resp.q, final=1.0, definition=definition,
                                      damping=damping)
            if math.isfinite(m.settling_time):
                break
            t_end *= 2.0
        if not second_order_holds(m.damping, m.overshoot_percent):
            m = replace(m, damping=math.nan)
        return m

    def sampled_stable(self) -> bool:
        """Whether every pole of :meth:`sampled` lies strictly inside the unit circle."""
        return bool(np.all(np.abs(self._sampled_poles) < 1.0))

    @cached_property
    def _sampled_poles(self) -> np.ndarray:
        # the poles of sampled(), built once per loop (sampled_metrics asks twice)
        return np.asarray(control.poles(self.sampled()), complex)


def sampled_loop(design: Design | None = None, *, kp: float | None = None,
                 kd: float = 0.0, params: ActuatorParams | None = None,
                 torque_output: bool = False,
                 viscous_compensated: float = 0.0) -> control.StateSpace:
    """Discrete closed loop of the core simulator's sampled-data controller.

    The loop of :meth:`LinearLoop.sampled` (see there for the timing) for a
    design, or for gains on a plant.

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
    viscous_compensated : float
        Fraction of the viscous term ``b*omega_hat`` a compensator adds to the
        next torque (:meth:`LinearLoop.sampled`) [-].

    Returns
    -------
    control.StateSpace
        As :meth:`LinearLoop.sampled`: state ``(q, omega, Tm, y_prev)``, at rest
        at ``q0`` it is ``(q0, 0, 0, q0)``.

    Examples
    --------
    >>> from fricctl.params import paper_actuator
    >>> loop = sampled_loop(kp=0.9, kd=0.07, params=paper_actuator())
    >>> loop.dt, loop.nstates, loop.noutputs
    (0.002, 4, 1)
    """
    if design is not None:
        if kp is not None or params is not None:
            raise ValueError("give either design or (kp, kd, params), not both")
        loop = LinearLoop.of(design)
    else:
        _check_params(params)
        if kp is None:
            raise ValueError("kp is required without a design")
        loop = LinearLoop(kp=kp, kd=kd, inertia=params.total_inertia, viscous=params.viscous,
                          sample_time=params.sample_time)
    return loop.sampled(torque_output=torque_output, viscous_compensated=viscous_compensated)


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
    >>> from fricctl.design import design_pd
    >>> d = design_pd(paper_actuator().with_link(), rise_time=0.22, damping=0.5)
    >>> t = np.arange(0, 2.0, 0.002)
    >>> q = linear_response(d, t, np.ones_like(t), sampled=True)
    >>> round(float(q[-1]), 3)
    1.0
    """
    loop = LinearLoop.of(design)
    t = v.array("t", t, min_size=2)
    r = v.array("reference", reference, shape=t.shape)
    q0 = v.real("q0", q0)
    dt = np.diff(t)
    h = float(dt.mean())
    if not h > 0 or np.max(np.abs(dt - h)) > 1e-6 * h:
        raise ValueError("t must be uniform and increasing")
    if not v.flag("sampled", sampled):
        resp = control.forced_response(loop.continuous(), t - t[0], r, initial_state=[q0, 0.0])
        return np.asarray(resp.outputs, dtype=float)
    ts = loop.sample_time
    m = ts / h
    if abs(m - round(m)) > 1e-6 * m or round(m) < 1:
        raise ValueError(f"for the sampled loop the grid spacing {h:g} s must be Ts/m "
                         f"(Ts = {ts:g} s, m a positive integer)")
    m = int(round(m))
    n_samples = (t.size + m - 1) // m
    resp = loop.sampled_response(r[::m][:n_samples], q0=q0, substeps=m)
    return np.array(resp.q[: t.size], dtype=float)   # a writable copy: resp.q is read-only
