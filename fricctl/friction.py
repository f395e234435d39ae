"""Friction laws of a drive joint, composable by addition.

Sign convention (stated once here and in ``docs/notation.md``): the friction
torque ``Tat`` has the sign of the velocity and enters the joint as

    I * q'' = Tm - Tat .

Direction-dependent values are always two *positive magnitudes*
(``pos`` for omega > 0, ``neg`` for omega < 0), never a signed pair.

Every law gives its sliding torque (:meth:`FrictionModel.torque`, for
omega != 0) and its breakaway level (:meth:`FrictionModel.breakaway`, the torque
the drive must exceed to start moving from rest).  Laws compose by addition::

    >>> from fricctl.friction import Viscous, Coulomb, Stribeck
    >>> law = Viscous(0.0169) + Coulomb(0.144) + Stribeck(0.036, 0.02)
    >>> round(law.breakaway(+1), 3), round(float(law.torque(1.0)), 4)
    (0.18, 0.1609)

Laws available: :class:`Viscous`, :class:`Coulomb`, :class:`Static` (breakaway
excess without sliding contribution), :class:`Stribeck` (exponential decay of the
excess with speed), :class:`LoadDependent` (friction growing with the
transmitted torque ``|Tm|``), :class:`PositionRipple` (a torque periodic in
position; not friction, not dissipative, but part of the resistive torque the
joint sees), :class:`LuGre` (presliding: turns the Coulomb + Stribeck part into
the LuGre bristle model), and the model-level ``scale`` and ``drift`` (overall
friction level, and its steady change in time: wear, warm-up).

Notes
-----
Not modelled: the dependence of friction on temperature except through
``drift``; dwell-time dependence of breakaway; frictional memory (hysteresis in
sliding) except through :class:`LuGre`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace

import numpy as np

__all__ = [
    "Viscous", "Coulomb", "Static", "Stribeck", "LoadDependent", "PositionRipple",
    "LuGre", "FrictionModel", "NPARAM",
]

# Layout of the parameter vector the compiled kernel reads (FrictionModel.vector()).
_FIELDS = (
    "viscous_pos", "viscous_neg", "coulomb_pos", "coulomb_neg",
    "static_pos", "static_neg", "stribeck_pos", "stribeck_neg",
    "stribeck_velocity", "stribeck_exponent",
    "ripple_amplitude", "ripple_period", "ripple_phase",
    "load_coefficient", "scale", "drift", "lugre_sigma0", "lugre_sigma1",
)
#: Length of the kernel's friction parameter vector.
NPARAM = len(_FIELDS)
IDX = {name: i for i, name in enumerate(_FIELDS)}


def _check(name: str, value, *, positive=False, allow_zero=True):
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
        raise ValueError(f"{name} must be a real number, got {value!r}")
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"{name} must be finite, got {value!r}")
    if positive and not (value > 0 or (allow_zero and value == 0)):
        raise ValueError(f"{name} must be {'>= 0' if allow_zero else '> 0'}, got {value!r}")
    return value


def _pair(name, level, pos, neg):
    if level is not None and (pos is not None or neg is not None):
        raise ValueError(f"{name}: give either one symmetric level or pos= and neg=, not both")
    if level is not None:
        v = _check(name, level, positive=True)
        return v, v
    if pos is None or neg is None:
        raise ValueError(f"{name}: give a symmetric level, or both pos= and neg= (positive magnitudes)")
    return _check(f"{name} pos", pos, positive=True), _check(f"{name} neg", neg, positive=True)


def _out(x):
    """A 0-d result as a Python float, arrays unchanged."""
    x = np.asarray(x, dtype=float)
    return float(x) if x.ndim == 0 else x


class _Law:
    """Base of the elementary laws: adding laws gives a :class:`FrictionModel`."""

    def _contribution(self) -> dict:  # pragma: no cover - abstract
        raise NotImplementedError

    def model(self) -> "FrictionModel":
        return FrictionModel().add(self)

    def __add__(self, other):
        return self.model() + other

    def __radd__(self, other):
        if other == 0:  # sum([...]) support
            return self.model()
        return NotImplemented

    def torque(self, omega, q=0.0, tm=0.0, t=0.0):
        return self.model().torque(omega, q, tm, t)

    def breakaway(self, direction=1, q=0.0, tm=0.0, t=0.0):
        return self.model().breakaway(direction, q, tm, t)


class Viscous(_Law):
    """Viscous friction ``b*omega`` (or ``b_pos``/``b_neg`` per direction) [N*m*s/rad]."""

    def __init__(self, b=None, *, pos=None, neg=None):
        self.pos, self.neg = _pair("Viscous", b, pos, neg)

    def _contribution(self):
        return {"viscous_pos": self.pos, "viscous_neg": self.neg}

    def __repr__(self):
        return f"Viscous(pos={self.pos}, neg={self.neg})"


class Coulomb(_Law):
    """Coulomb friction ``Fc*sign(omega)``, breakaway ``Fc`` [N*m]."""

    def __init__(self, level=None, *, pos=None, neg=None):
        self.pos, self.neg = _pair("Coulomb", level, pos, neg)

    def _contribution(self):
        return {"coulomb_pos": self.pos, "coulomb_neg": self.neg}

    def __repr__(self):
        return f"Coulomb(pos={self.pos}, neg={self.neg})"


class Static(_Law):
    """Breakaway excess over sliding friction, with no sliding contribution [N*m].

    The classic "static + Coulomb" model: the joint needs ``Fc + excess`` to
    start, and ``Fc`` once it slides (an infinitely narrow Stribeck curve).
    """

    def __init__(self, excess=None, *, pos=None, neg=None):
        self.pos, self.neg = _pair("Static", excess, pos, neg)

    def _contribution(self):
        return {"static_pos": self.pos, "static_neg": self.neg}

    def __repr__(self):
        return f"Static(pos={self.pos}, neg={self.neg})"


class Stribeck(_Law):
    """Exponential Stribeck excess ``(Fs - Fc) * exp(-(|omega|/vs)**delta) * sign(omega)``.

    Parameters
    ----------
    excess : float
        Fs - Fc, breakaway excess over the Coulomb level [N*m].
    velocity : float
        Stribeck velocity vs > 0 [rad/s].
    exponent : float
        Shape exponent delta > 0 (2 = Gaussian, the usual choice) [-].
    """

    def __init__(self, excess=None, velocity=None, exponent=2.0, *, pos=None, neg=None):
        self.pos, self.neg = _pair("Stribeck excess", excess, pos, neg)
        if velocity is None:
            raise ValueError("Stribeck: velocity (the Stribeck velocity vs [rad/s]) is required")
        self.velocity = _check("Stribeck velocity", velocity, positive=True, allow_zero=False)
        self.exponent = _check("Stribeck exponent", exponent, positive=True, allow_zero=False)

    def _contribution(self):
        return {"stribeck_pos": self.pos, "stribeck_neg": self.neg,
                "stribeck_velocity": self.velocity, "stribeck_exponent": self.exponent}

    def __repr__(self):
        return f"Stribeck(pos={self.pos}, neg={self.neg}, velocity={self.velocity}, exponent={self.exponent})"


class LoadDependent(_Law):
    """Friction growing with the transmitted torque: ``+ mu*|Tm|*sign(omega)`` [-].

    Gear-mesh friction of a harmonic drive rises with the load it transmits; the
    breakaway level rises by the same ``mu*|Tm|``.
    """

    def __init__(self, coefficient):
        self.coefficient = _check("LoadDependent coefficient", coefficient, positive=True)

    def _contribution(self):
        return {"load_coefficient": self.coefficient}

    def __repr__(self):
        return f"LoadDependent({self.coefficient})"


class PositionRipple(_Law):
    """Torque periodic in position: ``A*sin(2*pi*q/period + phase)`` [N*m].

    Not friction (it does not dissipate and has no sign of omega) but part of the
    resistive torque: the harmonic drive's wave generator, cogging, a cam.
    """

    def __init__(self, amplitude, period, phase=0.0):
        self.amplitude = _check("PositionRipple amplitude", amplitude, positive=True)
        self.period = _check("PositionRipple period", period, positive=True, allow_zero=False)
        self.phase = _check("PositionRipple phase", phase)

    def _contribution(self):
        return {"ripple_amplitude": self.amplitude, "ripple_period": self.period,
                "ripple_phase": self.phase}

    def __repr__(self):
        return f"PositionRipple({self.amplitude}, {self.period}, phase={self.phase})"


class LuGre(_Law):
    """LuGre presliding dynamics applied to the Coulomb + Stribeck part.

    ``z' = omega - sigma0*|omega|*z/g(omega)``,
    ``T = sigma0*z + sigma1*z' + viscous``, with ``g`` the Coulomb + Stribeck
    level.  With this law the joint has no exact stick: it creeps elastically
    (presliding displacement ~ g/sigma0) below breakaway.

    Parameters
    ----------
    sigma0 : float
        Bristle stiffness [N*m/rad].
    sigma1 : float
        Bristle damping [N*m*s/rad].
    """

    def __init__(self, sigma0, sigma1):
        self.sigma0 = _check("LuGre sigma0", sigma0, positive=True, allow_zero=False)
        self.sigma1 = _check("LuGre sigma1", sigma1, positive=True)

    def _contribution(self):
        return {"lugre_sigma0": self.sigma0, "lugre_sigma1": self.sigma1}

    def __repr__(self):
        return f"LuGre({self.sigma0}, {self.sigma1})"


_ADDITIVE = {"viscous_pos", "viscous_neg", "coulomb_pos", "coulomb_neg", "static_pos",
             "static_neg", "stribeck_pos", "stribeck_neg", "load_coefficient"}


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
            v = _check(f.name, getattr(self, f.name))
            if f.name not in ("ripple_phase", "drift") and v < 0:
                raise ValueError(f"{f.name} must be >= 0 [{f.metadata['unit']}], got {v!r}")
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
        if isinstance(law, FrictionModel):
            new = {n: getattr(self, n) for n in _FIELDS}
            for n in _FIELDS:
                v = getattr(law, n)
                if n in _ADDITIVE:
                    new[n] += v
                elif n == "scale":
                    new[n] *= v
                elif n == "drift":
                    new[n] += v
                elif v != _DEFAULTS[n]:  # shape parameters: the added model's, where it sets them
                    new[n] = v
            return FrictionModel(**new)
        if not isinstance(law, _Law):
            raise ValueError(f"cannot add {type(law).__name__} to a FrictionModel")
        new = {n: getattr(self, n) for n in _FIELDS}
        contrib = law._contribution()
        if isinstance(law, Stribeck) and (self.stribeck_pos > 0 or self.stribeck_neg > 0) and (
                law.velocity != self.stribeck_velocity or law.exponent != self.stribeck_exponent):
            raise ValueError("two Stribeck laws with different velocities or exponents cannot be "
                             "summed into one model")
        if isinstance(law, PositionRipple) and self.ripple_amplitude > 0:
            raise ValueError("a model holds one PositionRipple")
        for k, v in contrib.items():
            new[k] = new[k] + v if k in _ADDITIVE else v
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
        factor = _check("scale factor", factor, positive=True, allow_zero=False)
        return replace(self, scale=self.scale * factor)

    def with_drift(self, drift: float) -> "FrictionModel":
        """Copy whose friction scale changes by ``drift`` (relative) per second."""
        return replace(self, drift=_check("drift", drift))

    def vector(self) -> np.ndarray:
        """Coefficients in the compiled kernel's layout (``IDX``)."""
        return np.array([getattr(self, n) for n in _FIELDS], dtype=float)

    @property
    def is_lugre(self) -> bool:
        return self.lugre_sigma0 > 0

    def as_dict(self) -> dict:
        return {n: getattr(self, n) for n in _FIELDS}

    @classmethod
    def from_dict(cls, d: dict) -> "FrictionModel":
        unknown = sorted(set(d) - set(_FIELDS))
        if unknown:
            raise ValueError(f"unknown friction field(s): {', '.join(unknown)}")
        return cls(**d)

    # -- evaluation (numpy, vectorised) ----------------------------------
    def _scale(self, t):
        return self.scale * (1.0 + self.drift * np.asarray(t, dtype=float))

    def ripple(self, q):
        """Position-periodic torque at position ``q`` [N*m]."""
        q = np.asarray(q, dtype=float)
        if self.ripple_amplitude == 0:
            return np.zeros_like(q)
        return self.ripple_amplitude * np.sin(2 * np.pi * q / self.ripple_period + self.ripple_phase)

    def torque(self, omega, q=0.0, tm=0.0, t=0.0):
        """Sliding friction torque (plus ripple) at velocity ``omega`` [N*m].

        For ``omega == 0`` the friction torque is not a function of velocity (it
        is whatever reaction keeps the joint at rest, up to :meth:`breakaway`);
        this method returns the ripple alone there.  With :class:`LuGre` this is
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
        w = np.asarray(omega, dtype=float)
        pos = w > 0
        neg = w < 0
        aw = np.abs(w)
        b = np.where(pos, self.viscous_pos, self.viscous_neg)
        fc = np.where(pos, self.coulomb_pos, self.coulomb_neg)
        fs = np.where(pos, self.stribeck_pos, self.stribeck_neg)
        level = fc + self.load_coefficient * np.abs(np.asarray(tm, dtype=float)) + fs * np.exp(
            -(aw / self.stribeck_velocity) ** self.stribeck_exponent)
        sgn = pos.astype(float) - neg.astype(float)
        return _out(self._scale(t) * (b * w + sgn * level) + self.ripple(q))

    def breakaway(self, direction=1, q=0.0, tm=0.0, t=0.0):
        """Torque the drive must exceed to start moving in ``direction`` (+1/-1) [N*m].

        A positive magnitude.  The position ripple is not included: it adds to
        the drive torque (the joint breaks loose when ``Tm - ripple(q)`` leaves
        ``[-breakaway(-1), breakaway(+1)]``).
        """
        if direction not in (1, -1):
            raise ValueError(f"direction must be +1 or -1, got {direction!r}")
        if direction > 0:
            base = self.coulomb_pos + self.static_pos + self.stribeck_pos
        else:
            base = self.coulomb_neg + self.static_neg + self.stribeck_neg
        return _out(self._scale(t) * (base + self.load_coefficient * np.abs(np.asarray(tm, dtype=float))))

    def sliding_level(self, direction=1) -> float:
        """Coulomb level approached at high speed in ``direction`` [N*m] (scale applied)."""
        if direction not in (1, -1):
            raise ValueError(f"direction must be +1 or -1, got {direction!r}")
        return self.scale * (self.coulomb_pos if direction > 0 else self.coulomb_neg)

    def __str__(self):
        parts = [f"{n}={getattr(self, n):.6g}" for n in _FIELDS
                 if getattr(self, n) != _DEFAULTS[n]]
        return "FrictionModel(" + ", ".join(parts) + ")"


_DEFAULTS = {f.name: f.default for f in fields(FrictionModel)}
