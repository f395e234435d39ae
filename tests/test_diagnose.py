"""Tests of fricctl.diagnose and fricctl.bench.hidden_effects.

The hidden-effect tests hand ``diagnose`` only the record (and, for the
nominal-model causes, the nominal model an engineer would hold); the generator's
ground truth is used only to check the answer.  Seeds are fixed once (2026 + i),
not chosen after looking at results.  Every cause, hidden and named, is tested in
``test_diagnose_causes.py`` (parametrised over the cause registry).
"""

import dataclasses
import json
import math

import numpy as np
import pytest

from fricctl.bench.hidden_effects import (ENCODER_RESOLUTION, HIDDEN_CAUSES, NOMINAL_CAUSES,
                                          hidden_effect_record)
from fricctl.diagnose import (CAUSES, MIN_SCORE, NOMINAL_ONLY, diagnose, prediction_errors,
                              torque_residual, windowed_simulation)
from fricctl.friction import Coulomb, Viscous
from fricctl.plant import JointModel
from fricctl.plant.model import MODEL_VERSION

#: The candidates of a diagnosis without a nominal model.
FIT_MODE = set(CAUSES) - {"none"} - set(NOMINAL_ONLY)


def _record(cause, seed, **kw):
    return hidden_effect_record(np.random.default_rng([2026, seed]), cause=cause, **kw)


# ----------------------------------------------------------------------------- model file
def test_model_json_round_trip(tmp_path):
    m = JointModel(inertia=0.0075, friction=Viscous(0.0169) + Coulomb(pos=0.15, neg=0.13),
                   offset=0.01, delay=0.004, load_inertia=0.003, stiffness=50.0, damping=0.02,
                   source="test")
    path = m.save(tmp_path / "m.json")
    assert JointModel.load(path) == m
    d = json.loads(path.read_text())
    assert d["format"] == "fricctl.joint_model" and d["version"] == MODEL_VERSION


@pytest.mark.parametrize("change, match", [
    ({"version": 99}, "version"),
    ({"format": "other"}, "format"),
    ({"mass": 1.0}, "unknown key"),
    ({"inertia": -1.0}, "inertia"),
    ({"inertia": float("nan")}, "inertia"),
    ({"friction": {"coulomb_pos": 0.1, "wear": 1}}, "unknown field"),
])
def test_model_file_rejects_bad_content(change, match):
    d = JointModel(inertia=0.01, friction=Viscous(0.01) + Coulomb(0.1)).as_dict()
    d.update(change)
    with pytest.raises(ValueError, match=match):
        JointModel.from_dict(d)


def test_model_file_missing_key_and_bad_json(tmp_path):
    d = JointModel(inertia=0.01, friction=Viscous(0.01) + Coulomb(0.1)).as_dict()
    del d["friction"]
    with pytest.raises(ValueError, match="missing key 'friction'"):
        JointModel.from_dict(d)
    p = tmp_path / "bad.json"
    p.write_text("{not json")
    with pytest.raises(ValueError, match="bad.json"):
        JointModel.load(p)
    with pytest.raises(FileNotFoundError):
        JointModel.load(tmp_path / "absent.json")


def test_elastic_model_needs_stiffness():
    with pytest.raises(ValueError, match="stiffness"):
        JointModel(inertia=0.01, friction=Viscous(0.01) + Coulomb(0.1), load_inertia=0.004)


# ----------------------------------------------------------------------------- generator
def test_generator_hides_every_registered_cause():
    # every registered cause once: the fit-mode ones (registry order) and the nominal-only
    # ones; a cause added after the nominal-only ones (a higher order keeps the other causes'
    # test seeds) sits among the fit-mode ones here
    assert sorted(HIDDEN_CAUSES + NOMINAL_CAUSES) == sorted(CAUSES)
    assert HIDDEN_CAUSES == tuple(c for c in CAUSES if c not in NOMINAL_ONLY)
    assert NOMINAL_CAUSES == NOMINAL_ONLY


def test_generator_is_seeded_and_validates():
    a = _record("position_ripple", 1, duration=10.0)
    b = _record("position_ripple", 1, duration=10.0)
    np.testing.assert_array_equal(a.run.position, b.run.position)
    assert a.run.n_samples == 5000
    with pytest.raises(ValueError, match="cause"):
        hidden_effect_record(np.random.default_rng(0), cause="cogging")
    with pytest.raises(ValueError, match="duration"):
        hidden_effect_record(np.random.default_rng(0), duration=5.0)
    with pytest.raises(ValueError, match="Generator"):
        hidden_effect_record(0)


def test_generator_encoder_is_quantised():
    # reference: the paper actuator's load-side count, 2*pi/(2000*100) rad
    rec = _record("none", 2, duration=10.0)
    counts = rec.run.position / ENCODER_RESOLUTION
    np.testing.assert_allclose(counts, np.round(counts), atol=1e-6)


# ----------------------------------------------------------------------------- signals
def test_true_model_explains_noise_free_record():
    # noise-free recovery: the true model's equation error on a noise-free none record
    # is quantisation-limited; tolerance 5 % of the Coulomb level (RMS)
    rec = _record("none", 3, duration=20.0, noise=False)
    tr = torque_residual(rec.truth, rec.run)
    fc = rec.truth.friction.coulomb_pos
    assert np.sqrt(np.mean(tr.residual[tr.mask] ** 2)) == pytest.approx(tr.rms(), rel=1e-12)
    assert tr.rms() < 0.05 * fc


def test_true_model_replays_noise_free_record():
    # noise-free recovery: re-simulating the true model from the measured state
    # follows the encoder to within 20 counts RMS over 0.5 s windows (start-state
    # error from the velocity estimate grows linearly; a wrong model drifts far more)
    rec = _record("none", 4, duration=20.0, noise=False)
    sim = windowed_simulation(rec.truth, rec.run)
    pos = sim.rms().position
    assert pos < 20 * ENCODER_RESOLUTION
    wrong = JointModel(inertia=rec.truth.inertia, friction=rec.truth.friction.scaled(0.7))
    assert windowed_simulation(wrong, rec.run).rms().position > 2 * pos


# ----------------------------------------------------------------------------- hidden effects
def test_delay_and_ripple_estimates():
    # delay: a whole number of samples on the bench, recovered within the quarter-sample
    # grid step; ripple period within 1 % (the period grid refines to 1/(6*span) in
    # spatial frequency)
    rec = _record("time_delay", 20)
    d = diagnose(rec.run)
    assert d.extended.delay / rec.run.sample_time == pytest.approx(rec.magnitude["samples"],
                                                                   abs=0.25)
    rec = _record("position_ripple", 21)
    d = diagnose(rec.run)
    assert d.cause == "position_ripple"
    assert d.extended.friction.ripple_period == pytest.approx(rec.magnitude["period"], rel=0.01)
    assert "period" in d.evidence and "amplitude" in d.evidence


def test_paper_case_inertia_then_friction_scale():
    # the paper's aged actuator with the link: the nominal model misses the link inertia
    # (0.0046 kg*m^2) and a 0.95 friction scale; the forward selection names both
    from fricctl.controllers import Controller, sinusoid, step
    from fricctl.params import PAPER_LINK_INERTIA, paper_actuator
    from fricctl.simulate import simulate

    p = paper_actuator()
    nominal = JointModel(inertia=p.total_inertia, friction=Viscous(p.viscous) + Coulomb(p.coulomb))
    aged = p.with_link(PAPER_LINK_INERTIA)
    ctrl = Controller(kp=1.0, kd=0.05, reference=sinusoid(1.0, 0.5) + sinusoid(0.05, 0.11),
                      feedforward=step(0.0))
    res = simulate(aged, ctrl, duration=30.0, friction=nominal.friction.scaled(0.95),
                   noise_std=0.002, rng=np.random.default_rng(7))
    run = res.to_run()
    d1 = diagnose(run, nominal)
    assert d1.causes == ("inertia", "friction_scale"), d1.report()
    # reference: 0.002865 + 0.0046 kg*m^2 and the 0.95 scale; tolerances 3 % and 0.02
    assert d1.extended.inertia == pytest.approx(p.inertia + PAPER_LINK_INERTIA, rel=0.03)
    assert d1.extended.friction.scale == pytest.approx(0.95, abs=0.02)
    # diagnosed again with everything found, nothing is left
    assert diagnose(run, d1.extended).causes == ("none",)


# ----------------------------------------------------------------------------- results, input
def test_report_and_json():
    rec = _record("thermal_drift", 30, duration=20.0)
    d = diagnose(rec.run)
    out = json.loads(json.dumps(d.as_dict(), allow_nan=False))
    assert out["cause"] == "thermal_drift" and out["causes"] == ["thermal_drift"]
    step = out["steps"][0]
    assert step["cause"] == "thermal_drift" and step["score"] == pytest.approx(d.score)
    # the net score is the gross one less the measuring chain's estimated part of it
    # (selection.net_of_chain): (gross - chain) / (1 - chain)
    assert step["score"] == pytest.approx((step["gross"] - step["chain"]) / (1 - step["chain"]),
                                          abs=1e-12)
    assert step["torque_rms_after"] < step["torque_rms_before"]
    # every fit-mode candidate is scored once, best first
    assert sorted(r["cause"] for r in out["ranking"]) == sorted(FIT_MODE)
    scores = [r["score"] for r in out["ranking"]]
    assert scores == sorted(scores, reverse=True)
    assert out["gain"] == {k: getattr(d.gain, k) for k in (
        "torque_rms_before", "torque_rms_after", "simulation_rms_before", "velocity_rms_before",
        "simulation_rms_after", "velocity_rms_after")}
    assert out["extended"]["drift"] == d.extended.friction.drift != 0.0
    text = d.report()
    assert text.startswith("# Diagnosis: `thermal_drift`") and "Held-out gain" in text
    assert "| 1 | thermal_drift |" in text  # the steps table
    assert d.evidence in text and "friction level changes" in d.evidence
    # a last step stopped by a candidate above the line that cannot be told says so where it
    # gives that candidate's score (issue 21's pair [12102, 43, 1]: "backlash, removes 57.5 %"
    # alone read as if the naming line had stopped it); one below the line gives its score
    why = "the fitted gap (3.89 encoder counts) is at the lower end"
    over = dataclasses.replace(d, last_ranking=(("backlash", MIN_SCORE + 0.3),),
                               not_identifiable={"backlash": why})
    stop = next(s for s in over.report().splitlines() if s.startswith("Stopped"))
    assert stop.endswith(f"; not named: cannot be told on this record, because {why}."), stop
    under = dataclasses.replace(over, last_ranking=(("backlash", MIN_SCORE / 2),))
    stop = next(s for s in under.report().splitlines() if s.startswith("Stopped"))
    assert "not named" not in stop and stop.endswith("reaches the line)."), stop


def test_prediction_errors():
    # the same numbers as the two checks it combines (independent calls), and the true
    # model predicts better than one with 30 % too little friction
    rec = _record("none", 31, duration=10.0)
    e = prediction_errors(rec.truth, rec.run)
    assert e.torque_rms == pytest.approx(torque_residual(rec.truth, rec.run).rms(), rel=1e-12)
    sim = windowed_simulation(rec.truth, rec.run).rms()
    assert (e.simulation_rms, e.velocity_rms) == (sim.position, sim.velocity)
    assert all(math.isfinite(v) and v >= 0 for v in (e.torque_rms, e.simulation_rms, e.velocity_rms))
    wrong = JointModel(inertia=rec.truth.inertia, friction=rec.truth.friction.scaled(0.7))
    w = prediction_errors(wrong, rec.run)
    assert w.torque_rms > 2 * e.torque_rms and w.simulation_rms > e.simulation_rms


def test_bad_input():
    rec = _record("none", 32, duration=10.0)
    with pytest.raises(ValueError, match="Run"):
        diagnose(np.zeros(10))
    with pytest.raises(ValueError, match="folds"):
        diagnose(rec.run, folds=2)
    with pytest.raises(ValueError, match="JointModel"):
        diagnose(rec.run, model={"inertia": 1.0})
    with pytest.raises(ValueError, match="window"):
        diagnose(rec.run, window=-1.0)


def test_figures():
    import matplotlib

    matplotlib.use("Agg")
    from fricctl.figures import (plot_diagnosis, plot_residual, plot_residual_spectrum,
                                 plot_simulation)

    rec = _record("position_ripple", 33, duration=20.0)
    d = diagnose(rec.run)
    ax = plot_residual(d, "position", after=True)
    assert "position" in ax.get_xlabel() and "[rad]" in ax.get_xlabel()
    assert len(ax.lines) >= 2
    ax = plot_simulation(d, quantity="velocity")
    assert "rad/s" in ax.get_ylabel()
    ax = plot_residual_spectrum(d)
    assert "Hz" in ax.get_xlabel()
    fig = plot_diagnosis(d)
    assert len(fig.axes) == 6
    with pytest.raises(ValueError):
        plot_residual(d, "temperature")


# ----------------------------------------------------------------------------- EMPS
def test_emps_published_model(data_dir):
    from fricctl.datasets import emps

    est = emps(data_dir, kind="estimation").run
    val = emps(data_dir, kind="validation").run
    # published IDIM-LS model (EMPS_Description.pdf sec. 3.4)
    pub = JointModel(inertia=95.1089, friction=Viscous(203.5034) + Coulomb(20.3935), offset=-3.1648,
                     units="linear")
    d = diagnose(est, pub)
    # the ripple's periodogram searches only the periods the record resolves (two samples of
    # motion at the median sliding speed, 82.5 um per sample, and up): the 62 um alias the
    # whole periodogram peaked at (named before, issue 21, for a -0.1 % gain; then refused,
    # hiding the rest) is not tried; the ripple tried is one motor revolution, below the line
    assert "position_ripple" not in d.causes and "position_ripple" not in d.not_identifiable
    assert 0.10 < dict(d.last_ranking)["position_ripple"] < MIN_SCORE
    # the model's offset is removed to be judged (issue 21, item 4): the record supports a
    # viscous friction differing by direction instead (the published asymmetric model:
    # Fv+ 166.7, Fv- 240.4 N*s/m, EMPS sec. 3.4); the offset does not come back
    assert d.held == ("offset",) and d.causes == ("asymmetry",)
    assert d.origin == {"asymmetry": "found"} and d.extended.offset == 0.0
    # fit mode: the same causes
    d2 = diagnose(est)
    assert d2.causes == d.causes and not d2.held
    # and the verdict says what is left, both ways: not explained, the residual a function of
    # velocity (the presliding at reversals a careful analysis finds is not among the causes)
    for dd in (d, d2):
        assert not dd.explained and dd.verdict.residual_over_floor > 2
        assert dd.verdict.strongest == "velocity"
        fr = dd.extended.friction
        assert fr.viscous_neg > fr.viscous_pos
        # transfer to the PULSES file: the extension must not predict worse there
        before = prediction_errors(dd.baseline, val)
        after = prediction_errors(dd.extended, val)
        assert after.torque_rms < before.torque_rms


@pytest.mark.slow
def test_confusion_matrix_random_records():
    # >= 50 random records (cause drawn by the generator), >= 95 % named exactly as expected,
    # no false cause on `none`; seeds [6000, i] never looked at while building the issue-12
    # method.  Expected: the hidden cause when it weighs at least MIN_SCORE on its record
    # (HiddenEffectRecord.expected: a position load constant over the travel as an offset),
    # else nothing
    rows = []
    for i in range(55):
        rng = np.random.default_rng([6000, i])
        rec = hidden_effect_record(rng, nominal=bool(i % 5 == 4))
        expected = rec.expected()
        rows.append((rec.cause, expected, set(diagnose(rec.run, rec.nominal).causes) - {"none"}))
    correct = sum(e == n for _, e, n in rows)
    assert correct >= 0.95 * len(rows), rows
    assert all(not n for c, _, n in rows if c == "none"), rows


def test_on_baseline_must_be_callable():
    rec = hidden_effect_record(np.random.default_rng([2026, 78]), cause="none", duration=10.0)
    with pytest.raises(ValueError, match="on_baseline must be callable"):
        diagnose(rec.run, on_baseline=1)
