"""The friction parameter vector shared by :class:`~fricctl.friction.FrictionModel` and the kernels.

Built from the registered laws (:data:`fricctl.friction.laws.LAWS`, in their ``order``):
:meth:`FrictionModel.vector` writes the coefficients in this order and the compiled kernels
(:mod:`fricctl.friction.compiled`, generated from the same laws) read them by :data:`IDX`.
Nothing here is edited when a law is added.
"""

from __future__ import annotations

from .laws import LAWS

__all__ = ["FIELDS", "NPARAM", "IDX", "COEFFICIENTS"]

#: Every coefficient of every law, in the kernels' order.
COEFFICIENTS = tuple(c for law in LAWS.values() for c in law.coefficients)
#: Names of the coefficients, in the kernels' order.
FIELDS = tuple(c.name for c in COEFFICIENTS)
#: Length of the kernels' friction parameter vector.
NPARAM = len(FIELDS)
#: Position of each coefficient in the vector.
IDX = {name: i for i, name in enumerate(FIELDS)}
