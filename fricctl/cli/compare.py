"""``fricctl compare --out DIR [--seeds N] [--compensators LIST] [--experiments LIST] [--plants LIST] [--sigma0 S] [--sigma1 D] [--executor serial|process|dask] [--workers N] [--scheduler ADDRESS] [--force]``.

Runs every compensator on the paper's experiments (dead zone, PD steps, small steps, sawtooth
tracking, coast, limit cycle) and on perturbed plants (friction x0.8 and x1.2, wear, the SCARA
link, Stribeck velocity x0.5 and x2, a coarser encoder, one more sample of delay, torque noise),
the trained networks -- and every compensator on the noisy plant -- over seeds 0 .. N-1
(fricctl.compare).  Writes into DIR:

  comparison.json  {"rows": [...]}: one row per compensator x experiment x plant, with the
                   plant as an object, each metric with its unit (median, min, max and the
                   value of every seed) and the runaway checks passed;
  comparison.md    the same as Markdown tables, one per experiment.

Both are written atomically; an existing comparison.json or comparison.md in DIR is refused
unless --force.  --executor process runs the jobs on W local worker processes; --executor dask
starts a Dask LocalCluster of W single-threaded worker processes, or with --scheduler ADDRESS
joins a running Dask cluster (docs/cluster.md).  The rows are the same bit for bit whichever
executor ran them.  --sigma0 and --sigma1 give the LuGre observer its bristle (stiffness
[N*m/rad], damping [N*m*s/rad]; a unit suffix such as 2e4N*m/rad is accepted) in place of the
assumed one of a design model without a LuGre law (fricctl.compare.contenders.BRISTLE_COUNTS
encoder counts at the breakaway level, sigma1 = sqrt(sigma0 * I)), or of the model's own law.  Exit code 0 when the run completes (whatever it measured), 2 for bad
arguments.
"""

from __future__ import annotations

import argparse
import contextlib
import sys
import time
from pathlib import Path

from .reproduce import MAX_WORKERS, _count, _cpus

#: The executors ``--executor`` names.
EXECUTORS = ("serial", "process", "dask")
#: The files the command writes into DIR.
OUTPUTS = ("comparison.json", "comparison.md")


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "compare", help="every friction compensator on the paper's experiments and perturbed plants",
        description=__doc__.split("\n\n", 1)[1], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", type=Path, default=Path("fricctl-compare"), metavar="DIR",
                   help="output folder (made if missing; the folder it goes into must exist; "
                        "default ./fricctl-compare)")
    # numbers and names are read as text and checked in run(): one line, not argparse's usage block
    p.add_argument("--seeds", default="10", metavar="N",
                   help="seeds of the trained networks, 0 .. N-1 (default 10)")
    p.add_argument("--compensators", default=None, metavar="LIST",
                   help="comma-separated names of fricctl.compare.CONTENDERS (default all)")
    p.add_argument("--experiments", default=None, metavar="LIST",
                   help="comma-separated names of fricctl.compare.EXPERIMENTS (default all)")
    p.add_argument("--plants", default=None, metavar="LIST",
                   help="comma-separated names of fricctl.compare.PLANTS (default all)")
    p.add_argument("--sigma0", default=None, metavar="S",
                   help="lugre_observer's bristle stiffness sigma0 [N*m/rad] (default: the model's LuGre "
                        "law, or the assumed bristle of BRISTLE_COUNTS encoder counts at Fs)")
    p.add_argument("--sigma1", default=None, metavar="D",
                   help="lugre_observer's bristle damping sigma1 [N*m*s/rad] (default: the model's LuGre "
                        "law, or sqrt(sigma0 * I), I the joint's total inertia: damping ratio 0.5, "
                        "Canudas de Wit et al.'s example; the same rule as fricctl simulate)")
    p.add_argument("--bench", default=None, metavar="NAME",
                   help="the bench (fricctl.paper.benches.BENCHES); default the paper's default bench")
    p.add_argument("--executor", default=None, metavar="KIND",
                   help=f"where the jobs run: {', '.join(EXECUTORS)} (default serial; dask with --scheduler)")
    p.add_argument("--workers", default=None, metavar="W",
                   help=f"worker processes of --executor process or dask (default the CPUs, here {_cpus()})")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="join the Dask cluster whose scheduler is at ADDRESS (tcp://host:8786); "
                        "implies --executor dask")
    p.add_argument("--fast", action="store_true",
                   help="networks trained on the short experiments (for tests)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--force", action="store_true", help="replace comparison.json/.md in DIR")
    p.set_defaults(func=run)


def _list(option: str, text, known, noun: str | None = None) -> tuple | None:
    """The names of a comma-separated ``text`` (None: all), each one of ``known``; ``noun``
    names what they are in the messages (``--pipelines``: "pipeline")."""
    if text is None:
        return None
    names = tuple(s.strip() for s in str(text).split(","))
    if not all(names):
        raise ValueError(f"{option} must be names separated by commas, got {text!r}")
    unknown = [n for n in names if n not in known]
    if unknown:
        raise ValueError(f"{option}: unknown {noun or 'name'} {unknown[0]!r}; choose from {', '.join(known)}")
    if len(set(names)) != len(names):
        raise ValueError(f"{option} names {'a ' + noun if noun else 'one'} twice: {text!r}")
    return names


def _check_out(out: Path, force: bool) -> None:
    from ._output import check_new_folder

    if out.exists() and not out.is_dir():
        raise ValueError(f"--out {out} exists and is not a folder")
    if not out.is_dir():  # made after the run: its folder must exist (is not made) and be writable
        check_new_folder("--out", out)
    there = [n for n in OUTPUTS if (out / n).exists()]
    if there and not force:
        raise ValueError(f"--out {out} already holds {there[0]}: pass --force to replace it, or choose "
                         "another folder")
    for n in there:
        if (out / n).is_dir():
            raise ValueError(f"--out {out / n} is a folder where this command writes a file; move it away")


def executor_of(args, kinds: tuple, default: str) -> tuple:
    """``(kind, scheduler)`` of ``--executor`` (one of ``kinds``; ``default``, or dask with
    ``--scheduler``) and ``--scheduler`` (None, or the address), checked together with
    ``--workers`` (shared by ``compare`` and ``reproduce``)."""
    scheduler = None if args.scheduler is None else str(args.scheduler).strip()
    kind = ("dask" if scheduler is not None else default) if args.executor is None else \
        str(args.executor).strip()
    if kind not in kinds:
        raise ValueError(f"--executor must be one of {', '.join(kinds)}, got {args.executor!r}")
    if scheduler is not None:
        if not scheduler:
            raise ValueError("--scheduler needs an address, e.g. tcp://10.0.0.1:8786")
        if kind != "dask":
            raise ValueError(f"--scheduler joins a Dask cluster: it needs --executor dask, not {kind}")
        if args.workers is not None:
            raise ValueError("--workers starts a local cluster; with --scheduler the cluster's own "
                             "workers run the jobs: give one or the other")
    return kind, scheduler


@contextlib.contextmanager
def _executor(kind: str, workers: int, scheduler: str | None):
    """The executor of ``--executor`` (None for serial), closed when the block ends."""
    if kind == "serial":
        yield None
        return
    if kind == "process":
        from .reproduce import _worker_pool

        with _worker_pool(workers) as ex:
            yield ex
        return
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        raise ValueError("--executor dask needs Dask distributed: pip install 'fricctl[dask]' "
                         "(or 'dask[distributed]')") from None
    if scheduler is not None:
        with Client(scheduler, timeout="30s") as client:
            yield client.get_executor()
        return
    # one thread per worker process: the jobs are compiled numerics holding the GIL; no dashboard
    # (its fixed port would collide with another cluster on the machine)
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        yield client.get_executor()


def bristle(args, compared) -> dict:
    """The LuGre observer's options of ``--sigma0`` / ``--sigma1`` (``{}`` without them), each a
    finite number > 0 (>= 0 for the damping) in its unit; refused when ``compared`` (the
    compensators run) leaves the observer out."""
    from .simulate import bristle_options

    given = [k for k in ("sigma0", "sigma1") if getattr(args, k) is not None]
    if given and "lugre_observer" not in compared:
        raise ValueError(f"--{given[0]} has no effect: it is lugre_observer's, which --compensators "
                         "leaves out")
    return bristle_options(args)  # the benches are rotary


def run(args) -> int:
    from ..compare import CONTENDERS, EXPERIMENTS, PLANTS
    from ..compare.protocol import MAX_SEEDS
    from .reproduce import _bench

    seeds = _count("--seeds", args.seeds, 1, MAX_SEEDS)
    comps = _list("--compensators", args.compensators, tuple(CONTENDERS))
    exps = _list("--experiments", args.experiments, tuple(EXPERIMENTS))
    plants = _list("--plants", args.plants, tuple(PLANTS))
    bench = _bench(args.bench)
    kind, scheduler = executor_of(args, EXECUTORS, "serial")
    if kind == "serial" and args.workers is not None:
        raise ValueError("--workers needs --executor process or dask")
    workers = _cpus() if args.workers is None else _count("--workers", args.workers, 1, MAX_WORKERS)
    out: Path = args.out
    _check_out(out, args.force)

    from .._atomic import write_text
    from ..compare import compare

    options = {n: {"fast": True} for n in (comps or CONTENDERS)
               if args.fast and "fast" in (CONTENDERS[n].options or ())}
    lugre = bristle(args, comps or tuple(CONTENDERS))
    if lugre:
        options["lugre_observer"] = lugre
    t0 = time.perf_counter()
    with _executor(kind, workers, scheduler) as ex:
        res = compare(compensators=comps, experiments=exps, plants=plants, seeds=seeds, bench=bench,
                      options=options, executor=ex, progress=not args.quiet)
    out.mkdir(exist_ok=True)  # its folder is not made: a typo in a path became a new tree
    write_text(out / "comparison.json", res.to_json() + "\n", overwrite=args.force)
    write_text(out / "comparison.md", res.table(), overwrite=args.force)
    failed = [r for r in res.rows if r["runaway"]["failures"]]
    unjudged = [r for r in res.rows if r["runaway"].get("not_judged")]
    errors = [r for r in res.rows if r["errors"]]
    print(f"bench {bench}: {len(res.compensators)} compensators x {len(res.experiments)} experiments x "
          f"{len(res.plants)} plants = {len(res.rows)} rows, seeds 0..{seeds - 1} for the trained "
          f"networks; {len(failed)} rows with a runaway check failed in some run"
          + (f", {len(unjudged)} rows with runs too short for a check to judge" if unjudged else "")
          + (f", {len(errors)} rows with runs that could not be made (comparison.md says why)"
             if errors else ""))
    print(f"wrote comparison.json and comparison.md to {out} ({time.perf_counter() - t0:.0f} s, "
          f"executor {kind}{'' if kind == 'serial' else f', {workers if scheduler is None else scheduler}'})")
    return 0
