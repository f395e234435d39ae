""":class:`FrictionModel`, the sum of friction laws, its fields those of the registered laws.

See :mod:`fricctl.friction` for the sign convention and the laws.
"""

from __future__ import annotations

import math
from dataclasses import field, fields, make_dataclass, replace

import numpy as np

from .. import _validate as v
from .law import FrictionLaw
from .laws import LAWS, laws_with_role
from .layout import COEFFICIENTS, FIELDS

__all__ = ["FrictionLaw", "FrictionModel", "DEFAULTS"]


def _out(x):
    """A 0-d result as a Python float, arrays unchanged."""
    x = np.asarray(x, dtype=float)
    return float(x) if x.ndim == 0 else x


#: How each coefficient combines when two laws or models are summed (its law's declaration).
_COMBINE = {c.name: c.combine for c in COEFFICIENTS}


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


class _FrictionModelBase:
    """Sum of friction laws, stored as named coefficients (load side, SI).

    Build it by adding laws (``Viscous(b) + Coulomb(Fc)``), not field by field.  Its fields
    are the coefficients of the registered laws (:data:`fricctl.friction.laws.LAWS`), each
    with its unit in the field's metadata.  ``scale`` multiplies every friction term (not the
    position ripple); ``drift`` makes that scale change linearly in time:
    ``scale(t) = scale * (1 + drift*t)``.
    """

    def __post_init__(self):
        for c in COEFFICIENTS:
            x = v.real(c.name, getattr(self, c.name), nonneg=c.lower == 0.0 and not c.strict,
                       positive=c.lower == 0.0 and c.strict, unit=c.unit)
            if (c.lower not in (0.0, -math.inf) and (x < c.lower or c.strict and x == c.lower)) \
                    or x > c.upper:
                raise ValueError(f"{c.name} must be in [{c.lower:g}, {c.upper:g}] {c.unit}, got {x!r}")
            object.__setattr__(self, c.name, x)
        for law in LAWS.values():
            if law.check is not None:
                law.check(self)
        active = [law.name for law in laws_with_role("state") if law.active(self)]
        if len(active) > 1:
            raise ValueError(f"a model holds one presliding (state) law, got {', '.join(active)}")

    # -- composition -----------------------------------------------------
    def add(self, law) -> "FrictionModel":
        """This model plus a law or another model."""
        new = self.as_dict()
        if isinstance(law, FrictionModel):
            given = {n: getattr(law, n) for n in FIELDS if getattr(law, n) != DEFAULTS[n]}
        elif isinstance(law, FrictionLaw):
            law.check_compatible(self)
            given = law.contribution()
        else:
            raise ValueError(f"cannot add {type(law).__name__} to a FrictionModel")
        for n, x in given.items():
            how = _COMBINE[n]
            # magnitudes add, a scale multiplies, a shape parameter is the added one's
            new[n] = new[n] + x if how == "add" else new[n] * x if how == "multiply" else x
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
    def state_law(self):
        """The active presliding (state) law of the model (LuGre, Dahl), or None."""
        for law in laws_with_role("state"):
            if law.active(self):
                return law
        return None

    @property
    def has_state(self) -> bool:
        """True when a presliding law with a state (LuGre, Dahl) is part of the model."""
        return self.state_law is not None

    def laws(self) -> tuple:
        """The registered laws this model holds (a coefficient away from its default)."""
        return tuple(law for law in LAWS.values() if law.role != "scale" and law.active(self))

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

    # -- evaluation (numpy, vectorised; each term is its law's) -----------
    def _terms(self, role: str, *args):
        out = 0.0
        for law in laws_with_role(role):
            out = out + law.term(*args, **law.values(self))
        return out

    def scale_at(self, t):
        """Friction scale at time ``t``: ``scale*(1 + drift*t)`` [-]."""
        (law,) = laws_with_role("scale")
        return law.term(v.array("t", t, ndim=None), **law.values(self))

    def ripple(self, q):
        """Position-dependent torque at position ``q`` (the position laws; not scaled) [N*m]."""
        q = v.array("q", q, ndim=None)
        return np.zeros_like(q) + self._terms("position", q)

    def rate_terms(self, omega):
        """The rate laws' torque (viscous, drag) at ``omega``, not scaled [N*m]."""
        w = v.array("omega", omega, ndim=None)
        with np.errstate(over="ignore", invalid="ignore"):
            return self._terms("rate", w, np.sign(w))

    def level(self, omega, direction, tm=0.0):
        """The level laws' magnitude (Coulomb, Stribeck, load) sliding in ``direction``, not scaled [N*m]."""
        w = v.array("omega", omega, ndim=None)
        with np.errstate(over="ignore", invalid="ignore"):
            return self._terms("level", w, direction, v.array("tm", tm, ndim=None))

    def torque(self, omega, q=0.0, tm=0.0, t=0.0):
        """Sliding friction torque (plus ripple) at velocity ``omega`` [N*m].

        Inputs are real numbers or arrays that broadcast together; NaN, inf, text,
        booleans and a torque that overflows double precision raise :class:`ValueError`.
        For ``omega == 0`` the friction torque is not a function of velocity (it
        is whatever reaction keeps the joint at rest, up to :meth:`breakaway`);
        this method returns the ripple alone there.  With a presliding law (LuGre, Dahl)
        this is the steady-state (z at equilibrium) sliding torque.

        Parameters
        ----------
        omega : array_like
            Velocity [rad/s].
        q : array_like
            Position [rad] (position laws only).
        tm : array_like
            Transmitted motor torque [N*m] (load-dependent term only).
        t : array_like
            Time [s] (drift only).
        """
        w = v.array("omega", omega, ndim=None)
        tm = v.array("tm", tm, ndim=None)
        _broadcast(omega=w, q=v.array("q", q, ndim=None), tm=tm, t=v.array("t", t, ndim=None))
        sgn = (w > 0).astype(float) - (w < 0).astype(float)
        with np.errstate(over="ignore", invalid="ignore"):
            level = self._terms("level", w, sgn, tm)
            out = self.scale_at(t) * (self._terms("rate", w, sgn) + sgn * level) + self.ripple(q)
        return _out(_finite("friction torque", out))

    def along_motion(self, q, omega, tm, t):
        """Friction torque along a measured motion (position record ``q``) [N*m].

        Without a presliding law this is :meth:`torque`; with one (LuGre, Dahl) its state is
        integrated along the position record from rest (its law's ``along_motion``), so the
        torque at a reversal follows the bristle, not a jump.
        """
        law = self.state_law
        if law is None:
            return self.torque(omega, q, tm, t)
        return law.state.along_motion(self, v.array("q", q), v.array("omega", omega),
                                      v.array("tm", tm, ndim=None), v.array("t", t, ndim=None))

    def breakaway(self, direction=1, q=0.0, tm=0.0, t=0.0):
        """Torque the drive must exceed to start moving in ``direction`` (+1/-1) [N*m].

        A positive magnitude.  The position ripple is not included: it adds to
        the drive torque (the joint breaks loose when ``Tm - ripple(q)`` leaves
        ``[-breakaway(-1), breakaway(+1)]``).
        """
        s = _direction(direction)
        tm = v.array("tm", tm, ndim=None)
        _broadcast(q=v.array("q", q, ndim=None), tm=tm, t=v.array("t", t, ndim=None))
        base = 0.0
        for law in laws_with_role("level"):
            c = law.values(self)
            base = base + (law.breakaway(s, tm, **c) if law.breakaway is not None
                           else law.term(np.zeros_like(tm), s, tm, **c))
        with np.errstate(over="ignore", invalid="ignore"):
            out = self.scale_at(t) * base
        return _out(_finite("breakaway torque", out))

    def sliding_level(self, direction=1) -> float:
        """Coulomb level approached at high speed in ``direction`` [N*m] (scale applied)."""
        return self.scale * (self.coulomb_pos if _direction(direction) > 0 else self.coulomb_neg)

    def __str__(self):
        parts = [f"{n}={x:.6g}" for n, x in self.changed().items()]
        return "FrictionModel(" + ", ".join(parts) + ")"


def _field(c):
    return (c.name, float, field(default=c.default, metadata={"unit": c.unit, "doc": c.doc,
                                                              "provenance": c.provenance}))


#: The model class: one field per coefficient of every registered law, in layout order.
FrictionModel = make_dataclass("FrictionModel", [_field(c) for c in COEFFICIENTS],
                               bases=(_FrictionModelBase,), frozen=True, kw_only=True)
FrictionModel.__module__ = __name__
FrictionModel.__qualname__ = "FrictionModel"
FrictionModel.__doc__ = _FrictionModelBase.__doc__

#: Default value of every coefficient (the empty model).
DEFAULTS = {f.name: f.default for f in fields(FrictionModel)}
