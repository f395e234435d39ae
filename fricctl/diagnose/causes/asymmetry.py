"""Asymmetry: the viscous friction differs between the two directions.

Regressor: ``LP(|w|)``; coefficient ``d`` (free in sign): the viscous coefficient becomes
``b + d`` forward and ``b - d`` backward (around the model's own: in fit mode the
baseline's ``b*w`` is refitted with it, so the pair spans any two coefficients; against
a nominal model the split keeps the nominal mean).  Bench: a viscous ratio 1.5 .. 2.2
between the directions, either way.

Notes
-----
Identifiability.  A *Coulomb* level that differs between the directions by ``2c`` is
the constant torque ``c`` on a rigid joint: same sliding torque, same breakaway band
(:mod:`.offset`'s notes), so no record tells them apart and :mod:`.offset` names it;
this cause is what a constant cannot explain, a friction difference between the
directions that grows with speed.  It is told from a constant by the spread of the
record's speeds: where the joint slides at one speed only (both ways), ``|w|`` is a
constant too -- the selection's collinearity test then refuses one of them -- and
where the speeds are few, part of an offset is fitted as an asymmetry (the evidence
gives both directions' residual so that a reader sees which).  A fitted split that
leaves one direction with negative viscous friction is not physical: not told.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ...friction import Coulomb, FrictionModel, Viscous
from .base import Cause


def _variants(base, fold):
    sig = base.sig
    yield base.variant(None, sig.filt(np.abs(sig.w)), (0,))


def _split(friction: FrictionModel, d: float) -> dict:
    fr = friction.as_dict()
    fr["viscous_pos"] = fr["viscous_pos"] + d
    fr["viscous_neg"] = fr["viscous_neg"] - d
    return fr


def _extend(model, term, base):
    fr = _split(model.friction, float(term.coef[0]))
    fr["viscous_pos"], fr["viscous_neg"] = max(fr["viscous_pos"], 0.0), max(fr["viscous_neg"], 0.0)
    return replace(model, friction=FrictionModel.from_dict(fr))


def _identifiable(base, term):
    """Both directions keep a non-negative viscous coefficient (a friction)."""
    model = term.extended if term.extended is not None else base.fitted
    fr = model.friction.as_dict()
    if term.extended is not None:  # the joint fit's own coefficients, before any clipping
        return None if min(fr["viscous_pos"], fr["viscous_neg"]) > 0 else (
            f"the fitted split leaves a viscous coefficient at zero (forward "
            f"{fr['viscous_pos']:.3g}, backward {fr['viscous_neg']:.3g} {base.labels.viscous}): "
            f"not a friction")
    d = float(term.coef[0])
    fr = _split(model.friction, d)
    if min(fr["viscous_pos"], fr["viscous_neg"]) <= 0:
        return (f"the fitted split ({d:+.3g} {base.labels.viscous}) leaves a negative viscous "
                f"coefficient (forward {fr['viscous_pos']:.3g}, backward {fr['viscous_neg']:.3g} "
                f"{base.labels.viscous}): not a friction")
    return None


def _evidence(base, term, extended):
    sig, u, r = base.sig, base.labels, base.residual
    m = sig.moving
    fr = extended.friction
    w = np.abs(sig.w)
    lo = m & (w < np.percentile(w[m], 50)) if np.any(m) else m
    hi = m & ~lo
    parts = []
    for name, sel in (("forward", sig.w > 0), ("backward", sig.w < 0)):
        if not np.any(m & sel):  # a direction the record never slides in: said, not a NaN
            parts.append(f"no sliding sample {name}")
            continue
        a = f"{r[lo & sel].mean():+.3g}" if np.any(lo & sel) else "none"
        b = f"{r[hi & sel].mean():+.3g}" if np.any(hi & sel) else "none"
        parts.append(f"{a} -> {b} {u.torque} {name}")
    return (f"from the slower to the faster half of the sliding samples the baseline residual "
            f"averages {', '.join(parts)} (a constant torque would shift both alike at every "
            f"speed); fitted viscous +{fr.viscous_pos:.3g} / -{fr.viscous_neg:.3g} {u.viscous} "
            f"(a Coulomb level differing between the directions is a constant torque on a "
            f"rigid joint: named offset)")


def _either_way(rng, lo, hi):
    """A ratio in [lo, hi] or [1/hi, 1/lo] (two draws: the value, then the way)."""
    x = rng.uniform(lo, hi)
    return x if rng.random() < 0.5 else 1.0 / x


def _remove(model):
    fr = model.friction.as_dict()
    fr["viscous_pos"] = fr["viscous_neg"] = 0.5 * (fr["viscous_pos"] + fr["viscous_neg"])
    return replace(model, friction=FrictionModel.from_dict(fr))


def _inject(rng, act):
    b, fc = act.viscous, act.coulomb
    r = act.weaker(_either_way(rng, 1.5, 2.2))
    friction = Viscous(pos=b * math.sqrt(r), neg=b / math.sqrt(r)) + Coulomb(fc)
    mag = dict(viscous_pos=b * math.sqrt(r), viscous_neg=b / math.sqrt(r))
    return act.rigid(magnitude=mag, friction=friction)


CAUSE = Cause(
    name="asymmetry", order=20,
    physical="the viscous friction differs between the two directions",
    changes=("viscous_pos", "viscous_neg"),
    params=("viscous_split",), variants=_variants, extend=_extend,
    identifiable=_identifiable, evidence=_evidence, inject=_inject,
    remove=_remove)
