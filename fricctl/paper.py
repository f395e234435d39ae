"""The paper's experiments on the virtual bench, and its claims checked by numbers.

Gervini, Gomes & da Rosa (2003) show their results in Figs. 4-18.  Each
``figN(network)`` below re-runs the experiment of figure N on the virtual bench
(deterministic: every random draw comes from ``network.seed``) and returns a
frozen result; :mod:`fricctl.figures.paper` draws it.  All figures share one
trained network, :func:`train_paper_network` (the paper's pipeline run once:
Table-2-style experiments -> friction patterns with the paper's polynomial
velocity estimator -> 2-4-1 network).

:func:`paper_claims` turns the results into :class:`Claim` rows: the paper's
words, the paper's value, the value measured here and pass/fail, each with an
explicit tolerance in its text.  A claim that the bench does not reproduce is
reported as failing, with the physical reason in ``note``; nothing is tuned to
make a claim pass.  :func:`robustness_sweep` maps where NN compensation keeps
the PD steady-state error below 0.3 deg over friction scale and link inertia.
:func:`reproduce_paper` runs everything (``fricctl reproduce``).

Assumptions (the paper does not give these; labelled as such in the results):

* Fig. 9: sinusoidal torque of 1.1 x the breakaway level Fs, 0.5 Hz, 4 s;
* Fig. 16: step of 30 deg; the aged actuator is the bench's true friction x 0.95
  (the paper lowers the compensation scale to s = 0.95 after 30 h of wear
  without retraining); the Coulomb compensator is the nominal Coulomb level
  with the same s = 0.95;
* Fig. 17 runs on the same aged actuator and compensation as Fig. 16;
* Fig. 18: sawtooth period 1 s (two periods).

Notes
-----
The bench is the simulator of :mod:`fricctl.simulate` with the paper actuator of
:mod:`fricctl.params`; it has no measurement noise, no torque ripple and no
thermal drift unless asked for.  Claims about the real hardware (e.g. "after
30 h of operation") are modelled, not measured.
"""

from __future__ import annotations

import functools
import json
import math
import warnings
from concurrent.futures import Executor
from dataclasses import asdict, dataclass, field
from typing import Callable

import numpy as np

from . import controllers as ctl
from .compensators import CoulombCompensator, NNCompensator, NoCompensation
from .design import Design, DesignWarning, linear_response, paper_designs
from .estimation import DerivativeEstimate, backward_difference, estimate
from .friction import FrictionModel
from .bench.experiments import (DeadZone, DeadZonePrediction, Experiment, Patterns, dead_zone, friction_patterns,
                          predicted_dead_zone, train_network, training_experiments, true_patterns)
from .nn import FitReport, FrictionNet, TrainingResult, fit_report
from .params import ActuatorParams, paper_actuator
from .simulate import SimResult, simulate, simulate_batch

__all__ = [
    "PaperNetwork", "train_paper_network",
    "Fig4Result", "Fig5Result", "Fig8Result", "Fig9Result", "Fig10Result", "Fig11Result",
    "Fig12Result", "Fig13Result", "Fig14Result", "Fig16Result", "Fig17Result", "Fig18Result",
    "fig4", "fig5", "fig8", "fig9", "fig10", "fig11", "fig12", "fig13", "fig14", "fig16",
    "fig17", "fig18", "FIGURES",
    "ViscousExcluded", "SweepResult", "robustness_sweep",
    "Claim", "paper_claims", "claims_markdown", "claims_json",
    "PaperResults", "reproduce_paper",
    "ACCURACY_DEG", "STICK_MIN_DURATION", "AGED_SCALE",
]

#: The paper's steady-state accuracy, Fig. 14 ("less than 0.3 deg") [deg].
ACCURACY_DEG = 0.3
#: A rest shorter than this is a velocity reversal, not a stick interval [s].
STICK_MIN_DURATION = 0.02
#: Compensation scale of the aged actuator (Fig. 16), and its assumed friction change [-].
AGED_SCALE = 0.95
#: Window at the end of a run over which steady state is measured [s].
_SS_WINDOW = 0.5


@functools.lru_cache(maxsize=8)
def _designs(params: ActuatorParams) -> dict[str, Design]:
    # Cached: each design verifies itself on fine grids (~0.2 s); Designs are immutable.
    # The PD (0.3 s, 0.9) design warns that its sampled 0-100 % rise time is
    # ill-conditioned near zeta = 1 (expected; Chapter 6 explains it).
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DesignWarning)
        return paper_designs(params)


# --------------------------------------------------------------------------
# the shared network
# --------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class PaperNetwork:
    """The paper's pipeline run once: experiments, patterns, trained network, fit.

    Attributes
    ----------
    params : the actuator (no link) [-]
    experiments : the training experiments (records and truth)
    patterns : all friction patterns ``Tat = Tm - I*alpha_hat``
    train, held_out : random split of the patterns (``train_fraction`` / rest)
    training : the trainer's result (``.net``, ``.history``)
    fit_held_out : fit of the net on the held-out measured patterns
    fit_train : fit on the training patterns
    fit_true : fit on the held-out patterns against the simulator's *true* friction
    seed : seed of the split and of the trainer
    fast : whether the short experiments were used
    """

    params: ActuatorParams
    experiments: tuple
    patterns: Patterns
    train: Patterns
    held_out: Patterns
    training: TrainingResult
    fit_held_out: FitReport
    fit_train: FitReport
    fit_true: FitReport
    seed: int
    fast: bool

    @property
    def net(self) -> FrictionNet:
        """The trained 2-4-1 network."""
        return self.training.net

    def experiment(self, name: str) -> Experiment:
        """The training experiment called ``name`` (e.g. ``"open-loop steps"``)."""
        for ex in self.experiments:
            if ex.name == name:
                return ex
        raise ValueError(f"no experiment named {name!r}; have {[e.name for e in self.experiments]}")


def _check_seed(seed):
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed must be an integer >= 0, got {seed!r}")
    return int(seed)


def train_paper_network(params: ActuatorParams | None = None, *, fast: bool = False, seed: int = 0,
                        train_fraction: float = 0.8, estimator: str = "polynomial_segments",
                        **estimator_options) -> PaperNetwork:
    """Run the paper's training pipeline once (shared by every figure).

    Parameters
    ----------
    params : ActuatorParams, optional
        The actuator without link; default :func:`~fricctl.params.paper_actuator`.
    fast : bool
        Short experiments (8 torque levels, 6 closed-loop steps) for tests.
    seed : int
        Seed of the train/held-out split and of the trainer [-].
    train_fraction : float
        Fraction of the patterns used for training; the rest measure the fit [-].
    estimator : str
        Velocity/acceleration estimator of the patterns (the paper's by default).
    **estimator_options
        Passed to the estimator (e.g. ``window=100``).

    Returns
    -------
    PaperNetwork

    Notes
    -----
    Training uses the CasADi Levenberg-Marquardt trainer (3 seeded restarts, at
    most 4000 patterns); the paper's back-propagation reaches a similar loss far
    more slowly (Chapter 4 compares them).
    """
    p = paper_actuator() if params is None else params
    if not isinstance(p, ActuatorParams):
        raise ValueError(f"params must be an ActuatorParams, got {type(p).__name__}")
    seed = _check_seed(seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DesignWarning)
        exps = training_experiments(p, fast=fast)
    pats = friction_patterns(exps, p, method=estimator, **estimator_options)
    train, held = pats.split(train_fraction, np.random.default_rng(seed))
    res = train_network(train, rng=np.random.default_rng(seed))
    net = res.net
    return PaperNetwork(
        params=p, experiments=tuple(exps), patterns=pats, train=train, held_out=held, training=res,
        fit_held_out=fit_report(held.friction, net=net, tm=held.tm, omega=held.omega),
        fit_train=fit_report(train.friction, net=net, tm=train.tm, omega=train.omega),
        fit_true=fit_report(held.friction_true, net=net, tm=held.tm, omega=held.omega),
        seed=seed, fast=bool(fast))


def _check_network(network):
    if not isinstance(network, PaperNetwork):
        raise ValueError(f"network must be a PaperNetwork (train_paper_network), got "
                         f"{type(network).__name__}")
    return network


# --------------------------------------------------------------------------
# small measurements shared by several figures
# --------------------------------------------------------------------------
def stick_intervals_after_motion(result: SimResult, min_duration: float = STICK_MIN_DURATION):
    """Rest intervals of at least ``min_duration`` [s] that start after the joint first moved."""
    moving = np.flatnonzero(~result.stuck)
    if moving.size == 0:
        return []
    t0 = result.t[moving[0]]
    return [iv for iv in result.stuck_intervals(min_duration) if iv[0] > t0]


def restarts(result: SimResult, min_duration: float = STICK_MIN_DURATION) -> int:
    """Stick-slip cycles: rests of at least ``min_duration`` after first motion that end in motion."""
    end = result.t[-1]
    return sum(1 for a, b in stick_intervals_after_motion(result, min_duration) if b < end)


def sign_changes(x, *, tol: float = 0.0) -> int:
    """Number of sign changes of ``x`` (values with ``|x| <= tol`` are skipped)."""
    x = np.asarray(x, dtype=float)
    s = np.sign(x[np.abs(x) > tol])
    return int(np.count_nonzero(s[1:] != s[:-1]))


def _tail(result: SimResult, window: float = _SS_WINDOW):
    return result.t >= result.t[-1] - window + 1e-12


# --------------------------------------------------------------------------
# Fig. 4 and 5: measuring the patterns
# --------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class Fig4Result:
    """Fig. 4: raw (backward-difference) against filtered velocity, with the truth.

    Attributes
    ----------
    raw, filtered : estimates over the window shown [rad/s]
    truth_velocity : the simulator's velocity on the same samples [rad/s]
    raw_rms, filtered_rms : RMS velocity error over the window [rad/s]
    experiment : which training record
    """

    raw: DerivativeEstimate
    filtered: DerivativeEstimate
    truth_velocity: np.ndarray
    raw_rms: float
    filtered_rms: float
    experiment: str


def _window(est: DerivativeEstimate, sel) -> DerivativeEstimate:
    return DerivativeEstimate(t=est.t[sel], position=est.position[sel], velocity=est.velocity[sel],
                              acceleration=est.acceleration[sel], method=est.method)


def fig4(network: PaperNetwork, *, window: tuple[float, float] = (0.0, 1.0)) -> Fig4Result:
    """Raw vs filtered velocity of the first second of the PD training record (Fig. 4)."""
    net = _check_network(network)
    ex = net.experiment("PD steps")
    raw = backward_difference(ex.run.t, ex.run.position)
    filt = estimate(ex.run.t, ex.run.position, net.patterns.method)
    sel = (ex.run.t >= window[0]) & (ex.run.t <= window[1])
    if np.count_nonzero(sel) < 2:
        raise ValueError(f"window {window} s holds fewer than 2 samples")
    truth = ex.truth.omega[sel]
    rms = [float(np.sqrt(np.mean((e.velocity[sel] - truth) ** 2))) for e in (raw, filt)]
    return Fig4Result(_window(raw, sel), _window(filt, sel), truth.copy(), rms[0], rms[1], ex.name)


@dataclass(frozen=True, eq=False)
class Fig5Result:
    """Fig. 5: the open-loop training torque sequence and the measured friction.

    Attributes
    ----------
    t : time [s]
    torque : motor torque Tm [N*m]
    friction : patterns ``Tm - I*alpha_hat`` [N*m]
    friction_true : the simulator's friction [N*m]
    max_torque : Tmax [N*m]
    """

    t: np.ndarray
    torque: np.ndarray
    friction: np.ndarray
    friction_true: np.ndarray
    max_torque: float


def fig5(network: PaperNetwork) -> Fig5Result:
    """Torque steps of growing amplitude and the friction patterns they give (Fig. 5)."""
    net = _check_network(network)
    i = [e.name for e in net.experiments].index("open-loop steps")
    pats = net.patterns.subset(net.patterns.experiment == i)
    return Fig5Result(pats.t, pats.tm, pats.friction, pats.friction_true, net.params.max_torque)


# --------------------------------------------------------------------------
# Fig. 8: the network against the patterns
# --------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class Fig8Result:
    """Fig. 8: measured ("experimental") against network friction, held-out patterns.

    Attributes
    ----------
    target : held-out friction patterns [N*m]
    predicted : network estimate on them [N*m]
    fit_held_out, fit_train, fit_true : see :class:`PaperNetwork`
    gain_at_rest : ``dTat_hat/dTm`` at rest [-]
    fit_exact : held-out fit of the same network trained, with the same split and seed,
        on exact patterns (the simulator's true velocity and friction): what a perfect
        measuring chain would allow
    """

    target: np.ndarray
    predicted: np.ndarray
    fit_held_out: FitReport
    fit_train: FitReport
    fit_true: FitReport
    gain_at_rest: float
    fit_exact: FitReport


def fig8(network: PaperNetwork) -> Fig8Result:
    """The trained network on the held-out patterns (Fig. 8)."""
    net = _check_network(network)
    ho = net.held_out
    exact = true_patterns(net.experiments)
    # same permutation as the measured patterns' split (same length, same seed)
    train_e, held_e = exact.split(len(net.train) / len(net.patterns), np.random.default_rng(net.seed))
    net_e = train_network(train_e, rng=np.random.default_rng(net.seed)).net
    fit_exact = fit_report(held_e.friction, net_e(held_e.tm, held_e.omega))
    return Fig8Result(ho.friction, net.net(ho.tm, ho.omega), net.fit_held_out, net.fit_train,
                      net.fit_true, net.net.gain_at_rest(), fit_exact)


# --------------------------------------------------------------------------
# Fig. 9 and 10: open-loop compensation, the dead zone
# --------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class Fig9Result:
    """Fig. 9: open-loop sinusoidal torque near breakaway, without and with NN compensation.

    Attributes
    ----------
    without, with_nn : the two runs
    amplitude : control torque amplitude [N*m]
    frequency : [Hz]
    sticks_without, sticks_with : rests >= STICK_MIN_DURATION after first motion, (start, end) [s]
    peak_speed_without, peak_speed_with : max |omega| [rad/s]
    """

    without: SimResult
    with_nn: SimResult
    amplitude: float
    frequency: float
    sticks_without: list
    sticks_with: list
    peak_speed_without: float
    peak_speed_with: float


def fig9(network: PaperNetwork, *, amplitude_factor: float = 1.1, frequency: float = 0.5,
         duration: float = 4.0) -> Fig9Result:
    """Open-loop sinusoid of ``amplitude_factor * Fs`` without and with compensation (Fig. 9)."""
    net = _check_network(network)
    p = net.params
    amp = amplitude_factor * p.static
    c = ctl.open_loop(ctl.sinusoid(amp, frequency))
    r0 = simulate(p, c, NoCompensation(), duration=duration)
    r1 = simulate(p, c, NNCompensator(net.net), duration=duration)
    return Fig9Result(r0, r1, amp, frequency, stick_intervals_after_motion(r0),
                      stick_intervals_after_motion(r1), float(np.abs(r0.omega).max()),
                      float(np.abs(r1.omega).max()))


@dataclass(frozen=True, eq=False)
class Fig10Result:
    """Fig. 10: sinusoid at 10 % of Tmax (inside the dead zone), and the dead zone itself.

    Attributes
    ----------
    without, with_nn : open-loop runs at 10 % of Tmax
    dead_zone_without, dead_zone_with : measured dead zones (sinusoid batches)
    predicted : dead zone predicted from the net alone (DeadZonePrediction) [N*m]
    gain_at_rest : g of the net [-]
    """

    without: SimResult
    with_nn: SimResult
    dead_zone_without: DeadZone
    dead_zone_with: DeadZone
    predicted: DeadZonePrediction
    gain_at_rest: float

    @property
    def factor(self) -> float:
        """Dead-zone reduction factor, without / with compensation [-]."""
        return self.dead_zone_without.dead_zone / self.dead_zone_with.dead_zone

    @property
    def predicted_factor(self) -> float:
        """Breakaway level over the larger predicted dead zone [-]."""
        dz = self.predicted.largest
        fs = float(self.without.info.params.static)
        return fs / dz if dz > 0 else math.inf


def fig10(network: PaperNetwork, *, fraction: float = 0.10, frequency: float = 1.0,
          duration: float = 3.0) -> Fig10Result:
    """Control vs motor torque at 10 % of Tmax with compensation, and the dead zones (Fig. 10)."""
    net = _check_network(network)
    p = net.params
    c = ctl.open_loop(ctl.sinusoid(fraction * p.max_torque, frequency))
    nn = NNCompensator(net.net)
    return Fig10Result(simulate(p, c, NoCompensation(), duration=duration),
                       simulate(p, c, nn, duration=duration), dead_zone(p), dead_zone(p, nn),
                       predicted_dead_zone(net.net, p.static), net.net.gain_at_rest())


# --------------------------------------------------------------------------
# Figs. 11-14: P and PD steps on the actuator
# --------------------------------------------------------------------------
@dataclass(frozen=True)
class ViscousExcluded:
    """Estimator ``net(Tm, omega) - b*omega``: compensate only what the linear design left out.

    Not the paper's compensation (an extra of Fig. 12): the P design counts on the
    viscous term b for all its damping, so this estimator leaves it in the loop.
    """

    net: FrictionNet
    viscous: float

    def __call__(self, tm, omega):
        return self.net(tm, omega) - self.viscous * np.asarray(omega, dtype=float)


@dataclass(frozen=True, eq=False)
class IdealEstimate:
    """The best any static estimator could do on the bench: its exact friction while sliding,
    ``Tat = Tm`` at rest (the stuck pattern, g = 1); optionally without the viscous term.

    An extra of Fig. 12 that separates the two suspects of the P loop's behaviour:
    the network's errors, and the compensation scheme itself.
    """

    friction: FrictionModel
    viscous: float = 0.0

    def __call__(self, tm, omega):
        w = np.asarray(omega, dtype=float)
        tm = np.asarray(tm, dtype=float)
        return np.where(w == 0.0, tm, self.friction.torque(w) - self.viscous * w)


@dataclass(frozen=True, eq=False)
class Fig11Result:
    """Fig. 11: P step of 25 deg without compensation.

    Attributes
    ----------
    run : the run
    linear : linear viscous prediction on the same grid [rad]
    design : the P design (0.2 s, 0.3)
    steady_state_error : mean r - q over the last 0.5 s [rad]
    stuck_fraction : fraction of samples at rest [-]
    """

    run: SimResult
    linear: np.ndarray
    design: Design
    steady_state_error: float
    stuck_fraction: float


def _step_run(p, design, step_rad, comp, duration, friction=None):
    c = ctl.pd_control(design.kp, design.kd, ctl.step(step_rad)) if design.kd > 0 else \
        ctl.p_control(design.kp, ctl.step(step_rad))
    r = simulate(p, c, comp, duration=duration, friction=friction)
    return r, linear_response(design, r.t, r.reference, sampled=True)


def fig11(network: PaperNetwork, *, step_deg: float = 25.0, duration: float = 3.0) -> Fig11Result:
    """P step without compensation (Fig. 11)."""
    net = _check_network(network)
    d = _designs(net.params)["fig11-12"]
    r, lin = _step_run(net.params, d, np.deg2rad(step_deg), NoCompensation(), duration)
    return Fig11Result(r, lin, d, r.steady_state_error(_SS_WINDOW), float(np.mean(r.stuck)))


@dataclass(frozen=True, eq=False)
class Fig12Result:
    """Fig. 12: P step of 25 deg with full NN compensation, and the linear prediction.

    Attributes
    ----------
    run : with the paper's compensation ``s*net(Tm, omega_hat)``
    linear : linear viscous prediction [rad]
    design : the P design
    max_deviation : max |q - q_linear| [rad]
    growth : peak |r - q| in the last second over peak in the first second [-]
        (> 1: a growing oscillation)
    variant : run with :class:`ViscousExcluded` (extra, not in the paper)
    variant_max_deviation : max |q - q_linear| of the variant [rad]
    ideal, ideal_no_viscous : runs with :class:`IdealEstimate`, full and without the
        viscous term (extras, not in the paper)
    ideal_growth : growth of the ``ideal`` run [-]
    ideal_max_deviation : max |q - q_linear| of ``ideal`` [rad]
    ideal_no_viscous_max_deviation : max |q - q_linear| of ``ideal_no_viscous`` [rad]
    variant_growth : growth of the ``variant`` run [-]
    """

    run: SimResult
    linear: np.ndarray
    design: Design
    max_deviation: float
    growth: float
    variant: SimResult
    variant_max_deviation: float
    ideal: SimResult
    ideal_no_viscous: SimResult
    ideal_growth: float
    ideal_no_viscous_max_deviation: float
    ideal_max_deviation: float
    variant_growth: float


def _growth(r: SimResult) -> float:
    e = np.abs(r.error)
    first = e[r.t <= 1.0].max()
    return float(e[r.t >= r.t[-1] - 1.0].max() / first) if first > 0 else math.inf


def fig12(network: PaperNetwork, *, step_deg: float = 25.0, duration: float = 3.0) -> Fig12Result:
    """P step with NN compensation, against the linear viscous simulation (Fig. 12)."""
    net = _check_network(network)
    p = net.params
    d = _designs(p)["fig11-12"]
    r, lin = _step_run(p, d, np.deg2rad(step_deg), NNCompensator(net.net), duration)
    v, _ = _step_run(p, d, np.deg2rad(step_deg), NNCompensator(ViscousExcluded(net.net, p.viscous)),
                     duration)
    fm = p.friction_model()
    ideal, _ = _step_run(p, d, np.deg2rad(step_deg), NNCompensator(IdealEstimate(fm)), duration)
    ideal_nv, _ = _step_run(p, d, np.deg2rad(step_deg), NNCompensator(IdealEstimate(fm, p.viscous)),
                            duration)
    return Fig12Result(r, lin, d, float(np.abs(r.q - lin).max()), _growth(r), v,
                       float(np.abs(v.q - lin).max()), ideal, ideal_nv, _growth(ideal),
                       float(np.abs(ideal_nv.q - lin).max()), float(np.abs(ideal.q - lin).max()),
                       _growth(v))


@dataclass(frozen=True, eq=False)
class Fig13Result:
    """Fig. 13: PD step of 30 deg without compensation; the net's view of the residual torque.

    Attributes
    ----------
    run, linear, design : the run, the linear prediction [rad], the PD (0.3 s, 0.9)
    steady_state_error : [rad]
    torque_at_rest : motor torque held at the end [N*m]
    nn_at_rest : ``net(torque_at_rest, 0)``: the net's friction estimate there [N*m]
    nn_rmse : held-out RMSE of the net (its own accuracy) [N*m]
    """

    run: SimResult
    linear: np.ndarray
    design: Design
    steady_state_error: float
    torque_at_rest: float
    nn_at_rest: float
    nn_rmse: float


def fig13(network: PaperNetwork, *, step_deg: float = 30.0, duration: float = 3.0) -> Fig13Result:
    """PD step without compensation; residual motor torque against the NN estimate (Fig. 13)."""
    net = _check_network(network)
    d = _designs(net.params)["fig13-14"]
    r, lin = _step_run(net.params, d, np.deg2rad(step_deg), NoCompensation(), duration)
    tm = float(r.torque_motor[-1])
    return Fig13Result(r, lin, d, r.steady_state_error(_SS_WINDOW), tm, float(net.net(tm, 0.0)),
                       net.fit_held_out.rmse)


@dataclass(frozen=True, eq=False)
class Fig14Result:
    """Fig. 14: PD step of 30 deg with NN compensation.

    Attributes
    ----------
    run, linear, design : as Fig. 13
    steady_state_error : [rad]
    predicted_band : larger predicted residual dead zone over Kp: where the
        compensated joint may stop [rad]
    """

    run: SimResult
    linear: np.ndarray
    design: Design
    steady_state_error: float
    predicted_band: float


def fig14(network: PaperNetwork, *, step_deg: float = 30.0, duration: float = 3.0) -> Fig14Result:
    """PD step with NN compensation (Fig. 14)."""
    net = _check_network(network)
    p = net.params
    d = _designs(p)["fig13-14"]
    r, lin = _step_run(p, d, np.deg2rad(step_deg), NNCompensator(net.net), duration)
    band = predicted_dead_zone(net.net, p.static).largest / d.kp
    return Fig14Result(r, lin, d, r.steady_state_error(_SS_WINDOW), band)


# --------------------------------------------------------------------------
# Figs. 16-18: the actuator with the link
# --------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class Fig16Result:
    """Fig. 16: aged actuator with link, PD (0.4 s, 0.85): NN x 0.95, Coulomb, none.

    Attributes
    ----------
    runs : ``{"none", "NN x 0.95", "Coulomb"}`` -> run
    design : the PD design with the link
    step : reference step [rad]
    friction_scale : true friction of the aged actuator / nominal [-] (assumption)
    steady_state_error : per run, mean r - q over the last 0.5 s [rad]
    reference_crossings : per run, sign changes of r - q after the step [-]
    torque_sign_changes : per run, sign changes of Tm over the last 0.5 s [-]
    """

    runs: dict
    design: Design
    step: float
    friction_scale: float
    steady_state_error: dict
    reference_crossings: dict
    torque_sign_changes: dict


def _link_runs(net: PaperNetwork, design_key: str, reference, duration, friction_scale, scale):
    p = net.params.with_link()
    d = _designs(net.params)[design_key]
    comps = {"none": NoCompensation(),
             f"NN x {scale:g}": NNCompensator(net.net, scale=scale),
             "Coulomb": CoulombCompensator.symmetric(net.params.coulomb, scale=scale)}
    fr = p.friction_model().scaled(friction_scale)
    c = ctl.pd_control(d.kp, d.kd, reference)
    # one run each: a batch mixing compensator kinds would fall back to the Python loop
    return {k: simulate(p, c, comp, duration=duration, friction=fr) for k, comp in comps.items()}, d


def fig16(network: PaperNetwork, *, step_deg: float = 30.0, duration: float = 3.0,
          friction_scale: float = AGED_SCALE, scale: float = AGED_SCALE) -> Fig16Result:
    """Aged actuator with link: NN x 0.95 (no retraining) vs Coulomb vs none (Fig. 16)."""
    net = _check_network(network)
    step_rad = float(np.deg2rad(step_deg))
    runs, d = _link_runs(net, "fig16-17", ctl.step(step_rad), duration, friction_scale, scale)
    tol = net.params.encoder_resolution
    return Fig16Result(
        runs, d, step_rad, friction_scale,
        {k: r.steady_state_error(_SS_WINDOW) for k, r in runs.items()},
        {k: sign_changes(r.error[r.t > 0], tol=tol) for k, r in runs.items()},
        {k: sign_changes(r.torque_motor[_tail(r)]) for k, r in runs.items()})


@dataclass(frozen=True, eq=False)
class Fig17Result:
    """Fig. 17: small step of 0.08 rad, same actuator and compensation as Fig. 16.

    Attributes
    ----------
    runs : ``{"none", "NN x 0.95", "Coulomb"}`` -> run
    step : [rad]
    steady_state_error : per run [rad]
    max_motion : per run, peak |q| [rad]
    """

    runs: dict
    design: Design
    step: float
    steady_state_error: dict
    max_motion: dict


def fig17(network: PaperNetwork, *, step: float = 0.08, duration: float = 3.0,
          friction_scale: float = AGED_SCALE, scale: float = AGED_SCALE) -> Fig17Result:
    """Step of 0.08 rad with the link, without and with compensation (Fig. 17)."""
    net = _check_network(network)
    runs, d = _link_runs(net, "fig16-17", ctl.step(step), duration, friction_scale, scale)
    return Fig17Result(runs, d, float(step),
                       {k: r.steady_state_error(_SS_WINDOW) for k, r in runs.items()},
                       {k: float(np.abs(r.q).max()) for k, r in runs.items()})


@dataclass(frozen=True, eq=False)
class Fig18Result:
    """Fig. 18: sawtooth of 0.1 rad, PD (0.22 s, 0.5) with the link, without and with NN.

    Attributes
    ----------
    without, with_nn : the runs
    linear : linear viscous prediction [rad]
    amplitude, period : sawtooth [rad], [s]
    restarts_without : stick-slip cycles without compensation [-]
    max_motion_without : peak |q| without compensation [rad]
    rms_deviation_with : RMS of q - q_linear with compensation [rad]
    extra_without : a larger, slower sawtooth (extra, not in the paper) without compensation
    extra_amplitude, extra_period : [rad], [s]
    extra_restarts : its stick-slip cycles [-]
    """

    without: SimResult
    with_nn: SimResult
    linear: np.ndarray
    design: Design
    amplitude: float
    period: float
    restarts_without: int
    max_motion_without: float
    rms_deviation_with: float
    extra_without: SimResult
    extra_amplitude: float
    extra_period: float
    extra_restarts: int


def fig18(network: PaperNetwork, *, amplitude: float = 0.1, period: float = 1.0, periods: int = 2,
          extra_amplitude: float = 0.5, extra_period: float = 8.0) -> Fig18Result:
    """Sawtooth tracking without and with NN compensation (Fig. 18), plus a stick-slip extra."""
    net = _check_network(network)
    p = net.params.with_link()
    d = _designs(net.params)["fig18"]
    c = ctl.pd_control(d.kp, d.kd, ctl.sawtooth(amplitude, period))
    r0 = simulate(p, c, NoCompensation(), duration=periods * period)
    r1 = simulate(p, c, NNCompensator(net.net), duration=periods * period)
    lin = linear_response(d, r1.t, r1.reference, sampled=True)
    ce = ctl.pd_control(d.kp, d.kd, ctl.sawtooth(extra_amplitude, extra_period))
    rx = simulate(p, ce, NoCompensation(), duration=extra_period)
    return Fig18Result(r0, r1, lin, d, float(amplitude), float(period), restarts(r0),
                       float(np.abs(r0.q).max()), float(np.sqrt(np.mean((r1.q - lin) ** 2))),
                       rx, float(extra_amplitude), float(extra_period), restarts(rx))


#: Figure number -> experiment function.
FIGURES: dict[int, Callable] = {4: fig4, 5: fig5, 8: fig8, 9: fig9, 10: fig10, 11: fig11, 12: fig12,
                                13: fig13, 14: fig14, 16: fig16, 17: fig17, 18: fig18}


# --------------------------------------------------------------------------
# robustness sweep
# --------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class SweepResult:
    """Steady-state error of the PD step over friction scale x link inertia.

    Attributes
    ----------
    friction_scales : true friction / nominal [-], shape (S,)
    link_inertias : [kg*m^2], shape (L,)
    error_nn : |steady-state error| with NN compensation [rad], shape (L, S)
    error_none : without compensation [rad], shape (L, S)
    tolerance : the accuracy asked for [rad]
    step : reference step [rad]
    kp, kd : the gains used (fixed: the controller is not redesigned) [N*m/rad], [N*m*s/rad]
    compensation_scale : s [-]
    """

    friction_scales: np.ndarray
    link_inertias: np.ndarray
    error_nn: np.ndarray
    error_none: np.ndarray
    tolerance: float
    step: float
    kp: float
    kd: float
    compensation_scale: float

    @property
    def within(self) -> np.ndarray:
        """Where NN compensation meets the tolerance, shape (L, S) [bool]."""
        return self.error_nn < self.tolerance

    def report(self) -> str:
        """A table of |e_ss| [deg] with NN compensation (* marks >= tolerance)."""
        head = "J_link [kg*m^2] | " + " | ".join(f"x{s:.2f}" for s in self.friction_scales)
        rows = [f"|e_ss| [deg] with NN compensation, step {np.rad2deg(self.step):.1f} deg, "
                f"tolerance {np.rad2deg(self.tolerance):.2f} deg (* = not met)", head]
        for i, j in enumerate(self.link_inertias):
            cells = [f"{np.rad2deg(e):.3f}{'*' if not ok else ''}"
                     for e, ok in zip(self.error_nn[i], self.within[i])]
            rows.append(f"{j:.4f} | " + " | ".join(cells))
        rows.append(f"met in {int(self.within.sum())} of {self.within.size} cases")
        return "\n".join(rows)


def _sweep_row(params: ActuatorParams, net_json: str, scales: tuple, kp: float, kd: float,
               step: float, duration: float, comp_scale: float, simulator) -> tuple:
    # Module-level and fed plain data (the net as JSON) so that any Executor,
    # including a process pool or a dask client, can run it.
    net = FrictionNet.from_json(net_json)
    base = params.friction_model()
    frs = [base.scaled(float(s)) for s in scales]
    c = ctl.pd_control(kp, kd, ctl.step(step))
    nn = simulator(params, c, NNCompensator(net, scale=comp_scale), duration=duration, friction=frs)
    none = simulator(params, c, NoCompensation(), duration=duration, friction=frs)
    return (np.abs(nn.steady_state_error(_SS_WINDOW)), np.abs(none.steady_state_error(_SS_WINDOW)))


def robustness_sweep(net: FrictionNet, params: ActuatorParams | None = None, *,
                     friction_scales=(0.8, 0.9, 1.0, 1.1, 1.2),
                     link_inertias=(0.0, 0.0023, 0.0046, 0.0069, 0.0092),
                     step: float = float(np.deg2rad(30.0)), duration: float = 3.0,
                     design: Design | None = None, compensation_scale: float = 1.0,
                     tolerance: float = float(np.deg2rad(ACCURACY_DEG)),
                     executor: Executor | None = None, simulator=simulate_batch) -> SweepResult:
    """Where NN compensation keeps the PD steady-state error below ``tolerance``.

    For every link inertia (one job: a batch over the friction scales) the PD
    step is simulated with the net trained on the nominal actuator (not
    retrained) and without compensation.

    Parameters
    ----------
    net : FrictionNet
        Trained on the nominal actuator.
    params : ActuatorParams, optional
        The nominal actuator (its ``link_inertia`` is replaced by each sweep value).
    friction_scales : sequence of float
        True friction / nominal friction [-], > 0.
    link_inertias : sequence of float
        Link inertias [kg*m^2], >= 0.
    step : float
        Reference step [rad].
    duration : float
        Run length [s]; steady state is the mean over its last 0.5 s.
    design : Design, optional
        Fixed gains; default the paper's Fig. 16-17 PD (0.4 s, 0.85, with the
        0.0046 kg*m^2 link): a different load is *not* redesigned for.
    compensation_scale : float
        s of the compensator [-].
    tolerance : float
        Accuracy asked for [rad] (default the paper's 0.3 deg).
    executor : concurrent.futures.Executor, optional
        Runs the rows (``executor.submit``); e.g. a ``ProcessPoolExecutor`` or a
        ``dask.distributed.Client``'s executor.  Default: in this process.  A
        process pool must use the ``"spawn"`` start method
        (``mp_context=multiprocessing.get_context("spawn")``): forking a process
        whose numba/OpenMP threads have started aborts the workers.
    simulator : callable
        Batch simulator with :func:`fricctl.simulate.simulate_batch`'s signature.

    Returns
    -------
    SweepResult

    Notes
    -----
    Rigid joint only (the link is added to the inertia); the link's elasticity,
    gravity and a load-dependent friction are left out.
    """
    if not isinstance(net, FrictionNet):
        raise ValueError(f"net must be a FrictionNet, got {type(net).__name__}")
    p = paper_actuator() if params is None else params
    scales = np.asarray(friction_scales, dtype=float)
    links = np.asarray(link_inertias, dtype=float)
    if scales.ndim != 1 or scales.size == 0 or not np.all(np.isfinite(scales)) or np.any(scales <= 0):
        raise ValueError("friction_scales must be a non-empty 1-D array of finite values > 0")
    if links.ndim != 1 or links.size == 0 or not np.all(np.isfinite(links)) or np.any(links < 0):
        raise ValueError("link_inertias must be a non-empty 1-D array of finite values >= 0 [kg*m^2]")
    for name, v in (("step", step), ("duration", duration), ("tolerance", tolerance)):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be a finite number > 0, got {v!r}")
    if executor is not None and not hasattr(executor, "submit"):
        raise ValueError(f"executor must be a concurrent.futures.Executor, got {type(executor).__name__}")
    d = _designs(p)["fig16-17"] if design is None else design
    if not isinstance(d, Design):
        raise ValueError(f"design must be a Design, got {type(d).__name__}")
    args = [(p.replace(link_inertia=float(j)), net.to_json(), tuple(scales.tolist()), d.kp, d.kd,
             float(step), float(duration), float(compensation_scale), simulator) for j in links]
    if executor is None:
        rows = [_sweep_row(*a) for a in args]
    else:
        futures = [executor.submit(_sweep_row, *a) for a in args]
        rows = [f.result() for f in futures]
    return SweepResult(scales, links, np.array([r[0] for r in rows]), np.array([r[1] for r in rows]),
                       float(tolerance), float(step), d.kp, d.kd, float(compensation_scale))


# --------------------------------------------------------------------------
# claims
# --------------------------------------------------------------------------
@dataclass(frozen=True)
class Claim:
    """One claim of the paper checked on the bench.

    Attributes
    ----------
    id : short identifier
    claim : the paper's words, with the tolerance used here made explicit
    paper : the paper's value
    measured : the value measured here (with units)
    passed : whether the measured value meets the claim as stated
    figure : the figure it belongs to, e.g. "Fig. 9"
    note : why it fails (or what to know when it passes)
    """

    id: str
    claim: str
    paper: str
    measured: str
    passed: bool
    figure: str
    note: str = ""

    def __post_init__(self):
        for name in ("id", "claim", "paper", "measured", "figure", "note"):
            if not isinstance(getattr(self, name), str):
                raise ValueError(f"Claim.{name} must be a str, got {type(getattr(self, name)).__name__}")
        # numpy comparisons give numpy.bool_, which JSON does not accept
        object.__setattr__(self, "passed", bool(self.passed))

    def as_dict(self) -> dict:
        return asdict(self)


def _deg(x):
    return float(np.rad2deg(x))


def claim_fit(r: Fig8Result) -> Claim:
    f = r.fit_held_out
    ok = f.fit_percent >= 98.0
    return Claim(
        "nn-fit", "The 2-4-1 network learns the friction patterns with 98 % accuracy "
        "(here: normalised fit 100*(1 - ||e||/||y - mean y||) >= 98 % on held-out patterns)",
        "98 %", f"fit {f.fit_percent:.1f} %, R^2 {f.r_squared:.3f} (train fit {r.fit_train.fit_percent:.1f} %; "
        f"vs true friction {r.fit_true.fit_percent:.1f} %)", ok, "Fig. 8",
        "" if ok else "The paper does not define its accuracy. The patterns Tm - I*alpha_hat carry "
        "the estimator's error where the acceleration jumps (torque steps, stick/slip transitions): "
        f"trained on exact patterns the same network reaches a fit of {r.fit_exact.fit_percent:.1f} % "
        "(claim nn-fit-exact): most of the gap to 98 % is the measuring chain, not the 2-4-1 network. "
        f"R^2 is the kinder measure (R^2 = 0.98 is a fit of {100 * (1 - math.sqrt(1 - 0.98)):.1f} %).")


def claim_fit_exact(r: Fig8Result) -> Claim:
    f = r.fit_exact
    ok = f.fit_percent >= 98.0
    return Claim(
        "nn-fit-exact", "(Extra, not in the paper.) Trained on exact patterns -- the simulator's true "
        "velocity and friction at the same samples, same split and seed -- the same 2-4-1 network "
        "reaches 98 % (normalised fit on held-out patterns)", "not in the paper",
        f"fit {f.fit_percent:.1f} %, R^2 {f.r_squared:.4f}", ok, "Fig. 8",
        "" if ok else "close to 98 % but below it in this run: the exact-pattern fit varies between runs "
        "(the fast run's shorter experiments reach 98.4 % with the same architecture, split rule and "
        "seed), so this is the training data and the optimiser's local minimum, not a limit of the "
        "2-4-1 map; either way the measured-pattern fit (claim nn-fit) is far below it.")


def claim_fig4(r: Fig4Result) -> Claim:
    ok = r.filtered_rms < r.raw_rms
    return Claim(
        "fig4-filter", "Filtering the encoder velocity (piecewise 6th-order polynomials) gives a "
        "cleaner velocity than the raw backward difference (here: smaller RMS error against the "
        "simulator's true velocity over the first second)", "qualitative",
        f"RMS error raw {r.raw_rms:.4f} rad/s, filtered {r.filtered_rms:.4f} rad/s", ok, "Fig. 4",
        "" if ok else "the polynomial fit spreads the velocity jumps at torque steps over its window")


def claim_fig9(r: Fig9Result) -> Claim:
    n0, n1 = len(r.sticks_without), len(r.sticks_with)
    ok = n0 >= 1 and n1 == 0
    return Claim(
        "fig9-stick", f"Open-loop sinusoidal torque near the static friction: stick intervals without "
        f"compensation, none with (here: rests >= {1e3 * STICK_MIN_DURATION:.0f} ms after the first motion, "
        f"amplitude {r.amplitude:.3f} N*m = 1.1*Fs, {r.frequency:g} Hz)",
        "sticks without, none with",
        f"{n0} stick intervals without, {n1} with; peak speed {r.peak_speed_without:.2f} rad/s without, "
        f"{r.peak_speed_with:.1f} rad/s with", ok, "Fig. 9",
        ("with compensation the net's gain at rest g > 1 makes the open loop wind the torque up: the joint "
         "no longer sticks but runs far faster than without (see peak speeds)"
         if ok and r.peak_speed_with > 5 * r.peak_speed_without else
         "" if ok else "the compensated joint still stops at some velocity reversals for longer than "
         f"{1e3 * STICK_MIN_DURATION:.0f} ms"))


def claim_dead_zone(r: Fig10Result) -> Claim:
    f0 = r.dead_zone_without.fraction
    ok = abs(100 * f0 - 12.7) <= 1.0 and r.factor >= 4.0
    return Claim(
        "dead-zone", "The torque dead zone of 12.7 % of the maximum torque is reduced by NN compensation "
        "(here: uncompensated dead zone within 1 % of Tmax of 12.7 %, reduction factor >= 4)",
        "12.7 % of Tmax, factor ~6",
        f"{100 * f0:.2f} % -> {100 * r.dead_zone_with.fraction:.2f} % of Tmax, factor {r.factor:.1f} "
        f"(g = {r.gain_at_rest:.2f}; predicted from the net alone: factor {r.predicted_factor:.1f})",
        ok, "Fig. 10",
        "The 12.7 % half holds by construction (Tmax is defined as Fs/0.127); the measured part is the "
        "factor, judged by the issue's >= 4 (the paper's ~6 is one run of one net). It is set by the net's "
        "gain at rest g: the stuck loop settles at Tm = Tc/(1 - g) while g < 1, and at the fixed point "
        "Tm = Tc + T^at(Tm, 0) below Fs otherwise; g depends on the training seed and the estimator "
        "window (Chapter 5), so the factor does too."
        + ("" if ok else " Here it is below 4."))


def claim_fig10_motion(r: Fig10Result) -> Claim:
    c0, c1 = r.without.displacement_counts(), r.with_nn.displacement_counts()
    thr = r.dead_zone_with.threshold_counts
    ok = c0 <= thr < c1
    return Claim(
        "fig10-motion", "A sinusoidal control torque of 10 % of Tmax, inside the dead zone, moves the "
        f"joint with compensation and not without (here: encoder motion > {thr} counts)",
        "moves with, still without",
        f"{c0} counts without, {c1} counts with; peak |Tm| {np.abs(r.with_nn.torque_motor).max():.3f} N*m "
        f"for peak |Tc| {np.abs(r.with_nn.torque_cmd).max():.3f} N*m", ok, "Fig. 10",
        ("the loop winds the motor torque up to several times the control torque (g > 1 at rest): the "
         "joint moves, but it runs away rather than following the small control torque"
         if ok and np.abs(r.with_nn.torque_motor).max() > 2 * np.abs(r.with_nn.torque_cmd).max() else
         "" if ok else "the compensated motor torque stays below the breakaway level"))


def claim_fig11(r: Fig11Result) -> Claim:
    step = r.run.reference[-1]
    ok = abs(r.steady_state_error) >= 0.5 * abs(step) and r.stuck_fraction >= 0.9
    return Claim(
        "fig11-stuck", "P step of 25 deg without compensation: large steady-state error with the joint "
        "stuck (here: |e_ss| >= half the step, joint at rest >= 90 % of the run)",
        "large error, stuck", f"e_ss {_deg(r.steady_state_error):.2f} deg, at rest "
        f"{100 * r.stuck_fraction:.0f} % of the time", ok, "Fig. 11",
        f"Passes trivially: Kp*25 deg = {r.design.kp * abs(step):.3f} N*m is below the breakaway "
        f"level, so the joint never moves at all." if ok else "the joint moved")


def claim_fig12(r: Fig12Result) -> Claim:
    step = r.run.reference[-1]
    tol = 0.1 * abs(step)
    ok = r.max_deviation <= tol
    return Claim(
        "fig12-linear", "P step of 25 deg with NN compensation: close to the linear viscous simulation "
        f"(here: max |q - q_linear| <= 10 % of the step = {_deg(tol):.1f} deg over 3 s)",
        "close to linear", f"max deviation {_deg(r.max_deviation):.1f} deg; peak error in the last "
        f"second x{r.growth:.2f} that of the first", ok, "Fig. 12",
        "" if ok else "Two causes, measured apart. (1) The scheme: full compensation also cancels the "
        "viscous friction b, which is all the damping a P loop has (the design counts on it); with the "
        "one-sample delay the effective damping turns negative -- an ideal estimate (exact friction) "
        f"oscillates too, up to {_deg(r.ideal_max_deviation):.1f} deg from the linear response "
        "(claim fig12-ideal). (2) The network: its errors (g > 1 near rest, its slope in Tm while "
        f"sliding) wind the torque up and make the swing {r.max_deviation / r.ideal_max_deviation:.1f}x "
        "larger than the ideal estimate's.")


def claim_fig12_variant(r: Fig12Result) -> Claim:
    step = r.run.reference[-1]
    tol = 0.1 * abs(step)
    ok = r.variant_max_deviation <= tol
    last = np.abs(r.variant.error[r.variant.t >= r.variant.t[-1] - 1.0]).max()
    return Claim(
        "fig12-variant", "(Extra, not in the paper.) P step with compensation of net(Tm, w) - b*w only "
        f"(what the linear design left out): max |q - q_linear| <= {_deg(tol):.1f} deg",
        "not in the paper", f"max deviation {_deg(r.variant_max_deviation):.1f} deg; peak |r - q| in the "
        f"last second {_deg(last):.1f} deg", ok, "Fig. 12",
        "" if ok else "Leaving b in the loop tames the oscillation, but it "
        + ("decays only slowly" if r.variant_growth < 1 else "persists")
        + f" (peak error in the last second x{r.variant_growth:.2f} that of the first): the net's own "
        "error (its slope in Tm while sliding, g != 1 near rest) still feeds torque back through the "
        "one-sample delay; the ideal estimate minus b*w does follow the linear response (claim "
        "fig12-ideal), so here the net's error is the cause.")


def claim_fig12_ideal(r: Fig12Result) -> Claim:
    step = r.run.reference[-1]
    tol = 0.1 * abs(step)
    ok = r.ideal_growth > 1.0 and r.ideal_no_viscous_max_deviation <= tol
    return Claim(
        "fig12-ideal", "(Extra, not in the paper.) With an ideal estimate (the bench's exact friction "
        "while sliding, Tat = Tm at rest), full compensation still makes the P loop's oscillation grow, "
        f"and the same estimate minus b*w follows the linear response (max |q - q_linear| <= {_deg(tol):.1f} "
        "deg)", "not in the paper",
        f"full: error growth last/first second x{r.ideal_growth:.2f}; minus b*w: max deviation "
        f"{_deg(r.ideal_no_viscous_max_deviation):.2f} deg", ok, "Fig. 12",
        "Confirms the cause of fig12-linear: cancelling the viscous damping the P design relies on is "
        "what destabilises the loop, whatever the estimator's accuracy." if ok else
        "the ideal estimate does not separate the causes on this bench")


def claim_fig13(r: Fig13Result) -> Claim:
    diff = abs(r.torque_at_rest - r.nn_at_rest)
    ok = diff <= 0.2 * abs(r.torque_at_rest)
    return Claim(
        "fig13-residual", "PD step of 30 deg without compensation: the residual steady motor torque is "
        "close to the NN friction estimate (here: |Tm - net(Tm, 0)| at rest <= 20 % of Tm)",
        "Tm ~ NN estimate", f"Tm {r.torque_at_rest:.4f} N*m, net {r.nn_at_rest:.4f} N*m (difference "
        f"{diff:.4f} N*m, {100 * diff / abs(r.torque_at_rest):.0f} %; RMSE {r.nn_rmse:.4f} N*m); "
        f"e_ss {_deg(r.steady_state_error):.2f} deg", ok, "Fig. 13",
        "" if ok else "the net's estimate at rest differs from the held torque by more than 20 %")


def claim_fig14(r: Fig14Result) -> Claim:
    e = abs(r.steady_state_error)
    ok = _deg(e) < ACCURACY_DEG
    return Claim(
        "fig14-accuracy", "PD step of 30 deg with NN compensation: steady-state error below 0.3 deg",
        "< 0.3 deg", f"|e_ss| {_deg(e):.3f} deg (predicted band +-{_deg(r.predicted_band):.2f} deg)",
        ok, "Fig. 14",
        "" if ok else "The compensated loop keeps a residual dead zone DZ, so the joint can stop anywhere "
        f"within +-DZ/Kp of the reference (here +-{_deg(r.predicted_band):.2f} deg); < 0.3 deg for every "
        f"approach needs DZ < 0.3 deg*Kp = {r.design.kp * np.deg2rad(0.3):.4f} N*m, a dead-zone "
        f"reduction of {r.run.info.params.static / (r.design.kp * np.deg2rad(0.3)):.0f}x, far more "
        "than the paper's own ~6x.")


def _osc(r: Fig16Result, key: str) -> bool:
    return r.reference_crossings[key] >= 2 or r.torque_sign_changes[key] >= 10


def claim_fig16_nn(r: Fig16Result) -> Claim:
    k = next(k for k in r.runs if k.startswith("NN"))
    e, e0 = abs(r.steady_state_error[k]), abs(r.steady_state_error["none"])
    ok = _deg(e) < ACCURACY_DEG and r.torque_sign_changes[k] < 10
    return Claim(
        "fig16-nn", "Aged actuator (friction x 0.95, assumed) with link: NN compensation scaled to 0.95 "
        "works without retraining (here: |e_ss| < 0.3 deg and no chatter: < 10 sign changes of Tm "
        "in the last 0.5 s)", "works",
        f"|e_ss| {_deg(e):.3f} deg ({e0 / e if e > 0 else math.inf:.0f}x smaller than without), "
        f"{r.torque_sign_changes[k]} Tm sign changes", ok, "Fig. 16",
        "" if ok else "The loop is stable and the error much smaller than without, but it stops in the "
        "residual dead band +-DZ/Kp, as in Fig. 14.")


def claim_fig16_coulomb(r: Fig16Result) -> Claim:
    k = "Coulomb"
    ok = _osc(r, k)
    return Claim(
        "fig16-coulomb", "Coulomb compensation oscillates around the reference or chatters (here: the "
        "error changes sign >= 2 times, or Tm changes sign >= 10 times in the last 0.5 s)",
        "oscillates / chatters",
        f"{r.reference_crossings[k]} reference crossings, {r.torque_sign_changes[k]} Tm sign changes; "
        f"e_ss {_deg(r.steady_state_error[k]):.3f} deg", ok, "Fig. 16",
        "" if ok else "Fc*sign(omega_hat) is zero while the encoder reads no motion, so once the joint "
        "sticks the compensation vanishes and nothing drives a limit cycle: the joint overshoots (the "
        "braking Coulomb term is cancelled while moving) and stays stuck. Chatter needs a velocity "
        "estimate that is noisy at rest (noise, a finer encoder, a different estimator). Against the "
        f"paper, Coulomb compensation here also ends closer to the reference ({_deg(abs(r.steady_state_error[k])):.3f} "
        f"deg) than NN x 0.95 ({_deg(abs(r.steady_state_error['NN x 0.95'])):.3f} deg).")


def claim_fig16_none(r: Fig16Result) -> Claim:
    e = abs(r.steady_state_error["none"])
    ok = _deg(e) >= ACCURACY_DEG
    return Claim(
        "fig16-none", "Without compensation a steady-state error remains (here: |e_ss| >= 0.3 deg)",
        "error remains", f"|e_ss| {_deg(e):.2f} deg", ok, "Fig. 16",
        "The joint sticks inside the dead band +-Fs/Kp." if ok else "the joint reached the reference")


def claim_fig17_none(r: Fig17Result, resolution: float) -> Claim:
    m = r.max_motion["none"]
    ok = m <= resolution
    return Claim(
        "fig17-none", "Step of 0.08 rad without compensation: no motion (here: peak |q| <= 1 encoder count)",
        "no motion", f"peak |q| {m:.2e} rad (1 count = {resolution:.2e} rad)", ok, "Fig. 17",
        f"Passes trivially: Kp*0.08 rad = {r.design.kp * r.step:.3f} N*m is below the breakaway level."
        if ok else "the joint moved")


def claim_fig17_nn(r: Fig17Result) -> Claim:
    k = next(k for k in r.runs if k.startswith("NN"))
    e = abs(r.steady_state_error[k])
    ok = _deg(e) < ACCURACY_DEG
    return Claim(
        "fig17-nn", "Step of 0.08 rad with NN compensation: small steady-state error (here: < 0.3 deg, "
        "the paper's Fig. 14 accuracy)", "small error", f"|e_ss| {_deg(e):.3f} deg "
        f"({100 * e / r.step:.0f} % of the step)", ok, "Fig. 17",
        "" if ok else "same cause as Fig. 14: the residual dead zone lets the joint stop within "
        "+-DZ/Kp of the reference.")


def claim_fig18_without(r: Fig18Result) -> Claim:
    ok = r.restarts_without >= 2
    return Claim(
        "fig18-without", f"Sawtooth of {r.amplitude:g} rad without compensation: stick-slip (here: >= 2 "
        f"rests of >= {1e3 * STICK_MIN_DURATION:.0f} ms followed by motion; period {r.period:g} s assumed)",
        "stick-slip", f"{r.restarts_without} stick-slip cycles, peak |q| {r.max_motion_without:.2e} rad",
        ok, "Fig. 18",
        "" if ok else f"With the Fig.-18 gain Kp = {r.design.kp:.3f} N*m/rad the whole "
        f"sawtooth asks for at most Kp*{r.amplitude:g} rad = {r.design.kp * r.amplitude:.3f} N*m, below the "
        "breakaway level: the joint never moves at all. Stick-slip does appear for a larger, slower "
        f"ramp ({r.extra_amplitude:g} rad over {r.extra_period:g} s: {r.extra_restarts} cycles; see "
        "fig18-extra).")


def claim_fig18_with(r: Fig18Result) -> Claim:
    tol = 0.1 * r.amplitude
    ok = r.rms_deviation_with <= tol
    return Claim(
        "fig18-with", "Sawtooth with NN compensation: the joint tracks the reference (here: RMS of "
        f"q - q_linear <= 10 % of the amplitude = {tol:.3f} rad)", "tracks",
        f"RMS deviation from the linear viscous loop {r.rms_deviation_with:.4f} rad; "
        f"{restarts(r.with_nn)} stick-slip cycles", ok, "Fig. 18",
        "" if ok else f"The compensated joint moves, but itself in stick-slip ({restarts(r.with_nn)} "
        "cycles, a staircase): compensation breaks it loose, and each time it stops the residual dead "
        "zone holds it until Kp*e has grown by about DZ.")


def claim_fig18_extra(r: Fig18Result) -> Claim:
    ok = r.extra_restarts >= 2
    return Claim(
        "fig18-extra", f"(Extra, not in the paper.) A larger, slower sawtooth ({r.extra_amplitude:g} rad "
        f"over {r.extra_period:g} s) without compensation shows stick-slip (>= 2 cycles)",
        "not in the paper", f"{r.extra_restarts} stick-slip cycles", ok, "Fig. 18",
        "" if ok else "the joint creeps without sticking at this ramp rate")


# --------------------------------------------------------------------------
# everything
# --------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class PaperResults:
    """All figures, the sweep and the claims of one :func:`reproduce_paper` run."""

    network: PaperNetwork
    figures: dict
    sweep: SweepResult
    claims: tuple

    @property
    def n_passed(self) -> int:
        return sum(c.passed for c in self.claims)

    def summary(self) -> str:
        """``"N of M claims of the paper reproduced (extras: n of m)"``."""
        return _summary(self.claims)


def _is_extra(c: Claim) -> bool:
    """A check of ours that is not a claim of the paper."""
    return c.paper == "not in the paper"


def _summary(claims) -> str:
    paper_c = [c for c in claims if not _is_extra(c)]
    extra = [c for c in claims if _is_extra(c)]
    s = f"{sum(c.passed for c in paper_c)} of {len(paper_c)} claims of the paper reproduced"
    if extra:
        s += f" (extras, not in the paper: {sum(c.passed for c in extra)} of {len(extra)} pass)"
    return s


def paper_claims(figures: dict, params: ActuatorParams | None = None) -> list[Claim]:
    """Claims from figure results (``{4: Fig4Result, ...}``); missing figures are skipped."""
    p = paper_actuator() if params is None else params
    makers = {4: [claim_fig4], 8: [claim_fit, claim_fit_exact], 9: [claim_fig9], 10: [claim_dead_zone, claim_fig10_motion],
              11: [claim_fig11], 12: [claim_fig12, claim_fig12_variant, claim_fig12_ideal], 13: [claim_fig13],
              14: [claim_fig14], 16: [claim_fig16_nn, claim_fig16_coulomb, claim_fig16_none],
              17: [lambda r: claim_fig17_none(r, p.encoder_resolution), claim_fig17_nn],
              18: [claim_fig18_without, claim_fig18_with, claim_fig18_extra]}
    out = []
    for num in sorted(figures):
        for make in makers.get(num, []):
            out.append(make(figures[num]))
    return out


def _md(s: str) -> str:
    return s.replace("|", "\\|").replace("\n", " ")


def claims_markdown(claims, *, title: str = "Claims of Gervini, Gomes & da Rosa (2003) on the virtual bench",
                    preamble: str = "") -> str:
    """``claims.md``: the table, a summary line and the "not reproduced, and why" section."""
    claims = list(claims)
    lines = [f"# {title}", ""]
    if preamble:
        lines += [preamble, ""]
    lines += [f"**{_summary(claims)}.**", "",
              "| id | claim | paper | measured | pass/fail | figure |", "|---|---|---|---|---|---|"]
    for c in claims:
        lines.append(f"| {c.id} | {_md(c.claim)} | {_md(c.paper)} | {_md(c.measured)} | "
                     f"{'pass' if c.passed else '**FAIL**'} | {c.figure} |")
    failed = [c for c in claims if not c.passed]
    lines += ["", "## Not reproduced, and why", ""]
    lines += [f"- **{c.id}** ({c.figure}): {c.note}" for c in failed] or ["Every claim was reproduced."]
    notes = [c for c in claims if c.passed and c.note]
    if notes:
        lines += ["", "## Notes on claims that pass", ""]
        lines += [f"- **{c.id}** ({c.figure}): {c.note}" for c in notes]
    return "\n".join(lines) + "\n"


def claims_json(claims) -> str:
    """``claims.json``: a list of objects with id, claim, paper, measured, passed, figure (and note)."""
    return json.dumps([c.as_dict() for c in claims], indent=2)


def reproduce_paper(params: ActuatorParams | None = None, *, fast: bool = False, seed: int = 0,
                    executor: Executor | None = None,
                    progress: Callable[[int, int, str], None] | None = None) -> PaperResults:
    """Train once, run every figure and the robustness sweep, check the claims.

    Parameters
    ----------
    params : ActuatorParams, optional
    fast : bool
        Short training experiments and a small sweep grid.
    seed : int
        Seed of the network's split and training [-].
    executor : concurrent.futures.Executor, optional
        Passed to :func:`robustness_sweep`.
    progress : callable, optional
        ``progress(done, total, name)`` before each step.

    Returns
    -------
    PaperResults
    """
    p = paper_actuator() if params is None else params
    seed = _check_seed(seed)
    steps = ["network"] + [f"fig{n}" for n in FIGURES] + ["sweep"]
    total = len(steps)

    def tick(i, name):
        if progress is not None:
            progress(i, total, name)

    tick(0, "network")
    network = train_paper_network(p, fast=fast, seed=seed)
    figs = {}
    for i, (num, fn) in enumerate(FIGURES.items(), start=1):
        tick(i, f"fig{num}")
        figs[num] = fn(network)
    tick(total - 1, "sweep")
    grid = dict(friction_scales=(0.8, 1.0, 1.2), link_inertias=(0.0, 0.0046)) if fast else {}
    sweep = robustness_sweep(network.net, p, executor=executor, **grid)
    tick(total, "done")
    return PaperResults(network, figs, sweep, tuple(paper_claims(figs, p)))
