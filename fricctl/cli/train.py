"""``fricctl train PATTERNS.csv --out NET.json``: train the friction network.

PATTERNS.csv has a header naming exactly the columns ``tm,omega,friction``
(any order): motor torque [N*m], velocity [rad/s] and friction torque [N*m],
load side, one pattern per row.  The trained net is written as JSON
(:func:`fricctl.nn.save_net`) and its fit on the training patterns printed.
``--json`` prints one JSON object instead: ``out, trainer, hidden, seed,
n_patterns, fit{fit_percent, r_squared, rmse, max_abs_error, n, outside_envelope},
train_mse, gain_at_rest, envelope{tm[lo, hi], omega[lo, hi]}, c_source``.
"""

from __future__ import annotations

import argparse
import json
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
    p.add_argument("--trainer", choices=("casadi", "backprop"), default="casadi",
                   help="casadi: Levenberg-Marquardt (default); backprop: the paper's "
                        "back-propagation with momentum")
    p.add_argument("--hidden", type=int, default=4, help="hidden units (paper: 4)")
    p.add_argument("--seed", type=int, default=0, help="seed of the initial weights")
    p.add_argument("--recipe", choices=("paper", "converging"), default="paper",
                   help="backprop: default options; paper: constant rate as in the paper "
                        "(epochs 1000, learning rate 0.01, one start); converging: the options "
                        "measured to reach the Levenberg-Marquardt loss on the paper's patterns "
                        "(fricctl.nn.train.backprop.CONVERGING); the flags below override either")
    p.add_argument("--epochs", type=int, default=None, help="backprop: epochs per start")
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
                        "with --recipe converging)")
    p.add_argument("--c-source", type=Path, default=None, metavar="NET.c",
                   help="also write a self-contained C function of the net")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


def run(args) -> int:
    from .. import nn
    from ..nn.train.backprop import CONVERGING

    pats = read_patterns(args.patterns)
    tm, omega, friction = pats["tm"], pats["omega"], pats["friction"]
    if args.seed < 0:
        raise ValueError(f"--seed must be >= 0, got {args.seed}")
    rng = np.random.default_rng(args.seed)
    extra = {"seed": args.seed, "patterns_file": args.patterns.name}
    if args.trainer == "casadi":
        given = [f"--{k.replace('_', '-')}" for k in BACKPROP_FLAGS
                 if k != "restarts" and getattr(args, k) is not None]
        if given or args.recipe != "paper":
            raise ValueError(f"{', '.join(given) or '--recipe'} applies to --trainer backprop only")
    recipe = dict(PAPER_RECIPE if args.recipe == "paper" else CONVERGING)
    backprop = {k: recipe[k] if getattr(args, k) is None else getattr(args, k)
                for k in BACKPROP_FLAGS}
    options = {"casadi": dict(restarts=3 if args.restarts is None else args.restarts),
               "backprop": backprop}
    res = nn.TRAINERS[args.trainer].train(tm, omega, friction, hidden=args.hidden, rng=rng,
                                          metadata=extra, **options[args.trainer])
    net, hist = res.net, res.history
    nn.save_net(net, args.out)
    if args.c_source is not None:
        args.c_source.write_text(nn.c_source(net), encoding="utf-8")
    rep = nn.fit_report(friction, net=net, tm=tm, omega=omega)
    if args.json:
        out = {"out": str(args.out), "trainer": args.trainer, "hidden": net.hidden,
               "seed": args.seed, "n_patterns": int(tm.size), "fit": rep.as_dict(),
               "train_mse": float(hist.loss[-1]), "gain_at_rest": net.gain_at_rest(),
               "envelope": {"tm": [float(net.envelope_low[0]), float(net.envelope_high[0])],
                            "omega": [float(net.envelope_low[1]), float(net.envelope_high[1])]},
               "c_source": None if args.c_source is None else str(args.c_source)}
        print(json.dumps(out, indent=2, allow_nan=False))
    else:
        print(f"trained a 2-{net.hidden}-1 net with {args.trainer} (seed {args.seed}) "
              f"in {hist.elapsed[-1]:.3g} s -> {args.out}")
        print(rep.report())
        print(f"gain at rest dTat/dTm  {net.gain_at_rest():.4f}")
    return 0
