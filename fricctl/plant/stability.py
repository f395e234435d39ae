"""How many RK4 sub-steps a joint needs: its fastest rate against the sample time.

The compiled kernels integrate the sliding dynamics with classical RK4 on ``substeps``
sub-intervals of each sample.  RK4 is only stable while ``h*|lambda|`` stays below about
2.8 (2.785 on the negative real axis, 2.828 on the imaginary one), ``lambda`` the
plant's fastest eigenvalue; beyond it the state grows without bound (a viscous
coefficient of 20 N*m*s/rad on the paper's actuator gave ``|q| = 1.8e300``).  The rule
here keeps ``h*|lambda| <= 1``, well inside the region and accurate to about 2 % per
sub-step on the fastest mode:

* the friction laws' slopes on the moving inertia: ``lambda = d/J`` with ``d`` the sum of
  what each registered law declares (:attr:`fricctl.friction.Law.damping`: the viscous
  coefficient, the drag's ``2*c*|w|`` at the largest speed, the LuGre bristle damping);
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

import numpy as np

from .. import _validate as v
from ..friction import LAWS, FrictionModel

__all__ = ["fastest_rate", "friction_slope", "speed_bound", "required_substeps", "MAX_SUBSTEPS", "RATE_PER_SUBSTEP"]

#: ``h*|lambda|`` allowed per sub-step [-].
RATE_PER_SUBSTEP = 1.0
#: Most sub-steps per sample a simulation will run (above it: refused, with the number).
MAX_SUBSTEPS = 100_000


def friction_slope(friction: FrictionModel, speed: float | None = None) -> float:
    """The largest slope ``dTat/dw`` the model's laws declare up to ``speed`` [N*m*s/rad].

    Friction laws (rate and level roles) are multiplied by the model's scale; a presliding
    law's damping is not.  ``speed`` None: the slopes that grow with speed (drag) count as 0.
    """
    scaled = unscaled = 0.0
    for law in LAWS.values():
        if law.damping is None:
            continue
        d = law.damping(law.values(friction), speed)
        if law.role in ("rate", "level"):
            scaled += d
        else:
            unscaled += d
    return friction.scale * scaled + unscaled


def fastest_rate(*, inertia: float, friction: FrictionModel, load_inertia: float = 0.0,
                 stiffness: float = 0.0, damping: float = 0.0, speed: float | None = None) -> float:
    """The fastest linear rate of the joint's sliding dynamics [1/s].

    Parameters
    ----------
    inertia : float
        Motor-side inertia (the whole inertia of a rigid joint) [kg*m^2].
    friction : FrictionModel
    load_inertia, stiffness, damping : float
        The elastic joint's load inertia [kg*m^2], K [N*m/rad] and d [N*m*s/rad]; 0 for rigid.
    speed : float, optional
        The largest speed of the run, for laws whose slope grows with speed (drag) [rad/s].
    """
    jm = v.real("inertia", inertia, positive=True, unit="kg*m^2")
    v.instance("friction", friction, FrictionModel)
    jl = v.real("load_inertia", load_inertia, nonneg=True, unit="kg*m^2")
    k = v.real("stiffness", stiffness, nonneg=True, unit="N*m/rad")
    d = v.real("damping", damping, nonneg=True, unit="N*m*s/rad")
    if speed is not None:
        speed = v.real("speed", speed, nonneg=True, unit="rad/s")
    # the drift changes the scale over a run: the caller checks the scale stays positive, and
    # uses the largest scale of the run when it passes one (``friction.scaled``)
    rates = [friction_slope(friction, speed) / jm]
    if jl > 0 and k > 0:
        inv = 1.0 / jm + 1.0 / jl
        rates += [math.sqrt(k * inv), d * inv]
    return float(max(rates))


def speed_bound(friction: FrictionModel, torque: float | None, omega0: float = 0.0) -> float | None:
    """The largest speed a joint reaches from ``omega0`` under drive torques up to ``torque`` [rad/s].

    Friction grows with speed while sliding, so the joint cannot outrun the speed where its
    sliding friction (with the position torques at their worst) equals the largest drive torque;
    a run that starts faster only slows down.  None when ``torque`` is unknown (None) or the
    friction never reaches it (no rate law: then no law's slope depends on speed).
    """
    w0 = abs(v.real("omega0", omega0))
    if torque is None:
        return None
    # the position laws (ripple, load) at their worst push the joint on
    need = abs(v.real("torque", torque)) + sum(law.peak(law.values(friction))
                                               for law in LAWS.values() if law.peak is not None)

    def sliding(w):  # the weaker direction's sliding friction at speed(s) w, ripple left out
        return np.minimum(np.abs(friction.torque(w) - friction.ripple(0.0)),
                          np.abs(friction.torque(-np.asarray(w)) - friction.ripple(0.0)))

    # the last speed of a log grid where friction is still below the torque (a Stribeck level
    # falls with speed first, so the first crossing is not the joint's top speed), then bisection
    grid = np.logspace(-6, 12, 181)
    below = np.flatnonzero(sliding(grid) < need)
    if below.size == 0:
        return w0
    if below[-1] == grid.size - 1:
        return None  # friction never reaches the torque: no finite top speed
    lo, hi = float(grid[below[-1]]), float(grid[below[-1] + 1])
    for _ in range(60):  # bisection
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if sliding(mid) < need else (lo, mid)
    return max(hi, w0)


def required_substeps(*, sample_time: float, rate: float) -> int:
    """Sub-steps per sample keeping ``h*rate <= RATE_PER_SUBSTEP`` (at least 1)."""
    ts = v.real("sample_time", sample_time, positive=True, unit="s")
    r = v.real("rate", rate, nonneg=True, unit="1/s")
    return max(1, int(math.ceil(ts * r / RATE_PER_SUBSTEP)))
