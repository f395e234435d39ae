"""A Coulomb level reached smoothly, ``Fc*tanh(|w|/ws)`` in the direction of motion [N*m].

Dry friction that builds up over a speed range ``ws`` instead of at the first motion (a
compliant contact, a smoothed law fitted to a drive): *less* friction at low speed than the
Coulomb level, the opposite of the Stribeck effect, and no breakaway (its level at rest is 0).
The bench hides it in place of the Coulomb law as a friction law no cause of the diagnosis
represents (:data:`fricctl.bench.hidden_effects.FOREIGN`).
"""

from __future__ import annotations

import math

import numpy as np

from .. import law as L
from ... import _validate as v

__all__ = ["SmoothCoulomb", "LAW"]


class SmoothCoulomb(L.FrictionLaw):
    """Smooth Coulomb level ``Fc*tanh(|omega|/ws)*sign(omega)``, no breakaway.

    Parameters
    ----------
    level : float
        Fc, the level approached at high speed [N*m].
    velocity : float
        ws > 0, the speed over which it builds up (tanh(1) = 76 % of Fc at ws) [rad/s].
    """

    def __init__(self, level=None, velocity=None, *, pos=None, neg=None):
        self.pos, self.neg = L.pair("SmoothCoulomb level", level, pos, neg)
        if velocity is None:
            raise ValueError("SmoothCoulomb: velocity (ws [rad/s]) is required")
        self.velocity = v.real("SmoothCoulomb velocity", velocity, positive=True)

    def contribution(self):
        return {"smooth_coulomb_pos": self.pos, "smooth_coulomb_neg": self.neg,
                "smooth_coulomb_velocity": self.velocity}

    def check_compatible(self, model):
        L.same_shape(model, "smooth_coulomb", {"smooth_coulomb_velocity": self.velocity},
                     "two SmoothCoulomb laws with different velocities cannot be summed into "
                     "one model")


def term(w, s, tm, smooth_coulomb_pos, smooth_coulomb_neg, smooth_coulomb_velocity):
    return L.pick(s, smooth_coulomb_pos, smooth_coulomb_neg) * np.tanh(
        np.abs(w) / smooth_coulomb_velocity)


def compiled(w, s, tm, smooth_coulomb_pos, smooth_coulomb_neg, smooth_coulomb_velocity):
    fc = smooth_coulomb_pos if s > 0 else smooth_coulomb_neg
    if fc == 0.0:
        return 0.0
    return fc * math.tanh(abs(w) / smooth_coulomb_velocity)


def damping(c, speed):
    """``dT/dw = Fc/ws*(1 - tanh^2)``: largest at rest, ``Fc/ws``."""
    return max(c["smooth_coulomb_pos"], c["smooth_coulomb_neg"]) / c["smooth_coulomb_velocity"]


LAW = L.Law(
    name="smooth_coulomb", order=106, role="level", constructor=SmoothCoulomb,
    description="a Coulomb level built up smoothly over a speed range, without breakaway",
    coefficients=L.direction_pair("smooth_coulomb", "N*m", "smooth Coulomb level") + (
        L.Coefficient(name="smooth_coulomb_velocity", unit="rad/s", default=1.0, strict=True,
                      combine="replace", doc="speed ws over which the level builds up",
                      provenance="a placeholder while the level is 0"),),
    term=term, compiled=compiled, damping=damping,
)
