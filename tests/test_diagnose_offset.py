"""The constant torque (``offset``) against direction asymmetry, and EMPS told the same way
with and without a supplied model (issue 21, items 3-4).

Seeds: ``[2141, i]`` while building; ``[2142, i]`` (rotary) and ``[2143, i]`` (linear) for
the rates, never looked at while building.
"""

import numpy as np
import pytest

from fricctl.bench.hidden_effects import hidden_effect_record
from fricctl.datasets import Run
from fricctl.diagnose.causes import Baseline
from fricctl.diagnose.signals import estimate_signals
from fricctl.diagnose.twin import effect_free_twin


def _shifted(run: Run, off: float) -> Run:
    return Run(t=run.t, torque=run.torque + off, position=run.position,
               reference=run.reference, units=run.units, source="offset added")


def test_twin_carries_the_models_offset():
    # the twin of a model with a constant torque c, on the record shifted by c, is the twin
    # of the model without it on the record (the same physics): the chain's floor must not
    # hold the offset (it did: EMPS's floor was hypot(3.16, 0.66) N with the IDIM-LS model)
    rec = hidden_effect_record(np.random.default_rng([2141, 0]), cause="none", duration=10.0,
                               nominal=True)
    off = 0.3 * rec.nominal.friction.coulomb_pos
    from dataclasses import replace
    plain = effect_free_twin(Baseline(estimate_signals(rec.run, 8), rec.nominal, None)).rms
    moved = effect_free_twin(Baseline(estimate_signals(_shifted(rec.run, off), 8),
                                      replace(rec.nominal, offset=off), None)).rms
    # reference: the same simulation up to the constant (rounding of the encoder only)
    assert moved == pytest.approx(plain, rel=0.05)
    assert moved < 0.5 * off
