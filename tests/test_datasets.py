import numpy as np
import pytest

from fricctl.datasets import MIN_SAMPLES, PATTERN_COLUMNS, Run, emps, read_columns, read_patterns


def _run(n=100, **kw):
    t = np.arange(n) * 0.002
    args = dict(t=t, torque=np.sin(t), position=0.5 * t ** 2)
    args.update(kw)
    return Run(**args)


def test_run_basic_properties():
    run = _run(reference=np.zeros(100), units="linear", source="unit test")
    # sample time is the grid step by construction (exact up to float rounding)
    assert run.sample_time == pytest.approx(0.002, rel=1e-12)
    assert run.n_samples == 100 and run.torque_unit == "N" and run.position_unit == "m"
    assert run.torque_label == "force"
    with pytest.raises(ValueError):  # arrays are read-only
        run.torque[0] = 1.0


def test_csv_round_trip(tmp_path):
    run = _run(reference=np.cos(np.arange(100) * 0.002), units="linear", source="bench A")
    path = run.to_csv(tmp_path / "r.csv")
    back = Run.from_csv(path)
    # %.17g round-trips IEEE doubles exactly
    for name in ("t", "torque", "position", "reference"):
        np.testing.assert_array_equal(getattr(back, name), getattr(run, name))
    assert back.units == "linear" and back.source == "bench A"
    assert path.read_text().splitlines()[2] == "t,torque,position,reference"


def test_csv_without_reference_and_comments(tmp_path):
    p = tmp_path / "x.csv"
    t = np.arange(20) * 0.01
    p.write_text("t,torque,position\n" + "\n".join(f"{a},{1.0},{a * a}" for a in t) + "\n")
    run = Run.from_csv(p)
    assert run.reference is None and run.units == "rotary" and run.source == "x.csv"


@pytest.mark.parametrize("header,message", [
    ("t,torque", "missing column 'position'"),
    ("t,torque,position,foo", "unknown column 'foo'"),
])
def test_csv_bad_columns(tmp_path, header, message):
    p = tmp_path / "bad.csv"
    ncol = len(header.split(","))
    p.write_text(header + "\n" + "\n".join(",".join(["1"] * ncol) for _ in range(20)))
    with pytest.raises(ValueError, match=message):
        Run.from_csv(p)


def test_csv_non_numeric_and_missing_file(tmp_path):
    p = tmp_path / "bad.csv"
    p.write_text("t,torque,position\n0,1,2\n0.1,x,3\n")
    with pytest.raises(ValueError, match="bad.csv, line 3, column 'torque': not a number: 'x'"):
        Run.from_csv(p)
    with pytest.raises(FileNotFoundError):
        Run.from_csv(tmp_path / "nope.csv")


def test_validation_messages():
    t = np.arange(300) * 0.002
    tq = np.ones(300)
    q = t.copy()
    bad = tq.copy(); bad[17] = np.nan
    with pytest.raises(ValueError, match=r"torque holds NaN or inf \(nan\) at index 17"):
        Run(t=t, torque=bad, position=q)
    bad = q.copy(); bad[5] = np.inf
    with pytest.raises(ValueError, match=r"position holds NaN or inf \(inf\) at index 5"):
        Run(t=t, torque=tq, position=bad)
    tt = t.copy(); tt[203:] += 0.001
    with pytest.raises(ValueError, match="non-uniform time step at row 203"):
        Run(t=tt, torque=tq, position=q)
    tt = t.copy(); tt[10] = tt[9]
    with pytest.raises(ValueError, match="non-increasing time at row 10"):
        Run(t=tt, torque=tq, position=q)
    with pytest.raises(ValueError, match=f"fewer than {MIN_SAMPLES} samples"):
        Run(t=t[:5], torque=tq[:5], position=q[:5])
    with pytest.raises(ValueError, match="no motion"):
        Run(t=t, torque=tq, position=np.zeros(300))
    with pytest.raises(ValueError, match="length 299 differs"):
        Run(t=t, torque=tq[:-1], position=q)
    with pytest.raises(ValueError, match="units"):
        Run(t=t, torque=tq, position=q, units="metric")
    with pytest.raises(ValueError, match="1-D"):
        Run(t=t, torque=np.ones((300, 1)), position=q)


@pytest.mark.parametrize("content, message", [
    ("", "empty file, expected a header t, torque, position"),
    ("# source: x\n", "no header line"),
    ("t,torque,torque,position\n", "duplicate column 'torque'"),
    ("t,torque,position\n0,1,2\n0.1,2\n", "line 3: 2 fields, the header has 3"),
    ("# units: rotary\nt,torque,position\n0,1,2\n\n0.1,nan,3\n", "line 5, column 'torque': NaN"),
    ("t,position,torque\n0,1,inf\n", "line 2, column 'torque': inf"),
])
def test_csv_reader_names_file_line_and_column(tmp_path, content, message):
    # the one CSV reader behind Run.from_csv and read_patterns: every message names the file
    p = tmp_path / "bad.csv"
    p.write_text(content)
    with pytest.raises(ValueError, match="bad.csv") as err:
        Run.from_csv(p)
    assert message in str(err.value)


def test_csv_reader_rejects_binary_and_reads_patterns_by_name(tmp_path):
    p = tmp_path / "bin.csv"
    p.write_bytes(b"\xff\xfe\x00t,torque")
    with pytest.raises(ValueError, match="bin.csv: not a UTF-8 text file"):
        read_columns(p, required=("t",))
    p = tmp_path / "pat.csv"
    p.write_text("friction,tm,omega\n3,1,2\n6,4,5\n")
    pats = read_patterns(p)
    assert pats.n_rows == 2 and tuple(pats.columns) == ("friction", "tm", "omega")
    np.testing.assert_array_equal([pats[c] for c in PATTERN_COLUMNS], [[1, 4], [2, 5], [3, 6]])
    with pytest.raises(ValueError):
        pats["tm"][0] = 0.0  # read-only
    p.write_text("tm,omega,friction\n1,2,3\n")
    with pytest.raises(ValueError, match="need at least 2 data rows, got 1"):
        read_patterns(p)


def test_emps_missing_says_where(tmp_path, monkeypatch):
    monkeypatch.delenv("FRICCTL_DATA", raising=False)
    with pytest.raises(FileNotFoundError, match="FRICCTL_DATA"):
        emps()
    with pytest.raises(FileNotFoundError, match="EMPS benchmark"):
        emps(tmp_path)
    with pytest.raises(ValueError, match="kind"):
        emps(tmp_path, kind="test")


def test_emps_loader(data_dir, monkeypatch):
    d = emps(data_dir)
    # sizes and gains from the data README / EMPS_Description.pdf (sec. 1.3, 2.2)
    assert d.run.n_samples == 24841 and d.run.units == "linear"
    assert d.gtau == pytest.approx(35.15, abs=0.01)
    assert d.kp == pytest.approx(160.18) and d.kv == pytest.approx(243.45)
    np.testing.assert_allclose(d.run.torque, d.gtau * d.vir, rtol=0, atol=0)
    assert d.run.sample_time == pytest.approx(1e-3, rel=1e-4)
    v = emps(data_dir, kind="validation")
    assert v.pulses is not None and set(np.unique(v.pulses)) <= {0.0, 5.0}
    # the env variable gives the same as the argument
    monkeypatch.setenv("FRICCTL_DATA", str(data_dir))
    np.testing.assert_array_equal(emps().run.position, d.run.position)
