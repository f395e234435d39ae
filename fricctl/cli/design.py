"""``fricctl design {p,pd}``: gains from rise time and damping, verified.

Designs on the linear viscous model ``1/(s (I s + b))`` of the paper actuator
(``--link`` adds the 0.0046 kg*m^2 SCARA link), or of your own actuator with
``--model MODEL.json`` (a ``fricctl.joint_model`` file, e.g. from ``fricctl
identify --out``: its inertia, the mean viscous coefficient of both directions,
its sample time and units: a linear axis prints kg, N*s/m, N/m), and prints the
gains with the achieved step metrics of the continuous loop and of the sampled
loop at the sample time.  ``--json`` prints one JSON object
(:meth:`fricctl.design.Design.as_dict`), the same keys with or without ``--model``:
``law, units, kp, kd, inertia, viscous, sample_time, requested{rise_time, damping, priority},
rise_time_definition, wn, zeta, achieved{rise_time, damping, overshoot_percent,
settling_time}, sampled{...same...}, warnings[...]``; each quantity is ``{"value": ...,
"unit": ...}`` (as ``identify --json`` writes its parameters; ``"-"`` for a ratio); missing
values are null.
"""

from __future__ import annotations

import argparse
import sys
import warnings


#: The readings of "rise time" (:data:`fricctl.design.second_order.RISE_TIME_DEFINITIONS`;
#: written out so that building the parser does not import the design package).
RISE_TIME_CHOICES = ("0-100", "10-90", "peak")


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "design",
        help="P/PD gains from rise time and damping (linear viscous model)",
        description=__doc__.split("\n\n", 1)[1],
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("law", choices=("p", "pd"),
                   help="p: Tc = Kp (r - q); pd: Tc = Kp (r - q) - Kd omega_hat (rate feedback)")
    p.add_argument("--rise-time", type=float, default=None, metavar="S",
                   help="requested rise time [s] (required for pd)")
    p.add_argument("--damping", type=float, default=None, metavar="Z",
                   help="requested damping ratio [-] (required for pd)")
    p.add_argument("--link", action="store_true",
                   help="add the SCARA link inertia 0.0046 kg*m^2 to the paper's actuator")
    p.add_argument("--model", metavar="MODEL.json", default=None,
                   help="design for this model file instead of the paper's actuator")
    p.add_argument("--rise-time-definition", choices=RISE_TIME_CHOICES, default=None,
                   help="default 0-100 for damping < 1 and 10-90 for damping >= 1; 0-100 and "
                        "peak (the time of the first peak, the consistent bench's reading) are "
                        "refused for damping >= 1 (such a step never reaches its final value)")
    p.add_argument("--priority", choices=("rise_time", "damping"), default=None,
                   help="p with both specs: the one met exactly (default rise_time)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


def run(args) -> int:
    from ..design import DesignWarning, design_p, design_pd
    from ._output import json_text
    from ..params import paper_actuator
    from ..plant import JointModel

    if args.model is not None:
        if args.link:
            raise ValueError("--link has no effect with --model (the model holds the inertia)")
        params = JointModel.load(args.model)
    else:
        params = paper_actuator().with_link() if args.link else paper_actuator()
    with warnings.catch_warnings():
        # the Design records its warnings; the CLI prints them once, below
        warnings.simplefilter("ignore", DesignWarning)
        if args.law == "p":
            d = design_p(params, rise_time=args.rise_time, damping=args.damping,
                         priority=args.priority or "rise_time",
                         rise_time_definition=args.rise_time_definition)
        else:
            if args.priority is not None:
                raise ValueError("--priority applies to p only: a PD meets both specs")
            d = design_pd(params, rise_time=args.rise_time, damping=args.damping,
                          rise_time_definition=args.rise_time_definition)
    print(json_text(d.as_dict()) if args.json else d.report(with_warnings=False))
    for w in d.warnings:  # after the output, on stderr, as every command's warnings
        print(f"fricctl design: warning: {w}", file=sys.stderr)
    return 0
