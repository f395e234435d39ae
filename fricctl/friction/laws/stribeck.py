"""Stribeck friction: the breakaway excess decaying with speed, ``Fs*exp(-(|w|/vs)**delta)``."""

from __future__ import annotations

import math

import numpy as np

from .. import law as L
from ... import _validate as v

__all__ = ["Stribeck", "LAW"]


class Stribeck(L.FrictionLaw):
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
        self.pos, self.neg = L.pair("Stribeck excess", excess, pos, neg)
        if velocity is None:
            raise ValueError("Stribeck: velocity (the Stribeck velocity vs [rad/s]) is required")
        self.velocity = v.real("Stribeck velocity", velocity, positive=True)
        self.exponent = v.real("Stribeck exponent", exponent, positive=True)

    def contribution(self):
        return {"stribeck_pos": self.pos, "stribeck_neg": self.neg,
                "stribeck_velocity": self.velocity, "stribeck_exponent": self.exponent}

    def check_compatible(self, model):
        L.same_shape(model, "stribeck", {"stribeck_velocity": self.velocity,
                                         "stribeck_exponent": self.exponent},
                     "two Stribeck laws with different velocities or exponents cannot be summed "
                     "into one model")


def term(w, s, tm, stribeck_pos, stribeck_neg, stribeck_velocity, stribeck_exponent):
    with np.errstate(over="ignore"):  # (|w|/vs)^e -> inf: the Stribeck term's limit is 0
        dip = np.exp(-(np.abs(w) / stribeck_velocity) ** stribeck_exponent)
    return L.pick(s, stribeck_pos, stribeck_neg) * dip


def compiled(w, s, tm, stribeck_pos, stribeck_neg, stribeck_velocity, stribeck_exponent):
    fs = stribeck_pos if s > 0 else stribeck_neg
    if fs == 0.0:
        return 0.0
    x = abs(w) / stribeck_velocity
    if stribeck_exponent == 2.0:
        return fs * math.exp(-x * x)
    return fs * math.exp(-(x ** stribeck_exponent))


def breakaway(s, tm, stribeck_pos, stribeck_neg, stribeck_velocity, stribeck_exponent):
    return L.pick(s, stribeck_pos, stribeck_neg)


def compiled_breakaway(s, tm, stribeck_pos, stribeck_neg, stribeck_velocity, stribeck_exponent):
    return stribeck_pos if s > 0 else stribeck_neg


LAW = L.Law(
    name="stribeck", order=40, role="level", constructor=Stribeck,
    description="the Stribeck effect: friction falling from breakaway to Coulomb as speed builds",
    coefficients=L.direction_pair("stribeck", "N*m", "breakaway excess over Coulomb (Fs - Fc)") + (
        L.Coefficient(name="stribeck_velocity", unit="rad/s", default=1.0, strict=True,
                      combine="replace", doc="Stribeck velocity vs",
                      provenance="a placeholder while the excess is 0"),
        L.Coefficient(name="stribeck_exponent", unit="-", default=2.0, strict=True,
                      combine="replace", doc="shape exponent delta (2: Gaussian)",
                      provenance="the usual Gaussian shape")),
    term=term, compiled=compiled, breakaway=breakaway, compiled_breakaway=compiled_breakaway,
)
