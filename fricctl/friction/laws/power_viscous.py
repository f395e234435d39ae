"""Viscous friction growing sub-linearly with speed, ``c*|w|**p*sign(w)``, ``0 < p <= 1``.

A lubricated contact whose film thickens with speed (the velocity exponent ``delta_v`` of the
seven-parameter model of Armstrong-Helouvry et al. 1994): steeper than a viscous line at low
speed, flatter at high speed.  ``p = 1`` is the viscous law; the bench hides ``p`` in
0.4 .. 0.7 as a friction law no cause of the diagnosis represents
(:data:`fricctl.bench.hidden_effects.FOREIGN`).

The term keeps the direction of motion ``s`` the integrator slides in (``c*s*|w|**p``, equal
to ``c*|w|**p*sign(w)`` whenever ``s = sign(w)``): inside one RK4 step it never pushes the
joint, so its slope ``p*c*|w|**(p-1)``, unbounded at rest, cannot make a step gain speed;
the kernel's exact stop at ``w = 0`` ends the approach to rest.  It declares no damping for
that reason (sub-steps sized for an infinite slope would be refused).
"""

from __future__ import annotations

import numpy as np

from .. import law as L
from ... import _validate as v

__all__ = ["PowerViscous", "LAW"]


class PowerViscous(L.FrictionLaw):
    """Sub-linear viscous friction ``c*|omega|**p*sign(omega)`` (or ``pos``/``neg`` per direction).

    Parameters
    ----------
    coefficient : float
        c, the torque at 1 rad/s [N*m*(s/rad)^p].
    exponent : float
        p, 0 < p <= 1 (1: viscous) [-].
    """

    def __init__(self, coefficient=None, exponent=None, *, pos=None, neg=None):
        self.pos, self.neg = L.pair("PowerViscous coefficient", coefficient, pos, neg)
        if exponent is None:
            raise ValueError("PowerViscous: exponent (p, 0 < p <= 1) is required")
        self.exponent = v.real("PowerViscous exponent", exponent, positive=True)
        if self.exponent > 1.0:
            raise ValueError(f"PowerViscous exponent must be in (0, 1] (a sub-linear law; drag "
                             f"is the quadratic one), got {self.exponent:g}")

    def contribution(self):
        return {"power_viscous_pos": self.pos, "power_viscous_neg": self.neg,
                "power_viscous_exponent": self.exponent}

    def check_compatible(self, model):
        L.same_shape(model, "power_viscous", {"power_viscous_exponent": self.exponent},
                     "two PowerViscous laws with different exponents cannot be summed into one "
                     "model")


def term(w, s, power_viscous_pos, power_viscous_neg, power_viscous_exponent):
    return L.pick(s, power_viscous_pos, power_viscous_neg) * s * np.abs(w) ** power_viscous_exponent


def compiled(w, s, power_viscous_pos, power_viscous_neg, power_viscous_exponent):
    c = power_viscous_pos if s > 0 else power_viscous_neg
    if c == 0.0:
        return 0.0
    return c * s * abs(w) ** power_viscous_exponent


LAW = L.Law(
    name="power_viscous", order=105, role="rate", constructor=PowerViscous,
    description="sub-linear viscous friction: a torque growing as a power p < 1 of the speed",
    coefficients=L.direction_pair("power_viscous", "N*m*(s/rad)^p",
                                  "power-law viscous coefficient c") + (
        L.Coefficient(name="power_viscous_exponent", unit="-", default=1.0, strict=True,
                      upper=1.0, combine="replace", doc="velocity exponent p (1: viscous)",
                      provenance="the viscous line while the coefficient is 0"),),
    term=term, compiled=compiled,
)
