"""Asymmetry: friction differs between the two directions (or a constant torque offset).

Regressors: ``LP(w * (w > 0))`` (extra viscous coefficient forward) and ``LP(1)`` (a constant
torque, i.e. Coulomb ``Fc + c`` forward and ``Fc - c`` backward); both free in sign.
Bench: one of a Coulomb ratio 1.3 .. 1.7 between the directions, a viscous ratio 1.5 .. 2.2,
or a constant torque offset of 0.2 .. 0.4 Fc.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ...friction import Coulomb, FrictionModel, Viscous
from .base import Cause


def _variants(base, fold):
    sig = base.sig
    yield base.variant(None, np.column_stack([sig.filt(sig.w * (sig.w > 0)),
                                              sig.filt(np.ones(sig.t.size))]), (0, 0))


def _extend(model, term, base):
    db, c = term.coef
    d = model.friction.as_dict()
    d["viscous_pos"] = max(d["viscous_pos"] + db, 0.0)
    d["coulomb_pos"] = max(d["coulomb_pos"] + c, 0.0)
    d["coulomb_neg"] = max(d["coulomb_neg"] - c, 0.0)
    return replace(model, friction=FrictionModel.from_dict(d))


def _evidence(base, term, extended):
    sig, u, r = base.sig, base.labels, base.residual
    m = sig.moving
    fr = extended.friction
    pos = r[m & (sig.w > 0)].mean()
    neg = r[m & (sig.w < 0)].mean()
    return (f"the baseline residual averages {pos:+.3g} {u.torque} moving forward and {neg:+.3g} "
            f"{u.torque} moving backward; fitted Coulomb +{fr.coulomb_pos:.3g} / "
            f"-{fr.coulomb_neg:.3g} {u.torque}, viscous +{fr.viscous_pos:.3g} / "
            f"-{fr.viscous_neg:.3g} {u.viscous} (a constant offset of "
            f"{0.5 * (fr.coulomb_pos - fr.coulomb_neg):+.3g} {u.torque} slides the same way)")


def _either_way(rng, lo, hi):
    """A ratio in [lo, hi] or [1/hi, 1/lo] (two draws: the value, then the way)."""
    x = rng.uniform(lo, hi)
    return x if rng.random() < 0.5 else 1.0 / x


def _inject(rng, act):
    b, fc = act.viscous, act.coulomb
    which = str(rng.choice(("coulomb", "viscous", "offset")))
    if which == "coulomb":
        r = act.weaker(_either_way(rng, 1.3, 1.7))
        friction = Viscous(b) + Coulomb(pos=fc * math.sqrt(r), neg=fc / math.sqrt(r))
        mag = dict(kind=which, coulomb_pos=fc * math.sqrt(r), coulomb_neg=fc / math.sqrt(r))
    elif which == "viscous":
        r = act.weaker(_either_way(rng, 1.5, 2.2))
        friction = Viscous(pos=b * math.sqrt(r), neg=b / math.sqrt(r)) + Coulomb(fc)
        mag = dict(kind=which, viscous_pos=b * math.sqrt(r), viscous_neg=b / math.sqrt(r))
    else:
        off = rng.uniform(0.2, 0.4) * fc * rng.choice((-1.0, 1.0)) * act.strength
        # a constant resistive torque c is Coulomb fc+c one way, fc-c the other
        # (identical sliding torque and identical breakaway band)
        friction = Viscous(b) + Coulomb(pos=fc + off, neg=fc - off)
        mag = dict(kind=which, offset=off)
    return act.rigid(magnitude=mag, friction=friction,
                     breakaway=max(friction.coulomb_pos, friction.coulomb_neg))


CAUSE = Cause(
    name="asymmetry", order=20,
    physical="friction differs between the two directions (or a constant torque offset)",
    changes=("viscous_pos", "viscous_neg", "coulomb_pos", "coulomb_neg"),
    params=("delta_viscous_pos", "offset"), variants=_variants, extend=_extend,
    evidence=_evidence, inject=_inject)
