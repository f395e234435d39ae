"""Benchmark of the diagnosis (issues 7 and 12): confusion matrices on hidden-effect records
made on seeds never used while building the method, and the time of one 40 s record at
1 kHz end to end with the multi-cause search.

Seeds.  Used while building the issue-12 method (and so never here): the package bench
``[9100..9400, ...]`` and the tests' ``[2026..2028, i]``; the independent bench's
``[31, i]`` (tests), ``[40, i]`` and ``[41, i]``.  A first measurement on
``[12001..12005, ...]`` and ``[32, i]`` led to three changes (the band's definition, the
delay range, the load column; see ``benchmarks/README.md``), so those seeds count as used
too.  This
benchmark: ``[12101..12105, ...]`` (package bench) and ``[33, i]`` (independent bench).

Record sets (durations 20-60 s, rates 200 Hz-2 kHz, rotary and linear axes):

* ``singles``: every fit-mode cause x {mixed, closed-loop, mostly stuck} x {rotary,
  linear} x two rates, and the nominal-only causes against their nominal model;
* ``pairs``: every pair the bench can hide together (:data:`PAIRS`), twice;
* ``none``: no effect, over rates, axes, excitations, drawn sensors (encoder, noise);
* ``line``: single effects made weak (``strength`` 0.1-0.6), near the 10 % line;
* ``independent``: records of the second simulator (``tests/test_diagnose_independent.py``:
  solve_ivp with event-located stick-slip, a cascade loop, Tustin Stribeck, a two-harmonic
  ripple, warm-up drift, Dahl presliding, fractional delays).

Labels.  A hidden effect is *expected* when it weighs at least ``MIN_SCORE`` on its record
(:meth:`HiddenEffectRecord.weights`: knowing it removes 19 % of the residual, 10 % of the
RMS); a weaker one is *below the line* and the expected answer leaves it out
(:meth:`HiddenEffectRecord.expected`, which also expects a position load that is a constant
over the record's travel as the ``offset`` it is there).  The
independent bench has no exact model of its laws in fricctl: its effects are drawn well
above the line and all expected.

``issue21``: the causes issue 21 added hidden alone, end stops, effects that are not causes
(``foreign=``) and no effect, on seeds ``[12201..12204, ...]``; not in the default run.

``records DIR``: writes the seven CSV records the time changes are checked on (runs 11-13 of
``benchmarks/README.md``): ``r40.csv``, the two-cause 40 s record at 1 kHz of ``timing``, and six
20 s, 500 Hz records (``[12105, 100 + i]``: backlash, compliance, position load, position
ripple, Stribeck, one drawn); ``fricctl diagnose FILE --json --report DIR`` on each before and
after a change must give the same bytes.

Run:  .venv/bin/python benchmarks/bench_diagnose.py [timing|singles|pairs|none|line|independent|issue21 ...]
(all sets by default; nice it on a shared machine), or ``... bench_diagnose.py records DIR``.
"""

from __future__ import annotations

import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

import numpy as np

from fricctl.bench.hidden_effects import HIDDEN_CAUSES, NOMINAL_CAUSES, PAIRS, hidden_effect_record
from fricctl.diagnose import diagnose

RATES = (0.005, 0.002, 0.001, 0.0005)
DURATIONS = (20.0, 30.0, 40.0, 60.0)
EXCITATIONS = ("mixed", "closed_loop", "stuck")
AXES = ("rotary", "linear")
FIT_CAUSES = HIDDEN_CAUSES[1:]


def _row(rec, kind: str, label: str, t0: float) -> dict:
    d = diagnose(rec.run, rec.nominal)
    weights = rec.weights()
    expected = rec.expected(weights=weights)
    return dict(kind=kind, label=label, hidden=tuple(c for c in rec.causes if c != "none"),
                weights=weights, expected=expected, named=set(d.causes) - {"none"},
                seconds=time.perf_counter() - t0)


def singles():
    rows = []
    for j, cause in enumerate(FIT_CAUSES):
        for k, (exc, axis) in enumerate((e, a) for e in EXCITATIONS for a in AXES):
            for m in range(2):
                ts = RATES[(j + k + 2 * m) % 4]
                t0 = time.perf_counter()
                rec = hidden_effect_record(np.random.default_rng([12101, j, k, m]), cause=cause,
                                           sample_time=ts, duration=DURATIONS[(j + k + m) % 4],
                                           excitation=exc, axis=axis,
                                           sensors=("fixed", "drawn")[m])
                rows.append(_row(rec, "single", f"{cause} {exc} {axis} {1 / ts:.0f} Hz", t0))
    for j, cause in enumerate(NOMINAL_CAUSES):
        for k in range(6):
            t0 = time.perf_counter()
            rec = hidden_effect_record(np.random.default_rng([12101, 50 + j, k]), cause=cause,
                                       sample_time=RATES[k % 4], axis=AXES[k % 2],
                                       excitation=EXCITATIONS[k % 3], duration=30.0)
            rows.append(_row(rec, "single", f"{cause} (nominal)", t0))
    return rows


def pairs():
    rows = []
    for i, pair in enumerate(PAIRS):
        for m in range(2):
            exc = ("mixed", "closed_loop", "mixed")[(i + m) % 3]
            t0 = time.perf_counter()
            rec = hidden_effect_record(np.random.default_rng([12102, i, m]), cause=pair,
                                       sample_time=RATES[(i + m) % 4], axis=AXES[(i + m) % 2],
                                       excitation=exc, duration=DURATIONS[(i + 2 * m) % 4])
            rows.append(_row(rec, "pair", f"{'+'.join(pair)} {exc}", t0))
    return rows


def none():
    rows = []
    i = 0
    for exc in EXCITATIONS:
        for axis in AXES:
            for ts in RATES:
                for sensors in (("fixed", "drawn") if exc != "mixed" else ("drawn",)):
                    t0 = time.perf_counter()
                    rec = hidden_effect_record(np.random.default_rng([12103, i]), cause="none",
                                               sample_time=ts, axis=axis, excitation=exc,
                                               sensors=sensors, duration=DURATIONS[i % 4])
                    rows.append(_row(rec, "none", f"none {exc} {axis} {1 / ts:.0f} Hz {sensors}", t0))
                    i += 1
    return rows


def line():
    rows = []
    for j, cause in enumerate(FIT_CAUSES):
        for m, strength in enumerate((0.15, 0.3, 0.6)):
            t0 = time.perf_counter()
            rec = hidden_effect_record(np.random.default_rng([12104, j, m]), cause=cause,
                                       strength=strength, sample_time=RATES[(j + m) % 4],
                                       axis=AXES[(j + m) % 2], duration=40.0)
            rows.append(_row(rec, "line", f"{cause} x{strength}", t0))
    return rows


def independent():
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
    from test_diagnose_independent import EFFECTS, simulate_record

    specs = [()] * 10 + [(e,) for e in EFFECTS] * 2 + [
        ("asymmetry", "position_ripple"), ("stribeck", "time_delay"),
        ("load_dependent", "thermal_drift"), ("asymmetry", "compliance")]
    rows = []
    for i, effects in enumerate(specs):
        t0 = time.perf_counter()
        run, _ = simulate_record([33, i], effects=effects, axis=AXES[i % 2],
                                 sample_time=RATES[i % 4], duration=DURATIONS[i % 3])
        d = diagnose(run)
        # the independent bench's "asymmetry" is a Coulomb ratio between the directions: on a
        # rigid joint the constant torque (Fc+ - Fc-)/2 (same sliding torque, same breakaway
        # band; fricctl.diagnose.causes.offset), which the diagnosis names `offset`
        expected = {"offset" if e == "asymmetry" else e for e in effects}
        rows.append(dict(kind="independent", label=" + ".join(effects) or "none", hidden=effects,
                         weights={}, expected=expected, named=set(d.causes) - {"none"},
                         seconds=time.perf_counter() - t0))
    return rows


#: The causes issue 21 added, hidden alone on seeds [12201, ...] (never used while building).
NEW_CAUSES = tuple(c for c in ("backlash", "position_load", "offset", "drag") if c in FIT_CAUSES)


def _row_full(rec, kind: str, label: str, t0: float) -> dict:
    """:func:`_row` with the verdict (explained, residual over floor) and the stops found."""
    d = diagnose(rec.run, rec.nominal)
    weights = rec.weights() if rec.foreign == "none" else {}
    expected = rec.expected(weights=weights) if rec.foreign == "none" else set()
    return dict(kind=kind, label=label, hidden=tuple(c for c in rec.causes if c != "none"),
                weights=weights, expected=expected, named=set(d.causes) - {"none"},
                explained=d.explained, ratio=d.verdict.residual_over_floor,
                stops=len(d.end_stops.positions) if d.end_stops is not None else 0,
                seconds=time.perf_counter() - t0)


def issue21():
    """Issue 21's targets: the new causes alone (2 axes x 2 excitations x 2 rates), end stops
    with no cause and with four others, effects that are not causes (foreign), no effect."""
    from fricctl.bench.hidden_effects import FOREIGN

    rows = []
    for j, cause in enumerate(NEW_CAUSES):
        for k, (exc, axis) in enumerate((e, a) for e in EXCITATIONS[:2] for a in AXES):
            for m in range(2):
                t0 = time.perf_counter()
                rec = hidden_effect_record(np.random.default_rng([12201, j, k, m]), cause=cause,
                                           sample_time=RATES[(j + k + 2 * m) % 4], axis=axis,
                                           excitation=exc, duration=DURATIONS[(j + k + m) % 4])
                rows.append(_row_full(rec, "new", f"{cause} {exc} {axis}", t0))
    for i, cause in enumerate(("none", "none", "stribeck", "time_delay", "offset", "thermal_drift")):
        for m in range(2):
            t0 = time.perf_counter()
            try:
                rec = hidden_effect_record(np.random.default_rng([12202, i, m]), cause=cause,
                                           excitation=("mixed", "closed_loop")[m],
                                           duration=20.0, end_stops=0.05 + 0.05 * (i % 3))
            except ValueError:  # a stop the bench cannot place with this effect
                continue
            rows.append(_row_full(rec, "stops", f"{cause} + end stops", t0))
    for i, name in enumerate(f for f in FOREIGN if f != "none"):
        for m in range(4):
            t0 = time.perf_counter()
            rec = hidden_effect_record(np.random.default_rng([12203, i, m]), cause="none",
                                       foreign=name, excitation=EXCITATIONS[m % 3],
                                       axis=AXES[m % 2], duration=20.0)
            rows.append(_row_full(rec, "foreign", f"foreign {name}", t0))
    for m in range(8):
        t0 = time.perf_counter()
        rec = hidden_effect_record(np.random.default_rng([12204, m]), cause="none",
                                   excitation=EXCITATIONS[m % 3], axis=AXES[m % 2],
                                   sample_time=RATES[m % 4], duration=20.0, sensors="drawn")
        rows.append(_row_full(rec, "none", "none", t0))
    for kind in ("new", "stops", "foreign", "none"):
        sel = [r for r in rows if r["kind"] == kind]
        exact = sum(r["named"] == r["expected"] for r in sel)
        wrong = sum(bool(r["named"] - set(r["hidden"]) - r["expected"]) for r in sel)
        stand_in = sum(bool(r["expected"] - set(r["hidden"])) for r in sel)
        falsely = sum(r["explained"] and r["ratio"] > 2 for r in sel)
        print(f"{kind}: {len(sel)} records, named exactly {exact} ({100 * exact / max(len(sel), 1):.0f} %), "
              f"a cause neither hidden nor expected named on {wrong}, 'explained' above 2x "
              f"the floor {falsely}; expected as another cause (a load constant over the "
              f"travel: offset) on {stand_in}")
        if kind == "new":
            for cause in NEW_CAUSES:
                s2 = [r for r in sel if r["label"].startswith(cause + " ")]
                as_other = sum(bool(r["expected"] - set(r["hidden"])) for r in s2)
                below = sum(not r["expected"] for r in s2)
                named = sum(cause in r["named"] for r in s2)
                print(f"  {cause}: {sum(r['named'] == r['expected'] for r in s2)}/{len(s2)} "
                      f"named exactly as expected, {named}/{len(s2)} named {cause}"
                      + (f"; {as_other} expected as another cause" if as_other else "")
                      + (f"; {below} below the line (expected none)" if below else ""))
        for r in sel:
            if r["named"] != r["expected"] or (r["explained"] and r["ratio"] > 2):
                print(f"  - {r['label']}: expected {sorted(r['expected']) or ['none']}, named "
                      f"{sorted(r['named']) or ['none']}, ratio {r['ratio']:.2f}, "
                      f"{r['seconds']:.0f} s")
    print(f"time per record: median {np.median([r['seconds'] for r in rows]):.1f} s, "
          f"max {max(r['seconds'] for r in rows):.0f} s")
    return rows


def report(rows, title):
    """Confusion table (rows: expected causes; columns: named) and the rates.

    A *false* cause is named but neither hidden nor expected (:meth:`HiddenEffectRecord.expected`
    expects a position load constant over the travel as an offset); a hidden effect below the
    line that is named anyway is counted apart (the record carries it, only weakly)."""
    print(f"\n### {title} ({len(rows)} records)\n")
    exact = sum(r["named"] == r["expected"] for r in rows)
    print(f"named exactly as expected: {exact}/{len(rows)} = {100 * exact / max(len(rows), 1):.1f} %")
    false = Counter(c for r in rows for c in r["named"] - set(r["hidden"]) - r["expected"])
    missed = Counter(c for r in rows for c in r["expected"] - r["named"])
    weak = Counter(c for r in rows for c in (r["named"] & set(r["hidden"])) - r["expected"])
    print(f"false causes (named, neither hidden nor expected): {sum(false.values())} {dict(false)}; missed: "
          f"{sum(missed.values())} {dict(missed)}; hidden below the line and named anyway: "
          f"{sum(weak.values())} {dict(weak)}")
    names = sorted({c for r in rows for c in r["named"] | r["expected"]}) + ["none"]
    print("\n| expected \\ named | " + " | ".join(names) + " |")
    print("|---" * (len(names) + 1) + "|")
    for exp in sorted({tuple(sorted(r["expected"])) for r in rows}):
        sel = [r for r in rows if tuple(sorted(r["expected"])) == exp]
        cnt = Counter(c for r in sel for c in (r["named"] or {"none"}))
        print(f"| {' + '.join(exp) or 'none'} ({len(sel)}) | "
              + " | ".join(str(cnt.get(c, "")) for c in names) + " |")
    wrong = [r for r in rows if r["named"] != r["expected"]]
    for r in wrong:
        w = ", ".join(f"{c} {100 * x:.0f} %" for c, x in r["weights"].items())
        print(f"  - {r['label']}: hidden [{w or ', '.join(r['hidden'])}], named "
              f"{sorted(r['named']) or ['none']}")
    print(f"diagnosis time per record: median {np.median([r['seconds'] for r in rows]):.1f} s")
    return rows


def pair_rate(rows):
    both = [r for r in rows if len(r["expected"]) == 2]
    ok = sum(r["expected"] <= r["named"] for r in both)
    print(f"pairs with both effects above the line: {len(both)}; both named: {ok} "
          f"({100 * ok / max(len(both), 1):.1f} %)")


def timing():
    from fricctl.cli.diagnose import write_report
    from fricctl.identify import identify_run

    diagnose(hidden_effect_record(np.random.default_rng(0), cause="none", duration=10.0).run)
    for cause in (("asymmetry", "position_ripple"), "none"):
        t0 = time.perf_counter()
        rec = hidden_effect_record(np.random.default_rng([12105, 1]), cause=cause,
                                   sample_time=0.001, duration=40.0)
        t1 = time.perf_counter()
        d = diagnose(rec.run)
        t2 = time.perf_counter()
        with tempfile.TemporaryDirectory() as tmp:
            write_report(d, tmp)
        t3 = time.perf_counter()
        identify_run(rec.run)
        t4 = time.perf_counter()
        print(f"40 s at 1 kHz, hidden {rec.causes}, named {d.causes}: end to end {t3 - t0:.2f} s "
              f"(generate {t1 - t0:.2f}, diagnose {t2 - t1:.2f}, report {t3 - t2:.2f}); plain "
              f"baseline fit (identify_run) {t4 - t3:.2f} s")


def records(folder: Path) -> None:
    """The seven records of the time changes' byte-for-byte check (module notes)."""
    folder.mkdir(parents=True, exist_ok=True)
    rec = hidden_effect_record(np.random.default_rng([12105, 1]),
                               cause=("asymmetry", "position_ripple"), sample_time=0.001,
                               duration=40.0)
    rec.run.to_csv(folder / "r40.csv")
    for i, cause in enumerate(("backlash", "compliance", "position_load", "position_ripple",
                               "stribeck", None)):
        rec = hidden_effect_record(np.random.default_rng([12105, 100 + i]), cause=cause,
                                   duration=20.0)
        rec.run.to_csv(folder / f"g{i}-{cause or 'drawn'}.csv")


if __name__ == "__main__":
    if sys.argv[1:2] == ["records"]:
        if len(sys.argv) != 3:
            raise SystemExit("usage: bench_diagnose.py records DIR")
        records(Path(sys.argv[2]))
        raise SystemExit(0)
    chosen = sys.argv[1:] or ["timing", "singles", "pairs", "none", "line", "independent"]
    if "timing" in chosen:
        timing()
    if "issue21" in chosen:
        issue21()
    titles = dict(singles="single effects", pairs="two effects at once", none="no effect",
                  line="near the 10 % line", independent="independent bench")
    for name in ("singles", "pairs", "none", "line", "independent"):
        if name in chosen:
            rows = report(globals()[name](), titles[name])
            if name == "pairs":
                pair_rate(rows)
