"""Measured records (:class:`Run`), their CSV form, the one CSV reader, and the EMPS loader.

A :class:`Run` is what a test bench hands over: a uniform time vector, the applied
torque (or force, for a linear axis), the measured position and, optionally, the
reference.  Everything else in fricctl that consumes measurements (estimation,
identification, diagnosis, the CLI) takes a ``Run``.

CSV layout (what :meth:`Run.to_csv` writes and :meth:`Run.from_csv` reads)::

    # source: EMPS DATA_EMPS.mat
    # units: linear
    t,torque,position,reference
    0.0,89.23,7.45e-06,1.07e-04
    ...

Lines starting with ``#`` before the header carry metadata (``source``, ``units``);
the header must name ``t``, ``torque`` and ``position`` and may name ``reference``;
any other column is an error.  For a linear axis (``units="linear"``) the
``torque`` column holds a force [N] and ``position`` a displacement [m].

Every CSV file fricctl reads goes through :func:`read_columns` (columns named by
a header, in any order): records (:meth:`Run.from_csv`) and the network's
training patterns (:func:`read_patterns`, header ``tm,omega,friction``).  Its
errors name the file, the line and the column.

The EMPS data (Janot, Gautier & Brunot 2019) are *not* shipped: :func:`emps`
loads them from a folder given as argument or by the ``FRICCTL_DATA``
environment variable (the folder that holds ``emps/DATA_EMPS.mat``).
"""

from __future__ import annotations

import csv
import math
import os
import types
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping

import numpy as np

from . import _validate as v
from .units import KINDS, units as units_of

__all__ = [
    "Run",
    "EmpsData",
    "emps",
    "Table",
    "read_columns",
    "read_patterns",
    "PATTERN_COLUMNS",
    "MIN_SAMPLES",
    "EMPS_SOURCE_HINT",
]

#: Fewest samples a record may have: a 6th-order polynomial fit and the
#: four-parameter inverse model both need well over this many.
MIN_SAMPLES = 10

#: Relative tolerance on the time step: a record is uniform when every step lies
#: within this fraction of the median step (EMPS steps scatter by 2.4e-5 from float
#: rounding in the acquisition).
TIME_STEP_RTOL = 1e-3

_REQUIRED = ("t", "torque", "position")
_OPTIONAL = ("reference",)

#: Columns of a training-patterns file (``fricctl train``): motor torque [N*m],
#: velocity [rad/s] and friction torque [N*m], load side.
PATTERN_COLUMNS = ("tm", "omega", "friction")

#: Where to get the EMPS data when they are missing.
EMPS_SOURCE_HINT = (
    "the EMPS benchmark (A. Janot, M. Gautier, M. Brunot, 'Data Set and Reference Models "
    "of EMPS', Workshop on Nonlinear System Identification Benchmarks, 2019; "
    "https://www.nonlinearbenchmark.org/benchmarks/emps, also in the GitHub repository "
    "forgi86/sysid-neural-continuous under examples/EMPS/data/); put DATA_EMPS.mat and "
    "DATA_EMPS_PULSES.mat in <folder>/emps/ and set FRICCTL_DATA=<folder> "
    "(see ../shared/data/emps/README.md)"
)


# ---------------------------------------------------------------------- CSV reader
@dataclass(frozen=True, kw_only=True, eq=False)
class Table:
    """The columns of a CSV file, by header name (what :func:`read_columns` returns)."""

    path: Path
    """The file read."""
    columns: Mapping[str, np.ndarray]
    """Each column of the header, as a read-only float array (read-only mapping)."""
    meta: Mapping[str, str]
    """``# key: value`` lines before the header (read-only mapping)."""

    def __getitem__(self, name: str) -> np.ndarray:
        return self.columns[v.choice("column", name, tuple(self.columns))]

    @property
    def n_rows(self) -> int:
        """Number of data rows."""
        return int(next(iter(self.columns.values())).size)


def _expected(required, optional) -> str:
    return ", ".join(required) + "".join(f"[, {o}]" for o in optional)


def _header(path, cells, required, optional) -> list[str]:
    header = [h.strip() for h in cells]
    want = _expected(required, optional)
    unknown = [h for h in header if h not in required + optional]
    if unknown:
        s = "" if len(unknown) == 1 else "s"
        raise ValueError(f"{path}: unknown column{s} {', '.join(map(repr, unknown))} in the "
                         f"header; expected {want}")
    for name in header:
        if header.count(name) > 1:
            raise ValueError(f"{path}: duplicate column {name!r} in the header")
    for name in required:
        if name not in header:
            raise ValueError(f"{path}: missing column {name!r} in the header; expected {want}")
    return header


def read_columns(path, *, required: tuple[str, ...], optional: tuple[str, ...] = (),
                 min_rows: int = 0) -> Table:
    r"""Read a CSV file whose header names its columns (in any order).

    Layout: optional ``# key: value`` lines, a header line, then one row of numbers
    per line (blank lines are skipped).

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    required : tuple of str
        Columns the header must name.
    optional : tuple of str
        Columns the header may name; any other column is an error.
    min_rows : int
        Fewest data rows accepted.

    Returns
    -------
    Table
        The columns by name and the ``#`` metadata.

    Raises
    ------
    FileNotFoundError
        The file does not exist.
    ValueError
        Not UTF-8 text, no header, an unknown, missing or duplicate column, a row
        with another number of fields, a cell that is not a finite number (the
        message names the file, the line and the column), or fewer than
        ``min_rows`` rows.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = pathlib.Path(d) / "p.csv"
    ...     _ = p.write_text("# source: by hand\nb,a\n1,2\n3,4\n")
    ...     tab = read_columns(p, required=("a", "b"))
    >>> tab["a"].tolist(), tab.meta["source"]
    ([2.0, 4.0], 'by hand')
    """
    path = Path(path)
    required, optional = tuple(required), tuple(optional)
    min_rows = v.integer("min_rows", min_rows, low=0)
    want = _expected(required, optional)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such file")
    try:
        with path.open(newline="", encoding="utf-8") as fh:
            lines = fh.read().splitlines()
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not a UTF-8 text file (expected a CSV with a header "
                         f"{want})") from None
    meta: dict[str, str] = {}
    header = None
    rows = []
    for line_no, line in enumerate(lines, start=1):
        if header is None and line.startswith("#"):
            key, sep, value = line[1:].partition(":")
            if sep:
                meta[key.strip()] = value.strip()
            continue
        cells = next(csv.reader([line]), [])
        if not cells or all(not c.strip() for c in cells):
            continue
        if header is None:
            header = _header(path, cells, required, optional)
            continue
        if len(cells) != len(header):
            raise ValueError(f"{path}, line {line_no}: {len(cells)} fields, the header has "
                             f"{len(header)}")
        row = []
        for name, cell in zip(header, cells):
            try:
                x = float(cell)
            except ValueError:
                raise ValueError(f"{path}, line {line_no}, column {name!r}: not a number: "
                                 f"{cell.strip()!r}") from None
            if not math.isfinite(x):
                raise ValueError(f"{path}, line {line_no}, column {name!r}: "
                                 f"{'NaN' if math.isnan(x) else 'inf'} (not a finite number)")
            row.append(x)
        rows.append(row)
    if header is None:
        what = "no header line after the '#' lines" if meta or lines else "empty file"
        raise ValueError(f"{path}: {what}, expected a header {want}")
    if len(rows) < min_rows:
        raise ValueError(f"{path}: need at least {min_rows} data rows, got {len(rows)}")
    data = np.array(rows, dtype=float).reshape(-1, len(header))
    columns = {}
    for j, name in enumerate(header):
        col = data[:, j].copy()
        col.setflags(write=False)
        columns[name] = col
    return Table(path=path, columns=types.MappingProxyType(columns),
                 meta=types.MappingProxyType(meta))


def read_patterns(path) -> Table:
    """Training patterns of the friction network from a CSV file (``fricctl train``).

    The header names exactly :data:`PATTERN_COLUMNS` (``tm,omega,friction``, any
    order): motor torque [N*m], velocity [rad/s], friction torque [N*m], load
    side; at least 2 rows.  Errors as :func:`read_columns`.
    """
    return read_columns(path, required=PATTERN_COLUMNS, min_rows=2)


@dataclass(frozen=True, kw_only=True)
class Run:
    """One measured record on a uniform time grid.

    Parameters
    ----------
    t : ndarray, shape (N,)
        Sample times, strictly increasing and uniform [s].
    torque : ndarray, shape (N,)
        Applied (motor) torque [N*m]; force [N] when ``units="linear"``.
    position : ndarray, shape (N,)
        Measured position [rad]; [m] when ``units="linear"``.
    reference : ndarray, shape (N,) or None
        Position reference of a closed-loop run, same unit as ``position``.
    source : str
        Free text saying where the record comes from.
    units : {"rotary", "linear"}
        Axis kind; selects the labels N*m/rad or N/m.

    Notes
    -----
    A ``Run`` is validated on construction (finite values, equal lengths, at least
    :data:`MIN_SAMPLES` samples, strictly increasing uniform time, some motion);
    it holds no velocity or acceleration -- those are estimates, see
    :mod:`fricctl.estimation`.  Arrays are copied and made read-only.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(20) * 0.002
    >>> run = Run(t=t, torque=np.ones(20), position=0.5 * t**2)
    >>> round(run.sample_time, 6), run.torque_unit
    (0.002, 'N*m')
    """

    t: np.ndarray = field(metadata={"unit": "s"})
    """Sample times [s]."""
    torque: np.ndarray = field(metadata={"unit": "N*m or N"})
    """Applied torque [N*m] (rotary) or force [N] (linear)."""
    position: np.ndarray = field(metadata={"unit": "rad or m"})
    """Measured position [rad] (rotary) or [m] (linear)."""
    reference: np.ndarray | None = field(default=None, metadata={"unit": "rad or m"})
    """Optional position reference, same unit as ``position``."""
    source: str = ""
    """Provenance of the record (free text)."""
    units: str = "rotary"
    """``"rotary"`` (N*m, rad) or ``"linear"`` (N, m)."""

    def __post_init__(self):
        v.choice("units", self.units, KINDS)
        v.text("source", self.source)
        names = ["t", "torque", "position"] + (["reference"] if self.reference is not None else [])
        arrays = {}
        for name in names:
            arrays[name] = np.array(v.array(name, getattr(self, name), ndim=1, finite=False))
        n = arrays["t"].size
        for name, x in arrays.items():
            if x.size != n:
                raise ValueError(f"{name}: length {x.size} differs from t ({n})")
        if n < MIN_SAMPLES:
            raise ValueError(f"fewer than {MIN_SAMPLES} samples ({n})")
        for name, x in arrays.items():
            v.array(name, x)  # NaN or inf: the message names the first bad sample
        dt = np.diff(arrays["t"])
        bad = np.flatnonzero(dt <= 0)
        if bad.size:
            raise ValueError(f"t: non-increasing time at row {int(bad[0]) + 1}")
        # the median step is robust to the one bad step the message should point at
        ref_dt = float(np.median(dt))
        bad = np.flatnonzero(np.abs(dt - ref_dt) > TIME_STEP_RTOL * ref_dt)
        if bad.size:
            raise ValueError(
                f"t: non-uniform time step at row {int(bad[0]) + 1} "
                f"({dt[bad[0]]:.6g} s against a median of {ref_dt:.6g} s)")
        if np.ptp(arrays["position"]) == 0.0:
            raise ValueError("position: no motion (the position is constant)")
        for name, x in arrays.items():
            x.setflags(write=False)
            object.__setattr__(self, name, x)

    # ------------------------------------------------------------------ properties
    @property
    def sample_time(self) -> float:
        """Mean sample time [s]."""
        return float((self.t[-1] - self.t[0]) / (self.t.size - 1))

    @property
    def n_samples(self) -> int:
        """Number of samples [-]."""
        return int(self.t.size)

    @property
    def torque_unit(self) -> str:
        """Unit of :attr:`torque`: ``"N*m"`` or ``"N"``."""
        return units_of(self.units).torque

    @property
    def position_unit(self) -> str:
        """Unit of :attr:`position`: ``"rad"`` or ``"m"``."""
        return units_of(self.units).position

    @property
    def torque_label(self) -> str:
        """``"torque"`` or ``"force"``, for axis labels and reports."""
        return "torque" if self.units == "rotary" else "force"

    # ------------------------------------------------------------------ CSV
    def to_csv(self, path) -> Path:
        """Write the record as CSV with metadata comment lines; returns the path.

        Parameters
        ----------
        path : str or os.PathLike
            Destination file (overwritten).
        """
        path = Path(path)
        cols = [self.t, self.torque, self.position]
        header = ["t", "torque", "position"]
        if self.reference is not None:
            cols.append(self.reference)
            header.append("reference")
        data = np.column_stack(cols)
        with path.open("w", newline="") as fh:
            fh.write(f"# source: {self.source.replace(chr(10), ' ')}\n")
            fh.write(f"# units: {self.units}\n")
            fh.write(",".join(header) + "\n")
            np.savetxt(fh, data, delimiter=",", fmt="%.17g")
        return path

    @classmethod
    def from_csv(cls, path, *, units: str | None = None, source: str | None = None) -> "Run":
        """Read a record written by :meth:`to_csv` (or by hand in that layout).

        Parameters
        ----------
        path : str or os.PathLike
            CSV file with header ``t,torque,position[,reference]``.
        units : {"rotary", "linear"}, optional
            Overrides the ``# units:`` comment (default ``"rotary"`` if absent).
        source : str, optional
            Overrides the ``# source:`` comment (default: the file name).

        Raises
        ------
        FileNotFoundError
            The file does not exist.
        ValueError
            Missing or unknown column, non-numeric cell, or any :class:`Run`
            validation failure; the message starts with the file name.
        """
        table = read_columns(path, required=_REQUIRED, optional=_OPTIONAL)
        cols, meta = table.columns, table.meta
        try:
            return cls(
                t=cols["t"], torque=cols["torque"], position=cols["position"],
                reference=cols["reference"] if "reference" in cols else None,
                source=source if source is not None else meta.get("source", table.path.name),
                units=units if units is not None else meta.get("units", "rotary"))
        except ValueError as exc:
            raise ValueError(f"{table.path}: {exc}") from None


# ---------------------------------------------------------------------- EMPS
@dataclass(frozen=True, kw_only=True)
class EmpsData:
    """One EMPS record: the :class:`Run` plus the raw fields of the .mat file.

    Notes
    -----
    ``run.torque`` is the motor force ``gtau * vir`` [N]; ``run.position`` is
    ``qm`` [m], ``run.reference`` is ``qg`` [m].  ``pulses`` is only present in
    the validation file (0/5 square wave, dimensionless).
    """

    run: Run
    """The record (linear axis): force gtau*vir [N], position qm [m], reference qg [m]."""
    vir: np.ndarray = field(metadata={"unit": "V"})
    """Controller output [V]."""
    gtau: float = field(metadata={"unit": "N/V"})
    """Drive gain [N/V] (35.15 in the published data)."""
    kp: float = field(metadata={"unit": "1/s"})
    """Outer (position) loop gain [1/s]."""
    kv: float = field(metadata={"unit": "V/(m/s)"})
    """Inner (velocity) loop gain [V/(m/s)]."""
    kind: str
    """``"estimation"`` (DATA_EMPS.mat) or ``"validation"`` (DATA_EMPS_PULSES.mat)."""
    pulses: np.ndarray | None = None
    """``pulses_N`` of the validation file (0/5 square wave) [-], else None."""


_EMPS_FILES = {"estimation": "DATA_EMPS.mat", "validation": "DATA_EMPS_PULSES.mat"}


def _emps_folder(data_dir) -> Path:
    if data_dir is None:
        env = os.environ.get("FRICCTL_DATA")
        if not env:
            raise FileNotFoundError(
                "EMPS data: no folder given and FRICCTL_DATA is not set; get " + EMPS_SOURCE_HINT)
        data_dir = env
    d = Path(data_dir)
    # Accept either the folder holding emps/ or the emps/ folder itself.
    if (d / "emps").is_dir():
        d = d / "emps"
    return d


def emps(data_dir=None, *, kind: str = "estimation") -> EmpsData:
    """Load one EMPS record (real electro-mechanical positioning system).

    Parameters
    ----------
    data_dir : str or os.PathLike, optional
        Folder holding ``emps/`` (or the ``emps`` folder itself); default: the
        ``FRICCTL_DATA`` environment variable.
    kind : {"estimation", "validation"}
        ``DATA_EMPS.mat`` (identification) or ``DATA_EMPS_PULSES.mat``
        (cross-validation, with force pulses).

    Returns
    -------
    EmpsData
        The :class:`Run` (linear axis; force ``gtau*vir`` [N], position ``qm`` [m],
        reference ``qg`` [m]) and the raw fields.

    Raises
    ------
    FileNotFoundError
        The folder or file is missing; the message says where to get the data.

    Notes
    -----
    Cite Janot, Gautier & Brunot (2019) wherever the data are used.  ``vir`` is
    the controller output in volts, not a force (the benchmark PDF's variable list
    is wrong on that).  In the validation file ``qm`` looks low-pass filtered after
    acquisition; use it for validation only.
    """
    v.choice("kind", kind, tuple(_EMPS_FILES))
    folder = _emps_folder(data_dir)
    path = folder / _EMPS_FILES[kind]
    if not path.is_file():
        raise FileNotFoundError(f"EMPS data: {path} not found; get " + EMPS_SOURCE_HINT)
    from scipy.io import loadmat

    raw = loadmat(path)

    def col(name):
        return np.asarray(raw[name], dtype=float).ravel()

    def scalar(name):
        v = col(name)
        if v.size != 1:
            raise ValueError(f"{path.name}: {name} should be a scalar, has {v.size} values")
        return float(v[0])

    gtau = scalar("gtau")
    vir = col("vir")
    run = Run(t=col("t"), torque=gtau * vir, position=col("qm"), reference=col("qg"),
              source=f"EMPS {path.name} (Janot, Gautier & Brunot 2019)", units="linear")
    vir.setflags(write=False)
    pulses = col("pulses_N") if "pulses_N" in raw else None
    return EmpsData(run=run, vir=vir, gtau=gtau, kp=scalar("kp"), kv=scalar("kv"),
                    kind=kind, pulses=pulses)

