"""Benchmark of the friction network (issue 5).

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

import ctypes
import platform
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

from fricctl import nn
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


if __name__ == "__main__":
    import casadi
    import numba

    print(f"Python {platform.python_version()}, numpy {np.__version__}, casadi "
          f"{casadi.__version__}, numba {numba.__version__}, {platform.machine()}")
    bench_training()
    bench_c()
