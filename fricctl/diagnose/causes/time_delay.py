"""Time delay: the torque acts some samples later than recorded (computation, communication).

No extra column: each variant shifts the target by ``d`` = 1 .. max(20 ms, 6 samples) samples
beyond the baseline's delay; the delay with the least training error is chosen.
Bench: 4 .. 8 samples.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from .base import Cause


def _max_shift(sig) -> int:
    return max(int(round(0.02 / sig.ts)), 6)


def _variants(base, fold):
    sig = base.sig
    for d in range(1, _max_shift(sig) + 1):
        y = sig.torque_target(base.delay + d) - base.reference
        # the extra column is empty: the delay only moves the target
        yield base.variant(base.delay + d, np.zeros((sig.t.size, 0)), (), y=y)


def _extend(model, term, base):
    return replace(model, delay=term.h * base.sig.ts)


def _evidence(base, term, extended):
    sig = base.sig
    d = extended.delay_samples(sig.ts)
    return (f"the torque acts {d} samples ({1e3 * d * sig.ts:.3g} ms) later than recorded "
            f"(the held-out residual is least at that shift among 1 .. {_max_shift(sig)} samples)")


def _inject(rng, act):
    delay = max(int(round(int(rng.integers(4, 9)) * act.strength)), 1)
    return act.rigid(magnitude=dict(samples=delay, seconds=delay * act.sample_time), delay=delay)


CAUSE = Cause(
    name="time_delay", order=50,
    physical="the torque acts some samples later than recorded",
    changes=("delay",),
    params=(), variants=_variants, extend=_extend, evidence=_evidence, inject=_inject)
