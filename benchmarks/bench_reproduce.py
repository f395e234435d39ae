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

``--fresh`` measures what a new user meets (issues 22, 25): ``make reproduce``'s command
(``--seeds 10 --force``, all CPUs) on a fresh copy of the package -- no compiled kernels
beside the sources, an empty cache of trained networks --, then again on the same copy and
cache (warm), ``--repeat`` times, each copy new; ``--source DIR`` copies ``DIR/fricctl``
instead of the installed package (another checkout, e.g. ``git archive main``), so that two
versions can be alternated for a ratio.  Wall and CPU time (the command and its worker
processes) and the load average are printed per run: on a shared machine the CPU time is the
steadier number.

Usage: ``python benchmarks/bench_reproduce.py [--seeds 10] [--quick]`` (``--quick``: the
``--fast`` command only); ``python benchmarks/bench_reproduce.py --fresh [--seeds 10]
[--repeat 3] [--source DIR ...]``.
"""

from __future__ import annotations

import argparse
import multiprocessing
import os
import resource
import shutil
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


def fresh_command(seeds: int, package: Path, cache: Path, out: Path) -> tuple:
    """``make reproduce``'s command on the package copy ``package`` (its parent on PYTHONPATH):
    (wall [s], CPU of the command and its workers [s], load average before, after)."""
    env = dict(os.environ, PYTHONPATH=str(package.parent), FRICCTL_CACHE=str(cache), MPLBACKEND="Agg",
               PYTHONDONTWRITEBYTECODE="1")
    env.pop("NUMBA_CACHE_DIR", None)  # compiled code beside the copy's sources, as in a fresh clone
    before = load()
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "fricctl", "reproduce", "--seeds", str(seeds), "--out", str(out),
                    "--force"], check=True, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                   cwd=package.parent)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    return wall, cpu, before, load()


def fresh(seeds: int, repeat: int, sources: list) -> None:
    """Cold then warm on a fresh copy of each source, ``repeat`` rounds, sources alternated."""
    print(f"| source | round | run | wall [s] | CPU [s] | load average before (1, 5, 15 min) | after |")
    print("|---|---|---|---|---|---|---|")
    for k in range(repeat):
        for src in sources:
            with tempfile.TemporaryDirectory() as tmp:
                tmp = Path(tmp)
                package = tmp / "clone" / "fricctl"
                shutil.copytree(src, package, ignore=shutil.ignore_patterns("__pycache__", "*.nbi", "*.nbc"))
                for label in ("cold", "warm"):
                    wall, cpu, before, after = fresh_command(seeds, package, tmp / "cache", tmp / "out")
                    print(f"| {src} | {k + 1} | {label} | {wall:.1f} | {cpu:.1f} | {before} | {after} |",
                          flush=True)


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
    ap.add_argument("--fresh", action="store_true", help="cold and warm on a fresh copy of the package")
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--source", type=Path, action="append", default=None,
                    help="a folder holding fricctl/ (repeatable; default the installed package)")
    args, _ = ap.parse_known_args()  # run_all.py passes its own filter arguments
    print(f"load average before: {load()} (1, 5, 15 min); {os.cpu_count()} CPUs")
    if args.fresh:
        import fricctl

        sources = ([s.resolve() / "fricctl" for s in args.source] if args.source
                   else [Path(fricctl.__file__).resolve().parent])
        fresh(args.seeds, args.repeat, sources)
        return
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
