"""What the presliding laws with a state (LuGre, Dahl) share: the bristle along a measured motion.

Not a law (no ``LAW``): the helpers the state laws of :mod:`fricctl.friction.laws` build
their ``along_motion``, ``initial`` and checks from, and the bristle state the diagnosis's
presliding cause regresses on.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import jit

__all__ = ["bristle_state", "check_state_law", "level_along", "deflection_scale"]


@jit
def bristle_state(q, xc, z0, exponent):
    """Normalised bristle state ``n = sigma0*z/g`` along a position record.

    ``dn/dx = |1 - sign(dx)*n|^alpha * sign(1 - sign(dx)*n) / xc``: exact per step for
    ``alpha = 1`` (``n <- s + (n - s)*exp(-|dx|/xc)``, ``s = sign(dx)``), else RK4 on eight
    sub-steps of each step [-].
    """
    z = np.empty(q.size)
    if q.size == 0:  # nothing to integrate (and no z[0] to write)
        return z
    zz = z0
    z[0] = zz
    for k in range(1, q.size):
        dx = q[k] - q[k - 1]
        if dx != 0.0:
            s = 1.0 if dx > 0 else -1.0
            if exponent == 1.0:
                zz = s + (zz - s) * math.exp(-abs(dx) / xc)
            else:
                h = abs(dx) / 8.0
                for _i in range(8):  # along |x|: dn/d|x| = s*f(1 - s*n)/xc
                    k1 = _dn(zz, s, xc, exponent)
                    k2 = _dn(zz + 0.5 * h * k1, s, xc, exponent)
                    k3 = _dn(zz + 0.5 * h * k2, s, xc, exponent)
                    k4 = _dn(zz + h * k3, s, xc, exponent)
                    zz = zz + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
        z[k] = zz
    return z


@jit
def _dn(n, s, xc, exponent):
    u = 1.0 - s * n
    return s * abs(u) ** exponent * (1.0 if u >= 0.0 else -1.0) / xc


def check_state_law(model, name: str, switch: float) -> None:
    """What every presliding law needs of the model it is in (LuGre, Dahl)."""
    if switch > 0 and (model.static_excess_pos > 0 or model.static_excess_neg > 0):
        raise ValueError(f"{name} replaces stiction by bristle dynamics: it cannot be combined "
                         "with a Static law (use Stribeck for the breakaway excess)")
    if switch > 0 and min(model.coulomb_pos, model.coulomb_neg) <= 0:
        raise ValueError(f"{name} needs a Coulomb level > 0 in both directions (g(omega) > 0)")


def deflection_scale(model, sigma0: float) -> float:
    """``x_c = min(Fc)/sigma0``: the presliding displacement at the Coulomb level [rad]."""
    return min(model.coulomb_pos, model.coulomb_neg) / sigma0


def level_along(model, n, omega, tm):
    """The level ``g`` along a measured motion, not scaled [N*m]: every level law (Coulomb,
    Stribeck at the speed given, load) in the deflection's direction -- the laws of the ``g``
    the plant's state equation slides at, read two ways differently: the plant takes the
    direction of the velocity (after a reversal, the deflection's sign follows a few
    presliding lengths later; a difference only where the levels differ by direction), and
    its own speed, where this reads the speed it is given (a record's estimated velocity,
    which at low speed steps with the encoder's counts).

    (Coulomb and load alone until 2026-11-28: a LuGre joint's Stribeck hump, which the plant
    simulates, was missing from the torque along the motion, so a record's labels weighed the
    hump of a Stribeck hidden beside presliding at 0 % and the diagnosis's residual of such a
    model ignored it.)
    """
    return model.level(omega, np.where(n >= 0, 1.0, -1.0), tm)
