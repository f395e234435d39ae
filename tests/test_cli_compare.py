"""Tests of ``fricctl compare`` (a small table without trained networks, into temporary folders)."""

from __future__ import annotations

import json

import pytest

from fricctl.cli import main
from fricctl.compare import EXPERIMENTS, METRICS, check_plant

SMALL = ["--compensators", "none,coulomb", "--experiments", "coast,limit_cycle", "--plants",
         "nominal,friction_1.2", "--seeds", "2", "--quiet"]


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    import contextlib
    import io

    out = tmp_path_factory.mktemp("compare") / "out"
    stdout, stderr = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
        code = main(["compare", "--out", str(out)] + SMALL)
    return out, code, stdout.getvalue(), stderr.getvalue()


def test_compare_writes_one_row_per_compensator_experiment_and_plant(written):
    out, code, stdout, stderr = written
    assert code == 0 and stderr == ""  # --quiet: no progress bar
    d = json.loads((out / "comparison.json").read_text())
    rows = d["rows"]
    assert len(rows) == 2 * 2 * 2
    assert {(r["compensator"], r["experiment"], r["plant"]["name"]) for r in rows} == {
        (c, e, p) for c in ("none", "coulomb") for e in ("coast", "limit_cycle")
        for p in ("nominal", "friction_1.2")}
    for r in rows:
        assert r["plant"] == check_plant(r["plant"]["name"])  # the plant as an object
        assert tuple(r["metrics"]) == EXPERIMENTS[r["experiment"]].metrics
        assert all(m["unit"] == METRICS[k][0] for k, m in r["metrics"].items())
        assert r["seeds"] == [0]  # neither depends on the seed: run once, whatever --seeds says
    md = (out / "comparison.md").read_text()
    assert "## coast:" in md and "## limit_cycle:" in md
    assert "8 rows" in stdout and "comparison.json and comparison.md" in stdout


def test_compare_refuses_to_overwrite_without_force(written, tmp_path, capsys):
    out, *_ = written
    before = (out / "comparison.json").read_bytes()
    assert main(["compare", "--out", str(out)] + SMALL) == 2
    err = capsys.readouterr().err
    assert "already holds comparison.json" in err and "--force" in err and err.count("\n") == 1
    assert (out / "comparison.json").read_bytes() == before
    # --force replaces both files with the new run's (another table)
    assert main(["compare", "--out", str(out), "--force", "--compensators", "none", "--experiments",
                 "coast", "--plants", "nominal", "--quiet"]) == 0
    capsys.readouterr()
    assert len(json.loads((out / "comparison.json").read_text())["rows"]) == 1


@pytest.mark.parametrize("argv, match", [
    (["--seeds", "0"], "--seeds must be between 1"),
    (["--seeds", "two"], "--seeds must be a whole number"),
    (["--compensators", "none,bogus"], "--compensators: unknown name 'bogus'"),
    (["--compensators", "none,none"], "twice"),
    (["--experiments", ""], "names separated by commas"),
    (["--plants", "mars"], "--plants: unknown name 'mars'"),
    (["--bench", "bogus"], "--bench: unknown bench"),
    (["--executor", "gpu"], "--executor must be one of serial, process, dask"),
    (["--workers", "2"], "--workers needs --executor process or dask"),
    (["--executor", "process", "--workers", "0"], "--workers must be between 1"),
    (["--scheduler", "tcp://x:8786", "--executor", "process"], "needs --executor dask"),
    (["--scheduler", "tcp://x:8786", "--workers", "2"], "give one or the other"),
    (["--scheduler", " "], "--scheduler needs an address"),
    (["--sigma0", "-5"], "--sigma0 must be > 0 N*m/rad, got -5.0"),
    (["--sigma0", "nan"], "--sigma0 must be finite"),
    (["--sigma0", "soft"], "--sigma0: 'soft' is not a number"),
    (["--sigma0", "2e4N*s/m"], "--sigma0: unknown unit 'N*s/m'"),
    (["--sigma1", "-0.5"], "--sigma1 must be >= 0 N*m*s/rad, got -0.5"),
    (["--compensators", "none,dob", "--sigma0", "2e4"], "--sigma0 has no effect: it is lugre_observer's"),
])
def test_compare_bad_arguments_exit_2_with_one_line(argv, match, tmp_path, capsys):
    code = main(["compare", "--out", str(tmp_path / "o")] + argv)
    assert code == 2
    err = capsys.readouterr().err
    assert match in err and err.count("\n") == 1
    assert not (tmp_path / "o").exists()


def test_compare_out_is_a_file(tmp_path, capsys):
    f = tmp_path / "file.txt"
    f.write_text("x")
    assert main(["compare", "--out", str(f)] + SMALL) == 2
    assert "not a folder" in capsys.readouterr().err


def test_compare_into_a_missing_folder_is_refused(tmp_path, capsys):
    # audit C24 2: --out nodir/out made nodir too, after the whole run; every other output's
    # folder must exist (the default, ./fricctl-compare, goes into the working folder)
    out = tmp_path / "nodir" / "out"
    assert main(["compare", "--out", str(out)] + SMALL) == 2
    err = capsys.readouterr().err
    assert err == f"fricctl compare: error: --out: the folder {out.parent} does not exist\n"
    assert list(tmp_path.iterdir()) == []


@pytest.mark.slow
def test_compare_on_processes_and_dask_writes_the_serial_file(written, tmp_path, capsys):
    pytest.importorskip("distributed")
    out, *_ = written
    serial = tmp_path / "serial"
    assert main(["compare", "--out", str(serial)] + SMALL) == 0
    for kind in ("process", "dask"):
        assert main(["compare", "--out", str(tmp_path / kind), "--executor", kind, "--workers", "2"]
                    + SMALL) == 0
        assert (tmp_path / kind / "comparison.json").read_bytes() == (serial / "comparison.json").read_bytes()


def test_compare_sigma0_reaches_the_lugre_observer(tmp_path, capsys, monkeypatch):
    # --sigma0/--sigma1 (a unit suffix accepted) become the observer's options of compare(), and
    # the observer the rows ran is built with them (make_contender with the same options)
    import fricctl.compare as fc

    seen = {}
    real = fc.compare

    def spy(**kw):
        seen.update(kw["options"])
        return real(**kw)

    monkeypatch.setattr(fc, "compare", spy)
    assert main(["compare", "--out", str(tmp_path / "o"), "--compensators", "lugre_observer", "--experiments",
                 "pd_steps", "--plants", "nominal", "--quiet", "--sigma0", "2e4 N*m/rad", "--sigma1", "1.5"]) == 0
    capsys.readouterr()
    assert seen == {"lugre_observer": {"sigma0": 2e4, "sigma1": 1.5}}
    from fricctl.compare import make_contender
    from fricctl.paper.benches import DEFAULT_BENCH, bench
    from fricctl.paper.common import designs

    b = bench(DEFAULT_BENCH)
    obs = make_contender("lugre_observer", b.model, designs(b)["fig13-14"], b.actuator.sample_time,
                         options=seen["lugre_observer"])
    assert (obs.sigma0, obs.sigma1) == (2e4, 1.5)
