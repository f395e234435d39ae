import json

import numpy as np
import pytest

from fricctl.cli import main
from fricctl.datasets import Run


def test_simulate_pd_json_and_csv(tmp_path, capsys):
    csv = tmp_path / "run.csv"
    png = tmp_path / "run.png"
    from fricctl.design import DesignWarning

    with pytest.warns(DesignWarning, match="ill-conditioned"):  # the paper's 0.3 s / 0.9 design
        code = main(["simulate", "--controller", "pd", "--rise-time", "0.3", "--damping", "0.9",
                     "--reference", "step:0.5236", "--duration", "2", "--csv", str(csv),
                     "--figure", str(png), "--json"])
    assert code == 0
    out = json.loads(capsys.readouterr().out)
    # PD without compensation sticks inside the +-Fs/Kp band (8.5 deg for Kp = 1.213)
    assert out["stuck_at_end"] and 0 < out["steady_state_error_deg"] < 8.5
    run = Run.from_csv(csv)
    assert run.n_samples == 1000 and run.reference is not None
    assert png.stat().st_size > 1000


def test_open_loop_below_breakaway_does_not_move(capsys):
    assert main(["simulate", "--torque", "constant:0.17", "--duration", "0.5", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["max_abs_position_rad"] == 0.0


@pytest.mark.parametrize("argv,words", [
    (["simulate", "--torque", "ramp:1"], "unknown signal"),
    (["simulate", "--torque", "sinusoid:1"], "takes 2"),
    (["simulate", "--torque", "step:x"], "numbers"),
    (["simulate"], "needs --torque"),
    (["simulate", "--controller", "pd", "--reference", "step:0.1"], "--rise-time"),
    (["simulate", "--torque", "step:0.1", "--duration", "nan"], "--duration"),
    (["simulate", "--controller", "p", "--kp", "1", "--compensation", "nn"], "--net"),
])
def test_bad_input_one_line_exit_2(argv, words, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert words in err and err.count("\n") == 1
