import re

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


@pytest.mark.parametrize("content,words", [
    # a spreadsheet's CSV in a locale with decimal commas (issue 25: the error named the column
    # 't;torque;position' and nothing more)
    ("t;torque;position\n0;0,1;0\n0,002;0,1;0\n",
     "the file looks ';'-separated with decimal commas: fricctl reads ',' between fields and "
     "'.' as the decimal mark"),
    ("t;torque;position\n0;0.1;0\n", "the file looks ';'-separated: fricctl reads ','"),
    ("t\ttorque\tposition\n0\t0.1\t0\n", "the file looks tab-separated: fricctl reads ','"),
    ("t,torque,position\n0,0,1,0\n", "4 fields, the header has 3 (decimal commas? fricctl "
                                       "reads '.' as the decimal mark)"),
])
def test_csv_separator_and_decimal_comma_hints(tmp_path, content, words):
    p = tmp_path / "excel.csv"
    p.write_text(content)
    with pytest.raises(ValueError) as err:
        Run.from_csv(p)
    assert words in str(err.value) and "\n" not in str(err.value)


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
    with pytest.raises(ValueError, match="non-uniform time step at index 203"):
        Run(t=tt, torque=tq, position=q)
    tt = t.copy(); tt[10] = tt[9]
    with pytest.raises(ValueError, match="non-increasing time at index 10"):
        Run(t=tt, torque=tq, position=q)
    with pytest.raises(ValueError, match=f"fewer than {MIN_SAMPLES} samples"):
        Run(t=t[:5], torque=tq[:5], position=q[:5])
    # a joint stuck below breakaway is a valid record (issue 26); it lies on no encoder grid
    assert Run(t=t, torque=tq, position=np.zeros(300)).encoder_grid() is None
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


# -- records from .mat files, the encoder grid ----------------------------------------------
def test_load_record_mat_and_csv(data_dir, tmp_path):
    from fricctl.datasets import emps_file, load_record

    mat = data_dir / "emps" / "DATA_EMPS.mat"
    run = load_record(mat)
    # the same record as the EMPS loader (one reader behind both)
    np.testing.assert_array_equal(run.torque, emps(data_dir).run.torque)
    assert emps_file(mat).kind == "estimation"
    assert emps_file(data_dir / "emps" / "DATA_EMPS_PULSES.mat").kind == "validation"
    # the data README: one count = 5e-8 m on the load; the PULSES positions are filtered
    assert run.encoder_grid() == pytest.approx(5e-8, rel=1e-9)
    assert emps(data_dir, kind="validation").run.encoder_grid() is None
    with pytest.raises(ValueError, match="linear axis, not 'rotary'"):
        load_record(mat, units="rotary")
    csv = run.to_csv(tmp_path / "r.csv")
    np.testing.assert_array_equal(load_record(csv).position, run.position)


@pytest.mark.parametrize("content, message", [
    (b"\x00garbage" * 50, "not a MATLAB .mat file"),
    (b"", "not a MATLAB .mat file"),
])
def test_load_record_bad_mat(tmp_path, content, message):
    from fricctl.datasets import load_record

    p = tmp_path / "x.mat"
    p.write_bytes(content)
    with pytest.raises(ValueError, match=message):
        load_record(p)


def test_a_mat_variable_error_names_the_file_once_and_nan_plainly(tmp_path):
    # audit A 12: "e.mat: e.mat: variable qm ..." and "gtau must be finite, got np.float64(nan)"
    from scipy.io import savemat

    from fricctl.datasets import load_record

    n = 20
    good = dict(t=np.arange(n) * 1e-3, qm=np.zeros(n), qg=np.zeros(n), vir=np.zeros(n),
                gtau=35.15, kp=1.0, kv=1.0)
    savemat(tmp_path / "c.mat", {**good, "qm": np.zeros(n) + 1j})
    with pytest.raises(ValueError) as err:
        load_record(tmp_path / "c.mat")
    assert str(err.value) == f"{tmp_path / 'c.mat'}: variable qm must hold real numbers, not complex128"
    savemat(tmp_path / "g.mat", {**good, "gtau": np.nan})
    with pytest.raises(ValueError, match=r"g.mat: gtau must be finite, got nan$"):
        load_record(tmp_path / "g.mat")


def test_load_record_mat_missing_variables_and_folder(tmp_path):
    from scipy.io import savemat

    from fricctl.datasets import load_record

    savemat(tmp_path / "y.mat", {"t": np.arange(20.0)})
    with pytest.raises(ValueError, match="missing variable.*qm, qg, vir, gtau, kp, kv"):
        load_record(tmp_path / "y.mat")
    with pytest.raises(IsADirectoryError):
        load_record(tmp_path)


def test_encoder_grid():
    t = np.arange(50) * 0.001
    counts = np.cumsum(np.random.default_rng(3).integers(0, 4, 50))  # steps of 0..3 counts
    on_grid = Run(t=t, torque=np.zeros(50), position=1e-4 * counts + 0.3)
    assert on_grid.encoder_grid() == pytest.approx(1e-4, rel=1e-9)
    assert _run(position=np.sin(np.arange(100) * 0.002)).encoder_grid() is None


# -- patterns ---------------------------------------------------------------------------------
def _pattern_set(**kw):
    from fricctl.datasets import FrictionPatterns

    args = dict(tm=[0.1, 0.2, 0.3], omega=[0.0, 1.0, -1.0], friction=[0.1, 0.5, -0.5],
                at_rest=np.array([True, False, False]), units="linear", velocity_quantum=5e-5,
                meta={"source": "by hand"})
    args.update(kw)
    return FrictionPatterns(**args)


def test_patterns_round_trip_exact(tmp_path):
    from fricctl.datasets import write_patterns

    rng = np.random.default_rng(1)
    ps = _pattern_set(tm=rng.normal(size=40), omega=rng.normal(size=40),
                      friction=rng.normal(size=40), at_rest=rng.random(40) < 0.3)
    path = write_patterns(tmp_path / "p.csv", ps)
    tab = read_patterns(path)
    back = tab.patterns
    for name in ("tm", "omega", "friction", "at_rest"):
        np.testing.assert_array_equal(getattr(back, name), getattr(ps, name))  # %.17g: exact
    assert back.units == "linear" and back.velocity_quantum == 5e-5 and tab.has_at_rest
    assert back.meta["source"] == "by hand"
    assert "# columns: tm [N], omega [m/s], friction [N], at_rest [0/1]" in path.read_text()
    with pytest.raises(FileExistsError):
        write_patterns(path, ps, overwrite=False)


def test_three_column_patterns_still_read(tmp_path):
    p = tmp_path / "old.csv"
    p.write_text("tm,omega,friction\n1,2,3\n4,5,6\n")
    tab = read_patterns(p)
    assert not tab.has_at_rest and not tab.patterns.at_rest.any()
    assert tab.patterns.units == "rotary" and tab.patterns.velocity_quantum is None
    np.testing.assert_array_equal(tab["friction"], [3, 6])


@pytest.mark.parametrize("text, message", [
    ("tm,omega,friction,at_rest\n1,2,3,0\n4,5,6,0.5\n", "'at_rest' must hold 0 or 1, got 0.5 in data row 2"),
    ("# units: metric\ntm,omega,friction\n1,2,3\n4,5,6\n", "# units: must be one of rotary, linear"),
    ("# velocity_quantum: fast\ntm,omega,friction\n1,2,3\n4,5,6\n", "velocity_quantum: not a number"),
    ("# velocity_quantum: -1\ntm,omega,friction\n1,2,3\n4,5,6\n", "velocity_quantum must be > 0"),
    ("# velocity_quantum: nan\ntm,omega,friction\n1,2,3\n4,5,6\n", "velocity_quantum must be finite"),
    ("tm,omega,friction,at_rst\n1,2,3,0\n4,5,6,1\n", "unknown column 'at_rst'"),
])
def test_bad_patterns_file(tmp_path, text, message):
    p = tmp_path / "bad.csv"
    p.write_text(text)
    with pytest.raises(ValueError, match="bad.csv") as err:
        read_patterns(p)
    assert message in str(err.value)


def test_pattern_set_checks():
    with pytest.raises(ValueError, match="at_rest must be a boolean array"):
        _pattern_set(at_rest=np.array([1, 0, 0]))
    with pytest.raises(ValueError, match="omega must have 3 elements"):
        _pattern_set(omega=[0.0, 1.0])
    with pytest.raises(ValueError, match="velocity_quantum must be > 0"):
        _pattern_set(velocity_quantum=0.0)
    with pytest.raises(ValueError, match="cannot be a free"):
        _pattern_set(meta={"units": "rotary"})
    with pytest.raises(ValueError, match="friction holds NaN"):
        _pattern_set(friction=[0.0, np.nan, 1.0])


def test_record_patterns_by_hand():
    from fricctl.datasets import record_patterns

    # at rest for 200 samples, then a = 2 rad/s^2 under Tm = 1 N*m: with I = 0.25 the
    # friction is Tm - I*a = 0.5 N*m while moving and Tm = 1 N*m (the reaction) at rest
    n, ts = 600, 0.002
    t = np.arange(n) * ts
    tau = np.r_[np.full(200, 0.3), np.full(n - 200, 1.0)]
    q = np.where(np.arange(n) < 200, 0.0, (t - t[199]) ** 2)
    run = Run(t=t, torque=tau, position=q)
    p = record_patterns([run, run], inertia=0.25, estimator="savitzky_golay",
                        estimator_options=dict(window_length=11), border=5, guard=2)
    per = n - 10
    assert len(p) == 2 * per
    # at rest by hand: samples 2..197 have 2 equal neighbours each side; after the border, 5..197
    assert int(p.at_rest.sum()) == 2 * 193
    rest = p.at_rest[:per]
    np.testing.assert_array_equal(np.flatnonzero(rest) + 5, np.arange(5, 198))
    # well inside the motion the quadratic is exact for a cubic Savitzky-Golay filter
    inner = slice(300, per - 10)
    np.testing.assert_allclose(p.friction[:per][inner], 0.5, atol=1e-9)
    # at rest, away from the filter's reach of the start (5 samples): Tat = Tm exactly
    np.testing.assert_allclose(p.friction[:per][5:185], 0.3, atol=1e-9)
    with pytest.raises(ValueError, match="share their units"):
        record_patterns([run, _run(units="linear")], inertia=1.0)
    with pytest.raises(ValueError, match="inertia must be > 0"):
        record_patterns(run, inertia=-1.0)


def test_two_conflicting_units_lines_are_refused_naming_the_line(tmp_path):
    # issue 26: "# units: rotary" then "# units: linear": the last one won, silently
    body = "t,torque,position\n" + "".join(f"{k / 1000},0,{k}\n" for k in range(MIN_SAMPLES))
    p = tmp_path / "two.csv"
    p.write_text("# source: bench\n# units: rotary\n# relabelled by hand\n# units: linear\n" + body)
    with pytest.raises(ValueError, match=r"two.csv, line 4: '# units: linear' contradicts line 2 "
                                         r"\('# units: rotary'\)"):
        Run.from_csv(p)
    p.write_text("# units: linear\n# units: linear\n" + body)  # the same twice: no conflict
    assert Run.from_csv(p).units == "linear"
    pats = tmp_path / "pats.csv"
    pats.write_text("# velocity_quantum: 0.01\n# velocity_quantum: 0.02\ntm,omega,friction\n"
                    "1,1,1\n2,2,2\n")
    with pytest.raises(ValueError, match="line 2: '# velocity_quantum: 0.02' contradicts line 1"):
        read_patterns(pats)


@pytest.mark.parametrize("line,words", [
    ("# unit: linear", "line 2: unknown '# unit:' line (did you mean 'units'?)"),
    ("# Units: linear", "line 2: unknown '# Units:' line (did you mean 'units'?)"),
    ("# sorce: bench", "line 2: unknown '# sorce:' line (did you mean 'source'?); the '#' keys "
                       "of this file are source, units"),
])
def test_an_unknown_key_line_of_a_record_is_refused(tmp_path, line, words):
    # audit A 1: a misspelt "# unit: linear" was silently ignored and the record read as rotary
    body = "t,torque,position\n" + "".join(f"{k / 1000},0,{k}\n" for k in range(MIN_SAMPLES))
    p = tmp_path / "r.csv"
    p.write_text(f"# source: bench\n{line}\n" + body)
    with pytest.raises(ValueError, match="r.csv, " + re.escape(words)):
        Run.from_csv(p)
    # what Run.to_csv writes reads back, and a '#' line not read as a key is a free comment,
    # colons and all (review R11: comments with a colon were refused after audit A's fix)
    p.write_text("# source: bench: rig 2\n# recorded by hand\n# recorded 2026-11-28 10:15\n"
                 "# Note: gear 1:100\n# http://example.org/data\n# velocity_quantum: 0.1\n"
                 "# units: linear\n" + body)
    run = Run.from_csv(p)
    assert run.units == "linear" and run.source == "bench: rig 2"
    back = Run.from_csv(run.to_csv(tmp_path / "back.csv"))
    assert back.units == "linear" and back.source == "bench: rig 2"
    # a patterns file keeps other '#' lines as metadata: read_columns refuses only when told
    assert read_columns(p, required=("t",), optional=("torque", "position")).meta["units"]


@pytest.mark.parametrize("fast", [True, False])
def test_a_bad_time_in_a_csv_names_the_file_line(tmp_path, fast):
    # audit A 12: "row 500" counted samples from 0 where every other error names the file line
    rows = [f"{k / 1000},0,{k}" for k in range(40)]
    rows[20] = "0.0185,0,20" if fast else "0.0185,0, 20"  # a space: the line-by-line reader
    p = tmp_path / "t.csv"
    p.write_text("# source: bench\nt,torque,position\n" + "\n".join(rows[:10]) + "\n\n"
                 + "\n".join(rows[10:]) + "\n")  # a blank line: rows and lines part
    with pytest.raises(ValueError, match=r"t.csv, line 24, column 't': non-increasing time$"):
        Run.from_csv(p)
    rows[20] = "0.0205,0,20"
    p.write_text("t,torque,position\n" + "\n".join(rows) + "\n")
    with pytest.raises(ValueError, match=r"t.csv, line 22, column 't': non-uniform time step "
                                         r"\(0.0015 s against a median of 0.001 s\)"):
        Run.from_csv(p)


def test_a_bad_line_after_many_plain_rows_is_named_at_once(tmp_path):
    """The one-pass reader of plain rows must refuse a bad line in time linear in the file: a
    whole-number column (1500) once let its pattern split each cell several ways, so one
    short line after n rows cost ~4^n steps (a hang, not the error).  Run in a child process
    with a generous limit, so that a regression fails instead of stalling the suite."""
    import subprocess
    import sys

    p = tmp_path / "r.csv"
    rows = [f"{0.001 * i:.3f},1500,{i}" for i in range(3000)]
    p.write_text("t,torque,position\n" + "\n".join(rows) + "\n0.5,1.0\n")
    code = ("from fricctl.datasets import read_columns\n"
            "try:\n"
            f"    read_columns({str(p)!r}, required=('t', 'torque', 'position'))\n"
            "except ValueError as e:\n"
            "    print(e)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert "line 3002: 2 fields, the header has 3" in out.stdout, out.stdout + out.stderr
    # the same rows without the bad line: read in one pass, the same numbers as row by row
    p.write_text("t,torque,position\n" + "\n".join(rows) + "\n")
    tab = read_columns(p, required=("t", "torque", "position"))
    np.testing.assert_array_equal(tab["torque"], np.full(3000, 1500.0))
    np.testing.assert_array_equal(tab["position"], np.arange(3000.0))
