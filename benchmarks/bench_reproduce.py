"""Wall time of ``fricctl reproduce`` over seeds and pipelines (target: 10 seeds, both pipelines,
full mode, < 120 s on 2 cores; ``--fast`` much less).

The named alternative for the ratio is the budget the issue sets: the script prints
time / budget (< 1 is met).  Each command runs in a fresh process (worker start-up,
imports and numba's cache included) with a fresh cache of trained networks ("cold":
every network trained) and then again on the same cache ("warm": networks read back,
as a second ``make reproduce`` does).  A breakdown from the library run says where the
time goes: the jobs (training + figures + claims per network) and the serial rest.
The machine's load average is printed before and after: other work on the same cores
slows every number down.

Usage: ``python benchmarks/bench_reproduce.py [--seeds 10] [--quick]`` (``--quick``: the
``--fast`` command only).
"""

from __future__ import annotations

import argparse
import multiprocessing
import os
import statistics
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

BUDGET = 120.0  # [s], issue 11: 10 seeds, both pipelines, 2 cores
WORKERS = 2


def load() -> str:
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


def command(args: list[str], cache: Path) -> float:
    """Wall time of one ``fricctl reproduce`` in a fresh process [s]."""
    fricctl = Path(sys.executable).with_name("fricctl")
    env = dict(os.environ, FRICCTL_CACHE=str(cache), MPLBACKEND="Agg")
    t0 = time.perf_counter()
    subprocess.run([str(fricctl), "reproduce", *args], check=True, env=env, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    return time.perf_counter() - t0


def breakdown(seeds: int, cache: Path) -> None:
    """Where the time of the library run goes (cold cache), through a 2-worker spawn pool."""
    os.environ["FRICCTL_CACHE"] = str(cache)
    from fricctl import paper

    t0 = time.perf_counter()
    with ProcessPoolExecutor(max_workers=WORKERS, mp_context=multiprocessing.get_context("spawn")) as ex:
        t_pool = time.perf_counter()
        res = paper.reproduce_paper(seeds=seeds, executor=ex, figures=False)
        t_jobs = time.perf_counter()
    total = time.perf_counter() - t0
    print(f"library, cold cache: {total:.1f} s for {len(res.runs)} networks "
          f"(pool start {t_pool - t0:.1f} s, jobs {t_jobs - t_pool:.1f} s)")
    for name in res.pipelines:
        s = [res.runs[(name, k)].seconds for k in res.seeds]
        print(f"  {name:8s} per network: median {statistics.median(s):.1f} s, "
              f"max {max(s):.1f} s, sum {sum(s):.1f} s (train + figures + claims, in a worker)")
    print("  " + res.summary().replace("\n", "\n  "))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--quick", action="store_true")
    args, _ = ap.parse_known_args()  # run_all.py passes its own filter arguments
    print(f"load average before: {load()} (1, 5, 15 min); {os.cpu_count()} CPUs")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        runs = [("--fast", ["--fast"])] if args.quick else [("--fast", ["--fast"]), ("full", [])]
        for label, extra in runs:
            cache = tmp / f"cache{label}"
            out = tmp / f"out{label}"
            base = ["--seeds", str(args.seeds), "--workers", str(WORKERS), "--out", str(out), *extra]
            cold = command(base, cache)
            warm = command(base + ["--force"], cache)
            rows.append((label, cold, warm))
        print()
        print(f"| `fricctl reproduce --seeds {args.seeds}` (both pipelines, {WORKERS} workers) | cold cache [s] | "
              f"warm cache [s] | cold / {BUDGET:.0f} s |")
        print("|---|---|---|---|")
        for label, cold, warm in rows:
            print(f"| {label} | {cold:.1f} | {warm:.1f} | {cold / BUDGET:.2f} |")
        print()
        if not args.quick:
            breakdown(args.seeds, tmp / "cache-lib")
    print(f"load average after: {load()}")


if __name__ == "__main__":
    main()
