"""Friction patterns: the one type (:class:`FrictionPatterns`), patterns from records
(:func:`record_patterns`) and their CSV file (:func:`write_patterns`, :func:`read_patterns`).

:class:`FrictionPatterns` is what every part of fricctl that makes or uses patterns
hands over: records (here), noise-free patterns of a known law
(:func:`fricctl.nn.smooth_friction_patterns`), the virtual bench
(:class:`fricctl.bench.experiments.BenchPatterns`, which adds the simulator's truth) and
the pipelines that train the compensating network (:mod:`fricctl.nn.pipelines`).

Patterns file layout::

    # units: linear
    # columns: tm [N], omega [m/s], friction [N], at_rest [0/1]
    # velocity_quantum: 5e-05
    # source: DATA_EMPS.mat
    tm,omega,friction,at_rest
    89.23,0.0012,88.1,0
    ...

The header names ``tm,omega,friction`` (any order) and optionally ``at_rest``;
``# units:`` (default rotary) and ``# velocity_quantum:`` are checked, other
``#`` lines are kept as metadata.  Today's three-column files read unchanged.
"""

from __future__ import annotations

import types
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping

import numpy as np

from .. import _validate as v
from .._atomic import atomic_write
from ..estimation import at_rest, estimate
from ..units import KINDS, units as units_of
from .run import Run
from .table import Table, read_columns

__all__ = ["PATTERN_COLUMNS", "FrictionPatterns", "record_patterns", "write_patterns",
           "PatternTable", "read_patterns"]

#: Columns of a training-patterns file (``fricctl train``): motor torque [N*m],
#: velocity [rad/s] and friction torque [N*m], load side ([N], [m/s], [N] on a linear
#: axis); an ``at_rest`` column (0/1) may follow.
PATTERN_COLUMNS = ("tm", "omega", "friction")


@dataclass(frozen=True, kw_only=True, eq=False)
class FrictionPatterns:
    """Friction patterns ``(Tm, omega) -> Tat`` and what a pipeline must know of their records
    (load side).

    The arrays are checked (real, finite, one value per pattern, at least 2 patterns) and
    kept as read-only copies.
    """

    tm: np.ndarray = field(metadata={"unit": "N*m or N"})
    """Motor torque (force) of each pattern [N*m] or [N]."""
    omega: np.ndarray = field(metadata={"unit": "rad/s or m/s"})
    """Velocity estimate [rad/s] or [m/s] (exact for noise-free or true patterns)."""
    friction: np.ndarray = field(metadata={"unit": "N*m or N"})
    """Friction torque (force) ``Tat = Tm - I*alpha_hat`` [N*m] or [N]."""
    at_rest: np.ndarray
    """True where the joint was at rest: the encoder stood still over ``guard`` samples
    either side of the pattern (:func:`fricctl.estimation.at_rest`); a pattern with
    ``omega = 0`` that is not at rest is a breakaway transient (``Tat = Tm`` is wrong there)."""
    units: str = "rotary"
    """``"rotary"`` or ``"linear"``."""
    velocity_quantum: float | None = field(default=None, metadata={"unit": "rad/s or m/s"})
    """One encoder count per controller sample, resolution/Ts [rad/s] or [m/s] (the fricctl
    pipeline's velocity scale); None when unknown."""
    meta: Mapping[str, str] = field(default_factory=dict)
    """Other ``# key: value`` lines of the file (source, estimator, inertia, ...)."""

    def __post_init__(self):
        tm = v.array("tm", self.tm, min_size=2)
        cols = {"tm": tm, "omega": v.array("omega", self.omega, size=tm.size),
                "friction": v.array("friction", self.friction, size=tm.size)}
        rest = np.asarray(self.at_rest)
        if rest.dtype != np.bool_ or rest.shape != tm.shape:
            raise ValueError(f"at_rest must be a boolean array of {tm.size} patterns")
        cols["at_rest"] = rest
        for name, x in cols.items():
            x = np.array(x)
            x.setflags(write=False)
            object.__setattr__(self, name, x)
        v.choice("units", self.units, KINDS)
        if self.velocity_quantum is not None:
            object.__setattr__(self, "velocity_quantum", v.real(
                "velocity_quantum", self.velocity_quantum, positive=True))
        meta = {}
        for key, value in dict(self.meta).items():
            v.text("meta key", key, empty=False)
            v.text(f"meta[{key!r}]", value)
            if key in _PATTERN_META or any(c in key for c in ":\n#") or "\n" in value:
                raise ValueError(f"meta: {key!r} cannot be a free '# key: value' line")
            meta[key] = value
        object.__setattr__(self, "meta", types.MappingProxyType(meta))

    def __len__(self):
        return self.tm.size


#: Metadata lines of a patterns file that :func:`read_patterns` checks and returns as fields.
_PATTERN_META = ("units", "velocity_quantum")


def record_patterns(runs, *, inertia: float, estimator: str = "polynomial_segments",
                    estimator_options: dict | None = None, border: int = 5, guard: int = 2,
                    velocity_quantum: float | None = None) -> FrictionPatterns:
    """The paper's friction patterns from measured records: ``Tat = Tm - I*alpha_hat``.

    Parameters
    ----------
    runs : Run or sequence of Run
        Records of one axis (same ``units``).
    inertia : float
        I of the patterns, from the model [kg*m^2] or [kg].
    estimator : str
        Name in :data:`fricctl.estimation.ESTIMATORS` (the paper: polynomial segments).
    estimator_options : dict, optional
        Its keyword options.
    border : int
        Samples dropped at each end of each record (estimator end effects) [samples].
    guard : int
        Samples each side over which the encoder must stand still for a pattern to be
        at rest (:func:`fricctl.estimation.at_rest`) [samples].
    velocity_quantum : float, optional
        One encoder count per controller sample [rad/s] or [m/s], passed through.

    Notes
    -----
    At rest the friction is the reaction that holds the joint, ``Tat = Tm``; a
    pattern whose velocity estimate is 0 but whose encoder moves within ``guard``
    samples is a breakaway, where ``Tm`` is not the friction: ``at_rest`` tells the
    two apart, and a pipeline decides what to keep.  A record that never stands
    still (EMPS) has no ``at_rest`` pattern: nothing in it says what the friction
    does below breakaway.

    Examples
    --------
    >>> t = np.arange(400) * 0.002
    >>> run = Run(t=t, torque=0.5 * np.ones(400), position=t ** 2)   # a = 2: I*a = 0.5
    >>> p = record_patterns(run, inertia=0.25, estimator="savitzky_golay")
    >>> bool(np.allclose(p.friction, 0.0, atol=1e-9)), int(p.at_rest.sum())
    (True, 0)
    """
    if isinstance(runs, Run):
        runs = [runs]
    elif isinstance(runs, (list, tuple)):
        runs = list(runs)
    else:
        raise ValueError(f"runs must be a Run or a list of Run, got {type(runs).__name__}")
    if not runs:
        raise ValueError("runs: no record given")
    for i, r in enumerate(runs):
        v.instance(f"runs[{i}]", r, Run, "a fricctl.datasets.Run")
    kinds = sorted({r.units for r in runs})
    if len(kinds) > 1:
        raise ValueError(f"runs: records of one axis share their units, got {', '.join(kinds)}")
    inertia = v.real("inertia", inertia, positive=True)
    border = v.integer("border", border, low=0)
    guard = v.integer("guard", guard, low=1)
    cols = {"tm": [], "omega": [], "friction": [], "at_rest": []}
    for r in runs:
        if 2 * border >= r.n_samples - 2:
            raise ValueError(f"border: {border} leaves too few of the {r.n_samples} samples "
                             f"of {r.source or 'a record'}")
        est = estimate(r.t, r.position, estimator, **(estimator_options or {}))
        sl = slice(border, r.n_samples - border)
        cols["tm"].append(r.torque[sl])
        cols["omega"].append(est.velocity[sl])
        cols["friction"].append(r.torque[sl] - inertia * est.acceleration[sl])
        cols["at_rest"].append(at_rest(r.position, guard=guard)[sl])
    return FrictionPatterns(**{k: np.concatenate(c) for k, c in cols.items()}, units=kinds[0],
                            velocity_quantum=velocity_quantum)


def write_patterns(path, patterns: FrictionPatterns, *, overwrite: bool = True) -> Path:
    """Write patterns as CSV: ``# key: value`` lines, header ``tm,omega,friction,at_rest``.

    Numbers are written with 17 significant digits (exact round trip);
    ``at_rest`` as 0/1.  Returns the path.

    Parameters
    ----------
    path : str or os.PathLike
        Destination.
    patterns : FrictionPatterns
    overwrite : bool
        False: refuse (:class:`FileExistsError`) when ``path`` exists, also when another
        process creates it while this one writes (the file is written atomically:
        :mod:`fricctl._atomic`).
    """
    v.instance("patterns", patterns, FrictionPatterns)
    path = Path(path)
    if not v.flag("overwrite", overwrite) and path.exists():
        raise FileExistsError(17, "already exists (not overwritten)", str(path))
    u = units_of(patterns.units)
    lines = [f"# units: {patterns.units}",
             f"# columns: tm [{u.torque}], omega [{u.velocity}], friction [{u.torque}], "
             f"at_rest [0/1]"]
    if patterns.velocity_quantum is not None:
        lines.append(f"# velocity_quantum: {patterns.velocity_quantum!r}")
    lines += [f"# {k}: {x}" for k, x in patterns.meta.items() if k != "columns"]
    data = np.column_stack([patterns.tm, patterns.omega, patterns.friction])
    with atomic_write(path, overwrite=overwrite, newline="") as fh:
        fh.write("\n".join(lines) + "\ntm,omega,friction,at_rest\n")
        for row, rest in zip(data, patterns.at_rest):
            fh.write(",".join(format(x, ".17g") for x in row) + (",1\n" if rest else ",0\n"))
    return path


@dataclass(frozen=True, kw_only=True, eq=False)
class PatternTable(Table):
    """A patterns file as read by :func:`read_patterns`: the columns and the checked metadata."""

    patterns: FrictionPatterns
    """The patterns (``at_rest`` all False when the file has no such column)."""
    has_at_rest: bool
    """Whether the file has the ``at_rest`` column (today's 3-column files do not)."""


def read_patterns(path) -> PatternTable:
    """Training patterns of the friction network from a CSV file (``fricctl train``).

    The header names :data:`PATTERN_COLUMNS` (``tm,omega,friction``, any order)
    and optionally ``at_rest`` (0 or 1); at least 2 rows.  The ``# units:`` line
    (``rotary``, the default, or ``linear``) and ``# velocity_quantum:`` (> 0) are
    checked; other ``#`` lines are kept in ``meta``.  Errors as :func:`read_columns`; a
    folder or a missing file is named as the patterns file expected ("a folder, not a
    patterns file", "no such patterns file"), as a model or network file is.
    """
    path = Path(path)
    if path.is_dir():  # "not a CSV file": which of the command's files was meant?
        raise IsADirectoryError(21, "a folder, not a patterns file", str(path))
    if not path.is_file():
        raise FileNotFoundError(2, "no such patterns file", str(path))
    table = read_columns(path, required=PATTERN_COLUMNS, optional=("at_rest",), min_rows=2)
    meta = dict(table.meta)
    try:
        units = meta.pop("units", "rotary")
        if units not in KINDS:
            raise ValueError(f"# units: must be one of {', '.join(KINDS)}, got {units!r}")
        quantum = meta.pop("velocity_quantum", None)
        if quantum is not None:
            quantum = v.number_text("# velocity_quantum", quantum, finite=False)
            quantum = v.real("# velocity_quantum", quantum, positive=True)
        rest = table.columns.get("at_rest")
        if rest is not None and not np.all((rest == 0) | (rest == 1)):
            row = int(np.flatnonzero((rest != 0) & (rest != 1))[0])
            raise ValueError(f"column 'at_rest' must hold 0 or 1, got {float(rest[row])!r} in data "
                             f"row {row + 1}")
        meta.pop("columns", None)
        pats = FrictionPatterns(tm=table["tm"], omega=table["omega"], friction=table["friction"],
                                at_rest=np.zeros(table.n_rows, bool) if rest is None else rest == 1,
                                units=units, velocity_quantum=quantum, meta=meta)
    except ValueError as exc:
        raise ValueError(f"{table.path}: {exc}") from None
    return PatternTable(path=table.path, columns=table.columns, meta=table.meta,
                        patterns=pats, has_at_rest=rest is not None)
