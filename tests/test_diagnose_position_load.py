"""The position_load cause (``fricctl/diagnose/causes/position_load.py``) on the virtual bench:
named where the load hides, not where a ripple or a constant does, and fitted close to the truth.

Seeds ``[2121, i]`` (the load), ``[2122, i]`` (gravity over many revolutions), fixed before the
rates were measured; ``[12102, 35, 1]``: the pairs benchmark's record of issue 21 (a load and a
ripple on a drifting joint), taken as it was found.
"""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from fricctl.bench.hidden_effects import ENCODER_RESOLUTION, PAIRS, hidden_effect_record
from fricctl.datasets import Run
from fricctl.diagnose import causes, diagnose
from fricctl.diagnose.causes import Baseline, BenchActuator, Term
from fricctl.diagnose.causes.position_load import MAX_REACH, MIN_SHAPE_SHARE, reach
from fricctl.diagnose.crossval import baseline_fit
from fricctl.diagnose.selection import MIN_SCORE
from fricctl.diagnose.signals import estimate_signals
from fricctl.diagnose.stops import end_stops
from fricctl.friction import Coulomb, PositionLoad, PositionRipple, Viscous


def _load(fr, q):
    return fr.position_load_amplitude * np.sin(2 * np.pi * q / fr.position_load_period
                                               + fr.position_load_phase)


def test_hidden_load_is_named_on_most_seeds():
    # the issue's target for a new cause hidden alone: named (exactly) on >= 85 % of records;
    # measured 8 of 8 on these seeds (travels of 0.35-1.4 load periods)
    named = []
    for i in range(8):
        rec = hidden_effect_record(np.random.default_rng([2121, i]), cause="position_load")
        named.append(diagnose(rec.run, rec.nominal).causes == ("position_load",))
    assert sum(named) >= 7, named


def test_fitted_load_follows_the_true_one_over_the_travel():
    # the extended model's load along the record's travel against the hidden one: within 5 % of
    # the true amplitude RMS (a seeded noisy recovery; measured 0.09 %), the period within 5 %
    # (measured 0.8 %)
    rec = hidden_effect_record(np.random.default_rng([2121, 0]), cause="position_load")
    d = diagnose(rec.run, rec.nominal)
    assert d.causes == ("position_load",)
    q = np.linspace(rec.run.position.min(), rec.run.position.max(), 500)
    truth, fit = rec.truth.friction, d.extended.friction
    err = _load(fit, q) - _load(truth, q)
    assert np.sqrt(np.mean(err ** 2)) < 0.05 * truth.position_load_amplitude
    assert fit.position_load_period == pytest.approx(truth.position_load_period, rel=0.05)


def _gravity_as_ripple(name, rng, act, *, _inject=causes.inject):
    """Gravity on the joint's own link, m*g*r*sin(q + phi): period 2*pi, hidden as the ripple
    it is on a travel of two revolutions or more."""
    if name != "position_ripple":
        return _inject(name, rng, act)
    fc = act.coulomb
    mag = dict(amplitude=rng.uniform(0.3, 0.8) * fc, period=2 * math.pi,
               phase=rng.uniform(0, 2 * math.pi))
    return act.rigid(magnitude=mag, friction=act.friction() + PositionRipple(**mag),
                     breakaway=fc + mag["amplitude"])


def test_gravity_over_many_revolutions_stays_a_ripple(monkeypatch):
    # the independent bench's gravity over 5-14 revolutions was named position_ripple with
    # period 2*pi, which is right: a load periodic within the travel is a ripple, and the
    # load's periods start above half the travel
    monkeypatch.setattr(causes, "inject", _gravity_as_ripple)
    for i in range(3):
        rec = hidden_effect_record(np.random.default_rng([2122, i]), cause="position_ripple")
        assert np.ptp(rec.run.position) > 2 * 2 * math.pi  # two revolutions or more
        d = diagnose(rec.run, rec.nominal)
        assert d.causes == ("position_ripple",), d.report()
        assert d.extended.friction.ripple_period == pytest.approx(2 * math.pi, rel=0.02)


def test_bench_ripple_stays_a_ripple():
    rec = hidden_effect_record(np.random.default_rng([2122, 10]), cause="position_ripple")
    assert diagnose(rec.run, rec.nominal).causes == ("position_ripple",)


def test_a_constant_over_the_travel_is_not_a_load():
    # a constant torque (an offset) against the nominal model: the longest wave fits it as well
    # as a constant does, so its shape removes nothing of what a constant leaves -> not told
    rec = hidden_effect_record(np.random.default_rng([2121, 50]), cause="none", duration=10.0,
                               nominal=True)
    off = 0.3 * rec.nominal.friction.coulomb_pos
    shifted = Run(t=rec.run.t, torque=rec.run.torque + off,
                                position=rec.run.position, reference=rec.run.reference,
                                units=rec.run.units, source="offset added")
    base = Baseline(estimate_signals(shifted, 8), rec.nominal, None)
    cause = causes.get("position_load")
    lo, hi = base.sig.qf.min(), base.sig.qf.max()
    reason = cause.identifiable(base, Term(h=16 * (hi - lo), coef=np.array([0.0, off])))
    assert reason is not None and "constant" in reason
    assert MIN_SHAPE_SHARE == pytest.approx(1 - 0.9 ** 2)  # the selection's 10 % RMS line


def test_injection_is_gravity_behind_a_ratio():
    # the bench's draw (module docstring): m*g*r 0.3-0.8 Fc, period 2*pi*(4..8), on the baseline
    act = BenchActuator(motor_inertia=3e-3, link_inertia=2e-3, viscous=0.017, coulomb=0.14,
                        sample_time=0.002, duration=20.0, encoder_resolution=ENCODER_RESOLUTION)
    for seed in range(20):
        inj = causes.inject("position_load", np.random.default_rng(seed), act)
        fr = inj.truth.friction
        assert 0.3 * 0.14 <= fr.position_load_amplitude <= 0.8 * 0.14
        assert 4 * 2 * math.pi <= fr.position_load_period <= 8 * 2 * math.pi
        load = PositionLoad(fr.position_load_amplitude, fr.position_load_period,
                            fr.position_load_phase)
        assert fr == Viscous(0.017) + Coulomb(0.14) + load


def test_reach_is_measured_in_lengths_of_the_training_travel():
    # hand count: four blocks of ten samples; block 0 at q = -6 .. 3 against a training
    # travel 0 .. 9 (blocks 1-3, length 9) reaches 6 below it; a sample at rest counts
    # neither in the block held out nor in the training travel
    q = np.concatenate([np.arange(-6.0, 4.0), np.arange(10.0), np.arange(10.0), np.arange(10.0)])
    moving = np.ones(q.size, dtype=bool)
    sig = SimpleNamespace(qf=q, moving=moving, folds=np.repeat(np.arange(4), 10))
    assert reach(sig, 0) == pytest.approx(6 / 9, abs=1e-12)
    assert [reach(sig, f) for f in (1, 2, 3)] == [0.0, 0.0, 0.0]  # inside -6 .. 9
    moving[:2] = False  # q = -6, -5 at rest: the block reaches 4 below
    assert reach(sig, 0) == pytest.approx(4 / 9, abs=1e-12)
    moving[10:40] = q[10:40] < 9.0  # q = 9 at rest: the training travel 0 .. 8
    assert reach(sig, 0) == pytest.approx(4 / 8, abs=1e-12)
    q[30:40] = 30.0  # block 3 at q = 30: 22 above a training travel -4 .. 8 (blocks 0-2)
    assert reach(sig, 3) == pytest.approx(22 / 12, abs=1e-12)
    q[10:30] = 0.0  # blocks 1-2 at q = 0: block 0 (q = -4 .. 3) against a travel 0 .. 30
    assert reach(sig, 0) == pytest.approx(4 / 30, abs=1e-12)
    moving[:40] = False  # nothing slides: nothing reaches
    assert reach(sig, 0) == 0.0


def _issue21_record():
    """The pairs benchmark's record ``(i, m) = (35, 1)`` with its arguments
    (``benchmarks/bench_diagnose.py`` pairs: rate, axis, excitation, duration)."""
    i, m = 35, 1
    assert PAIRS[i] == ("position_ripple", "position_load")
    return hidden_effect_record(np.random.default_rng([12102, i, m]), cause=PAIRS[i],
                                sample_time=0.005, axis="rotary", excitation="mixed",
                                duration=30.0)


def test_a_block_far_beyond_the_training_travel_does_not_test_the_load():
    # issue 21's record: the joint drifts, and its first block reached 24.5 rad below a
    # training travel of 9.2 rad (2.7 of its lengths); a near-line wave fitted there 26x the
    # Coulomb level made the load's held-out share -3.64.  That block has no variant now (it
    # stays the model as it stands); the others, within the training travel or near it, and
    # all data keep theirs
    rec = _issue21_record()
    assert not end_stops(rec.run).found  # the diagnosis's signals: its eight blocks, all samples
    sig = estimate_signals(rec.run, 8)
    base = Baseline(sig, None, baseline_fit(sig).estimates.copy())
    reaches = [reach(sig, f) for f in range(sig.n_folds)]
    cause = causes.get("position_load")
    for f, r in enumerate(reaches):
        assert (base.variants(cause, f) == []) == (r > MAX_REACH), (f, r)
    assert reaches[0] > 2 * MAX_REACH  # the drifting block (measured 2.67)
    assert sum(r > MAX_REACH for r in reaches) == 1
    assert base.variants(cause, None)


def test_a_load_and_a_ripple_on_a_drifting_joint_are_both_named():
    # the same record diagnosed: named nothing before the rule (the load's share -3.64,
    # knowing the true load removes 69 % of the residual: rec.weights()); now both, the load
    # on its own share above the naming line (measured 24 %), fitted within 10 % of the true
    # amplitude (measured 4 %) and 5 % of the true period (measured 0.7 %): seeded noisy
    # recoveries
    rec = _issue21_record()
    assert rec.expected() == {"position_load", "position_ripple"}
    d = diagnose(rec.run, rec.nominal)
    assert set(d.causes) == {"position_load", "position_ripple"}, d.report()
    assert dict(d.ranking)["position_load"] >= MIN_SCORE
    truth, fit = rec.truth.friction, d.extended.friction
    assert fit.position_load_amplitude == pytest.approx(truth.position_load_amplitude, rel=0.10)
    assert fit.position_load_period == pytest.approx(truth.position_load_period, rel=0.05)
    # the block the load does not test stays without it at the next step too (the review of
    # issue 21: the all-data variant put it back there, and what it removed on that block was
    # credited to every candidate: backlash 0.30, stribeck 0.29, presliding 0.25, five more at
    # 0.21-0.24, and the ripple 0.69; now the ripple 0.43 and the next best 0.06)
    second = dict(d.steps[1].ranking)
    assert d.steps[1].cause == "position_ripple" and second["position_ripple"] < 0.6
    assert max(v for c, v in second.items() if c != "position_ripple") < 0.1, second


def test_an_offset_beside_a_load_is_named_where_the_record_tells_it():
    # issue 21's pairs: chosen alone, the load's period bent to take up an offset hidden beside
    # it (on this record the old choice named the load alone).  Chosen beside a constant where
    # the record tells one,
    # the period is the load's and the offset is named too.  Seed [2123, 21], looked at while
    # the rule was built (0.448 of the true period over the travel).  Tolerances: the period
    # to one FINE step (0.01 cycle at 0.45 cycles: 2.2 %), amplitude and offset to 5 %
    # (noisy recovery; measured 0.4 %, 0.2 %, 0.4 %)
    rec = hidden_effect_record(np.random.default_rng([2123, 21]), cause=("position_load", "offset"),
                               excitation="mixed", axis="rotary", duration=20.0)
    d = diagnose(rec.run, rec.nominal)
    assert set(d.causes) == {"position_load", "offset"}
    fr, true = d.extended.friction, rec.truth.friction
    assert fr.position_load_period == pytest.approx(true.position_load_period, rel=0.022)
    assert fr.position_load_amplitude == pytest.approx(true.position_load_amplitude, rel=0.05)
    assert d.extended.offset == pytest.approx(rec.truth.offset, rel=0.05)
