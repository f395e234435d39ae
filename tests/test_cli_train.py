"""Tests of ``fricctl train``."""

import json

import numpy as np
import pytest

from fricctl.cli import main
from fricctl.nn import fit_percent, load_net, smooth_friction_patterns


@pytest.fixture()
def patterns_csv(tmp_path):
    pats = smooth_friction_patterns(np.random.default_rng(0), n_sliding=300, n_stuck=0)
    tm, om, f = pats.tm, pats.omega, pats.friction
    path = tmp_path / "patterns.csv"
    # columns in a different order than tm,omega,friction: read by name
    np.savetxt(path, np.column_stack([om, f, tm]), delimiter=",", header="omega,friction,tm",
               comments="", fmt="%.17g")
    return path, (tm, om, f)


def test_train_casadi_writes_net_and_prints_fit(patterns_csv, tmp_path, capsys):
    path, (tm, om, f) = patterns_csv
    out = tmp_path / "net.json"
    csrc = tmp_path / "net.c"
    assert main(["train", str(path), "--out", str(out), "--seed", "1", "--restarts", "1",
                 "--c-source", str(csrc), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    net = load_net(out)
    # reference: the fit recomputed from the saved net (noise-free smooth law, > 99 %)
    assert report["fit"]["fit_percent"] == pytest.approx(fit_percent(f, net(tm, om)), rel=1e-12)
    assert report["fit"]["fit_percent"] > 99.0
    assert report["hidden"] == 4 and report["n_patterns"] == tm.size
    assert net.metadata["seed"] == 1 and net.metadata["trainer"] == "casadi"
    assert report["envelope"]["tm"] == [tm.min(), tm.max()]
    assert "double fricctl_friction_net(double tm, double omega, int clip)" in csrc.read_text()


def test_train_backprop_text_output(patterns_csv, tmp_path, capsys):
    path, _ = patterns_csv
    out = tmp_path / "bp.json"
    assert main(["train", str(path), "--out", str(out), "--trainer", "backprop",
                 "--epochs", "20", "--hidden", "3"]) == 0
    text = capsys.readouterr().out
    assert "fit" in text and "R^2" in text and "backprop" in text
    net = load_net(out)
    assert net.hidden == 3 and net.metadata["epochs"] == 20


@pytest.mark.parametrize("content, message", [
    ("tm,omega,torque\n1,2,3\n4,5,6\n", "unknown column"),
    ("tm,omega\n1,2\n3,4\n", "header"),
    ("tm,omega,friction\n1,2,x\n4,5,6\n", "line 2"),
    ("tm,omega,friction\n1,2,3\n4,nan,6\n", "NaN"),
    ("tm,omega,friction\n1,2,3\n4,5\n", "fields"),
    ("tm,omega,friction\n1,2,3\n", "at least 2"),
    ("", "empty"),
])
def test_bad_patterns_give_one_line_and_exit_2(tmp_path, capsys, content, message):
    path = tmp_path / "bad.csv"
    path.write_text(content)
    assert main(["train", str(path), "--out", str(tmp_path / "n.json")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err and err.startswith("fricctl train: error:")
    assert not (tmp_path / "n.json").exists()


def test_missing_file_and_bad_option_exit_2(patterns_csv, tmp_path, capsys):
    path, _ = patterns_csv
    assert main(["train", str(tmp_path / "absent.csv"), "--out", str(tmp_path / "n.json")]) == 2
    assert "absent.csv" in capsys.readouterr().err
    assert main(["train", str(path), "--out", str(tmp_path / "n.json"), "--hidden", "0"]) == 2
    assert "hidden" in capsys.readouterr().err
