"""The drive joint: rigid (paper Eq. 2) and flexible (paper Eq. 1), exact stick-slip.

Rigid joint (Eq. 2)::

    I * q'' = Tm - Tat(q, q', Tm, t)

Flexible joint (Eq. 1, friction on the motor side, encoder on the rotor)::

    Jm * qm'' = Tm - Tat(qm, qm', Tm, t) - K*(qm - ql) - d*(qm' - ql')
    Jl * ql'' =      K*(qm - ql) + d*(qm' - ql')

All quantities are load side (the rotor is reflected through the gear).

Stick-slip is handled exactly, not smoothed:

* at zero velocity the joint is *stuck* while the net drive torque lies within
  the breakaway band ``[-breakaway(-1), +breakaway(+1)]``; its position is then
  exactly constant (for the flexible joint, the load still moves on the spring);
* while sliding, the smooth sliding dynamics of the current direction are
  integrated with classical RK4 on ``substeps`` sub-intervals of each sample;
* a velocity that reaches zero inside a sub-interval is located by bisection on
  the RK4 map to machine precision; there the stick condition decides between
  stopping and reversing; the flexible joint's release from stick (the spring
  torque crossing the breakaway band) is located the same way.

No chattering arises because the friction of a stuck joint is not a function of
velocity (it is the reaction that keeps it at rest).

With :class:`fricctl.friction.LuGre` the joint has no exact stick (presliding
bristles); the state (q, omega, z) is integrated by RK4 with no events, so use
more substeps (the bristle dynamics are stiff at high speed).

Notes
-----
Not modelled: backlash, motor electrical dynamics, the kinematic error of the
harmonic drive (use a :class:`~fricctl.friction.PositionRipple`).  A stuck
flexible joint is tested for release once per sub-interval and at its end: an
excursion outside the breakaway band shorter than one sub-interval is missed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from .friction import IDX, FrictionModel, _Law
from .params import ActuatorParams

__all__ = ["RigidJoint", "FlexibleJoint", "RIGID", "FLEXIBLE", "LUGRE"]

#: Plant kinds understood by the compiled kernel.
RIGID, FLEXIBLE, LUGRE = 0, 1, 2

_VP, _VN, _CP, _CN = IDX["viscous_pos"], IDX["viscous_neg"], IDX["coulomb_pos"], IDX["coulomb_neg"]
_SP, _SN = IDX["static_pos"], IDX["static_neg"]
_STP, _STN, _VS, _DEL = IDX["stribeck_pos"], IDX["stribeck_neg"], IDX["stribeck_velocity"], IDX["stribeck_exponent"]
_RA, _RP, _RPH = IDX["ripple_amplitude"], IDX["ripple_period"], IDX["ripple_phase"]
_MU, _SC, _DR = IDX["load_coefficient"], IDX["scale"], IDX["drift"]
_L0, _L1 = IDX["lugre_sigma0"], IDX["lugre_sigma1"]
_TWO_PI = 2.0 * math.pi


# --------------------------------------------------------------------------
# friction primitives (compiled)
# --------------------------------------------------------------------------
@njit(cache=True)
def _ripple(fp, q):
    if fp[_RA] == 0.0:
        return 0.0
    return fp[_RA] * math.sin(_TWO_PI * q / fp[_RP] + fp[_RPH])


@njit(cache=True)
def _level(fp, w, s, tm, t):
    """Coulomb + load + Stribeck level (scaled) in direction s at speed |w|."""
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


@njit(cache=True)
def _viscous(fp, w, s, t):
    b = fp[_VP] if s > 0 else fp[_VN]
    return fp[_SC] * (1.0 + fp[_DR] * t) * b * w


@njit(cache=True)
def _sliding(fp, w, s, tm, t):
    """Friction torque (no ripple) while sliding in direction s; smooth in w."""
    return _viscous(fp, w, s, t) + s * _level(fp, w, s, tm, t)


@njit(cache=True)
def _breakaway(fp, s, tm, t):
    if s > 0:
        base = fp[_CP] + fp[_SP] + fp[_STP]
    else:
        base = fp[_CN] + fp[_SN] + fp[_STN]
    return fp[_SC] * (1.0 + fp[_DR] * t) * (base + fp[_MU] * abs(tm))


# --------------------------------------------------------------------------
# rigid joint
# --------------------------------------------------------------------------
@njit(cache=True)
def _rigid_acc(fp, q, w, s, tm, t, inv_i):
    return (tm - _sliding(fp, w, s, tm, t) - _ripple(fp, q)) * inv_i


@njit(cache=True)
def _rigid_rk4(fp, q, w, s, tm, t, h, inv_i):
    a1 = _rigid_acc(fp, q, w, s, tm, t, inv_i)
    q2 = q + 0.5 * h * w
    w2 = w + 0.5 * h * a1
    a2 = _rigid_acc(fp, q2, w2, s, tm, t + 0.5 * h, inv_i)
    q3 = q + 0.5 * h * w2
    w3 = w + 0.5 * h * a2
    a3 = _rigid_acc(fp, q3, w3, s, tm, t + 0.5 * h, inv_i)
    q4 = q + h * w3
    w4 = w + h * a3
    a4 = _rigid_acc(fp, q4, w4, s, tm, t + h, inv_i)
    return (q + h / 6.0 * (w + 2.0 * w2 + 2.0 * w3 + w4),
            w + h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4))


@njit(cache=True)
def _rigid_interval(fp, q, w, tm, t0, dt, nsub, inv_i):
    """Advance the rigid joint over [t0, t0+dt) under constant torque tm."""
    h = dt / nsub
    for i in range(nsub):
        rem = h
        t = t0 + i * h
        for _ev in range(32):
            if w == 0.0:
                net = tm - _ripple(fp, q)
                if net > _breakaway(fp, 1.0, tm, t):
                    s = 1.0
                elif -net > _breakaway(fp, -1.0, tm, t):
                    s = -1.0
                else:
                    break  # stuck: q unchanged, exactly
            else:
                s = 1.0 if w > 0.0 else -1.0
            qn, wn = _rigid_rk4(fp, q, w, s, tm, t, rem, inv_i)
            if s * wn > 0.0:
                q = qn
                w = wn
                break
            # the velocity reaches zero inside the step: locate it
            lo = 0.0
            hi = rem
            if w == 0.0:  # from rest: find a point where it has started to move
                lo = rem
                moving = False
                for _k in range(80):
                    lo *= 0.5
                    ql, wl = _rigid_rk4(fp, q, w, s, tm, t, lo, inv_i)
                    if s * wl > 0.0:
                        moving = True
                        break
                if not moving:
                    break  # numerically at the breakaway limit: stays at rest
            for _k in range(80):
                mid = 0.5 * (lo + hi)
                if mid <= lo or mid >= hi:
                    break
                qm, wm = _rigid_rk4(fp, q, w, s, tm, t, mid, inv_i)
                if s * wm > 0.0:
                    lo = mid
                else:
                    hi = mid
            qn, wn = _rigid_rk4(fp, q, w, s, tm, t, hi, inv_i)
            q = qn
            w = 0.0
            rem -= hi
            t += hi
            if rem <= 0.0:
                break
    return q, w


@njit(cache=True)
def _rigid_state_torque(fp, q, w, tm, t, inv_i):
    """Resistive torque Tat and acceleration right after t (torque tm applied)."""
    if w == 0.0:
        net = tm - _ripple(fp, q)
        if net > _breakaway(fp, 1.0, tm, t):
            f = _breakaway(fp, 1.0, tm, t) + _ripple(fp, q)
        elif -net > _breakaway(fp, -1.0, tm, t):
            f = -_breakaway(fp, -1.0, tm, t) + _ripple(fp, q)
        else:
            return tm, 0.0  # stuck: friction is the reaction
        return f, (tm - f) * inv_i
    s = 1.0 if w > 0.0 else -1.0
    f = _sliding(fp, w, s, tm, t) + _ripple(fp, q)
    return f, (tm - f) * inv_i


# --------------------------------------------------------------------------
# flexible joint (Eq. 1)
# --------------------------------------------------------------------------
@njit(cache=True)
def _flex_deriv(fp, qm, wm, ql, wl, s, tm, t, jm, jl, k, d):
    spring = k * (qm - ql) + d * (wm - wl)
    am = (tm - _sliding(fp, wm, s, tm, t) - _ripple(fp, qm) - spring) / jm
    al = spring / jl
    return am, al


@njit(cache=True)
def _flex_rk4(fp, qm, wm, ql, wl, s, tm, t, h, jm, jl, k, d, stuck):
    """One RK4 step; with stuck=True the motor is held (qm fixed, wm = 0)."""
    a1m, a1l = _flex_deriv(fp, qm, wm, ql, wl, s, tm, t, jm, jl, k, d)
    if stuck:
        a1m = 0.0
    qm2 = qm + 0.5 * h * wm
    wm2 = wm + 0.5 * h * a1m
    ql2 = ql + 0.5 * h * wl
    wl2 = wl + 0.5 * h * a1l
    a2m, a2l = _flex_deriv(fp, qm2, wm2, ql2, wl2, s, tm, t + 0.5 * h, jm, jl, k, d)
    if stuck:
        a2m = 0.0
    qm3 = qm + 0.5 * h * wm2
    wm3 = wm + 0.5 * h * a2m
    ql3 = ql + 0.5 * h * wl2
    wl3 = wl + 0.5 * h * a2l
    a3m, a3l = _flex_deriv(fp, qm3, wm3, ql3, wl3, s, tm, t + 0.5 * h, jm, jl, k, d)
    if stuck:
        a3m = 0.0
    qm4 = qm + h * wm3
    wm4 = wm + h * a3m
    ql4 = ql + h * wl3
    wl4 = wl + h * a3l
    a4m, a4l = _flex_deriv(fp, qm4, wm4, ql4, wl4, s, tm, t + h, jm, jl, k, d)
    if stuck:
        a4m = 0.0
    return (qm + h / 6.0 * (wm + 2.0 * wm2 + 2.0 * wm3 + wm4),
            wm + h / 6.0 * (a1m + 2.0 * a2m + 2.0 * a3m + a4m),
            ql + h / 6.0 * (wl + 2.0 * wl2 + 2.0 * wl3 + wl4),
            wl + h / 6.0 * (a1l + 2.0 * a2l + 2.0 * a3l + a4l))


@njit(cache=True)
def _flex_net(fp, qm, ql, wl, tm, k, d):
    """Drive torque on the stuck motor (everything but friction)."""
    return tm - _ripple(fp, qm) - k * (qm - ql) + d * wl


@njit(cache=True)
def _flex_band(fp, u, tm, t):
    """+1 / -1 when u breaks the joint loose in that direction, 0 inside the band."""
    if u > _breakaway(fp, 1.0, tm, t):
        return 1.0
    if -u > _breakaway(fp, -1.0, tm, t):
        return -1.0
    return 0.0


@njit(cache=True)
def _flex_interval(fp, qm, wm, ql, wl, tm, t0, dt, nsub, jm, jl, k, d):
    h = dt / nsub
    for i in range(nsub):
        rem = h
        t = t0 + i * h
        for _ev in range(32):
            if rem <= 0.0:
                break
            if wm == 0.0:
                s = _flex_band(fp, _flex_net(fp, qm, ql, wl, tm, k, d), tm, t)
                if s == 0.0:
                    a, b, ql1, wl1 = _flex_rk4(fp, qm, 0.0, ql, wl, 1.0, tm, t, rem, jm, jl, k, d, True)
                    if _flex_band(fp, _flex_net(fp, qm, ql1, wl1, tm, k, d), tm, t + rem) == 0.0:
                        ql = ql1
                        wl = wl1
                        break
                    lo = 0.0
                    hi = rem
                    for _k in range(80):
                        mid = 0.5 * (lo + hi)
                        if mid <= lo or mid >= hi:
                            break
                        a, b, qlm, wlm = _flex_rk4(fp, qm, 0.0, ql, wl, 1.0, tm, t, mid, jm, jl, k, d, True)
                        if _flex_band(fp, _flex_net(fp, qm, qlm, wlm, tm, k, d), tm, t + mid) == 0.0:
                            lo = mid
                        else:
                            hi = mid
                    a, b, ql, wl = _flex_rk4(fp, qm, 0.0, ql, wl, 1.0, tm, t, hi, jm, jl, k, d, True)
                    rem -= hi
                    t += hi
                    continue  # now outside the band: released on the next pass
            else:
                s = 1.0 if wm > 0.0 else -1.0
            qm1, wm1, ql1, wl1 = _flex_rk4(fp, qm, wm, ql, wl, s, tm, t, rem, jm, jl, k, d, False)
            if s * wm1 > 0.0:
                qm, wm, ql, wl = qm1, wm1, ql1, wl1
                break
            lo = 0.0
            hi = rem
            if wm == 0.0:
                lo = rem
                moving = False
                for _k in range(80):
                    lo *= 0.5
                    a, wml, c, e = _flex_rk4(fp, qm, wm, ql, wl, s, tm, t, lo, jm, jl, k, d, False)
                    if s * wml > 0.0:
                        moving = True
                        break
                if not moving:
                    # at the band's edge numerically: hold the motor for this sub-step
                    a, b, ql, wl = _flex_rk4(fp, qm, 0.0, ql, wl, 1.0, tm, t, rem, jm, jl, k, d, True)
                    break
            for _k in range(80):
                mid = 0.5 * (lo + hi)
                if mid <= lo or mid >= hi:
                    break
                a, wmm, c, e = _flex_rk4(fp, qm, wm, ql, wl, s, tm, t, mid, jm, jl, k, d, False)
                if s * wmm > 0.0:
                    lo = mid
                else:
                    hi = mid
            qm, wm, ql, wl = _flex_rk4(fp, qm, wm, ql, wl, s, tm, t, hi, jm, jl, k, d, False)
            wm = 0.0
            rem -= hi
            t += hi
    return qm, wm, ql, wl


@njit(cache=True)
def _flex_state_torque(fp, qm, wm, ql, wl, tm, t, jm, k, d):
    spring = k * (qm - ql) + d * (wm - wl)
    if wm == 0.0:
        u = tm - _ripple(fp, qm) - spring
        s = _flex_band(fp, u, tm, t)
        if s == 0.0:
            return tm - spring, 0.0  # reaction: friction + ripple = tm - spring
        f = s * _breakaway(fp, s, tm, t) + _ripple(fp, qm)
        return f, (tm - f - spring) / jm
    s = 1.0 if wm > 0.0 else -1.0
    f = _sliding(fp, wm, s, tm, t) + _ripple(fp, qm)
    return f, (tm - f - spring) / jm


# --------------------------------------------------------------------------
# LuGre (rigid, smooth; no events)
# --------------------------------------------------------------------------
@njit(cache=True)
def _lugre_deriv(fp, q, w, z, tm, t, inv_i):
    s = 1.0 if w >= 0.0 else -1.0
    g = _level(fp, w, s, tm, t)
    zd = w - fp[_L0] * abs(w) * z / g
    f = fp[_L0] * z + fp[_L1] * zd + _viscous(fp, w, s, t) + _ripple(fp, q)
    return (tm - f) * inv_i, zd, f


@njit(cache=True)
def _lugre_interval(fp, q, w, z, tm, t0, dt, nsub, inv_i):
    h = dt / nsub
    for i in range(nsub):
        t = t0 + i * h
        a1, z1, f = _lugre_deriv(fp, q, w, z, tm, t, inv_i)
        a2, z2, f = _lugre_deriv(fp, q + 0.5 * h * w, w + 0.5 * h * a1, z + 0.5 * h * z1, tm, t + 0.5 * h, inv_i)
        w2 = w + 0.5 * h * a1
        a3, z3, f = _lugre_deriv(fp, q + 0.5 * h * w2, w + 0.5 * h * a2, z + 0.5 * h * z2, tm, t + 0.5 * h, inv_i)
        w3 = w + 0.5 * h * a2
        a4, z4, f = _lugre_deriv(fp, q + h * w3, w + h * a3, z + h * z3, tm, t + h, inv_i)
        w4 = w + h * a3
        q = q + h / 6.0 * (w + 2.0 * w2 + 2.0 * w3 + w4)
        w = w + h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4)
        z = z + h / 6.0 * (z1 + 2.0 * z2 + 2.0 * z3 + z4)
    return q, w, z


# --------------------------------------------------------------------------
# one interval, any plant kind; state = [q (motor), omega (motor), ql, omega_l, z]
# --------------------------------------------------------------------------
@njit(cache=True)
def advance(kind, st, fp, tm, t0, dt, nsub, jm, jl, k, d):
    """Advance state ``st`` (modified in place) over one held-torque interval."""
    if kind == RIGID:
        st[0], st[1] = _rigid_interval(fp, st[0], st[1], tm, t0, dt, nsub, 1.0 / jm)
        st[2] = st[0]
        st[3] = st[1]
    elif kind == FLEXIBLE:
        st[0], st[1], st[2], st[3] = _flex_interval(fp, st[0], st[1], st[2], st[3], tm, t0, dt,
                                                     nsub, jm, jl, k, d)
    else:
        st[0], st[1], st[4] = _lugre_interval(fp, st[0], st[1], st[4], tm, t0, dt, nsub, 1.0 / jm)
        st[2] = st[0]
        st[3] = st[1]


@njit(cache=True)
def state_torque(kind, st, fp, tm, t, jm, k, d):
    """(resistive torque Tat on the motor side, motor acceleration) right after t."""
    if kind == RIGID:
        return _rigid_state_torque(fp, st[0], st[1], tm, t, 1.0 / jm)
    if kind == FLEXIBLE:
        return _flex_state_torque(fp, st[0], st[1], st[2], st[3], tm, t, jm, k, d)
    acc, zd, f = _lugre_deriv(fp, st[0], st[1], st[4], tm, t, 1.0 / jm)
    return f, acc


@njit(cache=True)
def advance_many(kind, states, fps, tms, t0, dt, nsub, jm, jl, k, d):
    """Advance N states (rows of ``states``) over one interval; arrays of length N."""
    for n in range(states.shape[0]):
        advance(kind, states[n], fps[n], tms[n], t0, dt, nsub, jm[n], jl[n], k[n], d[n])


# --------------------------------------------------------------------------
# public plant objects
# --------------------------------------------------------------------------
@dataclass(frozen=True, kw_only=True)
class RigidJoint:
    """Rigid joint ``I*q'' = Tm - Tat`` (paper Eq. 2).

    Parameters
    ----------
    inertia : float
        Total inertia I (actuator + link), load side [kg*m^2].
    friction : FrictionModel
        Resistive torque law.  A :class:`~fricctl.friction.LuGre` model is
        integrated without stick events.

    Examples
    --------
    >>> from fricctl.params import paper_actuator
    >>> p = paper_actuator()
    >>> joint = RigidJoint.from_params(p)
    >>> st = joint.initial_state()
    >>> float(joint.advance(st, torque=0.9 * p.static, t0=0.0, dt=0.002)[0])   # below breakaway
    0.0
    """

    inertia: float
    friction: FrictionModel

    def __post_init__(self):
        if not (isinstance(self.inertia, (int, float)) and math.isfinite(self.inertia) and self.inertia > 0):
            raise ValueError(f"inertia must be a finite number > 0 [kg*m^2], got {self.inertia!r}")
        if isinstance(self.friction, _Law):
            object.__setattr__(self, "friction", self.friction.model())
        if not isinstance(self.friction, FrictionModel):
            raise ValueError("friction must be a fricctl.friction.FrictionModel")

    @classmethod
    def from_params(cls, params: ActuatorParams, friction: FrictionModel | None = None):
        return cls(inertia=params.total_inertia,
                   friction=params.friction_model() if friction is None else friction)

    @property
    def kind(self) -> int:
        return LUGRE if self.friction.is_lugre else RIGID

    def kernel_args(self):
        """(kind, motor inertia, load inertia, stiffness, damping) for the compiled kernel."""
        return self.kind, self.inertia, self.inertia, 0.0, 0.0

    def initial_state(self, q0: float = 0.0, omega0: float = 0.0) -> np.ndarray:
        """State vector ``[q, omega, q_load, omega_load, z]``."""
        return np.array([q0, omega0, q0, omega0, 0.0], dtype=float)

    def advance(self, state, torque: float, t0: float, dt: float, substeps: int = 4) -> np.ndarray:
        """State after holding ``torque`` [N*m] for ``dt`` [s] from time ``t0`` [s]."""
        st = _checked_state(state)
        if not (math.isfinite(torque) and math.isfinite(t0) and dt > 0):
            raise ValueError("torque and t0 must be finite and dt > 0")
        kind, jm, jl, k, d = self.kernel_args()
        advance(kind, st, self.friction.vector(), float(torque), float(t0), float(dt),
                _checked_substeps(substeps), jm, jl, k, d)
        return st

    def resistive_torque(self, state, torque: float, t: float = 0.0):
        """(Tat [N*m], acceleration [rad/s^2]) right after ``t`` with ``torque`` applied."""
        st = _checked_state(state)
        kind, jm, jl, k, d = self.kernel_args()
        return state_torque(kind, st, self.friction.vector(), float(torque), float(t), jm, k, d)


@dataclass(frozen=True, kw_only=True)
class FlexibleJoint:
    """Elastic joint of paper Eq. 1: motor and load inertias joined by K and d.

    Friction acts on the motor side; the encoder is on the rotor (motor side).

    Parameters
    ----------
    motor_inertia : float
        Jm, rotor and flange reflected to the load side [kg*m^2].
    load_inertia : float
        Jl, link (and output flange) [kg*m^2].
    stiffness : float
        K [N*m/rad].
    damping : float
        d [N*m*s/rad].
    friction : FrictionModel
        Motor-side resistive torque law (LuGre not supported here).
    """

    motor_inertia: float
    load_inertia: float
    stiffness: float
    damping: float
    friction: FrictionModel

    def __post_init__(self):
        for name in ("motor_inertia", "load_inertia", "stiffness"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ValueError(f"{name} must be a finite number > 0, got {v!r}")
        if not (math.isfinite(self.damping) and self.damping >= 0):
            raise ValueError(f"damping must be finite and >= 0, got {self.damping!r}")
        if isinstance(self.friction, _Law):
            object.__setattr__(self, "friction", self.friction.model())
        if not isinstance(self.friction, FrictionModel):
            raise ValueError("friction must be a fricctl.friction.FrictionModel")
        if self.friction.is_lugre:
            raise ValueError("LuGre friction is supported on the rigid joint only")

    @classmethod
    def from_params(cls, params: ActuatorParams, friction: FrictionModel | None = None):
        if params.link_inertia <= 0:
            raise ValueError("link_inertia must be > 0 for a flexible joint (the load side needs inertia)")
        return cls(motor_inertia=params.inertia, load_inertia=params.link_inertia,
                   stiffness=params.stiffness, damping=params.joint_damping,
                   friction=params.friction_model() if friction is None else friction)

    @property
    def kind(self) -> int:
        return FLEXIBLE

    @property
    def resonance(self) -> float:
        """Locked-rotor-free resonance sqrt(K (1/Jm + 1/Jl)) [rad/s]."""
        return math.sqrt(self.stiffness * (1.0 / self.motor_inertia + 1.0 / self.load_inertia))

    def kernel_args(self):
        return FLEXIBLE, self.motor_inertia, self.load_inertia, self.stiffness, self.damping

    def initial_state(self, q0: float = 0.0, omega0: float = 0.0) -> np.ndarray:
        return np.array([q0, omega0, q0, omega0, 0.0], dtype=float)

    advance = RigidJoint.advance
    resistive_torque = RigidJoint.resistive_torque


def _checked_state(state) -> np.ndarray:
    st = np.array(state, dtype=float)
    if st.shape != (5,):
        raise ValueError(f"state must have shape (5,) [q, omega, q_load, omega_load, z], got {st.shape}")
    if not np.all(np.isfinite(st)):
        raise ValueError("state contains NaN or inf")
    return st


def _checked_substeps(substeps) -> int:
    if isinstance(substeps, bool) or not isinstance(substeps, (int, np.integer)) or substeps < 1:
        raise ValueError(f"substeps must be a positive integer, got {substeps!r}")
    return int(substeps)
