"""The protocol: every contender on every experiment and plant, over seeds, on any executor.

:func:`compare` runs the table in two rounds of jobs, each a plain module-level function fed
plain data (names, dicts, JSON text), so that any :class:`concurrent.futures.Executor` runs
them -- a process pool, or a Dask ``Client.get_executor()`` on a cluster:

1. *prepare*: for each seeded contender (a trained network) and seed, its per-seed step (the
   training, read from the disk cache of trained nets where it is there);
2. *evaluate*: for each contender, seed and plant, every experiment.

Every job is deterministic (no random draw but the training's seeded ones), so the rows are
the same bit for bit whichever executor ran them; the rows are assembled in the table's order,
not in the order the jobs finished.
"""

from __future__ import annotations

import functools
import json
import math
import re
from concurrent.futures import Executor, as_completed
from dataclasses import dataclass
from typing import Mapping, Sequence

import numpy as np

from .. import _validate as v
from .contenders import contender, make_contender
from .experiments import EXPERIMENTS, METRICS, experiment, scaled
from .plants import check_plant, noisy, realise

__all__ = ["ComparisonResult", "compare", "MAX_SEEDS"]

#: Most seeds one comparison runs [-].
MAX_SEEDS = 100


@functools.lru_cache(maxsize=4)
def _bench(name: str):
    from ..paper.benches import bench

    return bench(name)


@functools.lru_cache(maxsize=8)
def _model(bench_name: str, linked: bool):
    """The design model the compensators are made from: the bench's design actuator (with the
    link for the experiments that run it), as a :class:`~fricctl.plant.JointModel`."""
    from ..plant import JointModel

    b = _bench(bench_name)
    p = b.design_actuator.with_link(b.link_inertia) if linked else b.design_actuator
    return JointModel.from_params(p, source=f"bench {bench_name!r}: design model"
                                  + (" with the link" if linked else ""))


def _prepare_job(name: str, seed: int, options: dict) -> dict:
    """Round 1: the contender's per-seed step; returns the options its factory takes."""
    return contender(name).prepare(seed, options)


def _evaluate_job(name: str, seed: int, options: dict, plant: dict, experiments: tuple,
                  bench_name: str) -> list:
    """Round 2: every experiment of one contender, seed and plant -> plain dicts."""
    from ..paper.common import designs

    b = _bench(bench_name)
    out = []
    for en in experiments:
        ex = EXPERIMENTS[en]
        # the torque noise of seed s in experiment k: its own stream, whatever else is compared
        rng = np.random.default_rng([seed, list(EXPERIMENTS).index(en)])
        design = designs(b)[ex.design]
        base = b.linked_actuator if ex.linked else b.actuator
        pl = realise(plant, base)
        try:
            comp = make_contender(name, _model(bench_name, ex.linked), design, base.sample_time, seed,
                                  options)
            if not ex.closed_loop and comp.needs_reference:
                out.append({"experiment": en, "not_applicable": f"{name} acts on the position error "
                            "r - y, and this experiment is open loop (no reference to track)"})
                continue
            o = ex.run(b, pl, scaled(comp, pl.compensation_scale), design, rng)
        except ValueError as exc:  # a diverged loop, a compensator this loop cannot have: a result
            out.append({"experiment": en, "error": str(exc).splitlines()[0]})
            continue
        out.append({"experiment": en, "metrics": {k: float(o.metrics[k]) for k in ex.metrics},
                    "checks": [c.as_dict() for c in o.checks],
                    # a check whose record was too short for part of its criterion says so in the row
                    "warnings": list(o.warnings) + [c.reason for c in o.checks if not c.judged]})
    return out


def _stats(values: list) -> dict:
    """median, min, max over the finite values; the values (non-finite as None)."""
    finite = [x for x in values if x is not None and math.isfinite(x)]
    if not finite:
        return {"median": None, "min": None, "max": None,
                "values": [None if x is None or not math.isfinite(x) else x for x in values]}
    return {"median": float(np.median(finite)), "min": float(min(finite)), "max": float(max(finite)),
            "values": [None if x is None or not math.isfinite(x) else x for x in values]}


#: The torque checks of :mod:`fricctl.paper.runaway` a row may have used, and what they hold.
CRITERIA = {"wind-up": "friction estimate: |Tm| within |Tc| + Fs + b|omega| (wind_up)",
            "divergence": "not a friction estimate (DOB, integral action): beyond that bound only in "
                          "transients that die out by the run's last quarter (divergence)"}


def _criterion(outs: list) -> str | None:
    """The torque check the runs of a row used (one per compensator), None if none ran."""
    names = {c["name"] for o in outs if "checks" in o for c in o["checks"] if c["name"] in CRITERIA}
    if len(names) > 1:  # pragma: no cover - a compensator's estimates_friction does not change
        raise ValueError(f"the runs of one row used two torque checks: {sorted(names)}")
    return names.pop() if names else None


#: A number standing alone in a warning (not a digit of a name such as "L1"; "1.05x" is one).
_NUMBER = re.compile(r"(?<![A-Za-z_.\d])[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?(?![A-Za-wyz_\d]|\.\d)")


def _by_seed(said: list, n: int) -> list:
    """``(seed, warning)`` pairs as lines: one per seed, or, where several seeds warn alike (the
    same sentence with other numbers: a network outside its envelope for a few milliseconds in
    every seed), one line naming them, each number given as its range over them."""
    groups: dict = {}
    seen: dict = {}
    for s, w in said:
        template = _NUMBER.sub("#", w)
        k = seen[(s, template)] = seen.get((s, template), -1) + 1  # a seed's k-th such warning
        groups.setdefault((template, k), []).append((s, w))
    out = []
    for items in groups.values():
        if len(items) == 1:
            out.append(f"seed {items[0][0]}: {items[0][1]}")
            continue
        numbers = [_NUMBER.findall(w) for _, w in items]
        parts = _NUMBER.split(items[0][1])
        text = parts[0]
        for i, part in enumerate(parts[1:]):
            column = sorted({x[i] for x in numbers}, key=float)
            text += (column[0] if len(column) == 1 else f"{column[0]} to {column[-1]}") + part
        out.append(f"seeds {', '.join(str(s) for s, _ in items)} ({len(items)} of {n}): {text}")
    return out


def _row(name: str, en: str, plant: dict, seeds: list, outs: list, seeded: bool) -> dict:
    ex = EXPERIMENTS[en]
    warnings = []
    metrics = {}
    for m in ex.metrics:
        vals = [o["metrics"][m] if "metrics" in o else None for o in outs]
        bad = [s for s, x in zip(seeds, vals) if x is not None and not math.isfinite(x)]
        if bad:
            warnings.append(f"{m} is {vals[seeds.index(bad[0])]} for seed(s) {', '.join(map(str, bad))} "
                            "(left out of median/min/max)")
        metrics[m] = {"unit": METRICS[m][0], **_stats(vals)}
    # what an experiment could not judge, in its own words (e.g. a limit cycle too slow for the run)
    said = [(s, w) for s, o in zip(seeds, outs) for w in (o["warnings"] if "warnings" in o else ())]
    warnings += _by_seed(said, len(seeds)) if seeded else [w for _, w in said]
    na = [o["not_applicable"] for o in outs if "not_applicable" in o]
    if na:  # open loop for a compensator of the position error: nothing measured, nothing failed
        return {"compensator": name, "experiment": en, "plant": plant, "seeds": list(seeds),
                "seeded": seeded, "metrics": metrics, "not_applicable": na[0],
                "runaway": {"passed": 0, "runs": 0, "not_judged": 0, "rate": None, "criterion": None,
                            "failures": []},
                "errors": [], "warnings": []}
    passed, unjudged, reasons = 0, 0, []
    ran = [(s, o) for s, o in zip(seeds, outs) if "error" not in o]  # an error is not a runaway
    for s, o in ran:
        failed = [c for c in o["checks"] if not c["passed"]]
        if failed:
            reasons.append(f"seed {s}: {failed[0]['reason']}")
        elif any(not c.get("judged", True) for c in o["checks"]):
            unjudged += 1  # passed for want of record (its reason is among the warnings), not judged
        else:
            passed += 1
    judged = len(ran) - unjudged
    return {"compensator": name, "experiment": en, "plant": plant, "seeds": list(seeds),
            "seeded": seeded, "metrics": metrics,
            "runaway": {"passed": passed, "runs": len(ran), "not_judged": unjudged,
                        "rate": passed / judged if judged else None,
                        "criterion": _criterion(outs), "failures": reasons[:3]},
            "errors": [f"seed {s}: {o['error']}" for s, o in zip(seeds, outs) if "error" in o],
            "warnings": warnings}


@dataclass(frozen=True, kw_only=True, eq=False)
class ComparisonResult:
    """The comparison: one row per compensator x experiment x plant.

    Attributes
    ----------
    rows : plain dicts (JSON-ready): ``compensator``, ``experiment``, ``plant`` (the plant
        object), ``seeds`` (the seeds run; one where nothing depends on the seed), ``seeded``
        (whether the runs depend on the seed: a trained network, or a plant with noise), ``metrics`` (name -> ``unit``, ``median``, ``min``, ``max``, ``values`` per
        seed), ``runaway`` (``passed`` of the ``runs`` that ran -- a run that could not be made
        is an error, not a runaway --, ``not_judged``: the runs no check failed but one could
        not judge (too short a record; their reasons are among the ``warnings``), counted in
        neither, ``rate``: ``passed`` over the judged runs (None when none was), ``criterion``: the torque
        check its runs used, ``"wind-up"`` for a friction estimate or ``"divergence"`` for a
        DOB or integral action (:func:`fricctl.paper.runaway.torque_check`; None when none
        ran), the first ``failures``' reasons),
        ``errors`` (runs that could not be made, e.g. a diverged loop), ``warnings``, and
        ``not_applicable`` (why, with no metric and no runaway run) for a compensator of the
        position error on an open-loop experiment
    bench : the bench's name
    compensators, experiments : names, in table order
    plants : the plant objects, in table order
    seeds : the number of seeds of the runs that depend on the seed [-]
    """

    rows: tuple
    bench: str
    compensators: tuple
    experiments: tuple
    plants: tuple
    seeds: int

    def row(self, compensator: str, experiment: str, plant: str) -> dict:
        """The row of ``compensator`` on ``experiment`` and the plant named ``plant``."""
        for r in self.rows:
            if (r["compensator"], r["experiment"], r["plant"]["name"]) == (compensator, experiment, plant):
                return r
        raise ValueError(f"no row for ({compensator!r}, {experiment!r}, {plant!r})")

    def as_dict(self) -> dict:
        """``{"rows": [...]}`` and what was compared (JSON-ready)."""
        return {"rows": list(self.rows), "bench": self.bench, "bench_sensing_applied": False,
                "compensators": list(self.compensators),
                "experiments": list(self.experiments), "plants": list(self.plants), "seeds": self.seeds,
                "metrics": {k: {"unit": u, "description": d} for k, (u, d) in METRICS.items()}}

    def to_json(self, indent: int | None = 1) -> str:
        """:meth:`as_dict` as JSON text (strict: non-finite numbers are None in the rows)."""
        return json.dumps(self.as_dict(), indent=indent, allow_nan=False)

    def table(self) -> str:
        """Markdown: one table per experiment, a line per compensator and plant, each metric as
        median [min, max] over the seeds, and the runaway checks passed of the runs."""
        out = [f"# Compensator comparison (bench {self.bench})", "",
               f"Trained networks, and every compensator on a plant with noise, ran {self.seeds} seed(s) "
               "each; a run that does not depend on the seed ran once. Cells: median [min, max] over the seeds. Runaway: runs "
               "whose runaway checks (fricctl.paper.runaway) all passed; torque check: the criterion the "
               "motor torque was held to:", ""] + [f"- `{k}`: {d}" for k, d in CRITERIA.items()] + [""]
        sensing = _bench(self.bench).sensing
        if not sensing.ideal:
            out += [f"The bench's own sensing ({sensing.encoder_jitter:g} count of encoder jitter, "
                    f"{sensing.torque_noise:g} N*m of torque noise, {sensing.torque_ripple:g} N*m of "
                    "torque ripple) is **not applied** in this table: "
                    "its runs see the encoder's exact count, and torque noise only on the "
                    "`torque_noise` plant. The claims of the same bench (claims.md) run with it.", ""]
        for en in self.experiments:
            ex = EXPERIMENTS[en]
            out += [f"## {en}: {ex.description}", ""]
            head = ["compensator", "plant"] + [f"{m} [{METRICS[m][0]}]" for m in ex.metrics] + ["runaway",
                                                                                        "torque check"]
            out += ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
            for r in self.rows:
                if r["experiment"] != en:
                    continue
                cells = [r["compensator"], r["plant"]["name"]]
                for m in ex.metrics:
                    cells.append(_cell(r["metrics"][m]))
                rw = r["runaway"]
                if "not_applicable" in r:
                    cells.append("not applicable (open loop)")
                else:
                    cells.append(f"{rw['passed']}/{rw['runs']}"
                                 + (f" ({rw['not_judged']} not judged)" if rw.get("not_judged") else "")
                                 + (" (errors)" if r["errors"] else ""))
                cells.append(rw["criterion"] or "-")
                out.append("| " + " | ".join(cells) + " |")
            out.append("")
        notes = [f"- {r['compensator']} / {r['experiment']} / {r['plant']['name']}: {t}"
                 for r in self.rows for t in r["runaway"]["failures"] + r["errors"] + r["warnings"]]
        na = sorted({(r["compensator"], r["experiment"], r["not_applicable"]) for r in self.rows
                     if "not_applicable" in r})
        notes += [f"- {c} / {e}: not applicable: {t}" for c, e, t in na]
        if notes:
            out += ["## Runaways, errors and warnings", ""] + notes + [""]
        out += ["## Metrics", ""] + [f"- `{k}` [{u}]: {d}" for k, (u, d) in METRICS.items()] + [""]
        return "\n".join(out)


def _fmt(x) -> str:
    return "n/a" if x is None else f"{x:.3g}"


def _cell(s: dict) -> str:
    if s["median"] is None:
        return "n/a"
    if len(s["values"]) == 1 or s["min"] == s["max"]:
        return _fmt(s["median"])
    return f"{_fmt(s['median'])} [{_fmt(s['min'])}, {_fmt(s['max'])}]"


def _names(what: str, given, known: Sequence, check) -> tuple:
    names = tuple(known) if given is None else tuple(given)
    if not names:
        raise ValueError(f"{what}: at least one is needed")
    for n in names:
        check(n)
    if len(set(names)) != len(names):
        raise ValueError(f"{what} names one twice: {', '.join(names)}")
    return names


def compare(*, compensators: Sequence[str] | None = None, experiments: Sequence[str] | None = None,
            plants: Sequence | None = None, seeds: int = 10, bench: str | None = None,
            options: Mapping[str, Mapping] | None = None, executor: Executor | None = None,
            progress: bool = False) -> ComparisonResult:
    """Run the comparison.

    Parameters
    ----------
    compensators : sequence of str, optional
        Names of :data:`fricctl.compare.CONTENDERS` (default all).
    experiments : sequence of str, optional
        Names of :data:`fricctl.compare.EXPERIMENTS` (default all).
    plants : sequence of str or dict, optional
        Names of :data:`fricctl.compare.PLANTS` or plant objects (default all of them).
    seeds : int
        Seeds 0 .. seeds-1 of the seeded contenders [-].
    bench : str, optional
        The bench (:data:`fricctl.paper.benches.BENCHES`); default the paper's default bench.
    options : mapping, optional
        Contender name -> its options (e.g. ``{"nn": {"fast": True}}``).
    executor : concurrent.futures.Executor, optional
        Runs the jobs (``submit``); default: in this process.
    progress : bool
        A tqdm bar on stderr (only when stderr is a terminal).

    Returns
    -------
    ComparisonResult
    """
    from ..paper.benches import BENCHES, DEFAULT_BENCH
    from .contenders import CONTENDERS
    from .plants import PLANTS

    bench = DEFAULT_BENCH if bench is None else v.choice("bench", bench, tuple(BENCHES))
    comps = _names("compensators", compensators, CONTENDERS, contender)
    exps = _names("experiments", experiments, EXPERIMENTS, experiment)
    pls = tuple(check_plant(p) for p in (PLANTS if plants is None else plants))
    if not pls:
        raise ValueError("plants: at least one is needed")
    if len({p["name"] for p in pls}) != len(pls):
        raise ValueError("plants: two plants share a name")
    seeds = v.integer("seeds", seeds, low=1, high=MAX_SEEDS)
    options = {} if options is None else dict(options)
    unknown = sorted(set(options) - set(comps))
    if unknown:
        raise ValueError(f"options given for {unknown[0]!r}, which is not compared")
    opts = {n: contender(n).check_options(options[n] if n in options else {}) for n in comps}
    for n, o in opts.items():  # a contender trained on a bench (the networks) is trained on this one
        if "bench" in (contender(n).options or ()):
            if "bench" in o and o["bench"] != bench:
                raise ValueError(f"options of {n!r}: bench {o['bench']!r} is not the compared bench {bench!r}")
            o["bench"] = bench
    if executor is not None and not hasattr(executor, "submit"):
        raise ValueError(f"executor must be a concurrent.futures.Executor, got {type(executor).__name__}")
    # a contender whose options its maker checks (the registered compensators) is built once
    # here: a misspelt or non-physical option is this call's ValueError, not a table of rows
    # that all say "error"
    from ..paper.common import designs

    b = _bench(bench)
    for n in comps:
        if contender(n).options is None:
            ex = EXPERIMENTS[exps[0]]
            try:
                make_contender(n, _model(bench, ex.linked), designs(b)[ex.design],
                               b.actuator.sample_time, 0, opts[n])
            except ValueError as exc:
                raise ValueError(f"options of {n!r}: {exc}") from None

    def seeded(n, p) -> bool:
        return contender(n).seeded or noisy(p)

    def runs(n, p) -> list:
        return list(range(seeds)) if seeded(n, p) else [0]

    prep = [(n, s) for n in comps if contender(n).prepare is not None
            for s in sorted({s for p in pls for s in runs(n, p)})]
    jobs = [(n, s, p) for n in comps for p in pls for s in runs(n, p)]

    import sys

    from tqdm import tqdm

    with tqdm(total=len(prep) + len(jobs), desc="compare", unit="job", file=sys.stderr,
              disable=not (progress and sys.stderr.isatty())) as bar:
        prepared = dict(zip(prep, _run(executor, _prepare_job,
                                       [(n, s, opts[n]) for n, s in prep], bar)))
        args = [(n, s, prepared[(n, s)] if (n, s) in prepared else opts[n], p, exps, bench)
                for n, s, p in jobs]
        done = _run(executor, _evaluate_job, args, bar)
    results = {(n, s, p["name"]): out for (n, s, p), out in zip(jobs, done)}
    rows = []
    for n in comps:
        for en in exps:
            for p in pls:
                outs = [next(o for o in results[(n, s, p["name"])] if o["experiment"] == en)
                        for s in runs(n, p)]
                rows.append(_row(n, en, p, runs(n, p), outs, seeded(n, p)))
    return ComparisonResult(rows=tuple(rows), bench=bench, compensators=comps, experiments=exps,
                            plants=pls, seeds=seeds)


def _run(executor, fn, args: list, bar) -> list:
    """``fn(*a)`` for each ``a`` of ``args``, in order; through ``executor`` when given."""
    if executor is None:
        out = []
        for a in args:
            out.append(fn(*a))
            bar.update(1)
        return out
    futures = [executor.submit(fn, *a) for a in args]
    index = {id(f): i for i, f in enumerate(futures)}
    out = [None] * len(futures)
    for f in as_completed(futures):
        out[index[id(f)]] = f.result()
        bar.update(1)
    return out
