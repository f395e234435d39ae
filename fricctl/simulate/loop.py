"""The ONE sampled-data loop (compiled), used by every simulation of fricctl.

One sample of the loop is four compiled steps, each written once:

1. :func:`observe` -- encoder reading ``y_k`` (of the position plus the sample's position
   noise, when the loop has one) and backward-difference velocity;
2. :func:`control_torque` -- ``Tc_k = ff_k + Kp_k*(r_k - y_k) - Kd_k*omega_hat_k``;
3. :func:`act` -- ``Tm_{k+1} = clip(Tc_k + s*T^at_k)``, what the joint receives
   (delay, noise, saturation) and the records;
4. :func:`joint_interval` -- the joint's resistive torque and one held-torque interval
   of the plant.

Between 2 and 3 the compensator gives ``T^at_k``: :func:`compensate`, the compiled step of
the run's kind (:mod:`fricctl.compensators.compiled`), from its parameter vector, its state
vector (changed in place) and the signals of the sample (``Tm_k, omega_hat_k, y_k, r_k,
Tc_k, Ts``).  :func:`run_compiled` chains the steps for every registered compensator
(none, Coulomb, a :class:`fricctl.nn.FrictionNet`, the feedforward, the observers, integral
action; one kind per run); :func:`run_python` chains the same steps for any other
estimator callable ``(Tm, omega_hat) -> T^at`` (evaluated in Python between 2 and 3).
The timing is stated in :mod:`fricctl.simulate`.

What a batch is made of comes in the typed records of :mod:`fricctl.simulate.spec`
(:class:`PlantSpec`, :class:`LoopSpec`, :class:`ControlSpec`, :class:`CompensatorSpec`),
read by field name inside the compiled steps; the plant kernels' arguments are unpacked
from a :class:`PlantSpec` in one place, :func:`joint_interval`.  Per-sample settings are
2-D arrays indexed ``[run, sample]`` (a single row or column is shared by every run or
sample); ``segment_start`` marks samples where the reference is re-zeroed at the current
encoder reading (the hidden-effect bench chains experiments that way).
"""

from __future__ import annotations

import math

import numpy as np
from numba import get_num_threads, prange

from .._jit import jit
from ..compensators.compiled import step as _compensator_step
from ..plant.kernels import advance, state_torque
from .spec import CompensatorSpec, ControlSpec, LoopSpec, PlantSpec

__all__ = ["OUTPUTS", "observe", "control_torque", "compensate", "act", "joint_interval",
           "run_compiled", "run_python"]

#: Rows of the float output array, in order.
OUTPUTS = ("q", "q_meas", "q_load", "omega", "omega_hat", "torque_cmd", "torque_motor",
           "friction", "friction_est", "accel", "reference")
_Q, _Y, _QL, _W, _WH, _TC, _TM, _F, _FH, _A, _R = range(len(OUTPUTS))


@jit
def _at(a, n, k):
    """``a[n, k]`` with a single row or column shared by every run or sample."""
    return a[min(n, a.shape[0] - 1), min(k, a.shape[1] - 1)]


@jit
def quantize(q, res):
    """Encoder reading of position q with a count of ``res`` (0: no quantisation)."""
    if res > 0.0:
        return res * math.floor(q / res)
    return q


@jit
def observe(q, y_prev, k, ts, res, loop, n, nsamp):
    """(y_k, omega_hat_k): encoder reading and backward difference (0 at k = 0).

    The encoder reads ``q`` plus run n's position noise of sample k (``loop.position_noise``,
    :class:`LoopSpec`) when the loop has one: edge jitter moves the reading across a count
    edge that the joint sits near, before quantisation.
    """
    pn = loop.position_noise
    if pn.shape[1] == nsamp:  # else none: q itself, not q + 0.0 (bit for bit, -0.0 included)
        q = q + pn[min(n, pn.shape[0] - 1), k]
    y = quantize(q, res)
    wh = (y - y_prev) / ts if k > 0 else 0.0
    return y, wh


@jit
def control_torque(n, k, y, wh, offset, has_segments, control):
    """(r_k, Tc_k) of run n at sample k (:class:`ControlSpec`); ``offset`` is added to the
    reference of a segment."""
    r = _at(control.reference, n, k)
    if has_segments:
        r = offset + r
    tc = (_at(control.feedforward, n, k) + _at(control.kp, n, k) * (r - y)
          - _at(control.kd, n, k) * wh)
    return r, tc


@jit
def compensate(kind, p, x, tm, wh, y, r, tc, ts):
    """Friction estimate T^at of a compiled compensator (kind, parameter vector, state
    vector changed in place) at sample k (:mod:`fricctl.compensators.base`)."""
    return _compensator_step(kind, p, x, tm, wh, y, r, tc, ts)


@jit
def act(n, k, st, tm_k, tc, fh, y, wh, r, scale, loop, out, stuck):
    """The command ``Tm_{k+1}``, the torque the joint receives over sample k (delay, noise,
    saturation) and the records of sample k; returns both torques.

    ``scale`` is the compensation scale s of run n, ``loop`` the :class:`LoopSpec`.
    """
    # fields read first: the spec's other arrays are not held (reference-counted) to the end
    tmax, delay, noise = loop.max_torque[n], loop.delay, loop.noise
    tm_next = min(max(tc + scale * fh, -tmax), tmax)
    if delay > 0:
        applied = out[_TM, n, k - delay] if k >= delay else 0.0
    else:
        applied = tm_k
    if noise.shape[1] == out.shape[2]:
        applied += noise[min(n, noise.shape[0] - 1), k]
    applied = min(max(applied, -tmax), tmax)
    out[_Q, n, k] = st[0]
    out[_Y, n, k] = y
    out[_QL, n, k] = st[2]
    out[_W, n, k] = st[1]
    out[_WH, n, k] = wh
    out[_TC, n, k] = tc
    out[_TM, n, k] = tm_k
    out[_FH, n, k] = fh
    out[_R, n, k] = r
    stuck[n, k] = st[1] == 0.0
    return tm_next, applied


@jit
def joint_interval(plant, n, st, tm, t0, dt):
    """(resistive torque Tat, motor acceleration) of run n's joint right after ``t0``, then
    the joint (:class:`PlantSpec`) advanced in place over ``[t0, t0 + dt)`` with ``tm`` held.

    The one place the plant kernels' arguments are unpacked from a :class:`PlantSpec`.
    """
    # every field is read before the kernels run: the spec's arrays are not held
    # (reference-counted) across the calls; holding them cost ~7 % of the loop's time
    kind, fp, nsub = plant.kind, plant.friction[n], plant.substeps
    jm, jl = plant.motor_inertia[n], plant.load_inertia[n]
    kst, dmp, gap = plant.stiffness[n], plant.damping[n], plant.backlash[n]
    f, a = state_torque(kind, st, fp, tm, t0, jm, kst, dmp, gap)
    advance(kind, st, fp, tm, t0, dt, nsub, jm, jl, kst, dmp, gap)
    return f, a


@jit
def _one_run(n, plant, loop, control, comp, out, stuck):
    st = np.zeros(5)
    st[0] = loop.q0[n]
    st[2] = loop.q0[n]
    tm_next = 0.0
    res = loop.encoder_resolution[n]
    y_prev = quantize(loop.q0[n], res)
    offset = 0.0
    has_segments = control.segment_start.shape[1] == out.shape[2]
    kind = comp.kind[n]
    x = comp.state[n].copy()
    for k in range(out.shape[2]):
        y, wh = observe(st[0], y_prev, k, loop.sample_time, res, loop, n, out.shape[2])
        if has_segments and _at(control.segment_start, n, k):
            offset = y
        r, tc = control_torque(n, k, y, wh, offset, has_segments, control)
        tm_k = tm_next
        fh = compensate(kind, comp.params[n], x, tm_k, wh, y, r, tc, loop.sample_time)
        tm_next, applied = act(n, k, st, tm_k, tc, fh, y, wh, r, comp.scale[n], loop, out, stuck)
        out[_F, n, k], out[_A, n, k] = joint_interval(plant, n, st, applied, k * loop.sample_time,
                                                      loop.sample_time)
        y_prev = y


@jit
def _runs_serial(plant, loop, control, comp, out, stuck):
    for n in range(out.shape[1]):
        _one_run(n, plant, loop, control, comp, out, stuck)


@jit(parallel=True)
def _runs_parallel(plant, loop, control, comp, out, stuck):
    for n in prange(out.shape[1]):  # runs are independent: one per thread
        _one_run(np.int64(n), plant, loop, control, comp, out, stuck)


def run_compiled(plant: PlantSpec, loop: LoopSpec, control: ControlSpec, comp: CompensatorSpec,
                 out, stuck) -> None:
    """Run every run of the batch through the compiled loop (runs in parallel when N > 1 and
    numba may use more than one thread).

    ``out`` (11, N, K) and ``stuck`` (N, K) receive the records (rows :data:`OUTPUTS`).  Each
    run is the same compiled :func:`_one_run` either way (no sums across runs): the records are
    the same bit for bit.  With one thread (``numba.set_num_threads(1)``, as the worker
    processes of ``fricctl reproduce`` set it when they fill the CPUs) the parallel kernel is
    never compiled: it costs the longest compilation of all and would gain nothing.
    """
    runs = _runs_parallel if out.shape[1] > 1 and get_num_threads() > 1 else _runs_serial
    runs(plant, loop, control, comp, out, stuck)


def run_python(plant: PlantSpec, loop: LoopSpec, control: ControlSpec, estimators, scales,
               out, stuck) -> None:
    """The same steps as :func:`run_compiled`, with ``T^at`` from Python callables.

    ``estimators`` holds one callable ``(tm, omega_hat) -> T^at`` per run (the same
    object for every run is evaluated once per sample on the whole batch); ``scales``
    their compensation scales s [-].
    """
    n_runs, nsamp = stuck.shape
    ts, res = loop.sample_time, loop.encoder_resolution
    states = np.zeros((n_runs, 5))
    states[:, 0] = loop.q0
    states[:, 2] = loop.q0
    tm_next = np.zeros(n_runs)
    y_prev = np.array([quantize(q, r) for q, r in zip(loop.q0, res)])
    offset = np.zeros(n_runs)
    segs = control.segment_start
    has_segments = segs.shape[1] == nsamp
    y, wh, r, tc = (np.empty(n_runs) for _ in range(4))
    shared = len({id(e) for e in estimators}) == 1
    for k in range(nsamp):
        for n in range(n_runs):
            y[n], wh[n] = observe(states[n, 0], y_prev[n], k, ts, res[n], loop, n, nsamp)
            if has_segments and segs[min(n, segs.shape[0] - 1), k]:
                offset[n] = y[n]
            r[n], tc[n] = control_torque(n, k, y[n], wh[n], offset[n], has_segments, control)
        tm_k = tm_next.copy()
        if shared:
            fh = np.broadcast_to(np.asarray(estimators[0](tm_k, wh), dtype=float), (n_runs,)).copy()
        else:
            fh = np.array([float(np.asarray(e(tm_k[i:i + 1], wh[i:i + 1])).ravel()[0])
                           for i, e in enumerate(estimators)])
        if not np.all(np.isfinite(fh)):
            raise ValueError(f"the compensator returned NaN or inf at t = {k * ts:g} s")
        for n in range(n_runs):
            tm_next[n], applied = act(n, k, states[n], tm_k[n], tc[n], fh[n], y[n], wh[n], r[n],
                                      scales[n], loop, out, stuck)
            out[_F, n, k], out[_A, n, k] = joint_interval(plant, n, states[n], applied, k * ts, ts)
        y_prev = y.copy()
