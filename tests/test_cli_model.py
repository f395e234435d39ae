"""``fricctl model new/show`` (issue 25: your motor by its numbers) and the model file's page."""

import json
import math
import re
import subprocess
import sys
from pathlib import Path

import pytest

from fricctl.cli import main
from fricctl.plant import JointModel

DOCS = Path(__file__).resolve().parents[1] / "docs"


def test_model_new_writes_what_the_numbers_say(tmp_path, capsys):
    out = tmp_path / "my.json"
    assert main(["model", "new", "--inertia", "0.01", "--viscous", "0.05", "--coulomb", "0.1",
                 "--coulomb-neg", "0.12", "--static", "0.15", "--stribeck-velocity", "0.05",
                 "--sample-time", "0.002", "--encoder-counts", "4096", "--max-torque", "2",
                 "--friction", "load_coefficient=0.01", "--out", str(out)]) == 0
    m = JointModel.load(out)
    fr = m.friction
    assert (m.inertia, m.sample_time, m.max_torque) == (0.01, 0.002, 2.0)
    assert m.encoder_resolution == pytest.approx(2 * 3.141592653589793 / 4096, rel=1e-15)
    assert (fr.viscous_pos, fr.viscous_neg, fr.coulomb_pos, fr.coulomb_neg) == (0.05, 0.05, 0.1, 0.12)
    # the breakaway level is what --static says, in both directions (Fs = Fc + excess)
    assert fr.breakaway(1) == pytest.approx(0.15) and fr.breakaway(-1) == pytest.approx(0.15)
    assert fr.load_coefficient == 0.01
    assert m.provenance["inertia"].source == "datasheet"
    assert m.provenance["friction.stribeck_pos"].source == "derived"
    capsys.readouterr()
    assert main(["model", "show", str(out)]) == 0
    text = capsys.readouterr().out
    assert "friction.coulomb_neg         0.12 N*m  [datasheet]" in text
    assert "breakaway level              +0.15 / -0.15 N*m" in text
    assert main(["model", "show", str(out), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["friction"]["coulomb_neg"] == 0.12


@pytest.mark.parametrize("args, message", [
    (["--inertia", "0.01", "--friction", "coulmb_pos=1"], "did you mean 'coulomb_pos'"),
    (["--inertia", "0.01", "--coulomb", "0.2", "--static", "0.1", "--stribeck-velocity", "0.1"],
     "below the Coulomb level"),
    (["--inertia", "0.01", "--static", "0.1"], "go together"),
    (["--inertia", "-1"], "inertia"),
    (["--inertia", "0.01", "--viscous", "nan"], "--viscous"),
    (["--inertia", "0.01", "--units", "linear", "--encoder-counts", "100"], "linear axis"),
    (["--inertia", "0.01", "--sample-time", "2min"], "--sample-time: unknown unit 'min'"),
    (["--inertia", "0.01", "--coulomb", "0.1N"], "accepted units: N*m"),  # a force on a joint
    (["--inertia", "0.01", "--offset", "infN*m"], "--offset"),
    # audit A 4, 6: accepted, then design called a stable loop unstable / failed on NaN
    (["--inertia", "0.01", "--sample-time", "1e-20"], "sample_time must lie in [1e-09, 3600] s"),
    (["--inertia", "0.01", "--sample-time", "1e100"], "sample_time must lie in [1e-09, 3600] s"),
    (["--inertia", "0.01", "--encoder-resolution", "100"], "at most one revolution (2*pi rad)"),
    (["--inertia", "0.01", "--encoder-counts", "0.5"], "at most one revolution (2*pi rad)"),
])
def test_model_new_refuses_in_one_line(tmp_path, args, message):
    proc = subprocess.run([sys.executable, "-m", "fricctl", "model", "new", *args, "--out",
                           str(tmp_path / "m.json")], capture_output=True, text=True, cwd=tmp_path)
    assert proc.returncode == 2 and proc.stderr.count("\n") == 1 and message in proc.stderr
    assert not (tmp_path / "m.json").exists()


def test_model_new_takes_numbers_with_their_units(tmp_path):
    # a datasheet's numbers as printed: each converted to the SI unit the file holds
    out = tmp_path / "units.json"
    assert main(["model", "new", "--inertia", "30g*cm^2", "--viscous", "0.06N*m/rpm",
                 "--coulomb", "150mN*m", "--static", "0.2", "--stribeck-velocity", "5deg/s",
                 "--sample-time", "2ms", "--encoder-resolution", "0.01deg", "--out", str(out)]) == 0
    m = JointModel.load(out)
    assert m.inertia == pytest.approx(3e-6, rel=1e-12)
    assert m.viscous == pytest.approx(0.06 * 30 / math.pi, rel=1e-12)
    assert m.friction.coulomb_pos == pytest.approx(0.15, rel=1e-12)
    assert m.friction.stribeck_velocity == pytest.approx(5 * math.pi / 180, rel=1e-12)
    assert m.sample_time == pytest.approx(0.002, rel=1e-12)
    assert m.encoder_resolution == pytest.approx(0.01 * math.pi / 180, rel=1e-12)
    lin = tmp_path / "linear.json"  # the axis decides: mass in kg, force in N, lengths in m
    assert main(["model", "new", "--units", "linear", "--inertia", "95kg", "--viscous", "203Ns/m",
                 "--coulomb", "20N", "--offset=-3.2N", "--encoder-resolution", "0.05um", "--out", str(lin)]) == 0
    m = JointModel.load(lin)
    assert (m.inertia, m.viscous, m.friction.coulomb_pos, m.offset) == (95.0, 203.0, 20.0, -3.2)
    assert m.encoder_resolution == pytest.approx(5e-8, rel=1e-12)


def test_model_without_action_and_existing_output(tmp_path, capsys):
    assert main(["model"]) == 2
    out = tmp_path / "m.json"
    out.write_text("keep")
    assert main(["model", "new", "--inertia", "1", "--out", str(out)]) == 2
    assert out.read_text() == "keep"


def test_the_model_file_page_example_loads_and_lists_every_coefficient():
    text = (DOCS / "model_file.md").read_text(encoding="utf-8")
    example = re.search(r"```json\n(.*?)```", text, re.S).group(1)
    m = JointModel.from_dict(json.loads(example))
    assert m.friction.breakaway(1) == pytest.approx(0.13)
    sys.path.insert(0, str(DOCS / "_ext"))
    try:
        from fricctl_tables import coefficients_table, linear_unit, render_coefficients
    finally:
        sys.path.pop(0)
    from fricctl.friction import FIELDS

    table = coefficients_table()
    assert all(f"`{name}`" in table for name in FIELDS)  # read from the law registry
    # issue 25: the page itself lists every coefficient with its unit (read on GitHub or in an
    # editor, not only in the built book), and the committed list is the registry's
    assert table in text and render_coefficients(text) == text, \
        "docs/model_file.md's coefficients are stale: run `python docs/_ext/fricctl_tables.py`"
    assert "| `viscous_pos` | `N*m*s/rad` / `N*s/m` | 0 | `viscous` |" in text
    # the linear units are fricctl.units' labels of the same quantities
    from fricctl.units import UNITS

    rot, lin = UNITS["rotary"], UNITS["linear"]
    for q in ("torque", "position", "velocity", "viscous", "stiffness"):
        assert linear_unit(getattr(rot, q)) == getattr(lin, q)
    assert linear_unit("rad", "ripple_phase") == "rad"  # the angle of a sine on both axes


def test_model_new_keeps_the_breakaway_it_was_given(tmp_path):
    # --friction cannot change what --static was computed from (Fs - Fc per direction)
    proc = subprocess.run([sys.executable, "-m", "fricctl", "model", "new", "--inertia", "1",
                           "--coulomb", "1", "--static", "2", "--stribeck-velocity", "0.1",
                           "--friction", "coulomb_neg=1.5", "--out", str(tmp_path / "m.json")],
                          capture_output=True, text=True, cwd=tmp_path)
    assert proc.returncode == 2 and "own option" in proc.stderr


def test_the_actions_help_says_what_they_do(capsys):
    # issue 25 item 7, the sub-command's help: `fricctl model new --help` is where a user looks
    # (an error points there); it had the options alone, not the units a number may carry or
    # the page of the format
    assert main(["model", "new", "--help"]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "docs/model_file.md" in out and "--sample-time 2ms" in out and "--units linear" in out
    assert "--units {rotary,linear} rotary joint (default: N*m, rad, kg*m^2)" in out
    assert main(["model", "show", "--help"]) == 0
    assert "prints every value with its unit and provenance" in " ".join(capsys.readouterr().out.split())
