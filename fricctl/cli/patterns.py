"""``fricctl patterns RUN [RUN ...] --model MODEL.json --out PATTERNS.csv``: friction patterns.

The paper's recipe on measured records: velocity and acceleration from the
encoder with ``--estimator`` (default: the paper's polynomial segments, with the
fricctl pipeline's 50-sample windows, which do not fit across a torque step),
``Tat = Tm - I*alpha_hat`` with the model's inertia I, and an ``at_rest`` column
(1 where the encoder stood still for ``--guard`` samples each side: there the
friction is the reaction ``Tat = Tm``; a zero velocity next to motion is a
breakaway and is 0).  RUN is a CSV record or an EMPS-layout ``.mat`` file, in the
model's units.

PATTERNS.csv (:func:`fricctl.datasets.write_patterns`) has the header
``tm,omega,friction,at_rest`` and ``#`` lines ``units``, ``columns``,
``velocity_quantum`` (one encoder count per sample, ``encoder_resolution /
sample_time`` of the model; what the fricctl pipeline scales the velocity by),
``source``, ``estimator``, ``inertia``; ``fricctl train`` reads it.  An existing
file is kept unless ``--force``; an input is never overwritten.

``--net NET.json`` also judges a trained network on these patterns (held-out
records: patterns it was not trained on) and prints its fit.  ``--json`` prints
one object: ``out, units, n_patterns, n_at_rest, velocity_quantum, estimator,
inertia, records[{source, n_samples, sample_time}], friction_rms``, and with
``--net`` ``net{fit_percent, r_squared, rmse, max_abs_error, n, outside_envelope,
viscous_removed}``.  The net is judged as ``fricctl train`` judges it: by the full friction
estimate, ``net + b*omega`` for a ``--pipeline fricctl`` net (whose target left out the viscous
term ``b*omega``, ``viscous_removed`` in its file; 0 for any other net).
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path

import numpy as np

#: Estimator options of ``--estimator polynomial_segments``: the fricctl pipeline's.
POLYNOMIAL_OPTIONS = {"window": 50, "overlap": 25}


def register(subparsers) -> None:
    from ..estimation import ESTIMATORS

    p = subparsers.add_parser(
        "patterns", help="friction patterns Tat = Tm - I*alpha_hat from records, for training",
        description=__doc__.split("\n\n", 1)[1],
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("runs", nargs="+", metavar="RUN",
                   help="records (CSV t,torque,position[,reference] or EMPS-layout .mat)")
    p.add_argument("--model", required=True, metavar="MODEL.json",
                   help="model file (fricctl.joint_model): its inertia, units, sample time "
                        "and encoder resolution")
    p.add_argument("--out", type=Path, required=True, metavar="PATTERNS.csv",
                   help="where to write the patterns")
    p.add_argument("--estimator", choices=tuple(ESTIMATORS), default="polynomial_segments",
                   help="velocity/acceleration estimator (default polynomial_segments, "
                        "50-sample windows)")
    p.add_argument("--border", type=int, default=5, metavar="N",
                   help="samples dropped at each end of each record (default 5)")
    p.add_argument("--guard", type=int, default=2, metavar="N",
                   help="samples each side without encoder motion for a pattern at rest "
                        "(default 2)")
    p.add_argument("--net", type=Path, default=None, metavar="NET.json",
                   help="also print the fit of this network on the patterns (held-out check)")
    p.add_argument("--force", action="store_true", help="overwrite an existing --out file")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


def _refuse_repeated_records(runs) -> None:
    """Refuse a record given twice (the same file by its resolved path, or a hard link to it):
    its patterns were silently counted twice, weighing it double in the training."""
    from ._output import _file_id

    seen: dict = {}
    for r in runs:
        keys = [k for k in (Path(r).resolve(), _file_id(r)) if k is not None]
        for key in keys:
            if key in seen:
                same = "" if Path(r).resolve() == Path(seen[key]).resolve() else " (a hard link)"
                raise ValueError(f"RUN: {r} and {seen[key]} are the same record{same}; give "
                                 f"each record once (its patterns would count twice)")
        seen.update(dict.fromkeys(keys, r))


def run(args) -> int:
    from ..datasets import load_record, record_patterns, write_patterns
    from ..plant import JointModel
    from ..units import units as units_of
    from ._output import about, check_outputs, json_text

    check_outputs({"--out": args.out}, [*args.runs, args.model, args.net], force=args.force)
    _refuse_repeated_records(args.runs)
    with about(args.model):
        model = JointModel.load(args.model)
    records = []
    for r in args.runs:
        with about(r):
            records.append(load_record(r))
    from ..diagnose.api import check_model_agrees

    for path, rec in zip(args.runs, records):
        if rec.units != model.units:
            raise ValueError(f"{Path(path).name}: a {rec.units} record for a {model.units} model "
                             f"({Path(args.model).name})")
        # the velocity quantum is the model's encoder step over its sample time: both must be
        # the record's, as diagnose requires (issue 26: 0.031 or 0.5 rad/s for a true 0.0157)
        with about(path):
            check_model_agrees(model, rec, Path(args.model).name)
    options = POLYNOMIAL_OPTIONS if args.estimator == "polynomial_segments" else {}
    with about(*args.runs):
        pats = record_patterns(records, inertia=model.inertia, estimator=args.estimator,
                               estimator_options=options, border=args.border, guard=args.guard,
                               velocity_quantum=model.velocity_quantum)
    described = ", ".join(f"{k}={x}" for k, x in options.items())
    estimator = args.estimator + (f" ({described})" if described else "")
    pats = replace(pats, meta={"source": "; ".join(r.source for r in records),
                               "estimator": estimator,
                               "inertia": f"{model.inertia!r} (from {Path(args.model).name})"})
    net_fit = None
    if args.net is not None:
        from ..nn import fit_report, load_net
        from ..nn.pipelines import friction_estimate, viscous_removed_of

        net = load_net(args.net)
        if net.units != model.units:
            raise ValueError(f"{args.net.name}: a network trained on a {net.units} axis, the "
                             f"model ({Path(args.model).name}) is {model.units}")
        # judged as train judges it: the full friction estimate, net + b_hat*omega for a
        # fricctl-pipeline net (its target left the viscous term out; the net alone is not a
        # friction estimate)
        viscous = viscous_removed_of(net)
        net_fit = replace(fit_report(pats.friction, friction_estimate(net, pats.tm, pats.omega)),
                          outside_envelope=int(np.count_nonzero(
                              net.outside_envelope(pats.tm, pats.omega))))
    write_patterns(args.out, pats, overwrite=args.force)
    u = units_of(model.units)
    n_rest = int(np.count_nonzero(pats.at_rest))
    summary = {"out": str(args.out), "units": model.units, "n_patterns": len(pats),
               "n_at_rest": n_rest, "velocity_quantum": pats.velocity_quantum,
               "estimator": pats.meta["estimator"], "inertia": model.inertia,
               "records": [{"source": r.source, "n_samples": r.n_samples,
                            "sample_time": r.sample_time} for r in records],
               "friction_rms": float(np.sqrt(np.mean(pats.friction ** 2)))}
    if net_fit is not None:
        summary["net"] = {**net_fit.as_dict(), "viscous_removed": viscous}
    if args.json:
        print(json_text(summary))
        return 0
    q = "unknown" if pats.velocity_quantum is None else f"{pats.velocity_quantum:.4g} {u.velocity}"
    print(f"{len(pats)} patterns from {len(records)} record(s) -> {args.out} "
          f"(estimator {summary['estimator']}, I = {model.inertia:.6g} {u.inertia})")
    print(f"at rest: {n_rest} patterns; velocity quantum {q}; "
          f"friction RMS {summary['friction_rms']:.4g} {u.torque}")
    if n_rest == 0:
        print("no pattern at rest: these records say nothing about the friction below "
              "breakaway (the fricctl pipeline needs some)")
    if net_fit is not None:
        estimate = f" (net + b*omega, b = {viscous:.5g} {u.viscous})" if viscous else ""
        print(f"{args.net.name}{estimate} on these patterns: fit {net_fit.fit_percent:.2f} %, "
              f"R^2 {net_fit.r_squared:.5f}, RMSE {net_fit.rmse:.4g} {u.torque}, "
              f"max |error| {net_fit.max_abs_error:.4g} {u.torque}, "
              f"{net_fit.outside_envelope} outside the training envelope")
    return 0
