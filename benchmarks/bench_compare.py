"""Wall time of the compensator comparison (issue 23: every contender on every experiment and
plant, 10 seeds where training is involved, "the full table under 10 minutes on 2 cores").

The named alternative of the ratio is the issue's budget (600 s): the script prints time /
budget (< 1 is met).  By default it does not run the full table: it runs the table with
``--seeds`` seeds (default 2) on a fresh cache of trained networks, in two measured parts, and
projects the full table's time from them:

1. *training*: the networks of every seeded contender and seed (the comparison's first round of
   jobs), on a fresh cache -- what a first run pays;
2. *evaluation*: the whole table through :func:`fricctl.compare.compare` on that cache (the
   networks read back), one job per contender, seed and plant.

Projection to ``--full-seeds`` seeds (default 10): training x (full seeds / seeds) + evaluation x
(full jobs / jobs), both on the same workers; it assumes a job's cost does not depend on the
seed (true of the evaluation jobs, which run the same experiments) and that training times
scale with the number of networks.  ``--full`` runs the full table instead, cold, and prints
its measured time.  The machine's load average is printed before and after: other work on the
same cores slows every number down.

Usage: ``python benchmarks/bench_compare.py [--seeds 2] [--workers 2] [--full] [--full-seeds 10]
[--executor process|dask]``.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import tempfile
import time

BUDGET = 600.0  # [s], issue 23: the full table on 2 cores


def load() -> str:
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


@contextlib.contextmanager
def executor(kind: str, workers: int):
    from fricctl.cli.compare import _executor

    with _executor(kind, workers, None) as ex:
        yield ex


def table_size(seeds: int) -> tuple:
    """(networks, evaluation jobs) of the full list of contenders and plants at ``seeds``."""
    from fricctl.compare import CONTENDERS, PLANTS
    from fricctl.compare.plants import noisy

    nets = sum(seeds for c in CONTENDERS.values() if c.seeded)
    jobs = sum(seeds if c.seeded or noisy(p) else 1 for c in CONTENDERS.values() for p in PLANTS.values())
    return nets, jobs


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--full-seeds", type=int, default=10)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--executor", default="process", choices=("process", "dask"))
    ap.add_argument("--full", action="store_true", help="run the full table (cold) instead")
    args = ap.parse_args()
    os.environ["FRICCTL_CACHE"] = tempfile.mkdtemp(prefix="fricctl-bench-compare-")  # cold

    from fricctl.compare import CONTENDERS, EXPERIMENTS, PLANTS, compare
    from fricctl.compare.protocol import _prepare_job

    print(f"load average before: {load()}")
    print(f"{len(CONTENDERS)} contenders ({', '.join(CONTENDERS)}) x {len(EXPERIMENTS)} experiments x "
          f"{len(PLANTS)} plants; {args.workers} workers ({args.executor})")
    if args.full:
        t0 = time.perf_counter()
        with executor(args.executor, args.workers) as ex:
            res = compare(seeds=args.full_seeds, executor=ex)
        t = time.perf_counter() - t0
        print(f"full table, {args.full_seeds} seeds, cold: {len(res.rows)} rows in {t:.0f} s; "
              f"time / budget {t / BUDGET:.2f} ({'met' if t < BUDGET else 'NOT met'})")
        print(f"load average after: {load()}")
        return
    nets, jobs = table_size(args.seeds)
    full_nets, full_jobs = table_size(args.full_seeds)
    with executor(args.executor, args.workers) as ex:
        t0 = time.perf_counter()
        prep = [(n, s) for n, c in CONTENDERS.items() if c.seeded for s in range(args.seeds)]
        futures = [ex.submit(_prepare_job, n, s, {}) for n, s in prep]
        for f in futures:
            f.result()
        t_train = time.perf_counter() - t0
        t0 = time.perf_counter()
        res = compare(seeds=args.seeds, executor=ex)
        t_eval = time.perf_counter() - t0
    print(f"{args.seeds} seeds: training {nets} networks {t_train:.0f} s (cold cache); evaluation "
          f"{jobs} jobs, {len(res.rows)} rows {t_eval:.0f} s (networks read back); "
          f"measured total {t_train + t_eval:.0f} s")
    projected = t_train * full_nets / max(nets, 1) + t_eval * full_jobs / jobs
    print(f"projected full table ({args.full_seeds} seeds: {full_nets} networks, {full_jobs} jobs): "
          f"{projected:.0f} s cold; time / budget {projected / BUDGET:.2f} "
          f"({'met' if projected < BUDGET else 'NOT met'}, projected)")
    print(f"load average after: {load()}")


if __name__ == "__main__":
    main()
