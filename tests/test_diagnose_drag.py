"""Tests of the drag cause (fricctl.diagnose.causes.drag): friction growing as c*w*|w|.

The registry-wide tests (tests/test_diagnose_causes.py) hide drag once and require it named;
here it is asserted as a rate over seeds, its coefficient against the truth, and told apart
from the Stribeck effect, which the diagnosis once named for a true drag (issue 21).

Seeds: ``[2029, i]`` naming rate, ``[2030, 0]`` clean recovery, ``[2031, i]`` Stribeck
records; none of them was used while the cause was written (that used ``[555, i]``,
``[556, i]``, ``[777, i]`` and ``[778, i]``).
"""

import numpy as np
import pytest

from fricctl.bench.hidden_effects import hidden_effect_record
from fricctl.diagnose import diagnose
from fricctl.diagnose.causes import REGISTRY
from fricctl.friction import Drag


def test_drag_is_named_on_most_records():
    # the target for a new cause hidden alone: >= 85 % named (exactly, nothing else).
    # Measured when written: 8 of 8 seeds (100 %), net scores 71-96 % (Stribeck second at
    # 51-83 %); the drag at each record's 95th-percentile speed was 0.20-0.71 x Fc (the bench
    # sizes it at its top speed, 6 rad/s on a rotary joint; these records reach 4.1-6.9 rad/s).
    # On the linear axis (exploration seeds, not asserted here): 8 of 8 named, 0.19-0.57 x Fc
    named = []
    for i in range(8):
        rec = hidden_effect_record(np.random.default_rng([2029, i]), cause="drag", duration=20.0)
        named.append(diagnose(rec.run, progress=False).causes == ("drag",))
    assert np.mean(named) >= 0.85, named


def test_drag_coefficient_recovered_on_a_clean_record():
    # no torque noise (the encoder's quantisation stays): the extended model's drag is the
    # bench's within 3 % (measured when written: -1.5 %; 0.1-1.8 % on noisy records), the
    # viscous within 10 % (the drag and the viscous share the speed range: measured +0.6 %),
    # in both directions alike
    rec = hidden_effect_record(np.random.default_rng([2030, 0]), cause="drag", duration=20.0,
                               noise=False)
    d = diagnose(rec.run, progress=False)
    assert d.causes == ("drag",), d.report()
    truth, fr = rec.truth.friction, d.extended.friction
    assert fr.drag_pos == fr.drag_neg
    assert fr.drag_pos == pytest.approx(truth.drag_pos, rel=0.03)
    assert fr.viscous_pos == pytest.approx(truth.viscous_pos, rel=0.10)
    # the evidence says what the record shows and the fitted value, with units
    assert "N*m*s^2/rad^2" in d.evidence and "95th-percentile speed" in d.evidence


@pytest.mark.parametrize("i", range(3))
def test_stribeck_is_not_named_drag(i):
    # a low-speed hump is not a drag: the drag candidate is tried on the record but the
    # Stribeck excess (below its velocity, flat beyond) fits the record's shape better.
    # Measured when written: stribeck named on all three, drag's net score 0.3-2.4 %
    rec = hidden_effect_record(np.random.default_rng([2031, i]), cause="stribeck", duration=20.0)
    d = diagnose(rec.run, progress=False)
    assert "drag" not in d.causes, d.report()


def test_injection_sizes_the_drag_against_coulomb():
    # the bench's drag at the actuator's top speed is 0.3 .. 0.8 x Fc (times the strength),
    # and the truth's friction is the baseline's plus that drag alone
    from fricctl.diagnose.causes import BenchActuator

    act = BenchActuator(motor_inertia=3e-3, link_inertia=2e-3, viscous=0.017, coulomb=0.14,
                        sample_time=0.002, duration=20.0, encoder_resolution=3.14e-5)
    for seed in range(20):
        inj = REGISTRY["drag"].inject(np.random.default_rng(seed), act)
        m = inj.magnitude
        assert m["speed"] == act.top_speed == 6.0  # the default: 6 x travel (1 rad) per second
        assert 0.3 * act.coulomb <= m["coefficient"] * m["speed"] ** 2 <= 0.8 * act.coulomb
        assert inj.truth.friction == (act.friction() + Drag(m["coefficient"])).model()


def test_evidence_against_a_model_without_coulomb_friction_gives_no_share():
    # a fitted baseline may hold no Coulomb friction (its bound, 0: issue 21's pair
    # [12102, 43, 1], fitted on a delayed record); the drag's size was then given as
    # "14003820618838 % of the Coulomb level 0 N*m" (a share of the 1e-12 floor).  With a
    # level it is the plain ratio (hand calculation: 0.05 / 0.25 = 20 %)
    from dataclasses import replace

    from fricctl.diagnose.causes import Baseline, Term
    from fricctl.diagnose.causes.base import coulomb_share
    from fricctl.diagnose.signals import estimate_signals
    from fricctl.friction import Viscous

    rec = hidden_effect_record(np.random.default_rng([2030, 1]), cause="none", duration=10.0,
                               nominal=True)
    bare = replace(rec.nominal, friction=Viscous(rec.nominal.friction.viscous_pos).model())
    base = Baseline(estimate_signals(rec.run, 8), bare, None)
    cause = REGISTRY["drag"]
    term = Term(coef=np.array([1e-3]))
    text = cause.evidence(base, term, cause.extend(bare, term, base))
    assert "the Coulomb level is 0 N*m: no share of it" in text, text
    assert coulomb_share(0.05, 0.25, "N*m") == "20 % of the Coulomb level 0.25 N*m"
