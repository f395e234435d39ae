"""``fricctl reproduce [--out DIR] [--bench NAME] [--seeds N] [--pipelines paper,fricctl] [--workers W] [--executor process|dask] [--scheduler ADDRESS] [--fast] [--force]``.

Trains N networks (seeds 0 .. N-1) with each training pipeline -- "paper" (the paper's
literal recipe) and "fricctl" (the fix) --, re-runs the experiments of Figs. 4-18 and
the coast test on every network and checks the paper's claims on each, on one bench:
"consistent" (the default: the readings under which every statement of the paper holds,
docs/paper_consistency.md, with the sensing a real bench has) or "literal" (the paper's
numbers with fricctl's first readings, noise-free); claims.md and claims.json name it.  A claim
*holds* for a pipeline when it passes in at least 90 % of the seeds; a claim whose
measurement involves compensation also needs the runaway checks (no wind-up, the
velocity reversing under a sinusoidal torque, a coast test that decays).  Writes into
DIR:

  claims.md    the two pipelines side by side (pass rate, median [min, max] of the
               measured number), a summary line per pipeline, and why claims fail;
  claims.json  one object per (claim, pipeline): id, claim, paper, measured, passed,
               figure, note, pipeline, n_seeds, pass_rate, measured_median/min/max, ...;
  nets/<pipeline>-seed<K>.json   every trained network (re-run one with
               `fricctl simulate --compensation nn_confirmed --net ...` for
               the fricctl pipeline's, `--compensation nn` for the paper's);
  figures/<pipeline>-seed<K>/    one PNG per figure of the representative seed (the
               seed whose number of claims passed is the median), the coast test and a
               robustness sweep;
  comparison.md / comparison.json   the paper's continuation on this bench's nominal plant:
               every compensator of fricctl.compare (none, Coulomb at Fc and at the breakaway
               level, the networks of these pipelines and seeds, the static-model feedforward,
               the LuGre observer, the disturbance observer, integral action) on the paper's
               experiments (`fricctl compare` runs the perturbed plants too); the networks
               are the files of nets/, whose SHA-256 comparison.json lists under "nets".

  fricctl-manifest.json   the files this run wrote, with their SHA-256.

The run is written into a new folder beside DIR, which replaces DIR as a whole only
when the run is complete: an interrupted or failed run leaves DIR as it was.  Refuses a
DIR that exists and is not empty, unless --force.  With --force, the files the earlier
run's manifest lists (unchanged since) are the only ones removed; anything else in DIR
(your notes, other networks) is kept in the new DIR.  A claim that fails is reported,
not an error: the exit code is 0 whenever the run completes (2 for bad arguments).
"""

from __future__ import annotations

import argparse
import contextlib
import hashlib
import json
import multiprocessing
import os
import signal
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

#: Most worker processes accepted [-].
MAX_WORKERS = 256
#: The file in DIR that lists what a run wrote there: all that ``--force`` removes.
MANIFEST = "fricctl-manifest.json"
_MANIFEST_FORMAT = "fricctl.reproduce-manifest"


def _cpus() -> int:
    """CPUs this process may run on (the affinity mask where the OS has one)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - macOS, Windows
        return max(1, os.cpu_count() or 1)


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "reproduce", help="re-run the paper's figures over seeds and pipelines and check its claims",
        description=__doc__.split("\n\n", 1)[1], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", type=Path, default=Path("fricctl-reproduce"), metavar="DIR",
                   help="output folder (made if missing; the folder it goes into must exist; "
                        "default ./fricctl-reproduce)")
    # numbers are read as text and checked in run(): a bad value is one line, not argparse's usage block
    p.add_argument("--seeds", default="10", metavar="N",
                   help="networks per pipeline, seeds 0 .. N-1 (default 10)")
    # the names are checked in run(): reading the registry imports fricctl.paper, which every
    # other command's start would pay for
    p.add_argument("--bench", default=None, metavar="NAME",
                   help="the bench the paper is judged on: a name of fricctl.paper.benches.BENCHES "
                        "(an unknown name lists them); default fricctl.paper.benches.DEFAULT_BENCH")
    p.add_argument("--pipelines", default="paper,fricctl", metavar="LIST",
                   help="comma-separated training pipelines (default paper,fricctl)")
    p.add_argument("--workers", default=None, metavar="W",
                   help=f"worker processes (default: the CPUs available, here {_cpus()})")
    p.add_argument("--executor", default=None, metavar="KIND",
                   help="where the seeds, sweeps and figures run: process (a local pool of W workers; "
                        "the default) or dask (a Dask LocalCluster of W workers, or with --scheduler a "
                        "running cluster: docs/cluster.md)")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="join the Dask cluster whose scheduler is at ADDRESS; implies --executor dask")
    p.add_argument("--fast", action="store_true",
                   help="short training experiments and a small sweep (for tests)")
    p.add_argument("--force", action="store_true",
                   help="write into a non-empty DIR, replacing the files an earlier run's "
                        "manifest lists (and nothing else)")
    p.set_defaults(func=run)


class _Progress:
    """One text line on stderr, rewritten in place: ``[####....] 5/23 fricctl seed 2  31.2 s``."""

    def __init__(self, stream=None, width: int = 20):
        self.stream = sys.stderr if stream is None else stream
        self.width = width
        self.t0 = time.perf_counter()

    def __call__(self, done: int, total: int, name: str) -> None:
        k = int(round(self.width * done / total))
        line = (f"[{'#' * k}{'.' * (self.width - k)}] {done}/{total} {name:<24s} "
                f"{time.perf_counter() - self.t0:6.1f} s")
        end = "\n" if done >= total else ""
        self.stream.write("\r" + line + end)
        self.stream.flush()


def _bench_names() -> tuple:
    from ..paper.benches import BENCHES

    return tuple(BENCHES)


def _default_bench() -> str:
    from ..paper.benches import DEFAULT_BENCH

    return DEFAULT_BENCH


def _bench(text) -> str:
    names = _bench_names()
    name = _default_bench() if text is None else str(text).strip()
    if name not in names:
        raise ValueError(f"--bench: unknown bench {name!r}; choose from {', '.join(names)}")
    return name


def _count(name: str, text, low: int, high: int) -> int:
    try:
        n = int(str(text).strip())
    except ValueError:
        raise ValueError(f"{name} must be a whole number, got {text!r}") from None
    if not low <= n <= high:
        raise ValueError(f"{name} must be between {low} and {high}, got {n}")
    return n


def _pipelines(text: str) -> tuple:
    from ..nn.pipelines import PIPELINES
    from .compare import _list

    return _list("--pipelines", text, tuple(PIPELINES), noun="pipeline")


def _prepare_out(out: Path, force: bool) -> None:
    """Refuse a non-empty folder unless ``force``, and a folder this run could not replace
    (checked before the run: a refusal costs nothing)."""
    from ._output import check_new_folder, check_replaceable_folder

    if out.exists() and not out.is_dir():
        raise ValueError(f"--out {out} exists and is not a folder")
    check_new_folder("--out", out)  # the new tree is built beside DIR, whose folder must exist
    if not out.exists():
        return
    check_replaceable_folder("--out", out, "when the run completes")  # now, not after the run
    entries = sorted(out.iterdir())
    if not entries:
        return
    if not force:
        raise ValueError(f"--out {out} is not empty ({len(entries)} entries): pass --force to replace an "
                         "earlier run's files there, or choose another folder")
    for name in ("nets", "figures"):
        if (out / name).exists() and not (out / name).is_dir():
            raise ValueError(f"--out {out / name} is a file where this run writes a folder; move it away")
    _manifest(out)  # readable, before the run


def _digest(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _manifest(folder: Path) -> dict:
    """Relative path -> SHA-256 of the files the run that wrote ``folder`` wrote ({} when it
    has no manifest: a folder fricctl did not write, whose files are all kept)."""
    from .. import _validate as v

    path = folder / MANIFEST
    if not path.is_file():
        return {}
    try:
        data = v.strict_json(path.read_text(encoding="utf-8"), max_depth=4)
        if not (isinstance(data, dict) and data.get("format") == _MANIFEST_FORMAT
                and data.get("version") == 1 and isinstance(data.get("files"), dict)
                and all(isinstance(d, str) for d in data["files"].values())):
            raise ValueError(f"not a {_MANIFEST_FORMAT} version 1 object with a 'files' object")
    except (ValueError, UnicodeDecodeError) as exc:
        raise ValueError(f"--out: {path} is not a manifest fricctl reproduce wrote ({exc}); move it "
                         "away (with it, --force would not know which files an earlier run wrote)") from None
    return data["files"]


def _write_manifest(folder: Path) -> None:
    """List every file in ``folder`` (all written by this run) in its manifest."""
    from .._atomic import write_text

    files = {p.relative_to(folder).as_posix(): _digest(p)
             for p in sorted(folder.rglob("*")) if p.is_file()}
    write_text(folder / MANIFEST, json.dumps({"format": _MANIFEST_FORMAT, "version": 1,
                                              "files": files}, indent=1) + "\n")


def _earlier_run(folder: Path):
    """``keep(rel, file)`` for :func:`fricctl._atomic.replace_folder`: False for the files the
    manifest in ``folder`` lists and that are unchanged since (what an earlier run wrote).
    The manifest is read when the run is complete (another run may have replaced it)."""
    files: list = []

    def keep(rel: str, file: Path) -> bool:
        if rel == MANIFEST:
            return False
        if not files:
            files.append(_manifest(folder))
        digest = files[0].get(rel)
        return digest is None or not file.is_file() or file.is_symlink() or _digest(file) != digest

    return keep


def _worker_init(parent: int, threads: int) -> None:
    """In each worker: leave Ctrl-C to the parent (a terminal sends SIGINT to the whole
    process group; the parent stops the workers), exit when the parent is gone (even
    after ``kill -9`` of it, which would leave a worker blocked on its queue forever), and
    use ``threads`` numba threads (the CPUs shared among the workers: with one, the batch
    simulations run the serial kernel, and the parallel one is never compiled)."""
    import threading

    import numba

    numba.set_num_threads(max(1, min(threads, numba.config.NUMBA_NUM_THREADS)))
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if hasattr(signal, "pthread_sigmask"):  # started with SIGINT held (_Workers.submit)
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(0.2)
        os._exit(1)

    threading.Thread(target=watch, name="fricctl-parent-watch", daemon=True).start()


class _Workers(ProcessPoolExecutor):
    """The worker processes of ``reproduce``: they ignore Ctrl-C (the parent stops them), die
    with the parent (:func:`_worker_init`) and are stopped at once by :meth:`stop`."""

    def __init__(self, workers: int):
        # 'spawn': forking a process whose numba/OpenMP threads have started aborts the workers
        super().__init__(max_workers=workers, mp_context=multiprocessing.get_context("spawn"),
                         initializer=_worker_init, initargs=(os.getpid(), _cpus() // workers))

    def submit(self, *args, **kwargs):
        # a worker is started inside submit: it inherits SIGINT held, so a Ctrl-C while it
        # starts (before _worker_init ignores it) prints no traceback from it
        if not hasattr(signal, "pthread_sigmask"):  # pragma: no cover - Windows
            return super().submit(*args, **kwargs)
        old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
        try:
            return super().submit(*args, **kwargs)
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, old)

    def stop(self) -> None:
        """Cancel the queued jobs and end the running ones now (no waiting for them)."""
        # Python 3.11 has no Executor.terminate_workers (3.14): its process table is private
        procs = list((getattr(self, "_processes", None) or {}).values())
        self.shutdown(wait=False, cancel_futures=True)
        for proc in procs:
            proc.terminate()
        for proc in procs:
            proc.join(timeout=10)


@contextlib.contextmanager
def _worker_pool(workers: int):
    """:class:`_Workers`, stopped at once when the block ends by an exception (Ctrl-C, SIGTERM)."""
    ex = _Workers(workers)
    try:
        yield ex
    except BaseException:
        ex.stop()
        raise
    ex.shutdown(wait=True)


def _label(fig, text: str) -> None:
    """Add ``text`` to the figure's title (the pipeline and seed it shows)."""
    sup = fig.get_suptitle()
    fig.suptitle(f"{sup} ({text})" if sup else text, fontsize="medium")


def _render(bench, fast: bool, pipeline: str, seed: int, net_json: str, sweep, folder: str) -> list:
    """One representative seed's figures as PNGs in ``folder`` (a job: runs in a worker process).

    The network is trained again (read from the disk cache of trained nets when the job that
    judged it left it there) and must be the one judged; the figure results never leave the
    process that draws them (they hold python-control objects that do not pickle).
    """
    import matplotlib

    matplotlib.use("Agg")

    from ..figures.paper import PAPER_PLOTS, plot_coast, plot_sweep
    from ..paper.reproduce import representative_figures
    from ._output import save_figure

    _, figures = representative_figures(bench, fast, pipeline, seed, net_json)
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    plots = []
    for num, result in figures.items():
        plot = PAPER_PLOTS.get(num)
        if plot is None:  # a figure module without its @paper_plot: a bug of fricctl, not of the input
            raise RuntimeError(f"Fig. {num} has no plot registered with @paper_plot({num}) in "
                               "fricctl.figures.paper")
        plots.append((f"fig{num:02d}.png", plot(result)))
    plots.append(("coast.png", plot_coast(figures[9].coast)))
    plots.append(("sweep.png", plot_sweep(sweep)))
    written = []
    for fname, obj in plots:
        fig = getattr(obj, "figure", obj)
        _label(fig, f"{pipeline} pipeline, seed {seed}")
        save_figure(fig, folder / fname, overwrite=True)  # atomic; --force governs the folder
        written.append(str(folder / fname))
    return written


def _write_figures(res, out: Path, executor) -> list:
    """The representative seeds' figures, one job per pipeline (in parallel through ``executor``)."""
    args = [(res.bench, res.fast, name, res.representative[name],
             res.runs[(name, res.representative[name])].net_json, res.sweeps[name],
             str(out / "figures" / f"{name}-seed{res.representative[name]}")) for name in res.pipelines]
    if executor is None:
        return [f for a in args for f in _render(*a)]
    futures = [executor.submit(_render, *a) for a in args]
    return [f for fut in futures for f in fut.result()]


#: The network contender of each training pipeline (fricctl.compare.contenders).
_PIPELINE_CONTENDER = {"fricctl": "nn", "paper": "nn_paper"}


def _comparison(bench: str, fast: bool, seeds: int, pipelines: tuple, executor, nets: dict):
    """Every contender on the bench's nominal plant, the networks of ``pipelines`` only: the
    very networks the run wrote, ``nets[pipeline][seed]`` (their files' text; seeds 0 ..
    ``seeds`` - 1), not trained again nor read back from the cache of trained networks."""
    from ..compare import CONTENDERS, compare

    names = {_PIPELINE_CONTENDER[p]: p for p in pipelines}
    comps = [n for n in CONTENDERS if n not in _PIPELINE_CONTENDER.values() or n in names]
    options = {n: {"fast": True} for n in comps if fast and "fast" in (CONTENDERS[n].options or ())}
    for n, p in names.items():
        options[n] = {**options.get(n, {}), "networks": [nets[p][s] for s in range(seeds)]}
    return compare(compensators=comps, plants=["nominal"], seeds=seeds, bench=bench,
                   options=options, executor=executor)


def _comparison_json(cmp, digests: dict) -> str:
    """comparison.json: the comparison's rows and, under ``"nets"``, the SHA-256 of each network
    file (``nets/<pipeline>-seed<K>.json``) its network rows ran."""
    d = json.loads(cmp.to_json())
    d["nets"] = digests
    return json.dumps(d, indent=1, allow_nan=False)


def claims_table(stats, pipelines) -> str:
    """The claims as printed: one line per claim, ``holds k/n`` or ``FAILS k/n`` per pipeline,
    the first column as wide as the longest claim id (``fig16-coulomb-fs`` pushed its row one
    column right of the others at a fixed 15)."""
    ids = list(dict.fromkeys(s.id for s in stats))
    by = {(s.id, s.pipeline): s for s in stats}
    width = max([len("claim"), *map(len, ids)])
    lines = [f"{'claim':<{width}s} " + " ".join(f"{p:>18s}" for p in pipelines)]
    for cid in ids:
        cells = [f"{'holds' if s.holds else 'FAILS'} {s.n_passed:>3d}/{s.n_seeds:<3d}".rjust(18)
                 for s in (by[(cid, p)] for p in pipelines)]
        lines.append(f"{cid:<{width}s} " + " ".join(cells))
    return "\n".join(lines)


def run(args) -> int:
    from ..paper.reproduce import MAX_SEEDS

    bench = _bench(args.bench)
    seeds = _count("--seeds", args.seeds, 1, MAX_SEEDS)
    pipelines = _pipelines(args.pipelines)
    workers = _cpus() if args.workers is None else _count("--workers", args.workers, 1, MAX_WORKERS)
    from .compare import executor_of

    kind, scheduler = executor_of(args, ("process", "dask"), "process")
    out: Path = args.out
    _prepare_out(out, args.force)
    import matplotlib

    matplotlib.use("Agg")  # files only: never open windows from the command line

    from .._atomic import replace_folder, write_text
    from ..nn import save_net
    from ..paper import reproduce_paper

    workers = min(workers, seeds * len(pipelines))
    if kind == "process" and workers == 1:
        kind = "serial"
    progress = _Progress()
    # the whole tree is built beside DIR and replaces it only when complete (issue 26)
    with replace_folder(out, keep=_earlier_run(Path(os.path.realpath(out))),
                        overwrite=args.force) as new, contextlib.ExitStack() as stack:
        from .compare import _executor

        ex = stack.enter_context(_executor(kind, workers, scheduler))
        res = reproduce_paper(bench=bench, fast=args.fast, seeds=seeds, pipelines=pipelines, executor=ex,
                              progress=progress, figures=False)
        t0 = time.perf_counter()
        figures = _write_figures(res, new, ex)
        print(f"figures of the representative seeds drawn in {time.perf_counter() - t0:.1f} s",
              file=sys.stderr)
        (new / "nets").mkdir()
        nets, digests = {p: {} for p in pipelines}, {}
        for (name, seed), r in res.runs.items():
            path = save_net(r.net, new / "nets" / f"{name}-seed{seed}.json")
            nets[name][seed] = path.read_text(encoding="utf-8")  # the comparison runs these files
            digests[f"nets/{path.name}"] = _digest(path)
        write_text(new / "claims.md", res.markdown())
        write_text(new / "claims.json", res.json() + "\n")
        t0 = time.perf_counter()
        cmp = _comparison(bench, args.fast, seeds, pipelines, ex, nets)
        write_text(new / "comparison.md", cmp.table())
        write_text(new / "comparison.json", _comparison_json(cmp, digests) + "\n")
        print(f"the compensators compared on the nominal plant in {time.perf_counter() - t0:.1f} s",
              file=sys.stderr)
        _write_manifest(new)
    print(f"bench {bench}")
    print(claims_table(res.stats, pipelines))
    where = (scheduler if scheduler is not None else
             f"{workers} worker{'s' if workers != 1 else ''}{', dask' if kind == 'dask' else ''}")
    print(f"wrote {len(res.runs)} networks, {len(figures)} figures, claims.md, claims.json and the "
          f"comparison (comparison.md, .json) to {out} "
          f"({time.perf_counter() - progress.t0:.0f} s, {where})")
    print(res.summary())
    return 0
