"""Claims of the paper checked on the bench, and the claims table (``claims.md``, ``claims.json``).

A :class:`Claim` row holds the paper's words (with the tolerance used here made
explicit), the paper's value, the value measured here and pass/fail; a claim the
bench does not reproduce fails, with the physical reason in ``note``.  The claim
makers live with their figure (``figNN.py``); :func:`paper_claims` reaches them
through the figure registry.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass

from .. import _validate as v
from ..params import ActuatorParams, paper_actuator
from .registry import paper_figures

__all__ = ["Claim", "paper_claims", "claims_markdown", "claims_json", "claims_summary", "is_extra",
           "EXTRA"]

#: The ``paper`` value of a check of ours that is not a claim of the paper.
EXTRA = "not in the paper"


@dataclass(frozen=True, kw_only=True)
class Claim:
    """One claim of the paper checked on the bench.

    Attributes
    ----------
    id : short identifier
    claim : the paper's words, with the tolerance used here made explicit
    paper : the paper's value (:data:`EXTRA` for a check of ours)
    measured : the value measured here (with units)
    passed : whether the measured value meets the claim as stated
    figure : the figure it belongs to, e.g. "Fig. 9"
    note : why it fails (or what to know when it passes)
    """

    id: str
    claim: str
    paper: str
    measured: str
    passed: bool
    figure: str
    note: str = ""

    def __post_init__(self):
        for name in ("id", "claim", "paper", "measured", "figure", "note"):
            v.text(f"Claim.{name}", getattr(self, name))
        # numpy comparisons give numpy.bool_, which JSON does not accept
        object.__setattr__(self, "passed", bool(self.passed))

    def as_dict(self) -> dict:
        return asdict(self)


def is_extra(claim: Claim) -> bool:
    """True for a check of ours that is not a claim of the paper."""
    return claim.paper == EXTRA


def claims_summary(claims) -> str:
    """``"N of M claims of the paper reproduced"``, with the extras counted apart."""
    claims = list(claims)
    paper_c = [c for c in claims if not is_extra(c)]
    extra = [c for c in claims if is_extra(c)]
    s = f"{sum(c.passed for c in paper_c)} of {len(paper_c)} claims of the paper reproduced"
    if extra:
        s += f" (extras, not in the paper: {sum(c.passed for c in extra)} of {len(extra)} pass)"
    return s


def paper_claims(figures: dict, params: ActuatorParams | None = None) -> list[Claim]:
    """Claims from figure results (``{4: Fig4Result, ...}``); missing figures are skipped.

    The claim makers of each figure come from its registry entry
    (:func:`~fricctl.paper.paper_figures`), in figure order.
    """
    p = paper_actuator() if params is None else params
    registry = paper_figures()
    out = []
    for num in sorted(figures):
        if num in registry:
            out += registry[num].make_claims(figures[num], p)
    return out


def _md(s: str) -> str:
    return s.replace("|", "\\|").replace("\n", " ")


def claims_markdown(claims, *, title: str = "Claims of Gervini, Gomes & da Rosa (2003) on the virtual bench",
                    preamble: str = "") -> str:
    """``claims.md``: the table, a summary line and the "not reproduced, and why" section."""
    claims = list(claims)
    lines = [f"# {title}", ""]
    if preamble:
        lines += [preamble, ""]
    lines += [f"**{claims_summary(claims)}.**", "",
              "| id | claim | paper | measured | pass/fail | figure |", "|---|---|---|---|---|---|"]
    for c in claims:
        lines.append(f"| {c.id} | {_md(c.claim)} | {_md(c.paper)} | {_md(c.measured)} | "
                     f"{'pass' if c.passed else '**FAIL**'} | {c.figure} |")
    failed = [c for c in claims if not c.passed]
    lines += ["", "## Not reproduced, and why", ""]
    lines += [f"- **{c.id}** ({c.figure}): {c.note}" for c in failed] or ["Every claim was reproduced."]
    notes = [c for c in claims if c.passed and c.note]
    if notes:
        lines += ["", "## Notes on claims that pass", ""]
        lines += [f"- **{c.id}** ({c.figure}): {c.note}" for c in notes]
    return "\n".join(lines) + "\n"


def claims_json(claims) -> str:
    """``claims.json``: a list of objects with id, claim, paper, measured, passed, figure (and note)."""
    return json.dumps([c.as_dict() for c in claims], indent=2)
