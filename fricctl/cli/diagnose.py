"""``fricctl diagnose RUN.csv``: what the model gets wrong, its cause, the extended model, the gain.

Reads a record (CSV header ``t,torque,position[,reference]``, SI units, uniform
sampling, any rate; see :class:`fricctl.datasets.Run`; or a ``.mat`` file in the
EMPS layout, a linear axis), fits the rigid baseline (or takes ``--model FILE``, a
``fricctl.joint_model`` JSON file: its units, sample time and encoder count must agree
with the record's; the effects a cause can judge -- its offset, asymmetric levels,
Stribeck excess -- are removed and named again only where the record supports them,
so that a model's own claims do not decide the causes; the model's other values are trusted,
so the causes can differ from a diagnosis without it where the record's own fit is biased),
re-simulates it over 0.5 s windows, names every cause the record supports one
step at a time by blocked cross-validation (or ``none``), extends the model and
reports the held-out gain and the verdict: is the record explained?  ``--json`` prints one
object (finite numbers or null): ``explained`` (the final model's held-out torque residual
at most twice the measuring chain's floor, not far below it, and no caution),
``residual_over_floor``, ``verdict`` (``caution``: where fricctl identify's rigid fit
re-simulates the record better than the extended model, the causes named may stand in for a
bias of the least-squares fit; ``p_value`` of the variance-ratio test, ``dof``, ``dependence``: the share of the final
residual's variance its bin means against position, velocity, time and torque carry,
``strongest``, ``other_shape_share``: on a record above twice the floor, the held-out share of that
residual a friction law of another shape removes -- a generic odd function of the velocity,
not a cause of the list; gross of the measuring chain's share, a hint), ``cause`` (the first named), ``causes`` (all, in order; ``["none"]``), ``steps``
(per named cause: ``score`` net of the measuring chain's share, ``gross``,
``chain``, held-out torque and simulation RMS before and after, ``ranking`` of its
candidates; a step that settled a load dependence's column scores the settled model, so its
``score`` may exceed its own entry in ``ranking``; ``passed_over``: ``[{cause, gross}]`` of
candidates with no net share that removed more gross, for which the named cause may stand
in), ``ranking`` (``[{cause, score}]`` of the first step; a null ``score``: the
candidate's measuring-chain share could not be measured, the reason in ``undefined``),
``last_ranking`` (the step that named nothing), ``not_identifiable`` (cause -> why it
cannot be told on this record, or "tried, rejected: ..." when its extended model
re-simulates the held-out windows worse), ``evidence``, ``baseline`` (``fricctl identify``'s fit of the record,
``--no-offset --no-validation``, or the given model) and ``extended``
(parameter dicts), ``gain`` (``torque_rms_before``, ``torque_rms_after``,
``simulation_rms_before``, ``simulation_rms_after``, ...), all on held-out data,
``chain_rms``, ``cutoff`` and ``end_stops`` (the end stops the record hits: ``positions``,
``impacts``, ``excluded_samples``, ``description``; their contacts are left out of the fit,
the re-simulation windows, the floor and the verdict, and the text says so); with
``--model``, ``held_by_model`` (the causes whose effect the model held, removed to be
judged), ``origin`` (per named cause: "found" or "held by the supplied model") and
``supplied`` (the model's parameters); ``below_line``: the candidates below the naming line
that lower the held-out residual, supported first, each with ``score`` (net of
the measuring chain's share; gross where ``chain`` is null), ``gross``, ``chain``,
``p_value`` of the verdict's variance-ratio F test of the reduction (``dof`` effective
degrees of freedom before, ``dof_after`` after), ``supported`` (the test at p < 0.01 and the checks a named cause
passes), ``plausible``, ``reason``, ``parameters`` (what its fitted term sets: a ripple's
period and amplitude ...), ``evidence``, ``simulation_score`` and ``motor_revolutions`` (a
period over ``motor_revolution``, the travel of one motor revolution given by
``--motor-revolution``; EMPS: the screw's lead, 0.0025 m, which ``fricctl.datasets.emps``
attaches and a .mat or CSV file does not carry: give it).  The supported entries come in the
order a selection below the line takes them, each tested on what those before it leave.
A linear axis:
``# units: linear`` in the file or ``--units linear``.
``undefined`` gives the reason for every null number.
``--report DIR`` writes the figures (PNG: residuals, simulation, spectrum, steps),
``report.md`` and ``extended_model.json`` (a model file, version 2: provenance
"diagnosed" on every value the diagnosis added or changed; ``fricctl design
--model`` and ``fricctl simulate --model`` read it); existing files are not
overwritten without ``--force``.  A new DIR is built beside and renamed into place when
complete (an interrupted run leaves no DIR); with ``--force`` an existing DIR is replaced as a
whole: the new report is built in a folder beside it (the other files of DIR linked into it)
and swapped with it when complete, so an interrupted or failed run leaves the old report as it
was, never new files beside old figures (a DIR that holds the working folder is refused);
into an existing DIR without ``--force`` (none of the report's files there) each file is
written atomically.  With two cores or more the figures are drawn by two processes forked before the
diagnosis starts, which import matplotlib while it runs, once its baseline's fit has ended
(the same files; one core: drawn by the command itself).  A record longer than 500 000 samples is refused, counted before it is read
(7.0 kB per sample measured at the limit, a 4 GB budget); a progress bar shows on stderr when it is a
terminal.
Bad input prints one line on stderr and exits with code 2.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "diagnose", help="name what the model gets wrong in a record, extend it, measure the gain",
        description=__doc__.split("\n\n", 1)[1],
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("run", metavar="RUN", help="record: CSV with header "
                   "t,torque,position[,reference], or a .mat file in the EMPS layout")
    p.add_argument("--model", metavar="FILE", default=None,
                   help="nominal model (fricctl.joint_model JSON) to diagnose as given")
    p.add_argument("--units", choices=("rotary", "linear"), default=None,
                   help="override the record's '# units:' line")
    p.add_argument("--window", type=float, default=0.5, metavar="S",
                   help="re-simulation window [s] (default 0.5)")
    p.add_argument("--motor-revolution", type=float, default=None, metavar="L",
                   help="travel of one motor revolution in the record's position unit "
                        "(rad or m; the transmission: 2*pi/n for a gear ratio n, a screw's "
                        "lead): a period in position is then also given in motor revolutions")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--report", metavar="DIR", default=None,
                   help="write figures, report.md and extended_model.json to DIR (made if "
                        "missing; the folder it goes into must exist)")
    p.add_argument("--force", action="store_true",
                   help="replace the report in an existing --report DIR as a whole (its other "
                        "files are kept)")
    p.set_defaults(func=run)


#: The files ``--report DIR`` writes.
REPORT_FILES = ("residuals.png", "simulation.png", "spectrum.png", "steps.png", "report.md",
                "extended_model.json")


def run(args) -> int:
    from ..datasets import load_record
    from ..diagnose import MAX_SAMPLES, diagnose
    from ..plant import JointModel
    from ._output import check_new_folder, check_outputs, check_replaceable_folder
    from ._painters import forked_painters

    if args.report is not None:
        out = Path(args.report)
        if out.exists() and not out.is_dir():
            raise ValueError(f"--report: {out} exists and is not a folder")
        if out.is_dir():  # a new folder is made by write_report: nothing in it to clobber
            check_outputs({f"--report ({name})": out / name for name in REPORT_FILES},
                          [args.run, args.model], force=args.force)
            if args.force:  # replaced as a whole by a folder built beside it
                check_replaceable_folder("--report", out, "with --force")
                check_new_folder("--report", out)
        else:  # built beside, then renamed into place: its folder must exist and be writable
            _check_parent(out)
            check_new_folder("--report", out)
    if args.motor_revolution is not None:  # checked before the record is read
        from .. import _validate as v

        v.real("--motor-revolution", args.motor_revolution, positive=True)
    record = load_record(args.run, units=args.units, max_samples=MAX_SAMPLES)  # counted first
    model = JointModel.load(args.model) if args.model else None
    if model is not None:
        check_model(model, record, Path(args.model).name, units_given=args.units is not None)
    # the report's painters are forked now, before the diagnosis starts its thread, and import
    # matplotlib once that thread has ended (fricctl.cli._painters; None: drawn here, serially)
    with forked_painters(PAINTER_SHARES, draw_figures, prepare_figures,
                         wanted=args.report is not None) as painters:
        result = diagnose(record, model, window=args.window,
                          on_baseline=None if painters is None else painters.start,
                          motor_revolution=args.motor_revolution)
        if args.report:
            write_report(result, args.report, overwrite=args.force, painters=painters)
    if args.json:
        print(json.dumps(result.as_dict(), indent=2, allow_nan=False))
    else:
        print(f"{record.source}: {record.n_samples} samples at {record.sample_time:g} s")
        print(result.report())
    return 0


def check_model(model, record, name: str, *, units_given: bool = False) -> None:
    """Refuse a model file whose units (unless ``--units`` is given), sample time or encoder
    count disagree with the record (:func:`fricctl.diagnose.api.check_model_agrees`)."""
    from ..diagnose.api import check_model_agrees

    if not units_given and model.units != record.units:
        raise ValueError(f"{name}: model units {model.units!r} differ from the record's "
                         f"{record.units!r}")
    check_model_agrees(model, record, name)


def _margins(fig, *, rows: int = 1, cols: int = 1, left: float = 1.0, right: float = 0.25,
             top: float = 0.3, bottom: float = 0.6, gap_w: float = 1.15, gap_h: float = 0.75):
    """``fig`` with fixed margins and gaps between its ``rows`` x ``cols`` panels [in]: room
    for an axis label and tick labels of eight characters at the default font.  Constrained
    layout measured every tick label twice more, 40 % of the report's drawing time (1.2 of
    3.1 s CPU on a 40 s, 1 kHz record)."""
    w, h = fig.get_size_inches()
    aw = (w - left - right - (cols - 1) * gap_w) / cols
    ah = (h - top - bottom - (rows - 1) * gap_h) / rows
    fig.subplots_adjust(left=left / w, right=1 - right / w, bottom=bottom / h, top=1 - top / h,
                        wspace=gap_w / aw, hspace=gap_h / ah)
    return fig


def _residuals(result):
    from matplotlib.figure import Figure  # not pyplot: a figure saved, never shown

    from ..figures.diagnosis import plot_diagnosis

    return plot_diagnosis(result, fig=_margins(Figure(figsize=(11, 8.5)), rows=3, cols=2, top=0.5))


def _simulation(result):
    from matplotlib.figure import Figure

    from ..figures.diagnosis import plot_simulation

    fig = _margins(Figure(figsize=(8, 5)), rows=2, cols=1, gap_h=0.55)
    ax = fig.subplots(2, 1, sharex=True)
    plot_simulation(result, ax=ax[0], quantity="position")
    plot_simulation(result, ax=ax[1], quantity="velocity")
    return fig


def _spectrum(result):
    from matplotlib.figure import Figure

    from ..figures.diagnosis import plot_residual_spectrum

    fig = _margins(Figure(figsize=(6.4, 3.6)))
    plot_residual_spectrum(result, ax=fig.subplots())
    return fig


def _steps(result):
    from matplotlib.figure import Figure

    from ..figures.diagnosis import plot_steps

    fig = _margins(Figure(figsize=(6.4, 3.6)), bottom=1.05)
    plot_steps(result, ax=fig.subplots())
    return fig


#: The report's figures: file name -> the function that draws it from a diagnosis.
FIGURES = {"residuals.png": _residuals, "simulation.png": _simulation, "spectrum.png": _spectrum,
           "steps.png": _steps}


#: The figures each forked painter draws (:mod:`fricctl.cli._painters`).  Two shares because
#: the machine of the target (issue 21) has two cores; the split balances the measured times
#: (r40, load 4, wall, each drawn and saved: residuals 1.4 s; simulation, spectrum and steps
#: 0.45 + 0.6 + 0.2 s).
PAINTER_SHARES = (("residuals.png",), ("simulation.png", "spectrum.png", "steps.png"))


def prepare_figures() -> None:
    """What a painter does while the diagnosis runs: import what drawing the report imports
    (matplotlib's figure, never pyplot) and draw a small figure with a legend, mathtext and a
    PNG of the report's settings, thrown away: the first figure a process draws loads the
    fonts, builds the mathtext parser and imports PIL (0.25-0.4 s CPU), which its first figure
    of the report then does not wait for (r40: residuals 1.14-1.28 -> 0.72-1.00 s CPU, the
    other three 0.88-1.07 -> 0.49-0.81 s).  Caches of pure functions only: the report's
    bytes are the same (checked on the seven records of ``bench_diagnose.py records``)."""
    import io

    from matplotlib.figure import Figure

    from ..figures import diagnosis  # noqa: F401

    fig = Figure(figsize=(2, 1.5))
    ax = fig.subplots()
    ax.plot([0, 1], [0, 1], drawstyle="steps-post", label="a")
    ax.legend()
    ax.set_xlabel(r"velocity $\omega$ [rad/s]")
    ax.set_title("t")
    fig.savefig(io.BytesIO(), format="png", dpi=110, pil_kwargs={"compress_level": 1})


def draw_figures(result, names, folder: Path, *, overwrite: bool) -> None:
    """The figures ``names`` (keys of :data:`FIGURES`) of ``result`` drawn and saved into
    ``folder``, one at a time (:func:`~fricctl.cli._output.save_figure`: atomically)."""
    from ._output import save_figure

    for name in names:
        save_figure(FIGURES[name](result), folder / name, overwrite=overwrite)


def _check_parent(out: Path) -> None:
    """Refuse a report folder whose own folder is missing, as every other output is refused
    (``--report nodir/rep`` made ``nodir`` too: a typo in a path became a new tree)."""
    if not out.is_dir() and not Path(out.absolute()).parent.is_dir():
        raise ValueError(f"--report: the folder {out.parent} does not exist")


def write_report(result, folder, *, overwrite: bool = True, painters=None) -> Path:
    """Figures (PNG), ``report.md`` and ``extended_model.json`` into ``folder``.

    A new folder is built beside and renamed into place when complete (the folder it goes
    into must exist: it is not made, as no other output's folder is).  An existing folder,
    ``overwrite=True``: the new report is built in a folder beside it and replaces it as a
    whole when complete (:func:`~fricctl._atomic.replace_folder`; the folder's other files
    are kept): a failure or an interrupt before leaves the old report as it was, never new
    files beside old figures.  ``overwrite=False``: each file is written into it atomically,
    an existing file refused (also one another run writes meanwhile).  See
    :mod:`fricctl._atomic`.  ``painters``
    (:class:`fricctl.cli._painters.Painters`): the figures are drawn by those processes while
    this one writes the rest (the same bytes); None: drawn here, one after another.
    """
    from dataclasses import replace

    from .._atomic import atomic_folder, replace_folder, write_text

    out = Path(folder)
    if out.exists() and not out.is_dir():
        raise ValueError(f"--report: {out} exists and is not a folder")
    _check_parent(out)  # the caller checked the files (check_outputs)
    text = result.report() + "\n## Figures\n\n" + "\n".join(
        f"![{n[:-4]}]({n})" for n in FIGURES) + "\n"
    # an existing report replaced: built whole beside it, then swapped in (a run cut short
    # left a new report.md and extended_model.json beside the old figures)
    replaced = overwrite and out.is_dir()
    with (replace_folder(out, overwrite=True) if replaced else atomic_folder(out)) as where:
        if painters is None:
            draw_figures(result, FIGURES, where, overwrite=overwrite)
        try:
            if painters is not None:
                # the models left out: the figures do not read them (a JointModel does not pickle)
                drawn = replace(result, baseline=None, extended=None, supplied=None, fit=None)
                painters.draw(drawn, where, overwrite=overwrite)
            write_text(where / "report.md", text, overwrite=overwrite)
            result.extended.save(where / "extended_model.json", overwrite=overwrite)
            if painters is not None:
                painters.wait()  # raises a painter's error (the folder removed, as serially)
        except BaseException:  # an error, Ctrl-C: the painters still drawing are ended and
            if painters is not None:  # reaped before the folder is removed
                painters.stop()
            raise
    return out
