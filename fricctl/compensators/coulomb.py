"""Coulomb compensation ``T^at = Fc*sign(omega_hat)`` with a velocity dead band, at the
identified sliding (Coulomb) level or at the breakaway level (the classic model-based
compensator the paper compares against, Sec. 5 and Fig. 17)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _validate as v
from .base import Compensator, CompiledCompensator, Entry, friction_of

__all__ = ["CoulombCompensator", "ENTRY", "LEVELS"]

#: Kind id in the compiled loop.
KIND = 1
#: Where :meth:`CoulombCompensator.from_model` reads its level.
LEVELS = ("coulomb", "breakaway")


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

    @classmethod
    def from_model(cls, model, *, level: str = "coulomb", deadband: float = 0.0,
                   scale: float = 1.0) -> "CoulombCompensator":
        """The compensator at the identified model's level, per direction.

        Parameters
        ----------
        model : JointModel, ActuatorParams, FrictionModel or FrictionLaw
            The identified model (its friction scale applied).
        level : {"coulomb", "breakaway"}
            ``"coulomb"``: the sliding level Fc (:meth:`FrictionModel.sliding_level`);
            ``"breakaway"``: the breakaway level Fs (:meth:`FrictionModel.breakaway` at rest,
            Coulomb + Stribeck + static excess + load at zero torque), which over-compensates
            while sliding and so chatters sooner.
        deadband : float
            Velocity dead band [rad/s].
        scale : float
            Compensation scale s [-].

        Examples
        --------
        >>> from fricctl.params import paper_actuator
        >>> c = CoulombCompensator.from_model(paper_actuator(), level="breakaway")
        >>> round(c.coulomb_pos, 4), round(c.coulomb_neg, 4)
        (0.18, 0.18)
        """
        fr = friction_of(model)
        v.choice("level", level, LEVELS)
        if level == "coulomb":
            pos, neg = fr.sliding_level(1), fr.sliding_level(-1)
        else:
            pos, neg = float(fr.breakaway(1)), float(fr.breakaway(-1))
        if pos <= 0.0 and neg <= 0.0:
            raise ValueError(f"the model has no {level} level (0 in both directions): a "
                             "Coulomb compensation would add nothing")
        return cls(coulomb_pos=pos, coulomb_neg=neg, deadband=deadband, scale=scale,
                   name="Coulomb" if level == "coulomb" else "Coulomb (breakaway)")

    def __call__(self, tm, omega_hat):
        w = np.asarray(omega_hat, dtype=float)
        return np.where(w > self.deadband, self.coulomb_pos,
                        np.where(w < -self.deadband, -self.coulomb_neg, 0.0)) + 0.0 * np.asarray(tm)

    def compiled(self):
        return CompiledCompensator(kind=KIND,
                                   params=np.array([self.coulomb_pos, self.coulomb_neg, self.deadband]))


def step(p, wh):
    """Memoryless: ``p = (Fc_pos, Fc_neg, dead band)``."""
    if wh > p[2]:
        return p[0]
    if wh < -p[2]:
        return -p[1]
    return 0.0


def _make(model, design, sample_time, *, level: str = "coulomb", deadband: float = 0.0,
          scale: float = 1.0):
    return CoulombCompensator.from_model(model, level=level, deadband=deadband, scale=scale)


ENTRY = Entry(name="coulomb", kind=KIND, cls=CoulombCompensator, make=_make, step=step,
              description="Fc*sign(omega_hat) at the model's Coulomb (or breakaway) level")
