r"""LuGre presliding dynamics applied to the Coulomb + Stribeck part (Canudas de Wit et al. 1995).

.. math::

    \dot z = \omega - \sigma_0 \frac{|\omega|}{g(\omega)} z, \qquad
    T = \sigma_0 z + \sigma_1 \dot z + \text{(viscous and other rate terms)},

with ``g`` the Coulomb + Stribeck (+ load) level.  With this law the joint has no exact
stick: it creeps elastically (presliding displacement ~ ``g/sigma0``) below breakaway.
Along a measured motion its bristle is Dahl's (:func:`~fricctl.friction.presliding.bristle_state`,
``alpha = 1``) plus the damping ``sigma1*z'``.
"""

from __future__ import annotations

import numpy as np

from ..law import Coefficient, FrictionLaw, Law, StateEquation
from ..presliding import bristle_state, check_state_law, deflection_scale, level_along

__all__ = ["LuGre", "LAW"]


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
        from ... import _validate as v

        self.sigma0 = v.real("LuGre sigma0", sigma0, positive=True)
        self.sigma1 = v.real("LuGre sigma1", sigma1, nonneg=True)

    def contribution(self):
        return {"lugre_sigma0": self.sigma0, "lugre_sigma1": self.sigma1}


def _compiled(w, z, g, lugre_sigma0, lugre_sigma1):
    zd = w - lugre_sigma0 * abs(w) * z / g
    return zd, lugre_sigma0 * z + lugre_sigma1 * zd


def _along_motion(model, q, w, tm, t):
    n = bristle_state(q, deflection_scale(model, model.lugre_sigma0), 0.0, 1.0)
    damp = model.lugre_sigma1 * w * (1 - np.sign(w) * n)
    return (model.scale_at(t) * (level_along(model, n, w, tm) * n + model.rate_terms(w))
            + model.ripple(q) + damp)


def _initial(model, q):
    xc = deflection_scale(model, model.lugre_sigma0)
    return bristle_state(q, xc, 0.0, 1.0) * xc


LAW = Law(
    name="lugre", order=80, role="state", constructor=LuGre,
    description="LuGre presliding: elastic bristles with damping, the Stribeck curve in steady state",
    coefficients=(
        Coefficient(name="lugre_sigma0", unit="N*m/rad", combine="replace",
                    doc="bristle stiffness sigma0"),
        Coefficient(name="lugre_sigma1", unit="N*m*s/rad", combine="replace",
                    doc="bristle damping sigma1")),
    state=StateEquation(
        switch="lugre_sigma0", compiled=_compiled, along_motion=_along_motion, initial=_initial,
        speed_rate=lambda model, speed: speed / deflection_scale(model, model.lugre_sigma0)),
    damping=lambda c, speed: c["lugre_sigma1"],
    check=lambda model: check_state_law(model, "LuGre", model.lugre_sigma0),
)
