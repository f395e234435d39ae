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

import math
import numbers
from typing import Iterable

import numpy as np

__all__ = ["real", "integer", "flag", "choice", "rng", "array", "instance", "text",
           "is_real_scalar"]

#: Numbers larger than this are refused as "not a usable magnitude" (about 1e300):
#: their squares and products overflow double precision.
HUGE = 1e300


def _describe(v) -> str:
    r = repr(v)
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
        raise ValueError(f"{name} must hold real numbers, got an array of dtype {raw.dtype}")
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
            i = np.unravel_index(int(np.flatnonzero(bad.ravel())[0]), a.shape)
            if a.ndim == 0:
                raise ValueError(f"{name} holds NaN or inf ({float(a)!r})")
            where = i[0] if len(i) == 1 else i
            raise ValueError(f"{name} holds NaN or inf ({float(a[i])!r}) at index {where}")
    return a
