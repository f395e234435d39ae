"""A torque periodic in position, ``A*sin(2*pi*q/period + phase)`` [N*m].

Not friction (it does not dissipate and has no sign of the velocity) but part of the resistive
torque: the harmonic drive's wave generator, cogging, a cam.  Not scaled with friction.
"""

from __future__ import annotations

import math

import numpy as np

from ... import _validate as v
from ..law import Coefficient, FrictionLaw, Law

__all__ = ["PositionRipple", "LAW"]


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


def term(q, ripple_amplitude, ripple_period, ripple_phase):
    if ripple_amplitude == 0:
        return np.zeros_like(q)
    return ripple_amplitude * np.sin(2 * np.pi * q / ripple_period + ripple_phase)


def compiled(q, ripple_amplitude, ripple_period, ripple_phase):
    if ripple_amplitude == 0.0:
        return 0.0
    return ripple_amplitude * math.sin(2.0 * math.pi * q / ripple_period + ripple_phase)


def check(model):
    if model.ripple_amplitude > 0 and model.ripple_period <= 0:
        raise ValueError("ripple_period must be > 0 when ripple_amplitude > 0")


LAW = Law(
    name="position_ripple", order=50, role="position", constructor=PositionRipple,
    description="a torque periodic in position (wave generator, cogging): not friction",
    coefficients=(
        Coefficient(name="ripple_amplitude", unit="N*m", combine="replace", doc="amplitude A"),
        Coefficient(name="ripple_period", unit="rad", combine="replace", doc="period in position"),
        Coefficient(name="ripple_phase", unit="rad", lower=-math.inf, combine="replace",
                    doc="phase at q = 0")),
    term=term, compiled=compiled, check=check, peak=lambda c: c["ripple_amplitude"],
)
