"""The EMPS benchmark records (Janot, Gautier & Brunot 2019) and :func:`load_record`.

The EMPS data are *not* shipped: :func:`emps` loads them from a folder given as
argument or by the ``FRICCTL_DATA`` environment variable (the folder that holds
``emps/DATA_EMPS.mat``); :func:`emps_file` reads any MATLAB file in the EMPS
layout, and :func:`load_record` a record from a CSV file or such a ``.mat`` file.
"""

from __future__ import annotations

import os
import zlib
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from .. import _validate as v
from .run import Run

__all__ = ["EmpsData", "emps", "emps_file", "load_record", "EMPS_SOURCE_HINT", "EMPS_VARIABLES",
           "EMPS_MOTOR_REVOLUTION"]

#: Travel of the EMPS load per revolution of its motor: the ball screw's lead, 2.5 mm [m].
#: From the data folder's ``emps/README.md`` ("one motor revolution = 2.5 mm of travel",
#: with the encoder count of 5e-8 m on the load); the benchmark's PDF (Janot, Gautier &
#: Brunot 2019) names the ball screw but its text does not state the lead.  Attached to the
#: records :func:`emps` returns (:attr:`Run.motor_revolution`); :func:`emps_file` reads any
#: file of the layout and does not assume it.
EMPS_MOTOR_REVOLUTION = 2.5e-3

#: Where to get the EMPS data when they are missing.
EMPS_SOURCE_HINT = (
    "the EMPS benchmark (A. Janot, M. Gautier, M. Brunot, 'Data Set and Reference Models "
    "of EMPS', Workshop on Nonlinear System Identification Benchmarks, 2019; "
    "https://www.nonlinearbenchmark.org/benchmarks/emps, also in the GitHub repository "
    "forgi86/sysid-neural-continuous under examples/EMPS/data/); put DATA_EMPS.mat and "
    "DATA_EMPS_PULSES.mat in <folder>/emps/ and set FRICCTL_DATA=<folder> "
    "(see ../shared/data/emps/README.md)"
)


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
        reference ``qg`` [m], :attr:`~Run.motor_revolution` the screw's lead
        :data:`EMPS_MOTOR_REVOLUTION`) and the raw fields.

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
    path = _emps_folder(data_dir) / _EMPS_FILES[kind]
    if not path.is_file():
        raise FileNotFoundError(f"EMPS data: {path} not found; get " + EMPS_SOURCE_HINT)
    data = emps_file(path)
    return replace(data, run=replace(data.run, motor_revolution=EMPS_MOTOR_REVOLUTION))


#: Variables of a MATLAB file in the EMPS layout (``pulses_N`` only in the validation file).
EMPS_VARIABLES = ("t", "qm", "qg", "vir", "gtau", "kp", "kv")


def emps_file(path) -> EmpsData:
    """Read a MATLAB file in the EMPS layout (``t, qm, qg, vir, gtau, kp, kv[, pulses_N]``).

    Parameters
    ----------
    path : str or os.PathLike
        The ``.mat`` file (``DATA_EMPS.mat``, ``DATA_EMPS_PULSES.mat`` or a record of
        your own axis saved with the same variables).

    Returns
    -------
    EmpsData
        ``kind`` is ``"validation"`` when the file has ``pulses_N``, else ``"estimation"``.

    Raises
    ------
    FileNotFoundError
        No such file.
    ValueError
        Not a MATLAB file, a variable missing or of the wrong size, or the record
        invalid (:class:`Run`); the message names the file.
    """
    path = Path(path)
    if path.is_dir():
        raise IsADirectoryError(21, "a folder, not a record file", str(path))
    if not path.is_file():
        raise FileNotFoundError(2, "no such file", str(path))
    from scipy.io import loadmat
    from scipy.io.matlab import MatReadError

    try:
        raw = loadmat(path)
    except NotImplementedError:  # scipy's answer to a v7.3 file (HDF5 inside)
        raise ValueError(f"{path}: a MATLAB v7.3 (HDF5) file, which fricctl cannot read: save it "
                         "with -v7 (save(name, ..., '-v7')) or convert it") from None
    except zlib.error:
        raise ValueError(f"{path}: a corrupt MATLAB file (a compressed variable does not "
                         "decompress)") from None
    except (MatReadError, ValueError, TypeError, OSError, EOFError) as exc:  # scipy on junk
        first = str(exc).splitlines()[0][:80] if str(exc) else type(exc).__name__
        raise ValueError(f"{path}: not a MATLAB .mat file ({first.replace(str(path), path.name)})") from None
    missing = [n for n in EMPS_VARIABLES if n not in raw]
    if missing:
        raise ValueError(f"{path}: missing variable(s) {', '.join(missing)} (the EMPS layout has "
                         f"{', '.join(EMPS_VARIABLES)})")

    def col(name):
        x = np.asarray(raw[name])
        if x.dtype.kind not in "iuf":
            raise ValueError(f"{path}: variable {name} must hold real numbers, not {x.dtype}")
        return np.asarray(x, dtype=float).ravel()

    def scalar(name):
        x = col(name)
        if x.size != 1:
            raise ValueError(f"{path}: variable {name} should be a scalar, has {x.size} values")
        return v.real(f"{path.name}: {name}", x[0])

    gtau = scalar("gtau")
    vir = col("vir")
    t, qm, qg = col("t"), col("qm"), col("qg")  # outside the try: their errors name the file once
    try:
        run = Run(t=t, torque=gtau * vir, position=qm, reference=qg,
                  source=f"EMPS {path.name} (Janot, Gautier & Brunot 2019)", units="linear")
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None
    vir.setflags(write=False)
    pulses = col("pulses_N") if "pulses_N" in raw else None
    return EmpsData(run=run, vir=vir, gtau=gtau, kp=scalar("kp"), kv=scalar("kv"),
                    kind="estimation" if pulses is None else "validation", pulses=pulses)


def record_length(path) -> int | None:
    """Samples a record file holds, counted without parsing it [-]: a CSV's lines that are
    neither comments (``#``) nor its header, or the length of a ``.mat`` file's ``t``
    (an upper bound for a CSV with blank lines); None when a ``.mat`` file's table of
    contents cannot be read (its reader, :func:`emps_file`, then says why).  Reads a CSV in
    8 MB chunks."""
    path = Path(path)
    if path.suffix.lower() == ".mat":
        from scipy.io import whosmat

        try:
            shapes = {name: shape for name, shape, _ in whosmat(str(path))}
        except (ValueError, NotImplementedError, OSError, zlib.error):
            return None
        return int(np.prod(shapes["t"])) if "t" in shapes else None
    lines = comments = 0
    last = b"\n"
    with open(path, "rb") as f:
        while chunk := f.read(8 << 20):
            lines += chunk.count(b"\n")
            comments += chunk.count(b"\n#") + (last == b"\n" and chunk[:1] == b"#")
            last = chunk[-1:]
    if last != b"\n":
        lines += 1  # a last line without its newline
    return max(lines - comments - 1, 0)


def load_record(path, *, units: str | None = None, max_samples: int | None = None) -> Run:
    """A record from a CSV file (:meth:`Run.from_csv`) or a MATLAB file in the EMPS layout.

    Parameters
    ----------
    path : str or os.PathLike
        ``*.mat``: :func:`emps_file` (a linear axis: force ``gtau*vir`` [N], position
        ``qm`` [m]); anything else: CSV with header ``t,torque,position[,reference]``.
    units : {"rotary", "linear"}, optional
        Overrides the CSV's ``# units:`` line; for a ``.mat`` file it must be
        ``"linear"`` (the EMPS layout is a linear axis).
    max_samples : int, optional
        Refuse a longer record *before* reading it (:func:`record_length`): a command with a
        sample limit does not spend minutes and gigabytes parsing what it will refuse.
    """
    path = Path(path)
    if units is not None:
        v.choice("units", units, ("rotary", "linear"))
    if max_samples is not None and path.is_file():
        n = record_length(path)
        if n is not None and n > v.integer("max_samples", max_samples, low=1):
            raise ValueError(f"{path}: {n} samples, more than the {max_samples} this command "
                             f"takes; cut the record or decimate it by "
                             f"{-(-n // max_samples)}")
    if path.suffix.lower() == ".mat":
        if units not in (None, "linear"):
            raise ValueError(f"{path}: a .mat record in the EMPS layout is a linear axis, "
                             f"not {units!r}")
        return emps_file(path).run
    if path.is_dir():
        raise IsADirectoryError(21, "a folder, not a record file", str(path))
    return Run.from_csv(path, units=units)
