""":class:`FrictionModel`, the sum of friction laws, and :class:`FrictionLaw`, their base.

See :mod:`fricctl.friction` for the sign convention and the laws.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields, replace

import numpy as np

from .. import _validate as v
from .layout import FIELDS

__all__ = ["FrictionLaw", "FrictionModel", "DEFAULTS"]


class FrictionLaw:
    """Base of the elementary laws; adding laws (``Viscous(b) + Coulomb(Fc)``) gives a
    :class:`FrictionModel`.

    A law says which coefficients of the model it sets (:meth:`contribution`) and may
    refuse to be added to a model it cannot share (:meth:`check_compatible`).
    """

    def contribution(self) -> dict:  # pragma: no cover - abstract
        """``{field: value}`` this law adds to (or sets in) a model."""
        raise NotImplementedError

    def check_compatible(self, model: "FrictionModel") -> None:
        """Raise ``ValueError`` if this law cannot be added to ``model``."""

    def model(self) -> "FrictionModel":
        """The model holding this law alone."""
        return FrictionModel().add(self)

    def __add__(self, other):
        return self.model() + other

    def __radd__(self, other):
        if other == 0:  # sum([...]) support
            return self.model()
        return NotImplemented

    def torque(self, omega, q=0.0, tm=0.0, t=0.0):
        """:meth:`FrictionModel.torque` of this law alone [N*m]."""
        return self.model().torque(omega, q, tm, t)

    def breakaway(self, direction=1, q=0.0, tm=0.0, t=0.0):
        """:meth:`FrictionModel.breakaway` of this law alone [N*m]."""
        return self.model().breakaway(direction, q, tm, t)


def _out(x):
    """A 0-d result as a Python float, arrays unchanged."""
    x = np.asarray(x, dtype=float)
    return float(x) if x.ndim == 0 else x


#: Coefficients that add when two laws or models are summed.
_ADDITIVE = frozenset({"viscous_pos", "viscous_neg", "coulomb_pos", "coulomb_neg", "static_pos",
                       "static_neg", "stribeck_pos", "stribeck_neg", "load_coefficient"})
#: Coefficients that may be negative.
_SIGNED = frozenset({"ripple_phase", "drift"})


def _broadcast(**arrays) -> None:
    """Refuse inputs whose shapes do not broadcast together (naming them)."""
    try:
        np.broadcast_shapes(*(a.shape for a in arrays.values()))
    except ValueError:
        shapes = ", ".join(f"{k} {a.shape}" for k, a in arrays.items())
        raise ValueError(f"the inputs' shapes do not broadcast: {shapes}") from None


def _finite(what: str, x: np.ndarray) -> np.ndarray:
    """``x`` if finite; else a ValueError (finite inputs and coefficients <= 1e300 can overflow)."""
    if not np.all(np.isfinite(x)):
        raise ValueError(f"the {what} overflows double precision for these inputs "
                         f"(coefficients x velocity beyond 1e308 N*m)")
    return x


def _direction(direction) -> int:
    if isinstance(direction, bool) or direction not in (1, -1):
        raise ValueError(f"direction must be +1 or -1, got {direction!r}")
    return int(direction)


@dataclass(frozen=True, kw_only=True)
class FrictionModel:
    """Sum of friction laws, stored as named coefficients (load side, SI).

    Build it by adding laws (``Viscous(b) + Coulomb(Fc)``), not field by field.
    ``scale`` multiplies every friction term (not the position ripple);
    ``drift`` makes that scale change linearly in time:
    ``scale(t) = scale * (1 + drift*t)``.
    """

    viscous_pos: float = field(default=0.0, metadata={"unit": "N*m*s/rad"})
    viscous_neg: float = field(default=0.0, metadata={"unit": "N*m*s/rad"})
    coulomb_pos: float = field(default=0.0, metadata={"unit": "N*m"})
    coulomb_neg: float = field(default=0.0, metadata={"unit": "N*m"})
    static_pos: float = field(default=0.0, metadata={"unit": "N*m"})
    static_neg: float = field(default=0.0, metadata={"unit": "N*m"})
    stribeck_pos: float = field(default=0.0, metadata={"unit": "N*m"})
    stribeck_neg: float = field(default=0.0, metadata={"unit": "N*m"})
    stribeck_velocity: float = field(default=1.0, metadata={"unit": "rad/s"})
    stribeck_exponent: float = field(default=2.0, metadata={"unit": "-"})
    ripple_amplitude: float = field(default=0.0, metadata={"unit": "N*m"})
    ripple_period: float = field(default=0.0, metadata={"unit": "rad"})
    ripple_phase: float = field(default=0.0, metadata={"unit": "rad"})
    load_coefficient: float = field(default=0.0, metadata={"unit": "-"})
    scale: float = field(default=1.0, metadata={"unit": "-"})
    drift: float = field(default=0.0, metadata={"unit": "1/s"})
    lugre_sigma0: float = field(default=0.0, metadata={"unit": "N*m/rad"})
    lugre_sigma1: float = field(default=0.0, metadata={"unit": "N*m*s/rad"})

    def __post_init__(self):
        for f in fields(self):
            x = v.real(f.name, getattr(self, f.name), nonneg=f.name not in _SIGNED,
                       unit=f.metadata["unit"])
            object.__setattr__(self, f.name, x)
        if self.stribeck_velocity <= 0 or self.stribeck_exponent <= 0:
            raise ValueError("stribeck_velocity and stribeck_exponent must be > 0")
        if self.ripple_amplitude > 0 and self.ripple_period <= 0:
            raise ValueError("ripple_period must be > 0 when ripple_amplitude > 0")
        if self.lugre_sigma0 > 0 and (self.static_pos > 0 or self.static_neg > 0):
            raise ValueError("LuGre replaces stiction by bristle dynamics: it cannot be combined "
                             "with a Static law (use Stribeck for the breakaway excess)")
        if self.lugre_sigma0 > 0 and min(self.coulomb_pos, self.coulomb_neg) <= 0:
            raise ValueError("LuGre needs a Coulomb level > 0 in both directions (g(omega) > 0)")

    # -- composition -----------------------------------------------------
    def add(self, law) -> "FrictionModel":
        """This model plus a law or another model."""
        new = self.as_dict()
        if isinstance(law, FrictionModel):
            for n in FIELDS:
                x = getattr(law, n)
                if n in _ADDITIVE or n == "drift":
                    new[n] += x
                elif n == "scale":
                    new[n] *= x
                elif x != DEFAULTS[n]:  # shape parameters: the added model's, where it sets them
                    new[n] = x
            return FrictionModel(**new)
        if not isinstance(law, FrictionLaw):
            raise ValueError(f"cannot add {type(law).__name__} to a FrictionModel")
        law.check_compatible(self)
        for k, x in law.contribution().items():
            new[k] = new[k] + x if k in _ADDITIVE else x
        return FrictionModel(**new)

    def __add__(self, other):
        return self.add(other)

    def __radd__(self, other):
        if other == 0:
            return self
        return NotImplemented

    def model(self) -> "FrictionModel":
        """Itself (so laws and models share ``.model()``)."""
        return self

    def scaled(self, factor: float) -> "FrictionModel":
        """Copy with every friction term multiplied by ``factor`` (wear, load)."""
        factor = v.real("scale factor", factor, positive=True)
        return replace(self, scale=self.scale * factor)

    def with_drift(self, drift: float) -> "FrictionModel":
        """Copy whose friction scale changes by ``drift`` (relative) per second."""
        return replace(self, drift=v.real("drift", drift))

    def vector(self) -> np.ndarray:
        """Coefficients in the compiled kernels' layout (:data:`fricctl.friction.layout.FIELDS`)."""
        return np.array([getattr(self, n) for n in FIELDS], dtype=float)

    @property
    def is_lugre(self) -> bool:
        """True when the LuGre presliding law is part of the model."""
        return self.lugre_sigma0 > 0

    def as_dict(self) -> dict:
        """Every coefficient by name (JSON-ready)."""
        return {n: getattr(self, n) for n in FIELDS}

    def changed(self) -> dict:
        """The coefficients that differ from their defaults (an empty model has none)."""
        return {n: getattr(self, n) for n in FIELDS if getattr(self, n) != DEFAULTS[n]}

    @classmethod
    def from_dict(cls, d: dict) -> "FrictionModel":
        """Inverse of :meth:`as_dict`; missing fields take their defaults, unknown ones raise."""
        if not isinstance(d, dict):
            raise ValueError(f"friction must be an object of FrictionModel fields, got {type(d).__name__}")
        unknown = sorted(set(d) - set(FIELDS))
        if unknown:
            raise ValueError(f"unknown friction field(s): {', '.join(unknown)}")
        return cls(**d)

    # -- evaluation (numpy, vectorised) ----------------------------------
    def scale_at(self, t):
        """Friction scale at time ``t``: ``scale*(1 + drift*t)`` [-]."""
        return self.scale * (1.0 + self.drift * v.array("t", t, ndim=None))

    def ripple(self, q):
        """Position-periodic torque at position ``q`` [N*m]."""
        q = v.array("q", q, ndim=None)
        if self.ripple_amplitude == 0:
            return np.zeros_like(q)
        return self.ripple_amplitude * np.sin(2 * np.pi * q / self.ripple_period + self.ripple_phase)

    def torque(self, omega, q=0.0, tm=0.0, t=0.0):
        """Sliding friction torque (plus ripple) at velocity ``omega`` [N*m].

        Inputs are real numbers or arrays that broadcast together; NaN, inf, text,
        booleans and a torque that overflows double precision raise :class:`ValueError`.
        For ``omega == 0`` the friction torque is not a function of velocity (it
        is whatever reaction keeps the joint at rest, up to :meth:`breakaway`);
        this method returns the ripple alone there.  With ``LuGre`` this is
        the steady-state (z at equilibrium) sliding torque.

        Parameters
        ----------
        omega : array_like
            Velocity [rad/s].
        q : array_like
            Position [rad] (ripple only).
        tm : array_like
            Transmitted motor torque [N*m] (load-dependent term only).
        t : array_like
            Time [s] (drift only).
        """
        w = v.array("omega", omega, ndim=None)
        tm = v.array("tm", tm, ndim=None)
        _broadcast(omega=w, q=v.array("q", q, ndim=None), tm=tm, t=v.array("t", t, ndim=None))
        pos = w > 0
        neg = w < 0
        aw = np.abs(w)
        b = np.where(pos, self.viscous_pos, self.viscous_neg)
        fc = np.where(pos, self.coulomb_pos, self.coulomb_neg)
        fs = np.where(pos, self.stribeck_pos, self.stribeck_neg)
        with np.errstate(over="ignore"):  # (|w|/vs)^e -> inf: the Stribeck term's limit is 0
            dip = np.exp(-(aw / self.stribeck_velocity) ** self.stribeck_exponent)
        level = fc + self.load_coefficient * np.abs(tm) + fs * dip
        sgn = pos.astype(float) - neg.astype(float)
        with np.errstate(over="ignore", invalid="ignore"):
            out = self.scale_at(t) * (b * w + sgn * level) + self.ripple(q)
        return _out(_finite("friction torque", out))

    def breakaway(self, direction=1, q=0.0, tm=0.0, t=0.0):
        """Torque the drive must exceed to start moving in ``direction`` (+1/-1) [N*m].

        A positive magnitude.  The position ripple is not included: it adds to
        the drive torque (the joint breaks loose when ``Tm - ripple(q)`` leaves
        ``[-breakaway(-1), breakaway(+1)]``).
        """
        if _direction(direction) > 0:
            base = self.coulomb_pos + self.static_pos + self.stribeck_pos
        else:
            base = self.coulomb_neg + self.static_neg + self.stribeck_neg
        tm = v.array("tm", tm, ndim=None)
        _broadcast(q=v.array("q", q, ndim=None), tm=tm, t=v.array("t", t, ndim=None))
        with np.errstate(over="ignore", invalid="ignore"):
            out = self.scale_at(t) * (base + self.load_coefficient * np.abs(tm))
        return _out(_finite("breakaway torque", out))

    def sliding_level(self, direction=1) -> float:
        """Coulomb level approached at high speed in ``direction`` [N*m] (scale applied)."""
        return self.scale * (self.coulomb_pos if _direction(direction) > 0 else self.coulomb_neg)

    def __str__(self):
        parts = [f"{n}={x:.6g}" for n, x in self.changed().items()]
        return "FrictionModel(" + ", ".join(parts) + ")"


#: Default value of every coefficient (the empty model).
DEFAULTS = {f.name: f.default for f in fields(FrictionModel)}
