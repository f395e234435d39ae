"""Tables the book builds from fricctl's registries (no Sphinx needed: the tests import it).

``python docs/_ext/fricctl_tables.py`` rewrites the generated block of docs/model_file.md, so
that the page lists every friction coefficient where it is read (GitHub, an editor), not only
in the built book; tests/test_cli_model.py checks that the committed block is current.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

#: Where docs/model_file.md lists the friction coefficients (read from the law registry): the
#: lines between the two markers are :func:`coefficients_table`.
COEFFICIENTS_BEGIN = "<!-- BEGIN friction-coefficients (python docs/_ext/fricctl_tables.py) -->"
COEFFICIENTS_END = "<!-- END friction-coefficients -->"


def coefficients_table() -> str:
    """Markdown table of every registered friction law's coefficients (name, unit, default, law)."""
    from fricctl.friction import LAWS

    rows = ["| key under `friction` | unit (rotary / linear) | default | law | what it is |",
            "|---|---|---|---|---|"]
    for law in LAWS.values():
        for c in law.coefficients:
            rows.append(f"| `{c.name}` | `{c.unit}` / `{linear_unit(c.unit, c.name)}` | {c.default:g} | "
                        f"`{law.name}` | {c.doc} |")
    return "\n".join(rows)


def linear_unit(unit: str, name: str = "") -> str:
    """A coefficient's unit on a linear axis: a torque [N*m] is a force [N], a position [rad] a
    displacement [m] (``N*m*s/rad`` -> ``N*s/m``; fricctl.units.UNITS).  A phase (``*_phase``)
    is the angle of a sine, not a position: [rad] on both axes."""
    if name.endswith("_phase"):
        return unit
    return unit.replace("N*m", "N").replace("rad", "m")


def render_coefficients(text: str) -> str:
    """``text`` (docs/model_file.md) with its coefficients block holding the current table."""
    pattern = re.compile(rf"({re.escape(COEFFICIENTS_BEGIN)}\n)(?:.*?\n)?({re.escape(COEFFICIENTS_END)})",
                         re.S)
    if not pattern.search(text):
        raise ValueError(f"no block {COEFFICIENTS_BEGIN} ... {COEFFICIENTS_END}")
    return pattern.sub(lambda m: m.group(1) + coefficients_table() + "\n" + m.group(2), text)


if __name__ == "__main__":  # pragma: no cover
    page = Path(__file__).resolve().parents[1] / "model_file.md"
    page.write_text(render_coefficients(page.read_text(encoding="utf-8")), encoding="utf-8")
    sys.exit(0)
