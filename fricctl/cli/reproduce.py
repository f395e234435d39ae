"""``fricctl reproduce [--out DIR] [--fast] [--seed N]``: the paper on the virtual bench.

Trains the 2-4-1 network once (the paper's pipeline), re-runs the experiments of
Figs. 4-18 and a robustness sweep, and writes into DIR: one PNG per figure
(``fig04.png`` ... ``fig18.png``, ``sweep.png``), ``claims.md`` (the table of
claims, pass/fail, and why the failures fail) and ``claims.json`` (a list of
objects with ``id, claim, paper, measured, passed, figure, note``).  Prints
"N of M claims of the paper reproduced" (the extras, checks of ours marked "not in
the paper", are counted apart).  A claim that fails is reported, not an error: the
exit code is 0 whenever the run completes (2 for bad arguments).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "reproduce", help="re-run the paper's figures and check its claims (writes PNGs, claims.md/json)",
        description=__doc__.split("\n\n", 1)[1], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", type=Path, default=Path("fricctl-reproduce"), metavar="DIR",
                   help="output folder (created if missing; default ./fricctl-reproduce)")
    p.add_argument("--fast", action="store_true",
                   help="short training experiments and a small sweep (about 10 s)")
    p.add_argument("--seed", type=int, default=0, help="seed of the network's split and training (>= 0)")
    p.set_defaults(func=run)


class _Progress:
    """One text line on stderr, rewritten in place: ``[####....] 5/14 fig10  3.2 s``."""

    def __init__(self, stream=None, width: int = 20):
        self.stream = sys.stderr if stream is None else stream
        self.width = width
        self.t0 = time.perf_counter()

    def __call__(self, done: int, total: int, name: str) -> None:
        k = int(round(self.width * done / total))
        line = (f"[{'#' * k}{'.' * (self.width - k)}] {done}/{total} {name:<8s} "
                f"{time.perf_counter() - self.t0:6.1f} s")
        end = "\n" if done >= total else ""
        self.stream.write("\r" + line + end)
        self.stream.flush()


def run(args) -> int:
    if args.seed < 0:
        raise ValueError(f"--seed must be >= 0, got {args.seed}")
    out: Path = args.out
    if out.exists() and not out.is_dir():
        raise ValueError(f"--out {out} exists and is not a folder")
    import matplotlib

    matplotlib.use("Agg")  # files only: never open windows from the command line
    import matplotlib.pyplot as plt

    from ..figures.paper import PAPER_PLOTS, plot_sweep  # figure number -> its registered plot
    from ..paper import claims_json, claims_markdown, reproduce_paper

    out.mkdir(parents=True, exist_ok=True)
    res = reproduce_paper(fast=args.fast, seed=args.seed, progress=_Progress())
    written = []
    for num, result in res.figures.items():
        plot = PAPER_PLOTS.get(num)
        if plot is None:  # a figure module without its @paper_plot: a bug of fricctl, not of the input
            raise RuntimeError(f"Fig. {num} has no plot registered with @paper_plot({num}) in "
                               "fricctl.figures.paper")
        fig = plot(result)
        fig = getattr(fig, "figure", fig)
        path = out / f"fig{num:02d}.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        written.append(path.name)
    ax = plot_sweep(res.sweep)
    ax.figure.savefig(out / "sweep.png", dpi=110)
    plt.close(ax.figure)
    written.append("sweep.png")
    net = res.network
    pre = (f"Virtual bench, {'fast' if args.fast else 'full'} run, seed {args.seed}: network trained on "
           f"{len(net.train)} patterns, held-out fit {net.fit_held_out.fit_percent:.1f} % "
           f"(R^2 {net.fit_held_out.r_squared:.3f}), gain at rest g = {net.net.gain_at_rest():.3f}. "
           "Assumptions of the experiments are listed in `fricctl.paper`'s module docstring.\n\n"
           "Robustness sweep (not a claim of the paper):\n\n```\n" + res.sweep.report() + "\n```")
    (out / "claims.md").write_text(claims_markdown(res.claims, preamble=pre), encoding="utf-8")
    (out / "claims.json").write_text(claims_json(res.claims) + "\n", encoding="utf-8")
    for c in res.claims:
        print(f"{'pass' if c.passed else 'FAIL'}  {c.id:<15s} {c.figure:<8s} {c.measured}")
    print(f"wrote {len(written)} figures, claims.md and claims.json to {out}")
    print(res.summary())
    return 0
