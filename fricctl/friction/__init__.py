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

from .laws import Coulomb, LoadDependent, LuGre, PositionRipple, Static, Stribeck, Viscous
from .layout import FIELDS, IDX, NPARAM
from .model import DEFAULTS, FrictionLaw, FrictionModel

__all__ = [
    "FrictionLaw", "FrictionModel", "Viscous", "Coulomb", "Static", "Stribeck", "LoadDependent",
    "PositionRipple", "LuGre", "FIELDS", "IDX", "NPARAM", "DEFAULTS",
]
