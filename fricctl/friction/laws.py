"""The elementary friction laws; each sets a few coefficients of a :class:`FrictionModel`.

Adding a law: a subclass of :class:`~fricctl.friction.model.FrictionLaw` here with
its ``contribution()`` (and ``check_compatible`` if it cannot be summed freely), the
coefficients it sets in :mod:`.layout` and ``FrictionModel``, their evaluation in
``FrictionModel.torque``/``breakaway`` and in :mod:`.kernels`.
"""

from __future__ import annotations

from .. import _validate as v
from .model import FrictionLaw

__all__ = ["Viscous", "Coulomb", "Static", "Stribeck", "LoadDependent", "PositionRipple", "LuGre"]


def _pair(name, level, pos, neg):
    """One symmetric magnitude, or both per-direction magnitudes (never a signed pair)."""
    if level is not None and (pos is not None or neg is not None):
        raise ValueError(f"{name}: give either one symmetric level or pos= and neg=, not both")
    if level is not None:
        x = v.real(name, level, nonneg=True)
        return x, x
    if pos is None or neg is None:
        raise ValueError(f"{name}: give a symmetric level, or both pos= and neg= (positive magnitudes)")
    return v.real(f"{name} pos", pos, nonneg=True), v.real(f"{name} neg", neg, nonneg=True)


class Viscous(FrictionLaw):
    """Viscous friction ``b*omega`` (or ``b_pos``/``b_neg`` per direction) [N*m*s/rad]."""

    def __init__(self, b=None, *, pos=None, neg=None):
        self.pos, self.neg = _pair("Viscous", b, pos, neg)

    def contribution(self):
        return {"viscous_pos": self.pos, "viscous_neg": self.neg}

    def __repr__(self):
        return f"Viscous(pos={self.pos}, neg={self.neg})"


class Coulomb(FrictionLaw):
    """Coulomb friction ``Fc*sign(omega)``, breakaway ``Fc`` [N*m]."""

    def __init__(self, level=None, *, pos=None, neg=None):
        self.pos, self.neg = _pair("Coulomb", level, pos, neg)

    def contribution(self):
        return {"coulomb_pos": self.pos, "coulomb_neg": self.neg}

    def __repr__(self):
        return f"Coulomb(pos={self.pos}, neg={self.neg})"


class Static(FrictionLaw):
    """Breakaway excess over sliding friction, with no sliding contribution [N*m].

    The classic "static + Coulomb" model: the joint needs ``Fc + excess`` to
    start, and ``Fc`` once it slides (an infinitely narrow Stribeck curve).
    """

    def __init__(self, excess=None, *, pos=None, neg=None):
        self.pos, self.neg = _pair("Static", excess, pos, neg)

    def contribution(self):
        return {"static_pos": self.pos, "static_neg": self.neg}

    def __repr__(self):
        return f"Static(pos={self.pos}, neg={self.neg})"


class Stribeck(FrictionLaw):
    """Exponential Stribeck excess ``(Fs - Fc) * exp(-(|omega|/vs)**delta) * sign(omega)``.

    Parameters
    ----------
    excess : float
        Fs - Fc, breakaway excess over the Coulomb level [N*m].
    velocity : float
        Stribeck velocity vs > 0 [rad/s].
    exponent : float
        Shape exponent delta > 0 (2 = Gaussian, the usual choice) [-].
    """

    def __init__(self, excess=None, velocity=None, exponent=2.0, *, pos=None, neg=None):
        self.pos, self.neg = _pair("Stribeck excess", excess, pos, neg)
        if velocity is None:
            raise ValueError("Stribeck: velocity (the Stribeck velocity vs [rad/s]) is required")
        self.velocity = v.real("Stribeck velocity", velocity, positive=True)
        self.exponent = v.real("Stribeck exponent", exponent, positive=True)

    def contribution(self):
        return {"stribeck_pos": self.pos, "stribeck_neg": self.neg,
                "stribeck_velocity": self.velocity, "stribeck_exponent": self.exponent}

    def check_compatible(self, model):
        if (model.stribeck_pos > 0 or model.stribeck_neg > 0) and (
                self.velocity != model.stribeck_velocity or self.exponent != model.stribeck_exponent):
            raise ValueError("two Stribeck laws with different velocities or exponents cannot be "
                             "summed into one model")

    def __repr__(self):
        return (f"Stribeck(pos={self.pos}, neg={self.neg}, velocity={self.velocity}, "
                f"exponent={self.exponent})")


class LoadDependent(FrictionLaw):
    """Friction growing with the transmitted torque: ``+ mu*|Tm|*sign(omega)`` [-].

    Gear-mesh friction of a harmonic drive rises with the load it transmits; the
    breakaway level rises by the same ``mu*|Tm|``.
    """

    def __init__(self, coefficient):
        self.coefficient = v.real("LoadDependent coefficient", coefficient, nonneg=True)

    def contribution(self):
        return {"load_coefficient": self.coefficient}

    def __repr__(self):
        return f"LoadDependent({self.coefficient})"


class PositionRipple(FrictionLaw):
    """Torque periodic in position: ``A*sin(2*pi*q/period + phase)`` [N*m].

    Not friction (it does not dissipate and has no sign of omega) but part of the
    resistive torque: the harmonic drive's wave generator, cogging, a cam.
    """

    def __init__(self, amplitude, period, phase=0.0):
        self.amplitude = v.real("PositionRipple amplitude", amplitude, nonneg=True)
        self.period = v.real("PositionRipple period", period, positive=True)
        self.phase = v.real("PositionRipple phase", phase)

    def contribution(self):
        return {"ripple_amplitude": self.amplitude, "ripple_period": self.period,
                "ripple_phase": self.phase}

    def check_compatible(self, model):
        if model.ripple_amplitude > 0:
            raise ValueError("a model holds one PositionRipple")

    def __repr__(self):
        return f"PositionRipple({self.amplitude}, {self.period}, phase={self.phase})"


class LuGre(FrictionLaw):
    """LuGre presliding dynamics applied to the Coulomb + Stribeck part.

    ``z' = omega - sigma0*|omega|*z/g(omega)``,
    ``T = sigma0*z + sigma1*z' + viscous``, with ``g`` the Coulomb + Stribeck
    level.  With this law the joint has no exact stick: it creeps elastically
    (presliding displacement ~ g/sigma0) below breakaway.

    Parameters
    ----------
    sigma0 : float
        Bristle stiffness [N*m/rad].
    sigma1 : float
        Bristle damping [N*m*s/rad].
    """

    def __init__(self, sigma0, sigma1):
        self.sigma0 = v.real("LuGre sigma0", sigma0, positive=True)
        self.sigma1 = v.real("LuGre sigma1", sigma1, nonneg=True)

    def contribution(self):
        return {"lugre_sigma0": self.sigma0, "lugre_sigma1": self.sigma1}

    def __repr__(self):
        return f"LuGre({self.sigma0}, {self.sigma1})"
