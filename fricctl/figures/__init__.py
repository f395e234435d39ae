"""Figures: the only part of fricctl that imports matplotlib.

Every function is ``plot_*(result, *, ax=None) -> Axes`` (or a Figure for
multi-panel plots): it labels every axis with symbol and unit, draws held
inputs with ``drawstyle="steps-post"`` and never calls ``show()`` or
``savefig()``.  One submodule per topic; all are re-exported here.

The submodules are imported by name, so that a missing or broken one fails the
import with its own error (nothing is skipped).
"""

from __future__ import annotations

from . import core, design, diagnosis, diagram, identification, measure, network, paper

_SUBMODULES = (core, design, measure, network, paper, diagnosis, diagram, identification)

__all__ = [name for module in _SUBMODULES for name in module.__all__]
globals().update({name: getattr(module, name) for module in _SUBMODULES for name in module.__all__})
