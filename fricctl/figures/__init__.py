"""Figures: the only part of fricctl that imports matplotlib.

Every function is ``plot_*(result, *, ax=None) -> Axes`` (or a Figure for
multi-panel plots): it labels every axis with symbol and unit, draws held
inputs with ``drawstyle="steps-post"`` and never calls ``show()`` or
``savefig()``.  One submodule per topic; all are re-exported here.

The submodules are imported by name, so that a missing or broken one fails the
import with its own error (nothing is skipped).
"""

from __future__ import annotations

from . import core, design, diagnosis, measure, network, paper
from .core import plot_dead_zone, plot_friction_law, plot_response, plot_stuck, plot_torques
from .design import plot_root_locus, plot_step
from .diagnosis import plot_diagnosis, plot_residual, plot_residual_spectrum, plot_simulation
from .measure import plot_identification, plot_velocity_estimates
from .network import plot_fit, plot_friction_map, plot_training_history
from .paper import (PAPER_PLOTS, paper_plot, plot_fig4, plot_fig5, plot_fig8, plot_fig9, plot_fig10,
                    plot_fig11, plot_fig12, plot_fig13, plot_fig14, plot_fig16, plot_fig17, plot_fig18,
                    plot_sweep)

_SUBMODULES = (core, design, measure, network, paper, diagnosis)

__all__ = [name for module in _SUBMODULES for name in module.__all__]
