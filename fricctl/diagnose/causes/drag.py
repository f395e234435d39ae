"""Drag: friction grows faster than linearly with speed, ``c*w*|w|`` (churning, windage).

Regressor: ``LP(w*|w|)``; coefficient: the drag ``c >= 0`` (one for both directions: a
difference between the directions is :mod:`.asymmetry`'s).  In fit mode the baseline's
viscous and Coulomb terms are refitted with it, so the drag is what the record's friction
adds *above a straight line* in speed.
Bench: the drag at the actuator's top speed (``BenchActuator.top_speed``: 6 rad/s on the
bench's rotary joints, less on a heavy linear axis) is 0.3 .. 0.8 Fc.

Notes
-----
Drag and Stribeck both bend the friction-speed curve upward (convex): a Stribeck excess
decaying over a wide velocity, with the viscous term inflated, imitates a drag on a record
that the baseline cannot fit (that is how a drag was once reported as an "invented
low-speed hump").  What tells them apart is where the curve bends: the Stribeck excess lies
*below* its velocity and is flat beyond it, the drag grows along the whole range and
bends most at the top speeds.  Both candidates are tried on every record; the one whose
shape the data have removes more of the held-out residual.  The evidence states the
record's friction excess over the baseline's straight line at low, middle and top speed,
so that a reader sees which shape it has.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ...friction import Drag
from .base import Cause, coulomb_level, coulomb_share

def _v95(base) -> float:
    """95th percentile of |w| over the sliding samples [rad/s]."""
    sig = base.sig
    return float(np.percentile(np.abs(sig.w[sig.moving]), 95))


def _variants(base, fold):
    sig = base.sig
    # w*|w| is continuous through a reversal: no blending with the effective sign needed
    yield base.variant(None, sig.filt(sig.w * np.abs(sig.w)), (1,))


def _extend(model, term, base):
    return replace(model, friction=model.friction + Drag(max(float(term.coef[0]), 0.0)))


def _evidence(base, term, extended):
    sig, u = base.sig, base.labels
    c = float(extended.friction.drag_pos - base.fitted.friction.drag_pos)
    v95 = _v95(base)
    fc = coulomb_level(base.fitted)
    w = np.abs(sig.w[sig.moving])
    rr = (base.residual * np.sign(sig.w))[sig.moving]

    def mean(lo, hi):
        sel = (w >= lo * v95) & (w < hi * v95)
        return float(rr[sel].mean()) if np.any(sel) else float("nan")

    # the baseline fits a straight line in speed: a drag leaves its residual (in the
    # direction of motion) positive at both ends and negative in the middle, largest at
    # the top; a Stribeck excess leaves it positive at the lowest speeds only
    low, mid, top = mean(0.0, 0.1), mean(0.3, 0.6), mean(0.8, np.inf)

    def said(x):  # a band the record never slides in is said so, not a NaN
        return f"{x:+.3g} {u.torque}" if np.isfinite(x) else "no sliding sample"

    empty = sum(not np.isfinite(x) for x in (low, mid, top))
    if empty:
        shape = (f"{empty} of the three speed bands hold no sliding sample: the bend cannot be "
                 f"read on this record")
    elif top > mid and top > low:
        shape = ("largest at the top speeds: friction bending upward along the speed range, "
                 "where a low-speed hump would leave it largest at the lowest")
    else:
        shape = ("not largest at the top speeds: the upward bend is mixed with another "
                 "effect here")
    return (f"the baseline residual in the direction of motion averages {said(low)} "
            f"below {0.1 * v95:.3g} {u.velocity}, {said(mid)} at "
            f"{0.3 * v95:.3g}-{0.6 * v95:.3g} {u.velocity} and {said(top)} above "
            f"{0.8 * v95:.3g} {u.velocity} ({shape}); "
            f"fitted drag {c:.3g} {u.torque}*s^2/{u.position}^2, i.e. {c * v95 ** 2:.3g} "
            f"{u.torque} at the 95th-percentile speed {v95:.3g} {u.velocity} "
            f"({coulomb_share(c * v95 ** 2, fc, u.torque)}), "
            f"viscous {extended.friction.viscous_pos:.3g} {u.viscous}")


def _inject(rng, act):
    # the record's own speeds are not known before its excitation is drawn: the drag is sized
    # at the speed the bench's fastest excitation reaches with this actuator (a drag slows
    # the open-loop segments: the records that hide one reach 0.7-1.2 x it, rotary)
    speed = act.top_speed
    ratio = rng.uniform(0.3, 0.8) * act.strength
    mag = dict(coefficient=ratio * act.coulomb / speed ** 2, speed=speed,
               torque_at_speed=ratio * act.coulomb)
    return act.rigid(magnitude=mag, friction=act.friction() + Drag(mag["coefficient"]))


CAUSE = Cause(
    name="drag", order=110,
    physical="friction grows faster than linearly with speed (drag c*w*|w|)",
    changes=("drag_pos", "drag_neg"),
    params=("drag",), variants=_variants, extend=_extend, evidence=_evidence,
    inject=_inject, friction_curve=True)
