"""Compute per sample of each compensator's C export (issue 23: "compute per sample (C)").

Every compensator that has a C export -- the stateful ones of :mod:`fricctl.compensators`
(feedforward, LuGre observer, DOB, integral action) and the 2-4-1 network
(:mod:`fricctl.nn.c_export`) -- is generated for the paper's actuator, compiled with
``gcc -O2 -std=c99 -Wall -Werror`` together with a driver, and stepped ``N`` times on a
synthetic signal (a sinusoidal position and velocity, a torque and a reference) that changes
every sample so that no step can be folded away; the driver sums the outputs and prints the sum
(a checksum the optimiser must compute).  Time per sample = (time of N steps - time of N
iterations of the same loop with no compensator) / N: the loop's own cost is subtracted.

The named alternative of the ratio is the network's step (the paper's compensator): every row
prints its time and its ratio to the network's.  Wall-clock numbers depend on the machine and its
load (printed); the ratios much less.  The Coulomb compensator (``Fc*sign(omega_hat)``, no
export) and no compensation are not listed: one comparison and one multiplication.

Usage: ``python benchmarks/bench_compensator_c.py [--samples 20000000] [--repeats 5]``.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import tempfile
from pathlib import Path

DRIVER = r"""
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <math.h>
#include <time.h>
%(include)s

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int main(int argc, char **argv) {
    long n = atol(argv[1]);
    int with = atoi(argv[2]);
    const double ts = %(ts).17g;
    %(init)s
    double acc = 0.0, tm = 0.0;
    double t0 = now();
    for (long k = 0; k < n; k++) {
        double ph = 1e-3 * (double)(k %% 6283);
        double y = 0.3 * sin(ph), w = 0.3 * cos(ph), r = y + 1e-3;
        double tc = 0.1 * cos(1.3 * ph);
        double est = with ? %(step)s : 0.0;
        tm = tc + est;
        acc += tm + 0.0 * (r + ts);
    }
    double t1 = now();
    printf("%%.15f %%.17g\n", (t1 - t0) / (double)n, acc);
    return 0;
}
"""


def _programs():
    """(name, C name, header, source, init code, step expression) per compensator."""
    from fricctl import compensators
    from fricctl.compensators import c_export
    from fricctl.nn import c_export as nn_c
    from fricctl.paper.benches import bench
    from fricctl.paper.common import designs
    from fricctl.paper.network import train_paper_network

    b = bench("literal")
    model = b.model
    design = designs(b)["fig13-14"]
    out = []
    for name in c_export.exportable():
        options = {"sigma0": 2000.0, "sigma1": 1.0} if name == "lugre_observer" else {}
        comp = compensators.make(name, model, design, model.sample_time, **options)
        cname = f"fc_{name}"
        out.append((name, cname, c_export.c_header(comp, name=cname), c_export.c_source(comp, name=cname),
                    f"{cname}_state st; {cname}_init(&st, ts);",
                    f"{cname}_step(&st, tm, w, y, r, tc)"))
    net = train_paper_network(bench=b, fast=True, seed=0, pipeline="fricctl").net
    out.append(("nn (2-4-1)", "fc_nn", nn_c.c_header(net, name="fc_nn"), nn_c.c_source(net, name="fc_nn"),
                "", "fc_nn_compensation(tm, w, 1.0, 1)"))
    return model.sample_time, out


def _build(folder: Path, ts: float, stem, header, source, init, step) -> Path:
    (folder / f"{stem}.h").write_text(header)
    (folder / f"{stem}.c").write_text(source)
    (folder / f"{stem}_main.c").write_text(DRIVER % {"include": f'#include "{stem}.h"', "ts": ts,
                                                     "init": init, "step": step})
    exe = folder / stem
    subprocess.run(["gcc", "-O2", "-std=c99", "-Wall", "-Werror", "-o", str(exe),
                    str(folder / f"{stem}.c"), str(folder / f"{stem}_main.c"), "-lm"], check=True)
    return exe


def _time(exe: Path, n: int, repeats: int, with_step: int) -> float:
    best = float("inf")
    for _ in range(repeats):
        out = subprocess.run([str(exe), str(n), str(with_step)], check=True, capture_output=True,
                             text=True).stdout.split()
        best = min(best, float(out[0]))
    return best


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=20_000_000)
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args()
    if shutil.which("gcc") is None:
        raise SystemExit("bench_compensator_c: gcc not found")
    print(f"load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    ts, programs = _programs()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, stem, header, source, init, step in programs:
            exe = _build(Path(tmp), ts, stem, header, source, init, step)
            loop = _time(exe, args.samples, args.repeats, 0)
            full = _time(exe, args.samples, args.repeats, 1)
            rows.append((name, max(full - loop, 0.0) * 1e9))
    ref = dict(rows)["nn (2-4-1)"]
    print(f"{'compensator':<16} {'ns/sample':>10} {'/ network':>10}")
    for name, ns in rows:
        print(f"{name:<16} {ns:10.1f} {ns / ref:10.2f}")
    print(f"load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
