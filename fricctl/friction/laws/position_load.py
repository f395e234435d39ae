"""A smooth load of position over the travel, ``A*sin(2*pi*q/P + phase)`` [N*m].

Not friction (conservative: no sign of the velocity, not scaled with friction) but part of
the resistive torque: gravity on an off-centre link, ``m*g*r*sin(q + phi)`` (``P = 2*pi``, or
``2*pi*n`` behind a final ratio ``n``), a balancing spring or a cable over a part of its
stroke.  It is the position ripple's form with the other meaning: a ripple repeats within
the travel (cogging, the wave generator); a load is one smooth wave over it, whose period is
longer than half the travel (at long periods a line and a curvature over the travel: a
spring).  A joint can have both, so it is a law of its own (a model holds one ripple).

Notes
-----
One harmonic: a load with a sharper shape over the travel (a hard stop, a cam) is not this.
Outside the travel it was fitted on, the fitted wave continues as a sinusoid: bounded by
``A``, but only what the record covered was measured.
"""

from __future__ import annotations

import math

import numpy as np

from ... import _validate as v
from ..law import Coefficient, FrictionLaw, Law

__all__ = ["PositionLoad", "LAW"]


class PositionLoad(FrictionLaw):
    """A load of position ``A*sin(2*pi*q/period + phase)`` [N*m] (gravity, a spring, a cable).

    Parameters
    ----------
    amplitude : float
        ``A``, e.g. ``m*g*r`` of an off-centre link [N*m].
    period : float
        The load's period in position: ``2*pi`` for gravity on the joint's own link [rad].
    phase : float
        Phase at ``q = 0`` [rad].

    Examples
    --------
    >>> from fricctl.friction import Coulomb
    >>> m = Coulomb(0.1) + PositionLoad(0.5, 2 * math.pi, math.pi / 2)  # link horizontal at q=0
    >>> round(float(m.torque(1.0, q=0.0)), 6), round(float(m.torque(1.0, q=math.pi / 2)), 6)
    (0.6, 0.1)
    """

    def __init__(self, amplitude, period, phase=0.0):
        self.amplitude = v.real("PositionLoad amplitude", amplitude, nonneg=True)
        self.period = v.real("PositionLoad period", period, positive=True)
        self.phase = v.real("PositionLoad phase", phase)

    def contribution(self):
        return {"position_load_amplitude": self.amplitude, "position_load_period": self.period,
                "position_load_phase": self.phase}

    def check_compatible(self, model):
        if model.position_load_amplitude > 0:
            raise ValueError("a model holds one PositionLoad")


def term(q, position_load_amplitude, position_load_period, position_load_phase):
    if position_load_amplitude == 0:
        return np.zeros_like(q)
    return position_load_amplitude * np.sin(2 * np.pi * q / position_load_period
                                            + position_load_phase)


def compiled(q, position_load_amplitude, position_load_period, position_load_phase):
    if position_load_amplitude == 0.0:
        return 0.0
    return position_load_amplitude * math.sin(2.0 * math.pi * q / position_load_period
                                              + position_load_phase)


def check(model):
    if model.position_load_amplitude > 0 and model.position_load_period <= 0:
        raise ValueError("position_load_period must be > 0 when position_load_amplitude > 0")


LAW = Law(
    name="position_load", order=55, role="position", constructor=PositionLoad,
    description="a smooth load of position over the travel (gravity, a spring): not friction",
    coefficients=(
        Coefficient(name="position_load_amplitude", unit="N*m", combine="replace",
                    doc="amplitude A (m*g*r of an off-centre link)",
                    provenance="neutral: no load (0)"),
        Coefficient(name="position_load_period", unit="rad", combine="replace",
                    doc="period in position (2*pi: gravity on the joint's own link)",
                    provenance="neutral: unused while the amplitude is 0"),
        Coefficient(name="position_load_phase", unit="rad", lower=-math.inf, combine="replace",
                    doc="phase at q = 0", provenance="neutral: unused while the amplitude is 0")),
    term=term, compiled=compiled, check=check, peak=lambda c: c["position_load_amplitude"],
)
