"""Units of a rotary joint or a linear axis, and the gear-side conversions, stated once.

fricctl works in SI units on the *load side* of the gear.  A rotary joint has
torques [N*m] and angles [rad]; a linear axis (EMPS, a ball-screw table) has
forces [N] and positions [m].  :data:`UNITS` holds the labels of each quantity
for both, so that every report, table and figure labels a value the same way.

The conversion between the rotor and the load side of a gear of ratio n is one
function each way (:func:`to_load_side`, :func:`to_rotor_side`): inertia and
viscous coefficients scale with n^2, torques (Coulomb, static, motor torque) with
n, angles and velocities with 1/n.

Examples
--------
>>> UNITS["linear"].torque, UNITS["rotary"].viscous
('N', 'N*m*s/rad')
>>> to_load_side(gear_ratio=100, inertia=1e-7, torque=0.01)
{'inertia': 0.001, 'torque': 1.0}
"""

from __future__ import annotations

import math
import re

from dataclasses import dataclass

from . import _validate as v

__all__ = ["Units", "UNITS", "KINDS", "units", "quantity", "to_load_side", "to_rotor_side",
           "SUFFIXES", "parse_quantity"]


@dataclass(frozen=True, kw_only=True)
class Units:
    """Unit labels of one kind of axis."""

    kind: str
    """``"rotary"`` or ``"linear"``."""
    torque: str
    """Torque or force."""
    position: str
    """Angle or displacement."""
    velocity: str
    acceleration: str
    inertia: str
    """Inertia or mass."""
    viscous: str
    """Viscous coefficient (torque per velocity)."""
    stiffness: str
    """Spring stiffness (torque per position)."""


UNITS = {
    "rotary": Units(kind="rotary", torque="N*m", position="rad", velocity="rad/s",
                    acceleration="rad/s^2", inertia="kg*m^2", viscous="N*m*s/rad",
                    stiffness="N*m/rad"),
    "linear": Units(kind="linear", torque="N", position="m", velocity="m/s",
                    acceleration="m/s^2", inertia="kg", viscous="N*s/m", stiffness="N/m"),
}
#: The two kinds of axis.
KINDS = tuple(UNITS)


def units(kind) -> Units:
    """The :class:`Units` of ``"rotary"`` or ``"linear"`` (anything else is a ValueError)."""
    return UNITS[v.choice("units", kind, KINDS)]


def quantity(value, unit: str) -> dict:
    """A number with its unit, as fricctl's JSON summaries write every quantity.

    ``identify --json`` writes each parameter as ``{value, std, unit}``; ``design`` and
    ``simulate`` write each quantity as ``{value, unit}``, with the same keys whatever
    the plant (rotary or linear, the paper's actuator or a model file).  A dimensionless
    ratio has the unit ``"-"``.

    Examples
    --------
    >>> quantity(0.5, "rad")
    {'value': 0.5, 'unit': 'rad'}
    """
    return {"value": value, "unit": v.text("unit", unit)}


_FACTORS = {"inertia": 2, "viscous": 2, "torque": 1, "angle": -1, "velocity": -1}


def to_load_side(*, gear_ratio: float, inertia: float | None = None,
                 viscous: float | None = None, torque: float | None = None,
                 angle: float | None = None, velocity: float | None = None) -> dict:
    """Convert rotor-side quantities to the load side of a gear of ratio n.

    Parameters
    ----------
    gear_ratio : float
        n > 0 (rotor turns per load turn) [-].
    inertia, viscous, torque, angle, velocity : float, optional
        Rotor-side values [kg*m^2], [N*m*s/rad], [N*m], [rad], [rad/s].

    Returns
    -------
    dict
        Only the quantities given, converted to the load side.
    """
    n = v.real("gear_ratio", gear_ratio, positive=True)
    out = {}
    for name, value in (("inertia", inertia), ("viscous", viscous), ("torque", torque),
                        ("angle", angle), ("velocity", velocity)):
        if value is None:
            continue
        x = v.real(name, value, nonneg=name in ("inertia", "viscous"))
        try:
            y = x * n ** _FACTORS[name]
        except OverflowError:  # float ** raises where float * gives inf
            y = math.inf
        out[name] = v.real(f"{name} on the load side (gear_ratio {n:g})", y)
    return out


def to_rotor_side(*, gear_ratio: float, **quantities) -> dict:
    """Inverse of :func:`to_load_side` (same keyword names).

    Examples
    --------
    >>> to_rotor_side(gear_ratio=100, torque=1.0)
    {'torque': 0.01}
    """
    unknown = sorted(set(quantities) - set(_FACTORS))
    if unknown:
        raise ValueError(f"unknown quantity(ies): {', '.join(unknown)}; "
                         f"known: {', '.join(_FACTORS)}")
    n = v.real("gear_ratio", gear_ratio, positive=True)
    return to_load_side(gear_ratio=1.0 / n, **quantities)


#: Unit suffixes a number typed by a user may carry: (quantity, axis kind) -> suffix -> factor to
#: the SI unit fricctl computes in (the first suffix of each).  A bare number is in that SI unit.
SUFFIXES = {
    ("position", "rotary"): {"rad": 1.0, "mrad": 1e-3, "deg": math.pi / 180.0},
    ("position", "linear"): {"m": 1.0, "cm": 1e-2, "mm": 1e-3, "um": 1e-6},
    ("torque", "rotary"): {"N*m": 1.0, "Nm": 1.0, "mN*m": 1e-3, "mNm": 1e-3},
    ("torque", "linear"): {"N": 1.0, "kN": 1e3},
    ("time", "rotary"): {"s": 1.0, "ms": 1e-3},
    ("time", "linear"): {"s": 1.0, "ms": 1e-3},
    ("frequency", "rotary"): {"Hz": 1.0},
    ("frequency", "linear"): {"Hz": 1.0},
    ("velocity", "rotary"): {"rad/s": 1.0, "deg/s": math.pi / 180.0, "rpm": math.pi / 30.0},
    ("velocity", "linear"): {"m/s": 1.0, "mm/s": 1e-3},
    ("viscous", "rotary"): {"N*m*s/rad": 1.0, "Nms/rad": 1.0, "mN*m*s/rad": 1e-3,
                            "N*m/rpm": 30.0 / math.pi},
    ("viscous", "linear"): {"N*s/m": 1.0, "Ns/m": 1.0},
    ("inertia", "rotary"): {"kg*m^2": 1.0, "kgm2": 1.0, "g*cm^2": 1e-7},
    ("inertia", "linear"): {"kg": 1.0, "g": 1e-3},
    # a stiffness: the LuGre bristle's sigma0 (fricctl simulate/compare --sigma0)
    ("stiffness", "rotary"): {"N*m/rad": 1.0, "Nm/rad": 1.0},
    ("stiffness", "linear"): {"N/m": 1.0, "N/mm": 1e3},
}

#: What each SI unit is called in a message (a reader who typed 'degs' learns the default).
_UNIT_NAMES = {"rad": "radians", "m": "metres", "N*m": "newton metres", "N": "newtons",
               "s": "seconds", "Hz": "hertz", "rad/s": "radians per second",
               "m/s": "metres per second", "N*m*s/rad": "N*m*s/rad", "N*s/m": "N*s/m",
               "kg*m^2": "kg*m^2", "kg": "kilograms", "N*m/rad": "N*m/rad", "N/m": "newtons per metre"}

_NUMBER = re.compile(r"\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*(\S*)\s*")


def parse_quantity(text: str, quantity: str, kind: str = "rotary") -> float:
    """A number with an optional unit suffix, converted to fricctl's SI unit.

    Parameters
    ----------
    text : str
        ``"0.35"`` (already in the SI unit), ``"20deg"``, ``"5 mm"``, ``"0.2N*m"``.
    quantity : {"position", "torque", "time", "frequency", "velocity", "viscous", "inertia", "stiffness"}
        What the number is (angle or displacement for ``"position"``; force for a linear
        ``"torque"``, mass for a linear ``"inertia"``).
    kind : {"rotary", "linear"}
        Axis kind: a rotary position is in [rad] (``rad``, ``mrad``, ``deg`` accepted), a
        linear one in [m] (``m``, ``cm``, ``mm``, ``um``).

    Returns
    -------
    float
        The value in the SI unit (the first entry of :data:`SUFFIXES` for the quantity).

    Raises
    ------
    ValueError
        Not a number, or a unit not accepted for this quantity: the message says the
        default unit and lists the accepted suffixes.

    Examples
    --------
    >>> round(parse_quantity("20deg", "position"), 6)
    0.349066
    >>> parse_quantity("5mm", "position", "linear")
    0.005
    >>> parse_quantity("0.3", "position")
    0.3
    """
    kind = v.choice("units", kind, KINDS)
    table = SUFFIXES.get((quantity, kind))
    if table is None:
        raise ValueError(f"quantity must be one of {sorted({q for q, _ in SUFFIXES})}, got {quantity!r}")
    si = next(iter(table))
    accepted = (f"a bare number is in {_UNIT_NAMES[si]} ({si}); accepted units: "
                f"{', '.join(table)}")
    try:
        return float(text)  # a bare number (also inf, nan: the caller judges finiteness)
    except (TypeError, ValueError):
        pass
    m = _NUMBER.fullmatch(str(text))
    if m is None:
        raise ValueError(f"{text!r} is not a number ({accepted})")
    number, suffix = m.groups()
    if suffix not in table:
        raise ValueError(f"unknown unit {suffix!r} in {text!r} for a {kind} {quantity}; {accepted}")
    return float(number) * table[suffix]
