"""Tests of ``fricctl reproduce`` (fast mode, into a temporary folder)."""

from __future__ import annotations

import json
import re

import pytest

from fricctl.cli import main


def test_reproduce_fast_writes_everything(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["reproduce", "--out", str(out), "--fast", "--seed", "0"]) == 0  # 0 even with failing claims
    captured = capsys.readouterr()
    pngs = sorted(p.name for p in out.glob("*.png"))
    assert pngs == sorted([f"fig{n:02d}.png" for n in (4, 5, 8, 9, 10, 11, 12, 13, 14, 16, 17, 18)]
                          + ["sweep.png"])
    assert all((out / n).stat().st_size > 1000 for n in pngs)
    claims = json.loads((out / "claims.json").read_text())
    assert isinstance(claims, list) and len(claims) >= 16
    for c in claims:
        assert {"id", "claim", "paper", "measured", "passed", "figure"} <= set(c)
        assert isinstance(c["passed"], bool)
    paper_claims = [c for c in claims if c["paper"] != "not in the paper"]
    n, m = sum(c["passed"] for c in paper_claims), len(paper_claims)
    assert 0 < n < m  # the bench reproduces some claims and reports others as failing
    assert f"{n} of {m} claims of the paper reproduced" in captured.out
    md = (out / "claims.md").read_text()
    assert "| id | claim | paper | measured | pass/fail | figure |" in md
    assert "Not reproduced, and why" in md
    for c in claims:
        assert f"| {c['id']} |" in md
    # the progress line goes to stderr and ends at the last step
    assert re.search(r"\d+/(\d+) done", captured.err)


@pytest.mark.parametrize("argv", [["reproduce", "--seed", "-1"], ["reproduce", "--seed", "x"],
                                  ["reproduce", "--bogus"]])
def test_reproduce_bad_arguments_exit_2(argv, tmp_path, capsys):
    try:
        code = main(argv + ["--out", str(tmp_path / "o")])
    except SystemExit as exc:  # argparse rejects unknown or ill-typed options itself
        code = exc.code
    assert code == 2
    assert "error" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_reproduce_out_is_a_file(tmp_path, capsys):
    f = tmp_path / "file.txt"
    f.write_text("x")
    assert main(["reproduce", "--out", str(f), "--fast"]) == 2
    assert "not a folder" in capsys.readouterr().err
