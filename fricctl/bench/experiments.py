"""Experiments on the virtual bench: training patterns, estimator comparison, the dead zone.

The paper's pipeline, step by step:

1. :func:`training_experiments` -- the experiments of its Table 2, in spirit:
   open-loop torque steps of many amplitudes up to the maximum torque, both
   signs, with null-torque intervals between them, and closed-loop P and PD step
   sequences; optionally a pre-heating sinusoid first (the paper runs 5 minutes
   of it; on the virtual bench it only matters for a friction model with drift).
   Each returns a :class:`~fricctl.datasets.Run` (what a lab records) and the
   simulator's truth.
2. :func:`friction_patterns` -- ``Tat = Tm - I*alpha_hat`` with alpha_hat from
   the encoder (the paper's piecewise 6th-order polynomial fit by default).
3. :func:`train_network` -- the 2-4-1 network on those patterns.
4. :func:`dead_zone` -- open-loop sinusoids of growing amplitude; the dead zone
   is the smallest amplitude that moves the encoder by more than a few counts.

:func:`compare_estimators` measures each velocity/acceleration estimator
against the simulator's truth (issue: "which estimator, how wrong").
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from .. import _validate as v
from ..compensators import Compensator, NoCompensation
from ..controllers import open_loop, p_control, pd_control, sequence, sinusoid
from ..datasets import FrictionPatterns, Run
from ..estimation import ESTIMATORS, at_rest, estimate
from ..friction import FrictionModel
from ..params import ActuatorParams, paper_actuator
from ..simulate import SimResult, simulate, simulate_batch

__all__ = [
    "Experiment", "training_experiments", "BenchPatterns", "PatternSplit", "friction_patterns", "true_patterns", "train_network",
    "EstimatorError", "compare_estimators", "DeadZone", "dead_zone", "DeadZonePrediction", "predicted_dead_zone", "PaperGains", "paper_gains",
]


@dataclass(frozen=True, kw_only=True)
class Experiment:
    """One bench experiment: the record a lab would keep, and the simulator's truth."""

    name: str
    run: Run
    truth: SimResult


@dataclass(frozen=True, kw_only=True)
class PaperGains:
    """Gains of the paper's two training controllers."""

    p_kp: float
    """Kp of the P design (0.2 s, 0.3) [N*m/rad]."""
    pd_kp: float
    """Kp of the PD design (0.3 s, 0.9) [N*m/rad]."""
    pd_kd: float
    """Kd of the PD design [N*m*s/rad]."""


def _params(params) -> ActuatorParams:
    return v.instance("params", params, ActuatorParams, "a fricctl.params.ActuatorParams")


def _experiments(experiments) -> list:
    if not isinstance(experiments, (list, tuple)):
        raise ValueError(f"experiments must be a list of Experiment, got "
                         f"{type(experiments).__name__}")
    return [v.instance(f"experiments[{i}]", ex, Experiment, "an Experiment")
            for i, ex in enumerate(experiments)]


def paper_gains(params: ActuatorParams, *, rise_time_definition: str | None = None) -> PaperGains:
    """Gains of the paper's P (0.2 s, 0.3) and PD (0.3 s, 0.9) designs for ``params``.

    ``params`` is the design model (its ``viscous`` the b the designs count on);
    ``rise_time_definition`` how both read their rise time (default 0-100 %; a bench's
    reading, :mod:`fricctl.paper.benches`).  The PD design's sampled-loop warning (its
    0-100 % rise time is ill-conditioned at zeta = 0.9; see
    :func:`fricctl.design.design_pd`) is expected and silenced here.
    """
    import warnings

    from ..design import DesignWarning, design_p, design_pd

    p = design_p(params, rise_time=0.2, damping=0.3, rise_time_definition=rise_time_definition)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DesignWarning)
        pd = design_pd(params, rise_time=0.3, damping=0.9, rise_time_definition=rise_time_definition)
    return PaperGains(p_kp=p.kp, pd_kp=pd.kp, pd_kd=pd.kd)


def training_experiments(params: ActuatorParams | None = None, *, friction: FrictionModel | None = None,
                         fast: bool = False, preheat: bool = False, noise_std: float = 0.0,
                         rng: np.random.Generator | None = None,
                         gains: PaperGains | None = None) -> list[Experiment]:
    """Run the training-pattern experiments (paper Table 2 in spirit).

    Parameters
    ----------
    params : ActuatorParams, optional
        Default :func:`~fricctl.params.paper_actuator`.
    friction : FrictionModel, optional
        The bench's true friction; default ``params.friction_model()``.
    fast : bool
        Fewer amplitudes and shorter sequences (for tests and chapters).
    preheat : bool
        Prepend a sinusoidal pre-heating run (300 s, or 20 s with ``fast``) at 30 %
        of the maximum torque, 0.5 Hz; returned first, named ``"preheat"``.
    noise_std : float
        White torque noise at the joint [N*m] (needs ``rng``).
    rng : numpy.random.Generator, optional
    gains : PaperGains, optional
        The closed-loop experiments' gains; default :func:`paper_gains` of ``params``
        (a bench may design on another b or rise-time reading than its plant's).

    Returns
    -------
    list of Experiment
        ``"open-loop steps"``, ``"P steps"``, ``"PD steps"`` (and ``"preheat"``).

    Notes
    -----
    Amplitudes are fractions of the maximum torque: 20 levels from 2.5 % to 100 %
    (8 with ``fast``), each held 0.1 s with alternating sign, followed by 0.4 s at
    zero torque so the joint stops.  Closed-loop references are steps among
    +-0.2 ... +-0.8 rad, 1 s each, with the paper's P and PD gains.
    """
    p = paper_actuator() if params is None else _params(params)
    tmax = p.max_torque
    fr = p.friction_model() if friction is None else friction
    kw = dict(friction=fr, noise_std=noise_std, rng=rng)
    out = []
    if preheat:
        dur = 20.0 if fast else 300.0
        res = simulate(p, open_loop(sinusoid(0.3 * tmax, 0.5)), duration=dur, **kw)
        out.append(Experiment(name="preheat", run=res.to_run(source="bench: preheat"), truth=res))
    fractions = (np.array([0.05, 0.1, 0.15, 0.25, 0.4, 0.6, 0.8, 1.0]) if fast
                 else np.linspace(0.025, 1.0, 20))
    levels, durations = [0.0], [0.1]
    for i, f in enumerate(fractions):
        levels += [(-1) ** i * f * tmax, 0.0]
        durations += [0.1, 0.4]
    ctrl = open_loop(sequence(levels, durations))
    res = simulate(p, ctrl, duration=float(np.sum(durations)), **kw)
    out.append(Experiment(name="open-loop steps", run=res.to_run(source="bench: open-loop torque steps"),
                          truth=res))
    gains = paper_gains(p) if gains is None else v.instance("gains", gains, PaperGains)
    kp_p, kp_pd, kd_pd = gains.p_kp, gains.pd_kp, gains.pd_kd
    refs = [0.4, -0.4, 0.8, 0.0, -0.8, 0.2] if fast else [0.4, -0.4, 0.8, 0.0, -0.8, 0.2, 0.6, -0.2, 0.5, -0.6,
                                                           0.3, 0.0]
    ref = sequence(refs, [1.0] * len(refs))
    for name, ctrl in (("P steps", p_control(kp_p, ref)), ("PD steps", pd_control(kp_pd, kd_pd, ref))):
        res = simulate(p, ctrl, duration=float(len(refs)), **kw)
        out.append(Experiment(name=name, run=res.to_run(source=f"bench: closed-loop {name}"), truth=res))
    return out


@dataclass(frozen=True, kw_only=True, eq=False)
class BenchPatterns(FrictionPatterns):
    """Friction patterns made on the virtual bench, with where each came from and what the
    simulator knows of it.

    A :class:`~fricctl.datasets.FrictionPatterns` (``tm``, ``omega``, ``friction``,
    ``at_rest``, ``velocity_quantum``: what a pipeline trains on) plus what only a
    simulation has: the true friction at each pattern, its time and experiment, the
    estimator that made it.  The added arrays are checked like the others (one value per
    pattern) and kept as read-only copies.
    """

    friction_true: np.ndarray = field(metadata={"unit": "N*m"})
    """The simulator's true friction at the same samples [N*m]."""
    t: np.ndarray = field(metadata={"unit": "s"})
    """Time of each pattern within its experiment [s]."""
    experiment: np.ndarray
    """Index of the experiment (in the list given) each pattern comes from."""
    method: str
    """The velocity/acceleration estimator that made ``omega`` and ``friction``
    (``"truth"``: the simulator's own, :func:`true_patterns`)."""

    def __post_init__(self):
        super().__post_init__()
        n = self.tm.size
        for name in ("friction_true", "t"):
            object.__setattr__(self, name, _frozen(v.array(name, getattr(self, name), size=n)))
        experiment = np.asarray(self.experiment)
        if experiment.dtype.kind not in "iu" or experiment.shape != (n,):
            raise ValueError(f"experiment must be an integer array of {n} patterns")
        object.__setattr__(self, "experiment", _frozen(experiment))
        v.text("method", self.method, empty=False)

    def subset(self, index) -> "BenchPatterns":
        """The patterns at ``index`` (a boolean mask or integer indices)."""
        return replace(self, **{name: getattr(self, name)[index] for name in _PER_PATTERN})

    def split(self, fraction: float, rng: np.random.Generator) -> "PatternSplit":
        """Random split; ``fraction`` of the patterns go to training, the rest are held out."""
        fraction = v.real("fraction", fraction, low=0.0, high=1.0)
        if not 0 < fraction < 1:
            raise ValueError(f"fraction must lie in (0, 1), got {fraction!r}")
        idx = v.rng("rng", rng).permutation(len(self))
        k = int(round(fraction * len(self)))
        return PatternSplit(train=self.subset(np.sort(idx[:k])), held_out=self.subset(np.sort(idx[k:])))


#: The fields of :class:`BenchPatterns` with one value per pattern.
_PER_PATTERN = ("tm", "omega", "friction", "at_rest", "friction_true", "t", "experiment")


def _frozen(x: np.ndarray) -> np.ndarray:
    x = np.array(x)
    x.setflags(write=False)
    return x


@dataclass(frozen=True, kw_only=True)
class PatternSplit:
    """Patterns split at random into a training and a held-out part."""

    train: BenchPatterns
    held_out: BenchPatterns


def friction_patterns(experiments, params: ActuatorParams, *, method: str = "polynomial_segments",
                      border: int = 5, guard: int = 2, **options) -> BenchPatterns:
    """Friction patterns ``Tat = Tm - I*alpha_hat`` from the experiments' encoder records
    (``velocity_quantum``: one encoder count per sample of ``params``).

    Parameters
    ----------
    experiments : list of Experiment
    params : ActuatorParams
        Its ``total_inertia`` is the I of the patterns (the paper uses the nominal one).
    method : str
        Estimator from :data:`fricctl.estimation.ESTIMATORS`.
    border : int
        Samples dropped at each end of each record [samples].
    guard : int
        Samples either side that must show no encoder motion for a pattern to be at rest
        (:func:`fricctl.estimation.at_rest`).
    **options
        Passed to the estimator.
    """
    if method not in ESTIMATORS:
        raise ValueError(f"unknown estimator {method!r}; choose from {sorted(ESTIMATORS)}")
    params = _params(params)
    parts = []
    for i, ex in enumerate(_experiments(experiments)):
        est = estimate(ex.run.t, ex.run.position, method, **options)
        sl = slice(border, ex.run.n_samples - border)
        tm = ex.run.torque[sl]
        parts.append((tm, est.velocity[sl], tm - params.total_inertia * est.acceleration[sl],
                      ex.truth.friction[sl], ex.run.t[sl], np.full(tm.size, i),
                      at_rest(ex.run.position, guard=guard)[sl]))
    return _patterns(parts, method,
                     velocity_quantum=params.encoder_resolution / params.sample_time)


def _patterns(parts, method, velocity_quantum=None) -> BenchPatterns:
    names = ("tm", "omega", "friction", "friction_true", "t", "experiment", "at_rest")
    return BenchPatterns(method=method, velocity_quantum=velocity_quantum,
                         **{n: np.concatenate(c) for n, c in zip(names, zip(*parts))})


def true_patterns(experiments, *, border: int = 5) -> BenchPatterns:
    """The patterns a perfect measuring chain would give: the simulator's true velocity and friction.

    Same samples as :func:`friction_patterns` with the same ``border``; an upper
    bound of what the network can learn from these experiments.
    """
    parts = []
    for i, ex in enumerate(_experiments(experiments)):
        sl = slice(border, ex.run.n_samples - border)
        parts.append((ex.run.torque[sl], ex.truth.omega[sl], ex.truth.friction[sl], ex.truth.friction[sl],
                      ex.run.t[sl], np.full(ex.run.t[sl].size, i), ex.truth.stuck[sl]))
    return _patterns(parts, "truth")


def train_network(patterns: BenchPatterns, *, trainer: str = "casadi", hidden: int = 4, max_patterns: int = 4000,
                  rng: np.random.Generator | None = None, **options):
    """Train the friction network on (a random subset of at most ``max_patterns``) patterns.

    Returns
    -------
    fricctl.nn.TrainingResult
        ``.net`` and ``.history``.
    """
    from ..nn import train_backprop, train_casadi

    rng = np.random.default_rng(0) if rng is None else rng
    if trainer not in ("casadi", "backprop"):
        raise ValueError(f"trainer must be 'casadi' or 'backprop', got {trainer!r}")
    pats = patterns
    if len(patterns) > max_patterns:
        pats = patterns.subset(np.sort(rng.choice(len(patterns), max_patterns, replace=False)))
    fn = train_casadi if trainer == "casadi" else train_backprop
    meta = {"patterns": len(pats), "estimator": patterns.method}
    return fn(pats.tm, pats.omega, pats.friction, hidden=hidden, rng=rng, metadata=meta, **options)


@dataclass(frozen=True, kw_only=True)
class EstimatorError:
    """Errors of one estimator against the simulator's truth.

    RMS errors are dominated by the few samples around torque steps (the true
    acceleration jumps there, every smoothing estimator spreads the jump); the
    medians of the absolute errors over the samples where the joint truly moves
    say how good the estimate is elsewhere.
    """

    method: str
    velocity_rms: float
    acceleration_rms: float
    friction_rms: float
    velocity_median: float
    acceleration_median: float
    friction_median: float

    def as_dict(self):
        return {k: getattr(self, k) for k in ("method", "velocity_rms", "acceleration_rms", "friction_rms",
                                               "velocity_median", "acceleration_median", "friction_median")}


def compare_estimators(experiment: Experiment, params: ActuatorParams, *, methods=None, border: int = 25,
                       options: dict | None = None) -> list[EstimatorError]:
    """Velocity [rad/s], acceleration [rad/s^2] and friction [N*m] RMS errors per estimator.

    Samples where the truth is at rest are included (an estimator must say "at
    rest" there); ``border`` samples at each end are dropped.
    """
    options = {"butterworth_central": {"cutoff": 25.0}} if options is None else options
    methods = list(ESTIMATORS) if methods is None else methods
    v.instance("experiment", experiment, Experiment, "an Experiment")
    params = _params(params)
    tr = experiment.truth
    sl = slice(border, tr.t.size - border)
    out = []
    for m in methods:
        est = estimate(experiment.run.t, experiment.run.position, m, **options.get(m, {}))
        fr = experiment.run.torque - params.total_inertia * est.acceleration
        ev = est.velocity[sl] - tr.omega[sl]
        ea = est.acceleration[sl] - tr.accel[sl]
        ef = fr[sl] - tr.friction[sl]
        moving = tr.omega[sl] != 0.0
        if not moving.any():
            raise ValueError(f"experiment {experiment.name!r} never moves: nothing to compare")
        rms = [float(np.sqrt(np.mean(e ** 2))) for e in (ev, ea, ef)]
        med = [float(np.median(np.abs(e[moving]))) for e in (ev, ea, ef)]
        out.append(EstimatorError(method=m, velocity_rms=rms[0], acceleration_rms=rms[1],
                                  friction_rms=rms[2], velocity_median=med[0],
                                  acceleration_median=med[1], friction_median=med[2]))
    return out


@dataclass(frozen=True, kw_only=True)
class DeadZone:
    """Open-loop sinusoid amplitudes and the motion each produced.

    Attributes
    ----------
    amplitudes : control torque amplitudes tried [N*m]
    counts : peak-to-peak encoder motion at each amplitude [counts]
    threshold_counts : motion that counts as "moves" [counts]
    max_torque : Tmax of the actuator [N*m]
    compensator : name of the compensation used
    """

    amplitudes: np.ndarray
    counts: np.ndarray
    threshold_counts: int
    max_torque: float
    compensator: str
    results: tuple = field(default=(), repr=False)

    @property
    def dead_zone(self) -> float:
        """Smallest amplitude [N*m] above which every amplitude moves the joint."""
        moves = self.counts > self.threshold_counts
        if not moves.any():
            return float("inf")
        if moves.all():
            return float(self.amplitudes[0])
        last_still = np.flatnonzero(~moves)[-1]
        if last_still + 1 >= moves.size:
            return float("inf")
        return float(self.amplitudes[last_still + 1])

    @property
    def fraction(self) -> float:
        """Dead zone as a fraction of the maximum torque [-]."""
        return self.dead_zone / self.max_torque

    @property
    def at_grid_floor(self) -> bool:
        """Even the smallest amplitude tried moved the joint: :attr:`dead_zone` is an upper
        bound (the true dead zone is at most that), and a reduction factor a lower bound."""
        return bool(self.counts[0] > self.threshold_counts)


def dead_zone(params: ActuatorParams, compensator: Compensator | None = None, *,
              friction: FrictionModel | None = None, amplitudes=None, frequency: float = 1.0,
              periods: float = 2.0, threshold_counts: int = 3, keep_results: bool = False,
              delay: int = 0, noise_std: float = 0.0, rng: np.random.Generator | None = None) -> DeadZone:
    """Measure the torque dead zone with open-loop sinusoidal control torques.

    One run per amplitude (a batch), each ``periods`` periods of
    ``Tc = A*sin(2*pi*f*t)``; the joint "moves" at amplitude A when its encoder
    spans more than ``threshold_counts`` counts.

    Parameters
    ----------
    params : ActuatorParams
    compensator : Compensator, optional
        Default: none.
    friction : FrictionModel, optional
    amplitudes : array_like, optional
        Increasing amplitudes [N*m]; default 200 levels from 0.25 % to 20 % of Tmax.
    frequency : float
        [Hz].
    periods : float
        Periods per run.
    threshold_counts : int
        "A few encoder counts".
    keep_results : bool
        Keep every run in ``results``.
    delay : int
        Extra samples before the joint receives the torque
        (:func:`~fricctl.simulate.simulate_batch`) [-].
    noise_std : float
        White torque noise at the joint [N*m] (needs ``rng``).
    rng : numpy.random.Generator, optional
    """
    params = _params(params)
    comp = NoCompensation() if compensator is None else compensator
    amps = (np.linspace(0.0025, 0.2, 200) * params.max_torque if amplitudes is None
            else np.asarray(amplitudes, dtype=float))
    if amps.ndim != 1 or amps.size < 2 or np.any(np.diff(amps) <= 0) or np.any(amps <= 0):
        raise ValueError("amplitudes must be a 1-D increasing array of positive torques")
    ctrls = [open_loop(sinusoid(float(a), frequency)) for a in amps]
    batch = simulate_batch(params, ctrls, comp, duration=periods / frequency, friction=friction,
                           delay=delay, noise_std=noise_std, rng=rng)
    counts = np.round(np.ptp(batch.q_meas, axis=1) / params.encoder_resolution).astype(int)
    results = tuple(batch[i] for i in range(len(batch))) if keep_results else ()
    return DeadZone(amplitudes=amps, counts=counts, threshold_counts=int(threshold_counts),
                    max_torque=params.max_torque, compensator=comp.name, results=results)


@dataclass(frozen=True, kw_only=True)
class DeadZonePrediction:
    """Dead zone of the compensated loop predicted from the estimator alone [N*m]."""

    positive: float
    """Control torque the loop needs to break loose forward (a magnitude) [N*m]."""
    negative: float
    """The same backward (a magnitude) [N*m]."""

    @property
    def largest(self) -> float:
        """The larger of the two directions [N*m]."""
        return max(self.positive, self.negative)


def predicted_dead_zone(estimator, breakaway: float, *, scale: float = 1.0,
                        n: int = 2001) -> DeadZonePrediction:
    """Dead zone the compensated loop should show, from the estimator alone [N*m].

    At rest the encoder does not move, so ``omega_hat = 0`` and the loop iterates
    ``Tm(k+1) = Tc + s*T^at(Tm(k), 0)``.  For a slowly varying ``Tc`` it climbs
    to the first fixed point; the joint breaks loose only if no fixed point lies
    below the breakaway torque Fs, i.e. when

        Tc > max_{0 <= Tm <= Fs} (Tm - s*T^at(Tm, 0)).

    That maximum is the predicted dead zone (per direction).  For a linear
    estimate ``T^at = g*Tm`` near rest it is ``Fs*(1 - s*g)``: a reduction by
    ``1/(1 - s*g)``; with ``s*g >= 1`` it goes to zero (the loop winds the torque
    up like an integrator).

    Returns
    -------
    DeadZonePrediction
        Predicted dead zones for the two directions, positive magnitudes [N*m].
    """
    if not callable(estimator):
        raise ValueError(f"estimator must be a function (tm, omega) -> friction, e.g. a "
                         f"FrictionNet, got {type(estimator).__name__}")
    breakaway = v.real("breakaway", breakaway, positive=True, unit="N*m")
    tm = np.linspace(0.0, breakaway, n)
    pos = float(np.max(tm - scale * np.asarray(estimator(tm, np.zeros(n)))))
    neg = float(np.max(tm + scale * np.asarray(estimator(-tm, np.zeros(n)))))
    return DeadZonePrediction(positive=max(pos, 0.0), negative=max(neg, 0.0))
