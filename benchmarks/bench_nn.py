"""Benchmark of the friction network (issues 5 and 11).

1. Training: wall time for the CasADi Levenberg-Marquardt trainer
   (:func:`fricctl.nn.train_casadi`) to reach the final training loss of the
   paper's back-propagation with momentum (:func:`fricctl.nn.train_backprop`,
   per-pattern updates, numba inner loop), on the same patterns.  Both times
   are first-hitting times of that loss from the trainer's own history; the
   CasADi time is "cold" (the CasADi residual/Jacobian function is built inside
   the timed region) unless stated.  Target: >= 50x.
2. Evaluation: nanoseconds per call of the generated C function
   (:func:`fricctl.nn.c_source`, ``cc -O2``), timed over a C loop of 10^6
   samples, against the paper's real-time budget of 2 ms per sample; with the
   ctypes per-call overhead and numpy's scalar evaluation for comparison.

Run: ``.venv/bin/python benchmarks/bench_nn.py`` (about a minute on 2 cores).
"""

from __future__ import annotations

import argparse
import ctypes
import math
import platform
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

from fricctl import nn, paper
from fricctl.bench.experiments import train_network
from fricctl.nn.train.backprop import CONVERGING
from fricctl.nn.train.lm import clear_cache

SEEDS = range(5)
BP = dict(learning_rate=0.01, momentum=0.9, batch_size=1)
EPOCHS = (500, 2000, 10000)
CASES = {
    "sliding only, 800": dict(n_sliding=800, n_stuck=0),
    "sliding 800 + stuck 200": dict(n_sliding=800, n_stuck=200),
}


def bench_training():
    rows = []
    for case, kw in CASES.items():
        pats = nn.smooth_friction_patterns(np.random.default_rng(100), **kw)
        tm, om, f = pats.tm, pats.omega, pats.friction
        for epochs in EPOCHS:
            ratios, ratios_warm, t_bp_all, t_cas_all, fits_bp, fits_cas = [], [], [], [], [], []
            for seed in SEEDS:
                bp_res = nn.train_backprop(tm, om, f, epochs=epochs,
                                           rng=np.random.default_rng(seed), **BP)
                bp_net, bp = bp_res.net, bp_res.history
                target = bp.loss[-1]
                t_bp = bp.time_to_reach(target)  # first hit: SGD's loss fluctuates
                clear_cache()  # cold: build the CasADi functions in the timed region
                cas_res = nn.train_casadi(tm, om, f, restarts=3, rng=np.random.default_rng(seed))
                cas_net, cas = cas_res.net, cas_res.history
                t_cas = cas.time_to_reach(target)
                cas_warm = nn.train_casadi(tm, om, f, restarts=3,
                                           rng=np.random.default_rng(seed)).history
                t_warm = cas_warm.time_to_reach(target)
                ratios.append(t_bp / t_cas)
                ratios_warm.append(t_bp / t_warm)
                t_bp_all.append(t_bp)
                t_cas_all.append(t_cas)
                fits_bp.append(bp_net.metadata["fit_percent"])
                fits_cas.append(cas_net.metadata["fit_percent"])
            rows.append((case, epochs, np.median(t_bp_all), np.median(t_cas_all),
                         np.min(ratios), np.median(ratios), np.median(ratios_warm),
                         np.median(fits_bp), np.median(fits_cas)))
            print(".", end="", flush=True)
    print("\n\n### Training: CasADi LM vs back-propagation with momentum "
          f"(lr {BP['learning_rate']}, momentum {BP['momentum']}, per pattern; "
          f"{len(SEEDS)} seeds, median unless stated)\n")
    print("| patterns | back-prop epochs | back-prop time to its final loss [s] "
          "| CasADi LM time to that loss, cold [s] | speed-up cold, min / median "
          "| speed-up warm, median | fit back-prop [%] | fit CasADi, final [%] |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r[0]} | {r[1]} | {r[2]:.3f} | {r[3]:.4f} | {r[4]:.0f}x / {r[5]:.0f}x "
              f"| {r[6]:.0f}x | {r[7]:.2f} | {r[8]:.2f} |")


def bench_c():
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        print("\nno C compiler: C timing skipped")
        return
    pats = nn.smooth_friction_patterns(np.random.default_rng(100), n_sliding=800,
                                            n_stuck=200)
    tm, om, f = pats.tm, pats.omega, pats.friction
    net = nn.train_casadi(tm, om, f, restarts=1, rng=np.random.default_rng(0)).net
    n = 1_000_000
    rng = np.random.default_rng(1)
    x0 = rng.uniform(net.envelope_low[0], net.envelope_high[0], n)
    x1 = rng.uniform(net.envelope_low[1], net.envelope_high[1], n)
    out = np.empty(n)
    with tempfile.TemporaryDirectory() as d:
        src = Path(d) / "net.c"
        lib = Path(d) / "libnet.so"
        src.write_text(nn.c_source(net, name="net"))
        subprocess.run([cc, "-O2", "-shared", "-fPIC", "-std=c99", str(src), "-o", str(lib),
                        "-lm"], check=True)
        so = ctypes.CDLL(str(lib))
        dp = ctypes.POINTER(ctypes.c_double)
        so.net_batch.argtypes = [dp, dp, dp, ctypes.c_long, ctypes.c_int]
        so.net.restype = ctypes.c_double
        so.net.argtypes = [ctypes.c_double, ctypes.c_double, ctypes.c_int]
        best = {}
        for clip in (0, 1):
            ts = []
            for _ in range(5):
                t0 = time.perf_counter()
                so.net_batch(x0.ctypes.data_as(dp), x1.ctypes.data_as(dp),
                             out.ctypes.data_as(dp), n, clip)
                ts.append(time.perf_counter() - t0)
            best[clip] = min(ts) / n * 1e9
        assert np.max(np.abs(out - net(x0, x1, clip=True))) < 1e-12
        m = 20000
        a, b = x0[:m].tolist(), x1[:m].tolist()
        t0 = time.perf_counter()
        for u, v in zip(a, b):
            so.net(u, v, 1)
        t_ctypes = (time.perf_counter() - t0) / m * 1e9
    m = 5000
    t0 = time.perf_counter()
    for u, v in zip(x0[:m], x1[:m]):
        net(u, v, clip=True)
    t_numpy = (time.perf_counter() - t0) / m * 1e9
    budget = 2e-3 * 1e9
    print("\n### Evaluation of the 2-4-1 net, per sample\n")
    print("| implementation | ns per call | fraction of the 2 ms budget |")
    print("|---|---|---|")
    for name, t in (("C (cc -O2), loop in C, clip=0", best[0]),
                    ("C (cc -O2), loop in C, clip=1", best[1]),
                    ("C via ctypes, one call from Python, clip=1", t_ctypes),
                    ("FrictionNet.__call__ (numpy), scalar, clip=True", t_numpy)):
        print(f"| {name} | {t:.1f} | {t / budget:.1e} |")


TOLERANCE = 0.05   # back-prop reaches LM when its final loss <= (1 + TOLERANCE) x LM's
PAPER_BP = dict(learning_rate=0.05, momentum=0.9, epochs=2000)  # chapter 04, full mode


def _mse(net, pats) -> float:
    return float(np.mean((net(pats.tm, pats.omega) - pats.friction) ** 2))


def backprop_to_lm(*, fast: bool, seed: int) -> dict:
    """One seed of part 3: LM and back-prop on the same paper patterns (see the docstring)."""
    run = paper.train_paper_network(fast=fast, seed=seed)  # the patterns (its LM net may be cached)
    lm = train_network(run.train, trainer="casadi", rng=np.random.default_rng(seed))
    bp = train_network(run.train, trainer="backprop", rng=np.random.default_rng(seed), **CONVERGING)
    const = train_network(run.train, trainer="backprop", rng=np.random.default_rng(seed),
                          **PAPER_BP)
    lm_loss = float(lm.history.loss[-1])
    target = (1.0 + TOLERANCE) * lm_loss
    hit = np.flatnonzero(bp.history.loss <= target)
    t_bp = bp.history.time_to_reach(target)
    t_lm = lm.history.time_to_reach(target)
    return dict(seed=seed, lm_loss=lm_loss, bp_ratio=float(bp.history.loss[-1]) / lm_loss,
                reached=bool(bp.history.loss[-1] <= target),
                epochs=int(hit[0]) if hit.size else math.inf, t_bp=t_bp, t_lm=t_lm,
                t_lm_total=float(lm.history.elapsed[-1]), t_bp_total=float(bp.history.elapsed[-1]),
                const_ratio=float(const.history.loss[-1]) / lm_loss,
                const_last_half=(float(np.min(const.history.loss[PAPER_BP["epochs"] // 2:])),
                                 float(np.max(const.history.loss[PAPER_BP["epochs"] // 2:]))),
                held_ratio=_mse(bp.net, run.held_out) / _mse(lm.net, run.held_out),
                g_bp=bp.net.gain_at_rest(), g_lm=lm.net.gain_at_rest(),
                best_restart=bp.net.metadata["best_restart"])


def bench_paper_patterns(*, fast: bool, seeds) -> list[dict]:
    rows = []
    for seed in seeds:
        rows.append(backprop_to_lm(fast=fast, seed=seed))
        print(".", end="", flush=True)
    mode = "fast" if fast else "full"
    opts = ", ".join(f"{k}={v}" for k, v in CONVERGING.items())
    print(f"\n\n### Back-prop to LM's loss, paper's patterns ({mode} mode, {len(rows)} seeds; "
          f"back-prop {opts}; tolerance {TOLERANCE:.0%})\n")
    print("| seed | LM loss [(N*m)^2] | back-prop / LM, final | reached | epochs to LM's loss "
          "| back-prop time to it [s] | LM time to it [s] | ratio | held-out MSE back-prop / LM "
          "| paper's constant rate: final / LM |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        ratio = r["t_bp"] / r["t_lm"]
        print(f"| {r['seed']} | {r['lm_loss']:.5f} | {r['bp_ratio']:.3f} | "
              f"{'yes' if r['reached'] else 'no'} | {r['epochs']} | {r['t_bp']:.2f} | "
              f"{r['t_lm']:.2f} | {ratio:.1f}x | {r['held_ratio']:.3f} | {r['const_ratio']:.1f} |")
    ok = [r for r in rows if r["reached"]]

    def mmm(xs, fmt):
        xs = np.asarray(xs, dtype=float)
        return (f"{fmt.format(np.median(xs))} / {fmt.format(xs.min())} / {fmt.format(xs.max())}"
                if xs.size else "-")

    print(f"\nReached LM's loss (within {TOLERANCE:.0%}): **{len(ok)}/{len(rows)}** seeds.  "
          "Median / min / max:\n")
    print("| quantity | median / min / max |")
    print("|---|---|")
    print(f"| back-prop final loss / LM's, all seeds | {mmm([r['bp_ratio'] for r in rows], '{:.3f}')} |")
    print(f"| back-prop final loss [(N*m)^2], all seeds | "
          f"{mmm([r['bp_ratio'] * r['lm_loss'] for r in rows], '{:.5f}')} |")
    print(f"| LM final loss [(N*m)^2], all seeds | {mmm([r['lm_loss'] for r in rows], '{:.5f}')} |")
    print(f"| epochs to LM's loss, seeds reached | {mmm([r['epochs'] for r in ok], '{:.0f}')} |")
    print(f"| back-prop time to LM's loss [s], seeds reached | {mmm([r['t_bp'] for r in ok], '{:.2f}')} |")
    print(f"| LM time to the same loss [s] | {mmm([r['t_lm'] for r in ok], '{:.2f}')} |")
    print(f"| ratio back-prop / LM time, seeds reached | "
          f"{mmm([r['t_bp'] / r['t_lm'] for r in ok], '{:.1f}')} |")
    print(f"| back-prop total time ({CONVERGING['restarts']} starts) / LM total time | "
          f"{mmm([r['t_bp_total'] / r['t_lm_total'] for r in rows], '{:.1f}')} |")
    print(f"| held-out MSE back-prop / LM, all seeds | {mmm([r['held_ratio'] for r in rows], '{:.3f}')} |")
    print(f"| gain at rest dTat/dTm, back-prop | {mmm([r['g_bp'] for r in rows], '{:.2f}')} |")
    print(f"| gain at rest dTat/dTm, LM | {mmm([r['g_lm'] for r in rows], '{:.2f}')} |")
    print(f"| best of the {CONVERGING['restarts']} starts (0 = first) | "
          f"{mmm([r['best_restart'] for r in rows], '{:.0f}')} |")
    print(f"| paper's constant rate ({PAPER_BP}): final / LM | "
          f"{mmm([r['const_ratio'] for r in rows], '{:.1f}')} |")
    print(f"| paper's constant rate: min over the last half / LM | "
          f"{mmm([r['const_last_half'][0] / r['lm_loss'] for r in rows], '{:.2f}')} |")
    print(f"| paper's constant rate: max over the last half / LM | "
          f"{mmm([r['const_last_half'][1] / r['lm_loss'] for r in rows], '{:.1f}')} |")
    return rows


if __name__ == "__main__":
    import casadi
    import numba

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--only", choices=("training", "c", "paper"), default=None)
    ap.add_argument("--seeds", type=int, default=20, help="seeds of part 3 (full mode)")
    ap.add_argument("--fast-seeds", type=int, default=10, help="seeds of part 3 (fast mode)")
    args = ap.parse_args()
    print(f"Python {platform.python_version()}, numpy {np.__version__}, casadi "
          f"{casadi.__version__}, numba {numba.__version__}, {platform.machine()}")
    if args.only in (None, "training"):
        bench_training()
    if args.only in (None, "c"):
        bench_c()
    if args.only in (None, "paper"):
        bench_paper_patterns(fast=False, seeds=range(args.seeds))
        if args.fast_seeds:
            bench_paper_patterns(fast=True, seeds=range(args.fast_seeds))
