r"""Dahl's presliding friction: a bristle deflection ``z`` with ``F = sigma0*z``.

.. math::

    \dot z = \omega\,\left|1 - \frac{\sigma_0 z}{g}\,\mathrm{sgn}\,\omega\right|^{\alpha}
             \mathrm{sgn}\!\left(1 - \frac{\sigma_0 z}{g}\,\mathrm{sgn}\,\omega\right),
    \qquad T = \sigma_0 z,

with ``g`` the friction level of the model (Coulomb, Stribeck, load) and ``alpha`` the
shape exponent (Dahl 1968; ``alpha = 1`` is the usual choice and LuGre's bristle without
damping).  Like LuGre it has no exact stick: below breakaway the joint creeps elastically by
about ``g/sigma0``.  Viscous and other rate terms add to it; the position ripple too.

Along a measured motion (the diagnosis) the state is integrated along the position record
(:func:`~fricctl.friction.presliding.bristle_state`), exactly per step for ``alpha = 1``, with the level taken as the
Coulomb level of the deflection's direction plus the load term (the Stribeck part left out).
"""

from __future__ import annotations

from ..law import Coefficient, FrictionLaw, Law, StateEquation
from ..presliding import bristle_state, check_state_law, deflection_scale, level_along

__all__ = ["Dahl", "LAW"]


class Dahl(FrictionLaw):
    """Dahl presliding friction on the model's level.

    Parameters
    ----------
    sigma0 : float
        Bristle stiffness [N*m/rad].
    exponent : float
        Shape exponent alpha in [1, 2] [-] (1: Dahl's usual choice; below 1 the state equation
        is not Lipschitz at the Coulomb level and the fixed-step integrator cannot follow it).
    """

    def __init__(self, sigma0, exponent=1.0):
        from ... import _validate as v

        self.sigma0 = v.real("Dahl sigma0", sigma0, positive=True)
        self.exponent = v.real("Dahl exponent", exponent, positive=True)
        if not 1.0 <= self.exponent <= 2.0:
            raise ValueError(f"Dahl exponent must be in [1, 2], got {self.exponent}")

    def contribution(self):
        return {"dahl_sigma0": self.sigma0, "dahl_exponent": self.exponent}


def _compiled(w, z, g, dahl_sigma0, dahl_exponent):
    if w == 0.0:
        return 0.0, dahl_sigma0 * z
    s = 1.0 if w > 0.0 else -1.0
    u = 1.0 - s * dahl_sigma0 * z / g
    if dahl_exponent == 1.0:
        return w * u, dahl_sigma0 * z
    return w * abs(u) ** dahl_exponent * (1.0 if u >= 0.0 else -1.0), dahl_sigma0 * z


def _along_motion(model, q, w, tm, t):
    n = bristle_state(q, deflection_scale(model, model.dahl_sigma0), 0.0, model.dahl_exponent)
    return model.scale_at(t) * (level_along(model, n, w, tm) * n + model.rate_terms(w)) + model.ripple(q)


def _initial(model, q):
    xc = deflection_scale(model, model.dahl_sigma0)
    return bristle_state(q, xc, 0.0, model.dahl_exponent) * xc


LAW = Law(
    name="dahl", order=90, role="state", constructor=Dahl,
    description="Dahl presliding: an elastic bristle deflection carrying the friction",
    coefficients=(
        Coefficient(name="dahl_sigma0", unit="N*m/rad", combine="replace",
                    doc="bristle stiffness sigma0"),
        Coefficient(name="dahl_exponent", unit="-", default=1.0, lower=1.0, upper=2.0,
                    combine="replace", doc="shape exponent alpha",
                    provenance="Dahl's usual choice")),
    state=StateEquation(
        switch="dahl_sigma0", compiled=_compiled, along_motion=_along_motion, initial=_initial,
        speed_rate=lambda model, speed: speed / deflection_scale(model, model.dahl_sigma0)),
    check=lambda model: check_state_law(model, "Dahl", model.dahl_sigma0),
)
