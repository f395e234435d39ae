"""``fricctl diagnose``: JSON output, report folder, bad input -> one line + exit 2."""

import json
import threading

import numpy as np
import pytest

from fricctl.bench.hidden_effects import hidden_effect_record
from fricctl.cli import main
from fricctl.datasets import Run
from fricctl.diagnose import CAUSES, NOMINAL_ONLY
from fricctl.plant import JointModel


@pytest.fixture(scope="module")
def record_csv(tmp_path_factory):
    rec = hidden_effect_record(np.random.default_rng([2026, 77]), cause="time_delay", duration=20.0)
    path = tmp_path_factory.mktemp("rec") / "run.csv"
    rec.run.to_csv(path)
    return path, rec


def test_json_output(record_csv, capsys):
    path, rec = record_csv
    assert main(["diagnose", str(path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["cause"] == "time_delay" and out["causes"] == ["time_delay"]
    assert [s["cause"] for s in out["steps"]] == ["time_delay"]
    assert out["steps"][0]["score"] >= 0.19  # named: removes >= 10 % of the held-out RMS
    # fit mode: every candidate that needs no nominal model, scored once
    assert sorted(r["cause"] for r in out["ranking"]) == sorted(
        set(CAUSES) - {"none"} - set(NOMINAL_ONLY))
    assert {"inertia", "viscous_pos", "coulomb_pos"} <= set(out["baseline"])
    assert "delay" in out["extended"]
    assert set(out["gain"]) >= {"torque_rms_before", "torque_rms_after",
                                "simulation_rms_before", "simulation_rms_after"}
    assert out["gain"]["torque_rms_after"] < out["gain"]["torque_rms_before"]


def test_nominal_model_and_report(record_csv, tmp_path, capsys):
    path, rec = record_csv
    model = JointModel(inertia=rec.truth.inertia, friction=rec.truth.friction)  # without the delay
    mfile = model.save(tmp_path / "nominal.json")
    out_dir = tmp_path / "report"
    assert main(["diagnose", str(path), "--model", str(mfile), "--report", str(out_dir)]) == 0
    text = capsys.readouterr().out
    assert "# Diagnosis: `time_delay`" in text
    # nominal mode: the nominal-only candidates are scored too
    assert all(f"| {c} |" in text for c in NOMINAL_ONLY)
    for name in ("report.md", "residuals.png", "simulation.png", "spectrum.png", "steps.png",
                 "extended_model.json"):
        assert (out_dir / name).is_file(), name
    ext = JointModel.load(out_dir / "extended_model.json")
    # the bench's delay is whole samples; the diagnosis's grid is a quarter sample
    assert abs(ext.delay / rec.run.sample_time - rec.magnitude["samples"]) <= 0.25


@pytest.mark.parametrize("content, match", [
    ("t,torque\n0,1\n0.002,1\n", "missing column"),
    ("t,torque,position,speed\n0,1,0,0\n", "unknown column"),
])
def test_bad_csv_exits_2(tmp_path, capsys, content, match):
    p = tmp_path / "bad.csv"
    p.write_text(content)
    assert main(["diagnose", str(p)]) == 2
    err = capsys.readouterr().err
    assert match in err and len(err.strip().splitlines()) == 1


def test_bad_model_file_exits_2(record_csv, tmp_path, capsys):
    path, _ = record_csv
    bad = tmp_path / "m.json"
    bad.write_text(json.dumps({"format": "fricctl.joint_model", "version": 9}))
    assert main(["diagnose", str(path), "--model", str(bad)]) == 2
    assert "version" in capsys.readouterr().err
    assert main(["diagnose", str(tmp_path / "absent.csv")]) == 2


def test_linear_axis_from_the_command_line(tmp_path, capsys):
    # a linear-axis record without its "# units:" line: --units linear labels it (N, m)
    rec = hidden_effect_record(np.random.default_rng([2026, 78]), cause="none", duration=20.0,
                               axis="linear")
    path = rec.run.to_csv(tmp_path / "lin.csv")
    lines = [ln for ln in path.read_text().splitlines() if not ln.startswith("# units:")]
    path.write_text("\n".join(lines) + "\n")
    assert main(["diagnose", str(path), "--units", "linear", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["units"] == "linear" and out["causes"] == ["none"]
    assert main(["diagnose", str(path), "--units", "linear"]) == 0
    assert " N |" in capsys.readouterr().out  # forces in newtons in the gain table


# ----------------------------------------------------------------------------- issues 13, 15
def test_emps_mat_record(data_dir, capsys):
    # a .mat file in the EMPS layout is read as a record (a linear axis), like the CSV
    assert main(["diagnose", str(data_dir / "emps" / "DATA_EMPS.mat"), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["units"] == "linear" and out["causes"] and "undefined" in out


def _model_file(tmp_path, rec, name="m.json", **kw):
    m = JointModel(inertia=rec.truth.inertia, friction=rec.truth.friction, **kw)
    return m.save(tmp_path / name)


def test_model_sample_time_and_encoder_checked_against_the_record(record_csv, tmp_path, capsys):
    path, rec = record_csv
    ts, grid = rec.run.sample_time, rec.run.encoder_grid()
    bad_ts = _model_file(tmp_path, rec, "ts.json", sample_time=2 * ts)
    assert main(["diagnose", str(path), "--model", str(bad_ts)]) == 2
    err = capsys.readouterr().err
    assert "sample_time" in err and "differs from the record" in err
    assert len(err.strip().splitlines()) == 1
    bad_enc = _model_file(tmp_path, rec, "enc.json", sample_time=ts, encoder_resolution=3 * grid)
    assert main(["diagnose", str(path), "--model", str(bad_enc)]) == 2
    err = capsys.readouterr().err
    assert "encoder_resolution" in err and len(err.strip().splitlines()) == 1


def test_extended_model_feeds_design_and_simulate(record_csv, tmp_path, capsys):
    # the extended model of --report is a version-2 model file: provenance "diagnosed" on
    # what the diagnosis added, the model's sample time and encoder kept; design and
    # simulate read it
    path, rec = record_csv
    ts, grid = rec.run.sample_time, rec.run.encoder_grid()
    mfile = _model_file(tmp_path, rec, sample_time=ts, encoder_resolution=grid)
    out_dir = tmp_path / "rep"
    assert main(["diagnose", str(path), "--model", str(mfile), "--report", str(out_dir)]) == 0
    capsys.readouterr()
    ext_file = out_dir / "extended_model.json"
    raw = json.loads(ext_file.read_text())
    assert raw["version"] == 2
    assert raw["provenance"]["delay"]["source"] == "diagnosed"
    assert raw["sample_time"] == ts and raw["encoder_resolution"] == grid
    ext = JointModel.load(ext_file)
    assert ext.delay > 0
    assert main(["design", "pd", "--model", str(ext_file), "--rise-time", "0.1",
                 "--damping", "0.7", "--json"]) == 0
    design = json.loads(capsys.readouterr().out)
    assert design["kp"]["value"] > 0 and design["kp"]["unit"] == "N*m/rad"
    assert main(["simulate", "--model", str(ext_file), "--controller", "pd", "--rise-time", "0.1",
                 "--damping", "0.7", "--reference", "step:0.1", "--duration", "1",
                 "--json"]) == 0
    sim = json.loads(capsys.readouterr().out)
    assert sim["units"] == "rotary"


def test_report_folder_not_overwritten_without_force(record_csv, tmp_path, capsys):
    path, _ = record_csv
    out_dir = tmp_path / "rep"
    assert main(["diagnose", str(path), "--report", str(out_dir)]) == 0
    before = (out_dir / "extended_model.json").read_text()
    (out_dir / "extended_model.json").write_text("mine")
    capsys.readouterr()
    assert main(["diagnose", str(path), "--report", str(out_dir)]) == 2
    err = capsys.readouterr().err
    assert "exists (use --force" in err and len(err.strip().splitlines()) == 1
    assert (out_dir / "extended_model.json").read_text() == "mine"  # untouched
    assert main(["diagnose", str(path), "--report", str(out_dir), "--force"]) == 0
    assert (out_dir / "extended_model.json").read_text() == before
    afile = tmp_path / "a_file"
    afile.write_text("x")
    assert main(["diagnose", str(path), "--report", str(afile)]) == 2
    assert "not a folder" in capsys.readouterr().err


def test_report_drawn_in_forked_processes_has_the_serial_bytes(record_csv, tmp_path, capsys,
                                                               monkeypatch):
    """The painters (fricctl.cli._painters) against the figures drawn in the command itself:
    every file of the report the same bytes, and the JSON."""
    from fricctl.cli import _painters

    path, _ = record_csv
    forked = []
    real = _painters.Painters

    def counted(*args, **kwargs):
        forked.append(real(*args, **kwargs))
        return forked[-1]

    started = []  # by whom the painters were let import: the baseline's thread, when done
    real_start = real.start

    def start(self):
        started.append(threading.current_thread().name)
        real_start(self)

    monkeypatch.setattr(_painters, "parallel_available", lambda: True)  # even on one core
    monkeypatch.setattr(_painters, "Painters", counted)
    monkeypatch.setattr(real, "start", start)
    assert main(["diagnose", str(path), "--json", "--report", str(tmp_path / "forked")]) == 0
    assert len(forked) == 1 and len(forked[0]._all) == 2  # the figures were drawn by two
    assert started[0].startswith("fricctl-baseline"), started
    json_forked = capsys.readouterr().out
    monkeypatch.setattr(_painters, "parallel_available", lambda: False)
    assert main(["diagnose", str(path), "--json", "--report", str(tmp_path / "serial")]) == 0
    assert len(forked) == 1
    assert capsys.readouterr().out == json_forked
    names = sorted(p.name for p in (tmp_path / "serial").iterdir())
    assert names == sorted(p.name for p in (tmp_path / "forked").iterdir())
    assert len(names) == 6
    for name in names:
        forked_bytes = (tmp_path / "forked" / name).read_bytes()
        assert forked_bytes == (tmp_path / "serial" / name).read_bytes(), name


@pytest.mark.parametrize("window", ["1e-9", "0", "-1"])
def test_window_shorter_than_a_sample_exits_2(record_csv, capsys, window):
    path, _ = record_csv
    assert main(["diagnose", str(path), f"--window={window}"]) == 2
    err = capsys.readouterr().err
    assert "window" in err and len(err.strip().splitlines()) == 1


def test_time_column_times_1e300_exits_2(record_csv, tmp_path, capsys):
    path, rec = record_csv
    r = rec.run
    Run(t=r.t * 1e300, torque=r.torque, position=r.position).to_csv(tmp_path / "huge.csv")
    assert main(["diagnose", str(tmp_path / "huge.csv")]) == 2
    err = capsys.readouterr().err
    assert "sample time" in err and len(err.strip().splitlines()) == 1


def test_a_command_builds_its_own_parser_only(tmp_path):
    # `fricctl diagnose` registered every sub-command, importing the network and its trainers
    # (train's choices) that a diagnosis never uses; the usage, help and errors are its own
    import subprocess
    import sys

    code = ("import sys\nfrom fricctl.cli import main\ncode = main(sys.argv[1:])\n"
            "print(code, 'fricctl.nn' in sys.modules, 'fricctl.cli.train' in sys.modules)")

    def run(*argv):
        out = subprocess.run([sys.executable, "-c", code, *argv], capture_output=True, text=True,
                             cwd=tmp_path)
        return out.stdout.split()[-3:], out.stdout + out.stderr

    words, text = run("diagnose", "--help")
    assert words == ["0", "False", "False"] and "usage: fricctl diagnose" in text
    words, text = run("diagnose", "run.csv", "--windw", "1")  # a usage error names its command
    assert words == ["2", "False", "False"]
    assert "fricctl diagnose: error: unrecognized arguments: --windw" in text
    assert "did you mean --window?" in text and "(see fricctl diagnose --help)" in text
    words, text = run("--help")  # the whole parser: every command listed
    assert words == ["0", "True", "True"] and "diagnose" in text and "train" in text
    words, text = run("diagnos", "x")  # a misspelt command: the whole parser's suggestion
    assert words[0] == "2" and "did you mean diagnose?" in text


def test_a_report_into_a_missing_folder_is_refused(tmp_path, capsys):
    # audit A 8: --report nodir/rep made nodir too; every other output's folder must exist
    from fricctl.datasets import Run

    t = np.arange(50) * 0.002
    path = Run(t=t, torque=np.sin(t), position=t ** 2).to_csv(tmp_path / "r.csv")
    out = tmp_path / "nodir" / "rep"
    assert main(["diagnose", str(path), "--report", str(out)]) == 2
    err = capsys.readouterr().err
    assert err == f"fricctl diagnose: error: --report: the folder {out.parent} does not exist\n"
    assert not out.parent.exists()


@pytest.mark.parametrize("fails", ["steps.png", "extended_model.json"])
def test_a_forced_report_that_fails_leaves_the_old_folder_as_it_was(record_csv, tmp_path, capsys,
                                                                    monkeypatch, fails):
    # audit C24 1: --force over an existing report wrote its files one by one; a run cut short
    # left new figures (or a new report.md) beside the old files, a mixed report
    import errno

    from fricctl._atomic import TEMP_MARK
    from fricctl.cli import _painters
    from fricctl.cli import diagnose as cli_diagnose

    path, _ = record_csv
    out_dir = tmp_path / "rep"
    out_dir.mkdir()
    old = {name: f"old {name}".encode() for name in cli_diagnose.REPORT_FILES}
    old["notes.txt"] = b"mine"
    for name, data in old.items():
        (out_dir / name).write_bytes(data)

    def full(*args, **kwargs):  # the disk fills while the last figure or the model is written
        raise OSError(errno.ENOSPC, "No space left on device", str(out_dir / fails))

    monkeypatch.setattr(_painters, "parallel_available", lambda: False)  # drawn in order, here
    if fails == "steps.png":
        monkeypatch.setitem(cli_diagnose.FIGURES, "steps.png", full)
    else:
        monkeypatch.setattr(JointModel, "save", full)
    assert main(["diagnose", str(path), "--report", str(out_dir), "--force"]) == 2
    err = capsys.readouterr().err
    assert err == (f"fricctl diagnose: error: {out_dir / fails}: No space left on device\n")
    assert {p.name: p.read_bytes() for p in out_dir.iterdir()} == old
    assert [p.name for p in tmp_path.iterdir() if TEMP_MARK in p.name] == []
    monkeypatch.undo()
    assert main(["diagnose", str(path), "--report", str(out_dir), "--force"]) == 0
    now = {p.name: p.read_bytes() for p in out_dir.iterdir()}
    assert sorted(now) == sorted(old) and now["notes.txt"] == b"mine"  # the user's file kept
    assert all(now[name] != old[name] for name in cli_diagnose.REPORT_FILES)
    assert [p.name for p in tmp_path.iterdir()] == ["rep"]


def test_a_forced_report_over_the_working_folder_is_refused(record_csv, tmp_path, capsys,
                                                            monkeypatch):
    # replaced as a whole, the folder the command runs in would be swapped away under it
    path, _ = record_csv
    inner = tmp_path / "rep" / "inner"
    inner.mkdir(parents=True)
    monkeypatch.chdir(inner)
    for where in (inner, tmp_path / "rep"):
        assert main(["diagnose", str(path), "--report", str(where), "--force"]) == 2
        assert capsys.readouterr().err == (f"fricctl diagnose: error: --report: {where} holds "
                                           "the working folder, and is replaced as a whole with "
                                           "--force: run from another folder\n")
    assert [p.name for p in (tmp_path / "rep").iterdir()] == ["inner"]
