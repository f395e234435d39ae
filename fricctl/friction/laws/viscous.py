"""Viscous friction ``b*w``, one coefficient per direction [N*m*s/rad]."""

from __future__ import annotations

from ..law import DirectionalLaw, Law, direction_pair, pick

__all__ = ["Viscous", "LAW"]


class Viscous(DirectionalLaw):
    """Viscous friction ``b*omega`` (or ``b_pos``/``b_neg`` per direction) [N*m*s/rad]."""

    coefficients = ("viscous_pos", "viscous_neg")


def term(w, s, viscous_pos, viscous_neg):
    return pick(s, viscous_pos, viscous_neg) * w


def compiled(w, s, viscous_pos, viscous_neg):
    return (viscous_pos if s > 0 else viscous_neg) * w


def regressors(w, symmetric):
    if symmetric:
        return {"viscous": w}
    pos, neg = (w > 0).astype(float), (w < 0).astype(float)
    return {"viscous_pos": w * pos, "viscous_neg": w * neg}


LAW = Law(
    name="viscous", order=10, role="rate", constructor=Viscous,
    description="lubricated shear: a torque proportional to the velocity",
    coefficients=direction_pair("viscous", "N*m*s/rad", "viscous coefficient"),
    term=term, compiled=compiled, regressors=regressors,
    damping=lambda c, speed: max(c["viscous_pos"], c["viscous_neg"]),
)
