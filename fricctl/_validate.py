"""The one set of argument checks used everywhere in fricctl.

Every public function and dataclass checks its arguments with these helpers, so
that the same input is accepted or refused the same way in every module:

* a *real number* is a Python ``int`` or ``float`` or a NumPy integer or floating
  scalar (``np.int64``, ``np.float32`` ...) or a 0-d real array; ``bool``,
  strings, complex numbers and ``None`` are refused (never silently coerced);
* an *integer* is a Python ``int`` or NumPy integer (or a float with an integral
  value only where the caller says so: never by default);
* an *array* is converted with ``numpy.asarray(dtype=float)`` from real-valued
  input only (no strings, booleans, complex or object arrays).

Each helper raises :class:`ValueError` naming the argument, the constraint and the
value received, and returns the checked value as a plain Python ``float`` /
``int`` or a float ``ndarray``.

Examples
--------
>>> real("inertia", np.float32(0.5), positive=True)
0.5
>>> real("viscous", -1.0, nonneg=True)
Traceback (most recent call last):
...
ValueError: viscous must be >= 0, got -1.0
>>> integer("hidden", np.int64(4), low=1)
4
"""

from __future__ import annotations

import json
import math
import numbers
import re
from typing import Iterable

import numpy as np

__all__ = ["real", "integer", "flag", "choice", "rng", "array", "instance", "text",
           "is_real_scalar", "number_text", "strict_json", "json_numbers", "sample_time",
           "SAMPLE_TIME_RANGE"]

#: Numbers larger than this are refused as "not a usable magnitude" (about 1e300):
#: their squares and products overflow double precision.
HUGE = 1e300


#: Sample times a digital controller can have [s]: from 1 ns (a 1 GHz loop; below about 1e-17 s
#: the gains over Ts swamp the plant in double precision and a stable design came out
#: "unstable") to an hour (above about 1e100 s the ZOH discretisation overflowed to NaN).
SAMPLE_TIME_RANGE = (1e-9, 3600.0)


def sample_time(name: str, v) -> float:
    """A controller's sample time within :data:`SAMPLE_TIME_RANGE` [s], as ``float``."""
    x = real(name, v, positive=True, unit="s")
    low, high = SAMPLE_TIME_RANGE
    if not low <= x <= high:
        raise ValueError(f"{name} must lie in [{low:g}, {high:g}] s (a digital controller's "
                         f"sample time), got {x!r}")
    return x


def _describe(v) -> str:
    # a NumPy scalar as the number it holds ("nan", not "np.float64(nan)")
    r = repr(v.item() if isinstance(v, np.generic) else v)
    return r if len(r) <= 60 else r[:57] + "..."


def is_real_scalar(v) -> bool:
    """True for int/float/NumPy real scalars (and 0-d real arrays), False for bool, str, complex."""
    if isinstance(v, (bool, np.bool_)):
        return False
    if isinstance(v, np.ndarray):
        return v.ndim == 0 and v.dtype.kind in "iuf"
    return isinstance(v, (numbers.Integral, numbers.Real)) and not isinstance(v, complex)


def real(name: str, v, *, positive: bool = False, nonneg: bool = False,
         low: float | None = None, high: float | None = None, finite: bool = True,
         unit: str = "") -> float:
    """A real number, as ``float``; optionally > 0, >= 0, or within [low, high].

    Parameters
    ----------
    name : str
        What the caller calls the argument (appears in the message).
    v : object
        The value received.
    positive, nonneg : bool
        Require ``v > 0`` / ``v >= 0``.
    low, high : float, optional
        Inclusive bounds.
    finite : bool
        Refuse NaN and +-inf (default), and magnitudes above 1e300.
    unit : str
        Unit shown in the message (e.g. ``"N*m"``).
    """
    if not is_real_scalar(v):
        raise ValueError(f"{name} must be a real number, got {_describe(v)}")
    try:
        x = float(v)
    except OverflowError:
        raise ValueError(f"{name} is too large to be a number of double precision") from None
    u = f" {unit}" if unit else ""
    if finite and not math.isfinite(x):
        raise ValueError(f"{name} must be finite, got {_describe(v)}")
    if finite and abs(x) > HUGE:
        raise ValueError(f"{name} must be at most 1e300 in magnitude, got {x!r}")
    if positive and not x > 0:
        raise ValueError(f"{name} must be > 0{u}, got {x!r}")
    if nonneg and not x >= 0:
        raise ValueError(f"{name} must be >= 0{u}, got {x!r}")
    if low is not None and high is not None and not low <= x <= high:
        raise ValueError(f"{name} must lie in [{low:g}, {high:g}]{u}, got {x!r}")
    if low is not None and high is None and not x >= low:
        raise ValueError(f"{name} must be >= {low:g}{u}, got {x!r}")
    if high is not None and low is None and not x <= high:
        raise ValueError(f"{name} must be <= {high:g}{u}, got {x!r}")
    return x


def integer(name: str, v, *, low: int | None = None, high: int | None = None) -> int:
    """An integer (Python or NumPy), as ``int``; optionally within [low, high]."""
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, (numbers.Integral, np.integer)):
        raise ValueError(f"{name} must be an integer, got {_describe(v)}")
    i = int(v)
    if low is not None and high is not None and not low <= i <= high:
        raise ValueError(f"{name} must be an integer in {low} .. {high}, got {i}")
    if low is not None and high is None and i < low:
        raise ValueError(f"{name} must be an integer >= {low}, got {i}")
    if high is not None and low is None and i > high:
        raise ValueError(f"{name} must be an integer <= {high}, got {i}")
    return i


def flag(name: str, v) -> bool:
    """A boolean (``True``/``False`` or ``numpy.bool_``), as ``bool``."""
    if not isinstance(v, (bool, np.bool_)):
        raise ValueError(f"{name} must be True or False, got {_describe(v)}")
    return bool(v)


def choice(name: str, v, options: Iterable):
    """One of ``options`` (compared with ``==``; strings must match exactly)."""
    opts = tuple(options)
    if isinstance(v, str) or not isinstance(v, (list, dict, set, np.ndarray)):
        for o in opts:
            if type(o) is type(v) and o == v:
                return v
    raise ValueError(f"{name} must be one of {', '.join(map(repr, opts))}; got {_describe(v)}")


def rng(name: str, v) -> np.random.Generator:
    """A ``numpy.random.Generator`` (never a seed or the legacy global state)."""
    if not isinstance(v, np.random.Generator):
        raise ValueError(f"{name} must be a numpy.random.Generator (numpy.random.default_rng(seed)), "
                         f"got {type(v).__name__}")
    return v


def instance(name: str, v, cls, what: str | None = None):
    """``v`` itself if it is an instance of ``cls`` (a class or a tuple of classes)."""
    if not isinstance(v, cls):
        if what is None:
            names = cls.__name__ if isinstance(cls, type) else " or ".join(c.__name__ for c in cls)
            what = f"a {names}"
        raise ValueError(f"{name} must be {what}, got {type(v).__name__}")
    return v


def text(name: str, v, *, empty: bool = True) -> str:
    """A string (optionally non-empty)."""
    if not isinstance(v, str):
        raise ValueError(f"{name} must be a string, got {type(v).__name__}")
    if not empty and not v.strip():
        raise ValueError(f"{name} must not be empty")
    return v


def _holds_bool(seq) -> bool:
    """True if a (nested) list/tuple holds a bool or numpy.bool_ (ndarray items are skipped)."""
    stack = [seq]
    while stack:
        for x in stack.pop():
            if isinstance(x, (bool, np.bool_)):
                return True
            if isinstance(x, (list, tuple)):
                stack.append(x)
    return False


def array(name: str, v, *, ndim: int | None = 1, size: int | None = None,
          min_size: int = 0, finite: bool = True, shape: tuple | None = None) -> np.ndarray:
    """A real-valued array as a float ``ndarray`` (a new array only where conversion needs one).

    Parameters
    ----------
    name : str
        Argument name for the message.
    v : array_like
        Real numbers (lists, tuples, NumPy arrays of integer or floating dtype).
    ndim : int or None
        Required number of dimensions (``None``: any).
    size : int, optional
        Required number of elements.
    min_size : int
        Smallest number of elements.
    finite : bool
        Refuse NaN and +-inf (reporting the first bad index).
    shape : tuple, optional
        Required shape.
    """
    if v is None or isinstance(v, (str, bytes)):
        raise ValueError(f"{name} must be an array of real numbers, got {type(v).__name__}")
    try:
        raw = np.asarray(v)
    except ValueError:  # ragged nested sequences
        raise ValueError(f"{name} must be a rectangular array of real numbers (rows of equal "
                         f"length)") from None
    if raw.dtype.kind not in "iuf":
        what = {"U": "text", "S": "bytes", "b": "booleans", "c": "complex numbers",
                "O": "mixed or non-numeric objects"}.get(raw.dtype.kind, f"dtype {raw.dtype}")
        raise ValueError(f"{name} must hold real numbers, got an array of {what}")
    if isinstance(v, (list, tuple)) and _holds_bool(v):
        # numpy turns [True, 0.5] into [1.0, 0.5]: a boolean is not a number here either
        raise ValueError(f"{name} must hold real numbers, got a boolean among them")
    try:
        a = np.asarray(raw, dtype=float)
    except OverflowError:  # pragma: no cover - integer arrays beyond float range
        raise ValueError(f"{name} holds integers too large for double precision") from None
    if ndim is not None and a.ndim != ndim:
        raise ValueError(f"{name} must be a {ndim}-D array, got shape {a.shape}")
    if shape is not None and a.shape != tuple(shape):
        raise ValueError(f"{name} must have shape {tuple(shape)}, got {a.shape}")
    if size is not None and a.size != size:
        raise ValueError(f"{name} must have {size} elements, got {a.size}")
    if a.size < min_size:
        raise ValueError(f"{name} must have at least {min_size} elements, got {a.size}")
    if finite and a.size:
        bad = ~np.isfinite(a)
        if bad.any():
            i = tuple(int(k) for k in np.unravel_index(int(np.flatnonzero(bad.ravel())[0]), a.shape))
            if a.ndim == 0:
                raise ValueError(f"{name} holds NaN or inf ({float(a)!r})")
            where = i[0] if len(i) == 1 else i
            raise ValueError(f"{name} holds NaN or inf ({float(a[i])!r}) at index {where}")
    return a


#: A decimal number as a data file writes it: optional sign, digits with an optional
#: point, optional exponent; also nan/inf (so that the caller can name them).  Python's
#: ``float()`` also accepts ``1_000`` and surrounding whitespace of any kind; files are
#: read strictly, so ``0.00_2`` is an error, never 0.002.
_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?|[+-]?(?:nan|inf|infinity)",
                     re.IGNORECASE | re.ASCII)


def number_text(name: str, s: str, *, finite: bool = True) -> float:
    """The number a text cell holds (a CSV field, a ``# key: value`` line), strictly.

    Leading and trailing spaces are ignored; anything else that is not a plain decimal
    number (``1_000``, ``0x10``, ``1,5``, an empty cell) raises :class:`ValueError`
    naming ``name``.  ``finite`` refuses NaN and +-inf (and magnitudes beyond double
    precision, which ``float`` would turn into inf).

    Examples
    --------
    >>> number_text("torque", " -1.5e-3 ")
    -0.0015
    >>> number_text("torque", "0.00_2")
    Traceback (most recent call last):
    ...
    ValueError: torque: not a number: '0.00_2'
    """
    if not isinstance(s, str):
        raise ValueError(f"{name}: expected text, got {type(s).__name__}")
    cell = s.strip(" \t")
    if not _NUMBER.fullmatch(cell):
        raise ValueError(f"{name}: not a number: {_describe(cell)}")
    x = float(cell)
    if finite and not math.isfinite(x):
        what = "NaN" if math.isnan(x) else ("inf" if cell.lstrip("+-")[:1].lower() == "i"
                                             else "beyond double precision")
        raise ValueError(f"{name}: {what} (not a finite number)")
    return x


class _Constant:
    """Stands for a NaN/Infinity token until :func:`strict_json` knows under which key it is."""

    def __init__(self, token):
        self.token = token


def _find_constant(x, path=""):
    """(path, token) of the first :class:`_Constant` in a parsed document, or None."""
    if isinstance(x, _Constant):
        return path, x.token
    items = x.items() if isinstance(x, dict) else enumerate(x) if isinstance(x, list) else ()
    for key, item in items:
        sub = (f"{path}.{key}" if path else str(key)) if isinstance(x, dict) else f"{path}[{key}]"
        found = _find_constant(item, sub)
        if found:
            return found
    return None


def _parse_int(digits: str) -> int:
    # beyond 309 digits a number overflows a double; the caller's check names the key up to
    # 1000 digits, longer ones are refused here (Python's own limit is a 4300-digit error)
    if len(digits.lstrip("-")) > 1000:
        raise ValueError(f"an integer of {len(digits.lstrip('-'))} digits is not a usable number")
    return int(digits)


def _no_duplicates(pairs):
    out = {}
    for key, value in pairs:
        if key in out:
            raise ValueError(f"duplicate key {key!r}")
        out[key] = value
    return out


def _depth(text: str) -> int:
    """Deepest bracket nesting of a JSON text, outside strings."""
    depth = deepest = 0
    in_string = escaped = False
    for ch in text:
        if in_string:
            if escaped:
                escaped = False
            elif ch == "\\":
                escaped = True
            elif ch == '"':
                in_string = False
        elif ch == '"':
            in_string = True
        elif ch in "[{":
            depth += 1
            deepest = max(deepest, depth)
        elif ch in "]}":
            depth -= 1
    return deepest


def json_file(path, what: str, parse):
    """``parse(text)`` of the JSON file ``path`` (a fricctl file: ``what`` says which), its
    errors naming the file.

    Raises
    ------
    IsADirectoryError
        ``path`` is a folder ("a folder, not a {what}").
    FileNotFoundError
        No such file ("no such {what}").
    ValueError
        Not UTF-8 text, or whatever ``parse`` refuses, prefixed with the file's name.
    """
    from pathlib import Path

    path = Path(path)
    if path.is_dir():  # "no such model file" sent the user looking for a file that is there
        raise IsADirectoryError(21, f"a folder, not a {what}", str(path))
    if not path.is_file():
        raise FileNotFoundError(2, f"no such {what}", str(path))
    try:
        document = path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise ValueError(f"{path.name}: not a UTF-8 text file (a {what} is JSON)") from None
    try:
        return parse(document)
    except ValueError as exc:
        raise ValueError(f"{path.name}: {exc}") from None


def strict_json(document: str, *, max_depth: int):
    """Parse the JSON text of a fricctl file (model file, network file) strictly.

    Refused, each as a :class:`ValueError` (never a RecursionError or OverflowError):
    text that is not JSON, a duplicate key (``json`` keeps the last one silently),
    ``NaN``/``Infinity``, an integer of more than 1000 digits, and nesting deeper than
    ``max_depth`` (checked before parsing, so a hostile file cannot exhaust the stack).
    What the values mean is the caller's check (use :func:`real` / :func:`json_numbers`:
    they refuse booleans and numbers beyond double precision, naming the key).

    Examples
    --------
    >>> strict_json('{"a": [1, 2.5]}', max_depth=2)
    {'a': [1, 2.5]}
    >>> strict_json('{"a": 1, "a": 2}', max_depth=2)
    Traceback (most recent call last):
    ...
    ValueError: duplicate key 'a'
    """
    document = text("document", document)
    max_depth = integer("max_depth", max_depth, low=1)
    if _depth(document) > max_depth:
        raise ValueError(f"JSON nested deeper than {max_depth} levels (not this kind of file)")
    try:
        data = json.loads(document, object_pairs_hook=_no_duplicates, parse_constant=_Constant,
                          parse_int=_parse_int)
    except json.JSONDecodeError as exc:
        raise ValueError(f"not valid JSON ({exc.msg} at line {exc.lineno})") from None
    except RecursionError:  # pragma: no cover - the depth check comes first
        raise ValueError("JSON nested too deeply") from None
    found = _find_constant(data)
    if found:
        where, token = found
        raise ValueError(f"{where or 'the document'}: {token} is not a number (JSON has no NaN "
                         f"or Infinity)")
    return data


def json_numbers(name: str, x, *, shape: tuple = ()) -> np.ndarray:
    """A number or nested list of numbers parsed from JSON, as a float array of ``shape``.

    Every leaf must be a JSON number (``int`` or ``float``, never ``true``/``false``, a
    string or ``null``) within double precision; the message names the element
    (``w1[2][0]``).  ``shape=()`` is one number (returned as a 0-d array); a ``None``
    in ``shape`` accepts any length of at least 1 (``(None, 2)``: rows of two).

    Examples
    --------
    >>> json_numbers("b1", [0.5, 1], shape=(2,)).tolist()
    [0.5, 1.0]
    >>> json_numbers("b1", [0.5, True], shape=(2,))
    Traceback (most recent call last):
    ...
    ValueError: b1[1] must be a real number, got True
    """
    shape = tuple(shape)

    def walk(label, item, dims):
        if not dims:
            if not isinstance(item, (int, float)) or isinstance(item, bool):
                raise ValueError(f"{label} must be a real number, got {_describe(item)}")
            return real(label, item)
        if not isinstance(item, list):
            n = "" if dims[0] is None else f"{dims[0]} "
            raise ValueError(f"{label} must be a list of {n}"
                             f"{'numbers' if len(dims) == 1 else 'lists'}, got {_describe(item)}")
        if dims[0] is None and not item:
            raise ValueError(f"{label} must not be empty")
        if dims[0] is not None and len(item) != dims[0]:
            raise ValueError(f"{label} must have {dims[0]} entries, got {len(item)}")
        return [walk(f"{label}[{i}]", e, dims[1:]) for i, e in enumerate(item)]

    out = np.array(walk(name, x, shape), dtype=float)
    if out.ndim != len(shape):  # ragged rows under a None length
        raise ValueError(f"{name} must be a rectangular array (rows of equal length)")
    return out
