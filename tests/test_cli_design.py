"""Tests for ``fricctl design`` (fricctl/cli/design.py)."""

import json
import math

import numpy as np

import pytest

from fricctl.cli import main
from fricctl.design import design_p, design_pd
from fricctl.params import paper_actuator


def run(capsys, *argv):
    code = main(["design", *argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_pd_json_matches_library(capsys):
    code, out, err = run(capsys, "pd", "--rise-time", "0.22", "--damping", "0.5", "--link",
                         "--json")
    assert code == 0
    obj = json.loads(out)
    ref = design_pd(paper_actuator().with_link(), rise_time=0.22, damping=0.5)
    # same computation through the CLI: identical numbers (exact)
    assert obj["kp"] == {"value": ref.kp, "unit": "N*m/rad"}
    assert obj["kd"] == {"value": ref.kd, "unit": "N*m*s/rad"}
    assert obj["inertia"] == {"value": ref.inertia, "unit": "kg*m^2"}
    assert obj["viscous"] == {"value": ref.viscous, "unit": "N*m*s/rad"}
    assert obj["requested"] == {"rise_time": {"value": 0.22, "unit": "s"},
                                "damping": {"value": 0.5, "unit": "-"}, "priority": None}
    for key in ("achieved", "sampled"):
        assert set(obj[key]) == {"rise_time", "damping", "overshoot_percent", "settling_time"}
        assert {k: m["unit"] for k, m in obj[key].items()} == {
            "rise_time": "s", "damping": "-", "overshoot_percent": "%", "settling_time": "s"}
    assert obj["achieved"]["rise_time"]["value"] == pytest.approx(0.22, rel=0.01)  # step_info, 1 %
    assert obj["rise_time_definition"] == "0-100"


def test_p_json_kd_zero_and_text(capsys):
    code, out, _ = run(capsys, "p", "--rise-time", "0.2", "--damping", "0.3", "--json")
    assert code == 0
    obj = json.loads(out)
    assert obj["kd"]["value"] == 0 and obj["law"] == "p"
    ref = design_p(paper_actuator(), rise_time=0.2, damping=0.3)
    assert obj["kp"]["value"] == ref.kp
    code, out, _ = run(capsys, "p", "--damping", "0.4")
    assert code == 0
    # Kp = b^2/(4 I zeta^2) (closed form), printed with 6 significant digits
    p = paper_actuator()
    assert f"Kp = {p.viscous**2 / (4 * p.inertia * 0.16):.6g}" in out


def test_warning_goes_to_stderr_in_json_mode(capsys):
    code, out, err = run(capsys, "pd", "--rise-time", "0.02", "--damping", "0.7", "--json")
    assert code == 0
    obj = json.loads(out)
    assert obj["warnings"] and "sampled loop" in err


def test_warning_goes_to_stderr_in_text_mode(capsys):
    # audit A 12: design's text mode printed its warnings on stdout only
    code, out, err = run(capsys, "pd", "--rise-time", "0.02", "--damping", "0.7")
    assert code == 0 and "warning" not in out and "Ts=0.002 s" in out
    lines = err.splitlines()
    assert len(lines) == 2 and all(x.startswith("fricctl design: warning: sampled loop (Ts = "
                                                "0.002 s)") for x in lines), err
    from fricctl.design import DesignWarning

    with pytest.warns(DesignWarning):
        d = design_pd(paper_actuator(), rise_time=0.02, damping=0.7)
    assert d.report() == d.report(with_warnings=False) + "".join(
        f"\n  warning: {w}" for w in d.warnings)  # the library's report keeps them


def test_10_90_definition(capsys):
    code, out, _ = run(capsys, "pd", "--rise-time", "0.3", "--damping", "1.2", "--json")
    assert code == 0
    obj = json.loads(out)
    assert obj["rise_time_definition"] == "10-90"
    assert obj["achieved"]["overshoot_percent"]["value"] == 0.0  # overdamped: monotone step
    assert math.isfinite(obj["achieved"]["rise_time"]["value"])


def test_rise_time_definition_help_says_what_the_command_does(capsys):
    # issue 25: the help said "required for >= 1" but --damping 1.2 runs without it (and takes
    # 10-90, test_10_90_definition); the help now states that default and the refusal of 0-100
    assert main(["design", "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "10-90 for damping >= 1" in text and "required for >= 1" not in text
    assert "0-100 and peak (the time of the first peak, the consistent bench's reading) are refused for damping >= 1" in text


@pytest.mark.parametrize("argv,match", [
    (["pd", "--rise-time", "0.3", "--damping", "0"], "damping must be > 0"),
    (["pd", "--rise-time", "nan", "--damping", "0.5"], "rise_time must be finite"),
    (["pd", "--rise-time", "1", "--damping", "0.1"], "negative Kd"),
    (["pd", "--damping", "0.5"], "needs both"),
    (["pd", "--rise-time", "0.3", "--damping", "1.2", "--rise-time-definition", "0-100"],
     "10-90"),
    (["pd", "--rise-time", "0.3", "--damping", "1.2", "--rise-time-definition", "peak"],
     "first peak does not exist"),
    (["pd", "--rise-time", "0.3", "--damping", "0.5", "--priority", "damping"], "p only"),
    (["p"], "needs rise_time, damping, or both"),
])
def test_invalid_input_exits_2_with_one_line(capsys, argv, match):
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == ""
    assert err.startswith("fricctl design: error:") and match in err
    assert err.count("\n") == 1


# -- --model: your own actuator ------------------------------------------------------------
def _model_file(tmp_path, **kw):
    from fricctl.friction import Coulomb, Viscous
    from fricctl.plant import JointModel

    args = dict(inertia=95.1089, friction=(Viscous(203.5034) + Coulomb(20.3935)).model(),
                units="linear", sample_time=0.001)
    args.update(kw)
    return JointModel(**args).save(tmp_path / "axis.json")


def test_pd_on_a_linear_model(tmp_path, capsys):
    path = _model_file(tmp_path)
    code, out, _ = run(capsys, "pd", "--model", str(path), "--rise-time", "0.05", "--damping", "0.7")
    assert code == 0
    # closed form: wn = (pi - acos(zeta)) / (tr sqrt(1 - zeta^2)), Kp = M wn^2, Kd = 2 zeta wn M - b
    wn = (math.pi - math.acos(0.7)) / (0.05 * math.sqrt(1 - 0.49))
    kp, kd = 95.1089 * wn ** 2, 2 * 0.7 * wn * 95.1089 - 203.5034
    assert f"I = 95.1089 kg, b = 203.503 N*s/m" in out
    assert f"Kp = {kp:.6g} N/m, Kd = {kd:.6g} N*s/m" in out
    assert "Ts=0.001 s" in out
    code, out, _ = run(capsys, "pd", "--model", str(path), "--rise-time", "0.05", "--damping", "0.7",
                       "--json")
    obj = json.loads(out)
    assert obj["units"] == "linear" and obj["sample_time"] == {"value": 0.001, "unit": "s"}
    assert obj["kp"]["value"] == pytest.approx(kp, rel=1e-12) and obj["kp"]["unit"] == "N/m"
    assert obj["kd"]["value"] == pytest.approx(kd, rel=1e-12) and obj["kd"]["unit"] == "N*s/m"
    assert obj["inertia"]["unit"] == "kg"


def test_model_viscous_is_the_mean_of_both_directions(tmp_path, capsys):
    from fricctl.friction import FrictionModel

    # EMPS's direction-dependent fit (data README): b+ = 166.7061, b- = 240.4236 N*s/m
    path = _model_file(tmp_path, friction=FrictionModel(viscous_pos=166.7061, viscous_neg=240.4236))
    code, out, _ = run(capsys, "p", "--model", str(path), "--damping", "0.5", "--json")
    assert code == 0 and json.loads(out)["viscous"]["value"] == pytest.approx((166.7061 + 240.4236) / 2)


@pytest.mark.parametrize("kw,argv,match", [
    (dict(sample_time=None), [], "sample_time: the model has none"),
    # audit A 4: a sample time too short for the check names the model's value it concerns
    (dict(sample_time=1e-8), [], "sample_time: checking this design on the sampled loop needs"),
    ({}, ["--link"], "--link has no effect with --model"),
])
def test_model_errors_one_line(tmp_path, capsys, kw, argv, match):
    path = _model_file(tmp_path, **kw)
    code, out, err = run(capsys, "pd", "--model", str(path), "--rise-time", "0.05",
                         "--damping", "0.7", *argv)
    assert code == 2 and out == "" and match in err and err.count("\n") == 1


def test_shipped_paper_model_designs_like_the_paper_actuator(capsys):
    from fricctl.data import paper_actuator_file

    _, a, _ = run(capsys, "pd", "--rise-time", "0.22", "--damping", "0.5", "--json")
    _, b, _ = run(capsys, "pd", "--rise-time", "0.22", "--damping", "0.5", "--json",
                  "--model", str(paper_actuator_file()))
    assert json.loads(a) == json.loads(b)


def test_the_peak_reading_of_rise_time(capsys):
    """--rise-time-definition peak (the consistent bench's reading): the time of the first peak
    of the designed loop is the requested rise time, as python-control's step_info reads it."""
    import control

    from fricctl.cli.design import RISE_TIME_CHOICES
    from fricctl.design.second_order import RISE_TIME_DEFINITIONS

    assert set(RISE_TIME_CHOICES) == set(RISE_TIME_DEFINITIONS)
    code, out, err = run(capsys, "pd", "--rise-time", "0.2", "--damping", "0.5",
                         "--rise-time-definition", "peak", "--json")
    assert code == 0 and err == ""
    d = json.loads(out)
    assert d["rise_time_definition"] == "peak"
    kp, kd, i, b = (d[k]["value"] for k in ("kp", "kd", "inertia", "viscous"))
    loop = control.tf([kp], [i, b + kd, kp])
    peak = control.step_info(loop, T=np.linspace(0.0, 2.0, 200001))["PeakTime"]
    assert peak == pytest.approx(0.2, rel=1e-3)
def test_a_sampled_step_without_a_peak_is_said_so(capsys):
    """auditC item 5: the sampled loop of a 0.1 s / 0.9 design never overshoots (its slowest pole
    is real), so it has no peak time; the warning said 'rise time nan s differs ...'."""
    code, out, err = run(capsys, "pd", "--rise-time", "0.1", "--damping", "0.9",
                         "--rise-time-definition", "peak", "--json")
    assert code == 0
    d = json.loads(out)
    assert d["sampled"]["rise_time"]["value"] is None
    assert d["sampled"]["overshoot_percent"]["value"] == 0
    assert "nan" not in err and "has no peak" in err
    assert any("has no peak" in w for w in d["warnings"])


