"""Public entry points of the sampled loop: :func:`simulate`, :func:`simulate_batch`,
:func:`simulate_model`, :func:`simulate_schedule` and :func:`replay` (see
:mod:`fricctl.simulate` for the timing)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from .._jit import jit
from .. import _validate as v
from ..compensators import Compensator, NoCompensation
from ..controllers import Controller
from ..friction import FrictionLaw, FrictionModel
from ..params import ActuatorParams
from ..plant import FLEXIBLE, RIGID, STATE, FlexibleJoint, JointModel, KernelArgs, RigidJoint
from ..plant.joints import checked_state, checked_substeps, plant_label
from ..plant.stability import (MAX_SUBSTEPS, fastest_rate, friction_slope, required_substeps,
                               speed_bound)
from .loop import OUTPUTS, joint_interval, run_compiled, run_python
from .results import BatchResult, ReplayResult, SimInfo, SimResult
from .spec import CompensatorSpec, ControlSpec, LoopSpec, PlantSpec

__all__ = ["simulate", "simulate_batch", "simulate_model", "simulate_schedule", "replay",
           "Schedule", "DEFAULT_SUBSTEPS", "MAX_SAMPLES"]

#: Internal RK4 sub-intervals per sample, by plant kind.
DEFAULT_SUBSTEPS = {RIGID: 4, FLEXIBLE: 10, STATE: 40}
#: Memory per simulated sample [bytes]: 120 measured (peak RSS of a 1e6-sample P loop, 121 MB
#: above a 1e4-sample one: the records and the loop's buffers), plus 8 for a noise draw, rounded up.
BYTES_PER_SAMPLE = 160
#: The memory one call may take [bytes].
MEMORY_BUDGET = 4e9
#: Largest number of samples (runs x samples) one call simulates: :data:`MEMORY_BUDGET` at
#: :data:`BYTES_PER_SAMPLE` (25 million, 14 h at 500 Hz; ~1 min of computing); more is
#: refused with the number, before any work.
MAX_SAMPLES = int(MEMORY_BUDGET // BYTES_PER_SAMPLE)
_PLANTS = {"rigid": RIGID, "flexible": FLEXIBLE}
#: ``SimInfo.plant`` of each plant kind.


def _check_drift(friction: FrictionModel, t0: float, t1: float) -> None:
    """Friction whose drifting scale would turn negative drives the joint: refuse it."""
    for t in (t0, t1):
        if 1.0 + friction.drift * t <= 0.0:
            raise ValueError(f"friction drift {friction.drift:g} 1/s makes the friction scale "
                             f"1 + drift*t <= 0 at t = {t:g} s: friction would drive the joint")


def _speed_matters(friction: FrictionModel) -> bool:
    """True when a law's slope grows with speed (drag): the run's top speed sizes the sub-steps."""
    return friction_slope(friction, 1.0) != friction_slope(friction, 2.0)


def _substeps(requested, kind: int, ts: float, args_list, frictions, t0: float, t1: float, *,
              torque=None, omega0: float = 0.0) -> int:
    """RK4 sub-steps: the kind's default raised to what the plant's fastest rate needs
    (:mod:`fricctl.plant.stability`); an explicit count below that need is refused, as is a
    need above :data:`~fricctl.plant.stability.MAX_SUBSTEPS` (with the number).  ``torque``:
    the largest drive torque of the run (per run or one for all; None: unknown), which bounds
    the speed for laws whose slope grows with it (drag)."""
    need, rate = 1, 0.0
    torques = list(torque) if isinstance(torque, (list, tuple)) else [torque] * len(args_list)
    for a, fr, tq in zip(args_list, frictions, torques):
        # the drifting scale is largest at one end of the run
        peak = max(1.0 + fr.drift * t0, 1.0 + fr.drift * t1, 1e-300)
        r = fastest_rate(inertia=a.motor_inertia, friction=fr.scaled(peak) if peak != 1.0 else fr,
                         load_inertia=a.load_inertia if a.stiffness > 0 else 0.0,
                         stiffness=a.stiffness, damping=a.damping,
                         speed=speed_bound(fr, tq, omega0) if _speed_matters(fr) else None)
        rate = max(rate, r)
        need = max(need, required_substeps(sample_time=ts, rate=r))
    if requested is None:
        n = max(DEFAULT_SUBSTEPS[kind], need)
    else:
        n = checked_substeps(requested)
        if n > MAX_SUBSTEPS:  # an explicit count is the user's, not the plant's: say so
            raise ValueError(f"substeps={n} is more than the {MAX_SUBSTEPS} allowed per sample "
                             f"(this plant needs {need} at Ts = {ts:g} s; omit substeps to use it)")
        if n < need:
            raise ValueError(f"substeps={n} is too few: the plant's fastest rate {rate:.4g} 1/s "
                             f"needs at least {need} RK4 sub-steps per sample of {ts:g} s "
                             "(fewer diverge)")
    if n > MAX_SUBSTEPS:
        raise ValueError(f"this would take {n} RK4 sub-steps per sample (the plant's fastest rate "
                         f"{rate:.4g} 1/s against Ts = {ts:g} s), more than {MAX_SUBSTEPS}: the "
                         "plant is too stiff for this sample time")
    return n


def _check_finite(t, out, res) -> None:
    """Refuse a run whose record turned non-finite, or whose position left what the encoder
    counts exactly (2**53 counts: the compiled floor() wraps there and would hide it)."""
    bad = ~np.all(np.isfinite(out), axis=tuple(i for i in range(out.ndim) if i != out.ndim - 1))
    if np.ndim(res) == 0:
        res = np.array([res])
    for r in np.atleast_1d(res):
        if r > 0:
            q = out[0] if out.ndim == 3 else out
            bad |= ~np.all(np.abs(q) <= 2.0 ** 53 * r, axis=tuple(range(q.ndim - 1)))
    if bad.any():
        raise ValueError(f"the simulation diverged at t = {t[int(np.argmax(bad))]:g} s (the state "
                         "is no longer finite): the closed loop is unstable")


def _as_list(x, n, name, types):
    if isinstance(x, (list, tuple)):
        if len(x) not in (1, n):
            raise ValueError(f"{name}: got {len(x)} items for {n} runs")
        items = list(x) * (n if len(x) == 1 else 1)
    else:
        items = [x] * n
    for it in items:
        v.instance(name, it, types)
    return items


def _batch_size(*args):
    if any(isinstance(a, (list, tuple)) and len(a) == 0 for a in args):
        raise ValueError("an empty list was given for a batch argument (params, controller, "
                         "compensator or friction): give one item, or one per run")
    sizes = {len(a) for a in args if isinstance(a, (list, tuple)) and len(a) != 1}
    if len(sizes) > 1:
        raise ValueError(f"batch arguments disagree on the number of runs: {sorted(sizes)}")
    return sizes.pop() if sizes else 1


def _samples(duration, ts, n_runs) -> int:
    duration = v.real("duration", duration, positive=True, unit="s")
    nsamp = int(round(duration / ts))
    if nsamp < 2:
        raise ValueError(f"duration {duration} s is shorter than two samples of {ts} s")
    if n_runs * nsamp > MAX_SAMPLES:
        raise ValueError(f"duration {duration} s x {n_runs} runs is {n_runs * nsamp} samples, more "
                         f"than {MAX_SAMPLES} ({MEMORY_BUDGET / 1e9:g} GB at {BYTES_PER_SAMPLE} "
                         "bytes each): shorten the duration or split the batch")
    return nsamp


def _delay(delay, nsamp: int, ts: float, what: str = "delay") -> int:
    """Whole samples of delay, shorter than the run (a longer one: no torque reaches the joint)."""
    d = v.integer(what, delay, low=0)
    if d >= nsamp:  # compared as integers: a 400-digit delay is refused, not an OverflowError
        seconds = f"{d * ts:g} s" if d < 10 ** 300 else "beyond double precision"
        raise ValueError(f"{what} of {d if d < 10 ** 30 else f'~1e{len(str(d)) - 1}'} samples "
                         f"({seconds}) is not shorter than the run "
                         f"({nsamp} samples, {nsamp * ts:g} s): no torque would reach the joint")
    return d


def _noise(noise_std, rng, shape, name="noise_std", unit="N*m"):
    """(std, per-sample draws) of white noise ``name``: a ``(1, 1)`` zero array when its std is 0
    (nothing drawn from ``rng``).  Callers draw the torque noise first, then the position noise,
    so that a run without position noise draws what it always drew."""
    noise_std = v.real(name, noise_std, nonneg=True, unit=unit)
    if noise_std > 0:
        if not isinstance(rng, np.random.Generator):
            raise ValueError(f"{name} > 0 needs rng=numpy.random.default_rng(seed)")
        return noise_std, rng.normal(0.0, noise_std, size=shape)
    return noise_std, np.zeros((1, 1))


def _position_noise(position_noise_std, rng, shape):
    """(std, draws) of the position noise before quantisation (encoder edge jitter) [rad]."""
    return _noise(position_noise_std, rng, shape, "position_noise_std", "rad")


def _arrays(out, stuck) -> dict:
    return dict(zip(OUTPUTS, out), stuck=stuck)


def _run(plant: PlantSpec, loop: LoopSpec, control: ControlSpec, compensators, t):
    """Run a batch (one compensator per run) at sample instants ``t``: compiled when every
    compensator compiles to one kind, else with the compensators evaluated in Python.

    Returns the records (11, N, K) (rows :data:`~fricctl.simulate.loop.OUTPUTS`), ``stuck``
    (N, K) and the loop taken ("compiled" or "python"); a run that diverged is refused.
    """
    n = len(compensators)
    out, stuck = np.empty((len(OUTPUTS), n, t.size)), np.empty((n, t.size), dtype=np.bool_)
    comp = CompensatorSpec.of(compensators)
    if comp is not None:
        run_compiled(plant, loop, control, comp, out, stuck)
    else:
        run_python(plant, loop, control, compensators,
                   np.array([c.scale for c in compensators], dtype=float), out, stuck)
    _check_finite(t, out, loop.encoder_resolution)
    return out, stuck, "compiled" if comp is not None else "python"


def _batch_frictions(friction, plist, n: int, plant: str):
    """(each run's FrictionModel, the plant kind) of a batch: laws become models, a presliding
    law (LuGre, Dahl) makes the rigid joint the STATE kind."""
    if isinstance(friction, FrictionLaw):
        friction = friction.model()
    elif isinstance(friction, (list, tuple)):
        friction = [f.model() if isinstance(f, FrictionLaw) else f for f in friction]
    frs = [p.friction_model() for p in plist] if friction is None else _as_list(
        friction, n, "friction", FrictionModel)
    kind = _PLANTS[v.choice("plant", plant, tuple(_PLANTS))]
    state = {f.state_law for f in frs}
    if len(state) > 1:
        raise ValueError("a batch cannot mix presliding (LuGre, Dahl) and stick-slip friction "
                         "models, or two presliding laws")
    law = state.pop()
    if law is not None:
        if kind == FLEXIBLE:
            raise ValueError(f"{law.constructor.__name__} friction is supported on the rigid "
                             "joint only")
        kind = STATE
    return frs, kind


def _initial_positions(q0, n: int) -> np.ndarray:
    try:
        return np.broadcast_to(v.array("q0", q0, ndim=None), (n,)).copy()
    except ValueError as exc:
        if "q0" in str(exc):
            raise
        raise ValueError(f"q0 must be a number or an array of {n} initial positions, got shape "
                         f"{np.shape(q0)}") from None


def _kernel_args(p: ActuatorParams, kind: int) -> KernelArgs:
    """The joint of an actuator as the kernels see it: elastic (Eq. 1) or rigid (Eq. 2)."""
    flex = kind == FLEXIBLE
    return KernelArgs(kind=kind, motor_inertia=p.inertia if flex else p.total_inertia,
                      load_inertia=p.link_inertia if flex else p.total_inertia,
                      stiffness=p.stiffness if flex else 0.0,
                      damping=p.joint_damping if flex else 0.0)


def simulate_batch(params, controller, compensator=None, *, duration: float,
                   friction=None, plant: str = "rigid", substeps: int | None = None,
                   q0=0.0, noise_std: float = 0.0, rng: np.random.Generator | None = None,
                   delay: int = 0, quantize: bool = True,
                   position_noise_std: float = 0.0) -> BatchResult:
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
    position_noise_std : float
        Standard deviation of white position noise added to the joint's position before the
        encoder quantises it (encoder edge jitter) [rad]; needs ``rng``, drawn after the
        torque noise.  The true position ``q`` is untouched; ``q_meas`` and the velocity
        estimate see it.

    Returns
    -------
    BatchResult
    """
    n = _batch_size(params, controller, compensator, friction)
    plist = _as_list(params, n, "params", ActuatorParams)
    clist = _as_list(controller, n, "controller", Controller)
    comps = _as_list(NoCompensation() if compensator is None else compensator, n, "compensator",
                     Compensator)
    for c in comps:
        _check_axis(c, "rotary", "the actuator (ActuatorParams)")
    frs, kind = _batch_frictions(friction, plist, n, plant)
    ts = plist[0].sample_time
    if any(p.sample_time != ts for p in plist):
        raise ValueError("all runs of a batch must share one sample_time")
    _warn_sampling(clist, ts)
    nsamp = _samples(duration, ts, n)
    delay = _delay(delay, nsamp, ts)
    quantize = v.flag("quantize", quantize)
    noise_std, noise = _noise(noise_std, rng, (n, nsamp))
    pos_std, pos_noise = _position_noise(position_noise_std, rng, (n, nsamp))
    q0a = _initial_positions(q0, n)
    if kind == FLEXIBLE and any(p.link_inertia <= 0 for p in plist):
        raise ValueError("plant='flexible' needs link_inertia > 0 (the load-side inertia of Eq. 1)")
    for f in frs:
        _check_drift(f, 0.0, nsamp * ts)
    joints = [_kernel_args(p, kind) for p in plist]
    substeps = _substeps(substeps, kind, ts, joints, frs, 0.0, nsamp * ts,
                         torque=[p.max_torque for p in plist])

    t = np.arange(nsamp) * ts
    res = np.array([p.encoder_resolution if quantize else 0.0 for p in plist])
    loop = LoopSpec(sample_time=ts, encoder_resolution=res,
                    max_torque=np.array([p.max_torque for p in plist]), q0=q0a, delay=delay,
                    noise=noise, position_noise=pos_noise)
    out, stuck, path = _run(PlantSpec.of(joints, frs, substeps), loop, ControlSpec.of(clist, t),
                            comps, t)
    infos = tuple(SimInfo(
        params=plist[i], friction_model=frs[i], controller=clist[i].name, kp=clist[i].kp,
        kd=clist[i].kd, compensator=comps[i].name, compensation_scale=comps[i].scale,
        plant=plant_label(kind, frs[i]), substeps=int(substeps),
        delay=int(delay), noise_std=float(noise_std), encoder_resolution=float(res[i]), loop=path,
        position_noise_std=float(pos_std))
        for i in range(n))
    return BatchResult(t=t, infos=infos, **_arrays(out, stuck))


def simulate(params: ActuatorParams, controller: Controller, compensator: Compensator | None = None, *,
             duration: float, friction: FrictionModel | None = None, plant: str = "rigid",
             substeps: int | None = None, q0: float = 0.0, noise_std: float = 0.0,
             rng: np.random.Generator | None = None, delay: int = 0,
             quantize: bool = True, position_noise_std: float = 0.0) -> SimResult:
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
    v.instance("params", params, ActuatorParams)
    v.instance("controller", controller, Controller)
    return simulate_batch(params, controller, compensator, duration=duration, friction=friction,
                          plant=plant, substeps=substeps, q0=q0, noise_std=noise_std, rng=rng,
                          delay=delay, quantize=quantize, position_noise_std=position_noise_std)[0]


def _model_loop(model: JointModel, nsamp: int, res: float, q0, noise, position_noise) -> LoopSpec:
    """The loop around a model's joint: its torque limit (None: none), its delay in whole
    samples, its offset as a constant torque in what the joint receives."""
    ts = model.sample_time
    if model.offset != 0.0:  # the joint receives Tm - offset: a constant term of the loop's noise
        noise = np.broadcast_to(noise, (1, nsamp)) - model.offset
    tmax = math.inf if model.max_torque is None else model.max_torque
    return LoopSpec(sample_time=ts, encoder_resolution=np.array([res]), max_torque=np.array([tmax]),
                    q0=np.array([v.real("q0", q0)]),
                    delay=_delay(model.delay_samples(ts), nsamp, ts, "the model's delay"),
                    noise=noise, position_noise=position_noise)


def sampling_warnings(controller: Controller, sample_time: float) -> list[str]:
    """Why a run of ``controller`` sampled every ``sample_time`` may mislead: a reference or
    torque profile at or above the Nyquist frequency ``1/(2*sample_time)``.

    The loop reads the signal at the sample instants only, so it follows its alias: a
    300 Hz sinusoid at 500 Hz sampling is a 200 Hz one, and a 500 Hz one a constant (the
    "steady-state error" of such a run is that of the alias, not of the signal).

    Parameters
    ----------
    controller : Controller
    sample_time : float
        Ts [s].

    Returns
    -------
    list of str
        One sentence per signal above the Nyquist frequency (empty: none).  :func:`simulate`,
        :func:`simulate_batch` and :func:`simulate_model` also issue each as a
        :class:`RuntimeWarning`.

    Examples
    --------
    >>> from fricctl.controllers import pd_control, sinusoid
    >>> sampling_warnings(pd_control(1.0, 0.1, sinusoid(0.1, 300.0)), 0.002)[0][:60]
    'the reference (sinusoid 0.1 at 300 Hz) is at or above the Ny'
    """
    v.instance("controller", controller, Controller)
    ts = v.real("sample_time", sample_time, positive=True, unit="s")
    nyquist = 0.5 / ts
    out = []
    for what, sig in (("reference", controller.reference), ("torque profile", controller.feedforward)):
        f = sig.frequency
        if f is not None and f >= nyquist:
            alias = abs(f - round(f * ts) / ts)
            out.append(f"the {what} ({sig.description}) is at or above the Nyquist frequency "
                       f"{nyquist:g} Hz of the sample time {ts:g} s: the loop sees it aliased, "
                       f"at {alias:.4g} Hz")
    return out


def _warn_sampling(controllers, sample_time: float) -> None:
    import warnings

    for text in dict.fromkeys(t for c in controllers for t in sampling_warnings(c, sample_time)):
        warnings.warn(text, RuntimeWarning, stacklevel=3)


def _check_axis(comp: Compensator, kind: str, what: str) -> None:
    """Refuse a compensator made for another kind of axis (a net trained on a linear axis,
    force [N] and velocity [m/s], run on a rotary joint, or the reverse)."""
    from ..units import units as units_of

    if comp.units is not None and comp.units != kind:
        made, here = units_of(comp.units), units_of(kind)
        raise ValueError(f"compensator: its network was trained on a {made.kind} axis "
                         f"({made.torque}, {made.velocity}); {what} is a {here.kind} axis "
                         f"({here.torque}, {here.velocity})")


def _one_result(t, out, stuck, **info) -> SimResult:
    """The result of a one-run batch without :class:`~fricctl.params.ActuatorParams`
    (``info``: the other :class:`SimInfo` fields)."""
    return SimResult(t=t, info=SimInfo(params=None, **info),
                     **{k: x[0] for k, x in _arrays(out, stuck).items()})


def simulate_model(model: JointModel, controller: Controller,
                   compensator: Compensator | None = None, *, duration: float,
                   friction: FrictionModel | None = None, substeps: int | None = None,
                   q0: float = 0.0, noise_std: float = 0.0, rng: np.random.Generator | None = None,
                   quantize: bool = True, position_noise_std: float = 0.0) -> SimResult:
    """Simulate the sampled loop on a :class:`~fricctl.plant.JointModel` (your own actuator).

    The same compiled loop as :func:`simulate`, with everything taken from the model:
    the joint (rigid, or elastic when ``load_inertia > 0``), the sample time, the
    encoder count, the torque limit, the delay (whole samples) and the constant
    offset (the joint receives ``Tm - offset``).  Units follow the model: on a linear
    axis positions are [m], torques forces [N], gains [N/m] and [N*s/m].

    Parameters
    ----------
    model : JointModel
        Needs ``sample_time``; ``encoder_resolution`` None means no quantisation and
        ``max_torque`` None no saturation.
    controller : Controller
    compensator : Compensator, optional
        Any :class:`~fricctl.compensators.Compensator` (default none); a
        :class:`~fricctl.nn.FrictionNet` runs compiled, any other estimator in Python.
    duration : float
        Simulated time [s].
    friction : FrictionModel, optional
        The joint's true friction (default ``model.friction``).
    substeps : int, optional
        RK4 sub-intervals per sample (default by plant kind).
    q0 : float
        Initial position, at rest [rad] or [m].
    noise_std : float
        White torque noise at the joint [N*m] or [N]; needs ``rng``.
    rng : numpy.random.Generator, optional
    quantize : bool
        Encoder quantisation (when the model has a resolution).
    position_noise_std : float
        White position noise before quantisation (encoder edge jitter) [rad] or [m]; needs
        ``rng``, drawn after the torque noise.

    Returns
    -------
    SimResult
        ``info.params`` is None; ``info.encoder_resolution`` 0 without quantisation.

    Raises
    ------
    ValueError
        The model has no sample time, or the run diverges (a non-finite state: an
        unstable loop without a torque limit).

    Examples
    --------
    >>> from fricctl.controllers import open_loop, constant
    >>> from fricctl.data import paper_actuator_model
    >>> m = paper_actuator_model()
    >>> r = simulate_model(m, open_loop(constant(0.99 * 0.18)), duration=0.5)
    >>> float(abs(r.q).max())          # 1 % below breakaway: no motion at all
    0.0
    """
    v.instance("model", model, JointModel, "a fricctl.plant.JointModel")
    v.instance("controller", controller, Controller)
    comp = NoCompensation() if compensator is None else v.instance(
        "compensator", compensator, Compensator)
    if model.sample_time is None:
        raise ValueError("sample_time: the model has none (null): set the controller's sample "
                         "time in the model file")
    _check_axis(comp, model.units, "the model")
    ts = model.sample_time
    _warn_sampling([controller], ts)
    nsamp = _samples(duration, ts, 1)
    fr = model.friction if friction is None else v.instance("friction", friction, FrictionModel)
    a = replace(model, friction=fr).joint().kernel_args()
    substeps = _substeps(substeps, a.kind, ts, [a], [fr], 0.0, nsamp * ts, torque=model.max_torque)
    res = model.encoder_resolution if v.flag("quantize", quantize) and model.encoder_resolution else 0.0
    noise_std, noise = _noise(noise_std, rng, (1, nsamp))
    pos_std, pos_noise = _position_noise(position_noise_std, rng, (1, nsamp))
    _check_drift(fr, 0.0, nsamp * ts)
    t = np.arange(nsamp) * ts
    loop = _model_loop(model, nsamp, res, q0, noise, pos_noise)
    out, stuck, path = _run(PlantSpec.of([a], [fr], substeps), loop,
                            ControlSpec.of([controller], t), [comp], t)
    return _one_result(t, out, stuck, friction_model=fr, controller=controller.name,
                       kp=controller.kp, kd=controller.kd, compensator=comp.name,
                       compensation_scale=comp.scale, plant=plant_label(a.kind, fr),
                       substeps=int(substeps), delay=int(loop.delay), noise_std=float(noise_std),
                       encoder_resolution=float(res), loop=path, position_noise_std=float(pos_std),
                       units=model.units)


class Schedule:
    """Per-sample settings of one run: gains, reference, feed-forward, reference segments.

    Parameters
    ----------
    kp, kd : array_like, shape (K,)
        Gains at each sample [N*m/rad], [N*m*s/rad] (0 for open-loop segments).
    reference : array_like, shape (K,)
        Position reference of each segment, relative to the encoder reading at the
        segment's first sample [rad].
    feedforward : array_like, shape (K,)
        Open-loop torque [N*m].
    segment_start : array_like of bool, shape (K,)
        True at the first sample of each segment (the reference is re-zeroed there).
    """

    def __init__(self, *, kp, kd, reference, feedforward, segment_start):
        self.kp = v.array("kp", kp, min_size=2)
        k = self.kp.size
        self.kd = v.array("kd", kd, size=k)
        self.reference = v.array("reference", reference, size=k)
        self.feedforward = v.array("feedforward", feedforward, size=k)
        seg = np.asarray(segment_start)
        if seg.dtype != np.bool_ or seg.shape != (k,):
            raise ValueError(f"segment_start must be a boolean array of {k} samples")
        self.segment_start = seg
        if np.any(self.kp < 0) or np.any(self.kd < 0):
            raise ValueError("kp and kd must be >= 0")

    def __len__(self):
        return self.kp.size


def simulate_schedule(joint, schedule: Schedule, *, sample_time: float, max_torque: float,
                      encoder_resolution: float, substeps: int | None = None, delay: int = 0,
                      noise=None) -> SimResult:
    """Run the sampled loop on a joint with per-sample gains and references (no compensation).

    The experiments of a record are chained as segments: each segment's reference is
    relative to where its first sample finds the joint (the hidden-effect bench,
    :mod:`fricctl.bench.hidden_effects`, builds records this way).

    Parameters
    ----------
    joint : RigidJoint or FlexibleJoint
    schedule : Schedule
    sample_time : float
        Ts [s].
    max_torque : float
        Saturation of the commanded and the received torque [N*m].
    encoder_resolution : float
        One encoder count [rad] (0: no quantisation).
    substeps : int, optional
        RK4 sub-intervals per sample (default by plant kind).
    delay : int
        Samples by which the joint receives the recorded torque late.
    noise : array_like, shape (K,), optional
        Torque noise added to what the joint receives [N*m].

    Returns
    -------
    SimResult
        ``info.params`` is None (no :class:`~fricctl.params.ActuatorParams`); ``info.kp``
        and ``info.kd`` are the largest gains of the schedule.
    """
    v.instance("joint", joint, (RigidJoint, FlexibleJoint))
    v.instance("schedule", schedule, Schedule)
    ts = v.real("sample_time", sample_time, positive=True, unit="s")
    tmax = v.real("max_torque", max_torque, positive=True, unit="N*m")
    res = v.real("encoder_resolution", encoder_resolution, nonneg=True, unit="rad")
    nsamp = len(schedule)
    _samples(nsamp * ts, ts, 1)
    a = joint.kernel_args()
    substeps = _substeps(substeps, a.kind, ts, [a], [joint.friction], 0.0, nsamp * ts,
                         torque=tmax)
    delay = _delay(delay, nsamp, ts)
    noise = (np.zeros((1, 1)) if noise is None
             else v.array("noise", noise, size=nsamp).reshape(1, nsamp))
    _check_drift(joint.friction, 0.0, nsamp * ts)
    loop = LoopSpec(sample_time=ts, encoder_resolution=np.array([res]), max_torque=np.array([tmax]),
                    q0=np.zeros(1), delay=delay, noise=noise, position_noise=np.zeros((1, 1)))
    control = ControlSpec(reference=schedule.reference[None, :],
                          feedforward=schedule.feedforward[None, :], kp=schedule.kp[None, :],
                          kd=schedule.kd[None, :], segment_start=schedule.segment_start[None, :])
    t = np.arange(nsamp) * ts
    out, stuck, path = _run(PlantSpec.of([a], [joint.friction], substeps), loop, control,
                            [NoCompensation()], t)
    return _one_result(t, out, stuck, friction_model=joint.friction,
                       controller="schedule", kp=float(schedule.kp.max()),
                       kd=float(schedule.kd.max()), compensator="none", compensation_scale=1.0,
                       plant=plant_label(a.kind, joint.friction), substeps=int(substeps), delay=int(delay),
                       noise_std=float(np.std(noise)) if noise.size > 1 else 0.0,
                       encoder_resolution=res, loop=path)


@jit(nogil=True)  # identification replays the folds of a jackknife in threads
def _replay(plant, st, torque, t0, ts, o_q, o_w, o_f):
    """Drive the joint of a one-run :class:`PlantSpec` from state ``st`` with ``torque`` held
    per sample; records into ``o_q``, ``o_w``, ``o_f``."""
    for i in range(torque.size):
        t = t0 + i * ts
        o_q[i] = st[0]
        o_w[i] = st[1]
        o_f[i] = joint_interval(plant, 0, st, torque[i], t, ts)[0]


def replay(joint, torque, sample_time: float, *, q0: float = 0.0, omega0: float = 0.0,
           t0: float = 0.0, substeps: int | None = None, state=None) -> ReplayResult:
    """Drive a joint open loop with a recorded torque sequence (held per sample).

    This is "what the model predicts" for a measured record: the joint starts at
    ``(q0, omega0)`` (or a full ``state``) and receives ``torque[i]`` over
    ``[t0 + i*Ts, t0 + (i+1)*Ts)``.  No control loop: not the sampled loop of
    :func:`simulate`, only the plant.

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
    ReplayResult
        Position [rad], velocity [rad/s] and resistive torque [N*m] at each sample
        instant (before that sample's torque acts).
    """
    v.instance("joint", joint, (RigidJoint, FlexibleJoint))
    tq = v.array("torque", torque, min_size=1)
    ts = v.real("sample_time", sample_time, positive=True, unit="s")
    a = joint.kernel_args()
    st = joint.initial_state(q0, omega0) if state is None else checked_state(state)
    t0 = v.real("t0", t0)
    _check_drift(joint.friction, t0, t0 + tq.size * ts)
    substeps = _substeps(substeps, a.kind, ts, [a], [joint.friction], t0, t0 + tq.size * ts,
                         torque=float(np.max(np.abs(tq))), omega0=float(abs(st[1])))
    o_q, o_w, o_f = np.empty(tq.size), np.empty(tq.size), np.empty(tq.size)
    _replay(PlantSpec.of([a], [joint.friction], substeps), st, tq, t0, ts, o_q, o_w, o_f)
    _check_finite(t0 + np.arange(tq.size) * ts, np.vstack([o_q, o_w, o_f]), 0.0)
    return ReplayResult(q=o_q, omega=o_w, friction=o_f)
