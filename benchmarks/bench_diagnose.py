"""Benchmark of the diagnosis (issue 7): confusion matrix on random hidden-effect records,
and the time of one 40 s record end to end against a named alternative.

Records: :func:`fricctl.bench.hidden_effects.hidden_effect_record`, seeds [7000, i]; every
fifth record is drawn with a nominal model (``none`` or a nominal-only cause), the
others from ``HIDDEN_CAUSES``; both lists come from the cause registry
(:mod:`fricctl.diagnose.causes`), so a new cause module is benchmarked without an edit.
A second, stratified pass forces every cause k times (seeds [7200, j, i]) so that no
cause escapes the draw.  Timing: one 40 s record at 500 Hz, end to
end (generate, diagnose, write the report), against the same record's plain CasADi
baseline fit (:func:`fricctl.identify.identify_run`) as the named alternative.
Run:  .venv/bin/python benchmarks/bench_diagnose.py [N_random [K_per_cause]]
"""

from __future__ import annotations

import sys
import tempfile
import time

import numpy as np

from fricctl.diagnose import CAUSES, NOMINAL_ONLY, diagnose
from fricctl.bench.hidden_effects import hidden_effect_record


def confusion(n):
    rows = []
    for i in range(n):
        rec = hidden_effect_record(np.random.default_rng([7000, i]), nominal=bool(i % 5 == 4))
        rows.append((rec.cause, diagnose(rec.run, rec.nominal).cause))
    return _report(rows, f"{n} random records")


def stratified(k):
    """Every cause k times (seeds [7200, j, i]), so no cause is missed by the draw."""
    rows = []
    for j, cause in enumerate(CAUSES):
        nominal = cause in NOMINAL_ONLY
        for i in range(k):
            rec = hidden_effect_record(np.random.default_rng([7200, j, i]), cause=cause, nominal=nominal)
            rows.append((rec.cause, diagnose(rec.run, rec.nominal).cause))
    return _report(rows, f"{k} records per cause")


def _report(rows, title):
    n = len(rows)
    names = [c for c in CAUSES if any(a == c or b == c for a, b in rows)]
    print(f"confusion matrix ({title}; rows = hidden, columns = named)")
    print(" " * 16 + " ".join(f"{c[:7]:>7}" for c in names))
    for a in names:
        cnt = [sum(1 for x, y in rows if x == a and y == b) for b in names]
        if sum(cnt):
            print(f"{a:>15} " + " ".join(f"{k:7d}" for k in cnt))
    ok = sum(a == b for a, b in rows)
    false_none = sum(1 for a, b in rows if a == "none" and b != "none")
    print(f"correct {ok}/{n} = {100 * ok / n:.1f} %; false causes on none records: {false_none}")
    return rows


def timing():
    from fricctl.cli.diagnose import write_report
    from fricctl.identify import identify_run

    t0 = time.perf_counter()
    rec = hidden_effect_record(np.random.default_rng([7000, 999]), cause="position_ripple")
    t1 = time.perf_counter()
    d = diagnose(rec.run)
    t2 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        write_report(d, tmp)
    t3 = time.perf_counter()
    identify_run(rec.run)
    t4 = time.perf_counter()
    total = t3 - t0
    print(f"40 s record end to end: {total:.2f} s (generate {t1 - t0:.2f}, diagnose {t2 - t1:.2f}, "
          f"report {t3 - t2:.2f}); plain baseline fit (identify_run) {t4 - t3:.2f} s; "
          f"ratio {total / (t4 - t3):.1f}")


if __name__ == "__main__":
    diagnose(hidden_effect_record(np.random.default_rng(0), cause="none", duration=10.0).run)  # JIT warm-up
    timing()
    confusion(int(sys.argv[1]) if len(sys.argv) > 1 else 60)
    stratified(int(sys.argv[2]) if len(sys.argv) > 2 else 6)
