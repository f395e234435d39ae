"""Coulomb friction ``Fc*sign(w)``, breakaway ``Fc``, one level per direction [N*m]."""

from __future__ import annotations

from ..law import DirectionalLaw, Law, direction_pair, pick

__all__ = ["Coulomb", "LAW"]


class Coulomb(DirectionalLaw):
    """Coulomb friction ``Fc*sign(omega)``, breakaway ``Fc`` [N*m]."""

    coefficients = ("coulomb_pos", "coulomb_neg")


def term(w, s, tm, coulomb_pos, coulomb_neg):
    return pick(s, coulomb_pos, coulomb_neg) + 0.0 * w


def compiled(w, s, tm, coulomb_pos, coulomb_neg):
    return coulomb_pos if s > 0 else coulomb_neg


def regressors(w, symmetric):
    import numpy as np

    s = np.sign(w)
    if symmetric:
        return {"coulomb": s}
    return {"coulomb_pos": s * (1.0 + s) / 2.0, "coulomb_neg": s * (1.0 - s) / 2.0}


LAW = Law(
    name="coulomb", order=20, role="level", constructor=Coulomb,
    description="dry sliding friction: a constant level opposing the motion",
    coefficients=direction_pair("coulomb", "N*m", "Coulomb level"),
    term=term, compiled=compiled, regressors=regressors,
)
