"""Position ripple: a torque disturbance periodic in position (cogging, gear mesh, kinematic error).

Regressors: ``LP(sin(2*pi*q/P))`` and ``LP(cos(2*pi*q/P))`` (free in sign) for the periods ``P``
at the three highest peaks of the periodogram in position of the training residual of the
model as it stands (per block left out, again after each named cause), from the longest of
30 encoder counts, ``2e-5*span`` and two samples of motion at the median sliding speed (the
Nyquist limit in position) up to half the travel, and a finer period grid around each peak
(steps of ``1/(12*span)`` in spatial frequency, never below that limit).
Bench: amplitude 0.2 .. 0.5 Fc, period 0.04 .. 0.5 rad, random phase.
"""

from __future__ import annotations

import math
import weakref
from dataclasses import replace

import numpy as np
from scipy import signal

from ...friction import FrictionModel, PositionRipple
from .base import Cause, coulomb_level, coulomb_share


#: Variants made for a record, by its signals (weakly: gone with the record) and by (target,
#: spatial frequency on the periodogram's grid): the folds' periodograms share one grid (the
#: whole record's travel), so a peak found in several folds is one variant, filtered once and
#: its cross-validation products computed once (4 s of a 40 s, 1 kHz diagnosis before).
_MADE = weakref.WeakKeyDictionary()


def _sin_cos(base, period, ang=None):
    """The variant of period ``period`` (``ang = 2*pi*q/period`` along the record)."""
    sig = base.sig
    made = _MADE.setdefault(sig, {})
    key = (id(base.target), float(f"{1.0 / period:.10g}"))
    if key not in made:
        ang = 2 * np.pi * sig.qf / period if ang is None else ang
        made[key] = (base.target, base.variant(float(period), np.column_stack(
            [sig.filt(np.sin(ang)), sig.filt(np.cos(ang))]), (0, 0)))  # the target kept: its id stays its own
    return made[key][1]


def _variants(base, fold):
    """Periods at the top peaks of the residual's periodogram in position (training data)."""
    sig = base.sig
    rows = sig.moving & (sig.folds != fold) if fold is not None else sig.moving.copy()
    r = base.current_residual[rows]
    q = sig.qf[rows]
    # the bins and the frequency grid of the whole record's travel, shared by the folds
    q_all = sig.qf[sig.moving]
    span, q0 = float(np.ptp(q_all)), float(np.min(q_all))
    res = sig.resolution if sig.resolution > 0 else 1e-6 * span
    # the shortest period searched: 30 encoder counts, and two samples of motion at the
    # median sliding speed (a shorter one is an alias of the sampling: it would take the
    # periodogram's peaks and be refused, leaving a resolvable ripple untried -- EMPS's
    # 62 um alias hid the 2.50 mm ripple of one motor revolution)
    pmin = max(30 * res, 2e-5 * span, 2.0 * _per_sample(sig))
    pmax = span / 2
    out = []
    if pmax > 2 * pmin:
        # Schuster periodogram of the residual as a function of position: residual
        # summed into bins of pmin/4, FFT (zero-padded x2 for a finer grid).
        nb = int(min(2 ** 20, 2 ** math.ceil(math.log2(span / (pmin / 4) + 1))))
        width = span / (nb - 1) if nb > 1 else span
        idx = np.minimum(((q - q0) / width).astype(np.int64), nb - 1)
        binned = np.bincount(idx, weights=r - r.mean(), minlength=nb)
        spec = np.abs(np.fft.rfft(binned, n=2 * nb)) ** 2
        nu = np.fft.rfftfreq(2 * nb, d=width)
        ok = (nu >= 1 / pmax) & (nu <= 1 / pmin)
        power = np.where(ok, spec, 0.0)
        peaks, _ = signal.find_peaks(power)
        top = peaks[np.argsort(power[peaks])[::-1][:3]] if peaks.size else []
        for i in top:
            per = 1.0 / nu[i]
            out.append(_sin_cos(base, per))
    return out


def _refine(base, variants):
    """A finer period grid around each periodogram peak: +-1/(12*span) and +-1/(6*span) in
    spatial frequency."""
    out = list(variants)
    sig = base.sig
    span = float(np.ptp(sig.qf[sig.moving]))
    step = _per_sample(sig)
    nu_max = 1.0 / (2.0 * step) if step > 0 else math.inf
    for v in variants:
        dnu = 1.0 / (6 * span)
        for k in (-1.0, -0.5, 0.5, 1.0):
            nu = 1.0 / v.h + k * dnu
            if not 0 < nu <= nu_max:  # never below the Nyquist limit in position
                continue
            out.append(_sin_cos(base, 1.0 / nu))
    return out


def _per_sample(sig) -> float:
    """The motion of one sample at the record's median sliding speed [rad] ([m])."""
    return float(np.median(np.abs(sig.w[sig.moving]))) * sig.ts if np.any(sig.moving) else 0.0


def _identifiable(base, term):
    """A period the record can resolve: at the median sliding speed the joint crosses it in
    at least two samples (the Nyquist limit in position); a shorter one is an alias of the
    sampling, not a ripple of the drive (the periodogram's search starts there; the finer
    grid around a peak may step below)."""
    sig = base.sig
    per_sample = _per_sample(sig)
    if term.h < 2.0 * per_sample:
        u = base.labels
        return (f"the fitted period ({term.h:.3g} {u.position}) is shorter than two samples of "
                f"motion at the record's median sliding speed ({per_sample:.3g} {u.position} "
                f"per sample): above the Nyquist limit in position, an alias of the sampling")
    return _time_rival(base, term.h, per_sample / sig.ts)


def _time_rival(base, period: float, speed: float) -> str | None:
    """Why a ripple of ``period`` cannot be told from a torque periodic in time, or None.

    At the median sliding speed ``speed`` the ripple is a sinusoid in time of frequency
    ``speed/period``; only the record's spread of speeds tells the two apart.  A sinusoid in time
    at that frequency (filtered as the ripple's columns are) is fitted to the residual of the
    model as it stands on the sliding samples, as the ripple's own two columns are; where it
    leaves no more, the record cannot tell a ripple in position from a disturbance in time
    (audit B: a 3 Hz disturbance on a record tracking a triangle at one speed was named a
    ripple of 0.33 rad)."""
    sig = base.sig
    m = sig.moving
    if not np.any(m):
        return None
    r = base.current_residual[m]
    f = speed / period
    ang = 2 * np.pi * f * sig.t
    cols = {"position": _sin_cos(base, period).extra[m],
            "time": np.column_stack([sig.filt(np.sin(ang)), sig.filt(np.cos(ang))])[m]}
    left = {}
    for k, c in cols.items():
        coef = np.linalg.lstsq(c, r, rcond=None)[0]
        left[k] = float(np.sum((r - c @ coef) ** 2))
    total = float(r @ r)
    if not (total > 0 and left["time"] <= left["position"]):
        return None
    u = base.labels
    return (f"a torque periodic in time at {f:.3g} Hz (the period at the median sliding speed) "
            f"removes as much of the residual as the ripple ({100 * (1 - left['time'] / total):.0f} "
            f"% against {100 * (1 - left['position'] / total):.0f} %): the record slides at "
            f"too nearly one speed to tell a period in position ({period:.3g} {u.position}) "
            f"from one in time")


def _extend(model, term, base):
    al, be = term.coef
    ripple = PositionRipple(float(math.hypot(al, be)), term.h, float(math.atan2(be, al)))
    return replace(model, friction=model.friction + ripple)


def _remove(model):
    d = model.friction.as_dict()
    default = FrictionModel().as_dict()
    for key in ("ripple_amplitude", "ripple_period", "ripple_phase"):
        d[key] = default[key]
    return replace(model, friction=FrictionModel.from_dict(d))


def _evidence(base, term, extended):
    u = base.labels
    fr = extended.friction
    fc = coulomb_level(base.fitted)
    return (f"residual periodic in position, period {fr.ripple_period:.4g} {u.position}, amplitude "
            f"{fr.ripple_amplitude:.3g} {u.torque} "
            f"({coulomb_share(fr.ripple_amplitude, fc, u.torque)})")


def _inject(rng, act):
    fc = act.coulomb
    mag = dict(amplitude=rng.uniform(0.2, 0.5) * fc * act.strength,
               period=math.exp(rng.uniform(math.log(0.04), math.log(0.5))) * act.travel,
               phase=rng.uniform(0, 2 * math.pi))
    ripple = PositionRipple(mag["amplitude"], mag["period"], mag["phase"])
    return act.rigid(magnitude=mag, friction=act.friction() + ripple, breakaway=fc + mag["amplitude"])


CAUSE = Cause(
    name="position_ripple", order=40,
    physical="a torque disturbance periodic in position",
    changes=("ripple_amplitude", "ripple_period", "ripple_phase"),
    params=("ripple_sin", "ripple_cos"), variants=_variants, per_fold=True, per_step=True,
    refine=_refine, identifiable=_identifiable,
    extend=_extend, evidence=_evidence, inject=_inject, remove=_remove)
