"""``fricctl model {new,show}``: describe your own actuator by its numbers, and read a model file.

``fricctl model new --inertia I --viscous B --coulomb FC --sample-time TS --out my.json``
writes a model file (``fricctl.joint_model`` version 2, the format of
``docs/model_file.md``) from a datasheet's or a measurement's numbers: every value given is
recorded with its provenance (``--source-of`` says where they come from: datasheet by
default), every value not given is left out (zero friction terms, unknown encoder and torque
limit).  Per-direction values: ``--coulomb-neg``/``--viscous-neg`` (positive magnitudes);
the breakaway level ``--static`` (Fs >= Fc) with ``--stribeck-velocity``; any other
coefficient of a registered friction law as ``--friction NAME=VALUE`` (repeatable).  A bare
number is in the SI unit on the load side: N*m, rad, kg*m^2 (``--units linear``: N, m, kg);
a number of an option may carry its unit (``--friction NAME=VALUE`` takes SI values;
``--sample-time 2ms``, ``--coulomb 150mN*m``,
``--stribeck-velocity 5deg/s``, ``--encoder-resolution 0.01deg``; the accepted ones are in
:data:`fricctl.units.SUFFIXES`).

``fricctl model show my.json`` prints every value with its unit and provenance, the
breakaway level and the linear viscous model's time constant; ``--json`` prints the file's
content as one object.  Bad input prints one line on stderr and exits with code 2.
"""

from __future__ import annotations

import argparse
import math


def register(subparsers) -> None:
    p = subparsers.add_parser("model", help="write a model file from your actuator's numbers, "
                                            "or show one",
                              description=__doc__.split("\n\n", 1)[1],
                              formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="action", metavar="ACTION", parser_class=type(p))
    parts = __doc__.split("\n\n")  # [title, new, show]
    new = sub.add_parser("new", help="write a model file from numbers", description=parts[1],
                         formatter_class=argparse.RawDescriptionHelpFormatter)
    new.add_argument("--inertia", type=str, required=True,
                     help="total inertia I [kg*m^2] (linear: mass [kg])")
    new.add_argument("--viscous", type=str, default=0.0, help="viscous coefficient b [N*m*s/rad]")
    new.add_argument("--viscous-neg", type=str, default=None,
                     help="b for negative velocity if it differs [N*m*s/rad]")
    new.add_argument("--coulomb", type=str, default=0.0, help="Coulomb level Fc [N*m]")
    new.add_argument("--coulomb-neg", type=str, default=None,
                     help="Fc for negative velocity if it differs (a magnitude) [N*m]")
    new.add_argument("--static", type=str, default=None,
                     help="breakaway level Fs >= Fc [N*m] (needs --stribeck-velocity)")
    new.add_argument("--stribeck-velocity", type=str, default=None,
                     help="Stribeck velocity vs of the fall from Fs to Fc [rad/s]")
    new.add_argument("--friction", action="append", default=[], metavar="NAME=VALUE",
                     help="any other coefficient of fricctl.friction.FrictionModel (repeatable)")
    new.add_argument("--offset", type=str, default=0.0, help="constant resistive torque [N*m]")
    new.add_argument("--sample-time", type=str, default=None, help="controller's Ts [s]")
    new.add_argument("--encoder-resolution", type=str, default=None,
                     help="one encoder count [rad] (linear: [m])")
    new.add_argument("--encoder-counts", type=float, default=None,
                     help="counts per revolution on the load side (instead of the resolution)")
    new.add_argument("--max-torque", type=str, default=None, help="torque limit +-Tmax [N*m]")
    new.add_argument("--units", choices=("rotary", "linear"), default="rotary",
                     help="rotary joint (default: N*m, rad, kg*m^2) or linear axis (N, m, kg): "
                          "the SI unit of a bare number")
    new.add_argument("--source-of", choices=("datasheet", "measured", "identified", "assumption"),
                     default="datasheet", help="where the numbers come from (provenance)")
    new.add_argument("--source", default="", help="free text: which actuator, which document")
    new.add_argument("--out", required=True, help="the model file to write (.json)")
    new.add_argument("--force", action="store_true", help="overwrite an existing file")
    new.set_defaults(func=run_new)
    show = sub.add_parser("show", help="print a model file's values with units and provenance",
                          description=parts[2], formatter_class=argparse.RawDescriptionHelpFormatter)
    show.add_argument("file", help="model file (.json)")
    show.add_argument("--json", action="store_true", help="print the file's content as JSON")
    show.set_defaults(func=run_show)
    p.set_defaults(func=_no_action)


def _no_action(args) -> int:
    raise ValueError("an action is required: new or show (see fricctl model --help)")


#: The options that take a quantity, by argparse dest: what each is (:func:`fricctl.units.parse_quantity`).
QUANTITIES = {"inertia": "inertia", "viscous": "viscous", "viscous_neg": "viscous",
              "coulomb": "torque", "coulomb_neg": "torque", "static": "torque",
              "offset": "torque", "max_torque": "torque", "stribeck_velocity": "velocity",
              "sample_time": "time", "encoder_resolution": "position"}


def _quantities(args) -> None:
    """Each quantity option's text (``2ms``, ``0.15``) converted to its SI value in place, by
    the axis of ``--units``; a wrong unit or a non-number names the option."""
    from ..units import parse_quantity

    for dest, quantity in QUANTITIES.items():
        text = getattr(args, dest)
        if isinstance(text, str):
            try:
                value = parse_quantity(text, quantity, args.units)
            except ValueError as err:
                raise ValueError(f"--{dest.replace('_', '-')}: {err}") from None
            if not math.isfinite(value):
                raise ValueError(f"--{dest.replace('_', '-')} must be finite, got {text!r}")
            setattr(args, dest, value)


def _number(option: str, x, *, positive=False) -> float:
    if x is None or not math.isfinite(x) or (x <= 0 if positive else x < 0):
        raise ValueError(f"{option} must be a finite number {'> 0' if positive else '>= 0'}, got {x}")
    return float(x)


def _friction(args) -> dict:
    """The friction coefficients the options give, by FrictionModel field name."""
    from ..friction import FIELDS

    fr = {}
    for base, neg in (("viscous", args.viscous_neg), ("coulomb", args.coulomb_neg)):
        pos = _number(f"--{base}", getattr(args, base))
        fr[f"{base}_pos"], fr[f"{base}_neg"] = pos, pos if neg is None else _number(f"--{base}-neg", neg)
    if (args.static is None) != (args.stribeck_velocity is None):
        raise ValueError("--static and --stribeck-velocity go together (the breakaway level Fs "
                         "and the speed vs over which friction falls to Fc)")
    if args.static is not None:
        fs = _number("--static", args.static)
        if fs < max(fr["coulomb_pos"], fr["coulomb_neg"]):
            raise ValueError(f"--static {fs:g} is below the Coulomb level: the breakaway level "
                             "Fs is at least Fc")
        fr["stribeck_pos"] = fs - fr["coulomb_pos"]
        fr["stribeck_neg"] = fs - fr["coulomb_neg"]
        fr["stribeck_velocity"] = _number("--stribeck-velocity", args.stribeck_velocity, positive=True)
    own = {"viscous_pos", "viscous_neg", "coulomb_pos", "coulomb_neg", "stribeck_pos",
           "stribeck_neg", "stribeck_velocity"}  # set by their own options (Fs - Fc stays true)
    for item in args.friction:
        name, sep, value = item.partition("=")
        if not sep:
            raise ValueError(f"--friction {item!r}: expected NAME=VALUE")
        if name.strip() in own:
            raise ValueError(f"--friction {name.strip()}: set it with its own option (--viscous, "
                             "--coulomb, their -neg forms, --static, --stribeck-velocity)")
        if name.strip() not in FIELDS:
            from difflib import get_close_matches

            near = get_close_matches(name.strip(), FIELDS, n=1)
            raise ValueError(f"--friction: unknown coefficient {name.strip()!r}"
                             + (f" (did you mean {near[0]!r}?)" if near else ""))
        try:
            fr[name.strip()] = float(value)
        except ValueError:
            raise ValueError(f"--friction {name.strip()}: {value!r} is not a number") from None
    from ..friction import DEFAULTS

    return {k: x for k, x in fr.items() if x != DEFAULTS[k] or k == "stribeck_velocity"}


def run_new(args) -> int:
    from ..friction import FrictionModel
    from ..plant import JointModel
    from ..plant.model import Provenance
    from ._output import check_outputs

    check_outputs({"--out": args.out}, [], force=args.force)
    _quantities(args)
    fr = _friction(args)
    if args.encoder_resolution is not None and args.encoder_counts is not None:
        raise ValueError("give --encoder-resolution or --encoder-counts, not both")
    res = args.encoder_resolution
    if args.encoder_counts is not None:
        if args.units == "linear":
            raise ValueError("--encoder-counts is per revolution: a linear axis gives "
                             "--encoder-resolution [m]")
        res = 2.0 * math.pi / _number("--encoder-counts", args.encoder_counts, positive=True)
    values = {"inertia": args.inertia, "offset": args.offset, "sample_time": args.sample_time,
              "encoder_resolution": res, "max_torque": args.max_torque}
    note = "fricctl model new"
    prov = {k: Provenance(source=args.source_of, note=note) for k, x in values.items()
            if x is not None and (x != 0.0 or k == "inertia")}
    derived = {"stribeck_pos", "stribeck_neg"}  # Fs - Fc
    prov.update({f"friction.{k}": Provenance(source="derived" if k in derived else args.source_of,
                                             note="--static minus --coulomb" if k in derived else note)
                 for k in fr})
    model = JointModel(inertia=args.inertia, friction=FrictionModel(**fr), offset=args.offset,
                       units=args.units, source=args.source or "fricctl model new",
                       sample_time=args.sample_time, encoder_resolution=res,
                       max_torque=args.max_torque, provenance=prov)
    model.save(args.out, overwrite=args.force)
    print(f"wrote {args.out}: {_one_line(model)}")
    return 0


def _one_line(model) -> str:
    from ..units import units as units_of

    u = units_of(model.units)
    fr = model.friction
    return (f"I = {model.inertia:g} {u.inertia}, b = {model.viscous:g} {u.viscous}, "
            f"Fc = {fr.coulomb_pos:g}/{fr.coulomb_neg:g} {u.torque}, "
            f"breakaway {fr.breakaway(1):g}/{fr.breakaway(-1):g} {u.torque}")


def _axis_unit(unit: str, kind: str) -> str:
    """A coefficient's (rotary) unit on a linear axis: N*m -> N, rad -> m."""
    if kind != "linear":
        return unit
    return unit.replace("N*m", "N").replace("rad", "m")


def run_show(args) -> int:
    from ..friction.layout import COEFFICIENTS
    from ..plant import JointModel
    from ..units import units as units_of
    from ._output import json_text

    model = JointModel.load(args.file)
    if args.json:
        print(json_text(model.as_dict()))
        return 0
    u = units_of(model.units)
    rows = [("inertia", model.inertia, u.inertia)]
    unit_of = {c.name: _axis_unit(c.unit, model.units) for c in COEFFICIENTS}
    rows += [(f"friction.{k}", x, unit_of[k]) for k, x in model.friction.changed().items()]
    rows += [(k, getattr(model, k), unit) for k, unit in
             (("offset", u.torque), ("delay", "s"), ("load_inertia", u.inertia),
              ("stiffness", u.stiffness), ("damping", u.viscous), ("backlash", u.position),
              ("sample_time", "s"),
              ("encoder_resolution", u.position), ("max_torque", u.torque))]
    print(f"{args.file}: {model.units} axis; {model.source}")
    for name, x, unit in rows:
        p = model.provenance.get(name)
        where = "" if p is None else f"  [{p.source}{'' if p.std is None else f', std {p.std:.3g}'}]"
        text = "unknown" if x is None else f"{x:.6g} {unit}".rstrip()
        print(f"  {name:28s} {text}{where}")
    fr = model.friction
    print(f"  breakaway level              +{fr.breakaway(1):.6g} / -{fr.breakaway(-1):.6g} {u.torque}")
    if model.viscous > 0:
        print(f"  time constant I/b            {model.inertia / model.viscous:.6g} s "
              "(the linear viscous model)")
    return 0
