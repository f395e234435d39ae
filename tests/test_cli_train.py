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
    assert (tmp_path / "net.h").is_file()


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


@pytest.fixture()
def lattice_patterns_csv(tmp_path):
    """Patterns as `fricctl patterns` writes them: at_rest column and the velocity quantum."""
    from fricctl.datasets import FrictionPatterns, write_patterns

    q = 0.0157
    pats = smooth_friction_patterns(np.random.default_rng(4), n_sliding=500, n_stuck=250)
    om = np.round(pats.omega / q) * q          # the loop's velocity lattice
    path = tmp_path / "lattice.csv"
    write_patterns(path, FrictionPatterns(tm=pats.tm, omega=om, friction=pats.friction,
                                          at_rest=om == 0, units="rotary", velocity_quantum=q,
                                          meta={}))
    return path


def test_train_fricctl_pipeline_certifies_its_gain_band(lattice_patterns_csv, tmp_path, capsys):
    out, csrc = tmp_path / "n.json", tmp_path / "comp.c"
    assert main(["train", str(lattice_patterns_csv), "--pipeline", "fricctl", "--gain-band",
                 "0.95,0.98", "--out", str(out), "--c-source", str(csrc), "--json"]) == 0
    rep = json.loads(capsys.readouterr().out)
    net = load_net(out)
    # the certificate is re-checked on the saved net by finite differences at rest
    tm = np.linspace(-rep["certificate"]["rest_torque"], rep["certificate"]["rest_torque"], 1001)
    g = (net(tm + 1e-6, 0 * tm) - net(tm - 1e-6, 0 * tm)) / 2e-6
    assert 0.95 - 1e-5 <= g.min() and g.max() <= 0.98 + 1e-5
    assert rep["pipeline"] == "fricctl" and rep["trainer"] == "certified"
    assert rep["certificate"]["passed"] and rep["certificate"]["gain_band"] == [0.95, 0.98]
    assert rep["viscous_removed"] > 0 and net.metadata["viscous_removed"] == rep["viscous_removed"]
    assert (tmp_path / "comp.h").is_file() and "compensation" in csrc.read_text()


@pytest.mark.parametrize("args,message", [
    (["--pipeline", "fricctl", "--gain-band", "0.9"], "--gain-band must be LO,HI"),
    (["--pipeline", "fricctl", "--gain-band", "0.95,1.0"], "lo <= hi < 1"),
    (["--pipeline", "fricctl", "--trainer", "casadi"], "does not go with --pipeline"),
    (["--gain-band", "0.9,0.95"], "go with --pipeline"),
])
def test_train_pipeline_arguments_are_checked(lattice_patterns_csv, tmp_path, capsys, args, message):
    assert main(["train", str(lattice_patterns_csv), "--out", str(tmp_path / "n.json")] + args) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1


def test_train_refuses_to_clobber(patterns_csv, lattice_patterns_csv, tmp_path, capsys):
    path, _ = patterns_csv
    # a file without the at_rest column and the quantum cannot feed the fricctl pipeline
    assert main(["train", str(path), "--pipeline", "fricctl", "--out", str(tmp_path / "a.json")]) == 2
    assert "velocity_quantum" in capsys.readouterr().err
    assert main(["train", str(path), "--out", str(path)]) == 2            # its own input
    assert "is an input" in capsys.readouterr().err
    out = tmp_path / "b.json"
    out.write_text("keep me")
    assert main(["train", str(path), "--out", str(out), "--restarts", "1"]) == 2
    assert out.read_text() == "keep me" and "--force" in capsys.readouterr().err
    assert main(["train", str(path), "--out", str(out), "--restarts", "1", "--force"]) == 0
    assert load_net(out).hidden == 4


def test_train_pipeline_shows_its_trainers_progress_when_asked(lattice_patterns_csv, tmp_path, capsys):
    argv = ["train", str(lattice_patterns_csv), "--pipeline", "fricctl", "--gain-band", "0.95,0.98"]
    assert main([*argv, "--out", str(tmp_path / "a.json"), "--progress", "on"]) == 0
    err = capsys.readouterr().err
    assert "attempt" in err                  # the certified trainer's step, on stderr
    assert main([*argv, "--out", str(tmp_path / "b.json"), "--progress", "off"]) == 0
    assert capsys.readouterr().err == ""
