"""Friction growing with the transmitted torque, ``mu*|Tm|`` (gear-mesh load) [-]."""

from __future__ import annotations

import numpy as np

from ... import _validate as v
from ..law import Coefficient, FrictionLaw, Law

__all__ = ["LoadDependent", "LAW"]


class LoadDependent(FrictionLaw):
    """Friction growing with the transmitted torque: ``+ mu*|Tm|*sign(omega)`` [-].

    Gear-mesh friction of a harmonic drive rises with the load it transmits; the
    breakaway level rises by the same ``mu*|Tm|``.
    """

    def __init__(self, coefficient):
        self.coefficient = v.real("LoadDependent coefficient", coefficient, nonneg=True)

    def contribution(self):
        return {"load_coefficient": self.coefficient}


def term(w, s, tm, load_coefficient):
    return load_coefficient * np.abs(tm) + 0.0 * w


def compiled(w, s, tm, load_coefficient):
    return load_coefficient * abs(tm)


LAW = Law(
    name="load_dependent", order=60, role="level", constructor=LoadDependent,
    description="load-dependent friction: the gear mesh's level rising with the torque it carries",
    coefficients=(Coefficient(name="load_coefficient", unit="-",
                              doc="friction per unit of transmitted torque mu"),),
    term=term, compiled=compiled,
)
