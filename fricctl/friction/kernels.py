"""Compiled (numba) evaluation of a friction parameter vector (layout :mod:`.layout`).

These are the primitives the plant kernels integrate; they compute exactly what
:meth:`fricctl.friction.FrictionModel.torque` and ``breakaway`` compute in numpy,
one sample at a time (``tests/test_friction.py`` pins the two together on random
law mixes).  ``s`` is the direction of motion (+1 or -1), ``tm`` the transmitted
torque, ``t`` the time.
"""

from __future__ import annotations

import math

from .._jit import jit
from .layout import IDX

__all__ = ["ripple", "level", "viscous", "sliding", "breakaway", "scale_at"]

_VP, _VN, _CP, _CN = IDX["viscous_pos"], IDX["viscous_neg"], IDX["coulomb_pos"], IDX["coulomb_neg"]
_SP, _SN = IDX["static_pos"], IDX["static_neg"]
_STP, _STN = IDX["stribeck_pos"], IDX["stribeck_neg"]
_VS, _DEL = IDX["stribeck_velocity"], IDX["stribeck_exponent"]
_RA, _RP, _RPH = IDX["ripple_amplitude"], IDX["ripple_period"], IDX["ripple_phase"]
_MU, _SC, _DR = IDX["load_coefficient"], IDX["scale"], IDX["drift"]
_TWO_PI = 2.0 * math.pi


@jit
def ripple(fp, q):
    """Position-periodic torque at q [N*m] (not scaled: it is not friction)."""
    if fp[_RA] == 0.0:
        return 0.0
    return fp[_RA] * math.sin(_TWO_PI * q / fp[_RP] + fp[_RPH])


@jit
def scale_at(fp, t):
    """Friction scale at time t: ``scale*(1 + drift*t)`` [-]."""
    return fp[_SC] * (1.0 + fp[_DR] * t)


@jit
def level(fp, w, s, tm, t):
    """Coulomb + load + Stribeck level (scaled) in direction s at speed |w| [N*m]."""
    if s > 0:
        fc = fp[_CP]
        fs = fp[_STP]
    else:
        fc = fp[_CN]
        fs = fp[_STN]
    lev = fc + fp[_MU] * abs(tm)
    if fs != 0.0:
        x = abs(w) / fp[_VS]
        if fp[_DEL] == 2.0:
            lev += fs * math.exp(-x * x)
        else:
            lev += fs * math.exp(-(x ** fp[_DEL]))
    return fp[_SC] * (1.0 + fp[_DR] * t) * lev


@jit
def viscous(fp, w, s, t):
    """Viscous torque (scaled) in direction s [N*m]."""
    b = fp[_VP] if s > 0 else fp[_VN]
    return fp[_SC] * (1.0 + fp[_DR] * t) * b * w


@jit
def sliding(fp, w, s, tm, t):
    """Friction torque (no ripple) while sliding in direction s; smooth in w [N*m]."""
    return viscous(fp, w, s, t) + s * level(fp, w, s, tm, t)


@jit
def breakaway(fp, s, tm, t):
    """Torque the drive must exceed to start moving in direction s, a magnitude [N*m]."""
    if s > 0:
        base = fp[_CP] + fp[_SP] + fp[_STP]
    else:
        base = fp[_CN] + fp[_SN] + fp[_STN]
    return fp[_SC] * (1.0 + fp[_DR] * t) * (base + fp[_MU] * abs(tm))
