"""Backlash: the plant's dead band (fricctl.plant), the cause (fricctl.diagnose.causes.backlash)
and the compliance's test that a spring stays a spring where the load torque reverses.

Seeds: ``[2031, i]`` for the fast cases (chosen once, before looking at their results);
the rate sweep (``slow``) uses ``[2032, i]``, never run while the cause was built; the
independent bench (``tests/test_diagnose_independent.py``, its own integrator, contact and
loop) ``[31, 40 + i]`` (its exploration used ``[34, i]``).
"""

import math

import numpy as np
import pytest

from fricctl.bench.hidden_effects import hidden_effect_record
from fricctl.diagnose import diagnose
from fricctl.diagnose.causes import REGISTRY, Baseline, Term
from fricctl.diagnose.causes import backlash as backlash_cause
from fricctl.diagnose.causes import compliance as compliance_cause
from fricctl.diagnose.crossval import Problem, full_fit
from fricctl.diagnose.signals import (backlash_load, contact_damping_ratio, estimate_signals,
                                      restitution)
from fricctl.friction import Coulomb, FrictionModel, Viscous
from fricctl.plant import FlexibleJoint, JointModel


def _joint(gap, *, jm=2e-3, jl=3e-3, fc=300.0, zeta=0.5):
    mu = jm * jl / (jm + jl)
    k = (2 * math.pi * fc) ** 2 * mu
    return FlexibleJoint(motor_inertia=jm, load_inertia=jl, stiffness=k,
                         damping=2 * zeta * math.sqrt(k * mu), friction=FrictionModel(),
                         backlash=gap)


# ----------------------------------------------------------------------------- plant
def test_gap_crossing_in_closed_form():
    # frictionless joint, load in the middle of a gap g, motor driven by a constant T: the
    # motor alone accelerates at T/Jm and meets the load after t1 = sqrt(g*Jm/T) (it covers
    # g/2); until then q = T t^2/(2 Jm) exactly (RK4 is exact on a quadratic) and the load
    # has not moved at all
    jm, jl, gap, torque, ts = 2e-3, 3e-3, 0.02, 0.13, 1e-3
    joint = _joint(gap, jm=jm, jl=jl)
    t1 = math.sqrt(gap * jm / torque)
    st = joint.initial_state()
    rows = []
    for k in range(150):
        st = joint.advance(st, torque, k * ts, ts, 20)
        rows.append(st.copy())
    rows = np.array(rows)
    t = (np.arange(150) + 1) * ts
    before = t < t1
    np.testing.assert_allclose(rows[before, 0], torque * t[before] ** 2 / (2 * jm), rtol=1e-12)
    assert np.all(rows[before, 2] == 0.0) and np.all(rows[before, 3] == 0.0)
    # the first sample whose interval holds t1 moves the load
    assert t[np.argmax(rows[:, 2] != 0.0)] == pytest.approx(ts * math.ceil(t1 / ts), abs=1e-12)
    # the coupling is internal: momentum equals the impulse T*t (RK4 keeps linear invariants)
    momentum = jm * rows[:, 1] + jl * rows[:, 3]
    np.testing.assert_allclose(momentum, torque * t, rtol=1e-10)
    # long after the pick-up both move together, the contact deflected by what accelerates
    # the load: qm - ql = g/2 + T*Jl/((Jm + Jl)*K)
    k = joint.stiffness
    assert rows[-1, 0] - rows[-1, 2] == pytest.approx(gap / 2 + torque * jl / ((jm + jl) * k),
                                                      rel=1e-6)


@pytest.mark.parametrize("zeta", [0.2, 1.0])
def test_impact_conserves_momentum_and_loses_energy(zeta):
    # motor at w0 meeting the load at rest (the faces just touch), no torque, no friction:
    # the impact keeps the momentum Jm*w0 exactly and can only dissipate kinetic energy; the
    # contact only pushes, so the faces part where its force returns to zero, the load ahead
    # with a relative speed e*w0: e is the same at any speed (a linear contact has no scale)
    # and at least the restitution of the contact that would also pull, exp(-pi z/sqrt(1-z^2))
    jm, jl, gap = 2e-3, 3e-3, 0.1
    joint = _joint(gap, jm=jm, jl=jl, zeta=zeta)
    e = []
    for w0 in (1.0, 0.1):
        st = np.array([gap / 2, w0, 0.0, 0.0, 0.0])
        e0 = 0.5 * jm * w0 ** 2
        for k in range(20):
            st = joint.advance(st, 0.0, k * 1e-3, 1e-3, 20)
            assert jm * st[1] + jl * st[3] == pytest.approx(jm * w0, rel=1e-10)
            assert 0.5 * jm * st[1] ** 2 + 0.5 * jl * st[3] ** 2 <= e0 * (1 + 1e-12)
        assert abs(st[0] - st[2]) < gap / 2  # parted: back inside the gap
        e.append((st[3] - st[1]) / w0)
    assert e[0] == pytest.approx(e[1], rel=1e-6)
    assert restitution(zeta) <= e[0] < 1.0


def test_model_file_and_checks():
    fr = (Viscous(0.02) + Coulomb(0.1)).model()
    m = JointModel(inertia=5e-3, friction=fr, load_inertia=2e-3, stiffness=1e3, damping=0.5,
                   backlash=0.012)
    assert JointModel.from_json(m.to_json()) == m and m.as_dict()["backlash"] == 0.012
    assert m.joint().backlash == 0.012 and m.parameters()["backlash"] == 0.012
    with pytest.raises(ValueError, match="backlash: a dead band needs a load"):
        JointModel(inertia=5e-3, friction=fr, backlash=0.01)
    with pytest.raises(ValueError, match="backlash"):
        JointModel(inertia=5e-3, friction=fr, load_inertia=2e-3, stiffness=1e3, backlash=-1e-3)
    with pytest.raises(ValueError, match="backlash"):
        _joint(-0.01)
    v1 = {"format": "fricctl.joint_model", "version": 1, "inertia": 1.0,
          "friction": {}, "backlash": 0.0}
    with pytest.raises(ValueError, match="backlash"):  # a version 2 key
        JointModel.from_dict(v1)


def test_restitution_and_damping_ratio_are_inverse():
    # e = exp(-pi*zeta/sqrt(1 - zeta^2)) of a linear spring-damper contact (closed form)
    for e in (0.05, 0.3, 0.6, 0.9):
        assert restitution(contact_damping_ratio(e)) == pytest.approx(e, rel=1e-12)
    assert restitution(1.0) == 0.0 and contact_damping_ratio(0.0) == 1.0


# ----------------------------------------------------------------------------- the cause
def test_fitted_gap_and_load_where_backlash_hides():
    # nominal mode, one coefficient: the fitted gap within 10 % of the truth (the scan steps
    # by 6 %, the variants around its peaks by 1.5-3 %; 20 % off the gap the regressor removes
    # little: a broken scan or regressor misses it) and the load behind it within 20 %
    # (measured 0-12 % on the seeds built with)
    rec = hidden_effect_record(np.random.default_rng([2031, 0]), cause="backlash", nominal=True)
    sig = estimate_signals(rec.run, 8)
    base = Baseline(sig, rec.nominal, None)
    cause = REGISTRY["backlash"]
    best = full_fit(Problem(sig, None), base.variants(cause, None))
    gap, e = best.variant.h
    assert gap == pytest.approx(rec.magnitude["backlash"], rel=0.10)
    assert best.theta[0] == pytest.approx(rec.magnitude["load_inertia"], rel=0.20)
    term = Term(h=best.variant.h, coef=best.theta)
    assert cause.identifiable(base, term) is None
    extended = cause.extend(rec.nominal, term, base)
    assert extended.backlash == gap and extended.load_inertia == pytest.approx(best.theta[0])
    text = cause.evidence(base, term, extended)
    assert "deg" in text and "encoder counts" in text
    # the record crosses the gap many times; a gap below 4 counts is refused
    assert backlash_load(sig, gap).crossings >= backlash_cause.MIN_CROSSINGS
    tiny = Term(h=(2 * sig.resolution, 0.0), coef=best.theta, extended=extended)
    assert "encoder counts" in cause.identifiable(base, tiny)


def test_backlash_is_not_added_to_a_spring_nor_a_spring_to_backlash():
    rec = hidden_effect_record(np.random.default_rng([2031, 1]), cause="none", duration=10.0,
                               nominal=True)
    base = Baseline(estimate_signals(rec.run, 8), rec.nominal, None)
    spring = REGISTRY["compliance"].extend(rec.nominal, Term(h=(100.0, 0.05),
                                                             coef=np.array([1e-3])), base)
    with pytest.raises(ValueError, match="elastic already"):
        REGISTRY["backlash"].extend(spring, Term(h=(0.01, 0.0), coef=np.array([1e-3])), base)
    gap = REGISTRY["backlash"].extend(rec.nominal, Term(h=(0.01, 0.0), coef=np.array([1e-3])),
                                      base)
    with pytest.raises(ValueError, match="dead band"):
        REGISTRY["compliance"].extend(gap, Term(h=(100.0, 0.05), coef=np.array([1e-3])), base)


def test_a_spring_fitted_to_backlash_does_not_stay_a_spring():
    # the failure: an elastic model fitted where a dead band hides; the compliance's
    # own best term (nominal mode) is refused with the reason
    rec = hidden_effect_record(np.random.default_rng([2031, 2]), cause="backlash", nominal=True)
    sig = estimate_signals(rec.run, 8)
    base = Baseline(sig, rec.nominal, None)
    cause = REGISTRY["compliance"]
    best = full_fit(Problem(sig, None), base.variants(cause, None))
    term = Term(h=best.variant.h, coef=best.theta)
    reason = compliance_cause._stays_a_spring(base, term)
    assert reason is not None and "does not stay a spring" in reason


@pytest.mark.parametrize("axis, excitation", [("rotary", "mixed"), ("linear", "closed_loop")])
def test_diagnose_names_backlash(axis, excitation):
    rec = hidden_effect_record(np.random.default_rng([2031, 3]), cause="backlash", axis=axis,
                               excitation=excitation)
    d = diagnose(rec.run)
    assert d.causes == ("backlash",), d.report()
    assert d.extended.backlash == pytest.approx(rec.magnitude["backlash"], rel=0.10)


def test_no_gap_at_the_encoders_end_beside_a_drift_and_stops():
    # issue 21, the slow stops sweep's record 7116 (a thermal drift alone, end stops): a dead
    # band of 4 encoder counts -- the scan's first gap, its share falling monotonically from
    # there (0.37 of the true model's residual at 4 counts, 0.12 at 20) -- was named beside
    # the drift, 81 % of the inertia behind it.  Of what it removed 37 % lay at the one
    # impact the stops' detector misses (the upper stop, hit once at 0.17 rad/s), the rest
    # spread over the motion at the floor; with that contact masked it was named all the
    # same (net 36 %).  A 4-count band removes 15-49 % of the true model's residual on
    # eight records of the sweep, effect-free ones too: it fits the measuring chain.  A gap
    # at the grid's lower end is not located, as one at its upper end is not.
    from test_diagnose_stops import _rate_record

    cause, rec = _rate_record(7116)
    assert cause == "thermal_drift" and rec.causes == ("thermal_drift",)
    d = diagnose(rec.run)
    assert d.causes == ("thermal_drift",), d.report()
    assert "lower end" in d.not_identifiable["backlash"], d.not_identifiable


# ----------------------------------------------------------------------------- rates
def _sweep(cause, cases, seed0):
    named = []
    for i, (axis, excitation) in enumerate(cases):
        rec = hidden_effect_record(np.random.default_rng([2032, seed0 + i]), cause=cause,
                                   axis=axis, excitation=excitation)
        named.append(diagnose(rec.run).causes)
    return named


#: 24 backlash records: rotary and linear, mixed and closed-loop excitation, 6 of each.
SWEEP = [(a, x) for a in ("rotary", "linear") for x in ("mixed", "closed_loop") for _ in range(6)]


@pytest.mark.slow
def test_backlash_rate():
    # issue 21's target: backlash hidden alone named (exactly) on >= 85 % of the records
    named = _sweep("backlash", SWEEP, 0)
    rate = sum(c == ("backlash",) for c in named) / len(named)
    assert rate >= 0.85, named
    assert not any("compliance" in c for c in named), named


@pytest.mark.slow
def test_no_cause_on_effect_free_records():
    named = _sweep("none", SWEEP[::3], 100)
    assert all(c == ("none",) for c in named), named


@pytest.mark.slow
@pytest.mark.parametrize("i", range(4))
def test_backlash_on_the_independent_bench(i):
    # the second simulator's dead band (LSODA, smoothed friction, a cascade loop, gap
    # 0.5-1.5 deg x travel, contact 200-600 Hz): named, no spring invented, the gap within
    # 30 % (measured 0.2-24 % on the exploration seeds [34, 0-5]: bouncing contacts, damping
    # ratio 0.21-0.23, gave the 10.5 and 24 %, the gap read short; the scan is plastic)
    from test_diagnose_independent import simulate_record

    run, p = simulate_record([31, 40 + i], effects=("backlash",),
                             axis=("rotary", "linear")[i % 2],
                             sample_time=(0.001, 0.002)[(i // 2) % 2], duration=20.0)
    d = diagnose(run)
    assert d.causes == ("backlash",), d.report()
    assert d.extended.backlash == pytest.approx(p.effects["backlash"]["gap"], rel=0.30)


# ----------------------------------------------------------------------------- after a named cause
def _effect_free():
    """An effect-free record with its nominal model: the record, its signals, its baseline."""
    rec = hidden_effect_record(np.random.default_rng([2031, 4]), cause="none", duration=10.0,
                               nominal=True)
    sig = estimate_signals(rec.run, 8)
    return rec, sig, Baseline(sig, rec.nominal, None)


def test_the_scan_reads_the_model_as_it_stands():
    # the scan and its variants are of the residual of the model as it stands
    # (Baseline.advanced), not the baseline's: a residual that is one gap's column (plus a
    # tenth of the baseline's residual) is scanned to that gap, within half a scan step
    # (the grid's own resolution), and the variants sit around it.  Before, the scan read
    # the baseline's residual and its variants were made once: after a named delay they
    # stayed where the delay's misalignment had put them (issue 21's pair [12102, 43, 1])
    rec, sig, base = _effect_free()
    cause = REGISTRY["backlash"]
    gaps0, drops0 = backlash_cause.scan(base)
    before = base.variants(cause, None)  # made at the first step (cached per step)
    g0 = float(np.sqrt(gaps0[0] * gaps0[-1]))  # the grid's middle, in log
    col = backlash_cause._column(sig, g0)
    r = 1e-3 * col / np.std(col[sig.moving]) + 0.1 * base.residual
    now = base.advanced(r, base.target - r)
    gaps, drops = backlash_cause.scan(now)
    half = 10.0 ** (0.5 / backlash_cause.SCAN_PER_DECADE)
    assert g0 / half <= gaps[np.argmax(drops)] <= g0 * half
    assert any(g0 / half <= v.h[0] <= g0 * half for v in now.variants(cause, None))
    assert not any(g0 / half ** 3 <= v.h[0] <= g0 * half ** 3 for v in before)
    # the earlier step keeps its own scan
    assert np.array_equal(backlash_cause.scan(base)[1], drops0)


def test_a_gap_half_a_step_under_the_scan_is_at_its_lower_end():
    # a variant half a step under the scan's first gap (3.89 counts) comes from a peak at the
    # first gap: the reason is that no gap is located (the lower end), not that the encoder
    # cannot resolve a gap the scan found; a gap further down is below the encoder's counts
    rec, sig, base = _effect_free()
    cause = REGISTRY["backlash"]
    lo = backlash_cause.MIN_COUNTS * backlash_cause._counts(sig)
    half = 10.0 ** (0.5 / backlash_cause.SCAN_PER_DECADE)
    coef = np.array([0.3 * rec.nominal.inertia])
    low = cause.identifiable(base, Term(h=(lo / half, 0.0), coef=coef))
    assert "lower end" in low and "3.89 encoder counts" in low, low
    below = cause.identifiable(base, Term(h=(lo / half ** 2, 0.0), coef=coef))
    assert "below the 4 counts" in below, below


def test_delay_then_backlash_at_200_hz():
    # issue 21's pair [12102, 43, 1] (bench_diagnose's pairs: PAIRS[43], mixed, rotary,
    # 200 Hz, 30 s): a delay of 8 samples and a dead band of 712 encoder counts.  The
    # baseline's residual is the delay's misalignment (RMS 1.12 N*m; after the delay 0.251,
    # the truth without its dead band 0.251, the truth 0.078): there the scan peaked at its
    # first gap, 4 counts (2.5 %, the true gap 0.75 %), and the backlash was refused after
    # the delay as "3.89 encoder counts".  On the residual after the delay the scan peaks at
    # the true gap (91 %).  Named both; the gap within 10 % (the scan's step is 6 %, see
    # test_fitted_gap_and_load_where_backlash_hides)
    rec = hidden_effect_record(np.random.default_rng([12102, 43, 1]),
                               cause=("time_delay", "backlash"), sample_time=0.005,
                               axis="rotary", excitation="mixed", duration=30.0)
    d = diagnose(rec.run, rec.nominal)
    assert set(d.causes) == {"time_delay", "backlash"}, d.report()
    assert d.extended.backlash == pytest.approx(rec.magnitude["backlash"]["backlash"], rel=0.10)
    assert d.extended.delay == pytest.approx(rec.magnitude["time_delay"]["seconds"], rel=1e-9)
