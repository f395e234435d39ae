"""Time delay: the torque acts some samples later than recorded (computation, communication).

No extra column: each variant shifts the target by ``d`` samples beyond the baseline's
delay -- quarter samples up to 2, half samples up to 4, whole samples up to 12, then
steps of a quarter of the delay up to four periods of the low-pass cut-off (at least 12
samples), a fraction by linear interpolation of the held torque
(:func:`fricctl.diagnose.signals.delayed`); the delay with the least training error is
chosen.  Cannot be told when it takes the longest value searched.
Bench: 4 .. 8 samples (whole samples; the bench's loop holds the torque per sample).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from .base import Cause


def _max_shift(sig) -> float:
    """The longest delay searched: four periods of the cut-off, at least 12 samples [samples]."""
    return max(4.0 / (sig.cutoff * sig.ts), 12.0)


def shifts(sig) -> np.ndarray:
    """The delays searched beyond the baseline's [samples]: quarter samples up to 2, half
    samples up to 4, whole samples up to 12, then steps of a quarter of the delay."""
    top = _max_shift(sig)
    grid = [np.arange(0.25, 2.0, 0.25), np.arange(2.0, 4.0, 0.5), np.arange(4.0, 12.5)]
    d = 12.0
    while d * 1.25 <= top:
        d = round(d * 1.25)
        grid.append(np.array([d]))
    out = np.concatenate(grid)
    return out[out <= top]


def _variants(base, fold):
    sig = base.sig
    for d in shifts(sig):
        y = sig.torque_target(base.delay + d) - base.reference
        # the extra column is empty: the delay only moves the target
        yield base.variant(base.delay + float(d), np.zeros((sig.t.size, 0)), (), y=y)


def _extend(model, term, base):
    return replace(model, delay=term.h * base.sig.ts)


def _evidence(base, term, extended):
    sig = base.sig
    d = extended.delay / sig.ts
    return (f"the torque acts {d:.3g} samples ({1e3 * d * sig.ts:.3g} ms) later than recorded "
            f"(the held-out residual is least at that shift among 0.25 .. "
            f"{shifts(sig)[-1]:.0f} samples)")


def _identifiable(base, term):
    top = shifts(base.sig)[-1]
    if term.h >= base.delay + top - 1e-9:
        return (f"the delay takes the longest value searched ({top:.0f} samples): the residual "
                f"keeps falling with the shift, which a delay does not explain")
    return None


def _inject(rng, act):
    delay = max(int(round(int(rng.integers(4, 9)) * act.strength)), 1)
    return act.rigid(magnitude=dict(samples=delay, seconds=delay * act.sample_time), delay=delay)


CAUSE = Cause(
    name="time_delay", order=50,
    physical="the torque acts some samples later than recorded",
    changes=("delay",),
    params=(), variants=_variants, extend=_extend, evidence=_evidence,
    identifiable=_identifiable, inject=_inject)
