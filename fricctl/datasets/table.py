"""The one CSV reader of fricctl: :func:`read_columns` -> :class:`Table`.

Every CSV file fricctl reads (records, training patterns) goes through
:func:`read_columns`: optional ``# key: value`` lines, a header naming the
columns (in any order), one row of numbers per line.  Its errors name the file,
the line and the column.
"""

from __future__ import annotations

import csv
import functools
import re
import types
from dataclasses import dataclass
from pathlib import Path
from typing import Mapping

import numpy as np

from .. import _validate as v

__all__ = ["Table", "read_columns", "MAX_LINE"]

#: Longest line read [characters]: a record's row is about 100, a patterns file's ``# source:``
#: line of many records a few thousand; a longer line is not a CSV fricctl wrote or reads.
MAX_LINE = 100_000


@dataclass(frozen=True, kw_only=True, eq=False)
class Table:
    """The columns of a CSV file, by header name (what :func:`read_columns` returns)."""

    path: Path
    """The file read."""
    columns: Mapping[str, np.ndarray]
    """Each column of the header, as a read-only float array (read-only mapping)."""
    meta: Mapping[str, str]
    """``# key: value`` lines before the header (read-only mapping)."""
    row_lines: np.ndarray | None = None
    """The file's line number (from 1) of each data row, for messages about a row; None
    when not known."""

    def __getitem__(self, name: str) -> np.ndarray:
        return self.columns[v.choice("column", name, tuple(self.columns))]

    @property
    def n_rows(self) -> int:
        """Number of data rows."""
        return int(next(iter(self.columns.values())).size)


def _expected(required, optional) -> str:
    return ", ".join(required) + "".join(f"[, {o}]" for o in optional)


#: Separators a spreadsheet writes instead of ',' (a locale with decimal commas writes ';').
_OTHER_SEPARATORS = {";": "';'", "\t": "tab"}
_DECIMAL_COMMA = re.compile(r"\s*[+-]?\d+,\d+(?:[eE][+-]?\d+)?\s*")


def _dialect_hint(header_line: str, data_line: str | None, names) -> str:
    """Why a header may not split into the known columns: another separator and decimal
    commas (a spreadsheet's 'CSV' in a German or French locale), said in words; else ''."""
    for sep, name in _OTHER_SEPARATORS.items():
        cells = [c.strip() for c in header_line.split(sep)]
        if len(cells) > 1 and any(c in names for c in cells):
            commas = data_line is not None and any(
                _DECIMAL_COMMA.fullmatch(c) for c in data_line.split(sep))
            fix = (f"the decimal commas by '.', then each {name} by ','" if commas
                   else f"each {name} by ','")
            return (f"; the file looks {name}-separated{' with decimal commas' if commas else ''}"
                    f": fricctl reads ',' between fields and '.' as the decimal mark (export "
                    f"the CSV with those, or replace {fix})")
    return ""


def _header(path, cells, required, optional, hint: str = "") -> list[str]:
    header = [h.strip() for h in cells]
    want = _expected(required, optional)
    unknown = [h for h in header if h not in required + optional]
    if unknown:
        s = "" if len(unknown) == 1 else "s"
        raise ValueError(f"{path}: unknown column{s} {', '.join(map(repr, unknown))} in the "
                         f"header; expected {want}{hint}")
    for name in header:
        if header.count(name) > 1:
            raise ValueError(f"{path}: duplicate column {name!r} in the header")
    for name in required:
        if name not in header:
            raise ValueError(f"{path}: missing column {name!r} in the header; expected {want}")
    return header


#: ``#`` keys whose value fricctl reads: a second line with another value is refused (the
#: last one silently won: a record relabelled by hand with both lines kept).
SINGLE_KEYS = ("units", "velocity_quantum")


def _check_lines(path, lines: list[str], want: str) -> None:
    """Refuse a binary file (a NUL byte) or an overlong line, naming the file and the line."""
    for line_no, line in enumerate(lines, start=1):
        if "\x00" in line:
            raise ValueError(f"{path}, line {line_no}: a NUL byte: a binary file, not a CSV "
                             f"text file (expected a header {want})")
        if len(line) > MAX_LINE:
            raise ValueError(f"{path}, line {line_no}: {len(line)} characters, more than the "
                             f"{MAX_LINE} a line may hold: not a CSV record (expected a header "
                             f"{want})")


#: One cell that :func:`fricctl._validate.number_text` reads as a finite number, spaces
#: around it allowed (no nan/inf: a row holding one takes the line-by-line path, which names it).
#: Every part matches one way only (``\d+(?:\.\d*)?``, never ``\d+\.?\d*``, which splits
#: ``1500`` four ways), so a line that fails is refused in time linear in its length.
_PLAIN_CELL = r"[ \t]*[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?[ \t]*"


@functools.lru_cache(maxsize=16)
def _plain_row(width: int) -> re.Pattern:
    return re.compile(_PLAIN_CELL + ("," + _PLAIN_CELL) * (width - 1), re.ASCII)


def _plain_rows(lines: list, width: int):
    """The data rows as a ``(n, width)`` array when every non-blank line is ``width`` plain
    decimal cells that are finite as doubles -- the common file, read in one pass; else None
    (the line-by-line reader then names the first line that is not).  Each line is matched on
    its own, so one bad line costs no more than reading it."""
    body = [x for x in lines if x.strip()]
    if not body:
        return None
    row = _plain_row(width)
    if not all(row.fullmatch(x) for x in body):
        return None
    data = np.fromiter(map(float, ",".join(body).split(",")), dtype=float)
    return data.reshape(-1, width) if np.isfinite(data).all() else None


def _misspelt(key: str, keys: tuple[str, ...]) -> str | None:
    """The one of ``keys`` that ``key`` (the text before a ``#`` line's first colon) reads as
    a misspelling of -- one word close to it (``unit``, ``Units``, ``sorce``) -- or None.
    Review R11: refusing every other key refused comments with a colon ('# recorded 10:15',
    '# Note: gear 1:100', a URL)."""
    from difflib import get_close_matches

    word = key.lower()
    near = get_close_matches(word, keys, n=1, cutoff=0.75) if word.isidentifier() else []
    return near[0] if near else None


def _unknown_key(path, line_no: int, key: str, near: str, keys: tuple[str, ...]) -> ValueError:
    """The error of a ``# key:`` line whose key misspells ``near``, one of ``keys`` (a misspelt
    ``# unit: linear`` was silently ignored: the record was read as rotary)."""
    return ValueError(f"{path}, line {line_no}: unknown '# {key}:' line (did you mean "
                      f"{near!r}?); the '#' keys of this file are {', '.join(keys)} (a '#' line "
                      f"not read as one of them is a free comment)")


def read_columns(path, *, required: tuple[str, ...], optional: tuple[str, ...] = (),
                 min_rows: int = 0, keys: tuple[str, ...] | None = None) -> Table:
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
    keys : tuple of str, optional
        The ``# key: value`` keys the file may carry (exact spelling); a ``#`` line whose
        one-word key is close to one of them (a misspelling) is refused, naming the line and
        the key it resembles; any other ``#`` line is then a free comment.  None (default):
        any key.

    Returns
    -------
    Table
        The columns by name and the ``#`` metadata.

    Raises
    ------
    IsADirectoryError
        ``path`` is a folder.
    FileNotFoundError
        The file does not exist.
    ValueError
        Not UTF-8 text (a UTF-8 byte-order mark, as Excel writes, is accepted), a NUL
        byte (a binary file), a line longer than :data:`MAX_LINE` characters, no header, an unknown, missing or duplicate column, a row
        with another number of fields, a cell that is not a finite decimal number
        (``0.00_2``, ``0x10``, ``1,5``, NaN, inf; the message names the file, the line
        and the column), a ``#`` key misspelling one of ``keys``, two ``#`` lines of a :data:`SINGLE_KEYS` key with different
        values (naming the line), or fewer than
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
    keys = None if keys is None else tuple(keys)
    want = _expected(required, optional)
    if path.is_dir():
        raise IsADirectoryError(21, "a folder, not a CSV file", str(path))
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such file")
    try:
        with path.open(newline="", encoding="utf-8-sig") as fh:  # -sig: Excel's "CSV UTF-8"
            lines = fh.read().splitlines()
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not a UTF-8 text file (expected a CSV with a header "
                         f"{want})") from None
    _check_lines(path, lines, want)
    meta: dict[str, str] = {}
    meta_line: dict[str, int] = {}
    header = None
    rows = []
    row_lines: list[int] = []
    for line_no, line in enumerate(lines, start=1):
        if header is None and line.startswith("#"):
            key, sep, value = line[1:].partition(":")
            key, value = key.strip(), value.strip()
            if sep and keys is not None and key not in keys:
                near = _misspelt(key, keys)
                if near is not None:  # a misspelt key: refused, never a silent default
                    raise _unknown_key(path, line_no, key, near, keys)
                continue  # any other '#' line is a free comment ('# recorded 10:15', a URL)
            if sep and key in SINGLE_KEYS and key in meta and meta[key] != value:
                raise ValueError(f"{path}, line {line_no}: '# {key}: {value}' contradicts line "
                                 f"{meta_line[key]} ('# {key}: {meta[key]}'); keep one")
            if sep:
                meta[key], meta_line[key] = value, line_no
            continue
        try:
            cells = next(csv.reader([line]), [])
        except csv.Error as exc:
            raise ValueError(f"{path}, line {line_no}: not a CSV line ({exc})") from None
        if not cells or all(not c.strip() for c in cells):
            continue
        if header is None:
            following = next((x for x in lines[line_no:] if x.strip()), None)
            header = _header(path, cells, required, optional,
                             _dialect_hint(line, following, required + optional))
            fast = _plain_rows(lines[line_no:], len(header))
            if fast is not None:  # every row plain: the same numbers, read at once
                rows = fast
                row_lines = [k for k, x in enumerate(lines[line_no:], start=line_no + 1)
                             if x.strip()]
                break
            continue
        if len(cells) != len(header):
            more = (" (decimal commas? fricctl reads '.' as the decimal mark)"
                    if len(cells) > len(header) else "")
            raise ValueError(f"{path}, line {line_no}: {len(cells)} fields, the header has "
                             f"{len(header)}{more}")
        row = []
        for name, cell in zip(header, cells):
            # strictly a decimal number: Python's float() would read "0.00_2" as 0.002
            row.append(v.number_text(f"{path}, line {line_no}, column {name!r}", cell))
        rows.append(row)
        row_lines.append(line_no)
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
    row_lines = np.array(row_lines, dtype=int)
    row_lines.setflags(write=False)
    return Table(path=path, columns=types.MappingProxyType(columns), row_lines=row_lines,
                 meta=types.MappingProxyType(meta))
