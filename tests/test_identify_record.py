"""The default identification (issue 20): one fit for identify and diagnose, honest stds,
validation on held-out halves, the choice between estimators read off the record.

Records come from the package's sampled loop on the paper's actuator (Coulomb + viscous,
the identified model class, so the truth is known) at the sample rates and encoder
counts of the issue's grid; the slow test runs the whole grid (36 records, the
benchmark's: ``benchmarks/bench_identify_grid.py``).
"""

import json
import math
from dataclasses import replace

import numpy as np
import pytest

from fricctl import controllers as ctl
from fricctl import friction as fr
from fricctl import identify as I
from fricctl.datasets import Run
from fricctl.identify.uncertainty import block_covariance, correlation_time
from fricctl.params import paper_actuator
from fricctl.simulate import simulate

_P = paper_actuator()
LAW = fr.Viscous(_P.viscous) + fr.Coulomb(_P.coulomb)
OPEN = ctl.open_loop(ctl.sinusoid(0.4, 0.5) + ctl.sinusoid(0.15, 2.3))
CLOSED = ctl.pd_control(2.0, 0.05, ctl.sinusoid(1.0, 0.4) + ctl.sinusoid(0.3, 1.7))
#: issue 20's targets for the default command: inertia and Coulomb within 5 %, viscous 10 %
TARGETS = {"inertia": 0.05, "viscous": 0.10, "coulomb": 0.05}


def grid_record(rate: float, counts: int, loop: str, seed: int) -> tuple:
    """(record, truth) at ``rate`` [Hz] with ``counts`` per load revolution, 20 s, torque
    noise 0.005 N*m, the loop ``"open"`` or ``"closed"`` (PD 2.0, 0.05)."""
    p = replace(_P, sample_time=1.0 / rate, encoder_counts=counts // int(_P.gear_ratio))
    run = simulate(p, OPEN if loop == "open" else CLOSED, duration=20.0, friction=LAW,
                   noise_std=0.005, rng=np.random.default_rng(seed)).to_run()
    return run, dict(inertia=p.total_inertia, viscous=_P.viscous, coulomb=_P.coulomb)


def errors(params: dict, truth: dict) -> dict:
    return {k: params[k] / x - 1.0 for k, x in truth.items()}


def within_targets(params: dict, truth: dict) -> bool:
    return all(abs(e) < TARGETS[k] for k, e in errors(params, truth).items())


# the corners: coarse encoder at 1 kHz (equation error -46 % inertia), fine at 2 kHz
CORNERS = [(1000, 500, "closed", 1500), (500, 2000, "open", 2500), (2000, 10000, "closed", 12000)]


@pytest.fixture(scope="module", params=CORNERS, ids=lambda c: f"{c[0]}Hz-{c[1]}counts-{c[2]}")
def corner(request):
    rate, counts, loop, seed = request.param
    run, truth = grid_record(rate, counts, loop, seed)
    return run, truth, I.identify_record(run)


def test_default_meets_the_targets_where_the_equation_error_does_not(corner):
    run, truth, ident = corner
    assert within_targets(ident.parameters, truth), errors(ident.parameters, truth)
    # every number stands with its std: the truth within 4 of them (seeded records)
    r = ident.result
    for k, x in truth.items():
        assert abs(r.parameters[k] - x) < 4 * r.std[r.names.index(k)], k
    h = ident.held_out
    assert h.failure == "" and h.simulation_fit > 95 and not any("poor held-out" in w
                                                                for w in r.warnings)


def test_didim_is_reported_and_a_disagreement_is_told(corner):
    run, truth, ident = corner
    s, d = ident.start, ident.refined
    assert ident.result.method == "DIDIM" and d is not None
    assert np.all(ident.result.estimates == d.estimates)
    # the reported std is at least the block covariance's (the jackknife's where larger)
    assert np.all(ident.result.std >= d.std)
    apart = [abs(a - b) > I.record.DISAGREEMENT_SIGMAS * math.hypot(sa, sb)
             for a, sa, b, sb in zip(s.estimates, s.std, d.estimates, d.std)]
    told = any("disagree beyond their standard errors" in w for w in ident.warnings)
    assert told == any(apart)


def test_coarse_encoder_equation_error_is_biased_and_flagged():
    run, truth = grid_record(1000, 500, "closed", 1500)
    ident = I.identify_record(run, validate=False)
    # the errors-in-variables bias the issue reports, on the package's own generator
    assert errors(ident.start.parameters, truth)["inertia"] < -0.3
    assert ident.result.method == "DIDIM"
    assert within_targets(ident.parameters, truth)


def test_identify_and_diagnose_give_the_same_baseline():
    from fricctl.bench.hidden_effects import hidden_effect_record
    from fricctl.diagnose import diagnose

    rec = hidden_effect_record(np.random.default_rng(3), cause="time_delay", duration=20.0)
    d = diagnose(rec.run)
    ident = I.identify_record(rec.run, offset=False, validate=False)
    p = ident.parameters
    assert d.baseline.inertia == p["inertia"]
    assert d.baseline.friction.viscous_pos == p["viscous"]
    assert d.baseline.friction.coulomb_pos == p["coulomb"]
    assert d.baseline.provenance["inertia"].std == ident.result.std[0]
    # and through the CLI: fricctl identify --no-offset gives the same numbers
    from fricctl.cli import main
    import contextlib
    import io
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory() as tmp:
        path = rec.run.to_csv(Path(tmp) / "rec.csv")
        buf = io.StringIO()
        with contextlib.redirect_stdout(buf):
            assert main(["identify", str(path), "--no-offset", "--no-validation", "--json"]) == 0
    out = json.loads(buf.getvalue())
    for k, x in p.items():  # the CSV keeps 17 significant digits
        assert out["parameters"][k]["value"] == pytest.approx(x, rel=1e-9), k


def test_warnings_mark_the_model_file(tmp_path, capsys):
    from fricctl.cli import main
    from fricctl.plant import JointModel

    # a record whose offset is not identified (none in the truth): the warning names it, and
    # the model file says so in that value's provenance
    run, _ = grid_record(1000, 500, "closed", 1500)
    path = run.to_csv(tmp_path / "r.csv")
    out = tmp_path / "m.json"
    fig = tmp_path / "v.png"
    assert main(["identify", str(path), "--out", str(out), "--figure", str(fig), "--json"]) == 0
    res = json.loads(capsys.readouterr().out)
    assert res["warnings"], "the coarse record's estimators disagree: said"
    m = JointModel.load(out)
    assert all("flagged:" in m.provenance[k].note for k in ("inertia", "friction.coulomb_pos"))
    off = [w for w in res["warnings"] if w.startswith("offset:")]
    if off:
        assert off[0] in m.provenance["offset"].note
    assert fig.stat().st_size > 10_000 and fig.read_bytes()[:4] == b"\x89PNG"
    # every recipe of a linear model is validated on held-out halves, and can plot it
    w = tmp_path / "w.png"
    assert main(["identify", str(path), "--recipe", "idim_ls", "--figure", str(w), "--json"]) == 0
    ls = json.loads(capsys.readouterr().out)
    assert w.read_bytes()[:4] == b"\x89PNG"
    from fricctl.identify import idim_ls
    from fricctl.identify.record import held_out_halves

    held = held_out_halves(lambda r: idim_ls(r), run)
    assert ls["held_out"]["simulation_fit_percent"] == pytest.approx(held.simulation_fit)
    # a coarse encoder: the EMPS recipe's biased estimate replays the held-out half worse
    assert held.simulation_fit < res["held_out"]["simulation_fit_percent"]
    # not for a non-linear model
    assert main(["identify", str(path), "--recipe", "plain", "--model", "stribeck",
                 "--figure", str(tmp_path / "s.png")]) == 2
    assert "linear model only" in capsys.readouterr().err


def test_block_covariance_is_the_white_formula_for_white_noise_and_wider_for_coloured():
    rng = np.random.default_rng(0)
    n = 20000
    J = np.column_stack([np.ones(n), np.sin(np.arange(n) / 300.0)])
    white = rng.normal(size=n)
    bc = block_covariance(J, white)
    ref = np.sqrt(np.diag(np.linalg.inv(J.T @ J)))
    assert np.all(np.abs(bc.std / ref - 1) < 0.15) and bc.block <= 3
    # an AR(1) residual, rho = 0.95: correlation time (1+rho)/(1-rho) = 39 samples; the
    # std of the mean grows by sqrt(39) ~ 6.2
    e = np.empty(n)
    e[0] = 0.0
    for k in range(1, n):
        e[k] = 0.95 * e[k - 1] + white[k]
    assert correlation_time(e) == pytest.approx(39.0, rel=0.3)
    bc = block_covariance(J, e)
    sigma = np.std(e)
    assert bc.std[0] / (sigma * ref[0]) == pytest.approx(math.sqrt(39.0), rel=0.3)
    assert not bc.capped


@pytest.mark.slow
def test_std_is_calibrated_over_seeds():
    # the truth within the reported std as often as a normal law says, over 8 seeds of a
    # closed-loop and 8 of an open-loop 500 Hz / 2000-count record (48 errors): |z| < 2 for
    # at least 85 % of them (95 % for a calibrated std; measured 98 %).  The block
    # covariance alone is optimistic on replayed positions (75 % measured): the jackknife
    # is what makes the difference, so that is asserted too
    z, zb = [], []
    for loop in ("closed", "open"):
        for seed in range(8):
            run, truth = grid_record(500, 2000, loop, 100 + seed)
            ident = I.identify_record(run)
            r, d = ident.result, ident.refined
            z += [(r.parameters[k] - x) / r.std[r.names.index(k)] for k, x in truth.items()]
            zb += [(d.parameters[k] - x) / d.std[d.names.index(k)] for k, x in truth.items()]
    z, zb = np.abs(z), np.abs(zb)
    assert np.mean(z < 2.0) >= 0.85, np.round(z, 1)
    assert np.mean(zb < 2.0) < np.mean(z < 2.0)


def test_a_record_that_cannot_be_replayed_keeps_the_equation_error_and_says_so(monkeypatch):
    run, truth = grid_record(500, 2000, "open", 7)

    def refuse(*args, **kwargs):
        raise ValueError("diverging replay")

    monkeypatch.setattr(I.record, "didim", refuse)
    ident = I.identify_record(run, validate=False)
    assert ident.refined is None and ident.result.method == "IDIM-LS"
    assert any("could not be replayed (diverging replay)" in w for w in ident.warnings)


def test_validate_on_another_record():
    run, truth = grid_record(500, 2000, "open", 3)
    other, _ = grid_record(500, 2000, "closed", 4)
    ident = I.identify_record(run, validate=False)
    va = I.validate(ident.result, other)
    assert va.simulation_fit > 95 and va.equation_fit > 90
    # a wrong estimate validates worse: half the inertia, twice the Coulomb level
    bad = dict(ident.parameters, inertia=0.5 * truth["inertia"], coulomb=2 * truth["coulomb"])
    wrong = replace(ident.result, estimates=np.array([bad[n] for n in ident.result.names]))
    assert I.validate(wrong, other).simulation_fit < va.simulation_fit - 5
    with pytest.raises(ValueError, match="result"):
        I.validate(replace(ident.result, model="stribeck"), other)


def test_bad_input():
    run, _ = grid_record(500, 2000, "open", 3)
    with pytest.raises(ValueError, match="run"):
        I.identify_record({"t": [0.0]})
    with pytest.raises(ValueError, match="model"):
        I.identify_record(run, model="stribeck", validate=False)
    with pytest.raises(ValueError, match="refine"):
        I.identify_record(run, refine="yes")
    # a given equation error (the diagnosis hands over its own) of another model or record
    from fricctl.identify.signals import estimate_signals

    sig = estimate_signals(run, 1)
    with pytest.raises(ValueError, match="start: a IDIM-LS fit of"):
        I.identify_record(run, offset=False, validate=False,
                          start=I.equation_error(sig, "asymmetric", offset=False))
    other = Run(t=run.t[:6000], torque=run.torque[:6000], position=run.position[:6000])
    with pytest.raises(ValueError, match="the equation error of another record"):
        I.identify_record(other, offset=False, validate=False,
                          start=I.equation_error(sig, offset=False))
    with pytest.raises(ValueError, match="start"):
        I.identify_record(run, start=sig)
    still = Run(t=run.t, torque=0 * run.torque + 0.01,
                position=np.where(np.arange(run.n_samples) < 100, 0.0, 1e-3))
    with pytest.raises(ValueError, match="motion"):
        I.identify_record(still)


@pytest.mark.slow
def test_the_whole_grid_meets_the_targets():
    # the grid: 500 Hz - 2 kHz, 500 - 10 000 counts per revolution, open and closed
    # loop, two seeds each (36 records, benchmarks/bench_identify_grid.py prints the table)
    bad = []
    for rate in (500, 1000, 2000):
        for counts in (500, 2000, 10000):
            for loop in ("open", "closed"):
                for seed in (1, 2):
                    run, truth = grid_record(rate, counts, loop, rate + counts + seed)
                    ident = I.identify_record(run, validate=False)
                    if not within_targets(ident.parameters, truth):
                        bad.append((rate, counts, loop, seed, errors(ident.parameters, truth)))
    assert not bad, bad


def test_figure_without_validation_is_refused_before_any_output(tmp_path, capsys):
    # review finding: --figure --no-validation raised AttributeError (a traceback) after the
    # model file was written
    from fricctl.cli import main

    run, _ = grid_record(500, 2000, "open", 3)
    path = run.to_csv(tmp_path / "r.csv")
    for recipe in ("auto", "idim_ls"):
        assert main(["identify", str(path), "--recipe", recipe, "--no-validation", "--figure",
                     str(tmp_path / "f.png"), "--out", str(tmp_path / "m.json")]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "cannot go with --no-validation" in err
        assert not (tmp_path / "m.json").exists() and not (tmp_path / "f.png").exists()


def test_a_record_with_end_stops_is_identified_with_the_contacts_left_out():
    # a closed-loop bench record that hits both of its ideal stops (tests/test_diagnose_stops's
    # closed_loop-0: 2 impacts each): the contacts out of the equation error, the replay cut
    # into the stretches between them (a rigid replay cannot pass a stop)
    from fricctl.bench.hidden_effects import hidden_effect_record
    from fricctl.identify.stops import end_stops

    rec = hidden_effect_record(np.random.default_rng(0), cause="none", duration=20.0,
                               excitation="closed_loop", end_stops=0.1)
    stops = end_stops(rec.run)
    assert stops.found and len(rec.stops) == 2
    ident = I.identify_record(rec.run, offset=False)
    truth = {"inertia": rec.truth.inertia, "viscous": rec.truth.friction.viscous_pos,
             "coulomb": rec.truth.friction.coulomb_pos}
    r = ident.result
    assert r.method == "DIDIM" and ident.held_out.failure == ""
    # issue 20's targets (5 % / 10 % / 5 %) and the truth within 4 reported stds (seeded record)
    assert within_targets(r.parameters, truth), errors(r.parameters, truth)
    for k, x in truth.items():
        assert abs(r.parameters[k] - x) < 4 * r.std[r.names.index(k)], k
    # held-out blocks replayed between the contacts: a good fit (a replay through a stop runs
    # past it)
    assert ident.held_out.simulation_fit > 90
    assert np.all(np.isnan(ident.held_out.measured[np.isnan(ident.held_out.simulated)]))
    # said in the notes, the text and the JSON
    assert any("end stops at" in n and "stretches between the contacts" in n for n in ident.notes)
    assert "end stops at" in ident.report()
    out = json.loads(json.dumps(ident.as_dict()))
    assert out["end_stops"]["excluded_samples"] == int(stops.mask.sum()) > 0
    # the same stops handed in give the same numbers; another record's refused
    again = I.identify_record(rec.run, offset=False, validate=False, stops=stops)
    assert np.allclose(again.result.estimates, r.estimates)
    with pytest.raises(ValueError, match="stops"):
        I.identify_record(rec.run, validate=False, stops=end_stops(_closed_short()))


def _closed_short():
    from fricctl.bench.hidden_effects import hidden_effect_record

    return hidden_effect_record(np.random.default_rng(1), cause="none", duration=10.0).run


def test_a_record_without_stops_says_none_and_leaves_nothing_out():
    run, _ = grid_record(1000, 10000, "open", 7)
    ident = I.identify_record(run, offset=False, validate=False)
    assert not ident.end_stops.found
    assert not any("end stop" in n for n in ident.notes)
    assert ident.as_dict()["end_stops"]["excluded_samples"] == 0


def test_a_replay_the_model_cannot_follow_falls_back_to_the_equation_error():
    # a closed-loop record with stops the detector does not see (two gentle single impacts):
    # the rigid replay cannot follow it and DIDIM loses inertia, viscous and Coulomb (it ran
    # to a thousandth of the inertia, 8 min of replays, before its iterates were held within a
    # decade of the start); the equation error identifies them: it is reported, and said
    from fricctl.bench.hidden_effects import hidden_effect_record
    from fricctl.identify.didim import MIN_INERTIA_SHARE

    frac = 0.05 + 0.15 * np.random.default_rng([7107, 99]).random()
    rec = hidden_effect_record(np.random.default_rng(7107), cause="thermal_drift", duration=20.0,
                               excitation="closed_loop", end_stops=frac)
    ident = I.identify_record(rec.run, offset=False, validate=False)
    assert not ident.end_stops.found  # the case: stops the detector does not see
    assert ident.refined is not None and not ident.refined.identified.all()
    assert ident.refined.estimates[0] >= MIN_INERTIA_SHARE * ident.start.estimates[0] * (1 - 1e-9)
    assert ident.result is ident.start or np.array_equal(ident.result.estimates,
                                                         ident.start.estimates)
    assert any("the equation error is reported" in w for w in ident.result.warnings)
    assert ident.parameters["inertia"] == pytest.approx(rec.truth.inertia, rel=0.05)
    assert ident.parameters["viscous"] == pytest.approx(rec.truth.viscous, rel=0.1)


def test_a_trial_costlier_than_the_start_is_refused_before_it_is_simulated(monkeypatch):
    # a replay's cost per sample is its RK4 sub-step count; here a stand-in count that grows by
    # 36 per 0.1 % a parameter moves from the start (4 there), so that with MAX_REPLAY_COST = 10
    # every trial moving one by more than 0.1 % is too costly (DIDIM moves this record's
    # inertia by more).  None of them may be simulated (the Jacobians step 1e-4 from an
    # accepted iterate), and the warnings count them.
    import importlib

    D = importlib.import_module("fricctl.identify.didim")
    run, truth = grid_record(500, 2000, "open", 7)
    starts, simulated, real = [], [], D.simulate_record

    def substeps(run, params):
        th = np.array([params[n] for n in ("inertia", "viscous", "coulomb")])
        if not starts:  # DIDIM asks first at its start
            starts.append(th)
        return 4 + int(36e3 * np.max(np.abs(th / starts[0] - 1.0)))

    def simulate(run, params, loop, **kw):
        simulated.append(np.array([params[n] for n in ("inertia", "viscous", "coulomb")]))
        return real(run, params, loop, **kw)

    monkeypatch.setattr(D, "record_substeps", substeps)
    monkeypatch.setattr(D, "simulate_record", simulate)
    ident = I.identify_record(run, offset=False, validate=False)
    moved = np.max(np.abs(np.array(simulated) / starts[0] - 1.0), axis=1)
    assert D.MAX_REPLAY_COST == 10  # the stand-in's slope is set for it
    assert moved.max() <= 1e-3 + 2e-4, moved.max()
    assert np.any(moved > 1e-3 / 2)  # and the refinement did move (the test has a point)
    refused = [w for w in ident.refined.warnings if "trial step(s) whose simulation" in w]
    assert len(refused) == 1 and f"more than {D.MAX_REPLAY_COST} times the start's 4" in refused[0]


@pytest.mark.slow
def test_a_long_closed_loop_record_drifting_in_its_replay_is_not_refined_at_any_cost():
    # the 3324 s outlier of issue 21's benchmark (benchmarks/README.md): a 60 s, 2 kHz
    # closed-loop record with a position load the rigid model lacks; replayed open loop it
    # drifts off, and DIDIM's output error pulled toward a joint that barely moves (viscous
    # 0.024 -> 1885 N*m*s/rad at a tenth of the inertia): replays of 1585 RK4 sub-steps per
    # sample, 215 s of the diagnosis.  Now no simulation runs more than MAX_REPLAY_COST times
    # the start's sub-steps, and the reported estimate is the same: the equation error, said.
    import importlib

    from fricctl.bench.hidden_effects import hidden_effect_record

    D = importlib.import_module("fricctl.identify.didim")
    rec = hidden_effect_record(np.random.default_rng([12201, 1, 2, 0]), cause="position_load",
                               sample_time=0.0005, axis="rotary", excitation="closed_loop",
                               duration=60.0)
    counts = []
    real = D.simulate_record

    def simulate(run, params, loop, **kw):
        counts.append(D.record_substeps(run, params))
        return real(run, params, loop, **kw)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(D, "simulate_record", simulate)
        ident = I.identify_record(rec.run, offset=False, validate=False)
    assert max(counts) <= D.MAX_REPLAY_COST * counts[0]
    assert any("trial step(s) whose simulation" in w for w in ident.refined.warnings)
    assert np.array_equal(ident.result.estimates, ident.start.estimates)
    assert any("the equation error is reported" in w for w in ident.result.warnings)


def test_a_disagreement_without_standard_errors_is_worded_not_divided():
    # a parameter at a bound has std 0 in both estimators: the warning says so (it printed
    # "inf std" with a divide-by-zero warning)
    import warnings as _w
    with _w.catch_warnings():
        _w.simplefilter("error")
        assert I.record._apart_text("coulomb", 0.1, 0.2, 0.0) == (
            "coulomb 0.1 vs 0.2 (neither estimator gives it a standard error)")
        assert I.record._apart_text("viscous", 1.0, 1.5, 0.1) == "viscous 1 vs 1.5 (5.0 std)"
