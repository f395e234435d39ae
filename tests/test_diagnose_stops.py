"""End stops (issue 21, deliverable 3, ``end_stop``): the bench's ideal rigid stop
(:mod:`fricctl.bench.end_stops`) and their detection (:mod:`fricctl.diagnose.stops`)."""

import json

import numpy as np
import pytest

from fricctl import datasets
from fricctl.bench.end_stops import simulate_with_stops
from fricctl.bench.hidden_effects import HIDDEN_CAUSES, NOMINAL_CAUSES, hidden_effect_record
from fricctl.datasets import Run
from fricctl.diagnose import MIN_SCORE, diagnose
from fricctl.diagnose.signals import estimate_signals
from fricctl.diagnose.stops import LONE, MIN_IMPACTS, end_stops
from fricctl.diagnose.verdict import EXPLAINED_RATIO
from fricctl.diagnose.windows import window_grid
from fricctl.identify.signals import EXCLUDE_LEVEL
from fricctl.friction import Coulomb, Viscous
from fricctl.plant import RigidJoint
from fricctl.simulate import Schedule, simulate_schedule

TS = 0.002


def _schedule(n):
    """PD tracking for half the record, then an open-loop torque sine (a second segment)."""
    t = np.arange(n) * TS
    wn = 2 * np.pi * 3.0
    closed = t < t[n // 2]
    seg = np.zeros(n, bool)
    seg[[0, n // 2]] = True
    return Schedule(kp=np.where(closed, 5e-3 * wn ** 2, 0.0),
                    kd=np.where(closed, 2 * 0.7 * wn * 5e-3, 0.0),
                    reference=0.5 * np.sin(2 * np.pi * 0.5 * t),
                    feedforward=np.where(closed, 0.0, 0.4 * np.sin(2 * np.pi * 0.7 * t)),
                    segment_start=seg)


JOINT = RigidJoint(inertia=5e-3, friction=Viscous(0.02) + Coulomb(0.15))


@pytest.mark.parametrize("delay", [0, 2])
def test_the_stop_loop_without_stops_is_the_compiled_loop(delay):
    # reference: the compiled loop of fricctl.simulate (an independent implementation of the
    # same steps); equal to the last bit
    n = 3000
    sch = _schedule(n)
    noise = np.random.default_rng(0).normal(0.0, 0.003, n)
    sim = simulate_schedule(JOINT, sch, sample_time=TS, max_torque=2.0,
                            encoder_resolution=3.14e-5, delay=delay, noise=noise)
    ours = simulate_with_stops(JOINT, sch, sample_time=TS, max_torque=2.0,
                               encoder_resolution=3.14e-5, substeps=sim.info.substeps,
                               lower=-np.inf, upper=np.inf, delay=delay, noise=noise)
    for name in ("q", "q_meas", "torque_motor", "reference"):
        np.testing.assert_array_equal(getattr(ours, name), getattr(sim, name))
    assert ours.impacts.size == 0


def test_an_ideal_stop_holds_the_joint_on_the_limit():
    n = 3000
    sim = simulate_with_stops(JOINT, _schedule(n), sample_time=TS, max_torque=2.0,
                              encoder_resolution=3.14e-5, substeps=4, lower=-0.3, upper=0.3)
    # the joint never passes a stop (exactly: it is put back on it)
    assert sim.q.min() == -0.3 and sim.q.max() == 0.3
    assert sim.impacts.size >= 4 and set(sim.impact_side) == {-1, 1}
    on = np.isin(sim.q, (-0.3, 0.3))
    assert np.all(on[sim.impacts]) and not np.any(on[sim.impacts - 1])
    assert np.all(sim.impact_speed > 0)


def test_the_stop_loop_refuses_what_it_does_not_simulate():
    sch = _schedule(100)
    with pytest.raises(ValueError, match="enclose the start"):
        simulate_with_stops(JOINT, sch, sample_time=TS, max_torque=2.0, encoder_resolution=0.0,
                            substeps=4, lower=0.1, upper=0.3)
    with pytest.raises(ValueError, match="enclose the start"):
        simulate_with_stops(JOINT, sch, sample_time=TS, max_torque=2.0, encoder_resolution=0.0,
                            substeps=4, lower=np.nan, upper=0.3)


def test_the_bench_hides_stops_without_changing_its_draws():
    plain = hidden_effect_record(np.random.default_rng(4), cause="none", duration=20.0,
                                 excitation="closed_loop")
    same = hidden_effect_record(np.random.default_rng(4), cause="none", duration=20.0,
                                excitation="closed_loop", end_stops=0.0)
    np.testing.assert_array_equal(plain.run.position, same.run.position)
    stopped = hidden_effect_record(np.random.default_rng(4), cause="none", duration=20.0,
                                   excitation="closed_loop", end_stops=0.1)
    # the same actuator and excitation, the motion cut by the stops
    assert stopped.truth == plain.truth and stopped.excitation == plain.excitation
    assert plain.stops == () and plain.impacts.size == 0
    q = stopped.run.position
    assert len(stopped.stops) == 2 and stopped.impacts.size >= 2 * MIN_IMPACTS
    count = 2 * np.pi / 200000  # the encoder reads floor(q/count)*count: one count below
    assert min(stopped.stops) - count <= q.min() and q.max() <= max(stopped.stops)
    # a foreign position-sensor gain scales the stops as it scales the record
    scaled = hidden_effect_record(np.random.default_rng(4), cause="none", duration=20.0,
                                  excitation="closed_loop", end_stops=0.1, foreign="position_gain")
    gain = 1.0 + scaled.foreign_magnitude["error"]
    assert scaled.stops == pytest.approx(tuple(gain * x for x in stopped.stops), rel=1e-12)
    qs = scaled.run.position
    assert min(scaled.stops) - abs(gain) * count <= qs.min() and qs.max() <= max(scaled.stops)
    with pytest.raises(ValueError, match="end_stops"):
        hidden_effect_record(np.random.default_rng(4), cause="none", end_stops=0.5)
    with pytest.raises(ValueError, match="rigid joint"):
        hidden_effect_record(np.random.default_rng(4), cause="compliance", end_stops=0.1)


# Records made while building the detector (seeds 0-7 of closed_loop and mixed at 0.1); every
# side of these was hit at least MIN_IMPACTS times.  The rates on fresh seeds are measured in
# the branch's report (3000-3009, 60 records: 68 of 73 sides hit twice or more found, 3 of 28
# hit once with LONE = 30; 0 false stops on 180 records without one and on EMPS).
STOP_RECORDS = [("closed_loop", 0), ("closed_loop", 4), ("closed_loop", 5), ("mixed", 1)]


@pytest.fixture(scope="module", params=STOP_RECORDS, ids=lambda p: f"{p[0]}-{p[1]}")
def stopped(request):
    exc, seed = request.param
    return hidden_effect_record(np.random.default_rng(seed), cause="none", duration=20.0,
                                excitation=exc, end_stops=0.1)


def test_stops_are_found_where_they_are(stopped):
    es = end_stops(stopped.run)
    q = stopped.run.position
    count = float(np.min(np.abs(np.diff(q))[np.diff(q) != 0]))
    assert es.found and len(es.positions) == len(stopped.stops)
    # positions: the stop's encoder reading, within one count of the true stop
    for found, true in zip(es.positions, sorted(stopped.stops)):
        assert abs(found - true) <= 1.0 * count
    # every impact found (within 2 samples) and covered by the mask
    for i in stopped.impacts:
        assert np.min(np.abs(es.impacts - i)) <= 2
        assert es.mask[i] and es.mask[i - 1]
    # at most one contact more than the simulation logged (a gentle arrival on the stop's
    # reading), and the mask small
    assert es.impacts.size <= stopped.impacts.size + 1
    assert es.mask.sum() < 0.2 * q.size
    assert es.abrupt.sum() >= MIN_IMPACTS and np.all(es.ratio[es.abrupt] > 3.0)
    assert "end stop" in es.description and "left out" in es.description
    out = json.loads(json.dumps(es.as_dict()))
    assert out["excluded_samples"] == int(es.mask.sum())


def test_a_side_hit_once_hard_is_a_stop():
    # a mixed record one of whose stops is hit once, 10-30x faster than torque and friction
    # can stop it (seed 7022 while choosing LONE; 7027 since the asymmetry is hidden as a
    # viscous split: the first seed of 7000.. with such a side and both sides hit)
    rec = hidden_effect_record(np.random.default_rng(7027), cause="asymmetry", duration=20.0,
                               end_stops=0.062)
    mid = np.mean(rec.run.position)
    sides = ([i for i in rec.impacts if rec.run.position[i] < mid],
             [i for i in rec.impacts if rec.run.position[i] >= mid])
    once = [s[0] for s in sides if len(s) == 1]
    assert len(rec.stops) == 2 and len(once) == 1
    es = end_stops(rec.run)
    assert len(es.positions) == 2
    assert es.mask[once[0]] and LONE <= es.ratio[np.argmin(np.abs(es.impacts - once[0]))] < 30


@pytest.mark.parametrize("excitation", ["mixed", "closed_loop", "stuck"])
def test_no_stop_on_effect_free_records(excitation):
    found = [end_stops(hidden_effect_record(np.random.default_rng(seed), cause="none",
                                            duration=20.0, excitation=excitation).run).found
             for seed in range(5)]
    assert sum(found) == 0


def test_no_stop_on_records_with_other_effects():
    names = HIDDEN_CAUSES[1:] + NOMINAL_CAUSES
    found = {c: end_stops(hidden_effect_record(np.random.default_rng(7), cause=c,
                                               duration=20.0).run).found for c in names}
    assert not any(found.values()), found


@pytest.mark.parametrize("kind", ["estimation", "validation"])
def test_no_stop_on_emps(data_dir, kind):
    # EMPS reverses at the same extremes again and again, smoothly: its strongest braking
    # there reaches 0.76 of what its force and friction can do (measured), under MARGIN = 3
    es = end_stops(datasets.emps(data_dir, kind=kind).run)
    assert not es.found and not es.mask.any()
    assert "no end stop" in es.description
    assert 85.0 < es.inertia < 105.0  # published IDIM-LS 95.1 kg: the trimmed fit is sane


def test_a_record_that_does_not_move_is_not_checked():
    t = np.arange(100) * TS
    es = end_stops(Run(t=t, torque=np.full(100, 0.01), position=np.zeros(100)))
    assert not es.found and es.impacts.size == 0 and not es.mask.any()
    assert "not checked" in es.description
    with pytest.raises((TypeError, ValueError)):
        end_stops("a record")


# ------------------------------------------------------------------ wired into the diagnosis
@pytest.fixture(scope="module", params=[("closed_loop", 0), ("mixed", 1)],
                ids=lambda p: f"{p[0]}-{p[1]}")
def diagnosed(request):
    exc, seed = request.param
    rec = hidden_effect_record(np.random.default_rng(seed), cause="none", duration=20.0,
                               excitation=exc, end_stops=0.1)
    return rec, diagnose(rec.run)


def test_a_diagnosis_leaves_the_contacts_out_and_says_so(diagnosed):
    rec, d = diagnosed
    es = d.end_stops
    # effect-free records with stops: no cause invented by the impacts.  The filtered impact
    # rings at the cut-off beyond 1/fc (the rest guard): left out only that far, compliance
    # fitted the ringing, 18.9 % net on closed_loop-0 (MIN_SCORE is 20 %) and the residual
    # over floor 1.72 on mixed-1 (measured with EXCLUDE_LEVEL = 0.5); with the filter's whole
    # reach 0.6 % and 1.01
    assert d.causes == ("none",)
    assert dict(d.ranking).get("compliance", 0.0) < 0.05
    assert es.found and len(es.positions) == len(rec.stops)
    # no re-simulation window holds a contact
    for k0 in d.sim_before.starts:
        assert not es.mask[k0:k0 + d.sim_before.length].any()
    # the residual and the verdict are read without the contacts
    assert np.all(np.isnan(d.residual_after[es.mask]))
    assert d.explained == ("Explained within noise" in d.evidence)
    assert d.explained and d.verdict.residual_over_floor <= EXPLAINED_RATIO
    for text in (d.evidence, d.report()):
        assert "End stops at" in text and "left out" in text and "windows held or followed a contact" in text
    out = json.loads(json.dumps(d.as_dict()))
    assert out["end_stops"]["excluded_samples"] == int(es.mask.sum()) > 0
    assert len(out["end_stops"]["positions"]) == len(rec.stops)


def test_a_record_without_stops_is_diagnosed_on_every_window():
    rec = hidden_effect_record(np.random.default_rng(3), cause="time_delay", duration=20.0)
    d = diagnose(rec.run)
    assert d.causes == ("time_delay",) and not d.end_stops.found
    assert "End stop" not in d.evidence and "End stop" not in d.report()
    sig = estimate_signals(rec.run, 8)
    grid = window_grid(sig, 0.5)
    # every window of the grid that lies inside one block (the held-out re-simulation's)
    inside = sig.folds[grid.starts] == sig.folds[grid.starts + grid.length - 1]
    assert np.array_equal(np.sort(d.sim_before.starts), grid.starts[inside])
    assert d.as_dict()["end_stops"]["excluded_samples"] == 0


def test_the_exclusion_reaches_as_far_as_the_filter_rings():
    # reference: the zero-phase 4th-order Butterworth's response to an impulse, computed here
    # by scipy's filtfilt (an independent implementation of the package's zero_phase_filter
    # up to its padding); the reach is where it falls below EXCLUDE_LEVEL of its peak
    from scipy import signal

    run = hidden_effect_record(np.random.default_rng(0), cause="none", duration=20.0).run
    mask = np.zeros(run.n_samples, bool)
    mask[5000] = True
    sig = estimate_signals(run, 8, exclude=mask)
    b, a = signal.butter(4, 2 * sig.cutoff * sig.ts)
    x = np.zeros(4001)
    x[2000] = 1.0
    h = np.abs(signal.filtfilt(b, a, x))
    reach = int(np.max(np.abs(np.flatnonzero(h > EXCLUDE_LEVEL * h.max()) - 2000)))
    plain = estimate_signals(run, 8)
    gone = plain.moving & ~sig.moving
    assert gone.any() and np.flatnonzero(gone).min() >= 5000 - reach
    assert np.flatnonzero(gone).max() <= 5000 + reach
    assert not sig.moving[5000 - reach + 1:5000 + reach].any()
    np.testing.assert_array_equal(sig.excluded, mask)
    with pytest.raises(ValueError, match="exclude"):
        estimate_signals(run, 8, exclude=mask[:-1])


#: The fit-mode causes the bench hides with its ideal stops (a rigid joint without a friction
#: state: not compliance or backlash, whose joints have two bodies, nor presliding), none
#: included.  Backlash and offset joined HIDDEN_CAUSES after the rate below was first
#: measured (27 of 30, with neither in the registry); the bench refuses backlash with stops.
STOPPABLE = tuple(c for c in HIDDEN_CAUSES if c not in ("compliance", "backlash", "presliding"))


def test_the_stoppable_causes_are_those_the_bench_stops():
    """Every cause of STOPPABLE gets its stops from the bench; the ones left out are refused."""
    for cause in HIDDEN_CAUSES:
        rec = None
        try:
            rec = hidden_effect_record(np.random.default_rng([7099, len(cause)]), cause=cause,
                                       duration=10.0, end_stops=0.1)
        except ValueError as exc:
            assert "end_stops" in str(exc) and cause not in STOPPABLE, (cause, exc)
        if rec is not None:
            assert cause in STOPPABLE, cause


def _rate_record(seed):
    """One record per seed: the causes in turn, mixed and closed-loop excitation in turn,
    stops where the stop-free motion spends 5-20 % of its time beyond each."""
    cause = STOPPABLE[seed % len(STOPPABLE)]
    exc = ("mixed", "closed_loop")[(seed // len(STOPPABLE)) % 2]
    frac = 0.05 + 0.15 * np.random.default_rng([seed, 99]).random()
    return cause, hidden_effect_record(np.random.default_rng(seed), cause=cause, duration=20.0,
                                       excitation=exc, end_stops=frac)


@pytest.mark.slow
def test_the_hidden_causes_are_named_on_records_with_stops():
    # seeds 7100-7129, not used while building (100-101 and 7000-7029 were); the branch's
    # report gives the records one by one.  Targets of the task: >= 85 % named exactly, no
    # cause on an effect-free record, "explained" only at the floor.  Measured first (before
    # issue 21's causes joined the rotation): 27 of 30.  With them (drag, position load and
    # offset drawn; backlash left out, above), 2026-11-27: 26 of 30 once a backlash gap at
    # the scan's lower end was refused (25 before: a false backlash beside the thermal drift
    # of 7116).  Misses: two load dependences weighing 13 % and 36 % (7103, 7113) named none;
    # a drag (7107) named none and "not explained" (2.3x the floor); a position load (7128)
    # named none.  3 of 3 effect-free records none; no "explained" above 2x the floor.
    exact, n, false_on_none, explained_above = 0, 0, 0, 0
    for seed in range(7100, 7130):
        cause, rec = _rate_record(seed)
        d = diagnose(rec.run)
        n += 1
        exact += set(d.causes) == set(rec.causes)
        false_on_none += cause == "none" and d.causes != ("none",)
        explained_above += d.explained and d.verdict.residual_over_floor > EXPLAINED_RATIO
    assert exact >= 0.85 * n, (exact, n)
    assert false_on_none == 0 and explained_above == 0


def test_one_models_checks_leave_the_contacts_out(stopped):
    """torque_residual, windowed_simulation and prediction_errors read the record as the
    diagnosis does: the true model's equation error and replay do not measure the stops."""
    from fricctl.diagnose import prediction_errors, torque_residual, windowed_simulation
    from fricctl.diagnose.api import predict

    es = end_stops(stopped.run)
    tr = torque_residual(stopped.truth, stopped.run)
    assert not np.any(tr.mask & es.mask)  # no contact sample is in the mask
    naive = estimate_signals(stopped.run, 1)  # the stops' samples in
    r0 = predict(stopped.truth, naive).residual[naive.moving]
    # the impacts were most of the true model's equation error (22-50x on these records)
    assert np.sqrt(np.mean(r0 ** 2)) > 10 * tr.rms()
    sim = windowed_simulation(stopped.truth, stopped.run)
    ends = sim.starts + sim.length
    hit = np.concatenate([[0], np.cumsum(es.mask)])
    assert sim.starts.size > 0 and np.all(hit[ends] - hit[sim.starts] == 0)
    e = prediction_errors(stopped.truth, stopped.run)
    assert e.torque_rms == pytest.approx(tr.rms(), rel=1e-12)
    assert e.simulation_rms == sim.rms().position
    # the windows left out are counted, not hidden
    whole = window_grid(estimate_signals(stopped.run, 1, exclude=es.mask), 0.5)
    assert e.windows == sim.starts.size and e.windows_dropped > 0
    assert e.windows + e.windows_dropped == whole.starts.size


def test_the_benchs_weights_leave_the_contacts_out():
    # the bench's label of a record with stops: with the impacts in the residual every
    # weight read negative (stribeck -1.86 on this record), and the benchmark expected "none"
    # where the diagnosis rightly named the hidden cause
    rec = hidden_effect_record(np.random.default_rng([12202, 2, 0]), cause="stribeck",
                               excitation="mixed", duration=20.0, end_stops=0.15)
    assert rec.stops and rec.weights()["stribeck"] >= MIN_SCORE
