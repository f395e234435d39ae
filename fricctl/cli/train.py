"""``fricctl train PATTERNS.csv --out NET.json``: train the friction network.

PATTERNS.csv has a header naming the columns ``tm,omega,friction`` (any order,
optionally ``at_rest``): motor torque [N*m or N], velocity [rad/s or m/s] and friction
[N*m or N], load side, one pattern per row (``fricctl patterns`` writes such files
from records, with ``# units:`` and ``# velocity_quantum:`` lines).  Two ways to train:

* ``--trainer casadi|backprop``: a trainer on all the patterns (the full friction);
* ``--pipeline paper|fricctl``: a recipe of :mod:`fricctl.nn.pipelines`; ``fricctl``
  trains the nonlinear part ``Tat - b_hat*omega`` with the gain at rest certified inside
  ``--gain-band LO,HI`` (needs the ``at_rest`` column and ``# velocity_quantum:``).

The trained net is written as JSON (:func:`fricctl.nn.save_net`) and its fit printed
(for the fricctl pipeline, of the full estimate ``net + b_hat*omega``).  ``--json``
prints one JSON object instead: ``out, trainer, pipeline, units, hidden, seed,
n_patterns, fit{...}, train_mse, gain_at_rest, viscous_removed, certificate,
envelope{tm[lo, hi], omega[lo, hi]}, c_source``.  Outputs never overwrite an input or
an existing file without ``--force``; every output is checked (its folder exists and is
writable) before training starts.

Limits (refused above them, with the setting that would finish; docs/limits.md):
at most 32 hidden units and 100 restarts; back-prop at most 100 000 epochs per
start and restarts*epochs*patterns*hidden <= 2e10 (~10-20 min on one core);
Levenberg-Marquardt (casadi) restarts*200*patterns*(4*hidden+1)^2 <= 1e12.  Its
iterations stop by themselves: ``--epochs`` is refused with it.  A progress bar is
shown on stderr when stderr is a terminal (``--progress on|off`` to choose).
"""

from __future__ import annotations

import argparse
import contextlib
import sys
from pathlib import Path

import numpy as np

from ..datasets import PATTERN_COLUMNS, read_patterns

#: ``--recipe paper``: the back-prop options this command has always used.
PAPER_RECIPE = dict(epochs=1000, learning_rate=0.01, momentum=0.9, batch_size=1,
                    schedule="constant", restarts=1, velocity_scale=None)
BACKPROP_FLAGS = ("epochs", "learning_rate", "momentum", "batch_size", "schedule", "restarts",
                  "velocity_scale")


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "train",
        help="train the 2-H-1 friction network on (tm, omega, friction) patterns",
        description=__doc__.split("\n\n", 1)[1],
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("patterns", type=Path, metavar="PATTERNS.csv",
                   help=f"CSV with header {','.join(PATTERN_COLUMNS)} [N*m, rad/s, N*m]")
    p.add_argument("--out", type=Path, required=True, metavar="NET.json",
                   help="where to write the trained network")
    p.add_argument("--trainer", choices=("casadi", "backprop"), default=None,
                   help="casadi: Levenberg-Marquardt (default); backprop: the paper's "
                        "back-propagation with momentum")
    p.add_argument("--pipeline", choices=("paper", "fricctl"), default=None,
                   help="train with a recipe of fricctl.nn.pipelines instead of a bare trainer: "
                        "paper (full friction, least squares) or fricctl (nonlinear part, gain "
                        "at rest certified inside --gain-band)")
    p.add_argument("--gain-band", default=None, metavar="LO,HI",
                   help="fricctl pipeline: band of dTat/dTm at rest, 0 < LO <= HI < 1 "
                        "(default 0.98,0.99)")
    p.add_argument("--max-patterns", type=int, default=None, metavar="N",
                   help="pipelines: patterns drawn at random for training (default: the "
                        "pipeline's, 4000 paper / 2000 fricctl)")
    p.add_argument("--hidden", type=int, default=4, help="hidden units (paper: 4; at most 32)")
    p.add_argument("--seed", type=int, default=0, help="seed of the initial weights")
    p.add_argument("--recipe", choices=("paper", "converging"), default="paper",
                   help="backprop: default options; paper: constant rate as in the paper "
                        "(epochs 1000, learning rate 0.01, one start); converging: the options "
                        "measured to reach the Levenberg-Marquardt loss on the paper's patterns "
                        "(fricctl.nn.train.backprop.CONVERGING); the flags below override either")
    p.add_argument("--epochs", type=int, default=None, help="backprop: epochs per start (at most 100 000, and restarts*epochs*patterns*"
                        "hidden <= 2e10)")
    p.add_argument("--learning-rate", type=float, default=None,
                   help="backprop: step size (the first epoch's, for a schedule)")
    p.add_argument("--momentum", type=float, default=None, help="backprop: momentum [0, 1)")
    p.add_argument("--batch-size", type=int, default=None,
                   help="backprop: patterns per update (1 = per pattern, as in the paper)")
    p.add_argument("--schedule", default=None, metavar="{constant,cosine}",
                   help="backprop: learning rate per epoch (constant = the paper's; cosine = "
                        "annealed to zero over each start)")
    p.add_argument("--velocity-scale", type=float, default=None, metavar="RAD_PER_S",
                   help="backprop: the descent sees omega / this [rad/s] (default: the range "
                        "scaling of every trainer)")
    p.add_argument("--restarts", type=int, default=None,
                   help="starting points, the best kept (casadi: default 3; backprop: 1, or 5 "
                        "with --recipe converging); at most 100")
    p.add_argument("--c-source", type=Path, default=None, metavar="NET.c",
                   help="also write a self-contained C compensator of the net and its header "
                        "(NET.h beside it)")
    p.add_argument("--force", action="store_true", help="overwrite existing output files")
    p.add_argument("--progress", choices=("auto", "on", "off"), default="auto",
                   help="progress bar of the training on stderr (trainers; auto: when stderr is "
                        "a terminal)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


@contextlib.contextmanager
def progress_bar(mode: str, unit: str, stream=None):
    """A ``progress(done, total)`` callable drawing a tqdm bar on ``stream`` (stderr), or None.

    ``mode``: ``"on"``, ``"off"``, or ``"auto"`` (on when the stream is a terminal: a
    bar in a log file or a pipe is noise).
    """
    stream = sys.stderr if stream is None else stream
    isatty = getattr(stream, "isatty", None)
    if mode == "off" or (mode == "auto" and not (callable(isatty) and isatty())):
        yield None
        return
    from tqdm import tqdm

    bars = []  # drawn at the first report, when the total is known

    def report(done: int, total: int) -> None:
        if not bars:
            bars.append(tqdm(total=total, unit=unit, file=stream, leave=False, dynamic_ncols=True))
        bar = bars[0]
        if bar.total != total:
            bar.total = total
        bar.update(done - bar.n)

    try:
        yield report
    finally:
        for bar in bars:
            bar.close()


def _gain_band(text):
    parts = str(text).split(",")
    try:
        band = tuple(float(x) for x in parts)
    except ValueError:
        band = ()
    if len(band) != 2:
        raise ValueError(f"--gain-band must be LO,HI (two numbers), got {text!r}")
    return band


def _train_pipeline(args, pats, rng, extra):
    from ..nn import TRAINERS
    from ..nn.pipelines import DEFAULT_GAIN_BAND, pipeline

    p = pats.patterns
    options = {}
    if args.max_patterns is not None:
        options["max_patterns"] = args.max_patterns
    if args.pipeline == "fricctl":
        if p.velocity_quantum is None:
            raise ValueError(f"{args.patterns}: no '# velocity_quantum:' line; write the patterns "
                             "with fricctl patterns --model (a model with sample_time and "
                             "encoder_resolution)")
        if not pats.has_at_rest:
            raise ValueError(f"{args.patterns}: no at_rest column; write the patterns with "
                             "fricctl patterns, which marks the samples at rest")
        options["gain_band"] = DEFAULT_GAIN_BAND if args.gain_band is None else _gain_band(args.gain_band)
    elif args.gain_band is not None:
        raise ValueError("--gain-band applies to --pipeline fricctl only")
    trainer = {"paper": "casadi", "fricctl": "certified"}[args.pipeline]
    with progress_bar(args.progress, TRAINERS[trainer].step) as progress:
        return pipeline(args.pipeline).train(p, rng=rng, hidden=args.hidden, progress=progress,
                                             metadata={**extra, "units": p.units}, **options)


def run(args) -> int:
    from .. import nn
    from ..nn.c_export import c_header
    from ..nn.train.backprop import CONVERGING
    from ._output import check_outputs, json_text

    header = None if args.c_source is None else args.c_source.with_suffix(".h")
    check_outputs({"--out": args.out, "--c-source": args.c_source, "--c-source header": header},
                  [args.patterns], force=args.force)
    pats = read_patterns(args.patterns)
    units = pats.patterns.units
    tm, omega, friction = pats["tm"], pats["omega"], pats["friction"]
    if args.seed < 0:
        raise ValueError(f"--seed must be >= 0, got {args.seed}")
    rng = np.random.default_rng(args.seed)
    extra = {"seed": args.seed, "patterns_file": args.patterns.name}
    given = [f"--{k.replace('_', '-')}" for k in BACKPROP_FLAGS if getattr(args, k) is not None]
    if args.pipeline is not None:
        if args.trainer is not None or given or args.recipe != "paper":
            raise ValueError(f"{args.trainer and '--trainer' or ', '.join(given) or '--recipe'} "
                             "does not go with --pipeline (a pipeline chooses its trainer)")
        trained = _train_pipeline(args, pats, rng, extra)
        net, hist, trainer = trained.net, trained.history, trained.net.metadata["trainer"]
        estimate = trained.estimate(tm, omega)
        viscous, cert = trained.viscous_removed, trained.certificate
    else:
        if args.gain_band is not None or args.max_patterns is not None:
            raise ValueError("--gain-band and --max-patterns go with --pipeline")
        trainer = args.trainer or "casadi"
        if trainer == "casadi":
            given = [g for g in given if g != "--restarts"]
            if given or args.recipe != "paper":
                raise ValueError(f"{', '.join(given) or '--recipe'} applies to --trainer backprop only")
        recipe = dict(PAPER_RECIPE if args.recipe == "paper" else CONVERGING)
        backprop = {k: recipe[k] if getattr(args, k) is None else getattr(args, k)
                    for k in BACKPROP_FLAGS}
        options = {"casadi": dict(restarts=3 if args.restarts is None else args.restarts),
                   "backprop": backprop}
        with progress_bar(args.progress, nn.TRAINERS[trainer].step) as progress:
            res = nn.TRAINERS[trainer].train(tm, omega, friction, hidden=args.hidden, rng=rng,
                                             metadata={**extra, "units": units}, progress=progress,
                                             **options[trainer])
        net, hist = res.net, res.history
        estimate, viscous, cert = net(tm, omega), 0.0, None
    nn.save_net(net, args.out)
    if args.c_source is not None:
        # the functions keep one name (fricctl_friction_net...) whatever the file is called, so
        # a controller's code does not change when a new net is exported
        args.c_source.write_text(nn.c_source(net, units=units), encoding="utf-8")
        header.write_text(c_header(net, units=units), encoding="utf-8")
    rep = nn.fit_report(friction, estimate)
    if args.json:
        out = {"out": str(args.out), "trainer": trainer, "pipeline": args.pipeline, "units": units,
               "hidden": net.hidden, "seed": args.seed, "n_patterns": int(tm.size),
               "fit": rep.as_dict(), "train_mse": float(hist.loss[-1]),
               "gain_at_rest": net.gain_at_rest(), "viscous_removed": viscous,
               "certificate": None if cert is None else cert.as_dict(),
               "envelope": {"tm": [float(net.envelope_low[0]), float(net.envelope_high[0])],
                            "omega": [float(net.envelope_low[1]), float(net.envelope_high[1])]},
               "c_source": None if args.c_source is None else str(args.c_source)}
        print(json_text(out))
    else:
        how = f"the {args.pipeline} pipeline ({trainer})" if args.pipeline else trainer
        print(f"trained a 2-{net.hidden}-1 net with {how} (seed {args.seed}) "
              f"in {hist.elapsed[-1]:.3g} s -> {args.out}")
        print(rep.report(units))
        print(f"gain at rest dTat/dTm  {net.gain_at_rest():.4f}")
        if viscous:
            from ..units import units as units_of

            print(f"the net estimates Tat - b*omega, b = {viscous:.5g} {units_of(units).viscous} "
                  "(the compensation leaves the viscous damping in the loop)")
        if cert is not None:
            print(f"certified: dTat/dTm at rest in [{cert.gain_min:.4f}, {cert.gain_max:.4f}] "
                  f"(band {cert.gain_band[0]}..{cert.gain_band[1]}), |dTat/dTm| <= "
                  f"{cert.sliding_slope_max:.3f} while sliding")
    return 0
