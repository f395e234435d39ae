"""Inertia: the inertia differs from the nominal model (a link, a payload, a wrong datasheet).

Regressor (nominal model only: a refitted baseline fits its own inertia): the acceleration
``a``; coefficient: the change of inertia, free in sign.
Bench: true inertia 1.3 .. 2.6 x (70 %) or 0.6 .. 0.8 x the nominal.
"""

from __future__ import annotations

from dataclasses import replace

from .base import Cause


def _variants(base, fold):
    yield base.variant(None, base.sig.a, (0,))


def _extend(model, term, base):
    return replace(model, inertia=max(model.inertia + term.coef[0], 1e-3 * model.inertia))


def _evidence(base, term, extended):
    nominal = base.fitted
    return (f"inertia {extended.inertia:.4g} against the nominal {nominal.inertia:.4g} "
            f"({100 * (extended.inertia / nominal.inertia - 1):+.0f} %)")


def _inject(rng, act):
    f = rng.uniform(1.3, 2.6) if rng.random() < 0.7 else rng.uniform(0.6, 0.8)
    f = 1.0 + (f - 1.0) * act.strength
    return act.rigid(magnitude=dict(factor=f, nominal=act.inertia, true=act.inertia * f),
                     inertia=act.inertia * f)


CAUSE = Cause(
    name="inertia", order=90,
    physical="the inertia differs from the nominal model",
    changes=("inertia",),
    params=("delta_inertia",), variants=_variants, extend=_extend, evidence=_evidence,
    inject=_inject, nominal_only=True)
