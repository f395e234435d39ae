"""Claims of the paper checked on the bench for one network.

A :class:`Claim` row holds the paper's words (with the tolerance used here made
explicit), the paper's value, the value measured here (a sentence, and the number
the criterion thresholds) and pass/fail; a claim the bench does not reproduce fails,
with the physical reason in ``note``.  A claim whose measurement involves the
network's compensation also requires the runaway checks of
:mod:`fricctl.paper.runaway` (:func:`gate`).  The claim makers live with their figure
(``figNN.py``); :func:`paper_claims` reaches them through the figure registry.  The
table over seeds and pipelines (``claims.md``, ``claims.json``) is
:mod:`fricctl.paper.table`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

from .. import _validate as v
from .registry import paper_figures
from .runaway import RunawayCheck

__all__ = ["Claim", "gate", "paper_claims", "claims_summary", "is_extra", "EXTRA"]

#: The ``paper`` value of a check of ours that is not a claim of the paper.
EXTRA = "not in the paper"
#: Runaway checks measured in an experiment of their own, by check name -> the claim that
#: reports that experiment (the network's coast test: a torque pulse, then Tc = 0).  Every
#: compensated claim requires it; the note of any other claim names it instead of repeating
#: its reason (a step test's note would otherwise read "after the pulse the joint ...").
REPORTED_BY = {"coast": "coast-decay"}


@dataclass(frozen=True, kw_only=True)
class Claim:
    """One claim of the paper checked on the bench, for one network.

    Attributes
    ----------
    id : short identifier
    claim : the paper's words, with the tolerance used here made explicit
    paper : the paper's value (:data:`EXTRA` for a check of ours)
    measured : the value measured here, as a sentence (with units)
    passed : whether the measured value meets the claim as stated and, for a claim whose
        measurement involves compensation, every runaway check in ``checks`` passes
    figure : the figure it belongs to, e.g. "Fig. 9"
    value : the number the claim's criterion thresholds, in ``unit`` (``nan`` where it is
        undefined, ``inf`` where it is unbounded; ``note`` then says why)
    unit : the unit of ``value`` (``"deg"``, ``"%"``, ``"counts"``, ``"-"`` ...)
    note : why it fails (or what to know when it passes)
    checks : the runaway checks the claim required (:func:`gate`), empty for a claim
        without compensation
    """

    id: str
    claim: str
    paper: str
    measured: str
    passed: bool
    figure: str
    value: float
    unit: str
    note: str = ""
    checks: tuple = ()

    def __post_init__(self):
        for name in ("id", "claim", "paper", "measured", "figure", "unit", "note"):
            v.text(f"Claim.{name}", getattr(self, name))
        object.__setattr__(self, "value", v.real("Claim.value", self.value, finite=False))
        # numpy comparisons give numpy.bool_, which JSON does not accept
        object.__setattr__(self, "passed", bool(self.passed))
        checks = v.instance("Claim.checks", self.checks, tuple, "a tuple")
        for c in checks:
            v.instance("Claim.checks", c, RunawayCheck, "a tuple of RunawayCheck")
        if self.passed and any(not c.passed for c in checks):
            raise ValueError(f"claim {self.id} passes with a failed runaway check: use gate()")

    @property
    def runaway(self) -> bool:
        """True when one of the runaway checks the claim required failed."""
        return any(not c.passed for c in self.checks)

    def as_dict(self) -> dict:
        """JSON-ready: the fields, ``value`` None where it is not finite, the checks as objects."""
        d = {f.name: getattr(self, f.name) for f in fields(self) if f.name != "checks"}
        d["value"] = self.value if math.isfinite(self.value) else None
        d["checks"] = [c.as_dict() for c in self.checks]
        return d


def gate(claim: Claim, checks) -> Claim:
    """``claim`` with the runaway checks it requires: it fails if any of them fails.

    A claim whose measurement involves the network's compensation holds only if the
    compensated joint followed its control torque (:mod:`fricctl.paper.runaway`).  A
    failed check makes the claim fail, with ``"runaway: <reason>"`` first in its note
    (followed by the claim's own note, if its own criterion failed too); a failed check of
    another experiment (:data:`REPORTED_BY`: the coast test) is named with the claim that
    reports it, not described.

    Parameters
    ----------
    claim : Claim
        As its maker judged it on its own criterion (no checks yet).
    checks : iterable of RunawayCheck

    Returns
    -------
    Claim
    """
    v.instance("claim", claim, Claim)
    checks = tuple(checks)
    for c in checks:
        v.instance("checks", c, RunawayCheck, "RunawayCheck objects")
    failed = [c for c in checks if not c.passed]
    if not failed:
        return replace(claim, checks=claim.checks + checks)
    # a check of another experiment (the coast test's pulse) is named, not described: its
    # reason is not about this claim's run
    own = [c for c in failed if REPORTED_BY.get(c.name, claim.id) == claim.id]
    # one reason per kind of check: a claim made of several runs (Fig. 14's eight steps) would
    # otherwise repeat the same sentence for each
    by_name: dict[str, list] = {}
    for c in own:
        by_name.setdefault(c.name, []).append(c)
    reasons = [cs[0].reason.removeprefix("runaway: ")
               + (f" (and in {len(cs) - 1} more of its runs)" if len(cs) > 1 else "")
               for cs in by_name.values()]
    reasons += [f"the network fails its {c.name} test (claim {REPORTED_BY[c.name]}), which every "
                "claim measured with compensation requires" for c in failed if c not in own]
    runaway = "runaway: " + "; ".join(reasons) + "."
    if claim.passed:
        note = runaway + (" Its own criterion was met, by a joint that did not follow its control "
                          "torque." if own else " Its own criterion was met.")
    else:
        note = runaway + (" " + claim.note[:1].upper() + claim.note[1:] if claim.note else "")
    return replace(claim, passed=False, note=note, checks=claim.checks + checks)


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


def paper_claims(figures: dict, bench=None) -> list[Claim]:
    """Claims from figure results (``{4: Fig4Result, ...}``); missing figures are skipped.

    The claim makers of each figure come from its registry entry
    (:func:`~fricctl.paper.paper_figures`), in figure order.  ``bench`` is the bench the
    figures ran on (:func:`fricctl.paper.benches.as_bench`: a name, a Bench, an
    ActuatorParams -- the settings of ``PARAMS_BENCH`` on that plant --, or None: the default
    bench).
    """
    from .benches import as_bench

    b = as_bench(bench)
    registry = paper_figures()
    out = []
    for num in sorted(figures):
        if num in registry:
            out += registry[num].make_claims(figures[num], b)
    return out
