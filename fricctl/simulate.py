"""The sampled-data loop at Ts (500 Hz, zero-order hold) -> :class:`SimResult`.

Timing (the one place it is stated; the gain design's sampled-data model
follows it): at each sample instant ``t_k = k*Ts``

1. the encoder reads ``y_k = res*floor(q(t_k)/res)`` (``res`` = one count on the
   load side; ``quantize=False`` gives ``y_k = q(t_k)``);
2. the velocity estimate is the backward difference
   ``omega_hat_k = (y_k - y_{k-1})/Ts`` (``omega_hat_0 = 0``), as the paper's driver;
3. the controller gives ``Tc_k`` from ``y_k`` and ``omega_hat_k``;
4. the compensator gives ``T^at_k = T^at(Tm_k, omega_hat_k)`` and the loop commands
   ``Tm_{k+1} = clip(Tc_k + s*T^at_k, -Tmax, Tmax)`` (paper Eq. 3);
5. ``Tm_{k+1}`` is held (ZOH) over ``[t_{k+1}, t_{k+2})``: one sample of
   computation delay; ``Tm_0 = 0``.

``torque_motor[k]`` is ``Tm_k``, the torque recorded as applied over
``[t_k, t_{k+1})``.  With ``delay=d`` the joint receives ``Tm_{k-d}`` instead
(a drive that acts later than the record says); ``noise_std`` adds white torque
noise to what the joint receives.  The joint itself saturates at ``+-Tmax``.

The loop runs compiled (numba) for the library's controllers and compensators,
including a :class:`fricctl.nn.FrictionNet`; an arbitrary estimator callable
runs through an equivalent Python loop (same results, slower).
:func:`simulate_batch` runs N parameter variants in one call.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from typing import Sequence

import numpy as np
from numba import njit, prange

from .compensators import COMP_COULOMB, COMP_NN, Compensator, NoCompensation
from .controllers import Controller
from .friction import NPARAM, FrictionLaw, FrictionModel
from .params import ActuatorParams
from .plant import FLEXIBLE, LUGRE, RIGID
from .plant.kernels import advance, advance_many, state_torque

__all__ = ["SimResult", "BatchResult", "simulate", "simulate_batch", "replay", "DEFAULT_SUBSTEPS"]

#: Internal RK4 sub-intervals per sample, by plant kind.
DEFAULT_SUBSTEPS = {RIGID: 4, FLEXIBLE: 10, LUGRE: 40}
_PLANTS = {"rigid": RIGID, "flexible": FLEXIBLE}


# --------------------------------------------------------------------------
# results
# --------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
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
        if not window > 0:
            raise ValueError(f"window must be > 0 s, got {window!r}")
        sel = self.t >= self.t[-1] - window + 1e-12
        q = self.q_meas if measured else self.q
        return np.mean(self.reference[..., sel] - q[..., sel], axis=-1)


#: Names of the per-sample arrays of a run (all but the time vector).
_ARRAYS = tuple(f.name for f in fields(_Trajectories) if f.name != "t")


@dataclass(frozen=True, eq=False)
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
    info : dict of what was simulated (params, friction, controller, ...)
    """

    info: dict = field(default_factory=dict)

    @property
    def sample_time(self) -> float:
        return float(self.t[1] - self.t[0]) if self.t.size > 1 else float("nan")

    @property
    def error(self) -> np.ndarray:
        """Tracking error r - q (true position) [rad]."""
        return self.reference - self.q

    def steady_state_error(self, window: float = 0.5, *, measured: bool = False) -> float:
        """Mean error r - q over the last ``window`` seconds [rad]."""
        return float(self._final_mean_error(window, measured))

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
        res = self.info.get("encoder_resolution", 0.0)
        span = float(np.ptp(self.q_meas))
        return int(round(span / res)) if res > 0 else int(span > 0)

    def to_run(self, *, source: str = "fricctl simulation"):
        """The measured part as a :class:`fricctl.datasets.Run` (t, Tm, y, r)."""
        from .datasets import Run

        return Run(t=self.t.copy(), torque=self.torque_motor.copy(), position=self.q_meas.copy(),
                   reference=self.reference.copy(), source=source)


@dataclass(frozen=True, eq=False)
class BatchResult(_Trajectories):
    """N simulated runs of equal length: ``t`` has shape (K,), every other array (N, K)."""

    infos: tuple = ()

    def __len__(self):
        return self.q.shape[0]

    def __getitem__(self, i) -> SimResult:
        n = len(self)
        if not isinstance(i, (int, np.integer)) or not -n <= i < n:
            raise IndexError(f"index {i!r} out of range for {n} runs")
        return SimResult(t=self.t, info=self.infos[i], **{k: getattr(self, k)[i] for k in _ARRAYS})

    def steady_state_error(self, window: float = 0.5) -> np.ndarray:
        """Mean error r - q over the last ``window`` seconds, per run [rad]."""
        return self._final_mean_error(window)


# --------------------------------------------------------------------------
# compiled loop
# --------------------------------------------------------------------------
@njit(cache=True)
def _quantize(q, res):
    if res > 0.0:
        return res * math.floor(q / res)
    return q


@njit(cache=True)
def _compensate(kind, p, tm, wh):
    if kind == COMP_COULOMB:
        if wh > p[2]:
            return p[0]
        if wh < -p[2]:
            return -p[1]
        return 0.0
    if kind == COMP_NN:
        h = int(p[0])
        x0 = tm
        x1 = wh
        if p[7] != 0.0:
            x0 = min(max(x0, p[8]), p[10])
            x1 = min(max(x1, p[9]), p[11])
        x0 = (x0 - p[1]) / p[3]
        x1 = (x1 - p[2]) / p[4]
        y = p[12]
        w1 = 13
        b1 = 13 + 2 * h
        w2 = b1 + h
        for j in range(h):
            y += p[w2 + j] * math.tanh(p[w1 + 2 * j] * x0 + p[w1 + 2 * j + 1] * x1 + p[b1 + j])
        return y * p[6] + p[5]
    return 0.0


@njit(cache=True)
def _run_one(n, kind, nsamp, ts, nsub, jm, jl, kst, dmp, fps, tmax, res, q0, ref, ff, kp, kd,
             ckind, cpar, cscale, delay, noise,
             o_q, o_y, o_ql, o_w, o_wh, o_tc, o_tm, o_f, o_fh, o_a, o_st):
    st = np.zeros(5)
    st[0] = q0[n]
    st[2] = q0[n]
    rn = n if n < ref.shape[0] else ref.shape[0] - 1
    fn = n if n < ff.shape[0] else ff.shape[0] - 1
    nn = n if n < noise.shape[0] else noise.shape[0] - 1
    has_noise = noise.shape[1] == nsamp
    tm_next = 0.0
    y_prev = _quantize(q0[n], res[n])
    for k in range(nsamp):
        t = k * ts
        y = _quantize(st[0], res[n])
        wh = (y - y_prev) / ts if k > 0 else 0.0
        tm_k = tm_next
        tc = ff[fn, k] + kp[n] * (ref[rn, k] - y) - kd[n] * wh
        fh = _compensate(ckind, cpar[n], tm_k, wh)
        cmd = tc + cscale[n] * fh
        tm_next = min(max(cmd, -tmax[n]), tmax[n])
        if delay > 0:
            applied = o_tm[n, k - delay] if k >= delay else 0.0
        else:
            applied = tm_k
        if has_noise:
            applied += noise[nn, k]
        applied = min(max(applied, -tmax[n]), tmax[n])
        o_q[n, k] = st[0]
        o_y[n, k] = y
        o_ql[n, k] = st[2]
        o_w[n, k] = st[1]
        o_wh[n, k] = wh
        o_tc[n, k] = tc
        o_tm[n, k] = tm_k
        o_fh[n, k] = fh
        o_st[n, k] = st[1] == 0.0
        f, a = state_torque(kind, st, fps[n], applied, t, jm[n], kst[n], dmp[n])
        o_f[n, k] = f
        o_a[n, k] = a
        advance(kind, st, fps[n], applied, t, ts, nsub, jm[n], jl[n], kst[n], dmp[n])
        y_prev = y


@njit(cache=True)
def _loop_serial(kind, nsamp, ts, nsub, jm, jl, kst, dmp, fps, tmax, res, q0, ref, ff, kp, kd,
                 ckind, cpar, cscale, delay, noise,
                 o_q, o_y, o_ql, o_w, o_wh, o_tc, o_tm, o_f, o_fh, o_a, o_st):
    for n in range(fps.shape[0]):
        _run_one(n, kind, nsamp, ts, nsub, jm, jl, kst, dmp, fps, tmax, res, q0, ref, ff, kp, kd,
                 ckind, cpar, cscale, delay, noise,
                 o_q, o_y, o_ql, o_w, o_wh, o_tc, o_tm, o_f, o_fh, o_a, o_st)


@njit(cache=True, parallel=True)
def _loop_parallel(kind, nsamp, ts, nsub, jm, jl, kst, dmp, fps, tmax, res, q0, ref, ff, kp, kd,
          ckind, cpar, cscale, delay, noise,
          o_q, o_y, o_ql, o_w, o_wh, o_tc, o_tm, o_f, o_fh, o_a, o_st):
    for n in prange(fps.shape[0]):  # runs are independent: one per thread
        _run_one(np.int64(n), kind, nsamp, ts, nsub, jm, jl, kst, dmp, fps, tmax, res, q0, ref, ff, kp, kd,
                 ckind, cpar, cscale, delay, noise,
                 o_q, o_y, o_ql, o_w, o_wh, o_tc, o_tm, o_f, o_fh, o_a, o_st)


def _python_loop(kind, nsamp, ts, nsub, jm, jl, kst, dmp, fps, tmax, res, q0, ref, ff, kp, kd,
                 comps, delay, noise, out):
    """Same loop as :func:`_run_one`, for compensators that only exist in Python."""
    o_q, o_y, o_ql, o_w, o_wh, o_tc, o_tm, o_f, o_fh, o_a, o_st = out
    n_runs = fps.shape[0]
    states = np.zeros((n_runs, 5))
    states[:, 0] = q0
    states[:, 2] = q0
    ridx = np.minimum(np.arange(n_runs), ref.shape[0] - 1)
    fidx = np.minimum(np.arange(n_runs), ff.shape[0] - 1)
    nidx = np.minimum(np.arange(n_runs), noise.shape[0] - 1)
    has_noise = noise.shape[1] == nsamp
    quant = np.vectorize(_quantize, otypes=[float])
    tm_next = np.zeros(n_runs)
    y_prev = quant(q0, res)
    scales = np.array([c.scale for c in comps])
    for k in range(nsamp):
        t = k * ts
        y = quant(states[:, 0], res)
        wh = (y - y_prev) / ts if k > 0 else np.zeros(n_runs)
        tm_k = tm_next
        tc = ff[fidx, k] + kp * (ref[ridx, k] - y) - kd * wh
        if len(set(map(id, comps))) == 1:
            fh = np.broadcast_to(np.asarray(comps[0](tm_k, wh), dtype=float), (n_runs,)).copy()
        else:
            fh = np.array([float(np.asarray(c(tm_k[i:i + 1], wh[i:i + 1])).ravel()[0])
                           for i, c in enumerate(comps)])
        if not np.all(np.isfinite(fh)):
            raise ValueError(f"the compensator returned NaN or inf at t = {t:g} s")
        tm_next = np.clip(tc + scales * fh, -tmax, tmax)
        applied = (o_tm[:, k - delay] if k >= delay else np.zeros(n_runs)) if delay > 0 else tm_k.copy()
        if has_noise:
            applied = applied + noise[nidx, k]
        applied = np.clip(applied, -tmax, tmax)
        o_q[:, k] = states[:, 0]
        o_y[:, k] = y
        o_ql[:, k] = states[:, 2]
        o_w[:, k] = states[:, 1]
        o_wh[:, k] = wh
        o_tc[:, k] = tc
        o_tm[:, k] = tm_k
        o_fh[:, k] = fh
        o_st[:, k] = states[:, 1] == 0.0
        for n in range(n_runs):
            o_f[n, k], o_a[n, k] = state_torque(kind, states[n], fps[n], applied[n], t, jm[n], kst[n], dmp[n])
        advance_many(kind, states, fps, applied, t, ts, nsub, jm, jl, kst, dmp)
        y_prev = y


# --------------------------------------------------------------------------
# public API
# --------------------------------------------------------------------------
#: Largest number of samples (runs x samples) one call simulates (11 arrays of 8 bytes each).
_MAX_SAMPLES = 2e8


def _check_drift(friction: FrictionModel, t0: float, t1: float) -> None:
    """Friction whose drifting scale would turn negative drives the joint: refuse it."""
    for t in (t0, t1):
        if 1.0 + friction.drift * t <= 0.0:
            raise ValueError(f"friction drift {friction.drift:g} 1/s makes the friction scale "
                             f"1 + drift*t <= 0 at t = {t:g} s: friction would drive the joint")



def _as_list(x, n, name, types):
    if isinstance(x, (list, tuple)):
        if len(x) not in (1, n):
            raise ValueError(f"{name}: got {len(x)} items for {n} runs")
        items = list(x) * (n if len(x) == 1 else 1)
    else:
        items = [x] * n
    for it in items:
        if not isinstance(it, types):
            raise ValueError(f"{name} must be {' or '.join(t.__name__ for t in types)}, got {type(it).__name__}")
    return items


def _batch_size(*args):
    sizes = {len(a) for a in args if isinstance(a, (list, tuple)) and len(a) != 1}
    if len(sizes) > 1:
        raise ValueError(f"batch arguments disagree on the number of runs: {sorted(sizes)}")
    return sizes.pop() if sizes else 1


def simulate_batch(params, controller, compensator=None, *, duration: float,
                   friction=None, plant: str = "rigid", substeps: int | None = None,
                   q0=0.0, noise_std: float = 0.0, rng: np.random.Generator | None = None,
                   delay: int = 0, quantize: bool = True) -> BatchResult:
    """Simulate N variants of the closed (or open) loop in one call.

    Any of ``params``, ``controller``, ``compensator`` and ``friction`` may be a
    list of N items (the others are shared); ``q0`` may be an array of N.

    Parameters
    ----------
    params : ActuatorParams or list
        Actuator(s); inertia = ``total_inertia`` for the rigid joint.
    controller : Controller or list
    compensator : Compensator or list, optional
        Default :class:`NoCompensation`.
    duration : float
        Simulated time [s]; K = round(duration/Ts) samples.
    friction : FrictionModel or list, optional
        Default ``params.friction_model()``.
    plant : {"rigid", "flexible"}
        Rigid joint (Eq. 2) or elastic joint (Eq. 1, needs ``link_inertia > 0``).
    substeps : int, optional
        RK4 sub-intervals per sample (default 4 rigid, 10 flexible, 40 LuGre).
    q0 : float or array
        Initial position [rad] (at rest).
    noise_std : float
        Standard deviation of white torque noise added at the joint [N*m];
        needs ``rng``.
    rng : numpy.random.Generator, optional
    delay : int
        Extra samples by which the joint receives the recorded torque late.
    quantize : bool
        Encoder quantisation on (default) or off.

    Returns
    -------
    BatchResult
    """
    n = _batch_size(params, controller, compensator, friction)
    plist = _as_list(params, n, "params", (ActuatorParams,))
    clist = _as_list(controller, n, "controller", (Controller,))
    comps = _as_list(NoCompensation() if compensator is None else compensator, n, "compensator",
                     (Compensator,))
    if isinstance(friction, FrictionLaw):
        friction = friction.model()
    elif isinstance(friction, (list, tuple)):
        friction = [f.model() if isinstance(f, FrictionLaw) else f for f in friction]
    frs = [p.friction_model() for p in plist] if friction is None else _as_list(
        friction, n, "friction", (FrictionModel,))
    if plant not in _PLANTS:
        raise ValueError(f"plant must be one of {sorted(_PLANTS)}, got {plant!r}")
    kind = _PLANTS[plant]
    lugre = {f.is_lugre for f in frs}
    if len(lugre) > 1:
        raise ValueError("a batch cannot mix LuGre and stick-slip friction models")
    if lugre.pop():
        if kind == FLEXIBLE:
            raise ValueError("LuGre friction is supported on the rigid joint only")
        kind = LUGRE
    ts = plist[0].sample_time
    if any(p.sample_time != ts for p in plist):
        raise ValueError("all runs of a batch must share one sample_time")
    if isinstance(duration, bool) or not isinstance(duration, (int, float)) or not math.isfinite(duration) \
            or duration <= 0:
        raise ValueError(f"duration must be a finite number > 0 s, got {duration!r}")
    nsamp = int(round(duration / ts))
    if nsamp < 2:
        raise ValueError(f"duration {duration} s is shorter than two samples of {ts} s")
    if substeps is None:
        substeps = DEFAULT_SUBSTEPS[kind]
    if isinstance(substeps, bool) or not isinstance(substeps, (int, np.integer)) or substeps < 1:
        raise ValueError(f"substeps must be a positive integer, got {substeps!r}")
    if isinstance(delay, bool) or not isinstance(delay, (int, np.integer)) or delay < 0:
        raise ValueError(f"delay must be an integer number of samples >= 0, got {delay!r}")
    if not (math.isfinite(noise_std) and noise_std >= 0):
        raise ValueError(f"noise_std must be finite and >= 0 N*m, got {noise_std!r}")
    if noise_std > 0 and not isinstance(rng, np.random.Generator):
        raise ValueError("noise_std > 0 needs rng=numpy.random.default_rng(seed)")
    try:
        q0a = np.broadcast_to(np.asarray(q0, dtype=float), (n,)).copy()
    except ValueError:
        raise ValueError(f"q0 must be a number or an array of {n} initial positions, got shape "
                         f"{np.shape(q0)}") from None
    if not np.all(np.isfinite(q0a)):
        raise ValueError("q0 must be finite")
    if kind == FLEXIBLE and any(p.link_inertia <= 0 for p in plist):
        raise ValueError("plant='flexible' needs link_inertia > 0 (the load-side inertia of Eq. 1)")

    if n * nsamp > _MAX_SAMPLES:
        raise ValueError(f"duration {duration} s x {n} runs is {n * nsamp} samples, more than "
                         f"{_MAX_SAMPLES:.0e}: shorten the duration or split the batch")
    for f in frs:
        _check_drift(f, 0.0, nsamp * ts)
    t = np.arange(nsamp) * ts
    jm = np.array([p.inertia if kind == FLEXIBLE else p.total_inertia for p in plist])
    jl = np.array([p.link_inertia if kind == FLEXIBLE else p.total_inertia for p in plist])
    kst = np.array([p.stiffness if kind == FLEXIBLE else 0.0 for p in plist])
    dmp = np.array([p.joint_damping if kind == FLEXIBLE else 0.0 for p in plist])
    fps = np.array([f.vector() for f in frs]).reshape(n, NPARAM)
    tmax = np.array([p.max_torque for p in plist])
    res = np.array([p.encoder_resolution if quantize else 0.0 for p in plist])
    shared_ctrl = len({id(c) for c in clist}) == 1
    ref = np.array([c.reference(t) for c in (clist[:1] if shared_ctrl else clist)])
    ff = np.array([c.feedforward(t) for c in (clist[:1] if shared_ctrl else clist)])
    kp = np.array([c.kp for c in clist], dtype=float)
    kd = np.array([c.kd for c in clist], dtype=float)
    noise = (rng.normal(0.0, noise_std, size=(n, nsamp)) if noise_std > 0 else np.zeros((1, 1)))
    out = [np.empty((n, nsamp)) for _ in range(10)] + [np.empty((n, nsamp), dtype=np.bool_)]

    compiled = [c.compiled() for c in comps]
    for c in compiled:
        if c is not None and not np.all(np.isfinite(c[1])):
            raise ValueError("the compensator's parameters contain NaN or inf")
    if all(c is not None for c in compiled) and len({c[0] for c in compiled}) == 1:
        width = max(c[1].size for c in compiled)
        cpar = np.zeros((n, width))
        for i, (_, p) in enumerate(compiled):
            cpar[i, :p.size] = p
        cscale = np.array([c.scale for c in comps], dtype=float)
        loop = _loop_parallel if n > 1 else _loop_serial
        loop(kind, nsamp, ts, substeps, jm, jl, kst, dmp, fps, tmax, res, q0a, ref, ff, kp, kd,
              compiled[0][0], cpar, cscale, delay, noise, *out)
        path = "compiled"
    else:
        _python_loop(kind, nsamp, ts, substeps, jm, jl, kst, dmp, fps, tmax, res, q0a, ref, ff, kp, kd,
                     comps, delay, noise, out)
        path = "python"
    infos = tuple({
        "params": plist[i], "friction_model": frs[i], "controller": clist[i].name,
        "kp": clist[i].kp, "kd": clist[i].kd, "compensator": comps[i].name,
        "compensation_scale": comps[i].scale, "plant": plant if kind != LUGRE else "rigid (LuGre)",
        "substeps": int(substeps), "delay": int(delay), "noise_std": float(noise_std),
        "encoder_resolution": float(res[i]), "loop": path,
    } for i in range(n))
    o_q, o_y, o_ql, o_w, o_wh, o_tc, o_tm, o_f, o_fh, o_a, o_st = out
    ref_full = np.broadcast_to(ref, (n, nsamp)).copy() if ref.shape[0] == 1 else ref
    return BatchResult(t=t, reference=ref_full, q=o_q, q_meas=o_y, q_load=o_ql, omega=o_w,
                       omega_hat=o_wh, torque_cmd=o_tc, torque_motor=o_tm, friction=o_f,
                       friction_est=o_fh, accel=o_a, stuck=o_st, infos=infos)


def simulate(params: ActuatorParams, controller: Controller, compensator: Compensator | None = None, *,
             duration: float, friction: FrictionModel | None = None, plant: str = "rigid",
             substeps: int | None = None, q0: float = 0.0, noise_std: float = 0.0,
             rng: np.random.Generator | None = None, delay: int = 0,
             quantize: bool = True) -> SimResult:
    """Simulate one run of the sampled loop; see :func:`simulate_batch` for the arguments.

    Examples
    --------
    >>> from fricctl.params import paper_actuator
    >>> from fricctl.controllers import open_loop, constant
    >>> p = paper_actuator()
    >>> r = simulate(p, open_loop(constant(0.99 * p.static)), duration=0.5)
    >>> float(abs(r.q).max())          # 1 % below breakaway: no motion at all
    0.0
    """
    for name, v, types in (("params", params, ActuatorParams), ("controller", controller, Controller)):
        if not isinstance(v, types):
            raise ValueError(f"{name} must be a {types.__name__}, got {type(v).__name__}")
    return simulate_batch(params, controller, compensator, duration=duration, friction=friction,
                          plant=plant, substeps=substeps, q0=q0, noise_std=noise_std, rng=rng,
                          delay=delay, quantize=quantize)[0]


@njit(cache=True)
def _replay(kind, st, fp, torque, t0, ts, nsub, jm, jl, k, d, o_q, o_w, o_f):
    for i in range(torque.size):
        t = t0 + i * ts
        o_q[i] = st[0]
        o_w[i] = st[1]
        f, a = state_torque(kind, st, fp, torque[i], t, jm, k, d)
        o_f[i] = f
        advance(kind, st, fp, torque[i], t, ts, nsub, jm, jl, k, d)


def replay(joint, torque, sample_time: float, *, q0: float = 0.0, omega0: float = 0.0,
           t0: float = 0.0, substeps: int | None = None, state=None):
    """Drive a joint open loop with a recorded torque sequence (held per sample).

    This is "what the model predicts" for a measured record: the joint starts at
    ``(q0, omega0)`` (or a full ``state``) and receives ``torque[i]`` over
    ``[t0 + i*Ts, t0 + (i+1)*Ts)``.

    Parameters
    ----------
    joint : RigidJoint or FlexibleJoint
    torque : array_like, shape (K,)
        Torque held over each sample [N*m].
    sample_time : float
        Ts [s].
    q0, omega0 : float
        Initial position [rad] and velocity [rad/s].
    t0 : float
        Time of the first sample [s] (matters for a drifting friction model).
    substeps : int, optional
        RK4 sub-intervals per sample.
    state : array_like, optional
        Full initial state ``[q, omega, q_load, omega_load, z]``; overrides q0/omega0.

    Returns
    -------
    q, omega, friction : ndarray
        Position [rad], velocity [rad/s] and resistive torque [N*m] at each sample
        instant (before that sample's torque acts).
    """
    tq = np.asarray(torque, dtype=float)
    if tq.ndim != 1 or tq.size == 0:
        raise ValueError(f"torque must be a non-empty 1-D array, got shape {tq.shape}")
    if not np.all(np.isfinite(tq)):
        raise ValueError("torque contains NaN or inf")
    if not (math.isfinite(sample_time) and sample_time > 0):
        raise ValueError(f"sample_time must be > 0 s, got {sample_time!r}")
    ka = joint.kernel_args()
    kind, jm, jl, k, d = ka.kind, ka.motor_inertia, ka.load_inertia, ka.stiffness, ka.damping
    st = joint.initial_state(q0, omega0) if state is None else np.array(state, dtype=float)
    if st.shape != (5,) or not np.all(np.isfinite(st)):
        raise ValueError("state must be 5 finite numbers [q, omega, q_load, omega_load, z]")
    if not math.isfinite(t0):
        raise ValueError(f"t0 must be finite, got {t0!r}")
    _check_drift(joint.friction, t0, t0 + tq.size * sample_time)
    if substeps is None:
        substeps = DEFAULT_SUBSTEPS[kind]
    if isinstance(substeps, bool) or not isinstance(substeps, (int, np.integer)) or substeps < 1:
        raise ValueError(f"substeps must be a positive integer, got {substeps!r}")
    o_q, o_w, o_f = np.empty(tq.size), np.empty(tq.size), np.empty(tq.size)
    _replay(kind, st, joint.friction.vector(), tq, float(t0), float(sample_time), int(substeps),
            jm, jl, k, d, o_q, o_w, o_f)
    return o_q, o_w, o_f
