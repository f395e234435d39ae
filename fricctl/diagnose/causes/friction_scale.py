"""Friction scale: the overall friction level differs from the nominal model (wear, lubricant).

Regressor (nominal model only): the nominal friction along the measured motion;
coefficient: the relative change, free in sign.
Bench: friction 0.80 .. 0.93 x or 1.07 .. 1.20 x the nominal.
"""

from __future__ import annotations

from dataclasses import replace

from .base import Cause


def _variants(base, fold):
    yield base.variant(None, base.nominal_friction, (0,))


def _extend(model, term, base):
    return replace(model, friction=model.friction.scaled(max(1.0 + term.coef[0], 1e-3)))


def _evidence(base, term, extended):
    return (f"friction level x {extended.friction.scale / base.fitted.friction.scale:.3f} "
            f"of the nominal model")


def _inject(rng, act):
    f = rng.uniform(0.80, 0.93) if rng.random() < 0.5 else rng.uniform(1.07, 1.20)
    f = 1.0 + (f - 1.0) * act.strength
    return act.rigid(magnitude=dict(factor=f), friction=act.friction().scaled(f),
                     breakaway=act.coulomb * max(f, 1.0))


CAUSE = Cause(
    name="friction_scale", order=100,
    physical="the overall friction level differs from the nominal model",
    changes=("scale",),
    params=("delta_scale",), variants=_variants, extend=_extend, evidence=_evidence,
    inject=_inject, nominal_only=True, friction_curve=True)
