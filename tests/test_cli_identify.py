import json

import numpy as np
import pytest

from fricctl.cli import main
from fricctl.datasets import Run


def _synthetic_csv(path):
    # exact law on an analytic trajectory (no encoder grid): within 1 % is a loose bound
    # for the estimator error (tested tightly in test_identify)
    t = np.arange(0.0, 10.0, 0.002)
    q = 1.2 * np.sin(1.3 * t)
    w = 1.2 * 1.3 * np.cos(1.3 * t)
    a = -1.2 * 1.3 ** 2 * np.sin(1.3 * t)
    tau = 0.0046 * a + 0.0169 * w + 0.144 * np.sign(w) + 0.003
    Run(t=t, torque=tau, position=q, source="synthetic").to_csv(path)
    return path


def test_json_output(tmp_path, capsys):
    path = _synthetic_csv(tmp_path / "run.csv")
    assert main(["identify", str(path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out["parameters"]) == {"inertia", "viscous", "coulomb", "offset"}
    # noise-free synthetic record: true values to 1 % (the CLI estimates the derivatives itself)
    for name, value in dict(inertia=0.0046, viscous=0.0169, coulomb=0.144).items():
        assert out["parameters"][name]["value"] == pytest.approx(value, rel=0.01)
        assert np.isfinite(out["parameters"][name]["std"]) and out["parameters"][name]["std"] > 0
    assert out["parameters"]["offset"]["value"] == pytest.approx(0.003, abs=0.001)
    # the JSON's numbers are the library's: same fit through identify_run
    from fricctl.identify import identify_run

    res = identify_run(Run.from_csv(path))
    assert out["condition_number"] == pytest.approx(res.condition_number, rel=1e-9)
    assert out["fit_percent"] == pytest.approx(res.fit_percent, rel=1e-9) and res.fit_percent > 95


def test_text_output_and_models(tmp_path, capsys):
    path = _synthetic_csv(tmp_path / "run.csv")
    assert main(["identify", str(path), "--model", "asymmetric",
                 "--estimator", "polynomial_segments"]) == 0
    text = capsys.readouterr().out
    assert "Parameter coulomb_pos" in text and "Relative error (%)" in text
    assert main(["identify", str(path), "--model", "stribeck", "--json"]) == 0
    assert "stribeck_velocity" in json.loads(capsys.readouterr().out)["parameters"]


@pytest.mark.parametrize("content,msg", [
    ("t,torque,foo\n" + "1,2,3\n" * 20, "unknown column 'foo'"),
    ("t,torque\n" + "1,2\n" * 20, "missing column 'position'"),
])
def test_bad_csv_exit_2(tmp_path, capsys, content, msg):
    p = tmp_path / "bad.csv"
    p.write_text(content)
    assert main(["identify", str(p)]) == 2
    err = capsys.readouterr().err
    assert msg in err and len(err.strip().splitlines()) == 1


def test_missing_file_exit_2(tmp_path, capsys):
    assert main(["identify", str(tmp_path / "nope.csv")]) == 2
    assert "no such file" in capsys.readouterr().err


def test_emps_csv_within_one_percent(tmp_path, capsys, data_dir):
    from fricctl.datasets import emps

    path = emps(data_dir).run.to_csv(tmp_path / "emps.csv")
    assert main(["identify", str(path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    # published IDIM-LS values (Janot, Gautier & Brunot 2019, sec. 3.4), issue 4 asks 1 %
    for name, value in dict(inertia=95.1089, viscous=203.5034, coulomb=20.3935, offset=-3.1648).items():
        assert out["parameters"][name]["value"] == pytest.approx(value, rel=0.01), name
