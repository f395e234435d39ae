"""Load-dependent friction: friction grows with the transmitted torque |Tm| (mesh friction).

Regressor: ``LP(|Tm| * sign(w))``; coefficient ``mu`` in [0, :data:`MAX_LOAD_COEFFICIENT`].
Bench: mu = 0.08 .. 0.20 (friction + mu*|Tm|; harmonic drives lose 10-30 %).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ...friction import LoadDependent
from .base import Cause

#: Largest load-dependence mu (friction + mu*|Tm|) a diagnosis will fit [-].
MAX_LOAD_COEFFICIENT = 0.5


def _variants(base, fold):
    # |Tm|*sign(w) equals Tm itself whenever the drive pushes the way it moves, so without
    # braking phases in the training blocks the fit can slide to mu ~ 1 with I, b, Fc ~ 0
    # (the column "explains" the target). A drive whose mesh friction grows by more than
    # half the torque it transmits would hardly move a load; the bound excludes that.
    yield base.variant(None, base.sig.filt(np.abs(base.torque) * base.sign), (1,),
                       upper=(MAX_LOAD_COEFFICIENT,))


def _extend(model, term, base):
    return replace(model, friction=model.friction + LoadDependent(max(term.coef[0], 0.0)))


def _evidence(base, term, extended):
    m = base.sig.moving
    u = np.abs(base.torque[m])
    rr = (base.residual * np.sign(base.sig.w))[m]
    c = float(np.corrcoef(u, rr)[0, 1]) if u.std() > 0 else float("nan")
    return (f"the baseline residual in the direction of motion grows with |Tm| "
            f"(correlation {c:.2f}); fitted friction + {extended.friction.load_coefficient:.3g} x |Tm|")


def _inject(rng, act):
    mag = dict(coefficient=rng.uniform(0.08, 0.20) * act.strength)
    return act.rigid(magnitude=mag, friction=act.friction() + LoadDependent(mag["coefficient"]))


CAUSE = Cause(
    name="load_dependent", order=30,
    physical="friction grows with the transmitted torque |Tm|",
    changes=("load_coefficient",),
    params=("load_coefficient",), variants=_variants, extend=_extend, evidence=_evidence,
    inject=_inject)
