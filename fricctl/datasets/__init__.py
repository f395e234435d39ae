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

Lines starting with ``#`` before the header carry metadata (``source``, ``units``; a
``# key:`` line whose one-word key is close to one of them, ``# unit:`` or ``# Units:``, is
refused with the key it resembles; any other ``#`` line is a free comment, colons and all);
the header must name ``t``, ``torque`` and ``position`` and may name ``reference``;
any other column is an error.  For a linear axis (``units="linear"``) the
``torque`` column holds a force [N] and ``position`` a displacement [m].

Every CSV file fricctl reads goes through :func:`read_columns` (columns named by
a header, in any order): records (:meth:`Run.from_csv`) and the network's
training patterns (:func:`read_patterns`, header ``tm,omega,friction[,at_rest]``,
written by :func:`write_patterns` from :func:`record_patterns`; :class:`FrictionPatterns`,
the one pattern type of fricctl).  Its errors name
the file, the line and the column.  :func:`load_record` reads a record from a CSV
file or from a MATLAB file in the EMPS layout.

The EMPS data (Janot, Gautier & Brunot 2019) are *not* shipped: :func:`emps`
loads them from a folder given as argument or by the ``FRICCTL_DATA``
environment variable (the folder that holds ``emps/DATA_EMPS.mat``).
"""

from __future__ import annotations

from .emps_data import (EMPS_MOTOR_REVOLUTION, EMPS_SOURCE_HINT, EmpsData, emps, emps_file,
                        load_record, record_length)
from .patterns import (PATTERN_COLUMNS, FrictionPatterns, PatternTable, read_patterns,
                       record_patterns, write_patterns)
from .run import MIN_SAMPLES, RECORD_KEYS, TIME_STEP_RTOL, Run
from .table import Table, read_columns

__all__ = [
    "Run",
    "EmpsData",
    "EMPS_MOTOR_REVOLUTION",
    "emps",
    "emps_file",
    "load_record",
    "record_length",
    "Table",
    "read_columns",
    "FrictionPatterns",
    "PatternTable",
    "record_patterns",
    "write_patterns",
    "read_patterns",
    "PATTERN_COLUMNS",
    "MIN_SAMPLES",
    "TIME_STEP_RTOL",
    "EMPS_SOURCE_HINT",
]
