import json

import numpy as np
import pytest

from fricctl.cli import main
from fricctl.datasets import Run


def test_simulate_pd_json_and_csv(tmp_path, capsys):
    csv = tmp_path / "run.csv"
    png = tmp_path / "run.png"
    code = main(["simulate", "--controller", "pd", "--rise-time", "0.3", "--damping", "0.9",
                 "--reference", "step:0.5236", "--duration", "2", "--csv", str(csv),
                 "--figure", str(png), "--json"])
    assert code == 0
    captured = capsys.readouterr()
    out = json.loads(captured.out)
    # the paper's 0.3 s / 0.9 design warns (ill-conditioned 0-100 % rise time): one line on stderr
    assert captured.err.count("\n") == 1 and "warning: sampled loop" in captured.err
    # PD without compensation sticks inside the +-Fs/Kp band (8.5 deg for Kp = 1.213)
    assert out["stuck_at_end"] and 0 < out["steady_state_error_deg"] < 8.5
    run = Run.from_csv(csv)
    assert run.n_samples == 1000 and run.reference is not None
    assert png.stat().st_size > 1000


def test_open_loop_below_breakaway_does_not_move(capsys):
    assert main(["simulate", "--torque", "constant:0.17", "--duration", "0.5", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["max_abs_position_rad"] == 0.0


def test_output_path_errors_are_one_line(tmp_path, capsys):
    # an output path that is a directory, or below a file: one line, exit 2, no traceback
    (tmp_path / "afile").write_text("x")
    for argv in (["simulate", "--torque", "step:0.2", "--duration", "0.1", "--csv", str(tmp_path)],
                 ["simulate", "--torque", "step:0.2", "--duration", "0.1", "--figure",
                  str(tmp_path / "afile" / "x.png")]):
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "error:" in err


@pytest.mark.parametrize("argv,words", [
    (["simulate", "--torque", "ramp:1"], "unknown signal"),
    (["simulate", "--torque", "sinusoid:1"], "takes 2"),
    (["simulate", "--torque", "step:x"], "numbers"),
    (["simulate"], "needs --torque"),
    (["simulate", "--controller", "pd", "--reference", "step:0.1"], "--rise-time"),
    (["simulate", "--torque", "step:0.1", "--duration", "nan"], "--duration"),
    (["simulate", "--controller", "p", "--kp", "1", "--compensation", "nn"], "--net"),
    (["simulate", "--torque", "step:0.1", "--kp", "3"], "--kp has no effect"),
    (["simulate", "--controller", "p", "--kp", "5", "--kd", "3"], "--kd has no effect"),
    (["simulate", "--controller", "pd", "--kp", "5"], "needs --kd"),
    (["simulate", "--controller", "pd", "--kp", "5", "--kd", "0.1", "--rise-time", "0.3"], "--rise-time"),
    (["simulate", "--torque", "step:0.1", "--scale", "3"], "--scale has no effect"),
    (["simulate", "--torque", "step:0.1", "--net", "x.json"], "--net has no effect"),
    (["simulate", "--controller", "p", "--kp", "1", "--torque", "step:0.1"], "--torque has no effect"),
])
def test_bad_input_one_line_exit_2(argv, words, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert words in err and err.count("\n") == 1


def test_binary_file_and_negative_seed_are_one_line(tmp_path, capsys):
    binary = tmp_path / "bin.csv"
    binary.write_bytes(bytes(range(128, 256)))
    for argv, words in ((["identify", str(binary)], "not a UTF-8 text file"),
                        (["train", str(binary), "--out", str(tmp_path / "n.json")], "not a UTF-8 text file"),
                        (["diagnose", str(binary)], "not a UTF-8 text file")):
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert words in err and err.count("\n") == 1
    pats = tmp_path / "p.csv"
    pats.write_text("tm,omega,friction\n0.1,0.5,0.2\n0.2,1,0.3\n")
    assert main(["train", str(pats), "--out", str(tmp_path / "n.json"), "--seed", "-1"]) == 2
    assert "--seed must be >= 0" in capsys.readouterr().err
