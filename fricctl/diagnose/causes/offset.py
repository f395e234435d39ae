"""Offset: a constant torque acts on the joint (``JointModel.offset``: it receives ``Tm - c``).

Regressor: ``LP(1)``; coefficient: the offset ``c`` (free in sign), added to the model's
``offset``.  Bench: a constant torque of 0.2 .. 0.4 Fc, either sign, simulated as a
constant torque at the joint (not as friction).  Removed from a supplied model (to be
judged): its offset and any difference between its two Coulomb levels (the same effect,
below).

Notes
-----
Identifiability.  On a rigid joint whose friction is additive (Coulomb, viscous,
Stribeck, drag, ripple ...), a constant torque ``c`` and a Coulomb level that differs
between the directions by ``2c`` (``Fc + c`` forward, ``Fc - c`` backward) give the same
equation of motion while the joint slides (``I*q'' = Tm - c - F(w)`` is
``Tm - (F(w) + c)``, and ``F + c`` is that asymmetric friction) and the same breakaway
band at rest (the joint sticks while ``c - Fc < Tm < c + Fc`` either way).  No record of
such a joint tells them apart: this cause names the constant, and its evidence says
that a Coulomb asymmetry of ``2c`` slides the same way.  They differ only where the
constant exceeds friction (``|c| > Fc``: the joint drifts under zero torque, which no
friction does), where friction scales (a load-dependent or warming friction scales a
Coulomb asymmetry, not a constant) and in presliding (a bristle model centres its
band on zero torque); a record showing one of these tells them apart through that
cause.  What a constant cannot explain -- a viscous coefficient that differs between
the directions -- is :mod:`.asymmetry`'s.

A constant is told from the baseline's Coulomb column ``Fc*sign(w)`` only by a record
that moves both ways (one way, the two columns are the same: the selection's
collinearity test refuses it), and from a load of position only by the shape over
the travel (:mod:`.position_load` refuses a load that is a constant over the travel).
Beside a load of position, a constant is told only by what the load's wave leaves of it:
over a travel short against the load's period the wave's sine and cosine hold a constant,
and an offset beside the load removes less than the naming line of what the load leaves
(:mod:`.position_load`, *What it does not tell*).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ...friction import FrictionModel
from .base import Cause, coulomb_level, coulomb_share


def _variants(base, fold):
    sig = base.sig
    yield base.variant(None, sig.filt(np.ones(sig.t.size)), (0,))


def _extend(model, term, base):
    return replace(model, offset=model.offset + float(term.coef[0]))


def _evidence(base, term, extended):
    sig, u, r = base.sig, base.labels, base.residual
    m = sig.moving
    fwd, bwd = m & (sig.w > 0), m & (sig.w < 0)
    pos = float(r[fwd].mean()) if np.any(fwd) else float("nan")
    neg = float(r[bwd].mean()) if np.any(bwd) else float("nan")
    c = float(extended.offset - base.fitted.offset)
    fc = coulomb_level(extended)

    def said(x, way):  # a direction the record never slides in is said so, not a NaN
        return (f"{x:+.3g} {u.torque} moving {way}" if np.isfinite(x) else
                f"nothing moving {way} (no sliding sample)")

    text = (f"the baseline residual averages {said(pos, 'forward')} and "
            f"{said(neg, 'backward')} (a constant torque shifts both alike); "
            f"fitted offset {c:+.3g} {u.torque} (the model's offset {extended.offset:+.3g} "
            f"{u.torque}: the joint receives Tm - offset), "
            f"{coulomb_share(abs(extended.offset), fc, u.torque)}")
    if abs(extended.offset) > fc:
        return text + (f"; it exceeds the Coulomb level: under zero torque the joint would "
                       f"drift, which no friction does")
    return text + (f"; a Coulomb level differing between the directions by "
                   f"{2 * abs(extended.offset):.3g} {u.torque} slides the same way (Coulomb "
                   f"{fc + extended.offset:.3g} forward, {fc - extended.offset:.3g} backward): "
                   f"on a rigid joint the two are one effect")


def _remove(model):
    # the constant and its rigid-joint twin, a Coulomb level differing between the directions
    d = model.friction.as_dict()
    d["coulomb_pos"] = d["coulomb_neg"] = 0.5 * (d["coulomb_pos"] + d["coulomb_neg"])
    return replace(model, offset=0.0, friction=FrictionModel.from_dict(d))


def _inject(rng, act):
    fc = act.coulomb
    off = rng.uniform(0.2, 0.4) * fc * rng.choice((-1.0, 1.0)) * act.strength
    return act.rigid(magnitude=dict(offset=off), offset=off, breakaway=fc + abs(off))


CAUSE = Cause(
    name="offset", order=155,
    physical="a constant torque acts on the joint (or, the same on a rigid joint, a Coulomb "
             "level that differs between the directions; or a load of position, such as "
             "gravity, that is constant over the record's travel)",
    changes=("offset",),
    params=("offset",), variants=_variants, extend=_extend, evidence=_evidence,
    inject=_inject, remove=_remove)
