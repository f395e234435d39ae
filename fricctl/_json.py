"""Numbers made safe for standard JSON: the one place that decides what a NaN, an infinity,
a NumPy scalar or array becomes in fricctl's JSON output.

Standard JSON (``json.dumps(..., allow_nan=False)``) has no NaN or infinity and no NumPy
types.  :func:`finite_or_none` makes one number safe; :func:`json_safe` a nested summary,
and tells its caller the path of every value it writes as null (``undefined``), so that
the caller can say why (``fricctl.cli._output.json_text``, :meth:`Diagnosis.as_dict
<fricctl.diagnose.Diagnosis.as_dict>`).  The reader of fricctl's JSON files is
:func:`fricctl._validate.strict_json`.

Examples
--------
>>> json_safe({"a": np.float64(1.5), "b": [float("nan"), np.int64(2)], "c": np.array([1.0])})
{'a': 1.5, 'b': [None, 2], 'c': [1.0]}
>>> finite_or_none(np.float32(0.5)), finite_or_none(float("inf")), finite_or_none(None)
(0.5, None, None)
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np

__all__ = ["finite_or_none", "json_safe"]


def finite_or_none(x) -> float | None:
    """``x`` as a Python float, or None when it is None, NaN or infinite."""
    if x is None:
        return None
    x = float(x)
    return x if math.isfinite(x) else None


def json_safe(obj, undefined: Callable[[str, float | None], None] | None = None,
              path: str = ""):
    """``obj`` with every value standard JSON cannot hold replaced, recursively.

    A dict keeps its keys, a list or tuple becomes a list, a NumPy array its nested list;
    NumPy booleans and integers become Python ones; a float (NumPy floating included)
    becomes a Python float, or None when it is NaN or infinite; anything else is kept.

    Parameters
    ----------
    obj : object
        Nested dicts, lists, tuples, arrays, numbers, strings, None.
    undefined : callable, optional
        ``undefined(path, value)`` is called for every number written as null (``value``
        the number as a float: ``nan``, ``inf``, ``-inf``) and for every None of ``obj``
        (``value`` None); ``path`` is the place as ``"a.b[0]"``.
    path : str
        The path of ``obj`` itself (``""`` at the top).
    """
    if isinstance(obj, dict):
        return {k: json_safe(x, undefined, f"{path}.{k}" if path else str(k))
                for k, x in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [json_safe(x, undefined, f"{path}[{i}]") for i, x in enumerate(obj)]
    if isinstance(obj, np.ndarray):
        return json_safe(obj.tolist(), undefined, path)
    if isinstance(obj, np.bool_):
        return bool(obj)
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        x = finite_or_none(obj)
        if x is None and undefined is not None:
            undefined(path, float(obj))
        return x
    if obj is None and undefined is not None:
        undefined(path, None)
    return obj
