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

from dataclasses import dataclass

from . import _validate as v

__all__ = ["Units", "UNITS", "KINDS", "units", "to_load_side", "to_rotor_side"]


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
