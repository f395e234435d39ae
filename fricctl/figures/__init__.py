"""Figures: the only part of fricctl that imports matplotlib.

Every function is ``plot_*(result, *, ax=None) -> Axes`` (or a Figure for
multi-panel plots): it labels every axis with symbol and unit, draws held
inputs with ``drawstyle="steps-post"`` and never calls ``show()`` or
``savefig()``.  One submodule per topic; all are re-exported here.
"""

from __future__ import annotations

import importlib

_SUBMODULES = ("core", "design", "measure", "network", "paper", "diagnosis")

__all__: list[str] = []
for _name in _SUBMODULES:
    try:
        _mod = importlib.import_module(f".{_name}", __name__)
    except ModuleNotFoundError as _exc:
        if _exc.name == f"{__name__}.{_name}":
            continue
        raise
    for _fn in getattr(_mod, "__all__", ()):
        globals()[_fn] = getattr(_mod, _fn)
        __all__.append(_fn)
