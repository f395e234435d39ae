"""A measured record on a uniform time grid: :class:`Run`, and its CSV form."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .. import _validate as v
from .._atomic import atomic_write
from ..units import KINDS, units as units_of
from .table import read_columns

__all__ = ["Run", "MIN_SAMPLES", "TIME_STEP_RTOL", "RECORD_KEYS"]

#: Fewest samples a record may have: a 6th-order polynomial fit and the
#: four-parameter inverse model both need well over this many.
MIN_SAMPLES = 10

#: Relative tolerance on the time step: a record is uniform when every step lies
#: within this fraction of the median step (EMPS steps scatter by 2.4e-5 from float
#: rounding in the acquisition).
TIME_STEP_RTOL = 1e-3

_REQUIRED = ("t", "torque", "position")
_OPTIONAL = ("reference",)
#: The ``# key:`` lines of a record (what :meth:`Run.to_csv` writes); a one-word key close to
#: one of them is refused (a misspelling), any other ``#`` line is a free comment.
RECORD_KEYS = ("source", "units")


def _time_problem(t: np.ndarray) -> tuple[int, str, str] | None:
    """``(index, what, detail)`` of the first sample whose time step is not strictly
    increasing or not uniform (``index`` counts samples from 0), or None."""
    dt = np.diff(t)
    bad = np.flatnonzero(dt <= 0)
    if bad.size:
        return int(bad[0]) + 1, "non-increasing time", ""
    # the median step is robust to the one bad step the message should point at
    ref_dt = float(np.median(dt))
    bad = np.flatnonzero(np.abs(dt - ref_dt) > TIME_STEP_RTOL * ref_dt)
    if bad.size:
        return (int(bad[0]) + 1, "non-uniform time step",
                f" ({dt[bad[0]]:.6g} s against a median of {ref_dt:.6g} s)")
    return None


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
    motor_revolution : float or None
        Travel of the recorded position per revolution of the motor (the transmission:
        ``2*pi/n`` for a gear of ratio ``n``, the lead of a screw), same unit as
        ``position``; None when unknown (positive and finite when given).

    Notes
    -----
    A ``Run`` is validated on construction (finite values, equal lengths, at least
    :data:`MIN_SAMPLES` samples, strictly increasing uniform time); a joint that never
    moved (stuck below breakaway) is a valid record -- identification refuses it, not the
    record;
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
    motor_revolution: float | None = field(default=None, metadata={"unit": "rad or m"})
    """Travel of ``position`` per motor revolution (the transmission), or None (unknown)."""

    def __post_init__(self):
        v.choice("units", self.units, KINDS)
        if self.motor_revolution is not None:
            object.__setattr__(self, "motor_revolution", v.real(
                "motor_revolution", self.motor_revolution, positive=True,
                unit=units_of(self.units).position))
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
        problem = _time_problem(arrays["t"])
        if problem is not None:
            index, what, detail = problem
            raise ValueError(f"t: {what} at index {index}{detail}")
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

    def encoder_grid(self) -> float | None:
        """The count of the encoder grid the positions lie on [rad] or [m], or None.

        The smallest non-zero step between samples, when every position lies a whole
        number of such steps from the first (to 1e-3 of a step); None for a record
        that is not on one grid (filtered or interpolated positions).

        Examples
        --------
        >>> import numpy as np
        >>> t = np.arange(20) * 0.001
        >>> Run(t=t, torque=np.zeros(20), position=5e-8 * np.arange(20) ** 2).encoder_grid()
        5e-08
        """
        d = self.position - self.position[0]
        steps = np.abs(np.diff(self.position))
        if not np.any(steps > 0):  # a joint that never moved: no count was ever seen
            return None
        k = d / float(steps[steps > 0].min())
        n = np.round(k)
        if float(np.max(np.abs(k - n))) >= 1e-3:
            return None
        return float(n @ d / (n @ n))  # least squares over every sample: no rounding of one step

    @property
    def torque_label(self) -> str:
        """``"torque"`` or ``"force"``, for axis labels and reports."""
        return "torque" if self.units == "rotary" else "force"

    # ------------------------------------------------------------------ CSV
    def to_csv(self, path, *, overwrite: bool = True) -> Path:
        """Write the record as CSV with metadata comment lines; returns the path.

        The file is written atomically (:mod:`fricctl._atomic`): complete, or not at all.

        Parameters
        ----------
        path : str or os.PathLike
            Destination file.
        overwrite : bool
            False: refuse (:class:`FileExistsError`) when ``path`` exists.
        """
        path = Path(path)
        cols = [self.t, self.torque, self.position]
        header = ["t", "torque", "position"]
        if self.reference is not None:
            cols.append(self.reference)
            header.append("reference")
        data = np.column_stack(cols)
        with atomic_write(path, overwrite=v.flag("overwrite", overwrite), newline="") as fh:
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
            Missing or unknown column, non-numeric cell, a ``# key:`` line whose one-word key
            is close to one of :data:`RECORD_KEYS` but not one (``# unit:``, ``# Units:``; any
            other ``#`` line is a free comment), or any :class:`Run` validation failure; the
            message starts with the file name.
        """
        table = read_columns(path, required=_REQUIRED, optional=_OPTIONAL, keys=RECORD_KEYS)
        cols, meta = table.columns, table.meta
        problem = _time_problem(cols["t"]) if table.n_rows > 1 else None
        if problem is not None:  # named by the file's line, as every other error of the file
            index, what, detail = problem
            raise ValueError(f"{table.path}, line {int(table.row_lines[index])}, column 't': "
                             f"{what}{detail}")
        try:
            return cls(
                t=cols["t"], torque=cols["torque"], position=cols["position"],
                reference=cols["reference"] if "reference" in cols else None,
                source=source if source is not None else meta.get("source", table.path.name),
                units=units if units is not None else meta.get("units", "rotary"))
        except ValueError as exc:
            raise ValueError(f"{table.path}: {exc}") from None
