"""How many RK4 sub-steps a joint needs: its fastest rate against the sample time.

The compiled kernels integrate the sliding dynamics with classical RK4 on ``substeps``
sub-intervals of each sample.  RK4 is only stable while ``h*|lambda|`` stays below about
2.8 (2.785 on the negative real axis, 2.828 on the imaginary one), ``lambda`` the
plant's fastest eigenvalue; beyond it the state grows without bound (a viscous
coefficient of 20 N*m*s/rad on the paper's actuator gave ``|q| = 1.8e300``).  The rule
here keeps ``h*|lambda| <= 1``, well inside the region and accurate to about 2 % per
sub-step on the fastest mode:

* viscous friction on the moving inertia: ``lambda = b/J``;
* the elastic joint (Eq. 1): ``omega_r = sqrt(K (1/Jm + 1/Jl))`` and the structural
  damping ``d (1/Jm + 1/Jl)``;
* LuGre bristles: their damping ``(sigma1 + b)/J``; the bristle stiffness acts at a rate
  proportional to the speed (``|omega|/x_c``), which the caller covers with its own
  minimum (the kernels' default of 40 sub-steps for LuGre).

Examples
--------
>>> from fricctl.friction import Coulomb, Viscous
>>> required_substeps(sample_time=0.002, rate=fastest_rate(
...     inertia=2.865e-3, friction=(Viscous(20.0) + Coulomb(0.01)).model()))
14
"""

from __future__ import annotations

import math

from .. import _validate as v
from ..friction import FrictionModel

__all__ = ["fastest_rate", "required_substeps", "MAX_SUBSTEPS", "RATE_PER_SUBSTEP"]

#: ``h*|lambda|`` allowed per sub-step [-].
RATE_PER_SUBSTEP = 1.0
#: Most sub-steps per sample a simulation will run (above it: refused, with the number).
MAX_SUBSTEPS = 100_000


def fastest_rate(*, inertia: float, friction: FrictionModel, load_inertia: float = 0.0,
                 stiffness: float = 0.0, damping: float = 0.0) -> float:
    """The fastest linear rate of the joint's sliding dynamics [1/s].

    Parameters
    ----------
    inertia : float
        Motor-side inertia (the whole inertia of a rigid joint) [kg*m^2].
    friction : FrictionModel
    load_inertia, stiffness, damping : float
        The elastic joint's load inertia [kg*m^2], K [N*m/rad] and d [N*m*s/rad]; 0 for rigid.
    """
    jm = v.real("inertia", inertia, positive=True, unit="kg*m^2")
    v.instance("friction", friction, FrictionModel)
    jl = v.real("load_inertia", load_inertia, nonneg=True, unit="kg*m^2")
    k = v.real("stiffness", stiffness, nonneg=True, unit="N*m/rad")
    d = v.real("damping", damping, nonneg=True, unit="N*m*s/rad")
    # the drift changes the scale over a run: the caller checks the scale stays positive, and
    # uses the largest scale of the run when it passes one (``friction.scaled``)
    b = friction.scale * max(friction.viscous_pos, friction.viscous_neg) + friction.lugre_sigma1
    rates = [b / jm]
    if jl > 0 and k > 0:
        inv = 1.0 / jm + 1.0 / jl
        rates += [math.sqrt(k * inv), d * inv]
    return float(max(rates))


def required_substeps(*, sample_time: float, rate: float) -> int:
    """Sub-steps per sample keeping ``h*rate <= RATE_PER_SUBSTEP`` (at least 1)."""
    ts = v.real("sample_time", sample_time, positive=True, unit="s")
    r = v.real("rate", rate, nonneg=True, unit="1/s")
    return max(1, int(math.ceil(ts * r / RATE_PER_SUBSTEP)))
