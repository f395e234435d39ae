"""Typed results of the sampled loop: :class:`SimResult` (one run), :class:`BatchResult`
(N runs), :class:`SimInfo` (what was simulated) and :class:`ReplayResult` (a record replayed)."""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from .. import _validate as v
from ..friction import FrictionModel
from ..params import ActuatorParams
from ..units import KINDS

__all__ = ["SimInfo", "SimResult", "BatchResult", "ReplayResult", "ARRAYS", "SETTLING_BAND"]

#: Fraction of a run's largest error within which a settled run's error stays [-]: the 2 % band
#: of the settling time (python-control's default, ``fricctl.design.SETTLING_THRESHOLD``; not
#: imported from there, so that the simulation does not depend on the design package).
SETTLING_BAND = 0.02


@dataclass(frozen=True, kw_only=True)
class SimInfo:
    """What one run simulated."""

    params: ActuatorParams
    """The actuator."""
    friction_model: FrictionModel
    """The bench's true friction."""
    controller: str
    """``"open loop"``, ``"P"`` or ``"PD"``."""
    kp: float
    """Proportional gain [N*m/rad]."""
    kd: float
    """Rate-feedback gain [N*m*s/rad]."""
    compensator: str
    """Name of the compensator (``"none"``, ``"Coulomb"``, ``"NN"`` ...)."""
    compensation_scale: float
    """s of ``Tm(k+1) = Tc(k) + s*T^at(k)`` [-]."""
    plant: str
    """``"rigid"``, ``"flexible"`` or ``"rigid (LuGre)"``."""
    substeps: int
    """RK4 sub-intervals per sample."""
    delay: int
    """Samples by which the joint receives the recorded torque late."""
    noise_std: float
    """White torque noise at the joint [N*m]."""
    encoder_resolution: float
    """One encoder count [rad]; 0 without quantisation."""
    loop: str
    """``"compiled"`` or ``"python"`` (a compensator only Python can evaluate)."""
    position_noise_std: float = 0.0
    """White position noise added before the encoder quantises (edge jitter) [rad]."""
    units: str = "rotary"
    """The kind of axis, ``"rotary"`` or ``"linear"`` (:mod:`fricctl.units`): the units of every
    quantity of the run, [rad] and [N*m] as written above on a rotary joint, [m] and [N] on a
    linear axis (:func:`~fricctl.simulate.simulate_model` of a linear model).  A report of the run
    (the runaway checks' reasons) labels its numbers by it."""

    def __post_init__(self):
        v.choice("units", self.units, KINDS)


@dataclass(frozen=True, kw_only=True, eq=False)
class _Trajectories:
    """The arrays every result holds: per sample (SimResult) or per run and sample (BatchResult)."""

    t: np.ndarray
    reference: np.ndarray
    q: np.ndarray
    q_meas: np.ndarray
    q_load: np.ndarray
    omega: np.ndarray
    omega_hat: np.ndarray
    torque_cmd: np.ndarray
    torque_motor: np.ndarray
    friction: np.ndarray
    friction_est: np.ndarray
    accel: np.ndarray
    stuck: np.ndarray

    def _final_mean_error(self, window: float, measured: bool = False):
        """Mean of r - q over the last ``window`` seconds along the sample axis [rad]."""
        window = v.real("window", window, positive=True, unit="s")
        sel = self.t >= self.t[-1] - window + 1e-12
        q = self.q_meas if measured else self.q
        return np.mean(self.reference[..., sel] - q[..., sel], axis=-1)


#: Names of the per-sample arrays of a run (all but the time vector).
ARRAYS = tuple(f.name for f in fields(_Trajectories) if f.name != "t")


@dataclass(frozen=True, kw_only=True, eq=False)
class SimResult(_Trajectories):
    """One simulated run; arrays of length K, sample k at ``t[k] = k*Ts``.

    Attributes
    ----------
    t : time [s]
    reference : position reference r_k [rad]
    q : true (motor-side) position [rad]
    q_meas : encoder reading y_k [rad]
    q_load : load-side position (= q for the rigid joint) [rad]
    omega : true velocity [rad/s]
    omega_hat : backward-difference velocity estimate [rad/s]
    torque_cmd : controller output Tc_k [N*m]
    torque_motor : motor torque Tm_k over [t_k, t_k+1) [N*m]
    friction : true resistive torque Tat right after t_k [N*m]
    friction_est : compensator's estimate T^at_k [N*m]
    accel : true acceleration right after t_k [rad/s^2]
    stuck : joint at rest at t_k (omega exactly 0) [bool]
    info : SimInfo, what was simulated
    """

    info: SimInfo

    @property
    def sample_time(self) -> float:
        """Ts [s]."""
        return float(self.t[1] - self.t[0]) if self.t.size > 1 else float("nan")

    @property
    def error(self) -> np.ndarray:
        """Tracking error r - q (true position) [rad]."""
        return self.reference - self.q

    def steady_state_error(self, window: float = 0.5, *, measured: bool = False) -> float:
        """Mean error r - q over the last ``window`` seconds [rad]: a steady-state error only
        where the run has :meth:`settled`.

        Raises
        ------
        ValueError
            For an open-loop run: it has no reference (its ``reference`` array is zero
            by convention), so an error against it would be the position, not an error.
        """
        if self.info.controller == "open loop":
            raise ValueError("an open-loop run has no reference: no steady-state error")
        return float(self._final_mean_error(window, measured))

    def error_spread(self, window: float = 0.5) -> float:
        """Largest departure of r - q from its mean over the last ``window`` seconds [rad].

        How much the run still moves (against its reference) over the stretch that
        :meth:`steady_state_error` averages.
        """
        window = v.real("window", window, positive=True, unit="s")
        sel = self.t >= self.t[-1] - window + 1e-12
        e = self.reference[sel] - self.q[sel]
        return float(np.max(np.abs(e - np.mean(e))))

    def settling_band(self) -> float:
        """Half-width of the band within which a settled run's error stays [rad].

        The larger of one encoder count (a quantised loop may hunt by a count for ever) and
        :data:`SETTLING_BAND` of the run's largest error (for a step, of the step's size).
        """
        biggest = float(np.max(np.abs(self.reference - self.q)))
        return max(float(self.info.encoder_resolution), SETTLING_BAND * biggest)

    def settled(self, window: float = 0.5) -> bool:
        """Whether the run has settled: over the last ``window`` seconds its error r - q stays
        within :meth:`settling_band` of its mean (:meth:`error_spread`).

        A run that has not settled has no steady-state error: :meth:`steady_state_error` is then
        the mean of an error still in motion (a short run, a hunting or tracking loop).

        Raises
        ------
        ValueError
            For an open-loop run (no reference).
        """
        if self.info.controller == "open loop":
            raise ValueError("an open-loop run has no reference: it settles to no error")
        return self.error_spread(window) <= self.settling_band()

    def stuck_intervals(self, min_duration: float = 0.0) -> list[tuple[float, float]]:
        """``(t_start, t_end)`` of the intervals with the joint at rest [s].

        ``t_end`` is the last sample at rest; intervals shorter than
        ``min_duration`` are dropped.
        """
        s = self.stuck.astype(np.int8)
        edges = np.diff(np.concatenate([[0], s, [0]]))
        starts = np.flatnonzero(edges == 1)
        ends = np.flatnonzero(edges == -1) - 1
        return [(float(self.t[a]), float(self.t[b])) for a, b in zip(starts, ends)
                if self.t[b] - self.t[a] >= min_duration]

    def displacement_counts(self) -> int:
        """Peak-to-peak motion seen by the encoder, in counts."""
        res = self.info.encoder_resolution
        span = float(np.ptp(self.q_meas))
        return int(round(span / res)) if res > 0 else int(span > 0)

    def to_run(self, *, source: str = "fricctl simulation"):
        """The measured part as a :class:`fricctl.datasets.Run` (t, Tm, y, r)."""
        from ..datasets import Run

        return Run(t=self.t.copy(), torque=self.torque_motor.copy(), position=self.q_meas.copy(),
                   reference=self.reference.copy(), source=source)


@dataclass(frozen=True, kw_only=True, eq=False)
class BatchResult(_Trajectories):
    """N simulated runs of equal length: ``t`` has shape (K,), every other array (N, K)."""

    infos: tuple
    """One :class:`SimInfo` per run."""

    def __len__(self):
        return self.q.shape[0]

    def __getitem__(self, i) -> SimResult:
        n = len(self)
        if isinstance(i, (bool, np.bool_)) or not isinstance(i, (int, np.integer)) or not -n <= i < n:
            raise IndexError(f"index {i!r} out of range for {n} runs")
        return SimResult(t=self.t, info=self.infos[i], **{k: getattr(self, k)[i] for k in ARRAYS})

    def steady_state_error(self, window: float = 0.5) -> np.ndarray:
        """Mean error r - q over the last ``window`` seconds, per run [rad]."""
        return self._final_mean_error(window)


@dataclass(frozen=True, kw_only=True, eq=False)
class ReplayResult:
    """A joint driven open loop by a recorded torque (:func:`fricctl.simulate.replay`).

    Values at each sample instant, before that sample's torque acts.
    """

    q: np.ndarray
    """Motor-side position [rad]."""
    omega: np.ndarray
    """Motor-side velocity [rad/s]."""
    friction: np.ndarray
    """Resistive torque [N*m]."""
