"""The public joint objects: :class:`RigidJoint` (paper Eq. 2) and :class:`FlexibleJoint` (Eq. 1).

Both hand the compiled kernels (:mod:`fricctl.plant.kernels`) their arguments
through :meth:`kernel_args` and share :meth:`advance` (one held-torque interval)
and :meth:`resistive_torque`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _validate as v
from ..friction import FrictionLaw, FrictionModel
from ..params import ActuatorParams
from .kernels import FLEXIBLE, RIGID, STATE, advance, state_torque

__all__ = ["RigidJoint", "FlexibleJoint", "KernelArgs", "JointTorque", "plant_label", "checked_state",
           "checked_substeps"]


@dataclass(frozen=True, kw_only=True)
class KernelArgs:
    """What the compiled kernels need of a joint."""

    kind: int
    """:data:`~fricctl.plant.RIGID`, :data:`~fricctl.plant.FLEXIBLE` or `~fricctl.plant.STATE` (a presliding law)."""
    motor_inertia: float
    """Inertia on the motor (friction, encoder) side [kg*m^2]; the total one for a rigid joint."""
    load_inertia: float
    """Inertia behind the spring [kg*m^2] (the total one for a rigid joint: unused)."""
    stiffness: float
    """K [N*m/rad] (0 for a rigid joint)."""
    damping: float
    """Damping across the spring [N*m*s/rad] (0 for a rigid joint)."""
    backlash: float = 0.0
    """Total width of the dead band between motor and load, load side [rad] (0: none)."""


@dataclass(frozen=True, kw_only=True)
class JointTorque:
    """Resistive torque and acceleration of a joint right after an instant."""

    friction: float
    """Resistive torque Tat on the motor side (the reaction when stuck) [N*m]."""
    acceleration: float
    """Motor-side acceleration [rad/s^2]."""


def plant_label(kind: int, friction: FrictionModel) -> str:
    """``"rigid"``, ``"flexible"`` or ``"rigid (<presliding law>)"`` for a kernel's plant kind."""
    if kind == STATE:
        return f"rigid ({friction.state_law.constructor.__name__})"
    return "flexible" if kind == FLEXIBLE else "rigid"


def checked_state(state) -> np.ndarray:
    """A copy of ``state`` as 5 finite floats ``[q, omega, q_load, omega_load, z]``."""
    st = v.array("state", state, ndim=None).copy()
    if st.shape != (5,):
        raise ValueError(f"state must have shape (5,) [q, omega, q_load, omega_load, z], got {st.shape}")
    return st


def checked_substeps(substeps) -> int:
    """RK4 sub-intervals per sample: an integer >= 1."""
    return v.integer("substeps", substeps, low=1)


def _friction(friction) -> FrictionModel:
    if isinstance(friction, FrictionLaw):
        return friction.model()
    return v.instance("friction", friction, FrictionModel, "a fricctl.friction.FrictionModel")


class _Joint:
    """What both joints share: the state vector, one interval, the resistive torque."""

    friction: FrictionModel

    def kernel_args(self) -> KernelArgs:  # pragma: no cover - abstract
        raise NotImplementedError

    def initial_state(self, q0: float = 0.0, omega0: float = 0.0) -> np.ndarray:
        """State vector ``[q, omega, q_load, omega_load, z]`` at (q0, omega0), spring relaxed."""
        q0 = v.real("q0", q0)
        omega0 = v.real("omega0", omega0)
        return np.array([q0, omega0, q0, omega0, 0.0], dtype=float)

    def advance(self, state, torque: float, t0: float, dt: float, substeps: int = 4) -> np.ndarray:
        """State after holding ``torque`` [N*m] for ``dt`` [s] from time ``t0`` [s]."""
        st = checked_state(state)
        torque = v.real("torque", torque)
        t0 = v.real("t0", t0)
        dt = v.real("dt", dt, positive=True)
        a = self.kernel_args()
        advance(a.kind, st, self.friction.vector(), torque, t0, dt, checked_substeps(substeps),
                a.motor_inertia, a.load_inertia, a.stiffness, a.damping, a.backlash)
        return st

    def resistive_torque(self, state, torque: float, t: float = 0.0) -> JointTorque:
        """Resistive torque and acceleration right after ``t`` with ``torque`` [N*m] applied."""
        st = checked_state(state)
        a = self.kernel_args()
        f, acc = state_torque(a.kind, st, self.friction.vector(), v.real("torque", torque),
                              v.real("t", t), a.motor_inertia, a.stiffness, a.damping,
                              a.backlash)
        return JointTorque(friction=float(f), acceleration=float(acc))


@dataclass(frozen=True, kw_only=True)
class RigidJoint(_Joint):
    """Rigid joint ``I*q'' = Tm - Tat`` (paper Eq. 2).

    Parameters
    ----------
    inertia : float
        Total inertia I (actuator + link), load side [kg*m^2].
    friction : FrictionModel
        Resistive torque law.  A :class:`~fricctl.friction.LuGre` model is
        integrated without stick events.

    Examples
    --------
    >>> from fricctl.params import paper_actuator
    >>> p = paper_actuator()
    >>> joint = RigidJoint.from_params(p)
    >>> st = joint.initial_state()
    >>> float(joint.advance(st, torque=0.9 * p.static, t0=0.0, dt=0.002)[0])   # below breakaway
    0.0
    """

    inertia: float
    friction: FrictionModel

    def __post_init__(self):
        object.__setattr__(self, "inertia", v.real("inertia", self.inertia, positive=True,
                                                   unit="kg*m^2"))
        object.__setattr__(self, "friction", _friction(self.friction))

    @classmethod
    def from_params(cls, params: ActuatorParams, friction: FrictionModel | None = None):
        """The rigid joint of an actuator (``total_inertia``; its nominal friction by default)."""
        v.instance("params", params, ActuatorParams)
        return cls(inertia=params.total_inertia,
                   friction=params.friction_model() if friction is None else friction)

    @property
    def kind(self) -> int:
        return STATE if self.friction.has_state else RIGID

    def kernel_args(self) -> KernelArgs:
        return KernelArgs(kind=self.kind, motor_inertia=self.inertia, load_inertia=self.inertia,
                          stiffness=0.0, damping=0.0)


@dataclass(frozen=True, kw_only=True)
class FlexibleJoint(_Joint):
    """Elastic joint of paper Eq. 1: motor and load inertias joined by K and d.

    Friction acts on the motor side; the encoder is on the rotor (motor side).

    Parameters
    ----------
    motor_inertia : float
        Jm, rotor and flange reflected to the load side [kg*m^2].
    load_inertia : float
        Jl, link (and output flange) [kg*m^2].
    stiffness : float
        K [N*m/rad].
    damping : float
        d [N*m*s/rad].
    friction : FrictionModel
        Motor-side resistive torque law (LuGre not supported here).
    backlash : float
        Total width of a dead band between motor and load, load side [rad] ([m] on a
        linear axis); 0 (default): none.  With a gap the spring acts on the dead-zoned
        deflection ``dz(qm - ql)`` and the damper only in contact, and the contact only
        pushes: the motor crosses the gap with the load uncoupled (the load coasts), and
        picks it up with an impact.  A rigid joint with backlash is this joint with a stiff
        contact (a contact resonance above the band of interest).

    Notes
    -----
    The contact's onset is not located as an event: RK4 steps across it (the coupling torque
    is continuous in the deflection, its damper part jumps), so use sub-steps short against
    the contact's period (the default rule of :func:`fricctl.simulate.replay` sizes them by
    the contact resonance).
    """

    motor_inertia: float
    load_inertia: float
    stiffness: float
    damping: float
    friction: FrictionModel
    backlash: float = 0.0

    def __post_init__(self):
        for name, unit in (("motor_inertia", "kg*m^2"), ("load_inertia", "kg*m^2"),
                           ("stiffness", "N*m/rad")):
            object.__setattr__(self, name, v.real(name, getattr(self, name), positive=True, unit=unit))
        object.__setattr__(self, "damping", v.real("damping", self.damping, nonneg=True,
                                                   unit="N*m*s/rad"))
        object.__setattr__(self, "backlash", v.real("backlash", self.backlash, nonneg=True,
                                                    unit="rad"))
        object.__setattr__(self, "friction", _friction(self.friction))
        if self.friction.has_state:
            raise ValueError(f"{self.friction.state_law.constructor.__name__} friction is supported "
                             "on the rigid joint only")

    @classmethod
    def from_params(cls, params: ActuatorParams, friction: FrictionModel | None = None):
        """The elastic joint of an actuator with a link (``inertia`` | ``link_inertia``)."""
        v.instance("params", params, ActuatorParams)
        if params.link_inertia <= 0:
            raise ValueError("link_inertia must be > 0 for a flexible joint (the load side needs inertia)")
        return cls(motor_inertia=params.inertia, load_inertia=params.link_inertia,
                   stiffness=params.stiffness, damping=params.joint_damping,
                   friction=params.friction_model() if friction is None else friction)

    @property
    def kind(self) -> int:
        return FLEXIBLE

    @property
    def resonance(self) -> float:
        """Free (unlocked) resonance sqrt(K (1/Jm + 1/Jl)) [rad/s]."""
        return math.sqrt(self.stiffness * (1.0 / self.motor_inertia + 1.0 / self.load_inertia))

    def initial_state(self, q0: float = 0.0, omega0: float = 0.0) -> np.ndarray:
        """State vector ``[q, omega, q_load, omega_load, z]`` at (q0, omega0), spring relaxed;
        with backlash, a moving joint starts with the load in contact on the driving face
        (``q_load = q0 - sign(omega0) * backlash/2``), a joint at rest in the middle of the gap."""
        st = super().initial_state(q0, omega0)
        if self.backlash > 0 and st[1] != 0.0:
            st[2] -= math.copysign(0.5 * self.backlash, st[1])
        return st

    def kernel_args(self) -> KernelArgs:
        return KernelArgs(kind=FLEXIBLE, motor_inertia=self.motor_inertia,
                          load_inertia=self.load_inertia, stiffness=self.stiffness,
                          damping=self.damping, backlash=self.backlash)
