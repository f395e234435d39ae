"""Compliance: the joint is elastic (paper Eq. 1), a resonance the rigid model lacks.

Regressor: ``LP(a_load) - a`` with ``a_load`` the acceleration of a load on a spring driven by
the measured motion, for natural frequencies on a log grid (8 per decade) from 20 cycles
over the record up to the low-pass cut-off (the band the excitation reaches: above it the
column only smooths encoder noise) and damping ratios 0.02, 0.05, 0.12; coefficient:
the load inertia (>= 0; the model takes at most :data:`MAX_LOAD_SHARE` of the total inertia
fitted with it).  Cannot be told when the coupled resonance lies above that band or the
load share reaches that bound, or when the spring does not stay a spring where the load
torque reverses (a dead band between motor and load, :mod:`.backlash`'s column, removes more
of the residual than the spring: backlash imitated by a soft spring).  Not added to a
model with backlash (its contact is the joint's coupling already).
Bench: link 0.5 .. 1.5 x actuator inertia, coupled resonance 12 .. 40 Hz, structural damping
ratio 0.02 .. 0.1.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
from scipy import signal

from ...plant import FlexibleJoint, JointModel
from ..signals import backlash_load, load_acceleration
from . import backlash as _backlash
from .base import Cause, Injection


#: Largest share of the inertia a fitted load behind the spring may hold [-].
MAX_LOAD_SHARE = 0.95


def _variants(base, fold):
    sig = base.sig
    lowest = 20.0 / (sig.t[-1] - sig.t[0])
    n = max(int(np.floor(8 * np.log10(sig.cutoff / lowest))), 0) + 1
    for wl in 2 * np.pi * lowest * 10.0 ** (np.arange(n) / 8):
        for zeta in (0.02, 0.05, 0.12):
            col = sig.filt(load_acceleration(sig, wl, zeta)) - sig.a
            yield base.variant((float(wl), zeta), col, (1,))


def _extend(model, term, base):
    if model.backlash > 0:
        raise ValueError("backlash: the joint's coupling is a dead band with a stiff contact "
                         "already; a spring would replace that contact, not add to it")
    wl, zeta = term.h
    jl = min(max(term.coef[0], 1e-12), MAX_LOAD_SHARE * model.inertia)
    return replace(model, load_inertia=jl, stiffness=jl * wl * wl, damping=2 * zeta * wl * jl)


def _resonance(inertia, jl, wl) -> float:
    """Coupled resonance of a motor (inertia - jl) and a load jl on a spring of natural
    frequency wl (load side) [Hz]."""
    jm = max(inertia - jl, 1e-300)
    return wl * math.sqrt(1.0 + jl / jm) / (2 * math.pi)


def _stays_a_spring(base, term) -> str | None:
    """None when the spring stays a spring where the load torque reverses, else why not.

    A spring transmits torque through zero deflection; a dead band (backlash) transmits
    none inside its gap, and an elastic model fitted to it invents a soft spring that
    stands for the motor crossing the gap alone.  The record tells them apart: the load
    behind a dead band driven by the measured motion (:mod:`.backlash`'s column, a gap
    the record resolves and crosses) removes more of the residual than the spring does,
    where a true spring's ringing is not a dead band's.
    """
    sig = base.sig
    wl, zeta = term.h
    y = base.current_residual
    spring = _backlash.drop_share(base, sig.filt(load_acceleration(sig, wl, zeta)) - sig.a, y)
    rivals = base.variants(_backlash.CAUSE, None)
    if not rivals:
        return None
    drops = [_backlash.drop_share(base, v.extra[:, 0], y) for v in rivals]
    best = int(np.argmax(drops))
    gap, e = rivals[best].h
    if not drops[best] >= spring:
        return None
    if gap < _backlash.MIN_COUNTS * _backlash._counts(sig) * (1 - 1e-9):
        return None
    crossings = backlash_load(sig, gap, e).crossings
    if crossings < _backlash.MIN_CROSSINGS:
        return None
    size = (f"{math.degrees(gap):.3g} deg" if base.labels.position == "rad"
            else f"{gap:.3g} {base.labels.position}")
    return (f"the spring does not stay a spring where the load torque reverses: a dead band "
            f"of {size} between motor and load (rigid contact, crossed {crossings} times) "
            f"removes {100 * drops[best]:.0f} % of the residual's sum of squares, the spring "
            f"{100 * spring:.0f} %")


def _identifiable(base, term):
    wl, _ = term.h
    jl = float(term.coef[0])
    sig = base.sig
    total = term.extended.inertia if term.extended is not None else base.inertia
    if jl >= 0.999 * MAX_LOAD_SHARE * total:
        return (f"the load behind the spring takes {100 * MAX_LOAD_SHARE:.0f} % of the inertia "
                f"(its bound): the term smooths the acceleration instead of resolving a resonance")
    fr = _resonance(total, jl, wl)
    if fr > sig.cutoff:
        return (f"the fitted resonance ({fr:.3g} Hz) lies above the band the excitation reaches "
                f"on this record ({sig.cutoff:.3g} Hz; sampled at {sig.sample_rate:.4g} Hz)")
    return _stays_a_spring(base, term)


def _evidence(base, term, extended):
    sig, u, r = base.sig, base.labels, base.residual
    m = sig.moving
    jm = extended.inertia - extended.load_inertia
    fr_hz = math.sqrt(extended.stiffness * (1 / jm + 1 / extended.load_inertia)) / (2 * math.pi)
    f, pxx = signal.welch(np.where(m, r, 0.0), fs=1 / sig.ts, nperseg=min(1024, r.size))
    sel = f > 2.0
    fpk = float(f[sel][np.argmax(pxx[sel])]) if sel.any() else float("nan")
    return (f"residual spectrum peaks at {fpk:.3g} Hz; fitted elastic joint: stiffness K = "
            f"{extended.stiffness:.4g} {u.stiffness}, load inertia {extended.load_inertia:.3g}, "
            f"motor-side inertia {jm:.3g}, resonance {fr_hz:.3g} Hz")


def _inject(rng, act):
    jm = act.motor_inertia
    jl = rng.uniform(0.5, 1.5) * jm * act.strength
    act = replace(act, link_inertia=jl)  # the link is redrawn: it now sits behind the spring
    fr = rng.uniform(12.0, 40.0)
    kst = (2 * math.pi * fr) ** 2 / (1.0 / jm + 1.0 / jl)
    zeta = rng.uniform(0.02, 0.1)
    dmp = 2 * zeta * math.sqrt(kst * jl)
    friction = act.friction()
    return Injection(
        joint=FlexibleJoint(motor_inertia=jm, load_inertia=jl, stiffness=kst, damping=dmp,
                            friction=friction),
        truth=JointModel(inertia=jm + jl, friction=friction, load_inertia=jl, stiffness=kst,
                         damping=dmp, units=act.units),
        nominal=act.nominal(), breakaway=act.coulomb, substeps=10,
        magnitude=dict(stiffness=kst, damping=dmp, motor_inertia=jm, load_inertia=jl,
                       resonance_hz=fr))


CAUSE = Cause(
    name="compliance", order=70,
    physical="the joint is elastic: a resonance the rigid model lacks",
    changes=("load_inertia", "stiffness", "damping"),
    params=("load_inertia",), variants=_variants, extend=_extend, evidence=_evidence,
    identifiable=_identifiable, inject=_inject)
