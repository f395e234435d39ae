"""Figures: the only part of fricctl that imports matplotlib.

Every function is ``plot_*(result, *, ax=None) -> Axes`` (or a Figure for
multi-panel plots): it labels every axis with symbol and unit, draws held
inputs with ``drawstyle="steps-post"`` and never calls ``show()`` or
``savefig()``.  One submodule per topic; all are re-exported here.

A submodule is imported when one of its names is first asked for (PEP 562): ``fricctl
diagnose --report`` draws with :mod:`.diagnosis` alone and does not pay for the control
design and paper modules (0.3 s of a 40 s record's 10 s budget).  The table below names
each function's module; ``tests/test_figures_core.py`` checks it against every submodule's
``__all__``, and a broken submodule fails with its own error when it is imported.
"""

from __future__ import annotations

import importlib

#: The submodules, in the order their names are listed.
SUBMODULES = ("core", "design", "measure", "network", "paper", "diagnosis", "diagram",
              "identification", "compare")

_WHERE = {
    "core": ("plot_response", "plot_torques", "plot_friction_law", "plot_stuck",
             "plot_dead_zone"),
    "design": ("plot_root_locus", "plot_step"),
    "measure": ("plot_velocity_estimates", "plot_identification"),
    "network": ("plot_friction_map", "plot_training_history", "plot_fit"),
    "paper": ("plot_fig4", "plot_fig5", "plot_fig8", "plot_fig9", "plot_fig10", "plot_fig11",
              "plot_fig12", "plot_fig13", "plot_fig14", "plot_fig16", "plot_fig17",
              "plot_fig18", "plot_sweep", "plot_coast", "PAPER_PLOTS", "paper_plot"),
    "diagnosis": ("plot_simulation", "plot_residual", "plot_residual_spectrum", "plot_steps",
                  "plot_diagnosis"),
    "diagram": ("plot_compensation_loop",),
    "identification": ("plot_held_out", "plot_validation"),
    "compare": ("plot_comparison",),
}

_MODULE_OF = {name: module for module, names in _WHERE.items() for name in names}

__all__ = [name for module in SUBMODULES for name in _WHERE[module]]


def __getattr__(name: str):
    module = _MODULE_OF.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
