"""The claims table over seeds and pipelines: ``claims.md`` and ``claims.json``.

A claim about a trained network is a claim about training seeds.  For each claim
and pipeline, :func:`aggregate_claims` collects the per-seed verdicts into a
:class:`ClaimStats`: the pass rate over seeds, the median / min / max of the number
the claim's criterion thresholds, and how many seeds failed by runaway.  A claim
*holds* for a pipeline when it passes in at least :data:`HOLD_RATE` of the seeds.
"""

from __future__ import annotations

import json
import math
import re
from dataclasses import dataclass
from typing import Mapping, Sequence

import numpy as np

from .. import _validate as v
from .claims import EXTRA, Claim, is_extra

__all__ = ["HOLD_RATE", "ClaimStats", "aggregate_claims", "representative_seed", "holds_summary",
           "claims_markdown", "claims_json", "benches_glance"]

#: A claim holds for a pipeline when it passes in at least this fraction of seeds [-].
HOLD_RATE = 0.9


@dataclass(frozen=True, kw_only=True)
class ClaimStats:
    """One claim of one pipeline over the training seeds.

    Attributes
    ----------
    pipeline : ``"paper"`` or ``"fricctl"``
    claims : the claim of each seed, in seed order
    seeds : the seeds [-]
    representative : the seed whose figures are shown [-]
    """

    pipeline: str
    claims: tuple
    seeds: tuple
    representative: int

    def __post_init__(self):
        v.text("pipeline", self.pipeline, empty=False)
        if not self.claims or len(self.claims) != len(self.seeds):
            raise ValueError("ClaimStats needs one claim per seed, at least one")
        for c in self.claims:
            v.instance("claims", c, Claim, "Claim objects")
        if len({c.id for c in self.claims}) != 1:
            raise ValueError(f"ClaimStats mixes claims {sorted({c.id for c in self.claims})}")
        for s in self.seeds:
            v.integer("seeds", s, low=0)
        if self.representative not in self.seeds:
            raise ValueError(f"representative seed {self.representative} is not one of {self.seeds}")

    # -- what every seed shares --------------------------------------------
    @property
    def first(self) -> Claim:
        return self.claims[0]

    @property
    def id(self) -> str:
        return self.first.id

    @property
    def figure(self) -> str:
        return self.first.figure

    @property
    def unit(self) -> str:
        return self.first.unit

    @property
    def extra(self) -> bool:
        """A check of ours, not a claim of the paper."""
        return is_extra(self.first)

    @property
    def shown(self) -> Claim:
        """The representative seed's claim (its measured sentence is the table's)."""
        return self.claims[self.seeds.index(self.representative)]

    # -- over seeds ---------------------------------------------------------
    @property
    def n_seeds(self) -> int:
        return len(self.claims)

    @property
    def n_passed(self) -> int:
        return sum(c.passed for c in self.claims)

    @property
    def pass_rate(self) -> float:
        """Fraction of seeds in which the claim passes [-]."""
        return self.n_passed / self.n_seeds

    @property
    def holds(self) -> bool:
        """Passes in at least :data:`HOLD_RATE` of the seeds."""
        return self.pass_rate >= HOLD_RATE - 1e-12

    @property
    def runaway_failures(self) -> int:
        """Seeds in which a runaway check failed (the claim fails there, whatever its criterion)."""
        return sum(c.runaway for c in self.claims)

    @property
    def values(self) -> np.ndarray:
        """The measured number of each seed, in ``unit``."""
        return np.array([c.value for c in self.claims], dtype=float)

    def _stat(self, fn) -> float:
        x = self.values
        x = x[~np.isnan(x)]
        return float(fn(x)) if x.size else math.nan

    @property
    def median(self) -> float:
        """Median of the measured number over the seeds where it is defined (``nan`` if none)."""
        return self._stat(np.median)

    @property
    def minimum(self) -> float:
        return self._stat(np.min)

    @property
    def maximum(self) -> float:
        return self._stat(np.max)

    @property
    def note(self) -> str:
        """Why it fails: the representative seed's note if it fails there, else that of the first
        failing seed; the representative's note otherwise.  Over several seeds a failing note
        names its seed (its numbers are that seed's, not the table's median)."""
        if self.n_passed == self.n_seeds:
            return self.shown.note
        if not self.shown.passed:
            return f"(seed {self.representative}) {self.shown.note}" if self.n_seeds > 1 \
                else self.shown.note
        seed, c = next((s, c) for s, c in zip(self.seeds, self.claims) if not c.passed)
        return f"(seed {seed}) {c.note}"

    def as_dict(self) -> dict:
        """One object of ``claims.json`` (``allow_nan=False``: non-finite numbers become None, and
        ``undefined`` says why)."""
        shown = self.shown
        undefined = {}

        def finite(name, x):
            if math.isfinite(x):
                return x
            undefined[name] = _why_undefined(x, self)
            return None

        return {
            "id": self.id, "claim": shown.claim, "paper": shown.paper, "measured": shown.measured,
            "passed": self.holds, "figure": self.figure, "note": self.note, "pipeline": self.pipeline,
            "n_seeds": self.n_seeds, "n_passed": self.n_passed, "pass_rate": self.pass_rate,
            "measured_median": finite("measured_median", self.median),
            "measured_min": finite("measured_min", self.minimum),
            "measured_max": finite("measured_max", self.maximum),
            "unit": self.unit, "runaway_failures": self.runaway_failures,
            "representative_seed": self.representative,
            "checks": [c.as_dict() for c in shown.checks],
            "seeds": [{"seed": s, "passed": c.passed, "runaway": c.runaway,
                       "value": c.value if math.isfinite(c.value) else None}
                      for s, c in zip(self.seeds, self.claims)],
            "undefined": undefined,
        }


def _why_undefined(x: float, stats: ClaimStats) -> str:
    if math.isnan(x):
        return "the measured number is undefined in every seed (see note)"
    bad = [s for s, c in zip(stats.seeds, stats.claims) if math.isinf(c.value)]
    return f"unbounded ({'+' if x > 0 else '-'}inf) in seed(s) {', '.join(map(str, bad))}"


def representative_seed(n_passed: Mapping[int, int]) -> int:
    """The seed whose number of claims passed is closest to the median over seeds (lowest seed on ties).

    Examples
    --------
    >>> representative_seed({0: 14, 1: 17, 2: 15, 3: 15})
    2
    """
    if not n_passed:
        raise ValueError("representative_seed needs at least one seed")
    med = float(np.median(list(n_passed.values())))
    return min(n_passed, key=lambda s: (abs(n_passed[s] - med), s))


def aggregate_claims(per_seed: Mapping[tuple, Sequence[Claim]],
                     representative: Mapping[str, int]) -> tuple:
    """Per claim and pipeline over seeds.

    Parameters
    ----------
    per_seed : mapping
        ``(pipeline, seed) -> claims`` of that network (every seed of a pipeline gives the
        same claim ids in the same order).
    representative : mapping
        ``pipeline -> seed`` whose figures are shown.

    Returns
    -------
    tuple of ClaimStats
        In claim order, pipelines in the order first met, for each claim.
    """
    pipelines: dict[str, list] = {}
    for (pipeline, seed), claims in per_seed.items():
        pipelines.setdefault(pipeline, []).append((seed, list(claims)))
    out = []
    order: list[str] = []
    by_key = {}
    for pipeline, runs in pipelines.items():
        runs.sort(key=lambda r: r[0])
        ids = [c.id for c in runs[0][1]]
        for seed, claims in runs[1:]:
            if [c.id for c in claims] != ids:
                raise ValueError(f"{pipeline} seed {seed} gives claims {[c.id for c in claims]}, "
                                 f"seed {runs[0][0]} gives {ids}")
        if pipeline not in representative:
            raise ValueError(f"no representative seed for pipeline {pipeline!r}")
        for i, cid in enumerate(ids):
            if cid not in order:
                order.append(cid)
            by_key[(cid, pipeline)] = ClaimStats(
                pipeline=pipeline, claims=tuple(c[i] for _, c in runs), seeds=tuple(s for s, _ in runs),
                representative=representative[pipeline])
    for cid in order:
        out += [by_key[(cid, p)] for p in pipelines if (cid, p) in by_key]
    return tuple(out)


def holds_summary(stats, pipeline: str) -> str:
    """``"N of M claims of the paper hold in >= 90 % of seeds (extras: n of m)"`` for one pipeline."""
    mine = [s for s in stats if s.pipeline == pipeline]
    if not mine:
        raise ValueError(f"no claims of pipeline {pipeline!r}")
    own = [s for s in mine if not s.extra]
    extra = [s for s in mine if s.extra]
    n = mine[0].n_seeds
    text = (f"{sum(s.holds for s in own)} of {len(own)} claims of the paper hold in >= "
            f"{100 * HOLD_RATE:.0f} % of {n} seed{'s' if n != 1 else ''}")
    if extra:
        text += f" (extras, not in the paper: {sum(s.holds for s in extra)} of {len(extra)})"
    return text


#: A product written ``a*b`` (``N*m``, ``1.1*Fs``, ``b*w``): the star between two characters
#: of an expression, which Markdown would read as the start or end of an emphasis.
_PRODUCT = re.compile(r"(?<=[\w).‖])\*(?=[\w(.‖])")


def _text(s: str) -> str:
    """A claim's sentence on one line; a norm ``||x||`` written ``‖x‖``, a product ``a*b``
    written ``a·b`` (Markdown would set ``N*m ... b*w`` in italics).

    Examples
    --------
    >>> _text("0.090 N*m = 1.1*Fs, I*dw/dt = Tc - b*w, 100*(1 - ||e||)")
    '0.090 N·m = 1.1·Fs, I·dw/dt = Tc - b·w, 100·(1 - ‖e‖)'
    """
    return _PRODUCT.sub("·", s.replace("\n", " ").replace("||", "‖"))


def _cell_text(s: str) -> str:
    """A sentence for a Markdown table cell that reads the same as plain text: an absolute
    value ``|x|`` becomes ``abs(x)`` (a '|' would end the cell, and its escape ``\\|`` shows
    in plain text), a norm ``‖x‖``.

    Examples
    --------
    >>> _cell_text("fit 100*(1 - ||e||/||y||); |w(t)| <= |w_end|")
    'fit 100·(1 - ‖e‖/‖y‖); abs(w(t)) <= abs(w_end)'
    """
    s = re.sub(r"\|([^|]+?)\|", r"abs(\1)", _text(s))
    return s.replace("|", "/")  # an unpaired bar (none in the claims' texts) is no cell border


def _num(x: float) -> str:
    if math.isnan(x):
        return "undefined"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    return f"{x:.3g}"


def _seeds(s: ClaimStats) -> str:
    """``met in 9 of 10 seeds, the compensated joint ran away in 1``."""
    ran = (f", the compensated joint ran away in {s.runaway_failures}" if s.runaway_failures
           else "")
    return f"met in {s.n_passed} of {s.n_seeds} seed{'s' if s.n_seeds != 1 else ''}{ran}"


def _cell(s: ClaimStats) -> str:
    verdict = "reproduced" if s.holds else "**not reproduced**"
    spread = (f"{_num(s.median)} {s.unit}" if s.n_seeds == 1 else
              f"median {_num(s.median)} [{_num(s.minimum)}, {_num(s.maximum)}] {s.unit}")
    return f"{verdict}: {_seeds(s)}; {spread}"


def _glance(s: ClaimStats) -> str:
    """``reproduced, 10 of 10`` or ``**not reproduced**, 0 of 10 (ran away in 2)``."""
    return _glance_text(s.holds, s.n_passed, s.n_seeds, s.runaway_failures)


def _glance_text(holds: bool, n_passed: int, n_seeds: int, runaway: int) -> str:
    ran = f" (ran away in {runaway})" if runaway else ""
    verdict = "reproduced" if holds else "**not reproduced**"
    return f"{verdict}, {n_passed} of {n_seeds}{ran}"


#: The keys of a ``claims.json`` object that :func:`benches_glance` reads.
_GLANCE_KEYS = ("id", "pipeline", "paper", "figure", "passed", "n_passed", "n_seeds",
                "runaway_failures", "bench")


def benches_glance(claims: Mapping[str, Sequence[Mapping]]) -> str:
    """The at-a-glance table of several benches side by side (issue 22): one row per claim,
    one column per bench and pipeline, each cell as in ``claims.md``'s own "At a glance"
    (the verdict, in how many seeds the claim was met, runaways), and a last row counting the
    claims of the paper reproduced in each column (extras apart).

    Parameters
    ----------
    claims : mapping
        Bench name -> the objects of the ``claims.json`` that ``fricctl reproduce --bench
        NAME`` wrote (:func:`claims_json`), in the column order wanted.  Each object must name
        that bench (a folder of another bench is refused).

    Returns
    -------
    str
        A Markdown table.  A claim a column did not rate reads ``--``.

    Examples
    --------
    >>> row = {"id": "fig9-stick", "pipeline": "fricctl", "paper": "sticks without", "figure":
    ...        "Fig. 9", "passed": True, "n_passed": 2, "n_seeds": 2, "runaway_failures": 0}
    >>> print(benches_glance({"consistent": [{**row, "bench": "consistent"}],
    ...                       "literal": [{**row, "bench": "literal", "passed": False,
    ...                                    "n_passed": 0, "runaway_failures": 2}]}))
    | claim | figure | consistent bench, fricctl pipeline | literal bench, fricctl pipeline |
    |---|---|---|---|
    | fig9-stick | Fig. 9 | reproduced, 2 of 2 | **not reproduced**, 0 of 2 (ran away in 2) |
    | **claims of the paper reproduced** | | **1 of 1** | **0 of 1** |
    """
    if not claims:
        raise ValueError("benches_glance needs the claims of at least one bench")
    by, ids, columns, first = {}, [], [], {}
    for bench, rows in claims.items():
        v.text("bench", bench, empty=False)
        if not rows:
            raise ValueError(f"claims of bench {bench!r}: empty")
        for row in rows:
            missing = [k for k in _GLANCE_KEYS if k not in row]
            if missing:
                raise ValueError(f"claims of bench {bench!r}: an object without {missing[0]!r} "
                                 f"(not a claims.json of fricctl reproduce?)")
            if row["bench"] != bench:
                raise ValueError(f"claims given as bench {bench!r} were measured on bench "
                                 f"{row['bench']!r}")
            if (bench, row["pipeline"]) not in columns:
                columns.append((bench, row["pipeline"]))
            if row["id"] not in first:
                ids.append(row["id"])
                first[row["id"]] = row
            by[(row["id"], bench, row["pipeline"])] = row
    lines = ["| claim | figure | " + " | ".join(f"{b} bench, {p} pipeline" for b, p in columns) + " |",
             "|" + "---|" * (len(columns) + 2)]
    for cid in ids:
        extra = " (extra)" if first[cid]["paper"] == EXTRA else ""
        cells = [_glance_text(bool(r["passed"]), r["n_passed"], r["n_seeds"], r["runaway_failures"])
                 if (r := by.get((cid, b, p))) is not None else "--" for b, p in columns]
        lines.append(f"| {cid}{extra} | {first[cid]['figure']} | " + " | ".join(cells) + " |")
    counts = []
    for b, p in columns:
        rows = [by[(cid, b, p)] for cid in ids if (cid, b, p) in by]
        own = [r for r in rows if r["paper"] != EXTRA]
        extra = [r for r in rows if r["paper"] == EXTRA]
        text = f"**{sum(bool(r['passed']) for r in own)} of {len(own)}**"
        if extra:
            text += f" (extras: {sum(bool(r['passed']) for r in extra)} of {len(extra)})"
        counts.append(text)
    lines.append("| **claims of the paper reproduced** | | " + " | ".join(counts) + " |")
    return "\n".join(lines)


def _summary_line(stats, pipeline: str, seed: int) -> str:
    """The Markdown summary of one pipeline: claims of the paper reproduced, then the extras."""
    mine = [s for s in stats if s.pipeline == pipeline]
    own = [s for s in mine if not s.extra]
    extra = [s for s in mine if s.extra]
    n = mine[0].n_seeds
    text = (f"- **{pipeline} pipeline: {sum(s.holds for s in own)} of {len(own)} claims of the paper "
            f"reproduced** (each met in at least {100 * HOLD_RATE:.0f} % of the {n} training "
            f"seed{'s' if n != 1 else ''})")
    if extra:
        text += f"; our extra checks, not in the paper: {sum(s.holds for s in extra)} of {len(extra)}"
    return text + f"; figures from seed {seed}."


def claims_markdown(stats, *, title: str = "Claims of Gervini, Gomes & da Rosa (2003) on the virtual bench",
                    preamble: str = "", why: Sequence[str] = (), appendix: str = "") -> str:
    """``claims.md``: the pipelines side by side, a summary line per pipeline, the measured
    sentences of the representative seeds and the "not reproduced, and why" section.

    Parameters
    ----------
    stats : sequence of ClaimStats
        From :func:`aggregate_claims`.
    title : str
    preamble : str
        After the summary lines: what was run.
    why : sequence of str
        Paragraphs (with numbers) on why some claims cannot hold on this bench, appended to
        the "not reproduced, and why" section.
    appendix : str
        At the end (e.g. the robustness sweeps).
    """
    stats = list(stats)
    if not stats:
        raise ValueError("claims_markdown needs at least one ClaimStats")
    pipelines = list(dict.fromkeys(s.pipeline for s in stats))
    rep = {s.pipeline: s.representative for s in stats}
    ids = list(dict.fromkeys(s.id for s in stats))
    by = {(s.id, s.pipeline): s for s in stats}
    lines = [f"# {title}", ""]
    lines += [_summary_line(stats, p, rep[p]) for p in pipelines]
    lines.append("")
    if preamble:
        lines += [preamble, ""]
    lines += [f"A claim is *reproduced* when it is met in at least {100 * HOLD_RATE:.0f} % of the "
              "training seeds. A claim measured with compensation is met only if the compensated "
              "joint also followed its control torque: its torque did not wind up, under a "
              "sinusoidal torque it reversed, and the network lets the joint coast down after a "
              "torque pulse (the coast test, claim coast-decay); otherwise it *ran away*. Each cell: "
              "the verdict, in how many seeds the claim was met, and the median [min, max] over "
              "the seeds of the number the claim's criterion thresholds.", ""]
    lines += ["## At a glance", "",
              "| claim | figure | " + " | ".join(f"{p} pipeline" for p in pipelines) + " |",
              "|" + "---|" * (len(pipelines) + 2)]
    for cid in ids:
        first = next(by[(cid, p)] for p in pipelines if (cid, p) in by)
        extra = " (extra)" if first.extra else ""
        lines.append(f"| {cid}{extra} | {first.figure} | "
                     + " | ".join(_glance(by[(cid, p)]) if (cid, p) in by else "--"
                                  for p in pipelines) + " |")
    lines += ["", "## The claims in full", ""]
    head = "| id | claim | paper | " + " | ".join(f"{p} pipeline" for p in pipelines) + " | figure |"
    lines += [head, "|" + "---|" * (len(pipelines) + 4)]
    for cid in ids:
        first = next(by[(cid, p)] for p in pipelines if (cid, p) in by)
        cells = [_cell(by[(cid, p)]) if (cid, p) in by else "--" for p in pipelines]
        lines.append(f"| {cid} | {_cell_text(first.shown.claim)} | {_cell_text(first.shown.paper)} | "
                     + " | ".join(cells) + f" | {first.figure} |")
    for p in pipelines:
        lines += ["", f"## Measured, {p} pipeline, seed {rep[p]} (the figures)", "",
                  "| id | measured | criterion |", "|---|---|---|"]
        for cid in ids:
            if (cid, p) in by:
                c = by[(cid, p)].shown
                lines.append(f"| {cid} | {_cell_text(c.measured)} | "
                             f"{'met' if c.passed else '**not met**'} |")
    lines += ["", "## Not reproduced, and why", ""]
    for p in pipelines:
        failing = [by[(cid, p)] for cid in ids if (cid, p) in by and not by[(cid, p)].holds]
        lines += [f"### {p} pipeline", ""]
        lines += [f"- **{s.id}** ({s.figure}; {_seeds(s)}; median {_num(s.median)} {s.unit}): "
                  f"{_text(s.note)}" for s in failing] or ["Every claim is reproduced."]
        lines.append("")
    if why:
        lines += ["### Why some claims cannot hold on this bench", ""]
        lines += [f"- {w}" for w in why]
        lines.append("")
    if appendix:
        lines += [appendix, ""]
    return "\n".join(lines).rstrip() + "\n"


def claims_json(stats, *, bench: str | None = None) -> str:
    """``claims.json``: one object per (claim, pipeline) (:meth:`ClaimStats.as_dict`), strict JSON;
    with ``bench``, each object also names the bench it was measured on (``"bench"``)."""
    extra = {} if bench is None else {"bench": v.text("bench", bench, empty=False)}
    return json.dumps([{**s.as_dict(), **extra} for s in stats], indent=2, allow_nan=False)
