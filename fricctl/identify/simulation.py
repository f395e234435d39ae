"""A record simulated with identified parameters: the model half of IDIM-IV and DIDIM.

Both refinements of IDIM-LS need what the *model* says the record should have been:
IDIM-IV builds its instruments from the simulated (noise-free) motion
(:mod:`~fricctl.identify.iv`), DIDIM minimises the simulation error
(:mod:`~fricctl.identify.didim`).  This module says once how a record is simulated:

* **closed loop** when the record's controller is known -- the record's reference
  through a PD law ``Tm = kp*(r - y) - kd*omega_hat`` in the package's one sampled
  loop (:func:`fricctl.simulate.simulate_model`: backward-difference velocity, one
  sample of computation delay), given as ``controller`` or, when the record has a
  reference that moves, the PD gains fitted to the record's torque
  (:func:`record_loop`);
* **open loop** otherwise -- the recorded torque replayed on the rigid joint
  (:func:`fricctl.simulate.replay`), starting from the record's first position and
  its estimated velocity.

The simulated joint is the :class:`~fricctl.plant.JointModel` of the parameters
(:meth:`~fricctl.plant.JointModel.from_estimates`: rigid, ``offset`` a constant torque the
joint does not receive), without encoder quantisation or noise.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .. import _validate as v
from ..controllers import Controller, from_array, pd_control
from ..datasets import Run

__all__ = ["RecordLoop", "SimulatedRecord", "record_loop", "simulate_record", "initial_velocity",
           "record_substeps", "PD_FIT_TOLERANCE"]

#: Largest relative error [-] of the PD law fitted to a record's torque for the record to be
#: simulated in closed loop with it (EMPS: 0.047, its own law differs from the loop's by a
#: half-sample velocity filter and a sample of delay; a record of the package's loop: 0).
PD_FIT_TOLERANCE = 0.1


@dataclass(frozen=True, kw_only=True)
class RecordLoop:
    """How a record is simulated: open loop, or closed through a PD law."""

    closed: bool
    """True: the reference through the PD law; False: the recorded torque replayed."""
    kp: float = field(default=0.0, metadata={"unit": "N*m/rad or N/m"})
    """Proportional gain of the closed loop [N*m/rad] or [N/m]."""
    kd: float = field(default=0.0, metadata={"unit": "N*m*s/rad or N*s/m"})
    """Rate-feedback gain of the closed loop [N*m*s/rad] or [N*s/m]."""
    source: str = ""
    """Where the gains come from ("given", "fitted to the record's torque", "")."""
    warnings: tuple = ()
    """Why a record with a reference is simulated open loop (one sentence each)."""

    def __post_init__(self):
        object.__setattr__(self, "closed", v.flag("closed", self.closed))
        object.__setattr__(self, "kp", v.real("kp", self.kp, nonneg=True))
        object.__setattr__(self, "kd", v.real("kd", self.kd, nonneg=True))
        object.__setattr__(self, "warnings", tuple(self.warnings))

    def describe(self) -> str:
        """One phrase: ``"closed loop (PD kp=..., kd=..., given)"`` or ``"open loop"``."""
        if not self.closed:
            return "open loop (recorded torque replayed)"
        return f"closed loop (PD kp={self.kp:.6g}, kd={self.kd:.6g}, {self.source})"


@dataclass(frozen=True, kw_only=True)
class SimulatedRecord:
    """The record as the model simulates it, sample by sample (no quantisation, no noise)."""

    position: np.ndarray = field(metadata={"unit": "rad or m"})
    """Simulated position [rad] or [m]."""
    velocity: np.ndarray = field(metadata={"unit": "rad/s or m/s"})
    """Simulated velocity [rad/s] or [m/s]."""
    torque: np.ndarray = field(metadata={"unit": "N*m or N"})
    """Torque the simulated drive applies (the recorded one in open loop) [N*m] or [N]."""

    def __post_init__(self):
        for name in ("position", "velocity", "torque"):
            x = np.array(getattr(self, name), dtype=float)
            x.setflags(write=False)
            object.__setattr__(self, name, x)


def _fitted_pd(run: Run) -> tuple:
    """(kp, kd, relative error) of ``Tm_{k+1} = kp*(r_k - y_k) - kd*(y_k - y_{k-1})/Ts``,
    the loop's own timing (:mod:`fricctl.simulate`), by least squares on the record."""
    y, r, tm, ts = run.position, run.reference, run.torque, run.sample_time
    X = np.column_stack([(r - y)[1:-1], -np.diff(y)[:-1] / ts])
    b = tm[2:]
    g, *_ = np.linalg.lstsq(X, b, rcond=None)
    err = float(np.linalg.norm(b - X @ g) / (np.linalg.norm(b) or 1.0))
    return float(g[0]), float(g[1]), err


def record_loop(run, controller: Controller | None = None) -> RecordLoop:
    """How to simulate ``run``: closed loop through its controller, or open loop.

    Parameters
    ----------
    run : fricctl.datasets.Run
        The record.
    controller : fricctl.controllers.Controller, optional
        The record's controller; its ``kp`` and ``kd`` are used with the *record's*
        reference (its own reference and feed-forward are ignored).  Needs a record
        with a reference column.  Default: fitted (see Notes).

    Notes
    -----
    Without ``controller``, a record whose reference moves is simulated in closed loop
    with the PD gains that best explain its torque in the loop's timing, when they
    explain it to :data:`PD_FIT_TOLERANCE` (relative error) and both are positive;
    otherwise, and for a record without reference, open loop with a warning.  A record
    whose reference is constant (what :meth:`fricctl.simulate.SimResult.to_run` writes
    for an open-loop run) is open loop, without warning.
    """
    v.instance("run", run, Run, "a fricctl.datasets.Run")
    if controller is not None:
        v.instance("controller", controller, Controller, "a fricctl.controllers.Controller")
        if run.reference is None:
            raise ValueError("controller: the record has no reference column to feed it")
        return RecordLoop(closed=True, kp=controller.kp, kd=controller.kd, source="given")
    if run.reference is None:
        return RecordLoop(closed=False, warnings=(
            "the record has no reference column: simulated open loop (recorded torque "
            "replayed), not through its controller",))
    if np.ptp(run.reference) == 0.0:
        return RecordLoop(closed=False)
    kp, kd, err = _fitted_pd(run)
    if err <= PD_FIT_TOLERANCE and kp > 0 and kd > 0:
        return RecordLoop(closed=True, kp=kp, kd=kd,
                          source=f"fitted to the record's torque, relative error {100 * err:.2g} %")
    return RecordLoop(closed=False, warnings=(
        f"no PD law explains the record's torque (best kp={kp:.3g}, kd={kd:.3g}, relative "
        f"error {100 * err:.2g} %): simulated open loop; give the controller",))


def simulate_record(run, parameters: dict, loop: RecordLoop, *,
                    initial_velocity: float = 0.0) -> SimulatedRecord:
    """Simulate ``run`` with identified ``parameters`` (names of :data:`~fricctl.identify.MODELS`).

    Parameters
    ----------
    run : fricctl.datasets.Run
        The record (its torque in open loop, its reference in closed loop).
    parameters : dict
        Name -> value of a linear friction model (``inertia`` > 0).
    loop : RecordLoop
        From :func:`record_loop`.
    initial_velocity : float
        Velocity at the first sample of an open-loop replay [rad/s] or [m/s] (a closed
        loop starts at rest).

    Raises
    ------
    ValueError
        ``inertia`` not positive (the joint cannot be simulated), or a diverging run.
    """
    from ..plant.model import JointModel
    from ..simulate import replay, simulate_model

    v.instance("loop", loop, RecordLoop)
    if not parameters.get("inertia", 0.0) > 0:
        raise ValueError(f"parameters: inertia {parameters.get('inertia')} is not positive; "
                         "the joint cannot be simulated")
    model = JointModel.from_estimates(parameters, units=run.units, source="identification",
                                      sample_time=run.sample_time)
    if not loop.closed:
        out = replay(model.joint(), run.torque - model.offset, run.sample_time,
                     q0=float(run.position[0]), omega0=v.real("initial_velocity", initial_velocity))
        return SimulatedRecord(position=out.q, velocity=out.omega, torque=run.torque)
    ref = from_array(run.t - run.t[0], run.reference)
    sim = simulate_model(model, pd_control(loop.kp, loop.kd, ref), duration=run.n_samples *
                         run.sample_time, q0=float(run.position[0]), quantize=False)
    n = run.n_samples  # the loop's sample count is round(duration/Ts): the record's
    return SimulatedRecord(position=sim.q[:n], velocity=sim.omega[:n], torque=sim.torque_motor[:n])


def record_substeps(run, parameters: dict) -> int:
    """RK4 sub-steps per sample :func:`simulate_record` runs for ``parameters`` on ``run`` [-]:
    the kernels' default, raised to what the joint's fastest rate (viscous/inertia for the
    linear models) needs at the record's sample time (:mod:`fricctl.plant.stability`).  A
    simulation's cost is proportional to it (times the record's samples).

    Raises
    ------
    ValueError
        ``inertia`` not positive.
    """
    from ..plant.model import JointModel
    from ..plant.stability import fastest_rate, required_substeps
    from ..simulate import DEFAULT_SUBSTEPS

    v.instance("run", run, Run, "a fricctl.datasets.Run")
    if not parameters.get("inertia", 0.0) > 0:
        raise ValueError(f"parameters: inertia {parameters.get('inertia')} is not positive; "
                         "the joint cannot be simulated")
    joint = JointModel.from_estimates(parameters, units=run.units, source="identification",
                                      sample_time=run.sample_time).joint()
    rate = fastest_rate(inertia=joint.inertia, friction=joint.friction)
    return max(DEFAULT_SUBSTEPS[joint.kind], required_substeps(sample_time=run.sample_time,
                                                               rate=rate))


def initial_velocity(run, cutoff: float, order: int) -> float:
    """Velocity at the record's first sample, to start an open-loop replay [rad/s] or [m/s]:
    the Butterworth + central-difference estimate there (cut-off [Hz], order [-]); its
    error decays with the joint's mechanical time constant."""
    from ..estimation import butterworth_central

    v.instance("run", run, Run, "a fricctl.datasets.Run")
    return float(butterworth_central(run.t, run.position, cutoff=cutoff, order=order).velocity[0])
