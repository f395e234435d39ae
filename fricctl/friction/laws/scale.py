"""The level of every friction term and its steady change in time: ``scale*(1 + drift*t)``.

Not a law of its own physics but the model-level factor (wear, load, warm-up) every friction
term is multiplied by (not the position ripple).  Exactly one law has this role.
"""

from __future__ import annotations

import math

from ..law import Coefficient, FrictionLaw, Law

__all__ = ["LAW"]


class Scale(FrictionLaw):
    """Multiply every friction term by ``factor`` and let it drift by ``drift`` per second."""

    def __init__(self, factor=1.0, drift=0.0):
        from ... import _validate as v

        self.factor = v.real("scale factor", factor, positive=True)
        self.drift = v.real("drift", drift)

    def contribution(self):
        return {"scale": self.factor, "drift": self.drift}


def term(t, scale, drift):
    return scale * (1.0 + drift * t)


def compiled(t, scale, drift):
    return scale * (1.0 + drift * t)


LAW = Law(
    name="scale", order=70, role="scale", constructor=Scale,
    description="the friction level (wear, load) and its drift in time (warm-up, wear)",
    coefficients=(
        Coefficient(name="scale", unit="-", default=1.0, combine="multiply",
                    doc="factor of every friction term", provenance="neutral: no change"),
        Coefficient(name="drift", unit="1/s", lower=-math.inf,
                    doc="relative change of the scale per second")),
    term=term, compiled=compiled,
)
