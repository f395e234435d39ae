"""The README's generated tables are what the code computes now; the quick start is wired up."""
from pathlib import Path

from fricctl import _readme

ROOT = Path(__file__).resolve().parents[1]


def test_generated_blocks_are_current():
    text = (ROOT / "README.md").read_text()
    assert _readme.render(text) == text, "README tables are stale: run `python -m fricctl._readme`"


def test_quick_start_commands_exist():
    text = (ROOT / "README.md").read_text()
    assert "make reproduce" in text and "make test" in text
    makefile = (ROOT / "Makefile").read_text()
    assert "\nreproduce:" in makefile and "\ntest:" in makefile
    ci = (ROOT / ".ci" / "run").read_text()
    assert "make test" in ci and "FRICCTL_DATA" in ci
