"""Compliance: the joint is elastic (paper Eq. 1), a resonance the rigid model lacks.

Regressor: ``LP(a_load) - a`` with ``a_load`` the acceleration of a load on a spring driven by
the measured motion, for natural frequencies on a log grid (8 per decade) from 20 cycles
over the record up to the low-pass cut-off (the band the excitation reaches: above it the
column only smooths encoder noise) and damping ratios 0.02, 0.05, 0.12, the best of them
refined within one grid step around it (:func:`_refine`: a lightly damped resonance's band is
narrower than the grid's step); coefficient: the load inertia (>= 0; the model takes at most
:data:`MAX_LOAD_SHARE` of the total inertia fitted with it).  Cannot be told when the coupled
resonance lies above that band, the load share reaches that bound or the refined damping the
bound of its search (a smoothing, not a resonance), when the spring does not stay a spring
where the load torque reverses (a dead band between motor and load, :mod:`.backlash`'s column,
removes more of the residual than the spring, or fitted beside it :data:`DEAD_BAND_SHARE` of
what the spring leaves: backlash imitated by a soft spring), or when a sinusoid in time near
its frequency removes as much (:func:`_periodic_in_time`: a disturbance periodic in time, which
a tuned spring rides on).  Not added to a model with backlash (its contact is the joint's
coupling already).
Bench: link 0.5 .. 1.5 x actuator inertia, coupled resonance 12 .. 40 Hz, structural damping
ratio 0.02 .. 0.1.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
from scipy import signal
from scipy.optimize import minimize

from ...plant import FlexibleJoint, JointModel
from ..signals import backlash_load, load_acceleration
from . import backlash as _backlash
from .base import Cause, Injection


#: Largest share of the inertia a fitted load behind the spring may hold [-].
MAX_LOAD_SHARE = 0.95


def _spring_column(sig, wl, zeta) -> np.ndarray:
    """The regressor: ``LP(a_load) - a`` for a load on a spring of natural frequency ``wl``
    [rad/s] and damping ratio ``zeta`` driven by the measured motion."""
    return sig.filt(load_acceleration(sig, wl, zeta)) - sig.a


def _variants(base, fold):
    sig = base.sig
    lowest = 20.0 / (sig.t[-1] - sig.t[0])
    n = max(int(np.floor(8 * np.log10(sig.cutoff / lowest))), 0) + 1
    for wl in 2 * np.pi * lowest * 10.0 ** (np.arange(n) / 8):
        for zeta in (0.02, 0.05, 0.12):
            yield base.variant((float(wl), zeta), _spring_column(sig, wl, zeta), (1,))


#: Least share of what the spring leaves that a dead band beside it (fitted with it) must remove
#: for the spring to stand for a dead band: the selection's 10 % line on the RMS [-].
DEAD_BAND_SHARE = 1.0 - 0.9 ** 2
#: The refined natural frequency stays within one step of the coarse grid (8 per decade)
#: of the best grid point, the damping ratio within these bounds [-].
REFINE_ZETA = (0.005, 0.5)


def _refine(base, variants):
    """A resonance found between the grid's points: the natural frequency and damping ratio
    of the best grid variant refined by a local search, and its neighbours.

    The grid (8 per decade, three damping ratios) is coarse for a lightly damped resonance,
    whose band is about ``2*zeta`` wide: on the second simulator's compliant linear axis at
    500 Hz ([33, 29]: a natural frequency of 7.48 Hz, zeta 0.066) the grid's neighbours 6.67
    and 8.89 Hz left 38-47 N of held-out residual where the true pair leaves 4.7 N (the chain's
    floor 2.66 N), and the half-fitted spring left the record "not explained" at 18.7 times the
    floor.  Scored as the grid's variants are ranked, by the residual of the model as it stands
    refitted with the baseline's columns and the term (all sliding samples); the search
    (Nelder-Mead on the logarithms) stays within one grid step of the best grid point (one
    step below the grid's lowest point when that is the best) and below the cut-off.  The
    selection then cross-validates the refined variants with the others, as it does the grid's
    (a cause per step: the residual is the model's as it stands); the search sees all the
    data, the held-out blocks too, as the choice of a grid point's neighbourhood does."""
    sig = base.sig
    y = base.current_residual
    if not variants or not np.any(y[sig.moving]):
        return list(variants)
    q = _backlash._basis(base)

    def left(col):  # the share of y the term leaves, its load inertia >= 0
        return 1.0 - _backlash.drop_share(base, col, y, basis=q)

    best = min(variants, key=lambda v: left(v.extra[:, 0]))
    wl0, z0 = best.h
    step = np.log(10.0) / 8  # one step of the grid in log frequency
    lo = np.array([np.log(wl0) - step, np.log(REFINE_ZETA[0])])
    hi = np.array([min(np.log(wl0) + step, np.log(2 * np.pi * sig.cutoff)), np.log(REFINE_ZETA[1])])
    if not lo[0] < hi[0]:  # the best grid point lies a step or more above the cut-off
        return list(variants)

    def cost(x):
        x = np.clip(x, lo, hi)
        return left(_spring_column(sig, float(np.exp(x[0])), float(np.exp(x[1]))))

    res = minimize(cost, np.array([np.log(wl0), np.log(z0)]), method="Nelder-Mead",
                   options=dict(xatol=1e-3, fatol=1e-6, maxfev=80, initial_simplex=np.array([
                       [np.log(wl0), np.log(z0)], [np.log(wl0) + step / 2, np.log(z0)],
                       [np.log(wl0), np.log(z0) + 0.5]])))
    wl, zeta = np.exp(np.clip(res.x, lo, hi))
    out = list(variants)
    seen = {v.h for v in out}
    for f, z in ((1.0, 1.0), (1.02, 1.0), (1 / 1.02, 1.0), (1.0, 1.2), (1.0, 1 / 1.2)):
        w2, z2 = float(wl * f), float(np.clip(zeta * z, *REFINE_ZETA))
        # (a damping at its bound clips a neighbour onto the refined point itself)
        if w2 <= 2 * np.pi * sig.cutoff and (w2, z2) not in seen:
            seen.add((w2, z2))
            out.append(base.variant((w2, z2), _spring_column(sig, w2, z2), (1,)))
    return out


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


def _share(base, columns, y) -> tuple:
    """Share of ``y``'s sum of squares over the sliding samples that ``columns`` remove
    together (least squares), what the baseline's columns carry taken out in fit mode, and
    their coefficients ``(share, coef)`` [-]."""
    m = base.sig.moving
    x = np.column_stack(columns)[m]
    q = _backlash._basis(base)
    if q is not None:  # what the baseline's columns cannot already carry
        x = x - q @ (q.T @ x)
    ym = np.asarray(y, dtype=float)[m]
    yy = float(ym @ ym)
    if not yy > 0:
        return 0.0, np.zeros(x.shape[1])
    coef = np.linalg.lstsq(x, ym, rcond=None)[0]
    return 1.0 - float(np.sum((ym - x @ coef) ** 2)) / yy, coef


def _stays_a_spring(base, term) -> str | None:
    """None when the spring stays a spring where the load torque reverses, else why not.

    A spring transmits torque through zero deflection; a dead band (backlash) transmits
    none inside its gap, and an elastic model fitted to it invents a soft spring that
    stands for the motor crossing the gap alone.  The record tells them apart with the
    load behind a dead band driven by the measured motion (:mod:`.backlash`'s column, a gap
    the record resolves and crosses): it removes more of the residual than the spring does,
    or, fitted beside the spring, it removes :data:`DEAD_BAND_SHARE` of what the spring
    leaves -- an effect the spring cannot carry, where a true spring's ringing leaves a dead
    band little (a joint model holds a spring or a dead band, not both).  The dead band is the
    one best on its own (the backlash's variants), fitted beside the spring.  The second test
    is what keeps a spring refined between the grid's points (:func:`_refine`, its damping
    free) from standing for a dead band with a stiff contact that the rigid column models
    only up to the impacts: issue 21's new set, a gap of 1.0 deg at 1 kHz in closed loop,
    read as a spring of 15.5 Hz at zeta 0.39 (76 % of the residual, the dead band alone 69 %,
    beside the spring 39 % of what it leaves); on twelve development records with a true
    spring ([9402, 0..7], the second simulator's [31, 100, 102, 201, 202]) a dead band beside
    it removed 0-3 %; at 200 Hz up to 14 % (review R16, four of twelve compliance records), a
    thinner margin to the line.
    """
    sig = base.sig
    wl, zeta = term.h
    y = base.current_residual
    col = _spring_column(sig, wl, zeta)
    spring = _backlash.drop_share(base, col, y)
    rivals = base.variants(_backlash.CAUSE, None)
    if not rivals:
        return None
    drops = [_backlash.drop_share(base, v.extra[:, 0], y) for v in rivals]
    best = int(np.argmax(drops))
    gap, e = rivals[best].h
    both, coef = _share(base, [col, rivals[best].extra[:, 0]], y)
    beside = (both - spring) / (1.0 - spring) if spring < 1.0 and coef[1] > 0 else 0.0
    if not (drops[best] >= spring or beside >= DEAD_BAND_SHARE):
        return None
    if gap < _backlash.MIN_COUNTS * _backlash._counts(sig) * (1 - 1e-9):
        return None
    crossings = backlash_load(sig, gap, e).crossings
    if crossings < _backlash.MIN_CROSSINGS:
        return None
    size = (f"{math.degrees(gap):.3g} deg" if base.labels.position == "rad"
            else f"{gap:.3g} {base.labels.position}")
    band = (f"a dead band of {size} between motor and load (rigid contact, crossed "
            f"{crossings} times)")
    if drops[best] >= spring:
        return (f"the spring does not stay a spring where the load torque reverses: {band} "
                f"removes {100 * drops[best]:.0f} % of the residual's sum of squares, the "
                f"spring {100 * spring:.0f} %")
    return (f"the spring does not stay a spring where the load torque reverses: {band}, "
            f"fitted beside it, removes {100 * beside:.0f} % of what the spring leaves (the "
            f"naming line {100 * DEAD_BAND_SHARE:.0f} %; alone {100 * drops[best]:.0f} % of the "
            f"residual, the spring {100 * spring:.0f} %): a dead band the spring cannot carry, "
            f"and a joint model holds one or the other")


def _periodic_in_time(base, term) -> str | None:
    """Why the spring cannot be told from a torque periodic in time, or None.

    A spring driven by the measured motion rings at its natural frequency wherever the motion
    has energy there; a disturbance periodic in time makes the joint move at its own frequency,
    and a spring tuned to it rides on that motion (the refined spring named a foreign
    ``time_sine`` as ``compliance``).  The residual's strongest frequency within one step of the
    grid (8 per decade) around the spring's natural frequency is taken from its periodogram
    (zero-padded four times), and a sinusoid in time at it (filtered as the spring's column is)
    is fitted to the residual of the model as it stands on the sliding samples; where it
    removes at least as much as the spring, the record cannot tell a resonance from a
    disturbance in time.  A true resonance rings with the phase of each change of the motion,
    which no one sinusoid over the record follows."""
    sig = base.sig
    m = sig.moving
    y = np.asarray(base.current_residual, dtype=float)
    if np.count_nonzero(m) < 8:
        return None
    wl, zeta = term.h
    f0 = wl / (2 * np.pi)
    n = 4 * y.size
    spec = np.abs(np.fft.rfft(np.where(m, y, 0.0), n))
    freqs = np.fft.rfftfreq(n, sig.ts)
    band = (freqs >= f0 / 10.0 ** (1 / 8)) & (freqs <= f0 * 10.0 ** (1 / 8))
    if not np.any(band):
        return None
    f = float(freqs[band][np.argmax(spec[band])])
    ang = 2 * np.pi * f * sig.t
    share, _ = _share(base, [sig.filt(np.sin(ang)), sig.filt(np.cos(ang))], y)
    spring = _backlash.drop_share(base, _spring_column(sig, wl, zeta), y)
    if not (share > 0 and share >= spring):
        return None
    return (f"a torque periodic in time at {f:.3g} Hz removes as much of the residual as the "
            f"spring ({100 * share:.0f} % against {100 * spring:.0f} %): the record cannot tell "
            f"a resonance at {f0:.3g} Hz from a disturbance in time")


def _identifiable(base, term):
    wl, zeta = term.h
    if zeta >= REFINE_ZETA[1] * (1 - 1e-9):
        return (f"the fitted damping ratio reaches the bound of its search ({REFINE_ZETA[1]:g}): "
                f"the term smooths the acceleration instead of resolving a resonance")
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
    return _stays_a_spring(base, term) or _periodic_in_time(base, term)


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
    identifiable=_identifiable, inject=_inject, refine=_refine, per_step=True)
