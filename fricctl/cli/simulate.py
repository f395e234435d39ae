"""``fricctl simulate``: one run of the virtual bench, as a summary, a CSV record and a figure.

The plant is the paper's actuator (``--link``, ``--plant``), or your own actuator
with ``--model MODEL.json`` (a ``fricctl.joint_model`` file: its joint, sample time,
encoder, torque limit, offset, delay and units; references, torques and gains in
its units, e.g. [m], [N], [N/m] on a linear axis).  With ``--model`` the summary
keys are ``controller, kp, kd, compensator, compensation_scale, units,
final_error, steady_state_error, tracking_error_rms, max_abs_error,
max_abs_position, max_abs_torque, stuck_intervals, stuck_at_end`` (positions in
the model's unit).  ``--c-source NAME.c`` (with ``--compensation nn``) also writes
the simulated compensator as C: ``NAME.c`` and its header ``NAME.h``
(:func:`fricctl.nn.c_export.c_source`, functions prefixed ``NAME``).  An existing
output file is kept unless ``--force``.

Examples::

    fricctl simulate --controller pd --rise-time 0.3 --damping 0.9 --reference step:0.5236 --duration 3
    fricctl simulate --torque sinusoid:0.2,1 --duration 2 --csv run.csv --figure run.png
    fricctl simulate --controller pd --rise-time 0.4 --damping 0.85 --link --reference step:0.08 \\
        --compensation nn --net net.json --scale 0.95 --friction-scale 0.95 --json
    fricctl simulate --model emps.json --controller pd --rise-time 0.05 --damping 0.7 \\
        --reference sinusoid:0.05,0.5 --compensation nn --net net.json --c-source emps_comp.c
"""

from __future__ import annotations

import argparse
import math
import warnings
from pathlib import Path

import numpy as np

_SIGNALS = {"step": 1, "constant": 1, "sawtooth": 2, "sinusoid": 2}


def parse_signal(spec: str):
    """``kind:a[,b]`` -> a :class:`fricctl.controllers.Signal`.

    ``step:A`` (at t = 0), ``constant:A``, ``sawtooth:A,PERIOD``, ``sinusoid:A,FREQ``.
    """
    from .. import controllers as c

    kind, _, args = spec.partition(":")
    if kind not in _SIGNALS:
        raise ValueError(f"unknown signal {kind!r} in {spec!r}; use step:A, constant:A, sawtooth:A,PERIOD "
                         "or sinusoid:A,FREQ")
    try:
        vals = [float(v) for v in args.split(",")] if args else []
    except ValueError:
        raise ValueError(f"signal {spec!r}: arguments must be numbers") from None
    if len(vals) != _SIGNALS[kind] or not all(math.isfinite(v) for v in vals):
        raise ValueError(f"signal {spec!r}: {kind} takes {_SIGNALS[kind]} finite number(s)")
    return {"step": c.step, "constant": c.constant, "sawtooth": c.sawtooth, "sinusoid": c.sinusoid}[kind](*vals)


def register(sub):
    p = sub.add_parser("simulate", help="simulate the actuator (virtual bench) and save the record",
                       description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--controller", choices=("open", "p", "pd"), default="open")
    p.add_argument("--rise-time", type=float, help="design rise time [s] (P/PD)")
    p.add_argument("--damping", type=float, help="design damping ratio [-] (P/PD)")
    p.add_argument("--kp", type=float, help="proportional gain [N*m/rad] instead of a design")
    p.add_argument("--kd", type=float, default=None, help="rate gain [N*m*s/rad] instead of a design")
    p.add_argument("--reference", default=None, help="position reference [rad] (P/PD; default step:0.5236)")
    p.add_argument("--torque", default=None, help="open-loop torque [N*m], e.g. sinusoid:0.2,1")
    p.add_argument("--model", metavar="MODEL.json", default=None,
                   help="simulate this model file (your own actuator) instead of the paper's")
    p.add_argument("--link", action="store_true", help="attach the SCARA link (0.0046 kg*m^2)")
    p.add_argument("--plant", choices=("rigid", "flexible"), default=None,
                   help="paper actuator: rigid (default) or flexible joint")
    p.add_argument("--friction-scale", type=float, default=1.0, help="true friction x this factor")
    p.add_argument("--compensation", choices=("none", "coulomb", "nn"), default="none",
                   help="none; coulomb: s*Fc*sign(omega_hat) at the model's sliding (Coulomb) "
                        "level per direction, scaled with the friction (not the breakaway "
                        "level; a model without Coulomb friction is refused); nn: the network "
                        "of --net.  A compensated run is checked for wind-up (warning)"),
    p.add_argument("--net", help="FrictionNet JSON (for --compensation nn)")
    p.add_argument("--scale", type=float, default=None, help="compensation scale s (default 1)")
    p.add_argument("--clip", action="store_true",
                   help="clip the network's inputs to its training envelope")
    p.add_argument("--duration", type=float, default=3.0, help="[s]")
    p.add_argument("--csv", help="write the measured record t,torque,position,reference")
    p.add_argument("--figure", metavar="FILE.png",
                   help="write a figure of position and torques; the name must end in .png, "
                        ".pdf or .svg (a folder or a bare name is refused: nothing is written "
                        "beside it)")
    p.add_argument("--c-source", metavar="NAME.c", default=None,
                   help="with --compensation nn: write the compensator as C (NAME.c, NAME.h)")
    p.add_argument("--force", action="store_true", help="overwrite existing output files")
    p.add_argument("--json", action="store_true", help="print a JSON summary")
    p.set_defaults(func=run)


def _check_combination(args) -> None:
    """Refuse options that would have no effect in this combination (nothing silently ignored)."""
    given = {name for name in ("kp", "kd", "rise_time", "damping", "reference", "torque", "net", "scale")
             if getattr(args, name) is not None}

    def refuse(names, why):
        bad = sorted(given & set(names))
        if bad:
            opts = ", ".join("--" + b.replace("_", "-") for b in bad)
            raise ValueError(f"{opts} has no effect {why}")

    if args.controller == "open":
        if args.torque is None:
            raise ValueError("--controller open needs --torque, e.g. --torque sinusoid:0.2,1")
        refuse(("kp", "kd", "rise_time", "damping", "reference"), "with --controller open")
    else:
        refuse(("torque",), "with a P/PD controller (it is the open-loop torque)")
        if args.kp is not None:
            refuse(("rise_time", "damping"), "when the gains are given with --kp")
            if args.controller == "p":
                refuse(("kd",), "with --controller p")
            elif args.kd is None:
                raise ValueError("--controller pd with --kp needs --kd too")
        else:
            refuse(("kd",), "without --kp (the design gives Kd)")
    if args.compensation != "nn":
        refuse(("net",), f"with --compensation {args.compensation}")
    elif args.net is None:
        raise ValueError("--compensation nn needs --net NET.json (see `fricctl train`)")
    if args.compensation == "none":
        refuse(("scale",), "with --compensation none")
    if args.compensation != "nn" and (args.clip or args.c_source):
        raise ValueError(f"{'--clip' if args.clip else '--c-source'} applies to --compensation nn")
    if args.model is not None:
        bad = [o for o, x in (("--link", args.link), ("--plant", args.plant)) if x]
        if bad:
            raise ValueError(f"{', '.join(bad)} has no effect with --model (the model is the plant)")
        if args.controller != "open" and args.reference is None:
            raise ValueError("--model needs --reference (in the model's position unit)")


def _controller(args, plant):
    from ..controllers import open_loop, p_control, pd_control

    if args.controller == "open":
        return open_loop(parse_signal(args.torque))
    ref = parse_signal(args.reference or "step:0.5236")
    if args.kp is not None:
        kp, kd = args.kp, (args.kd if args.controller == "pd" else 0.0)
    else:
        if args.rise_time is None or args.damping is None:
            raise ValueError(f"--controller {args.controller} needs --rise-time and --damping (or --kp)")
        from ..design import design_p, design_pd

        d = (design_p(plant, rise_time=args.rise_time, damping=args.damping) if args.controller == "p"
             else design_pd(plant, rise_time=args.rise_time, damping=args.damping))
        kp, kd = d.kp, d.kd
    return p_control(kp, ref) if args.controller == "p" else pd_control(kp, kd, ref)


def _compensator(args, scale, coulomb_pos, coulomb_neg):
    from ..compensators import CoulombCompensator, NNCompensator, NoCompensation

    if args.compensation == "none":
        return NoCompensation()
    if args.compensation == "coulomb":
        if coulomb_pos <= 0.0 and coulomb_neg <= 0.0:
            raise ValueError("--compensation coulomb: the model has no Coulomb friction "
                             "(coulomb_pos = coulomb_neg = 0), so the compensation would add "
                             "nothing; use --compensation none or a model with its Coulomb level")
        return CoulombCompensator(coulomb_pos=coulomb_pos, coulomb_neg=coulomb_neg, scale=scale)
    from ..nn import load_net

    return NNCompensator(load_net(args.net), scale=scale, clip=args.clip)


def _outputs(args) -> dict:
    outs = {"--csv": args.csv, "--figure": args.figure, "--c-source": args.c_source}
    if args.c_source is not None:
        from ..nn.c_export import check_c_name

        c = Path(args.c_source)
        if c.suffix != ".c" or not (c.stem.isidentifier() and c.stem.isascii()):
            raise ValueError(f"--c-source must be NAME.c with NAME a C identifier (the functions' "
                             f"prefix), got {c.name!r}")
        try:  # not int.c, default.c, tanh.c: the C would not compile
            check_c_name(c.stem)
        except ValueError as exc:
            raise ValueError(f"--c-source {c.name}: the function {exc}") from None
        outs["--c-source (its header)"] = c.with_suffix(".h")
    return outs


#: Why an open-loop run's error values are null (it follows a torque, not a reference).
NO_REFERENCE = "open loop: there is no reference, so no error"


def _errors(res, keys) -> dict:
    """The error values of a summary (null for an open-loop run: see :data:`NO_REFERENCE`)."""
    if res.info.controller == "open loop":
        return dict.fromkeys(keys)
    err = res.reference - res.q
    values = {"final_error": float(err[-1]),
              "steady_state_error": res.steady_state_error(min(0.5, res.t[-1] / 2)),
              "tracking_error_rms": float(np.sqrt(np.mean(err ** 2))),
              "max_abs_error": float(np.max(np.abs(err)))}
    return {k: values[k] for k in keys}


def _model_summary(res, model) -> dict:
    return {"controller": res.info.controller, "kp": res.info.kp, "kd": res.info.kd,
            "compensator": res.info.compensator, "compensation_scale": res.info.compensation_scale,
            "units": model.units,
            **_errors(res, ("final_error", "steady_state_error", "tracking_error_rms",
                            "max_abs_error")),
            "max_abs_position": float(np.max(np.abs(res.q))),
            "max_abs_torque": float(np.max(np.abs(res.torque_motor))),
            "stuck_intervals": len(res.stuck_intervals()), "stuck_at_end": bool(res.stuck[-1])}


def _figure(res, path, units, *, overwrite: bool) -> None:
    import matplotlib.pyplot as plt

    from .. import figures
    from ..units import units as units_of
    from ._output import save_figure

    fig, (a, b) = plt.subplots(2, 1, sharex=True, figsize=(7, 5), layout="constrained")
    figures.plot_response(res, ax=a, unit="deg" if units is None else "rad")
    figures.plot_stuck(res, ax=a)
    figures.plot_torques(res, ax=b)
    if units is not None:  # the figures label a rotary joint; relabel for the model's units
        u = units_of(units)
        a.set_ylabel(f"position q [{u.position}]")
        b.set_ylabel(f"{'torque' if units == 'rotary' else 'force'} [{u.torque}]")
    save_figure(fig, path, overwrite=overwrite)


def run(args) -> int:
    from ..datasets import Run
    from ..params import paper_actuator
    from ..plant import JointModel
    from ..simulate import sampling_warnings, simulate, simulate_model
    from ._output import check_figure, check_outputs, json_text

    _check_combination(args)
    check_figure("--figure", args.figure)
    outputs = _outputs(args)
    check_outputs(outputs, [args.model, args.net], force=args.force)
    scale = 1.0 if args.scale is None else args.scale
    for name, v in (("duration", args.duration), ("friction_scale", args.friction_scale), ("scale", scale)):
        if not (math.isfinite(v) and v > 0):
            raise ValueError(f"--{name.replace('_', '-')} must be a finite number > 0, got {v}")
    if args.model is not None:
        model = JointModel.load(args.model)
        fr = model.friction
        comp = _compensator(args, scale, fr.scale * fr.coulomb_pos, fr.scale * fr.coulomb_neg)
        ctl = _controller(args, model)
        res = simulate_model(model, ctl, comp, duration=args.duration,
                             friction=fr.scaled(args.friction_scale))
        summary, units = _model_summary(res, model), model.units
    else:
        params = paper_actuator().with_link() if args.link else paper_actuator()
        comp = _compensator(args, scale, params.coulomb, params.coulomb)
        ctl = _controller(args, params)
        res = simulate(params, ctl, comp, duration=args.duration,
                       plant=args.plant or "rigid",
                       friction=params.friction_model().scaled(args.friction_scale))
        summary, units = _paper_summary(res, args.duration), None
    warns = sampling_warnings(ctl, res.sample_time) + _runaway_warnings(res)
    summary.update(_compensation_level(comp))
    if args.csv:
        Run(t=res.t, torque=res.torque_motor, position=res.q_meas, reference=res.reference,
            source="fricctl simulate" + (f" --model {Path(args.model).name}" if args.model else ""),
            units=units or "rotary").to_csv(args.csv, overwrite=args.force)
    if args.figure:
        _figure(res, args.figure, units, overwrite=args.force)
    if args.c_source:
        from .._atomic import write_text
        from ..nn.c_export import c_header, c_source

        c = Path(args.c_source)
        net = comp.estimator
        write_text(c, c_source(net, name=c.stem, units=units or "rotary"), overwrite=args.force)
        write_text(c.with_suffix(".h"), c_header(net, name=c.stem, units=units or "rotary"),
                   overwrite=args.force)
    for text in warns:
        warnings.warn(text, stacklevel=1)
    if args.json:
        summary["warnings"] = warns
        print(json_text(summary, reasons={k: NO_REFERENCE for k, x in summary.items() if x is None}))
    else:
        labels = {} if units is None else _unit_labels(units)
        for k, v in summary.items():
            if k == "warnings":
                continue
            if v is None:
                print(f"{k:26s} - ({NO_REFERENCE})")
                continue
            text = f"{v:.6g}" if isinstance(v, float) else f"{v}"
            print(f"{k:26s} {text} {labels.get(k, '')}".rstrip())
    return 0


def _runaway_warnings(res) -> list[str]:
    """The wind-up check (:func:`fricctl.paper.runaway.wind_up`) of a compensated run, as warnings."""
    if res.info.compensator == "none":
        return []
    from ..paper.runaway import wind_up

    check = wind_up(res)
    return [] if check.passed else [f"the compensated joint winds its torque up: {check.reason}"]


def _compensation_level(comp) -> dict:
    """The Coulomb compensation's levels (what it adds per direction, before its scale) [N*m]."""
    from ..compensators import CoulombCompensator

    if not isinstance(comp, CoulombCompensator):
        return {}
    return {"coulomb_compensation_pos": float(comp.coulomb_pos),
            "coulomb_compensation_neg": float(comp.coulomb_neg)}


def _unit_labels(units) -> dict:
    """Unit of each summary value of a model run (the model's units)."""
    from ..units import units as units_of

    u = units_of(units)
    out = {"kp": u.stiffness, "kd": u.viscous, "max_abs_torque": u.torque}
    out.update({k: u.position for k in ("final_error", "steady_state_error", "tracking_error_rms",
                                          "max_abs_error", "max_abs_position")})
    return out


def _paper_summary(res, duration) -> dict:
    e = _errors(res, ("final_error", "steady_state_error"))
    return {
        "controller": res.info.controller, "kp": res.info.kp, "kd": res.info.kd,
        "compensator": res.info.compensator, "compensation_scale": res.info.compensation_scale,
        "final_error_rad": e["final_error"],
        "steady_state_error_deg": (None if e["steady_state_error"] is None
                                   else math.degrees(e["steady_state_error"])),
        "max_abs_position_rad": float(np.max(np.abs(res.q))),
        "stuck_intervals": len(res.stuck_intervals()),
        "stuck_at_end": bool(res.stuck[-1]),
    }
