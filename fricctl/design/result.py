"""The result of a gain design: :class:`Design`, and :class:`DesignWarning`."""

from __future__ import annotations

import math
from dataclasses import dataclass

import control

from .. import _validate as v
from ..units import KINDS, quantity, units as units_of
from .second_order import RISE_TIME_DEFINITIONS, StepMetrics

__all__ = ["DesignWarning", "Design"]


class DesignWarning(UserWarning):
    """A design that is valid but misses a specification by more than 10 %."""


@dataclass(frozen=True, kw_only=True, eq=False)
class Design:
    """A P or PD position controller designed on the linear viscous model.

    Build it with :func:`~fricctl.design.design_p` or :func:`~fricctl.design.design_pd`.

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
    """``"0-100"``, ``"10-90"`` or ``"peak"`` (the time of the first peak)."""
    wn: float
    """Natural frequency of the continuous closed loop [rad/s]."""
    zeta: float
    """Damping ratio of the continuous closed loop [-]."""
    closed_loop: control.TransferFunction
    """Continuous closed loop q/r (python-control, no zero)."""
    sampled_closed_loop: control.StateSpace
    """Sampled-data closed loop q_k/r_k at Ts (see :func:`~fricctl.design.sampled_loop`)."""
    achieved: StepMetrics
    """Step metrics of the continuous closed loop."""
    sampled: StepMetrics
    """Step metrics of the sampled-data loop (evaluated between samples too)."""
    warnings: tuple[str, ...] = ()
    """Messages of the :class:`DesignWarning` issued while designing."""
    units: str = "rotary"
    """Axis kind: ``"rotary"`` (Kp [N*m/rad], Kd [N*m*s/rad]) or ``"linear"`` (Kp [N/m],
    Kd [N*s/m], inertia a mass [kg]); the unit labels above are the rotary ones."""

    def __post_init__(self):
        v.choice("units", self.units, KINDS)

    @property
    def rise_time_limits(self) -> tuple[float, float] | None:
        """``RiseTimeLimits`` for :func:`control.step_info` [-]; None for ``"peak"`` (its
        ``PeakTime`` is the rise time)."""
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

    def report(self, *, with_warnings: bool = True) -> str:
        """A readable multi-line summary with units; ``with_warnings=False`` leaves out the
        warning lines (``fricctl design`` prints them on stderr, as every command does)."""
        def spec(x, unit):
            return "-" if x is None else f"{x:.4g} {unit}".rstrip()

        u = units_of(self.units)
        law = {"p": "P: Tc = Kp (r - q)",
               "pd": "PD (rate feedback): Tc = Kp (r - q) - Kd omega_hat"}[self.law]
        lines = [
            f"{law}",
            f"  plant        I = {self.inertia:.6g} {u.inertia}, b = {self.viscous:.6g} {u.viscous}",
            f"  requested    rise time {spec(self.requested_rise_time, 's')} "
            f"({self.rise_time_definition}), damping {spec(self.requested_damping, '')}"
            + (f", priority {self.priority}" if self.priority else ""),
            f"  gains        Kp = {self.kp:.6g} {u.stiffness}, Kd = {self.kd:.6g} {u.viscous}",
            f"  closed loop  wn = {self.wn:.6g} rad/s, zeta = {self.zeta:.4g}",
            f"  {'':12} {'rise [s]':>10} {'damping':>9} {'OS [%]':>9} {'settle [s]':>11}",
        ]
        def cell(x, width, digits):  # an undefined metric (nan) is '-' (the JSON's null)
            return f"{'-':>{width}}" if not math.isfinite(x) else f"{x:{width}.{digits}f}"

        for name, m in (("continuous", self.achieved),
                        (f"Ts={self.sample_time:g} s", self.sampled)):
            lines.append(f"  {name:12} {cell(m.rise_time, 10, 4)} {cell(m.damping, 9, 4)} "
                         f"{cell(m.overshoot_percent, 9, 3)} {cell(m.settling_time, 11, 4)}")
        s = self.sampled
        if not math.isfinite(s.damping) and math.isfinite(s.overshoot_percent):
            # stable (it has an overshoot) but no damping: no single pole pair dominates
            lines.append(f"  {'':12} {'':10} damping -: the sampled loop is not second-order")
        for w in self.warnings if v.flag("with_warnings", with_warnings) else ():
            lines.append(f"  warning: {w}")
        return "\n".join(lines)

    def as_dict(self) -> dict:
        """JSON-ready dict (the CLI's ``--json`` object): every quantity as ``{value, unit}``
        (:func:`fricctl.units.quantity`), in the units of :attr:`units`, with the same keys
        for the paper's actuator and a model file."""
        u = units_of(self.units)
        return {
            "law": self.law,
            "units": self.units,
            "kp": quantity(self.kp, u.stiffness),
            "kd": quantity(self.kd, u.viscous),
            "inertia": quantity(self.inertia, u.inertia),
            "viscous": quantity(self.viscous, u.viscous),
            "sample_time": quantity(self.sample_time, "s"),
            "requested": {"rise_time": quantity(self.requested_rise_time, "s"),
                          "damping": quantity(self.requested_damping, "-"),
                          "priority": self.priority},
            "rise_time_definition": self.rise_time_definition,
            "wn": quantity(self.wn, "rad/s"),
            "zeta": quantity(self.zeta, "-"),
            "achieved": self.achieved.as_dict(),
            "sampled": self.sampled.as_dict(),
            "warnings": list(self.warnings),
        }
