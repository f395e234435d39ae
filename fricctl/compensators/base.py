"""What a compensator module provides: :class:`Compensator`, :class:`CompiledCompensator`,
:class:`Entry` (the registry's entry) and :class:`CCode` (its C export).

Kept apart from :mod:`fricctl.compensators` (the registry) so that a compensator module
imports its interface without importing the registry that imports it.

The compiled step
-----------------
A compensator owns a parameter vector ``p`` (fixed for a run) and a state vector ``x``
(changed in place by its step; empty for a memoryless one).  At sample k the compiled loop
(:mod:`fricctl.simulate.loop`) calls the step of the run's kind with the signals its step
function names, from :data:`SIGNALS`:

``tm``
    ``Tm_k``, the motor torque commanded at sample k-1 and held over ``[k Ts, (k+1) Ts)``
    [N*m] (what the loop applies now, before any delay of the plant);
``wh``
    ``omega_hat_k = (y_k - y_{k-1}) / Ts``, the backward-difference velocity [rad/s]: the
    mean velocity over the *previous* interval (0 at k = 0);
``y``
    ``y_k``, the encoder reading [rad];
``r``
    ``r_k``, the position reference [rad];
``tc``
    ``Tc_k``, the controller's torque (feed-forward + PD) [N*m];
``ts``
    Ts, the sample time [s].

and adds ``s * T^at_k`` (its return value) to ``Tc_k``: ``Tm_{k+1} = clip(Tc_k + s*T^at_k)``.
"""

from __future__ import annotations

import inspect
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

__all__ = ["Compensator", "CompiledCompensator", "Entry", "CCode", "SIGNALS", "joint_model",
           "friction_of", "static_curve"]

#: The signals a compiled step may name (besides ``p``, its parameters, and ``x``, its state).
SIGNALS = ("tm", "wh", "y", "r", "tc", "ts")


@dataclass(frozen=True, kw_only=True, eq=False)
class CompiledCompensator:
    """What the compiled loop needs of a compensator: its kind, parameter and state vectors."""

    kind: int
    """The kind id of its registry entry (:attr:`Entry.kind`)."""
    params: np.ndarray
    """Parameters in the kind's layout (Coulomb: pos, neg, dead band; NN:
    :mod:`fricctl.netlayout`; the others: their module's ``P_*`` indices)."""
    state: np.ndarray = field(default_factory=lambda: np.zeros(0))
    """Initial state in the kind's layout (empty: memoryless)."""


class Compensator:
    """Interface: ``scale``, ``name``, ``compiled()`` and, for a memoryless compensator,
    ``__call__(tm, omega_hat) -> T^at`` [N*m]."""

    scale: float = 1.0
    name: str = "compensator"
    #: Kind of axis the compensator was made for (``"rotary"``, ``"linear"``); None: any.
    units: str | None = None
    #: True when it has a state (it runs in the compiled loop only; no ``__call__``).
    stateful: bool = False

    @property
    def needs_reference(self) -> bool:
        """Whether its estimate depends on the position error ``r - y`` (integral action, an
        observer with an error gain): meaningless in an open-loop experiment, which has no
        reference to track."""
        return False

    @property
    def estimates_friction(self) -> bool:
        """Whether ``T^at`` is an estimate of the joint's friction (bounded by the largest
        friction the joint can have: the runaway check :func:`fricctl.paper.runaway.wind_up`
        holds it to that); False for a compensator whose output also carries other torques --
        a disturbance observer (inertia error, load), integral action (its integrated error)
        -- which :func:`fricctl.paper.runaway.divergence` judges instead."""
        return True

    def __call__(self, tm, omega_hat):
        if self.stateful:
            raise ValueError(f"the {self.name} compensator has a state: it is not a function of "
                             "(tm, omega_hat); run it in the loop (fricctl.simulate)")
        raise NotImplementedError  # pragma: no cover - a memoryless subclass defines it

    def compiled(self):
        """A :class:`CompiledCompensator` for the compiled loop, or ``None`` (Python loop)."""
        return None


@dataclass(frozen=True, kw_only=True, eq=False)
class CCode:
    """A compensator as C: the fields of its state struct, its initialisation and its step.

    The generated functions (:func:`fricctl.compensators.c_export.c_source`) are::

        void NAME_init(NAME_state *st, double ts);
        double NAME_step(NAME_state *st, double tm, double omega_hat, double y, double r,
                         double tc);

    ``init`` and ``step`` are C statements with ``st`` the state pointer and ``P_<name>``
    the parameters (``static const double``); ``step`` ends with a ``return``.
    """

    params: tuple
    """``(name, value, comment)`` of each constant parameter."""
    state: tuple
    """``(name, comment)`` of each ``double`` field of the state struct (``ts`` is added)."""
    init: str
    """C statements setting the state (``st->ts`` is already set)."""
    step: str
    """C statements of one sample, ending with ``return T^at;`` (before the scale s)."""


@dataclass(frozen=True, kw_only=True, eq=False)
class Entry:
    """One registered compensator: a module of :mod:`fricctl.compensators` defines ``ENTRY``."""

    name: str
    """Name the user picks it by (``fricctl simulate --compensation NAME``, :func:`make`)."""
    kind: int
    """Its id in the compiled loop, unique; also the order of :func:`available`."""
    description: str
    """One line: what it computes."""
    cls: type
    """The public class."""
    make: Callable
    """``make(model, design, sample_time, **options) -> Compensator``: built from what a user
    has (a :class:`~fricctl.plant.JointModel`, the design, Ts); see each module."""
    step: Callable | None = None
    """The compiled step (plain Python that numba compiles): arguments named ``p``, ``x`` and
    :data:`SIGNALS`; returns ``T^at`` [N*m].  None: 0 (no compensation)."""
    c_code: Callable | None = None
    """``c_code(compensator) -> CCode`` for those meant for a real controller; else None."""

    def __post_init__(self):
        if not (self.name.isidentifier() and self.name.islower()):
            raise ValueError(f"compensator name {self.name!r} must be a lower-case identifier")
        if self.step is not None:
            for arg in inspect.signature(self.step).parameters:
                if arg not in ("p", "x", *SIGNALS):
                    raise ValueError(f"compensator {self.name}: step argument {arg!r} is not "
                                     f"p, x or a signal {SIGNALS}")


def joint_model(model):
    """A :class:`~fricctl.plant.JointModel` of ``model`` (a JointModel, or the
    :class:`~fricctl.params.ActuatorParams` of the paper's actuator as its rigid joint)."""
    from ..params import ActuatorParams
    from ..plant import JointModel

    if isinstance(model, ActuatorParams):
        return JointModel.from_params(model, source="fricctl.params.ActuatorParams")
    if not isinstance(model, JointModel):
        raise ValueError("model must be a fricctl.plant.JointModel or a "
                         f"fricctl.params.ActuatorParams, got {type(model).__name__}")
    return model


def friction_of(model):
    """The :class:`~fricctl.friction.FrictionModel` of a JointModel, ActuatorParams,
    FrictionModel or friction law."""
    from ..friction import FrictionLaw, FrictionModel

    if isinstance(model, FrictionLaw):
        return model.model()
    if isinstance(model, FrictionModel):
        return model
    return joint_model(model).friction


def static_curve(friction, direction: int) -> tuple:
    """``(Fc, Fs - Fc, b)`` of one direction of the identified static model, the friction
    scale applied, and ``(ws, exponent)`` of its Stribeck curve [N*m, N*m, N*m*s/rad, rad/s, -].

    Read from the Coulomb, Stribeck and viscous laws only (static excess, drag, load and
    position terms are left out; a reader of the curve sees that in the caller's Notes).
    """
    s = friction.scale
    pick = (lambda a, b: a) if direction > 0 else (lambda a, b: b)
    return (s * pick(friction.coulomb_pos, friction.coulomb_neg),
            s * pick(friction.stribeck_pos, friction.stribeck_neg),
            s * pick(friction.viscous_pos, friction.viscous_neg),
            friction.stribeck_velocity, friction.stribeck_exponent)
