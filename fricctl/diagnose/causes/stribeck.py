"""Stribeck effect: friction at low speed exceeds the Coulomb level and decays toward it with speed.

Regressor: ``LP(sign(w) * exp(-(w/vs)^2))`` for 14 Stribeck velocities ``vs`` from 0.1 % to
20 % of the 95th percentile of |w|; coefficient: the excess ``Fs - Fc >= 0``.
Bench: excess 0.5 .. 1.0 Fc, Stribeck velocity 0.02 .. 0.1 rad/s.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ...friction import FrictionModel, Stribeck
from .base import Cause, coulomb_level, coulomb_share


def _variants(base, fold):
    sig = base.sig
    v95 = float(np.percentile(np.abs(sig.w[sig.moving]), 95))
    for vs in v95 * np.logspace(-3, -0.7, 14):
        yield base.variant(float(vs), sig.filt(base.sign * np.exp(-(sig.w / vs) ** 2)), (1,))


def _extend(model, term, base):
    return replace(model, friction=model.friction + Stribeck(max(term.coef[0], 0.0), term.h))


def _evidence(base, term, extended):
    sig, u = base.sig, base.labels
    vs = term.h
    fr = extended.friction
    fc = coulomb_level(base.fitted)
    w = np.abs(sig.w[sig.moving])
    rr = (base.residual * np.sign(sig.w))[sig.moving]
    # a band the record's sliding samples never reach is said so (not a mean of nothing)
    low, high = w < vs, w > 10 * vs
    lo = (f"below |w| = {vs:.3g} {u.velocity} the baseline residual averages "
          f"{rr[low].mean():+.3g} {u.torque} in the direction of motion" if np.any(low) else
          f"no sliding sample below |w| = {vs:.3g} {u.velocity}")
    hi = (f"above {10 * vs:.3g} {u.velocity} {rr[high].mean():+.3g} {u.torque}" if np.any(high)
          else f"none above {10 * vs:.3g} {u.velocity}")
    return (f"{lo}, {hi}; "
            f"fitted Stribeck excess {fr.stribeck_pos:.3g} {u.torque} "
            f"({coulomb_share(fr.stribeck_pos, fc, u.torque)}), "
            f"Stribeck velocity {vs:.3g} {u.velocity}")


def _identifiable(base, term):
    # the hump is exp(-(w/vs)^2): with no sliding sample below vs its column is the tail alone,
    # and the excess is extrapolated to speeds the record never slides at (audit B: 24.5 N*m,
    # 11476 % of the Coulomb level, on a triangle record at one speed)
    w = np.abs(base.sig.w[base.sig.moving])
    if w.size and not np.any(w < term.h):
        u = base.labels
        return (f"the fitted Stribeck velocity {term.h:.3g} {u.velocity} lies below every "
                f"sliding sample's speed (slowest {float(w.min()):.3g} {u.velocity}): the hump "
                f"is fitted on its tail and its excess is not determined by the record")
    return None


def _remove(model):
    d = model.friction.as_dict()
    d["stribeck_pos"] = d["stribeck_neg"] = 0.0
    d["stribeck_velocity"] = FrictionModel().as_dict()["stribeck_velocity"]
    return replace(model, friction=FrictionModel.from_dict(d))


def _inject(rng, act):
    fc = act.coulomb
    mag = dict(excess=rng.uniform(0.5, 1.0) * fc * act.strength,
               velocity=rng.uniform(0.02, 0.1) * act.travel)
    return act.rigid(magnitude=mag, friction=act.friction() + Stribeck(mag["excess"], mag["velocity"]),
                     breakaway=fc + mag["excess"])


CAUSE = Cause(
    name="stribeck", order=10,
    physical="friction at low speed exceeds the Coulomb level and decays toward it with speed",
    changes=("stribeck_pos", "stribeck_neg", "stribeck_velocity"),
    params=("stribeck_excess",), variants=_variants, extend=_extend, evidence=_evidence,
    inject=_inject, remove=_remove, friction_curve=True, identifiable=_identifiable)
