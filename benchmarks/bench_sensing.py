"""Which claims each sensing item of a bench changes (issue 22, item 2), and the claims rated with
the bench's sensing on.

For one bench (default the consistent one), every claim of both pipelines over ``--seeds`` seeds
with the bench's sensing switched five ways: off (noise- and ripple-free, today's method), each
item alone (encoder edge jitter; current-loop torque noise; the drive's torque ripple), and all
of it (the bench as shipped).  The networks are the same in the five (trained on the clean
records; the disk cache trains each once), so a difference between two columns is the
sensing's alone.  A cell is "passed/seeds";
a claim *holds* at >= 90 % of the seeds.

``--sweep``: instead, Fig. 16's Coulomb pair (``fig16-coulomb-fs`` oscillates, ``fig16-coulomb-fc``
does not) against the edge jitter sigma on both benches, torque noise off and on, the ripple off
(a deterministic torque: it makes nothing flicker, ``tests/test_paper_sensing.py``), over 5 seeds
of the sensing noise on one fast fricctl network (the Coulomb runs do not involve its weights).

Usage: ``python benchmarks/bench_sensing.py [--bench consistent] [--seeds 10] [--fast] [--sweep]``.
"""

from __future__ import annotations

import argparse
import multiprocessing
import os
import time
from concurrent.futures import ProcessPoolExecutor

from fricctl import paper
from fricctl.paper import fig16
from fricctl.paper.benches import BENCHES, bench

#: Edge jitters of the sweep [counts].
SIGMAS = (0.0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5)


def sweep(noise_seeds: int = 5) -> None:
    """Fig. 16's Coulomb pair over :data:`SIGMAS`, both benches, the consistent bench's torque noise
    off and on: seeds where each claim passes."""
    noise = bench("consistent").sensing.torque_noise
    print("| sigma [counts] | bench | torque noise [N*m] | fs passes | fc passes | per seed: (fs crossings, "
          "fs counts, fc crossings, fc counts) |")
    print("|---|---|---|---|---|---|")
    for name in ("consistent", "literal"):
        net = paper.train_paper_network(bench=name, fast=True, seed=0, pipeline="fricctl")
        for sigma in SIGMAS:
            for tn in (0.0, noise):
                b = bench(name).with_sensing("bench_sensing.py --sweep", encoder_jitter=sigma, torque_noise=tn,
                                             torque_ripple=0.0)
                rs = [fig16.run(net.sensed_on(b, k)) for k in range(noise_seeds)]
                fs = sum(fig16.claim_fig16_coulomb_fs(r, b).passed for r in rs)
                fc = sum(fig16.claim_fig16_coulomb_fc(r, b).passed for r in rs)
                per = [(r.reference_crossings[k1], r.cycles[k1].counts, r.reference_crossings[k2], r.cycles[k2].counts)
                       for r in rs for k1, k2 in [(fig16.COULOMB_RUNS[0], fig16.COULOMB_RUNS[1])]]
                print(f"| {sigma:g} | {name} | {tn:.3g} | {fs}/{noise_seeds} | {fc}/{noise_seeds} | {per} |", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--bench", choices=tuple(BENCHES), default="consistent")
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--fast", action="store_true", help="short training experiments")
    ap.add_argument("--pipelines", default="fricctl,paper")
    ap.add_argument("--sweep", action="store_true", help="Fig. 16's Coulomb pair against the jitter")
    args = ap.parse_args()
    if args.sweep:
        sweep()
        return
    b = bench(args.bench)
    s = b.sensing
    pipelines = tuple(args.pipelines.split(","))
    jitter, noise, ripple = s.encoder_jitter, s.torque_noise, s.torque_ripple
    period, phase = s.torque_ripple_period, s.torque_ripple_phase
    if s.ideal:  # a bench without sensing: switch on the consistent bench's items
        ref = bench("consistent").sensing
        jitter, noise, ripple = ref.encoder_jitter, ref.torque_noise, ref.torque_ripple
        period, phase = ref.torque_ripple_period, ref.torque_ripple_phase
    # the bench as shipped and without sensing first (the claims rated with the sensing on, and before)
    configs = {"all": (jitter, noise, ripple), "off": (0.0, 0.0, 0.0), "jitter alone": (jitter, 0.0, 0.0),
               "torque noise alone": (0.0, noise, 0.0), "ripple alone": (0.0, 0.0, ripple)}
    print(f"bench {b.name}; items switched on: encoder jitter {jitter:g} counts, torque noise {noise:g} "
          f"N*m, torque ripple {ripple:g} N*m of period {period:.6g} rad (phase {phase} rad); velocity "
          f"{s.velocity_estimate}; {args.seeds} seeds, {'fast' if args.fast else 'full'} mode")
    print(f"load average before: {os.getloadavg()[0]:.2f}")
    results = {}
    with ProcessPoolExecutor(max_workers=2, mp_context=multiprocessing.get_context("spawn")) as ex:
        for name, (j, n, a) in configs.items():
            t0 = time.perf_counter()
            bb = b.with_sensing(f"bench_sensing.py: {name}", encoder_jitter=j, torque_noise=n,
                                torque_ripple=a, torque_ripple_period=period, torque_ripple_phase=phase)
            results[name] = paper.reproduce_paper(bench=bb, fast=args.fast, seeds=args.seeds,
                                                  pipelines=pipelines, executor=ex, figures=False)
            print(f"{name}: {time.perf_counter() - t0:.0f} s (load average {os.getloadavg()[0]:.2f})",
                  flush=True)
            for pipe in pipelines:  # each configuration as it is done (the table below compares them)
                print(f"  {pipe}: " + ", ".join(
                    f"{st.id} {st.n_passed}" + (f"R{st.runaway_failures}" if st.runaway_failures else "")
                    for st in results[name].stats if st.pipeline == pipe), flush=True)
    for pipe in pipelines:
        print(f"\n{pipe} pipeline: passed / {args.seeds} seeds (R: seeds failed by a runaway check)\n")
        print("| claim | " + " | ".join(configs) + " |")
        print("|---|" + "---|" * len(configs))
        stats = {name: {st.id: st for st in res.stats if st.pipeline == pipe} for name, res in results.items()}
        ids = list(stats["all"])
        for cid in ids:
            cells = []
            for name in configs:
                st = stats[name][cid]
                cells.append(f"{st.n_passed}" + (f" R{st.runaway_failures}" if st.runaway_failures else ""))
            mark = "" if len({c for c in cells}) == 1 else " (changes)"
            extra = " (extra)" if stats["all"][cid].extra else ""
            print(f"| {cid}{extra}{mark} | " + " | ".join(cells) + " |")
        for name in configs:
            paper_claims = [st for st in stats[name].values() if not st.extra]
            runaway = sum(st.runaway_failures for st in stats[name].values())
            print(f"{name}: {sum(st.holds for st in paper_claims)} of {len(paper_claims)} paper claims hold; "
                  f"runaway failures over all claims and seeds: {runaway}")


if __name__ == "__main__":
    main()
