"""``fricctl train PATTERNS.csv --out NET.json``: train the friction network.

PATTERNS.csv has a header naming the columns ``tm,omega,friction`` (any order,
optionally ``at_rest``): motor torque [N*m or N], velocity [rad/s or m/s] and friction
[N*m or N], load side, one pattern per row (``fricctl patterns`` writes such files
from records, with ``# units:`` and ``# velocity_quantum:`` lines).  Two ways to train:

* ``--trainer NAME``: a trainer of fricctl.nn.TRAINERS on all the patterns (the full
  friction), with the options it declares (``--recipe`` and the flags after it);
* ``--pipeline NAME``: a recipe of :mod:`fricctl.nn.pipelines`; ``fricctl``
  trains the nonlinear part ``Tat - b_hat*omega`` with the gain at rest certified inside
  ``--gain-band LO,HI`` (needs the ``at_rest`` column and ``# velocity_quantum:``).

The trained net is written as JSON (:func:`fricctl.nn.save_net`) and its fit printed
(for the fricctl pipeline, of the full estimate ``net + b_hat*omega``).  ``--json``
prints one JSON object instead: ``out, trainer, pipeline, units, hidden, seed,
n_patterns, fit{...}, train_mse, gain_at_rest, viscous_removed, certificate,
envelope{tm[lo, hi], omega[lo, hi]}, c_source, warnings`` (each warning also on stderr:
a gain at rest >= 1).  Outputs never overwrite an input or
an existing file without ``--force``; every output is checked (its folder exists and is
writable) before training starts.  A progress bar is shown on stderr when stderr is a
terminal (``--progress on|off`` to choose).
"""

# The trainers, their options, recipes and limits, and the pipelines are read from their
# registries (fricctl.nn.TRAINERS, fricctl.nn.pipelines.PIPELINES): a new trainer module
# appears here with its flags without an edit of this file.

from __future__ import annotations

import argparse
import contextlib
import inspect
import sys
import textwrap
import warnings
from pathlib import Path

import numpy as np

from ..datasets import PATTERN_COLUMNS, read_patterns

#: The trainer each pipeline runs, for the unit of its progress bar (a Pipeline entry does not
#: say; another pipeline's bar counts "step"s).
_PIPELINE_TRAINER = {"paper": "casadi", "fricctl": "certified"}


def _bare_trainers() -> dict:
    """The trainers ``--trainer`` offers: those whose entry requires nothing beyond bare patterns."""
    from ..nn import TRAINERS

    return {name: t for name, t in TRAINERS.items() if t.requires is None}


def _flags(trainers: dict) -> dict:
    """Loop option -> [(trainer, TrainerOption)] over the trainers that declare it, in their order."""
    found: dict = {}
    for t in trainers.values():
        for opt in t.flags:
            found.setdefault(opt.name, []).append((t, opt))
    for name, owners in found.items():
        if len({opt.type for _, opt in owners}) > 1:
            raise ValueError(f"trainers {', '.join(t.name for t, _ in owners)} declare "
                             f"{owners[0][1].flag} with different types")
    return found


def _show(value) -> str:
    if value is None:
        return "none"
    if isinstance(value, int):
        return f"{value:,}".replace(",", " ")
    return f"{value:g}" if isinstance(value, float) else str(value)


def _flag_help(owners: list) -> str:
    """``trainer: help (default X; Y with --recipe R; at most N)`` for each trainer declaring it."""
    parts = []
    for t, opt in owners:
        first = t.defaults()[opt.name]
        others = [(r.name, t.defaults(r.name)[opt.name]) for r in t.recipes[1:]]
        text = f"default {_show(first)}" + "".join(
            f"; {_show(value)} with --recipe {name}" for name, value in others if value != first)
        if opt.high is not None:
            text += f"; at most {_show(opt.high)}"
        parts.append(f"{t.name}: {opt.help} ({text})")
    return "; ".join(parts)


def _description(trainers: dict) -> str:
    from ..nn.train.core import MAX_HIDDEN, MAX_RESTARTS

    limits = "".join(f"; {name}: {t.limits}" for name, t in trainers.items() if t.limits)
    text = (f"Limits (refused above them, with the setting that would finish; docs/limits.md): at "
            f"most {MAX_HIDDEN} hidden units and {MAX_RESTARTS} restarts{limits}.")
    return __doc__.split("\n\n", 1)[1].rstrip() + "\n\n" + textwrap.fill(text, width=88) + "\n"


def _escape(text: str) -> str:
    return text.replace("%", "%%")  # argparse %-formats every help string


def register(subparsers) -> None:
    from ..nn import TRAINERS
    from ..nn.pipelines import PIPELINES
    from ..nn.train import DEFAULT_TRAINER
    from ..nn.train.core import MAX_HIDDEN

    trainers = _bare_trainers()
    p = subparsers.add_parser(
        "train",
        help="train the 2-H-1 friction network on (tm, omega, friction) patterns",
        description=_description(trainers),
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("patterns", type=Path, metavar="PATTERNS.csv",
                   help=f"CSV with header {','.join(PATTERN_COLUMNS)} [N*m, rad/s, N*m]")
    p.add_argument("--out", type=Path, required=True, metavar="NET.json",
                   help="where to write the trained network")
    elsewhere = [f"{name} (only in a pipeline: it needs {t.requires})"
                 for name, t in TRAINERS.items() if name not in trainers]
    p.add_argument("--trainer", choices=tuple(trainers), default=None, help=_escape(
        f"a trainer of fricctl.nn.TRAINERS (default {DEFAULT_TRAINER}): "
        + "; ".join([f"{name}: {t.description}" for name, t in trainers.items()] + elsewhere)))
    p.add_argument("--pipeline", choices=tuple(PIPELINES), default=None, help=_escape(
        "train with a recipe of fricctl.nn.pipelines instead of a bare trainer: "
        + "; ".join(f"{name}: {pl.description}" for name, pl in PIPELINES.items())))
    p.add_argument("--gain-band", default=None, metavar="LO,HI",
                   help="fricctl pipeline: band of dTat/dTm at rest, 0 < LO <= HI < 1 "
                        "(default 0.98,0.99)")
    sizes = ", ".join(f"{inspect.signature(pl.train).parameters['max_patterns'].default} {name}"
                      for name, pl in PIPELINES.items())
    p.add_argument("--max-patterns", type=int, default=None, metavar="N",
                   help=f"pipelines: patterns drawn at random for training (default: the "
                        f"pipeline's, {sizes})")
    p.add_argument("--hidden", type=int, default=4,
                   help=f"hidden units (paper: 4; at most {MAX_HIDDEN})")
    p.add_argument("--seed", type=int, default=0, help="seed of the initial weights")
    recipes = [(name, r) for name, t in trainers.items() for r in t.recipes]
    if recipes:
        p.add_argument("--recipe", choices=tuple(dict.fromkeys(r.name for _, r in recipes)),
                       default=None, help=_escape("a named set of the trainer's options: " + "; ".join(
                           f"{name} {r.name}{' (default)' if r is trainers[name].recipes[0] else ''}: "
                           f"{r.description}" for name, r in recipes)
                           + "; the flags below override it"))
    for name, owners in _flags(trainers).items():
        opt = owners[0][1]
        metavar = next((o.metavar for _, o in owners if o.metavar), None)
        p.add_argument(opt.flag, type=opt.type, default=None, metavar=metavar,
                       help=_escape(_flag_help(owners)))
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
    trainer = _PIPELINE_TRAINER.get(args.pipeline)
    with progress_bar(args.progress, TRAINERS[trainer].step if trainer else "step") as progress:
        return pipeline(args.pipeline).train(p, rng=rng, hidden=args.hidden, progress=progress,
                                             metadata={**extra, "units": p.units}, **options)


def _recipe_chosen(args, trainers: dict) -> bool:
    """``--recipe`` names a choice: a recipe that is no trainer's default (its first)."""
    recipe = getattr(args, "recipe", None)  # no --recipe when no trainer declares a recipe
    return recipe is not None and recipe not in {t.recipes[0].name for t in trainers.values()
                                                 if t.recipes}


def _trainer_options(args, trainers: dict, given: list) -> dict:
    """The options of the trainer ``--trainer`` names: its recipe's, then the flags ``given``."""
    t = trainers[args.trainer]
    foreign = [name for name in given if name not in {o.name for o in t.flags}]
    if foreign:
        owners = [n for n, other in trainers.items() if any(o.name in foreign for o in other.flags)]
        raise ValueError(f"{', '.join(_flags(trainers)[n][0][1].flag for n in foreign)} applies to "
                         f"--trainer {', '.join(owners)} only")
    recipe = getattr(args, "recipe", None)
    if not t.recipes:
        if _recipe_chosen(args, trainers):
            owners = [n for n, other in trainers.items() if other.recipes]
            raise ValueError(f"--recipe applies to --trainer {', '.join(owners)} only")
        recipe = None
    elif recipe is not None and recipe not in [r.name for r in t.recipes]:
        raise ValueError(f"--recipe {recipe} is not a recipe of --trainer {t.name} (its recipes: "
                         f"{', '.join(r.name for r in t.recipes)})")
    return {**t.defaults(recipe), **{name: getattr(args, name) for name in given}}


def run(args) -> int:
    from .. import nn
    from .._atomic import write_text
    from ..nn.c_export import c_header
    from ..nn.train import DEFAULT_TRAINER
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
    trainers = _bare_trainers()
    given = [name for name in _flags(trainers) if getattr(args, name) is not None]
    if args.pipeline is not None:
        if args.trainer is not None or given or _recipe_chosen(args, trainers):
            flags = ", ".join(_flags(trainers)[n][0][1].flag for n in given)
            raise ValueError(f"{args.trainer and '--trainer' or flags or '--recipe'} "
                             "does not go with --pipeline (a pipeline chooses its trainer)")
        trained = _train_pipeline(args, pats, rng, extra)
        net, hist, trainer = trained.net, trained.history, trained.net.metadata["trainer"]
        estimate = trained.estimate(tm, omega)
        viscous, cert = trained.viscous_removed, trained.certificate
    else:
        if args.gain_band is not None or args.max_patterns is not None:
            raise ValueError("--gain-band and --max-patterns go with --pipeline")
        args.trainer = trainer = args.trainer or DEFAULT_TRAINER
        options = _trainer_options(args, trainers, given)
        with progress_bar(args.progress, trainers[trainer].step) as progress:
            res = trainers[trainer].train(tm, omega, friction, hidden=args.hidden, rng=rng,
                                          metadata={**extra, "units": units}, progress=progress,
                                          **options)
        net, hist = res.net, res.history
        estimate, viscous, cert = net(tm, omega), 0.0, None
    nn.save_net(net, args.out, overwrite=args.force)  # atomic: complete or absent
    if args.c_source is not None:
        # the functions keep one name (fricctl_friction_net...) whatever the file is called, so
        # a controller's code does not change when a new net is exported
        write_text(args.c_source, nn.c_source(net, units=units), overwrite=args.force)
        write_text(header, c_header(net, units=units), overwrite=args.force)
    rep = nn.fit_report(friction, estimate)
    from ..nn.envelope import narrow_speed_warnings

    warns = _gain_warnings(net) + narrow_speed_warnings(net, pats.patterns.velocity_quantum)
    for text in warns:
        warnings.warn(text, stacklevel=1)
    if args.json:
        out = {"out": str(args.out), "trainer": trainer, "pipeline": args.pipeline, "units": units,
               "hidden": net.hidden, "seed": args.seed, "n_patterns": int(tm.size),
               "fit": rep.as_dict(), "train_mse": float(hist.loss[-1]),
               "gain_at_rest": net.gain_at_rest(), "viscous_removed": viscous,
               "certificate": None if cert is None else cert.as_dict(),
               "envelope": {"tm": [float(net.envelope_low[0]), float(net.envelope_high[0])],
                            "omega": [float(net.envelope_low[1]), float(net.envelope_high[1])]},
               "c_source": None if args.c_source is None else str(args.c_source),
               "warnings": warns}
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


def _gain_warnings(net) -> list[str]:
    """A gain at rest dTat/dTm >= 1 cannot hold the joint: say so (the fixed point of Eq. 3)."""
    g = net.gain_at_rest()
    if g < 1.0:
        return []
    return [f"gain at rest dTat/dTm = {g:.4g} >= 1: with s = 1 the compensated joint at rest has "
            "no fixed point Tm = Tc/(1 - s*g) and winds its torque up; train with --pipeline "
            "fricctl (certified g < 1) or compensate with s < 1/g"]
