"""``fricctl identify RUN``: fit a friction law to a measured record, write the model file.

RUN is a CSV record (header ``t,torque,position[,reference]``, see
:class:`fricctl.datasets.Run`) or a MATLAB file in the EMPS layout (``*.mat``,
see :func:`fricctl.datasets.emps_file`).  ``--recipe auto`` (default) is
:func:`fricctl.identify.identify_record`, the same fit as every diagnosis's baseline:
the equation error on the record's own signals (low-pass at the band the motion
reaches above the encoder's quantisation), refined by DIDIM on the record's torque
replayed (no derivative of the encoder, no model of the controller), which is reported,
with a warning when the two disagree beyond their standard errors; standard errors from
the residual summed over blocks and a delete-a-block jackknife (the larger); validated
on held-out blocks (each of four replayed with the estimate of the other three).  End stops
the record hits (:func:`fricctl.identify.stops.end_stops`) are left out: their contacts out of
the equation error, the replay run on the stretches between them, and a note says so.  Linear
models only (``--recipe plain --model stribeck`` for the Stribeck curve).

Other recipes: ``plain`` estimates velocity and acceleration with the chosen
estimator, drops the border samples and the samples at rest, and fits by
inverse-dynamics least squares (standard errors: the residual summed over blocks, with the
moves of two refits added in quadrature -- the Butterworth cut-off halved, the torque half a
sample earlier -- and a warning where those moves exceed the residual's std); ``idim_ls`` is
the EMPS benchmark's IDIM-LS (Butterworth + central differences, decimation by 10; its
published table to every decimal); ``idim_iv`` refines it with instruments from the
simulated model (Janot, Vandanjon & Gautier 2014) and ``didim`` minimises the simulation
error of the record (Gautier, Janot & Vandanjon 2013).  Both simulate a record with a moving
reference
in closed loop through its PD controller (``--controller KP KD``, else the gains
fitted to the record's torque) and any other record open loop (its torque
replayed); a record without reference column is simulated open loop with a
warning.  Every recipe warns of a held-out simulation fit, or a fit of its own (``Fit (%)``),
below 80 %.  Warnings go to stderr, one line each, and into the JSON.  Prints the estimates
with standard errors in the IDIM-LS layout, or with ``--json`` one object:
``model, units, n_samples, parameters{name: {value, std, unit}}, fit_percent,
relative_error_percent, residual_rms, condition_number, solver_status, method,
warnings, estimator, recipe, out`` (``auto`` adds ``equation_error``, ``didim``,
``cutoff_hz``, ``std_notes``, ``end_stops{positions, impacts, excluded_samples,
description, ...}`` and ``held_out{simulation_fit_percent, equation_fit_percent, failure}``).
Every recipe of a linear model is validated on held-out data (``auto`` on 4 blocks, the
others on halves: each half fitted alone and the other replayed with it; ``held_out`` in the
JSON, ``--no-validation`` skips it); ``--figure FILE.png`` plots it: the replayed position and
the equation error's torque against the record's.

``--out MODEL.json`` writes the identified model (:class:`fricctl.plant.JointModel`,
version 2) with each value's standard error in ``provenance``, the record's
sample time and encoder grid (null when the positions lie on none) and
``--max-torque`` (null = unknown); every warning is written into the provenance note of
the values it concerns ("flagged: ..."); ``design``, ``simulate`` and ``patterns`` read it.
An existing file is kept unless ``--force``.  Bad input prints one line on stderr
and exits with code 2.
"""

from __future__ import annotations

import argparse
from pathlib import Path

#: The recipes; those that simulate the record take the controller.
_RECIPES = ("auto", "plain", "idim_ls", "idim_iv", "didim")
_SIMULATING = ("idim_iv", "didim")


def register(subparsers) -> None:
    from ..estimation import ESTIMATORS
    from ..identify import MODELS
    from ..units import KINDS

    p = subparsers.add_parser(
        "identify", help="fit a friction law to a measured record (CSV or EMPS .mat), "
                         "write the model file",
        description=__doc__.split("\n\n", 1)[1],
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("run", metavar="RUN", help="record: CSV with header t,torque,position"
                                              "[,reference], or an EMPS-layout .mat file")
    p.add_argument("--model", choices=tuple(MODELS), default="coulomb_viscous",
                   help="friction law (default coulomb_viscous: inertia, viscous, Coulomb, offset)")
    p.add_argument("--recipe", choices=_RECIPES, default="auto",
                   help="auto (default): equation error on the record's signals refined by "
                        "DIDIM on the replayed torque, jackknife stds, held-out validation; "
                        "plain: estimator + least squares; idim_ls: the EMPS benchmark's IDIM-LS "
                        "(Butterworth 100 Hz, decimation by 10); idim_iv: IDIM-LS with "
                        "instruments from the simulated model; didim: the simulation error "
                        "minimised")
    p.add_argument("--offset", action=argparse.BooleanOptionalAction, default=None,
                   help="fit a constant torque offset (default: as the model says; "
                        "coulomb_viscous yes, asymmetric no)")
    p.add_argument("--no-validation", action="store_true",
                   help="skip the validation on held-out data (auto: and the jackknife; "
                        "other recipes: two fits of half the record)")
    p.add_argument("--figure", type=Path, default=None, metavar="FILE.png",
                   help="plot the held-out validation (replayed position, equation-error "
                        "torque)")
    p.add_argument("--controller", type=float, nargs=2, default=None, metavar=("KP", "KD"),
                   help="idim_iv/didim: the record's PD gains [N*m/rad, N*m*s/rad or N/m, "
                        "N*s/m] (default: fitted to the record's torque)")
    p.add_argument("--estimator", choices=tuple(ESTIMATORS), default=None,
                   help="plain recipe: velocity/acceleration estimator (default "
                        "butterworth_central, cut-off a fifth of the Nyquist frequency)")
    p.add_argument("--units", choices=KINDS, default=None,
                   help="override the record's '# units:' line")
    p.add_argument("--border", type=int, default=None, metavar="N",
                   help="plain recipe: samples dropped at each end (default 50)")
    p.add_argument("--max-torque", type=float, default=None, metavar="TMAX",
                   help="torque (force) limit of the drive [N*m or N] for the --out model file "
                        "(datasheet); default unknown (null)")
    p.add_argument("--out", type=Path, default=None, metavar="MODEL.json",
                   help="write the identified model (fricctl.joint_model, version 2)")
    p.add_argument("--force", action="store_true",
                   help="overwrite an existing --out or --figure file")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


def identified_model(result, record, *, recipe: str, max_torque: float | None = None):
    """The :class:`~fricctl.plant.JointModel` of an identification of ``record``.

    Every identified value carries its standard error; the sample time and the
    encoder grid come from the record (:meth:`fricctl.datasets.Run.encoder_grid`).
    """
    from ..plant.model import JointModel, Provenance

    grid = record.encoder_grid()
    where = f"{record.source}, {record.n_samples} samples at {record.sample_time:g} s"
    prov = {"sample_time": Provenance(source="measured", note=f"sample time of {where}"),
            "encoder_resolution": Provenance(
                source="measured", note="smallest position step of the record; every position "
                                        "lies on its grid" if grid else
                "the record's positions lie on no encoder grid: unknown")}
    if max_torque is not None:
        prov["max_torque"] = Provenance(source="datasheet", note="given as --max-torque")
    how = {"idim_ls": "IDIM-LS", "idim_iv": "IDIM-IV", "didim": "DIDIM"}.get(
        recipe, "inverse-dynamics least squares")
    if recipe == "auto":
        how = f"{result.method} (fricctl identify's default: the record's equation error and DIDIM)"
    std = ("sigma^2 (Z^T X)^-1 Z^T Z (X^T Z)^-1" if recipe == "idim_iv"
           else "the residual summed over blocks" if recipe in ("auto", "didim")
           else "the larger of sigma*sqrt(diag((J^T J)^-1)) and the residual summed over "
                "blocks, with the moves of two refits added in quadrature (the estimator's "
                "cut-off halved, the torque half a sample earlier)"
           if recipe == "plain" else "sigma*sqrt(diag((J^T J)^-1))")
    note = f"{how} ({result.model}) on {where}; std from {std}"
    m = JointModel.from_estimates(
        result.parameters, std=dict(zip(result.names, map(float, result.std))),
        units=record.units, source=f"fricctl identify: {result.model} on {record.source}",
        note=note, sample_time=record.sample_time, encoder_resolution=grid,
        max_torque=max_torque, provenance=prov)
    return _flagged(m, result)


def _model_file(result, record, args):
    """:func:`identified_model` for ``--out``; a fit whose parameters sit on their bounds (a
    torque column of the wrong sign gives inertia 0) is said to be non-physical, not a bad
    value of the user's ("inertia must be > 0 kg*m^2, got 0.0")."""
    import re

    from ..identify.models import parameter_unit

    try:
        return identified_model(result, record, recipe=args.recipe, max_torque=args.max_torque)
    except ValueError as exc:
        bound = [n for n, b in zip(result.names, result.at_bound) if b]
        if not bound:
            raise
        at = ", ".join(f"{n} {result.parameters[n]:.4g} {parameter_unit(n, result.units)}"
                       for n in bound)
        need = re.sub(r"^(\S+) must be (.*?)(, got .*)?$", r"\1 \2", str(exc))
        raise ValueError(f"the fit gave a non-physical model, so no model file can be written: "
                         f"{at} at {'its bound' if len(bound) == 1 else 'their bounds'} (a model "
                         f"needs {need}; does the torque column have the sign of the motion it "
                         f"drives?)") from None


def _fit_again(args, record, controller, estimator):
    """The recipe of ``args`` on another record (a half, for the held-out validation)."""
    from ..identify import didim, identify_run, idim_iv, idim_ls

    if args.recipe == "idim_ls":
        return idim_ls(record, model=args.model, offset=args.offset)
    if args.recipe in _SIMULATING:
        fit = idim_iv if args.recipe == "idim_iv" else didim
        return fit(record, model=args.model, offset=args.offset, controller=controller)
    return identify_run(record, model=args.model, estimator=estimator, offset=args.offset,
                        **_border(args))


def _border(args) -> dict:
    """``--border`` as identify_run's keyword, or nothing (its default)."""
    return {} if args.border is None else {"border": args.border}


def _poor_fit(result) -> list:
    """The recipe's own fit (its report's ``Fit (%)``) below the held-out check's
    :data:`~fricctl.identify.record.POOR_FIT_PERCENT`: the same threshold, as it is the same
    measure (the share of the fitted signal's variation the model explains, normalised RMSE)
    of the signal the recipe fits -- the torque for an equation error, the simulated output
    for DIDIM.  A record mostly at rest, whose holding torques no friction law explains, gives
    one with a biased estimate and standard errors that assume the model holds."""
    from ..identify.record import POOR_FIT_PERCENT

    if result.fit_percent >= POOR_FIT_PERCENT:
        return []
    what = ("its simulated output (simulation error)" if result.method == "DIDIM"
            else "the torque (equation error)")
    return [f"poor fit: {result.fit_percent:.3g} % of {what} (< {POOR_FIT_PERCENT:g} %): the "
            f"model explains little of this record (samples at rest, noise, or an effect it "
            f"lacks), and its standard errors assume it does"]


def _bias_checked(record, args, estimator, result):
    """The plain fit with the bias its residual cannot show in its standard errors.

    An estimator's filtering and the torque's timing bias the plain fit in ways its residual
    cannot show (on seeded records: the quantisation noise of a twice-differentiated encoder
    pulls the inertia 5 % down at 1 kHz and 10-90 % at 5 kHz, 9-50 of the residual's std; a
    torque held over each sample (ZOH) against the motion at its start pushes it 0.5 % up at
    1 kHz, 4-7 std).  Two refits change what the record cannot settle: the Butterworth cut-off
    halved (``butterworth_central``), and the torque taken half a sample earlier (the mean of
    two samples: a record does not say whether its torque was held over the next interval or
    measured at the instant).  Each refit's move is a component of the uncertainty, added in
    quadrature to the residual's std (a type-B component in the GUM's words); where a move
    exceeds :data:`~fricctl.identify.record.DISAGREEMENT_SIGMAS` of the residual's std, the
    estimator's bias dominates and a warning says so (the std then rest on these two checks
    alone, and are lower bounds of what another estimator would show)."""
    from dataclasses import replace

    import numpy as np

    from ..datasets import Run
    from ..identify import identify_run
    from ..identify.record import DISAGREEMENT_SIGMAS

    border = _border(args)
    cutoff = 0.1 / record.sample_time  # butterworth_central's default: a fifth of Nyquist
    late = record.torque.copy()
    late[1:] = 0.5 * (record.torque[1:] + record.torque[:-1])
    checks = [("the torque taken half a sample earlier",
               lambda: identify_run(Run(t=record.t, torque=late, position=record.position,
                                        units=record.units), model=args.model,
                                    estimator=estimator, offset=args.offset, **border))]
    if estimator == "butterworth_central":
        checks.insert(0, (f"the estimator's cut-off halved ({cutoff:.4g} -> {cutoff / 2:.4g} Hz)",
                          lambda: identify_run(record, model=args.model, offset=args.offset,
                                               estimator_options={"cutoff": cutoff / 2},
                                               **border)))
    var, moved = result.std ** 2, []
    for what, refit in checks:
        try:
            other = refit()
        except ValueError:  # the record cannot be fitted so: nothing to compare
            continue
        move = np.abs(other.estimates - result.estimates)
        var = var + move ** 2
        with np.errstate(divide="ignore", invalid="ignore"):
            gap = move / result.std
        big = [f"{n} {x:.4g} -> {y:.4g} ({g:.1f} std)" for n, x, y, g in
               zip(result.names, result.estimates, other.estimates, gap)
               if g > DISAGREEMENT_SIGMAS]
        if big:
            moved.append(f"{what}: {', '.join(big)}")
    warnings = result.warnings
    if moved:
        warnings += (f"the estimates move beyond {DISAGREEMENT_SIGMAS:g} of the residual's "
                     f"standard errors with " + "; with ".join(moved) + ": the estimator "
                     f"biases the fit by more than its noise; the standard errors include these "
                     f"moves and are lower bounds of the bias another estimator would show (the "
                     f"default recipe refines by the simulation error, with no derivative of "
                     f"the encoder)",)
    return replace(result, std=np.sqrt(var), warnings=warnings)


def _flagged(model, result):
    """The model with each warning in the provenance note of the values it concerns: a
    warning that starts with a parameter's name concerns that parameter, any other all."""
    from dataclasses import replace

    from ..plant.model import ESTIMATE_FIELDS

    if not result.warnings:
        return model
    own = {n: [w for w in result.warnings if w.startswith(f"{n}:")] for n in result.names}
    general = [w for w in result.warnings if not any(w.startswith(f"{n}:") for n in result.names)]
    prov = dict(model.provenance)
    for n in result.names:
        flags = own[n] + general
        for key in ESTIMATE_FIELDS[n]:
            if flags and key in prov:
                p = prov[key]
                prov[key] = replace(p, note=f"{p.note}; flagged: " + " | ".join(flags))
    return replace(model, provenance=prov)


def run(args) -> int:
    import sys
    import warnings
    from dataclasses import replace

    from ..controllers import constant, pd_control
    from ..datasets import load_record
    from ..identify import LINEAR_MODELS, didim, identify_record, identify_run, idim_iv, idim_ls
    from ..identify.record import held_out_halves, held_out_warnings
    from ._output import about, check_figure, check_outputs, json_text

    check_figure("--figure", args.figure)  # before the fit: matplotlib would refuse it after
    check_outputs({"--out": args.out, "--figure": args.figure}, [args.run], force=args.force)
    if args.max_torque is not None and not args.max_torque > 0:
        raise ValueError(f"--max-torque must be a number > 0, got {args.max_torque}")
    if args.max_torque is not None and args.out is None:
        raise ValueError("--max-torque has no effect without --out (it is written into the "
                         "model file, not used by the fit)")
    if args.force and args.out is None and args.figure is None:
        raise ValueError("--force has no effect without --out or --figure (it lets them "
                         "overwrite an existing file)")
    if args.figure is not None and args.no_validation:
        raise ValueError("--figure plots the held-out validation: it cannot go with "
                         "--no-validation")
    if args.model not in LINEAR_MODELS:
        given = [o for o, x in (("--no-validation", args.no_validation or None),
                                ("--figure", args.figure)) if x is not None]
        if given:
            raise ValueError(f"{', '.join(given)} has no effect with --model {args.model} (a "
                             f"fit is validated on held-out data for a linear model only)")
    if args.recipe == "auto" and args.model not in LINEAR_MODELS:
        raise ValueError(f"--model {args.model} is not linear in its parameters: the auto recipe "
                         f"fits {' and '.join(LINEAR_MODELS)}; use --recipe plain")
    if args.recipe != "plain":
        given = [o for o, x in (("--estimator", args.estimator), ("--border", args.border))
                 if x is not None]
        if given:
            raise ValueError(f"{', '.join(given)} has no effect with --recipe {args.recipe} (only "
                             f"plain takes an estimator and a border)")
    if args.controller is not None and args.recipe not in _SIMULATING:
        raise ValueError(f"--controller has no effect with --recipe {args.recipe} (only "
                         f"{' and '.join(_SIMULATING)} simulate the record)")
    controller = None
    if args.controller is not None:
        controller = pd_control(*args.controller, constant(0.0))
    with about(args.run), warnings.catch_warnings(record=True) as caught:
        # a Python warning raised on the way (numpy's...) is one of the result's, so that the
        # JSON holds every warning printed
        record = load_record(args.run, units=args.units)
        if record.encoder_grid() is None and record.position.min() == record.position.max():
            # a valid record (a joint stuck below breakaway), but nothing to identify from
            raise ValueError("position: no motion (the position is constant): a joint that "
                             "never moved says nothing about its dynamics")
        ident = None
        if args.recipe == "auto":
            ident = identify_record(record, model=args.model, offset=args.offset,
                                    validate=not args.no_validation)
            result = ident.result
            estimator = "butterworth_central"
        elif args.recipe == "idim_ls":
            result = idim_ls(record, model=args.model, offset=args.offset)
            estimator = "butterworth_central"
        elif args.recipe in _SIMULATING:
            fit = idim_iv if args.recipe == "idim_iv" else didim
            result = fit(record, model=args.model, offset=args.offset, controller=controller)
            estimator = "butterworth_central"
        else:
            estimator = args.estimator or "butterworth_central"
            result = identify_run(record, model=args.model, estimator=estimator, offset=args.offset,
                                  **_border(args))
            if args.model in LINEAR_MODELS:
                result = _bias_checked(record, args, estimator, result)
        held = None
        if ident is None and args.model in LINEAR_MODELS and not args.no_validation:
            held = held_out_halves(lambda r: _fit_again(args, r, controller, estimator), record)
        extra = _poor_fit(result)  # every recipe's, the default's too (review R12)
        if ident is None:  # the default recipe's result carries its held-out warnings already
            extra = held_out_warnings(held, refined=args.recipe == "didim") + extra
    extra += [str(w.message).splitlines()[0] or w.category.__name__ for w in caught]
    if extra:
        result = replace(result, warnings=tuple(dict.fromkeys(result.warnings + tuple(extra))))
        if ident is not None:
            ident = replace(ident, result=result)
    # before any output: a fit that gives no model file is one error line, not warnings first
    model = None if args.out is None else _model_file(result, record, args)
    for w in result.warnings:
        print(f"fricctl identify: warning: {w}", file=sys.stderr)
    fig = None
    if args.figure is not None:  # drawn before any file is written: a validation that failed
        from ..figures.identification import plot_held_out, plot_validation  # leaves nothing

        fig = (plot_held_out(ident) if ident is not None else plot_validation(
            held, result=result, title=f"{result.method} ({result.model}): each half "
                                       f"replayed with the other half's estimate"))
    if fig is not None:
        from ._output import save_figure

        save_figure(fig, args.figure, overwrite=args.force)  # atomic
    if model is not None:  # last: a call that failed on the way leaves no model file
        model.save(args.out, overwrite=args.force)  # atomic
    if args.json:
        out = result.as_dict() if ident is None else ident.as_dict()
        if ident is None:
            out["held_out"] = None if held is None else held.as_dict()
        out.update(estimator=estimator, recipe=args.recipe,
                   out=None if args.out is None else str(args.out))
        print(json_text(out))
    else:
        print(f"{record.source}: {record.n_samples} samples at {record.sample_time:g} s, "
              f"{'estimator ' + estimator if args.recipe == 'plain' else 'recipe ' + args.recipe}"
              + (f", low-pass at {ident.cutoff:.4g} Hz (the record's motion band)" if ident else ""))
        print(result.report() if ident is None else ident.report())
        if held is not None and not held.failure:
            print(f"Held-out halves: simulation fit (position) {held.simulation_fit:.2f} %, "
                  f"equation-error fit {held.equation_fit:.2f} %")
        if args.figure is not None:
            print(f"figure written to {args.figure}")
        if args.out is not None:
            print(f"model written to {args.out}")
    return 0
