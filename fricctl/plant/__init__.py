"""The drive joint: rigid (paper Eq. 2) and flexible (paper Eq. 1), exact stick-slip.

Rigid joint (Eq. 2)::

    I * q'' = Tm - Tat(q, q', Tm, t)

Flexible joint (Eq. 1, friction on the motor side, encoder on the rotor)::

    Jm * qm'' = Tm - Tat(qm, qm', Tm, t) - K*(qm - ql) - d*(qm' - ql')
    Jl * ql'' =      K*(qm - ql) + d*(qm' - ql')

All quantities are load side (the rotor is reflected through the gear).

Stick-slip is handled exactly, not smoothed:

* at zero velocity the joint is *stuck* while the net drive torque lies within
  the breakaway band ``[-breakaway(-1), +breakaway(+1)]``; its position is then
  exactly constant (for the flexible joint, the load still moves on the spring);
* while sliding, the smooth sliding dynamics of the current direction are
  integrated with classical RK4 on ``substeps`` sub-intervals of each sample;
* a velocity that reaches zero inside a sub-interval is located by bisection on
  the RK4 map to machine precision; there the stick condition decides between
  stopping and reversing; the flexible joint's release from stick (the spring
  torque crossing the breakaway band) is located the same way.

No chattering arises because the friction of a stuck joint is not a function of
velocity (it is the reaction that keeps it at rest).

With :class:`fricctl.friction.LuGre` the joint has no exact stick (presliding
bristles); the state (q, omega, z) is integrated by RK4 with no events, so use
more substeps (the bristle dynamics are stiff at high speed).

Notes
-----
Backlash (a dead band of total width ``g`` between motor and load) is the flexible
joint with the spring acting on the dead-zoned deflection and the damper only in contact::

    Tc = K*dz(qm - ql) + d*(qm' - ql')   in contact (|qm - ql| > g/2), pushing only
    Tc = 0                               inside the gap
    dz(x) = x - sign(x)*g/2 outside the gap

a rigid joint with backlash is that joint with a stiff contact.

Not modelled: motor electrical dynamics, the kinematic error of the
harmonic drive (use a :class:`~fricctl.friction.PositionRipple`).  A stuck
flexible joint is tested for release once per sub-interval and at its end: an
excursion outside the breakaway band shorter than one sub-interval is missed.
"""

from __future__ import annotations

from .joints import FlexibleJoint, JointTorque, KernelArgs, RigidJoint
from .kernels import FLEXIBLE, LUGRE, RIGID, STATE
from .model import MODEL_FORMAT, MODEL_VERSION, JointModel

__all__ = ["RigidJoint", "FlexibleJoint", "KernelArgs", "JointTorque", "JointModel", "MODEL_FORMAT",
           "MODEL_VERSION", "RIGID", "FLEXIBLE", "STATE", "LUGRE"]
