"""``fricctl simulate``: one run of the virtual bench, as a summary, a CSV record and a figure.

The plant is the paper's actuator (``--link``, ``--plant``), or your own actuator
with ``--model MODEL.json`` (a ``fricctl.joint_model`` file: its joint, sample time,
encoder, torque limit, offset, delay and units; references, torques and gains in
its units, e.g. [m], [N], [N/m] on a linear axis).  A number in ``--reference`` or
``--torque`` is in that unit, or carries its own: ``step:30deg``, ``step:5mm``
(:data:`fricctl.units.SUFFIXES`).  The summary has the same keys with or
without ``--model``: ``controller, kp, kd, compensator, compensation_scale, units,
final_error, steady_state_error, settled, tracking_error_rms, max_abs_error,
max_abs_position, max_abs_torque, stuck_intervals, stuck_at_end`` (and a Coulomb
compensation's ``coulomb_compensation_pos, coulomb_compensation_neg``); each quantity
is printed with its unit and in ``--json`` is ``{"value": ..., "unit": ...}`` (as
``identify --json`` writes its parameters), in SI units of the plant's axis ([rad],
[N*m] on a rotary joint; the text also gives an angle in [deg]).  ``settled`` says whether
``steady_state_error`` (the mean error over the last 0.5 s, or half a shorter run) is one: the
run settled when its error stays over that stretch within one encoder count, or 2 % of its
largest error, of its mean; a run that did not settle gets a warning saying how far it still
moves, and its text line says "not settled" (null for an open-loop run).
``--compensation none,coulomb`` runs each compensation on the same plant and
reference: one entry each in the summary (``--json``: ``{"runs": [...]}``), one
overlaid figure.  Besides none, coulomb and nn, ``--compensation`` takes every compensator
of the registry (:func:`fricctl.compensators.available`: the static-model feedforward, the
LuGre observer, the disturbance observer, integral action ...), built from the model by
:func:`fricctl.compensators.make` (integral action from the P/PD gains on the model's
inertia and viscous coefficient).  ``--c-source NAME.c`` (with ``--compensation nn`` or
``nn_confirmed`` -- the network's C, whose header also gives the confirmed velocity --, or one
compensation that has a C export: :func:`fricctl.compensators.c_export.exportable`) also
writes the simulated compensator as C: ``NAME.c`` and its header ``NAME.h``
(:func:`fricctl.nn.c_export.c_source`, :func:`fricctl.compensators.c_export.c_source`;
functions prefixed ``NAME``).  ``--sigma0`` (and ``--sigma1``) give the LuGre observer
(``--compensation lugre_observer``) its bristle's stiffness [N*m/rad] (and damping
[N*m*s/rad]; [N/m] and [N*s/m] on a linear axis) where the model has no LuGre law, or
replace the law's; without ``--sigma1`` the damping is the law's, else ``sqrt(sigma0 * I)``
(:func:`fricctl.compensators.lugre_observer.default_sigma1`, as ``fricctl compare``).  An existing
output file is kept unless ``--force``.

Examples::

    fricctl simulate --controller pd --rise-time 0.3 --damping 0.9 --reference step:30deg --duration 3
    fricctl simulate --torque sinusoid:0.2,1 --duration 2 --csv run.csv --figure run.png
    fricctl simulate --controller pd --rise-time 0.3 --damping 0.9 --compensation none,coulomb \\
        --figure compare.png
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

#: Each signal's arguments after the amplitude, and what they are (for their units).
_SIGNALS = {"step": (), "constant": (), "sawtooth": ("time",), "sinusoid": ("frequency",)}
#: The compensations that run a trained network (``--net``).
_NETS = ("nn", "nn_confirmed")


def parse_signal(spec: str, quantity: str = "position", kind: str = "rotary"):
    """``kind:a[,b]`` -> a :class:`fricctl.controllers.Signal`.

    ``step:A`` (at t = 0), ``constant:A``, ``sawtooth:A,PERIOD``, ``sinusoid:A,FREQ``.
    Each number may carry a unit (:func:`fricctl.units.parse_quantity`): the amplitude
    one of ``quantity`` on a ``kind`` axis (``step:20deg``, ``step:5mm``), the period one of
    time (``500ms``), the frequency ``Hz``; a bare number is in the SI unit ([rad], [m],
    [N*m], [N], [s], [Hz]).
    """
    from .. import controllers as c
    from ..units import parse_quantity

    name, _, args = spec.partition(":")
    if name not in _SIGNALS:
        raise ValueError(f"unknown signal {name!r} in {spec!r}; use step:A, constant:A, sawtooth:A,PERIOD "
                         "or sinusoid:A,FREQ")
    words = args.split(",") if args else []
    quantities = (quantity, *_SIGNALS[name])
    if len(words) != len(quantities):
        raise ValueError(f"signal {spec!r}: {name} takes {len(quantities)} finite number(s)")
    try:
        vals = [parse_quantity(w, q, kind) for w, q in zip(words, quantities)]
    except ValueError as exc:
        raise ValueError(f"signal {spec!r}: arguments must be numbers; {exc}") from None
    if not all(math.isfinite(v) for v in vals):
        raise ValueError(f"signal {spec!r}: {name} takes {len(quantities)} finite number(s)")
    return {"step": c.step, "constant": c.constant, "sawtooth": c.sawtooth, "sinusoid": c.sinusoid}[name](*vals)


def compensations() -> tuple[str, ...]:
    """The names ``--compensation`` takes: the registry's (:func:`fricctl.compensators.available`;
    read when an argument is parsed, so the command starts without loading the compiled loop)."""
    from ..compensators import available

    return available()


def _compensations(text: str) -> tuple[str, ...]:
    """``--compensation``: one of :func:`compensations` or a comma list of them, each once."""
    names = tuple(w.strip() for w in text.split(","))
    known = compensations()
    bad = [n for n in names if n not in known]
    if bad:
        from difflib import get_close_matches

        near = get_close_matches(bad[0], known, n=1)
        raise argparse.ArgumentTypeError(
            f"unknown compensation {bad[0]!r} in {text!r}"
            + (f" (did you mean {near[0]}?)" if near else "")
            + f"; use one of {', '.join(known)} or a comma list of them, e.g. none,coulomb")
    if len(set(names)) != len(names):
        raise argparse.ArgumentTypeError(f"{text!r} names a compensation twice")
    return names


def register(sub):
    p = sub.add_parser("simulate", help="simulate the actuator (virtual bench) and save the record",
                       description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--controller", choices=("open", "p", "pd"), default="open")
    p.add_argument("--rise-time", type=float,
                   help="design rise time [s] (P/PD): 0-100 %% for damping < 1, 10-90 %% from 1 "
                        "(fricctl design's default; design --rise-time-definition shows others "
                        "and their gains, which --kp/--kd then take)")
    p.add_argument("--damping", type=float, help="design damping ratio [-] (P/PD)")
    p.add_argument("--kp", type=float, help="proportional gain [N*m/rad] instead of a design")
    p.add_argument("--kd", type=float, default=None, help="rate gain [N*m*s/rad] instead of a design")
    p.add_argument("--reference", default=None,
                   help="position reference (P/PD; default step:0.5236): step:A, constant:A, "
                        "sawtooth:A,PERIOD or sinusoid:A,FREQ; a bare number is in [rad] ([m] on "
                        "a linear --model), or give a unit: rad, mrad, deg (linear: m, cm, mm, "
                        "um), e.g. step:30deg; PERIOD in [s] or ms, FREQ in [Hz]")
    p.add_argument("--torque", default=None,
                   help="open-loop torque, e.g. sinusoid:0.2,1: a bare number is in [N*m] ([N] on "
                        "a linear --model), or give a unit: N*m, Nm, mN*m (linear: N, kN)")
    p.add_argument("--model", metavar="MODEL.json", default=None,
                   help="simulate this model file (your own actuator) instead of the paper's")
    p.add_argument("--link", action="store_true", help="attach the SCARA link (0.0046 kg*m^2)")
    p.add_argument("--plant", choices=("rigid", "flexible"), default=None,
                   help="paper actuator: rigid (default) or flexible joint")
    p.add_argument("--friction-scale", type=float, default=1.0, help="true friction x this factor")
    p.add_argument("--compensation", type=_compensations, default=("none",),
                   metavar="NAME[,...]",
                   help="none; coulomb: s*Fc*sign(omega_hat) at the model's sliding (Coulomb) "
                        "level per direction, scaled with the friction (not the breakaway "
                        "level; a model without Coulomb friction is refused); nn: the network "
                        "of --net; or any other name of fricctl.compensators.available() "
                        "(feedforward, observers, integral action; an unknown name is refused "
                        "with the list), built from the model with its defaults.  "
                        "A comma list (none,coulomb,nn) runs each on the same plant "
                        "and reference: one figure overlays them, the summary has one entry "
                        "per compensation (--json: runs[...]), --csv is refused.  A "
                        "compensated run is checked for a runaway (a warning on stderr and in --json's "
                        "warnings): wind-up, or divergence for a compensator that is not a "
                        "friction estimate (observer, integral), and reversal under "
                        "--torque sinusoid; a run too short for a check to tell says so "
                        "(\"cannot judge this run: too short to tell\"): run a longer --duration to "
                        "judge it")
    p.add_argument("--net", help="FrictionNet JSON (for --compensation nn or nn_confirmed)")
    p.add_argument("--scale", type=float, default=None, help="compensation scale s (default 1)")
    p.add_argument("--sigma0", default=None, metavar="S",
                   help="with --compensation lugre_observer: the bristle stiffness sigma0 [N*m/rad] "
                        "(a model without a LuGre law needs it; e.g. 2e4 or 2e4N*m/rad)")
    p.add_argument("--sigma1", default=None, metavar="D",
                   help="with --compensation lugre_observer: the bristle damping sigma1 [N*m*s/rad] "
                        "(default: the model's LuGre law's, else sqrt(sigma0 * I), I the joint's "
                        "total inertia: damping ratio 0.5, Canudas de Wit et al.'s example; the "
                        "same rule as fricctl compare)")
    p.add_argument("--clip", action="store_true",
                   help="clip the network's inputs to its training envelope")
    p.add_argument("--duration", type=float, default=3.0, help="[s]")
    p.add_argument("--csv", help="write the measured record t,torque,position,reference")
    p.add_argument("--figure", metavar="FILE.png",
                   help="write a figure of position and torques; the name must end in .png, "
                        ".pdf or .svg (a folder or a bare name is refused: nothing is written "
                        "beside it)")
    p.add_argument("--c-source", metavar="NAME.c", default=None,
                   help="with --compensation nn or nn_confirmed (the network's C; its header gives "
                        "the confirmed velocity too), or one compensation with a C export ("
                        "feedforward, lugre_observer, dob, integral): write the compensator "
                        "as C (NAME.c, NAME.h)")
    p.add_argument("--force", action="store_true", help="overwrite existing output files")
    p.add_argument("--json", action="store_true", help="print a JSON summary")
    p.set_defaults(func=run)


def _check_combination(args) -> None:
    """Refuse options that would have no effect in this combination (nothing silently ignored)."""
    given = {name for name in ("kp", "kd", "rise_time", "damping", "reference", "torque", "net", "scale",
                               "sigma0", "sigma1") if getattr(args, name) is not None}

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
    given_comp = ",".join(args.compensation)
    if "lugre_observer" not in args.compensation:
        refuse(("sigma0", "sigma1"), f"with --compensation {given_comp} (they are lugre_observer's)")
    nets = [n for n in args.compensation if n in _NETS]
    if not nets:
        refuse(("net",), f"with --compensation {given_comp}")
    elif args.net is None:
        raise ValueError(f"--compensation {nets[0]} needs --net NET.json (see `fricctl train`)")
    if args.compensation == ("none",):
        refuse(("scale",), "with --compensation none")
    if not nets and args.clip:
        raise ValueError("--clip applies to --compensation nn or nn_confirmed")
    if args.c_source and not nets:
        from ..compensators.c_export import exportable

        have = [n for n in args.compensation if n in exportable()]
        if len(have) != 1:
            raise ValueError("--c-source applies to --compensation nn or to one compensation "
                             f"with a C export ({', '.join(exportable())}); got {given_comp}")
    if args.controller == "open" and "integral" in args.compensation:
        raise ValueError("--compensation integral extends a P/PD controller: give --controller "
                         "p or pd")
    if len(args.compensation) > 1 and args.csv:
        raise ValueError(f"--csv writes one record; --compensation {given_comp} makes "
                         f"{len(args.compensation)} (give one compensation with --csv)")
    if args.force and args.csv is None and args.figure is None and args.c_source is None:
        raise ValueError("--force has no effect without --csv, --figure or --c-source (it lets "
                         "them overwrite an existing file)")
    if args.model is not None:
        bad = [o for o, x in (("--link", args.link), ("--plant", args.plant)) if x]
        if bad:
            raise ValueError(f"{', '.join(bad)} has no effect with --model (the model is the plant)")
        if args.controller != "open" and args.reference is None:
            raise ValueError("--model needs --reference (in the model's position unit)")


def _controller(args, plant, kind: str = "rotary"):
    """The controller of ``args`` and the warnings of its design (a missed specification, a
    sampled loop off its continuous design: empty for given gains or the open loop)."""
    from ..controllers import open_loop, p_control, pd_control

    if args.controller == "open":
        return open_loop(parse_signal(args.torque, "torque", kind)), ()
    ref = parse_signal(args.reference or "step:0.5236", "position", kind)
    if args.kp is not None:
        kp, kd, design_warnings = args.kp, (args.kd if args.controller == "pd" else 0.0), ()
    else:
        if args.rise_time is None or args.damping is None:
            raise ValueError(f"--controller {args.controller} needs --rise-time and --damping (or --kp)")
        from ..design import design_p, design_pd

        d = (design_p(plant, rise_time=args.rise_time, damping=args.damping) if args.controller == "p"
             else design_pd(plant, rise_time=args.rise_time, damping=args.damping))
        kp, kd, design_warnings = d.kp, d.kd, d.warnings
    ctrl = p_control(kp, ref) if args.controller == "p" else pd_control(kp, kd, ref)
    return ctrl, design_warnings


def _compensator(name, args, scale, coulomb_pos, coulomb_neg, plant=None, ctrl=None):
    """The compensator ``name`` (one of :func:`compensations`); ``plant`` (the model or the
    paper's actuator) and ``ctrl`` (the controller: its gains) build the registry's others."""
    from ..compensators import CoulombCompensator, NoCompensation, make
    from ..compensators.nn_confirmed import network_compensator

    if name not in ("none", "coulomb", *_NETS):
        from ..design import LinearLoop

        loop = None
        if ctrl is not None and ctrl.kp > 0 and plant.sample_time is not None:
            inertia = getattr(plant, "total_inertia", None) or plant.inertia
            loop = LinearLoop(kp=ctrl.kp, kd=ctrl.kd, inertia=inertia, viscous=plant.viscous,
                              sample_time=plant.sample_time)
        options = _bristle(args, plant) if name == "lugre_observer" else {}
        try:
            return make(name, plant, loop, scale=scale, **options)
        except ValueError as exc:
            raise ValueError(f"--compensation {name}: {exc}") from None
    if name == "none":
        return NoCompensation()
    if name == "coulomb":
        if coulomb_pos <= 0.0 and coulomb_neg <= 0.0:
            raise ValueError("--compensation coulomb: the model has no Coulomb friction "
                             "(coulomb_pos = coulomb_neg = 0), so the compensation would add "
                             "nothing; use --compensation none or a model with its Coulomb level")
        return CoulombCompensator(coulomb_pos=coulomb_pos, coulomb_neg=coulomb_neg, scale=scale)
    from ..nn import load_net

    return network_compensator(load_net(args.net), "confirmed" if name == "nn_confirmed"
                               else "backward-difference", scale=scale, clip=args.clip)


def bristle_options(args, kind: str = "rotary") -> dict:
    """``sigma0`` / ``sigma1`` of the options ``--sigma0`` / ``--sigma1`` that were given, in the
    axis's units (a unit suffix accepted), checked: a finite stiffness > 0, a damping >= 0.
    Shared by ``fricctl simulate`` and ``fricctl compare``."""
    from .. import _validate as v
    from ..units import parse_quantity, units

    u = units(kind)
    out = {}
    for key, quantity in (("sigma0", "stiffness"), ("sigma1", "viscous")):
        text = getattr(args, key)
        if text is None:
            continue
        unit = u.stiffness if key == "sigma0" else u.viscous
        try:
            x = parse_quantity(str(text).strip(), quantity, kind)
        except ValueError as exc:
            raise ValueError(f"--{key}: {exc}") from None
        out[key] = v.real(f"--{key}", x, positive=key == "sigma0", nonneg=True, unit=unit)
    return out


def _bristle(args, plant) -> dict:
    """:func:`bristle_options` in the plant's units; a model without a LuGre law and no
    ``--sigma0`` is refused here, naming the option."""
    from ..compensators.base import friction_of
    from ..units import units

    kind = getattr(plant, "units", "rotary")
    u = units(kind)
    out = bristle_options(args, kind)
    if "sigma0" not in out and not friction_of(plant).lugre_sigma0 > 0.0:
        raise ValueError("--compensation lugre_observer: the model has no LuGre law (lugre_sigma0 = 0): "
                         f"give the bristle stiffness with --sigma0 [{u.stiffness}] (and its "
                         f"damping with --sigma1 [{u.viscous}])")
    return out


def _velocity_note(name: str, comp) -> list:
    """A warning when a network is run on another velocity than its pipeline's claims fed it
    (its file's ``metadata["pipeline"]``; :func:`fricctl.paper.network.pipeline_velocity`)."""
    if name not in _NETS:
        return []
    pipeline = comp.estimator.metadata.get("pipeline")
    if pipeline not in ("paper", "fricctl"):
        return []
    from ..paper.network import pipeline_velocity

    want = pipeline_velocity(pipeline)
    have = "confirmed" if name == "nn_confirmed" else "backward-difference"
    if want == have:
        return []
    other = "nn_confirmed" if want == "confirmed" else "nn"
    return [f"this network was trained by the {pipeline} pipeline, whose claims feed it the {want} "
            f"velocity; --compensation {name} feeds it the {have} one (--compensation {other} runs "
            "it as the claims did)"]


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


def _ss_window(res) -> float:
    """The stretch ``steady_state_error`` averages over: the last 0.5 s, or half a shorter
    run [s]."""
    return min(0.5, res.t[-1] / 2)


def _settling_warnings(res, kind: str) -> list[str]:
    """A closed-loop run that has not settled (:meth:`fricctl.simulate.SimResult.settled`) has no
    steady-state error: say how much it still moves, and over what."""
    from ..units import units as units_of

    if res.info.controller == "open loop" or res.settled(_ss_window(res)):
        return []
    w, u = _ss_window(res), units_of(kind).position
    last = res.t >= res.t[-1] - w + 1e-12
    tracking = bool(np.ptp(res.reference[last]) > 0)
    return [f"the run has not settled: over its last {w:g} s its error still moves up to "
            f"{res.error_spread(w):.4g} {u} about its mean, beyond the settling band "
            f"{res.settling_band():.4g} {u} (one encoder count, or 2 % of its largest error); "
            f"steady_state_error is the mean of an error still in motion, not a steady state: "
            + ("the reference still moves there (a tracking run)" if tracking else "run longer")]


def _envelope_warnings(res, comp, name: str, kind: str) -> list[str]:
    """Where a network compensation ran its net outside the net's training envelope: how far
    and how long (:func:`fricctl.nn.envelope.excursion`).  The net's inputs are the held motor
    torque Tm_k and the loop's velocity estimate omega_hat_k (``nn_confirmed`` passes it or 0)."""
    if name not in _NETS:
        return []
    from ..nn.envelope import excursion, excursion_warnings

    exc = excursion(comp.estimator, res.torque_motor, res.omega_hat, res.sample_time)
    return excursion_warnings(exc, kind, clipped=comp.clip)


def _errors(res, keys) -> dict:
    """The error values of a summary (null for an open-loop run: see :data:`NO_REFERENCE`)."""
    if res.info.controller == "open loop":
        return dict.fromkeys(keys)
    err = res.reference - res.q
    values = {"final_error": float(err[-1]),
              "steady_state_error": res.steady_state_error(_ss_window(res)),
              "tracking_error_rms": float(np.sqrt(np.mean(err ** 2))),
              "max_abs_error": float(np.max(np.abs(err)))}
    return {k: values[k] for k in keys}


def _figure(results, path, units, *, overwrite: bool) -> None:
    """Position (with the stuck intervals) over torques, titled with the controller, its
    gains and the compensation(s); both panels carry their time tick labels.  Several runs
    (one per compensation) are overlaid, each in its own colour, with their motor torques."""
    import matplotlib.pyplot as plt

    from .. import figures
    from ..units import units as units_of
    from ._output import save_figure

    fig, (a, b) = plt.subplots(2, 1, sharex=True, figsize=(7, 5), layout="constrained")
    unit = "deg" if units is None else "rad"
    if len(results) == 1:
        figures.plot_response(results[0], ax=a, unit=unit)
        figures.plot_stuck(results[0], ax=a)
        figures.plot_torques(results[0], ax=b)
    else:
        for i, res in enumerate(results):
            name, color = res.info.compensator, f"C{i}"
            figures.plot_response(res, ax=a, unit=unit, reference=i == 0, color=color,
                                  label=f"position q, {name}")
            # each run's stuck intervals as a strip along the bottom, one strip per run
            figures.plot_stuck(res, ax=a, color=color, alpha=0.5, label=f"stuck (ω = 0), {name}",
                               band=(0.035 * i, 0.035 * (i + 1)))
            b.plot(res.t, res.torque_motor, drawstyle="steps-post", color=color,
                   label=f"motor torque Tm, {name}")
        b.set_xlabel("time t [s]")
        b.set_ylabel("torque [N·m]")
        b.legend(loc="best", fontsize="small")
    if units is not None:  # the figures label a rotary joint; relabel for the model's units
        u = units_of(units)
        a.set_ylabel(f"position q [{u.position}]")
        b.set_ylabel(f"{'torque' if units == 'rotary' else 'force'} [{u.torque}]")
    a.tick_params(labelbottom=True)  # sharex hides the top panel's time labels
    fig.suptitle(_title(results, units or "rotary"), fontsize="medium")
    save_figure(fig, path, overwrite=overwrite)


def _title(results, kind: str) -> str:
    """``PD: Kp = 1.213 N*m/rad, Kd = 0.08922 N*m*s/rad; compensation Coulomb (s = 1)``
    (several compensations: ``compensation none, Coulomb, NN (s = 1)``)."""
    from ..units import units as units_of

    info, u = results[0].info, units_of(kind)
    gains = "" if info.controller == "open loop" else f": Kp = {info.kp:.4g} {u.stiffness}"
    if info.controller == "PD":
        gains += f", Kd = {info.kd:.4g} {u.viscous}"
    names = [r.info.compensator for r in results]
    scale = "" if names == ["none"] else f" (s = {info.compensation_scale:g})"
    return f"{info.controller}{gains}; compensation {', '.join(names)}{scale}"


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
        ctrl, design_warnings = _controller(args, model, model.units)
        comps = [_compensator(name, args, scale, fr.scale * fr.coulomb_pos,
                              fr.scale * fr.coulomb_neg, model, ctrl) for name in args.compensation]
        results = [simulate_model(model, ctrl, comp, duration=args.duration,
                                  friction=fr.scaled(args.friction_scale)) for comp in comps]
        units = model.units
    else:
        params = paper_actuator().with_link() if args.link else paper_actuator()
        ctrl, design_warnings = _controller(args, params)
        comps = [_compensator(name, args, scale, params.coulomb, params.coulomb, params, ctrl)
                 for name in args.compensation]
        results = [simulate(params, ctrl, comp, duration=args.duration, plant=args.plant or "rigid",
                            friction=params.friction_model().scaled(args.friction_scale))
                   for comp in comps]
        units = None
    period = _torque_period(args, ctrl)
    warns = [sampling_warnings(ctrl, res.sample_time) + _runaway_warnings(res, comp, period)
             + _velocity_note(name, comp) + _settling_warnings(res, units or "rotary")
             + _envelope_warnings(res, comp, name, units or "rotary")
             for res, comp, name in zip(results, comps, args.compensation)]
    summaries = [_summary(res, units or "rotary", comp) for res, comp in zip(results, comps)]
    if args.csv:
        res = results[0]
        Run(t=res.t, torque=res.torque_motor, position=res.q_meas, reference=res.reference,
            source="fricctl simulate" + (f" --model {Path(args.model).name}" if args.model else ""),
            units=units or "rotary").to_csv(args.csv, overwrite=args.force)
    if args.figure:
        _figure(results, args.figure, units, overwrite=args.force)
    if args.c_source and any(n in _NETS for n in args.compensation):
        from .._atomic import write_text
        from ..nn.c_export import c_header, c_source

        c = Path(args.c_source)  # the network's C (its header says how to confirm the velocity)
        net = next(x for n, x in zip(args.compensation, comps) if n in _NETS).estimator
        write_text(c, c_source(net, name=c.stem, units=units or "rotary"), overwrite=args.force)
        write_text(c.with_suffix(".h"), c_header(net, name=c.stem, units=units or "rotary"),
                   overwrite=args.force)
    elif args.c_source:
        from .._atomic import write_text
        from ..compensators.c_export import c_header, c_source, exportable

        c = Path(args.c_source)
        (comp,) = [x for n, x in zip(args.compensation, comps) if n in exportable()]
        write_text(c, c_source(comp, name=c.stem), overwrite=args.force)
        write_text(c.with_suffix(".h"), c_header(comp, name=c.stem), overwrite=args.force)
    several = len(results) > 1
    for name, texts in zip(args.compensation, warns):
        for text in texts:
            warnings.warn(f"--compensation {name}: {text}" if several else text, stacklevel=1)
    for summary, texts in zip(summaries, warns):
        # the design's own warnings are on stderr already (DesignWarning, once for all runs)
        summary["warnings"] = [*design_warnings, *texts]
    if args.json:
        # one compensation: its summary, as before; several: one entry per compensation
        out = {"runs": summaries} if several else summaries[0]
        print(json_text(out, reasons=_no_reference(out)))
    else:
        print("\n\n".join(_summary_text(x) for x in summaries))
    return 0


def _no_reference(out: dict) -> dict:
    """Why each null error value of a summary (or of each of its ``runs``) is undefined."""
    entries = ({f"runs[{i}].": x for i, x in enumerate(out["runs"])} if "runs" in out
               else {"": out})
    return {**{f"{where}{k}.value": NO_REFERENCE for where, x in entries.items()
               for k, q in x.items() if isinstance(q, dict) and q["value"] is None},
            **{f"{where}{k}": NO_REFERENCE for where, x in entries.items()
               for k, q in x.items() if q is None}}


def _torque_period(args, ctrl) -> float | None:
    """The period [s] of an open-loop ``--torque sinusoid:A,FREQ`` (None for any other run):
    under it a joint that follows its control torque reverses every period."""
    if args.controller != "open" or args.torque.partition(":")[0] != "sinusoid":
        return None
    return 1.0 / ctrl.feedforward.frequency


#: The first words of a failed runaway check's warning, by the check's name (``{torque}``: the
#: word for the axis, torque or force).
_RUNAWAY = {"wind-up": "the compensated joint winds its {torque} up",
            "divergence": "the compensated loop runs away",
            "reversal": "the compensated joint runs away under the sinusoidal torque"}


def _runaway_warnings(res, comp, period: float | None = None) -> list[str]:
    """The runaway checks of a compensated run (:mod:`fricctl.paper.runaway`), as warnings.

    The torque check the compensator asks for (:func:`~fricctl.paper.runaway.torque_check`:
    the wind-up bound for a friction estimate, the divergence check for a disturbance observer
    or integral action, which may exceed that bound in a transient that dies out), and under an
    open-loop sinusoidal torque of ``period`` [s] the reversal check (from its second full
    period on).  A run too short for a check is said so, not judged: one that cannot hold the
    check at all (a ValueError), or whose record cannot tell what the check asks (its
    ``judged`` False and ``passed``: a first excess that begins too late in the run to say
    whether it dies out) -- never a runaway the record does not show."""
    if res.info.compensator == "none":
        return []
    from ..paper.runaway import reversal, torque_check

    out = []
    checks = [("torque", lambda: torque_check(res, comp))]
    if period is not None and res.t[-1] + res.sample_time >= 2 * period:
        checks.append(("reversal", lambda: reversal(res, period)))
    for what, check in checks:
        try:
            c = check()
        except ValueError as exc:
            out.append(f"the {what} runaway check cannot judge this run: {exc}")
            continue
        if not c.passed:
            torque = "torque" if res.info.units == "rotary" else "force"
            out.append(f"{_RUNAWAY[c.name].format(torque=torque)}: {c.reason}")
        elif not c.judged:
            out.append(f"the {what} runaway check cannot judge this run: {c.reason}")
    return out


#: Keys of the summary, in order: the same for the paper's actuator and a model file
#: (each quantity ``{value, unit}`` in the plant's units; see :func:`_summary`).
SUMMARY_KEYS = ("controller", "kp", "kd", "compensator", "compensation_scale", "units",
                "final_error", "steady_state_error", "settled", "tracking_error_rms",
                "max_abs_error",
                "max_abs_position", "max_abs_torque", "stuck_intervals", "stuck_at_end")


def _summary(res, kind: str, comp) -> dict:
    """The summary of one run: :data:`SUMMARY_KEYS`, each quantity as ``{value, unit}``
    (:func:`fricctl.units.quantity`) in the units of a ``kind`` axis, whatever the plant; a
    Coulomb compensation adds its levels per direction (before its scale)."""
    from ..compensators import CoulombCompensator
    from ..units import quantity, units as units_of

    u = units_of(kind)
    errors = _errors(res, ("final_error", "steady_state_error", "tracking_error_rms",
                           "max_abs_error"))
    out = {"controller": res.info.controller,
           "kp": quantity(res.info.kp, u.stiffness), "kd": quantity(res.info.kd, u.viscous),
           "compensator": res.info.compensator,
           "compensation_scale": quantity(res.info.compensation_scale, "-"),
           "units": kind,
           **{k: quantity(x, u.position) for k, x in errors.items()},
           # whether steady_state_error is one (null for an open-loop run: no reference)
           "settled": (None if res.info.controller == "open loop"
                       else bool(res.settled(_ss_window(res)))),
           "max_abs_position": quantity(float(np.max(np.abs(res.q))), u.position),
           "max_abs_torque": quantity(float(np.max(np.abs(res.torque_motor))), u.torque),
           "stuck_intervals": len(res.stuck_intervals()), "stuck_at_end": bool(res.stuck[-1])}
    if isinstance(comp, CoulombCompensator):
        out["coulomb_compensation_pos"] = quantity(float(comp.coulomb_pos), u.torque)
        out["coulomb_compensation_neg"] = quantity(float(comp.coulomb_neg), u.torque)
    # the keys in their documented order (settled sits after steady_state_error)
    return {k: out[k] for k in (*SUMMARY_KEYS, *(k for k in out if k not in SUMMARY_KEYS))}


def _summary_text(summary: dict) -> str:
    """The summary as aligned lines ``key value unit``; an angle also in degrees (a reader
    of a joint thinks in degrees, the JSON and the computation stay in radians)."""
    lines = []
    for k, x in summary.items():
        if k == "warnings":
            continue
        if x is None:
            lines.append(f"{k:26s} - ({NO_REFERENCE})")
            continue
        if not isinstance(x, dict):
            lines.append(f"{k:26s} {x:.6g}" if isinstance(x, float) else f"{k:26s} {x}")
            continue
        v, unit = x["value"], x["unit"]
        if v is None:
            lines.append(f"{k:26s} - ({NO_REFERENCE})")
            continue
        text = f"{k:26s} {v:.6g} {'' if unit == '-' else unit}".rstrip()
        if unit == "rad":
            text += f" ({math.degrees(v):.6g} deg)"
        if k == "steady_state_error" and summary["settled"] is False:
            text += " -- not settled: the mean of an error still in motion (see the warning)"
        lines.append(text)
    return "\n".join(lines)
