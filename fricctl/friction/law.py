"""What a friction law declares: :class:`Coefficient` and :class:`Law` (the registry's entries).

A law is one module of :mod:`fricctl.friction.laws` holding ``LAW = Law(...)`` and the public
class a user adds to a model (``Viscous(b) + Coulomb(Fc)``).  Everything else is built from
the registered laws: the coefficient layout (:mod:`.layout`), the fields and the numpy
evaluation of :class:`~fricctl.friction.FrictionModel`, the compiled kernels
(:mod:`.compiled`), the integrator's sub-steps (:mod:`fricctl.plant.stability`), the
diagnosis's torque along a measured motion and the regressor columns of identification.

Roles
-----
A law's terms enter the friction torque by its ``role`` (``w`` velocity, ``s`` the direction
of motion +1/-1, ``tm`` the transmitted torque, ``q`` position, ``t`` time):

``"rate"``
    an odd function of ``w`` (viscous ``b*w``, drag ``c*w*|w|``), multiplied by the scale;
    a state law leaves it alone.
``"level"``
    a magnitude in direction ``s`` (Coulomb, Stribeck, load-dependent; ``Static`` adds to the
    breakaway only): the sliding torque is ``s*level``, the breakaway the level at rest plus
    any breakaway-only term; multiplied by the scale.  A state law turns the level ``g`` into
    presliding dynamics.
``"position"``
    a torque of position added as it is (the position ripple, the position load: not
    friction, not scaled); it declares its ``peak``, its largest magnitude.
``"scale"``
    the factor of every friction term (``scale*(1 + drift*t)``); one law has this role.
``"state"``
    presliding dynamics with a state ``z`` (LuGre, Dahl): ``z' = rate(w, z, g)``, friction
    ``force(w, z, z', g)`` in place of ``s*g``; at most one is active in a model.

The numpy term and the compiled term of a law compute the same thing (the first on arrays,
the second on scalars, written for numba; ``tests/test_friction.py`` pins them together for
every registered law).  A compiled term's arguments are named: signals (``w, s, tm, q, t, z,
zd, g``) and the law's coefficient names, which the kernel generator reads from the layout.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Mapping

__all__ = ["Coefficient", "Law", "StateEquation", "FrictionLaw", "DirectionalLaw", "ROLES", "SIGNALS", "pair",
           "direction_pair", "pick"]

#: The roles a law can have (see the module docstring).
ROLES = ("rate", "level", "position", "scale", "state")
#: Names a compiled term may take as signals (any other argument is a coefficient).
SIGNALS = ("w", "s", "tm", "q", "t", "z", "zd", "g")
#: How a coefficient combines when two models are added.
COMBINE = ("add", "multiply", "replace")


@dataclass(frozen=True, kw_only=True)
class Coefficient:
    """One coefficient of a law: a field of :class:`~fricctl.friction.FrictionModel`."""

    name: str
    """Field name, unique over every law (e.g. ``"viscous_pos"``)."""
    unit: str
    """SI unit on the load side (rotary; a linear axis reads N for N*m, m for rad)."""
    doc: str
    """One line: what it is."""
    default: float = 0.0
    """Value of the empty model (the law absent, or its neutral setting)."""
    lower: float = 0.0
    """Lowest accepted value (``-inf``: signed)."""
    strict: bool = False
    """True when ``lower`` itself is refused (a value must be above it)."""
    upper: float = math.inf
    """Highest accepted value."""
    combine: str = "add"
    """``"add"`` (magnitudes sum), ``"multiply"`` (a scale) or ``"replace"`` (a shape parameter:
    the added model's value, where it sets one)."""
    provenance: str = "neutral: the law absent"
    """Where the default comes from."""

    def __post_init__(self):
        if self.combine not in COMBINE:
            raise ValueError(f"coefficient {self.name}: combine must be one of {COMBINE}")
        if not self.lower <= self.default <= self.upper or (self.strict and self.default == self.lower):
            raise ValueError(f"coefficient {self.name}: default {self.default} outside its bounds")

    @property
    def signed(self) -> bool:
        """True when negative values are accepted."""
        return self.lower == -math.inf


@dataclass(frozen=True, kw_only=True)
class StateEquation:
    """The presliding dynamics of a state law (one scalar state ``z``, a deflection [rad])."""

    switch: str
    """The coefficient whose value > 0 makes the law active (its stiffness)."""
    compiled: Callable
    """Scalar ``(w, z, g, <coefficients>) -> (z', friction)``: the state's rate [rad/s] and the
    friction torque it carries [N*m] (rate and position terms excluded)."""
    along_motion: Callable
    """numpy ``(model, q, w, tm, t) -> friction`` along a measured motion: the state integrated
    along the position record (no acceleration needed) [N*m]; what the diagnosis evaluates."""
    initial: Callable
    """numpy ``(model, q) -> z`` along a position record, from rest: the state a re-simulation
    starts each window with [rad]."""
    speed_rate: Callable
    """``(model, speed) -> rate`` [1/s]: the state's own rate at a speed (``|w|/x_c``)."""


@dataclass(frozen=True, kw_only=True)
class Law:
    """A friction law: the registry entry of its module (``LAW = Law(...)``)."""

    name: str
    """Registry key, the module's name (``"viscous"``)."""
    description: str
    """One line: the physics."""
    order: int
    """Position in the coefficient layout (laws sorted by it)."""
    role: str
    """One of :data:`ROLES`."""
    coefficients: tuple
    """Its :class:`Coefficient` s, in layout order."""
    constructor: type
    """The public class a user adds to a model (a :class:`~fricctl.friction.FrictionLaw`)."""
    term: Callable | None = None
    """numpy term by role: rate ``(w, s, **c)``, level ``(w, s, tm, **c)``, position
    ``(q, **c)``, scale ``(t, **c)``; arrays in, array out."""
    compiled: Callable | None = None
    """The same term on scalars, for numba (arguments named, see :data:`SIGNALS`)."""
    breakaway: Callable | None = None
    """Level laws: numpy ``(s, tm, **c)``, the breakaway contribution (default: the level at
    rest)."""
    compiled_breakaway: Callable | None = None
    """The same on scalars (default: the compiled level at ``w = 0``)."""
    damping: Callable | None = None
    """``(c, speed) -> d`` [N*m*s/rad]: the slope ``dT/dw`` this law adds at speeds up to
    ``speed`` (None: unknown), for the integrator's sub-steps; None adds nothing."""
    state: StateEquation | None = None
    """State laws: the presliding dynamics."""
    regressors: Callable | None = None
    """Laws linear in coefficients: ``(w, symmetric) -> {name: column}``, the identification
    model's columns (``symmetric``: one coefficient for both directions, named without
    ``_pos``/``_neg``)."""
    peak: Callable | None = None
    """Position laws: ``(c) -> |term|`` at its worst over every position [N*m] (the ripple's
    amplitude), for the top speed a drive torque can reach (:mod:`fricctl.plant.stability`)."""
    check: Callable | None = None
    """``(model) -> None``: raise ``ValueError`` when the model's coefficients cannot hold
    together for this law (e.g. LuGre without a Coulomb level)."""
    field_names: tuple = field(init=False)
    """The coefficients' names."""

    def __post_init__(self):
        if self.role not in ROLES:
            raise ValueError(f"law {self.name}: role must be one of {ROLES}, got {self.role!r}")
        if (self.role == "state") != (self.state is not None):
            raise ValueError(f"law {self.name}: a state law, and only one, declares a state")
        if self.role != "state" and (self.term is None or self.compiled is None):
            raise ValueError(f"law {self.name}: a {self.role} law declares its numpy and compiled term")
        if (self.role == "position") != (self.peak is not None):
            raise ValueError(f"law {self.name}: a position law, and only one, declares its peak")
        object.__setattr__(self, "field_names", tuple(c.name for c in self.coefficients))

    def values(self, model) -> dict:
        """This law's coefficients in ``model`` by name."""
        return {n: getattr(model, n) for n in self.field_names}

    def active(self, model) -> bool:
        """True when ``model`` holds this law (a coefficient away from its default)."""
        if self.state is not None:
            return getattr(model, self.state.switch) > 0
        return any(getattr(model, c.name) != c.default for c in self.coefficients)


# ---------------------------------------------------------------------------- the laws' base
class FrictionLaw:
    """Base of the public law classes; adding laws (``Viscous(b) + Coulomb(Fc)``) gives a
    :class:`~fricctl.friction.FrictionModel`.

    A law says which coefficients of the model it sets (:meth:`contribution`) and may
    refuse to be added to a model it cannot share (:meth:`check_compatible`).
    """

    def contribution(self) -> dict:  # pragma: no cover - abstract
        """``{field: value}`` this law adds to (or sets in) a model."""
        raise NotImplementedError

    def check_compatible(self, model) -> None:
        """Raise ``ValueError`` if this law cannot be added to ``model``."""

    def model(self):
        """The model holding this law alone."""
        from .model import FrictionModel

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

    def __repr__(self):
        args = ", ".join(f"{k}={x}" for k, x in vars(self).items())
        return f"{type(self).__name__}({args})"


class DirectionalLaw(FrictionLaw):
    """A law of one magnitude per direction: ``Law(x)`` symmetric, or ``Law(pos=, neg=)``.

    A subclass names its two coefficients (``coefficients = ("viscous_pos", "viscous_neg")``).
    """

    coefficients: tuple = ()

    def __init__(self, value=None, *, pos=None, neg=None):
        self.pos, self.neg = pair(type(self).__name__, value, pos, neg)

    def contribution(self):
        return dict(zip(self.coefficients, (self.pos, self.neg)))


def pair(name: str, level, pos, neg) -> tuple[float, float]:
    """One symmetric magnitude, or both per-direction magnitudes (never a signed pair)."""
    from .. import _validate as v

    if level is not None and (pos is not None or neg is not None):
        raise ValueError(f"{name}: give either one symmetric level or pos= and neg=, not both")
    if level is not None:
        x = v.real(name, level, nonneg=True)
        return x, x
    if pos is None or neg is None:
        raise ValueError(f"{name}: give a symmetric level, or both pos= and neg= (positive magnitudes)")
    return v.real(f"{name} pos", pos, nonneg=True), v.real(f"{name} neg", neg, nonneg=True)


def direction_pair(base: str, unit: str, what: str) -> tuple:
    """The two per-direction magnitudes ``<base>_pos`` and ``<base>_neg`` of a law."""
    return (Coefficient(name=f"{base}_pos", unit=unit, doc=f"{what}, positive velocity"),
            Coefficient(name=f"{base}_neg", unit=unit, doc=f"{what}, negative velocity (a magnitude)"))


def same_shape(model, base: str, shape: Mapping, message: str) -> None:
    """Refuse a law whose shape parameters (``shape``: coefficient name -> this law's value)
    differ from those of the same law already in ``model`` (its ``<base>_pos``/``_neg`` level
    non-zero): two shapes cannot be summed into one set of coefficients; ``message`` says so."""
    if (getattr(model, f"{base}_pos") > 0 or getattr(model, f"{base}_neg") > 0) and any(
            value != getattr(model, key) for key, value in shape.items()):
        raise ValueError(message)


def pick(s, pos, neg):
    """numpy: ``pos`` where ``s > 0``, else ``neg``."""
    import numpy as np

    return np.where(s > 0, pos, neg)
