"""No compensation: ``T^at = 0`` (the paper's uncompensated PD, Figs. 9-11)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _validate as v
from .base import Compensator, CompiledCompensator, Entry

__all__ = ["NoCompensation", "ENTRY"]

#: Kind id in the compiled loop.
KIND = 0


@dataclass(frozen=True, kw_only=True)
class NoCompensation(Compensator):
    """No compensation: ``Tm(k+1) = Tc(k)``."""

    scale: float = 1.0
    """Compensation scale s (no effect here) [-]."""
    name: str = "none"
    """Label in results and plots."""

    def __post_init__(self):
        v.real("scale", self.scale, nonneg=True)
        v.text("name", self.name)

    def __call__(self, tm, omega_hat):
        return np.zeros(np.broadcast(np.asarray(tm), np.asarray(omega_hat)).shape)

    def compiled(self):
        return CompiledCompensator(kind=KIND, params=np.zeros(1))


def _make(model, design, sample_time, *, scale: float = 1.0):
    return NoCompensation(scale=scale)


ENTRY = Entry(name="none", kind=KIND, cls=NoCompensation, make=_make,
              description="no compensation: the PD alone")
