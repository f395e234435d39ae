"""Friction compensators behind one interface (paper Eq. 3).

At sample k the compensator returns a friction estimate ``T^at(k)`` from the
motor torque ``Tm(k)`` applied over the current interval and the measured
velocity ``omega_hat(k)``; the loop then commands

    Tm(k+1) = clip(Tc(k) + s * T^at(k), -Tmax, +Tmax)

with ``s`` the compensator's ``scale`` (1, or 0.95 for the aged actuator of
Fig. 16).  Three kinds:

* :class:`NoCompensation` -- ``T^at = 0``;
* :class:`CoulombCompensator` -- ``Fc*sign(omega_hat)`` with an optional velocity
  dead band (the classic model-based compensator the paper compares against);
* :class:`NNCompensator` -- any estimator ``(Tm, omega) -> T^at``; a
  :class:`fricctl.nn.FrictionNet` runs inside the compiled loop, any other
  callable through the (slower) Python loop.

Each has ``__call__(tm, omega_hat)`` (vectorised numpy) and ``compiled()``,
which returns the kernel's ``(kind, parameter vector)`` or ``None``.  The
network's parameter vector and its offsets are :mod:`fricctl.nn.layout`'s
(:func:`~fricctl.nn.layout.pack_compiled`, evaluated by
:func:`~fricctl.nn.layout.forward_packed`).
"""

from __future__ import annotations

from dataclasses import KW_ONLY, dataclass
from typing import Callable

import numpy as np

from . import _validate as v
from .netlayout import NET_ATTRIBUTES, pack_compiled

__all__ = ["Compensator", "NoCompensation", "CoulombCompensator", "NNCompensator",
           "CompiledCompensator", "COMP_NONE", "COMP_COULOMB", "COMP_NN"]

COMP_NONE, COMP_COULOMB, COMP_NN = 0, 1, 2


@dataclass(frozen=True, kw_only=True, eq=False)
class CompiledCompensator:
    """What the compiled loop needs of a compensator: its kind and its parameter vector."""

    kind: int
    """:data:`COMP_NONE`, :data:`COMP_COULOMB` or :data:`COMP_NN`."""
    params: np.ndarray
    """Parameters in the kind's layout (Coulomb: pos, neg, dead band; NN: :mod:`fricctl.nn.layout`)."""


class Compensator:
    """Interface: ``scale`` and ``__call__(tm, omega_hat) -> T^at`` [N*m]."""

    scale: float = 1.0
    name: str = "compensator"
    #: Kind of axis the compensator was made for (``"rotary"``, ``"linear"``); None: any.
    units: str | None = None

    def __call__(self, tm, omega_hat):  # pragma: no cover - abstract
        raise NotImplementedError

    def compiled(self):
        """A :class:`CompiledCompensator` for the compiled loop, or ``None`` (Python loop)."""
        return None


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
        return CompiledCompensator(kind=COMP_NONE, params=np.zeros(1))


@dataclass(frozen=True, kw_only=True)
class CoulombCompensator(Compensator):
    """``T^at = Fc_pos`` if ``omega_hat > deadband``, ``-Fc_neg`` if below ``-deadband``, else 0.

    Parameters
    ----------
    coulomb_pos, coulomb_neg : float
        Compensated Coulomb levels, positive magnitudes [N*m].
    deadband : float
        Velocity dead band [rad/s]; 0 = pure sign function (chatters at rest).
    scale : float
        Compensation scale s [-].
    """

    coulomb_pos: float = 0.0
    """Level for positive velocity [N*m]."""
    coulomb_neg: float = 0.0
    """Magnitude of the level for negative velocity [N*m]."""
    deadband: float = 0.0
    """Velocity dead band [rad/s]."""
    scale: float = 1.0
    """Compensation scale s [-]."""
    name: str = "Coulomb"
    """Label in results and plots."""

    def __post_init__(self):
        for name in ("coulomb_pos", "coulomb_neg", "deadband", "scale"):
            v.real(name, getattr(self, name), nonneg=True)
        v.text("name", self.name)

    @classmethod
    def symmetric(cls, level: float, *, deadband: float = 0.0, scale: float = 1.0):
        """The same level ``level`` [N*m] in both directions."""
        return cls(coulomb_pos=level, coulomb_neg=level, deadband=deadband, scale=scale)

    def __call__(self, tm, omega_hat):
        w = np.asarray(omega_hat, dtype=float)
        return np.where(w > self.deadband, self.coulomb_pos,
                        np.where(w < -self.deadband, -self.coulomb_neg, 0.0)) + 0.0 * np.asarray(tm)

    def compiled(self):
        return CompiledCompensator(kind=COMP_COULOMB,
                                   params=np.array([self.coulomb_pos, self.coulomb_neg, self.deadband]))


@dataclass(frozen=True)
class NNCompensator(Compensator):
    """Neural (or any learned) friction compensation ``s * T^at(Tm, omega_hat)``.

    Parameters
    ----------
    estimator : callable
        ``estimator(tm, omega) -> T^at`` [N*m], vectorised.  A
        :class:`fricctl.nn.FrictionNet` (or any object with its weight and
        scaling attributes, :data:`fricctl.nn.layout.NET_ATTRIBUTES`) is evaluated
        inside the compiled loop.  The only positional argument.
    scale : float
        s [-]: 1 for the trained actuator, 0.95 for the aged one (Fig. 16,
        without retraining).
    clip : bool
        Clip the inputs to the net's training envelope before evaluation.
    """

    estimator: Callable
    """``(tm [N*m], omega [rad/s]) -> T^at [N*m]``, vectorised."""
    _: KW_ONLY
    scale: float = 1.0
    """Compensation scale s [-]."""
    clip: bool = False
    """Clip the inputs to the net's training envelope (nets only)."""
    name: str = "NN"
    """Label in results and plots."""

    def __post_init__(self):
        if not callable(self.estimator):
            raise ValueError("estimator must be callable (tm, omega) -> friction estimate")
        v.real("scale", self.scale, nonneg=True)
        v.flag("clip", self.clip)
        v.text("name", self.name)

    def _is_net(self) -> bool:
        return all(hasattr(self.estimator, a) for a in NET_ATTRIBUTES)

    @property
    def units(self) -> str | None:
        """The axis the network was trained on (:attr:`fricctl.nn.FrictionNet.units`); None
        for an estimator that does not say."""
        kind = getattr(self.estimator, "units", None)
        return kind if isinstance(kind, str) else None

    def __call__(self, tm, omega_hat):
        if self.clip and self._is_net():
            return np.asarray(self.estimator(tm, omega_hat, clip=True), dtype=float)
        return np.asarray(self.estimator(tm, omega_hat), dtype=float)

    def compiled(self):
        if not self._is_net():
            return None
        return CompiledCompensator(kind=COMP_NN, params=pack_compiled(self.estimator, self.clip))
