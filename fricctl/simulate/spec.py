"""Typed specifications of a batch for the compiled loop: plant, loop, control, compensator.

:mod:`fricctl.simulate.api` checks the user's arguments and builds these four records;
:mod:`fricctl.simulate.loop` reads their fields by name inside compiled code (numba
compiles a :class:`typing.NamedTuple` of arrays, floats and ints as one argument).  A new
plant parameter or loop setting is one field here, filled where the spec is built and read
where the loop needs it; no signature between the two changes.

Arrays indexed by run have N rows (N runs in the batch).  Per-sample arrays are 2-D,
``[run, sample]``: a single row (or column) is shared by every run (or every sample), so
gains constant over a run are ``(N, 1)`` and a reference shared by the runs is ``(1, K)``.

Notes
-----
The records are immutable, their arrays are not: the loop only reads them.  They hold no
validation of their own; the entry points of :mod:`fricctl.simulate.api` check every value
before building them.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..friction import NPARAM

__all__ = ["PlantSpec", "LoopSpec", "ControlSpec", "CompensatorSpec"]


class PlantSpec(NamedTuple):
    """The joint of each run, in the form the plant kernels (:mod:`fricctl.plant.kernels`) read.

    Attributes
    ----------
    kind : int
        :data:`~fricctl.plant.RIGID`, :data:`~fricctl.plant.FLEXIBLE` or
        :data:`~fricctl.plant.STATE`; one for the whole batch.
    friction : ndarray, shape (N, NPARAM)
        Each run's true friction as its coefficient vector in the layout of
        :mod:`fricctl.friction.layout` (units per coefficient there).
    motor_inertia : ndarray, shape (N,)
        Inertia on the motor side (friction, encoder) [kg*m^2]; the total inertia of a
        rigid joint.
    load_inertia : ndarray, shape (N,)
        Inertia behind the spring [kg*m^2] (rigid joint: the total inertia, unused).
    stiffness : ndarray, shape (N,)
        Spring stiffness K of the elastic joint [N*m/rad] (0 for a rigid joint).
    damping : ndarray, shape (N,)
        Damping across the spring [N*m*s/rad] (0 for a rigid joint).
    backlash : ndarray, shape (N,)
        Total width of the dead band between motor and load [rad] (0: none; the spring
        then acts on the dead-zoned deflection, the damper only in contact).
    substeps : int
        RK4 sub-intervals per held-torque interval [-].
    """

    kind: int
    friction: np.ndarray
    motor_inertia: np.ndarray
    load_inertia: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    backlash: np.ndarray
    substeps: int

    @classmethod
    def of(cls, joints, frictions, substeps: int) -> "PlantSpec":
        """The spec of N runs from their :class:`~fricctl.plant.KernelArgs` and
        :class:`~fricctl.friction.FrictionModel` (one each per run, one kind)."""
        friction = np.array([f.vector() for f in frictions]).reshape(len(frictions), NPARAM)
        return cls(kind=joints[0].kind, friction=friction,
                   motor_inertia=np.array([a.motor_inertia for a in joints]),
                   load_inertia=np.array([a.load_inertia for a in joints]),
                   stiffness=np.array([a.stiffness for a in joints]),
                   damping=np.array([a.damping for a in joints]),
                   backlash=np.array([a.backlash for a in joints]),
                   substeps=substeps)


class LoopSpec(NamedTuple):
    """The sampled loop around the joint: sampling, encoder, drive and initial position.

    Attributes
    ----------
    sample_time : float
        Ts, the sample time of every run [s].
    encoder_resolution : ndarray, shape (N,)
        One encoder count [rad] (0: no quantisation).
    max_torque : ndarray, shape (N,)
        Saturation of the commanded and of the received torque [N*m] (``inf``: none).
    q0 : ndarray, shape (N,)
        Initial position, at rest [rad].
    delay : int
        Whole samples by which the joint receives the recorded torque late [-].
    noise : ndarray, shape (N or 1, K) or (1, 1)
        Torque added to what the joint receives at each sample [N*m]; a ``(1, 1)`` array
        means none.
    position_noise : ndarray, shape (N or 1, K) or (1, 1)
        Position added to the joint's position before the encoder quantises it, at each
        sample [rad] (encoder edge jitter: the reading flickers between counts at rest); a
        ``(1, 1)`` array means none (the reading is that of the true position, bit for bit).
    """

    sample_time: float
    encoder_resolution: np.ndarray
    max_torque: np.ndarray
    q0: np.ndarray
    delay: int
    noise: np.ndarray
    position_noise: np.ndarray


class ControlSpec(NamedTuple):
    """The controller's per-sample settings: ``Tc = ff + Kp*(r - y) - Kd*omega_hat``.

    Every field is a 2-D ``[run, sample]`` array (a single row or column is shared, see
    :mod:`fricctl.simulate.spec`).

    Attributes
    ----------
    reference : ndarray
        Position reference r [rad]; relative to the segment's first encoder reading when
        there are segments.
    feedforward : ndarray
        Open-loop torque ff [N*m].
    kp : ndarray
        Proportional gain [N*m/rad] (0: open loop).
    kd : ndarray
        Derivative gain on the estimated velocity [N*m*s/rad].
    segment_start : ndarray of bool
        True at the first sample of a segment, where the reference is re-zeroed at the
        current encoder reading; a ``(1, 1)`` array means no segments (r is absolute).
    """

    reference: np.ndarray
    feedforward: np.ndarray
    kp: np.ndarray
    kd: np.ndarray
    segment_start: np.ndarray

    @classmethod
    def of(cls, controllers, t) -> "ControlSpec":
        """The spec of N runs' :class:`~fricctl.controllers.Controller` objects at sample
        instants ``t`` [s] (one shared row of signals when every run has the same object)."""
        signals = controllers[:1] if len({id(c) for c in controllers}) == 1 else controllers
        return cls(reference=np.array([c.reference(t) for c in signals]),
                   feedforward=np.array([c.feedforward(t) for c in signals]),
                   kp=np.array([[c.kp] for c in controllers], dtype=float),
                   kd=np.array([[c.kd] for c in controllers], dtype=float),
                   segment_start=np.zeros((1, 1), dtype=np.bool_))


class CompensatorSpec(NamedTuple):
    """Compensators the compiled loop evaluates itself, one per run: kind, parameters, state.

    Attributes
    ----------
    kind : ndarray of int64, shape (N,)
        Each run's kind id (:attr:`fricctl.compensators.Entry.kind`; the runs of a batch
        may differ).
    params : ndarray, shape (N, P)
        Each run's parameter vector in its kind's layout (Coulomb: pos [N*m], neg [N*m],
        dead band [rad/s]; NN: :mod:`fricctl.netlayout`; the others: their module's
        ``P_*``), zero-padded to the longest.
    state : ndarray, shape (N, S)
        Each run's initial state in its kind's layout (zero-padded, S >= 1); the loop
        works on a copy.
    scale : ndarray, shape (N,)
        Compensation scale s in ``Tm = clip(Tc + s*T^at)`` [-].
    """

    kind: np.ndarray
    params: np.ndarray
    state: np.ndarray
    scale: np.ndarray

    @classmethod
    def of(cls, compensators) -> "CompensatorSpec | None":
        """The spec of N runs' :class:`~fricctl.compensators.Compensator` objects, or None
        when one of them has no compiled form (the Python loop runs).

        Raises
        ------
        ValueError
            A compiled compensator's parameters or state contain NaN or inf (a compensator
            stores "no limit" as a finite code, e.g. integral action's 0), or a batch mixes
            a compensator with a state (compiled only) with one that runs in Python.
        """
        compiled = [c.compiled() for c in compensators]
        for c in compiled:
            if c is not None and not (np.all(np.isfinite(c.params)) and np.all(np.isfinite(c.state))):
                raise ValueError("the compensator's parameters contain NaN or inf")
        if any(c is None for c in compiled):
            stateful = [k.name for k in compensators if k.stateful]
            if stateful:
                raise ValueError(f"the batch mixes the {stateful[0]} compensator (it has a state: "
                                 "compiled loop only) with an estimator that runs in Python; "
                                 "simulate them in separate calls")
            return None
        params = np.zeros((len(compiled), max(c.params.size for c in compiled)))
        state = np.zeros((len(compiled), max([1] + [c.state.size for c in compiled])))
        for i, c in enumerate(compiled):
            params[i, :c.params.size] = c.params
            state[i, :c.state.size] = c.state
        return cls(kind=np.array([c.kind for c in compiled], dtype=np.int64), params=params,
                   state=state, scale=np.array([c.scale for c in compensators], dtype=float))

