"""Tests for ``fricctl design`` (fricctl/cli/design.py)."""

import json
import math

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
    assert obj["kp"] == ref.kp and obj["kd"] == ref.kd
    assert obj["inertia"] == ref.inertia and obj["viscous"] == ref.viscous
    assert obj["requested"] == {"rise_time": 0.22, "damping": 0.5, "priority": None}
    for key in ("achieved", "sampled"):
        assert set(obj[key]) == {"rise_time", "damping", "overshoot_percent", "settling_time"}
    assert obj["achieved"]["rise_time"] == pytest.approx(0.22, rel=0.01)  # step_info, 1 %
    assert obj["rise_time_definition"] == "0-100"


def test_p_json_kd_zero_and_text(capsys):
    code, out, _ = run(capsys, "p", "--rise-time", "0.2", "--damping", "0.3", "--json")
    assert code == 0
    obj = json.loads(out)
    assert obj["kd"] == 0 and obj["law"] == "p"
    ref = design_p(paper_actuator(), rise_time=0.2, damping=0.3)
    assert obj["kp"] == ref.kp
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


def test_10_90_definition(capsys):
    code, out, _ = run(capsys, "pd", "--rise-time", "0.3", "--damping", "1.2", "--json")
    assert code == 0
    obj = json.loads(out)
    assert obj["rise_time_definition"] == "10-90"
    assert obj["achieved"]["overshoot_percent"] == 0.0  # overdamped: monotone step
    assert math.isfinite(obj["achieved"]["rise_time"])


@pytest.mark.parametrize("argv,match", [
    (["pd", "--rise-time", "0.3", "--damping", "0"], "damping must be > 0"),
    (["pd", "--rise-time", "nan", "--damping", "0.5"], "rise_time must be finite"),
    (["pd", "--rise-time", "1", "--damping", "0.1"], "negative Kd"),
    (["pd", "--damping", "0.5"], "needs both"),
    (["pd", "--rise-time", "0.3", "--damping", "1.2", "--rise-time-definition", "0-100"],
     "10-90"),
    (["pd", "--rise-time", "0.3", "--damping", "0.5", "--priority", "damping"], "p only"),
    (["p"], "needs rise_time, damping, or both"),
])
def test_invalid_input_exits_2_with_one_line(capsys, argv, match):
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == ""
    assert err.startswith("fricctl design: error:") and match in err
    assert err.count("\n") == 1
