r"""Integral action as a compensator: the PD becomes a PID with anti-windup,
``T^at_k = Ki * I_k``, ``I_k = I_{k-1} + Ts (r_k - y_k)``.

The linear answer a control student tries first: the integral of the position error
builds the torque that friction (or a load) holds against the PD, whatever its cause.

Anti-windup: *clamping* (conditional integration).  The integrator holds when the torque
held now, ``Tm_k``, sits at the torque limit and the error would drive it further into
it (``|Tm_k| >= Tmax`` and ``e * Tm_k > 0``), and ``|Ki I|`` is kept at or below
``Tmax`` [N*m].  With no torque limit (``Tmax = inf``) it is a plain integrator.

Design of Ki (:func:`design_ki`, python-control): the PI zero a decade below the
closed-loop bandwidth of the PD design, ``Ki = Kp * wb / 10`` with ``wb`` the -3 dB
bandwidth of the design's continuous closed loop (``control.bandwidth``); the PID loop
``I s^3 + (b + Kd) s^2 + Kp s + Ki`` is then checked stable with ``control`` (its poles).

Provenance: Kp, Kd, inertia and viscous of the design (:class:`~fricctl.design.Design`
or :class:`~fricctl.design.LinearLoop`), Tmax of the model (:attr:`JointModel.max_torque`,
``inf`` when unknown).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _validate as v
from .base import CCode, Compensator, CompiledCompensator, Entry, joint_model

__all__ = ["IntegralAction", "ENTRY", "design_ki"]

#: Kind id in the compiled loop.
KIND = 6
P_KI, P_TMAX = range(2)
X_I = 0


def _gains(design) -> tuple:
    """``(Kp, Kd, I, b)`` of a design: a :class:`~fricctl.design.Design` or
    :class:`~fricctl.design.LinearLoop` (read by attribute: the compensators sit below the
    design in the package's layers)."""
    names = ("kp", "kd", "inertia", "viscous")
    if not all(hasattr(design, n) for n in names):
        raise ValueError("design must be a fricctl.design.Design or LinearLoop (the PD the "
                         f"integral action extends), got {type(design).__name__}")
    kp, kd, inertia, viscous = (v.real(f"design.{n}", getattr(design, n)) for n in names)
    if not (kp > 0 and kd >= 0 and inertia > 0 and viscous >= 0):
        raise ValueError(f"design: needs kp > 0, kd >= 0, inertia > 0, viscous >= 0; got kp = "
                         f"{kp:g}, kd = {kd:g}, inertia = {inertia:g}, viscous = {viscous:g}")
    return kp, kd, inertia, viscous


def design_ki(design, *, decade: float = 10.0) -> float:
    """Ki [N*m/(rad*s)] placing the PI zero ``decade`` times below the PD loop's bandwidth.

    Parameters
    ----------
    design : Design or LinearLoop
        The PD (or P) design the integral action extends (``kp > 0``).
    decade : float
        Ratio bandwidth / zero (> 1; 10: a decade).

    Returns
    -------
    float
        ``Ki = Kp * wb / decade``; ``wb`` from ``control.bandwidth`` of the continuous
        closed loop q/r.

    Raises
    ------
    ValueError
        No proportional gain, or a PID loop that python-control finds unstable.

    Examples
    --------
    >>> from fricctl.design import LinearLoop
    >>> loop = LinearLoop(kp=1.0, kd=0.1, inertia=0.01, viscous=0.0, sample_time=0.002)
    >>> round(design_ki(loop), 4)   # -3 dB of wn = 10 rad/s, zeta = 0.5: wb = 12.71 rad/s
    1.2712
    """
    import control

    kp, kd, inertia, viscous = _gains(design)
    decade = v.real("decade", decade, low=1.0)
    if decade == 1.0:
        raise ValueError("decade must be > 1 (the zero below the bandwidth)")
    # the rate-feedback PD's closed loop q/r = Kp / (I s^2 + (b + Kd) s + Kp)
    wb = float(control.bandwidth(control.tf([kp], [inertia, viscous + kd, kp])))
    ki = kp * wb / decade
    pid = control.tf([ki], [inertia, viscous + kd, kp, ki])
    if not np.all(np.real(control.poles(pid)) < 0):
        raise ValueError(f"Ki = {ki:.4g} makes the PID loop unstable (poles "
                         f"{np.round(control.poles(pid), 4)})")
    return ki


@dataclass(frozen=True, kw_only=True)
class IntegralAction(Compensator):
    """``T^at = Ki * I``, I the clamped integral of the position error (r - y).

    Parameters
    ----------
    ki : float
        Integral gain Ki [N*m/(rad*s)] (> 0).
    max_torque : float
        Torque limit Tmax of the anti-windup clamp [N*m] (> 0; ``inf``: none).
    scale : float
        Compensation scale s [-] (the loop adds ``s*Ki*I``).

    Notes
    -----
    With static friction above the Coulomb level, integral action trades the PD's dead
    zone for hunting (a slow stick-slip limit cycle around the target): the integral
    grows until the joint breaks away, overshoots and sticks on the other side.

    The clamp sees the loop's saturation only through the torque held, ``Tm_k``, which the
    loop has clipped to *its* limit (:attr:`fricctl.simulate.LoopSpec.max_torque`, the
    simulated model's ``max_torque``); the step is not given that limit.  It holds the
    integrator when ``|Tm_k| >= max_torque``, so ``max_torque`` must be the loop's: with a
    larger one the held torque never reaches it and the integrator winds up to
    ``max_torque/Ki`` while the drive saturates; with a smaller one it holds before the
    drive does.  :func:`make` and the comparison (:mod:`fricctl.compare`) take it from the
    model the loop runs (the design model shares the bench's torque limit; a test checks
    this for every bench and plant).  It is not a friction estimate
    (``estimates_friction`` is False): its runs are judged by
    :func:`fricctl.paper.runaway.divergence`, not by the friction bound.
    """

    ki: float
    """Integral gain Ki [N*m/(rad*s)]."""
    max_torque: float = math.inf
    """Tmax of the clamp [N*m]."""
    scale: float = 1.0
    """Compensation scale s [-]."""
    name: str = "integral"
    """Label in results and plots."""
    stateful = True  # its state: the integral of the error

    @property
    def needs_reference(self) -> bool:
        """True: it integrates the position error ``r - y``."""
        return True

    @property
    def estimates_friction(self) -> bool:
        """False: ``Ki I`` is an integral of the position error, not a friction estimate."""
        return False

    def __post_init__(self):
        v.real("ki", self.ki, positive=True, unit="N*m/(rad*s)")
        mt = v.real("max_torque", self.max_torque, positive=True, finite=False, unit="N*m")
        if math.isnan(mt):
            raise ValueError("max_torque must be > 0 N*m or inf, got nan")
        v.real("scale", self.scale, nonneg=True)
        v.text("name", self.name)

    @classmethod
    def from_design(cls, design, *, model=None, decade: float = 10.0,
                    scale: float = 1.0) -> "IntegralAction":
        """Ki from :func:`design_ki`, Tmax from ``model`` (None or no limit: ``inf``)."""
        tmax = math.inf
        if model is not None:
            m = joint_model(model)
            tmax = math.inf if m.max_torque is None else m.max_torque
        return cls(ki=design_ki(design, decade=decade), max_torque=tmax, scale=scale)

    def compiled(self):
        # no torque limit is 0 in the vector (the loop's vectors hold finite numbers only)
        tmax = self.max_torque if math.isfinite(self.max_torque) else 0.0
        return CompiledCompensator(kind=KIND, params=np.array([self.ki, tmax]), state=np.zeros(1))


def step(p, x, tm, y, r, ts):
    """Clamped integration of e = r_k - y_k (see the module docstring), then Ki * I_k."""
    e = r - y
    i = x[X_I]
    tmax = p[P_TMAX]
    if not (tmax > 0.0 and abs(tm) >= tmax and e * tm > 0.0):
        i = i + ts * e
    if tmax > 0.0:  # 0: no torque limit
        lim = tmax / p[P_KI]
        if i > lim:
            i = lim
        elif i < -lim:
            i = -lim
    x[X_I] = i
    return p[P_KI] * i


def c_code(comp: IntegralAction) -> CCode:
    tmax = comp.max_torque
    return CCode(
        params=(("ki", comp.ki, "integral gain Ki [N*m/(rad*s)]"),
                ("tmax", tmax if math.isfinite(tmax) else 0.0,
                 "torque limit of the clamp [N*m] (0: none)")),
        state=(("i", "integral of r - y [rad*s]"),),
        init="    st->i = 0.0;\n",
        step="""    double e = r - y, i = st->i, lim;
    (void)omega_hat; (void)tc;
    if (!(P_tmax > 0.0 && fabs(tm) >= P_tmax && e * tm > 0.0)) i = i + st->ts * e;
    if (P_tmax > 0.0) {
        lim = P_tmax / P_ki;
        if (i > lim) i = lim;
        else if (i < -lim) i = -lim;
    }
    st->i = i;
    return P_ki * i;
""")


def _make(model, design, sample_time, *, decade: float = 10.0, ki: float | None = None,
          scale: float = 1.0):
    if ki is not None:
        m = joint_model(model)
        return IntegralAction(ki=ki, max_torque=math.inf if m.max_torque is None else m.max_torque,
                              scale=scale)
    if design is None:
        raise ValueError("integral: needs the PD design (a fricctl.design.Design or LinearLoop) "
                         "to place Ki, or ki=")
    return IntegralAction.from_design(design, model=model, decade=decade, scale=scale)


ENTRY = Entry(name="integral", kind=KIND, cls=IntegralAction, make=_make, step=step,
              c_code=c_code,
              description="integral action Ki * int(r - y) with clamping anti-windup: the PD "
                          "becomes a PID (Ki: a zero a decade below the PD's bandwidth)")
