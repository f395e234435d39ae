"""Thermal drift: the friction level changes steadily over the record (warm-up, wear).

Regressor: the baseline friction times time, ``LP((t - t_mid) * (b*w + Fc*sign(w)))`` with the
baseline fitted on all data (fit mode), or ``LP((t - t0) * F_nominal)``; free in sign.
Bench: the friction level changes by 25 .. 50 % over the record (either sign).
"""

from __future__ import annotations

from dataclasses import replace

from .base import Cause


def _variants(base, fold):
    sig = base.sig
    if base.fit_mode:
        _, b, fc = base.theta
        tc = sig.t - 0.5 * (sig.t[0] + sig.t[-1])
        col = sig.filt(tc * (b * sig.w + fc * base.sign))
    else:
        col = sig.filt((sig.t - sig.t[0]) * base.nominal_friction_raw)
    yield base.variant(None, col, (0,))


def _extend(model, term, base):
    delta = float(term.coef[0])
    fr = model.friction
    if base.fit_mode:  # the column is centred on the record: rescale to a drift from t = 0
        t = base.sig.t
        tmid = 0.5 * (t[0] + t[-1])
        s0 = max(1.0 - delta * tmid, 1e-3)
        fr = replace(fr.scaled(s0), drift=delta / s0)
    else:
        fr = replace(fr, drift=fr.drift + delta)
    return replace(model, friction=fr)


def _evidence(base, term, extended):
    fr = extended.friction
    t0, t1 = base.sig.t[0], base.sig.t[-1]
    s0 = fr.scale * (1 + fr.drift * t0)
    s1 = fr.scale * (1 + fr.drift * t1)
    return (f"the friction level changes by {100 * (s1 / s0 - 1):+.0f} % over the record "
            f"({t1 - t0:.3g} s, {100 * fr.drift / max(s0, 1e-12) * fr.scale:+.3g} % per s)")


def _inject(rng, act):
    change = rng.uniform(0.25, 0.5) * rng.choice((-1.0, 1.0)) * act.strength
    return act.rigid(magnitude=dict(change=change, rate=change / act.duration),
                     friction=act.friction().with_drift(change / act.duration),
                     breakaway=act.coulomb * max(1.0, 1.0 + change))


CAUSE = Cause(
    name="thermal_drift", order=60,
    physical="the friction level changes steadily over the record",
    changes=("scale", "drift"),
    params=("drift",), variants=_variants, extend=_extend, evidence=_evidence, inject=_inject)
