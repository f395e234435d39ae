"""The bench's sampled loop with ideal rigid end stops: records in which the joint hits a limit.

:func:`simulate_with_stops` runs the loop of :func:`fricctl.simulate.simulate_schedule`
(encoder reading, backward-difference velocity, ``Tc = ff + Kp (r - y) - Kd w_hat``, one
sample of computation delay, saturation, delay and noise on what the joint receives, the
reference re-zeroed at each segment start) one sample at a time in Python, the joint
advanced by its own :meth:`~fricctl.plant.RigidJoint.advance`, and after every sample
interval it applies the stop: a joint found beyond a limit is put back on it at rest.

Notes
-----
The stop is *idealised*: perfectly rigid and perfectly inelastic (the joint loses all its
momentum on impact, no bounce, no contact stiffness), resolved at the sample grid (the
impact's instant inside the interval is not located: the joint is put on the stop at the
end of the interval in which it crossed, so up to one sample interval of free motion
beyond the stop is undone).  While the joint presses into the stop it stays on it; it
leaves when the torque it receives pulls it away past its breakaway.  Only a rigid joint
without a friction state (no presliding bristle) is simulated: the state of a spring or a
bristle at an impact is more physics than an ideal stop states.  Python speed: about
20 000 samples per second.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _validate as v
from ..plant import RigidJoint
from ..simulate import Schedule

__all__ = ["StopSimulation", "simulate_with_stops"]


@dataclass(frozen=True, kw_only=True, eq=False)
class StopSimulation:
    """A record of the sampled loop with end stops (:func:`simulate_with_stops`)."""

    t: np.ndarray
    """Sample instants [s]."""
    q: np.ndarray
    """True position at each sample instant [rad] ([m] on a linear axis)."""
    q_meas: np.ndarray
    """Encoder reading [rad]."""
    torque_motor: np.ndarray
    """The command each sample holds (the recorded torque) [N*m]."""
    reference: np.ndarray
    """Position reference [rad]."""
    lower: float
    """Lower stop [rad] (``-inf``: none)."""
    upper: float
    """Upper stop [rad] (``inf``: none)."""
    impacts: np.ndarray
    """Samples at which the joint is found on a stop having arrived with speed (the first
    sample of each contact) [-]."""
    impact_speed: np.ndarray
    """Speed at which the joint crossed the stop, per impact [rad/s]."""
    impact_side: np.ndarray
    """+1 for the upper stop, -1 for the lower, per impact [-]."""


def simulate_with_stops(joint: RigidJoint, schedule: Schedule, *, sample_time: float,
                        max_torque: float, encoder_resolution: float, substeps: int,
                        lower: float, upper: float, delay: int = 0,
                        noise=None) -> StopSimulation:
    """Run the sampled loop of :func:`fricctl.simulate.simulate_schedule` on ``joint`` with
    ideal rigid stops at ``lower`` and ``upper`` (see the module notes).

    Parameters
    ----------
    joint : RigidJoint
        A rigid joint whose friction has no state.
    schedule : Schedule
        Gains, reference, feed-forward and segments, per sample.
    sample_time : float
        Ts [s].
    max_torque : float
        Saturation of the commanded and the received torque [N*m].
    encoder_resolution : float
        One encoder count [rad] (0: no quantisation).
    substeps : int
        RK4 sub-intervals per sample (the stop-free simulation's, ``SimResult.info.substeps``).
    lower, upper : float
        The stops [rad]; ``-inf`` / ``inf`` for none.  The joint starts at 0, between them.
    delay : int
        Samples by which the joint receives the recorded torque late.
    noise : array_like, shape (K,), optional
        Torque noise added to what the joint receives [N*m].

    Returns
    -------
    StopSimulation

    Examples
    --------
    >>> import numpy as np
    >>> from fricctl.friction import Coulomb, FrictionModel, Viscous
    >>> from fricctl.simulate import Schedule
    >>> joint = RigidJoint(inertia=5e-3, friction=Viscous(0.02) + Coulomb(0.1))
    >>> n = 200
    >>> sch = Schedule(kp=np.zeros(n), kd=np.zeros(n), reference=np.zeros(n),
    ...                feedforward=np.full(n, 0.3), segment_start=np.zeros(n, bool))
    >>> sim = simulate_with_stops(joint, sch, sample_time=0.002, max_torque=1.0,
    ...                           encoder_resolution=1e-4, substeps=4, lower=-1.0, upper=0.05)
    >>> float(sim.q.max()), sim.impacts.size
    (0.05, 1)
    """
    v.instance("joint", joint, RigidJoint, "a RigidJoint (an ideal stop on a spring or a "
                                           "bristle state is not simulated)")
    if joint.friction.state_law is not None:
        raise ValueError("joint: its friction has a state (presliding); an ideal stop is "
                         "simulated on a joint without one")
    v.instance("schedule", schedule, Schedule)
    ts = v.real("sample_time", sample_time, positive=True, unit="s")
    tmax = v.real("max_torque", max_torque, positive=True, unit="N*m")
    res = v.real("encoder_resolution", encoder_resolution, nonneg=True, unit="rad")
    substeps = v.integer("substeps", substeps, low=1)
    lower = float(lower)
    upper = float(upper)
    if not lower < 0.0 < upper:  # NaN fails too
        raise ValueError(f"lower, upper: the stops must enclose the start 0, got "
                         f"{lower!r}, {upper!r}")
    delay = v.integer("delay", delay, low=0)
    n = len(schedule)
    noise = np.zeros(n) if noise is None else v.array("noise", noise, size=n)
    kp, kd, ref = schedule.kp, schedule.kd, schedule.reference
    ff, seg = schedule.feedforward, schedule.segment_start

    def reading(q):
        return res * math.floor(q / res) if res > 0 else q

    st = joint.initial_state(0.0, 0.0)
    q, y_rec, tm_rec, r_rec = (np.empty(n) for _ in range(4))
    impacts, speeds, sides = [], [], []
    tm_next, y_prev, offset = 0.0, reading(0.0), 0.0
    for k in range(n):
        y = reading(st[0])
        wh = (y - y_prev) / ts if k > 0 else 0.0
        if seg[k]:
            offset = y
        r = offset + ref[k]
        tc = ff[k] + kp[k] * (r - y) - kd[k] * wh
        tm_k = tm_next
        tm_next = min(max(tc, -tmax), tmax)
        applied = (tm_rec[k - delay] if k >= delay else 0.0) if delay > 0 else tm_k
        applied = min(max(applied + noise[k], -tmax), tmax)
        q[k], y_rec[k], tm_rec[k], r_rec[k] = st[0], y, tm_k, r
        was_on_stop = st[1] == 0.0 and st[0] in (lower, upper)
        st = joint.advance(st, applied, k * ts, ts, substeps)
        for side, limit in ((1, upper), (-1, lower)):
            if side * (st[0] - limit) > 0.0:  # beyond: back on the stop, at rest
                if not was_on_stop and k + 1 < n:
                    impacts.append(k + 1)
                    speeds.append(abs(float(st[1])))
                    sides.append(side)
                st[0] = st[2] = limit
                st[1] = st[3] = 0.0
        y_prev = y
    return StopSimulation(t=np.arange(n) * ts, q=q, q_meas=y_rec, torque_motor=tm_rec,
                          reference=r_rec, lower=lower, upper=upper,
                          impacts=np.asarray(impacts, dtype=int),
                          impact_speed=np.asarray(speeds, dtype=float),
                          impact_side=np.asarray(sides, dtype=int))
