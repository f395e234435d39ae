"""What the record supports below the naming line (issue 21, item 4): ``Diagnosis.below_line``,
the motor revolution a period is compared with, and ``--motor-revolution``."""

import json
import math
import re
from dataclasses import replace

import numpy as np
import pytest
from scipy import stats

from fricctl.bench.hidden_effects import hidden_effect_record
from fricctl.cli import main
from fricctl.datasets import Run
from fricctl.diagnose import MIN_SCORE, diagnose
from fricctl.diagnose.verdict import SIGNIFICANCE, reduction_p


def _entry(d, cause):
    return next((e for e in d.below_line if e.cause == cause), None)


# ----------------------------------------------------------------------------- the test
def test_reduction_p_is_the_variance_ratio_test_of_the_two_mean_squares():
    # reference: the F distribution's survival function at the ratio of the mean squares
    # before and after, 1/(1 - share), each with dof degrees of freedom (scipy, independently
    # of the module); no reduction: p = 1; a larger share on the same dof: a smaller p
    assert reduction_p(0.0, 800.0) == 1.0 and reduction_p(-0.2, 800.0) == 1.0
    for share, dof in ((0.05, 4000.0), (0.16, 772.0), (0.3, 50.0)):
        assert reduction_p(share, dof) == pytest.approx(
            stats.f.sf(1.0 / (1.0 - share), dof, dof), rel=1e-12)
    # each mean square with its own count: F(dof before, dof after), told apart both ways round
    for share, d1, d2 in ((0.16, 772.0, 293.0), (0.16, 293.0, 772.0), (0.05, 4000.0, 2500.0)):
        assert reduction_p(share, d1, d2) == pytest.approx(
            stats.f.sf(1.0 / (1.0 - share), d1, d2), rel=1e-12)
    assert reduction_p(0.16, 772.0, 293.0) != pytest.approx(reduction_p(0.16, 293.0, 772.0), rel=1e-3)
    ps = [reduction_p(s, 800.0) for s in (0.02, 0.1, 0.18)]
    assert ps[0] > ps[1] > ps[2]
    assert math.isnan(reduction_p(0.1, math.nan))
    # the limits the docstring and docs/limits.md state: p = 0.01 at 15 % for 800 degrees of
    # freedom, at 7 % for 4000
    assert reduction_p(0.14, 800.0) > 0.01 > reduction_p(0.16, 800.0)
    assert reduction_p(0.065, 4000.0) > 0.01 > reduction_p(0.075, 4000.0)


# ----------------------------------------------------------------------------- generator
#: Records of a weak ripple, (seed, strength): its term removes less than the naming line on
#: each (asserted below: the test is of what is reported below the line).
WEAK = (((2121, 2), 0.05), ((2121, 1), 0.08))


@pytest.mark.parametrize("seed, strength", WEAK)
def test_weak_ripple_is_reported_below_the_line_with_its_period(seed, strength):
    rec = hidden_effect_record(np.random.default_rng(list(seed)), cause="position_ripple",
                               strength=strength, duration=20.0)
    d = diagnose(rec.run, motor_revolution=2 * math.pi)
    assert "position_ripple" not in d.causes  # below the naming line: not named
    e = _entry(d, "position_ripple")
    assert e is not None and e.score < MIN_SCORE
    assert e.supported and e.plausible and e.p_value < SIGNIFICANCE and e.reason == ""
    # the hidden period within 1 %: the period grid's finest step around a peak is
    # 1/(12*span) in spatial frequency, far under 1 % of a period of a few % of the travel
    assert e.parameters["ripple_period"] == pytest.approx(rec.magnitude["period"], rel=0.01)
    assert e.parameters["ripple_amplitude"] > 0
    # the period compared with the revolution given (2*pi rad: a direct drive)
    assert e.motor_revolutions["ripple_period"] == pytest.approx(
        e.parameters["ripple_period"] / (2 * math.pi), rel=1e-12)
    assert math.isfinite(e.simulation_score)  # computed for a supported term
    # said in the JSON and the report
    out = d.as_dict()
    j = next(x for x in out["below_line"] if x["cause"] == "position_ripple")
    assert j["supported"] is True and j["parameters"]["ripple_period"] == e.parameters["ripple_period"]
    assert out["motor_revolution"] == pytest.approx(2 * math.pi)
    rep = d.report()
    assert "## Supported by the data but below the naming line" in rep
    assert "`position_ripple`" in rep.split("## Supported by the data but below")[1]


def test_effect_free_records_have_no_supported_entry_below_the_line():
    # records without any effect: nothing named and nothing "supported" below the line;
    # what lowers the held-out residual at all is reported as not supported, with the reason
    for i in range(3):
        rec = hidden_effect_record(np.random.default_rng([2122, i]), cause="none", duration=20.0)
        d = diagnose(rec.run)
        assert d.causes == ("none",)
        assert not any(e.supported for e in d.below_line), [e.as_dict() for e in d.below_line]
        for e in d.below_line:
            assert e.reason and e.score < MIN_SCORE
        if d.below_line:
            assert "## Below the naming line, not supported" in d.report()
            assert "## Supported by the data but below" not in d.report()


def test_entries_are_of_the_last_step_only_and_sorted():
    # the below-line entries are candidates of the step that named nothing (never a named
    # cause, never one reported as not identifiable), supported first, then by net share
    rec = hidden_effect_record(np.random.default_rng([2121, 2]), cause="position_ripple",
                               strength=1.0, duration=20.0)
    d = diagnose(rec.run, motor_revolution=2 * math.pi)
    # a named ripple's period is given in motor revolutions too (period / 2*pi), and only
    # where the revolution is known
    assert d.causes == ("position_ripple",)
    turns = d.extended.friction.ripple_period / (2 * math.pi)
    assert f"its period is {turns:#.3g} motor revolutions" in d.evidence
    assert "motor revolutions" not in diagnose(rec.run).evidence
    last = {c for c, _ in d.last_ranking}
    for e in d.below_line:
        assert e.cause in last and e.cause not in d.causes
        assert e.cause not in d.not_identifiable
    supported = [e.supported for e in d.below_line]
    assert supported == sorted(supported, reverse=True)  # the supported ones first
    rest = [-e.score for e in d.below_line if not e.supported]
    assert rest == sorted(rest)  # in the order taken, then the others by net share


# ----------------------------------------------------------------------------- the revolution
@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan, math.inf, "2 mm"])
def test_motor_revolution_is_checked(bad):
    rec = hidden_effect_record(np.random.default_rng([2121, 0]), cause="none", duration=10.0)
    with pytest.raises(ValueError, match="motor_revolution"):
        diagnose(rec.run, motor_revolution=bad)
    with pytest.raises(ValueError, match="motor_revolution"):
        Run(t=rec.run.t, torque=rec.run.torque, position=rec.run.position, motor_revolution=bad)


@pytest.mark.parametrize("bad", ["0", "-2.5e-3", "nan", "inf"])
def test_cli_motor_revolution_bad_value_exits_2(tmp_path, capsys, bad):
    rec = hidden_effect_record(np.random.default_rng([2121, 0]), cause="none", duration=10.0)
    path = tmp_path / "run.csv"
    rec.run.to_csv(path)
    assert main(["diagnose", str(path), f"--motor-revolution={bad}"]) == 2
    cap = capsys.readouterr()
    assert cap.out == "" and len(cap.err.strip().splitlines()) == 1
    assert "--motor-revolution" in cap.err


def test_cli_motor_revolution_reaches_the_json(tmp_path, capsys):
    rec = hidden_effect_record(np.random.default_rng([2121, 0]), cause="none", duration=10.0)
    path = tmp_path / "run.csv"
    rec.run.to_csv(path)
    assert main(["diagnose", str(path), "--json", "--motor-revolution", "6.25"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["motor_revolution"] == 6.25 and isinstance(out["below_line"], list)


# ----------------------------------------------------------------------------- EMPS
def test_emps_ripple_of_one_motor_revolution_with_and_without_the_published_model(data_dir):
    # issue 21, item 4: the same causes with and without the published IDIM-LS model (Janot,
    # Gautier & Brunot 2019: M 95.1089 kg, Fv 203.5034 N*s/m, Fc 20.3935 N, offset -3.1648 N),
    # and below the naming line the same ripple, its period within 2 % of one motor
    # revolution (the screw's lead, 2.5 mm: the data folder's README)
    from fricctl.datasets import EMPS_MOTOR_REVOLUTION, emps
    from fricctl.friction import Coulomb, Viscous
    from fricctl.plant import JointModel

    est = emps(data_dir, kind="estimation").run
    assert est.motor_revolution == EMPS_MOTOR_REVOLUTION == 2.5e-3
    pub = JointModel(inertia=95.1089, friction=Viscous(203.5034) + Coulomb(20.3935),
                     offset=-3.1648, units="linear", source="EMPS IDIM-LS (published)")
    fit, model = diagnose(est), diagnose(est, pub)
    assert fit.causes == model.causes
    periods = []
    for d in (fit, model):
        e = _entry(d, "position_ripple")
        assert e is not None, [x.as_dict() for x in d.below_line]
        # reported with its period, but not supported: with each residual's own effective
        # degrees of freedom (the ripple taken out, the rest correlates longer: about 300
        # against 800) the F test cannot tell its 16 % at p < 0.01 (measured 0.02-0.04)
        assert not e.supported and SIGNIFICANCE <= e.p_value < 0.1 and e.dof_after < e.dof
        assert 0.10 < e.score < MIN_SCORE
        assert e.parameters["ripple_period"] == pytest.approx(2.5e-3, rel=0.02)
        assert e.motor_revolutions["ripple_period"] == pytest.approx(1.0, rel=0.02)
        periods.append(e.parameters["ripple_period"])
        assert "motor revolutions" in d.report()
        json.dumps(d.as_dict(), allow_nan=False)
    assert periods[0] == pytest.approx(periods[1], rel=1e-9)  # the same period both ways


# ----------------------------------------------------------------------------- review findings
def _review_record(i, cause, strength, axis, seed=779, **kw):
    return hidden_effect_record(np.random.default_rng([seed, i]), cause=cause, strength=strength,
                                duration=20.0, excitation=kw.get("excitation", "closed_loop"),
                                sample_time=kw.get("sample_time", 0.001), axis=axis,
                                **{k: v for k, v in kw.items()
                                   if k not in ("excitation", "sample_time")})


def test_competing_candidates_are_not_all_supported():
    # a weak drag (seed [779, 20], the review's): backlash, drag and stribeck each lowered the
    # residual on their own; backlash re-simulated worse and stribeck had nothing left once
    # drag was in.  Only the hidden drag is supported; no evidence prints a mean of nothing
    rec = _review_record(20, "drag", 0.15, "rotary")
    d = diagnose(rec.run)
    assert d.causes == ("none",)
    assert [e.cause for e in d.below_line if e.supported] == ["drag"]
    for e in d.below_line:
        assert not re.search(r"\bnan\b", e.sentence("N*m", "rad"), re.I), e.sentence()


def test_a_term_that_resimulates_worse_is_not_supported():
    # a weak compliance (seed [779, 6], linear): the term lowers the torque residual but its
    # model re-simulates the held-out windows worse; a named cause would be rejected for it
    rec = _review_record(6, "compliance", 0.05, "linear")
    d = diagnose(rec.run)
    e = _entry(d, "compliance")
    assert e is not None and not e.supported and "re-simulates" in e.reason
    assert not any(x.supported for x in d.below_line if x.simulation_score <= 0)


def test_a_share_at_the_line_is_net_of_the_measured_chain():
    # an effect-free, mostly stuck record at 200 Hz (seed [777, 202]): a candidate whose gross
    # share reached the line had its chain share measured by the selection; it is reported
    # net of it (here below zero: left out), never as "gross, not measured" at 21 %
    rec = _review_record(202, "none", 1.0, "rotary", seed=777, excitation="stuck",
                         sample_time=0.005, sensors="fixed")
    d = diagnose(rec.run)
    assert d.causes == ("none",) and not any(e.supported for e in d.below_line)
    for e in d.below_line:
        assert e.score < MIN_SCORE and e.score > 0
        if e.gross >= MIN_SCORE:
            assert math.isfinite(e.chain)


def test_a_candidate_reaching_the_line_in_a_later_round_is_reported(monkeypatch):
    # backlash + offset (seed [881, 70], the second review's): the selection names nothing
    # (backlash re-simulates no better); below the line the offset is taken, and then the
    # compliance term removes more than the line of what is left -- reported (with why it is
    # not supported), not dropped as before.  The record was found with the compliance's grid
    # alone: its refined spring (issue 21, a later session) goes to the damping's bound here and
    # is not told at all, so the grid's is restored for this test of the rounds
    from fricctl.diagnose import api

    grid_only = api.causes.candidates

    def candidates(nominal=False):
        return tuple(replace(c, refine=None, per_step=False) if c.name == "compliance" else c
                     for c in grid_only(nominal=nominal))

    monkeypatch.setattr(api.causes, "candidates", candidates)
    rec = hidden_effect_record(np.random.default_rng([881, 70]), cause=("backlash", "offset"),
                               strength=0.1, duration=40.0)
    d = diagnose(rec.run)
    assert d.causes == ("none",)
    assert [e.cause for e in d.below_line][:1] == ["offset"] and d.below_line[0].supported
    e = _entry(d, "compliance")
    assert e is not None and e.score >= MIN_SCORE and not e.supported and e.reason
    assert "at the naming line only once the entries taken below it" in e.sentence()
