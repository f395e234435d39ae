"""Compiled plant kernels: one held-torque interval of the rigid, flexible or presliding joint.

The state is ``[q (motor), omega (motor), q_load, omega_load, z]``; see
:mod:`fricctl.plant` for the equations and the event handling.
"""

from __future__ import annotations

import numpy as np

from .._jit import jit
from ..friction.compiled import breakaway as _breakaway
from ..friction.compiled import level as _level
from ..friction.compiled import rate as _rate
from ..friction.compiled import ripple as _ripple
from ..friction.compiled import sliding as _sliding
from ..friction.compiled import state as _state

__all__ = ["RIGID", "FLEXIBLE", "STATE", "LUGRE", "advance", "state_torque"]

#: Plant kinds understood by the compiled kernel: a rigid joint with exact stick, the elastic
#: joint (Eq. 1), a rigid joint whose friction has a presliding state (LuGre, Dahl).
RIGID, FLEXIBLE, STATE = 0, 1, 2
#: The presliding kind under its first law's name (kept for callers of fricctl < 0.2).
LUGRE = STATE


# --------------------------------------------------------------------------
# rigid joint
# --------------------------------------------------------------------------
@jit
def _rigid_acc(fp, q, w, s, tm, t, inv_i):
    return (tm - _sliding(fp, w, s, tm, t) - _ripple(fp, q)) * inv_i


@jit
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


@jit
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


@jit
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
@jit
def _coupling(k, d, gap, x, v):
    """Torque the motor passes to the load across the spring (or the contact) at deflection
    ``x = qm - ql`` and deflection rate ``v``.

    Without a gap (``gap == 0``): the spring and damper of Eq. 1, ``k*x + d*v``.  With a
    dead band of total width ``gap``: nothing while ``|x| <= gap/2`` (the motor crosses the
    gap with the load uncoupled); in contact, the spring acts on the dead-zoned deflection and
    the damper only there, and the contact only pushes (a tooth face does not pull: the
    torque is cut at zero when the damper would make it pull while the faces separate).
    """
    if gap <= 0.0:
        return k * x + d * v
    h = 0.5 * gap
    if x > h:
        f = k * (x - h) + d * v
        return f if f > 0.0 else 0.0
    if x < -h:
        f = k * (x + h) + d * v
        return f if f < 0.0 else 0.0
    return 0.0


@jit
def _flex_deriv(fp, qm, wm, ql, wl, s, tm, t, jm, jl, k, d, gap):
    spring = _coupling(k, d, gap, qm - ql, wm - wl)
    am = (tm - _sliding(fp, wm, s, tm, t) - _ripple(fp, qm) - spring) / jm
    al = spring / jl
    return am, al


@jit
def _flex_rk4(fp, qm, wm, ql, wl, s, tm, t, h, jm, jl, k, d, gap, stuck):
    """One RK4 step; with stuck=True the motor is held (qm fixed, wm = 0)."""
    a1m, a1l = _flex_deriv(fp, qm, wm, ql, wl, s, tm, t, jm, jl, k, d, gap)
    if stuck:
        a1m = 0.0
    qm2 = qm + 0.5 * h * wm
    wm2 = wm + 0.5 * h * a1m
    ql2 = ql + 0.5 * h * wl
    wl2 = wl + 0.5 * h * a1l
    a2m, a2l = _flex_deriv(fp, qm2, wm2, ql2, wl2, s, tm, t + 0.5 * h, jm, jl, k, d, gap)
    if stuck:
        a2m = 0.0
    qm3 = qm + 0.5 * h * wm2
    wm3 = wm + 0.5 * h * a2m
    ql3 = ql + 0.5 * h * wl2
    wl3 = wl + 0.5 * h * a2l
    a3m, a3l = _flex_deriv(fp, qm3, wm3, ql3, wl3, s, tm, t + 0.5 * h, jm, jl, k, d, gap)
    if stuck:
        a3m = 0.0
    qm4 = qm + h * wm3
    wm4 = wm + h * a3m
    ql4 = ql + h * wl3
    wl4 = wl + h * a3l
    a4m, a4l = _flex_deriv(fp, qm4, wm4, ql4, wl4, s, tm, t + h, jm, jl, k, d, gap)
    if stuck:
        a4m = 0.0
    return (qm + h / 6.0 * (wm + 2.0 * wm2 + 2.0 * wm3 + wm4),
            wm + h / 6.0 * (a1m + 2.0 * a2m + 2.0 * a3m + a4m),
            ql + h / 6.0 * (wl + 2.0 * wl2 + 2.0 * wl3 + wl4),
            wl + h / 6.0 * (a1l + 2.0 * a2l + 2.0 * a3l + a4l))


@jit
def _flex_net(fp, qm, ql, wl, tm, k, d, gap):
    """Drive torque on the stuck motor (everything but friction)."""
    return tm - _ripple(fp, qm) - _coupling(k, d, gap, qm - ql, -wl)


@jit
def _flex_band(fp, u, tm, t):
    """+1 / -1 when u breaks the joint loose in that direction, 0 inside the band."""
    if u > _breakaway(fp, 1.0, tm, t):
        return 1.0
    if -u > _breakaway(fp, -1.0, tm, t):
        return -1.0
    return 0.0


@jit
def _flex_interval(fp, qm, wm, ql, wl, tm, t0, dt, nsub, jm, jl, k, d, gap):
    h = dt / nsub
    for i in range(nsub):
        rem = h
        t = t0 + i * h
        for _ev in range(32):
            if rem <= 0.0:
                break
            if wm == 0.0:
                s = _flex_band(fp, _flex_net(fp, qm, ql, wl, tm, k, d, gap), tm, t)
                if s == 0.0:
                    a, b, ql1, wl1 = _flex_rk4(fp, qm, 0.0, ql, wl, 1.0, tm, t, rem, jm, jl, k, d, gap, True)
                    if _flex_band(fp, _flex_net(fp, qm, ql1, wl1, tm, k, d, gap), tm, t + rem) == 0.0:
                        ql = ql1
                        wl = wl1
                        break
                    lo = 0.0
                    hi = rem
                    for _k in range(80):
                        mid = 0.5 * (lo + hi)
                        if mid <= lo or mid >= hi:
                            break
                        a, b, qlm, wlm = _flex_rk4(fp, qm, 0.0, ql, wl, 1.0, tm, t, mid, jm, jl, k, d, gap, True)
                        if _flex_band(fp, _flex_net(fp, qm, qlm, wlm, tm, k, d, gap), tm, t + mid) == 0.0:
                            lo = mid
                        else:
                            hi = mid
                    a, b, ql, wl = _flex_rk4(fp, qm, 0.0, ql, wl, 1.0, tm, t, hi, jm, jl, k, d, gap, True)
                    rem -= hi
                    t += hi
                    continue  # now outside the band: released on the next pass
            else:
                s = 1.0 if wm > 0.0 else -1.0
            qm1, wm1, ql1, wl1 = _flex_rk4(fp, qm, wm, ql, wl, s, tm, t, rem, jm, jl, k, d, gap, False)
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
                    a, wml, c, e = _flex_rk4(fp, qm, wm, ql, wl, s, tm, t, lo, jm, jl, k, d, gap, False)
                    if s * wml > 0.0:
                        moving = True
                        break
                if not moving:
                    # at the band's edge numerically: hold the motor for this sub-step
                    a, b, ql, wl = _flex_rk4(fp, qm, 0.0, ql, wl, 1.0, tm, t, rem, jm, jl, k, d, gap, True)
                    break
            for _k in range(80):
                mid = 0.5 * (lo + hi)
                if mid <= lo or mid >= hi:
                    break
                a, wmm, c, e = _flex_rk4(fp, qm, wm, ql, wl, s, tm, t, mid, jm, jl, k, d, gap, False)
                if s * wmm > 0.0:
                    lo = mid
                else:
                    hi = mid
            qm, wm, ql, wl = _flex_rk4(fp, qm, wm, ql, wl, s, tm, t, hi, jm, jl, k, d, gap, False)
            wm = 0.0
            rem -= hi
            t += hi
    return qm, wm, ql, wl


@jit
def _flex_state_torque(fp, qm, wm, ql, wl, tm, t, jm, k, d, gap):
    spring = _coupling(k, d, gap, qm - ql, wm - wl)
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
# presliding state (LuGre, Dahl: rigid, smooth; no events)
# --------------------------------------------------------------------------
@jit
def _state_deriv(fp, q, w, z, tm, t, inv_i):
    s = 1.0 if w >= 0.0 else -1.0
    g = _level(fp, w, s, tm, t)
    zd, fz = _state(fp, w, z, g)
    f = fz + _rate(fp, w, s, t) + _ripple(fp, q)
    return (tm - f) * inv_i, zd, f


@jit
def _state_interval(fp, q, w, z, tm, t0, dt, nsub, inv_i):
    h = dt / nsub
    for i in range(nsub):
        t = t0 + i * h
        a1, z1, f = _state_deriv(fp, q, w, z, tm, t, inv_i)
        a2, z2, f = _state_deriv(fp, q + 0.5 * h * w, w + 0.5 * h * a1, z + 0.5 * h * z1, tm, t + 0.5 * h, inv_i)
        w2 = w + 0.5 * h * a1
        a3, z3, f = _state_deriv(fp, q + 0.5 * h * w2, w + 0.5 * h * a2, z + 0.5 * h * z2, tm, t + 0.5 * h, inv_i)
        w3 = w + 0.5 * h * a2
        a4, z4, f = _state_deriv(fp, q + h * w3, w + h * a3, z + h * z3, tm, t + h, inv_i)
        w4 = w + h * a3
        q = q + h / 6.0 * (w + 2.0 * w2 + 2.0 * w3 + w4)
        w = w + h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4)
        z = z + h / 6.0 * (z1 + 2.0 * z2 + 2.0 * z3 + z4)
    return q, w, z


# --------------------------------------------------------------------------
# one interval, any plant kind; state = [q (motor), omega (motor), ql, omega_l, z]
# --------------------------------------------------------------------------
@jit
def advance(kind, st, fp, tm, t0, dt, nsub, jm, jl, k, d, gap):
    """Advance state ``st`` (modified in place) over one held-torque interval (``gap``: the
    flexible joint's backlash, total width [rad]; 0 for none)."""
    if kind == RIGID:
        st[0], st[1] = _rigid_interval(fp, st[0], st[1], tm, t0, dt, nsub, 1.0 / jm)
        st[2] = st[0]
        st[3] = st[1]
    elif kind == FLEXIBLE:
        st[0], st[1], st[2], st[3] = _flex_interval(fp, st[0], st[1], st[2], st[3], tm, t0, dt,
                                                     nsub, jm, jl, k, d, gap)
    else:
        st[0], st[1], st[4] = _state_interval(fp, st[0], st[1], st[4], tm, t0, dt, nsub, 1.0 / jm)
        st[2] = st[0]
        st[3] = st[1]


@jit
def state_torque(kind, st, fp, tm, t, jm, k, d, gap):
    """(resistive torque Tat on the motor side, motor acceleration) right after t."""
    if kind == RIGID:
        return _rigid_state_torque(fp, st[0], st[1], tm, t, 1.0 / jm)
    if kind == FLEXIBLE:
        return _flex_state_torque(fp, st[0], st[1], st[2], st[3], tm, t, jm, k, d, gap)
    acc, zd, f = _state_deriv(fp, st[0], st[1], st[4], tm, t, 1.0 / jm)
    return f, acc
