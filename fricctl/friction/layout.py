"""The friction parameter vector shared by :class:`~fricctl.friction.FrictionModel` and the kernels.

:meth:`FrictionModel.vector` writes the coefficients in this order; the compiled
kernels (:mod:`fricctl.friction.kernels`) read them by :data:`IDX`.  A test pins
the two together (``tests/test_friction.py``).  Adding a field: append its name
here, add the dataclass field of the same name to ``FrictionModel`` (with its
unit and default), and read it in the kernels.
"""

from __future__ import annotations

__all__ = ["FIELDS", "NPARAM", "IDX"]

#: Names of the coefficients, in the kernels' order.
FIELDS = (
    "viscous_pos", "viscous_neg", "coulomb_pos", "coulomb_neg",
    "static_pos", "static_neg", "stribeck_pos", "stribeck_neg",
    "stribeck_velocity", "stribeck_exponent",
    "ripple_amplitude", "ripple_period", "ripple_phase",
    "load_coefficient", "scale", "drift", "lugre_sigma0", "lugre_sigma1",
)
#: Length of the kernels' friction parameter vector.
NPARAM = len(FIELDS)
#: Position of each coefficient in the vector.
IDX = {name: i for i, name in enumerate(FIELDS)}
