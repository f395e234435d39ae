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

Each law is one module of :mod:`fricctl.friction.laws` (registry :data:`LAWS`; what a law
declares: :mod:`fricctl.friction.law`), whose public class is importable from here:
:class:`Viscous`, :class:`Coulomb`, :class:`Static` (breakaway excess without sliding
contribution), :class:`Stribeck` (exponential decay of the excess with speed),
:class:`LoadDependent` (friction growing with the transmitted torque ``|Tm|``),
:class:`PositionRipple` (a torque periodic in position; not friction, not dissipative, but
part of the resistive torque the joint sees), :class:`PositionLoad` (a smooth load of position
over the travel: gravity on an off-centre link, a spring; not friction either), presliding laws with a state such as
:class:`LuGre` (they turn the Coulomb + Stribeck level into bristle dynamics), the
model-level ``scale`` and ``drift`` (overall friction level, and its steady change in time:
wear, warm-up), and whatever else :data:`LAWS` holds.  The numpy evaluation
(:class:`FrictionModel`) and the compiled one (:mod:`fricctl.friction.compiled`) are both
built from the registered laws.

Notes
-----
Not modelled: the dependence of friction on temperature except through
``drift``; dwell-time dependence of breakaway; frictional memory (hysteresis in
sliding) except through the presliding laws.
"""

from __future__ import annotations

from .law import Coefficient, FrictionLaw, Law
from .laws import LAWS, law_of_field, laws_with_role
from .layout import FIELDS, IDX, NPARAM
from .model import DEFAULTS, FrictionModel

# every registered law's public class (Viscous, Coulomb, ...), read from the registry: a new
# law module is importable from here without an edit of this file
globals().update({law.constructor.__name__: law.constructor for law in LAWS.values()})

__all__ = ["FrictionLaw", "FrictionModel", "FIELDS", "IDX", "NPARAM", "DEFAULTS", "LAWS", "Law",
           "Coefficient", "laws_with_role", "law_of_field",
           *(law.constructor.__name__ for law in LAWS.values())]
