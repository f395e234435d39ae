"""``fricctl simulate``: one run of the virtual bench, as a summary, a CSV record and a figure.

Examples::

    fricctl simulate --controller pd --rise-time 0.3 --damping 0.9 --reference step:0.5236 --duration 3
    fricctl simulate --torque sinusoid:0.2,1 --duration 2 --csv run.csv --figure run.png
    fricctl simulate --controller pd --rise-time 0.4 --damping 0.85 --link --reference step:0.08 \\
        --compensation nn --net net.json --scale 0.95 --friction-scale 0.95 --json
"""

from __future__ import annotations

import argparse
import json
import math

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
    p.add_argument("--link", action="store_true", help="attach the SCARA link (0.0046 kg*m^2)")
    p.add_argument("--plant", choices=("rigid", "flexible"), default="rigid")
    p.add_argument("--friction-scale", type=float, default=1.0, help="true friction x this factor")
    p.add_argument("--compensation", choices=("none", "coulomb", "nn"), default="none")
    p.add_argument("--net", help="FrictionNet JSON (for --compensation nn)")
    p.add_argument("--scale", type=float, default=None, help="compensation scale s (default 1)")
    p.add_argument("--duration", type=float, default=3.0, help="[s]")
    p.add_argument("--csv", help="write the measured record t,torque,position,reference")
    p.add_argument("--figure", help="write a PNG of position and torques")
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


def run(args) -> int:
    from ..compensators import CoulombCompensator, NNCompensator, NoCompensation
    from ..controllers import open_loop, p_control, pd_control
    from ..params import paper_actuator
    from ..simulate import simulate

    params = paper_actuator()
    if args.link:
        params = params.with_link()
    _check_combination(args)
    scale = 1.0 if args.scale is None else args.scale
    for name, v in (("duration", args.duration), ("friction_scale", args.friction_scale), ("scale", scale)):
        if not (math.isfinite(v) and v > 0):
            raise ValueError(f"--{name.replace('_', '-')} must be a finite number > 0, got {v}")
    if args.controller == "open":
        ctrl = open_loop(parse_signal(args.torque))
    else:
        ref = parse_signal(args.reference or "step:0.5236")
        if args.kp is not None:
            kp, kd = args.kp, (args.kd if args.controller == "pd" else 0.0)
        else:
            if args.rise_time is None or args.damping is None:
                raise ValueError(f"--controller {args.controller} needs --rise-time and --damping (or --kp)")
            from ..design import design_p, design_pd

            d = (design_p(params, rise_time=args.rise_time, damping=args.damping) if args.controller == "p"
                 else design_pd(params, rise_time=args.rise_time, damping=args.damping))
            kp, kd = d.kp, d.kd
        ctrl = p_control(kp, ref) if args.controller == "p" else pd_control(kp, kd, ref)
    if args.compensation == "none":
        comp = NoCompensation()
    elif args.compensation == "coulomb":
        comp = CoulombCompensator.symmetric(params.coulomb, scale=scale)
    else:
        from ..nn import load_net

        comp = NNCompensator(load_net(args.net), scale=scale)
    res = simulate(params, ctrl, comp, duration=args.duration, plant=args.plant,
                   friction=params.friction_model().scaled(args.friction_scale))
    summary = {
        "controller": res.info.controller, "kp": res.info.kp, "kd": res.info.kd,
        "compensator": res.info.compensator, "compensation_scale": res.info.compensation_scale,
        "final_error_rad": float(res.reference[-1] - res.q[-1]),
        "steady_state_error_deg": math.degrees(res.steady_state_error(min(0.5, args.duration / 2))),
        "max_abs_position_rad": float(np.max(np.abs(res.q))),
        "stuck_intervals": len(res.stuck_intervals()),
        "stuck_at_end": bool(res.stuck[-1]),
    }
    if args.csv:
        res.to_run(source="fricctl simulate").to_csv(args.csv)
    if args.figure:
        import matplotlib.pyplot as plt

        from .. import figures

        fig, (a, b) = plt.subplots(2, 1, sharex=True, figsize=(7, 5), layout="constrained")
        figures.plot_response(res, ax=a)
        figures.plot_stuck(res, ax=a)
        figures.plot_torques(res, ax=b)
        fig.savefig(args.figure, dpi=110)
        plt.close(fig)
    if args.json:
        print(json.dumps(summary, indent=2))
    else:
        for k, v in summary.items():
            print(f"{k:26s} {v:.6g}" if isinstance(v, float) else f"{k:26s} {v}")
    return 0
