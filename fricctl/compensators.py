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
which returns the kernel's ``(kind, parameter vector)`` or ``None``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

__all__ = ["Compensator", "NoCompensation", "CoulombCompensator", "NNCompensator",
           "COMP_NONE", "COMP_COULOMB", "COMP_NN"]

COMP_NONE, COMP_COULOMB, COMP_NN = 0, 1, 2


def _nonneg(name, v):
    if isinstance(v, bool) or not isinstance(v, (int, float, np.floating)) or not math.isfinite(v) or v < 0:
        raise ValueError(f"{name} must be a finite number >= 0, got {v!r}")
    return float(v)


class Compensator:
    """Interface: ``scale`` and ``__call__(tm, omega_hat) -> T^at`` [N*m]."""

    scale: float = 1.0
    name: str = "compensator"

    def __call__(self, tm, omega_hat):  # pragma: no cover - abstract
        raise NotImplementedError

    def compiled(self):
        """``(kind, params)`` for the compiled loop, or ``None`` (Python loop)."""
        return None


@dataclass(frozen=True)
class NoCompensation(Compensator):
    """No compensation: ``Tm(k+1) = Tc(k)``."""

    scale: float = 1.0
    name: str = "none"

    def __post_init__(self):
        _nonneg("scale", self.scale)

    def __call__(self, tm, omega_hat):
        return np.zeros(np.broadcast(np.asarray(tm), np.asarray(omega_hat)).shape)

    def compiled(self):
        return COMP_NONE, np.zeros(1)


@dataclass(frozen=True)
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
    coulomb_neg: float = 0.0
    deadband: float = 0.0
    scale: float = 1.0
    name: str = "Coulomb"

    def __post_init__(self):
        _nonneg("coulomb_pos", self.coulomb_pos)
        _nonneg("coulomb_neg", self.coulomb_neg)
        _nonneg("deadband", self.deadband)
        _nonneg("scale", self.scale)

    @classmethod
    def symmetric(cls, level: float, *, deadband: float = 0.0, scale: float = 1.0):
        return cls(coulomb_pos=level, coulomb_neg=level, deadband=deadband, scale=scale)

    def __call__(self, tm, omega_hat):
        w = np.asarray(omega_hat, dtype=float)
        return np.where(w > self.deadband, self.coulomb_pos,
                        np.where(w < -self.deadband, -self.coulomb_neg, 0.0)) + 0.0 * np.asarray(tm)

    def compiled(self):
        return COMP_COULOMB, np.array([self.coulomb_pos, self.coulomb_neg, self.deadband])


_NET_ATTRS = ("w1", "b1", "w2", "b2", "input_offset", "input_scale", "output_offset",
              "output_scale", "envelope_low", "envelope_high")


@dataclass(frozen=True)
class NNCompensator(Compensator):
    """Neural (or any learned) friction compensation ``s * T^at(Tm, omega_hat)``.

    Parameters
    ----------
    estimator : callable
        ``estimator(tm, omega) -> T^at`` [N*m], vectorised.  A
        :class:`fricctl.nn.FrictionNet` is evaluated inside the compiled loop.
    scale : float
        s [-]: 1 for the trained actuator, 0.95 for the aged one (Fig. 16,
        without retraining).
    clip : bool
        Clip the inputs to the net's training envelope before evaluation.
    """

    estimator: Callable
    scale: float = 1.0
    clip: bool = False
    name: str = "NN"

    def __post_init__(self):
        if not callable(self.estimator):
            raise ValueError("estimator must be callable (tm, omega) -> friction estimate")
        _nonneg("scale", self.scale)

    def __call__(self, tm, omega_hat):
        if self.clip and hasattr(self.estimator, "envelope_low"):
            return np.asarray(self.estimator(tm, omega_hat, clip=True), dtype=float)
        return np.asarray(self.estimator(tm, omega_hat), dtype=float)

    def compiled(self):
        net = self.estimator
        if not all(hasattr(net, a) for a in _NET_ATTRS):
            return None
        w1 = np.asarray(net.w1, dtype=float)
        h = w1.shape[0]
        head = np.concatenate([
            [h], np.asarray(net.input_offset, float), np.asarray(net.input_scale, float),
            [float(net.output_offset), float(net.output_scale), 1.0 if self.clip else 0.0],
            np.asarray(net.envelope_low, float), np.asarray(net.envelope_high, float),
            [float(net.b2)]])
        return COMP_NN, np.concatenate([head, w1.ravel(), np.asarray(net.b1, float),
                                        np.asarray(net.w2, float)])
