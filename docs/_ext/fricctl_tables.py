"""Tables the book builds from fricctl's registries (no Sphinx needed: the tests import it)."""

from __future__ import annotations

#: Where docs/model_file.md lists the friction coefficients (read from the law registry).
COEFFICIENTS_PLACEHOLDER = "<!-- fricctl: friction coefficients -->"


def coefficients_table() -> str:
    """Markdown table of every registered friction law's coefficients (name, unit, default, law)."""
    from fricctl.friction import LAWS

    rows = ["| key under `friction` | unit (rotary) | default | law | what it is |",
            "|---|---|---|---|---|"]
    for law in LAWS.values():
        for c in law.coefficients:
            rows.append(f"| `{c.name}` | `{c.unit}` | {c.default:g} | `{law.name}` | {c.doc} |")
    return "\n".join(rows)
