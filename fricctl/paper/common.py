"""What several figures share: the paper's constants, its cached controller designs,
the step and link-run helpers, and small measurements on a run (stick intervals,
stick-slip cycles, sign changes).
"""

from __future__ import annotations

import functools
import threading
import warnings
import zlib
from dataclasses import dataclass
from types import MappingProxyType
from typing import Mapping

import numpy as np

from .. import _validate as v
from .. import controllers as ctl
from ..bench.experiments import DeadZone, dead_zone
from ..compensators import CoulombCompensator, NoCompensation
from ..design import Design, DesignWarning, linear_response, paper_designs
from ..params import PAPER_LINK_INERTIA, ActuatorParams
from ..simulate import SimResult, simulate
from .coast import CoastResult
from .network import PaperNetwork
from .runaway import RunawayCheck

__all__ = ["ACCURACY_DEG", "STICK_MIN_DURATION", "AGED_SCALE", "SS_WINDOW", "designs",
           "stick_intervals_after_motion", "restarts", "periods_with_motion", "FIG18_PERIODS",
           "sign_changes", "last_window", "deg", "stuck_band", "gain_for_band",
           "StepRun", "step_run", "LinkRuns", "link_runs", "read_only", "linear_prediction",
           "OpenLoopChecks", "LinkFigure", "COULOMB_AT_FS", "COULOMB_AT_FC", "CoulombLevels",
           "uncompensated_dead_zone", "coulomb_levels", "Oscillation", "oscillation", "sensed"]

#: The paper's steady-state accuracy, Fig. 14 ("less than 0.3 deg") [deg].
ACCURACY_DEG = 0.3
#: A rest shorter than this is a velocity reversal, not a stick interval [s].
STICK_MIN_DURATION = 0.02
#: Periods of Fig. 18's sawtooth that are run and judged: the figure's two and one more, so
#: that a joint parked after a start-up transient does not count as stick-slip, and a single
#: rest that noise moves across the end of the second period does not decide the claim.
FIG18_PERIODS = 3
#: Compensation scale of the aged actuator (Fig. 16), and its assumed friction change [-].
AGED_SCALE = 0.95
#: Window at the end of a run over which steady state is measured [s].
SS_WINDOW = 0.5
#: Window at the end of a run over which a limit cycle is measured (Figs. 16-17) [s]: a few
#: periods of the PD loop's mode (3-5 Hz with the link).
CYCLE_WINDOW = 1.0
#: Keys of the two Coulomb runs of Figs. 16-17: the paper's compensation at the dry friction
#: identified experimentally (the breakaway level), and at a smaller level (the identified
#: Coulomb level), both scaled by s like the network (:class:`CoulombLevels`).
COULOMB_AT_FS = "Coulomb at Fs"
COULOMB_AT_FC = "Coulomb at Fc"


def stuck_band(breakaway: float, gain: float, kp: float, scale: float = 1.0) -> float:
    """Half-width of the band a stuck, compensated PD loop stops in [rad]: with the
    compensation ``scale * T^at`` linear near rest (gain at rest ``gain``), the stuck loop
    settles at ``Tm = Kp*e / (1 - scale*gain)``, so the joint breaks away once that reaches
    ``breakaway`` [N*m]: ``breakaway * (1 - scale*gain) / kp``."""
    return breakaway * (1 - scale * gain) / kp


def gain_for_band(band: float, breakaway: float, kp: float, scale: float = 1.0) -> float:
    """The gain at rest whose :func:`stuck_band` is ``band`` [rad] [-]."""
    return (1 - band * kp / breakaway) / scale


def designs(bench) -> Mapping[str, Design]:
    """The paper's four controllers on a bench (:func:`fricctl.design.paper_designs`), cached and
    read-only.

    ``bench`` is a :class:`~fricctl.paper.benches.Bench` (the designs count on its design model,
    :attr:`~fricctl.paper.benches.Bench.design_actuator`, read "rise time" as its
    ``rise_time_reading`` and attach its link) or an :class:`~fricctl.params.ActuatorParams`
    (designed on as it is: 0-100 % rise time, the paper's link).

    Cached because each design verifies itself on fine grids (~0.2 s) and Designs
    are immutable; the mapping is read-only so that no caller can change what the
    next one gets.  The PD (0.3 s, 0.9) design warns that its sampled 0-100 % rise
    time is ill-conditioned near zeta = 1 (expected; Chapter 6 explains it): the
    warning is silenced here.
    """
    from .benches import Bench

    if isinstance(bench, Bench):
        return _designs(bench.design_actuator, bench.rise_time_reading, bench.link_inertia)
    v.instance("bench", bench, (Bench, ActuatorParams), "a Bench or an ActuatorParams")
    return _designs(bench, "0-100", PAPER_LINK_INERTIA)


@functools.lru_cache(maxsize=8)
def _designs(params: ActuatorParams, reading: str, link_inertia: float) -> Mapping[str, Design]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DesignWarning)
        return MappingProxyType(paper_designs(params, rise_time_definition=reading,
                                              link_inertia=link_inertia))


def sensed(network: PaperNetwork, label: str, plant) -> dict:
    """The keyword arguments of :func:`fricctl.simulate.simulate` that give a figure's run of
    ``network`` its bench's sensing (:meth:`fricctl.paper.benches.Sensing.options`).

    ``plant``: the run's plant friction -- a :class:`~fricctl.friction.FrictionModel`, or the
    run's :class:`~fricctl.params.ActuatorParams` for its own (``friction_model()``); the
    arguments hold it as ``friction``, with the bench's torque ripple added.

    The noise is drawn from a generator seeded by the network's seed
    (:attr:`~fricctl.paper.PaperNetwork.noise_seed`) and the run's ``label``
    (its CRC-32), so that a run is reproducible, each run of a figure draws its own noise (and
    torque-ripple phase; the runs of one batch share it: one session of the drive), and
    the seeds of ``fricctl reproduce`` are seeds of the sensing too.  On a noise-free bench
    nothing is drawn: the run is bit for bit the one without these arguments.

    Every run of the bench's loop that a figure makes for its network takes them; the model
    predictions it compares with (the linear viscous actuator, the ideal estimates) and the
    experiments that identify (the training records, the dead-zone experiment) stay noise-free.
    """
    seed = [int(network.noise_seed), zlib.crc32(v.text("label", label, empty=False).encode())]
    friction = plant.friction_model() if isinstance(plant, ActuatorParams) else plant
    return network.bench.sensing.options(np.random.default_rng(seed), friction)


# --------------------------------------------------------------------------
# measurements on a run
# --------------------------------------------------------------------------
def stick_intervals_after_motion(result: SimResult, min_duration: float = STICK_MIN_DURATION):
    """Rest intervals of at least ``min_duration`` [s] that start after the joint first moved.

    Returns a list of ``(start, end)`` times [s].
    """
    moving = np.flatnonzero(~result.stuck)
    if moving.size == 0:
        return []
    t0 = result.t[moving[0]]
    return [iv for iv in result.stuck_intervals(min_duration) if iv[0] > t0]


def periods_with_motion(result: SimResult, period: float, periods: int) -> int:
    """Of the ``periods`` periods of ``period`` [s] a run spans, those in which the joint (its true
    position) moves by more than one encoder count (a joint that stick-slips keeps moving in every
    period; one parked after a start-up transient does not)."""
    period = v.real("period", period, positive=True, unit="s")
    periods = v.integer("periods", periods, low=1)
    res = result.info.encoder_resolution
    k = np.minimum((result.t / period).astype(int), periods - 1)
    return int(sum(np.ptp(result.q[k == j]) > res for j in range(periods) if np.any(k == j)))


def restarts(result: SimResult, min_duration: float = STICK_MIN_DURATION) -> int:
    """Stick-slip cycles: rests of at least ``min_duration`` after first motion that end in motion."""
    end = result.t[-1]
    return sum(1 for a, b in stick_intervals_after_motion(result, min_duration) if b < end)


def sign_changes(x, *, tol: float = 0.0) -> int:
    """Number of sign changes of ``x`` (values with ``|x| <= tol`` are skipped).

    Examples
    --------
    >>> sign_changes([1.0, -1.0, 0.0, -2.0, 3.0])
    2
    >>> sign_changes([1.0, -0.1, 1.0], tol=0.5)
    0
    """
    x = v.array("x", x, ndim=None, finite=False)
    s = np.sign(x[np.abs(x) > tol])
    return int(np.count_nonzero(s[1:] != s[:-1]))


def last_window(result: SimResult, window: float = SS_WINDOW) -> np.ndarray:
    """Mask of the samples in the last ``window`` seconds of a run [bool]."""
    return result.t >= result.t[-1] - window + 1e-12


def deg(x) -> float:
    """Radians to degrees, as a plain ``float``."""
    return float(np.rad2deg(x))


@dataclass(frozen=True, kw_only=True)
class Oscillation:
    """The oscillation of a run's position over its last ``window`` seconds (a limit cycle, if
    it is sustained there).

    Measured on the encoder reading ``q_meas`` about its mean over the window: zero amplitude
    and frequency for a joint at rest (the encoder still) over the whole window.
    """

    amplitude: float
    """Half the peak-to-peak encoder motion over the window [rad]."""
    frequency: float
    """From the sign changes of ``q_meas - mean`` (beyond one encoder count) over the window:
    ``(n - 1)/2`` periods between the first and the last of ``n >= 2`` changes; 0 with fewer [Hz]."""
    crossings: int
    """Those sign changes [-]."""
    counts: int
    """Peak-to-peak encoder motion over the window [counts]."""
    window: float
    """The window at the end of the run [s]."""

    @property
    def sustained(self) -> bool:
        """True when the joint still moves back and forth in the window (two crossings or more)."""
        return self.crossings >= 2


def oscillation(result: SimResult, window: float = CYCLE_WINDOW) -> Oscillation:
    """Amplitude and frequency of ``result``'s position over its last ``window`` seconds.

    Examples
    --------
    >>> from fricctl.simulate import simulate
    >>> from fricctl.params import paper_actuator
    >>> import fricctl.controllers as ctl
    >>> r = simulate(paper_actuator(), ctl.open_loop(ctl.sinusoid(0.01, 1.0)), duration=2.0)
    >>> oscillation(r)                      # 0.01 N*m is below breakaway: at rest
    Oscillation(amplitude=0.0, frequency=0.0, crossings=0, counts=0, window=1.0)
    """
    v.instance("result", result, SimResult)
    window = v.real("window", window, positive=True, unit="s")
    w = last_window(result, window)
    y, t = result.q_meas[w], result.t[w]
    res = result.info.params.encoder_resolution
    keep = np.abs(y - y.mean()) > res
    s, t = np.sign(y - y.mean())[keep], t[keep]
    at = t[1:][s[1:] != s[:-1]]  # the first sample past each sign change
    f = (at.size - 1) / (2 * (at[-1] - at[0])) if at.size >= 2 else 0.0
    counts = int(round(np.ptp(y) / res)) if res > 0 else 0
    return Oscillation(amplitude=float(np.ptp(y) / 2), window=window, frequency=float(f),
                       crossings=int(at.size), counts=counts)


# --------------------------------------------------------------------------
# the runs several figures make
# --------------------------------------------------------------------------
@dataclass(frozen=True, eq=False, kw_only=True)
class StepRun:
    """A step on the actuator and the linear viscous prediction on the same grid.

    Attributes
    ----------
    run : the nonlinear run
    linear : the sampled linear viscous loop's position [rad]
    """

    run: SimResult
    linear: np.ndarray


def read_only(*arrays_or_runs) -> None:
    """Make arrays (or every array of frozen results) read-only.

    For results that several figure results share (the memoised runs below): nobody can
    change what the next caller gets.
    """
    for x in arrays_or_runs:
        items = [x] if isinstance(x, np.ndarray) else list(vars(x).values())
        for a in items:
            if isinstance(a, np.ndarray):
                a.setflags(write=False)


_LINEAR: dict = {}
_LINEAR_LOCK = threading.Lock()


def linear_prediction(design: Design, run: SimResult, key: tuple) -> np.ndarray:
    """The sampled linear viscous loop's response to ``run``'s reference (read-only, memoised).

    It depends only on the design and the reference, not on the network, so every network
    of a process shares it (one python-control simulation, ~0.15 s, instead of one per
    figure and network).  ``key`` names the reference (e.g. ``("step", 0.52)``); the
    design is keyed by identity (the designs of :func:`designs` are cached and immutable)
    and the time grid by its length and step.
    """
    k = (id(design), key, run.t.size, float(run.t[1] - run.t[0]) if run.t.size > 1 else 0.0)
    with _LINEAR_LOCK:
        hit = _LINEAR.get(k)
    if hit is not None and hit[0] is design:
        return hit[1]
    lin = linear_response(design, run.t, run.reference, sampled=True)
    read_only(lin)
    with _LINEAR_LOCK:
        if len(_LINEAR) > 256:  # a bound: a long-lived process with many designs starts again
            _LINEAR.clear()
        _LINEAR[k] = (design, lin)  # holding the design keeps its id from being reused
    return lin


def step_run(params: ActuatorParams, design: Design, step_rad: float, compensator, duration: float,
             friction=None, sensing: dict | None = None) -> StepRun:
    """A P (``design.kd == 0``) or PD step of ``step_rad`` [rad] with ``compensator``;
    ``sensing``: the run's sensing (:func:`sensed`, which holds the run's friction; None:
    noise-free, the plant's own friction or ``friction``)."""
    c = ctl.pd_control(design.kp, design.kd, ctl.step(step_rad)) if design.kd > 0 else \
        ctl.p_control(design.kp, ctl.step(step_rad))
    if sensing is not None and friction is not None:
        raise ValueError("step_run: give the run's friction to sensed(), not beside it")
    r = simulate(params, c, compensator, duration=duration,
                 **(sensing if sensing is not None else {"friction": friction}))
    return StepRun(run=r, linear=linear_prediction(design, r, ("step", float(step_rad))))


@functools.lru_cache(maxsize=4)
def uncompensated_dead_zone(params: ActuatorParams) -> DeadZone:
    """The dead-zone experiment without compensation on ``params`` (memoised, read-only).

    The paper's way of reading the breakaway level off the bench: open-loop sinusoids of
    growing amplitude, the joint "moves" when its encoder spans more than a few counts
    (:func:`fricctl.bench.experiments.dead_zone`, defaults).  The same for every network of
    a process (Figs. 10, 16 and 17 share it).
    """
    dz = dead_zone(params)
    read_only(dz)
    return dz


@dataclass(frozen=True, kw_only=True)
class CoulombLevels:
    """The levels of the Coulomb compensator of Figs. 16-17, identified on the bench's records.

    The paper compensated "at the dry friction identified experimentally" -- its breakaway
    level, 0.18 N*m -- and saw the joint oscillate; at a smaller level the oscillation
    disappeared.  Both levels are read here from what the bench's experiments record, never
    from the bench's true parameters:

    * ``breakaway``: the dead zone of the uncompensated dead-zone experiment
      (:func:`uncompensated_dead_zone`), the torque at which the joint breaks away, to the
      experiment's amplitude step;
    * ``coulomb``: the smaller level, the Coulomb level a least-squares fit of
      ``Tat = Fc*sign(omega) + b*omega`` gives on the sliding friction patterns the pipeline
      measured (``network.patterns`` not at rest): the level the identification gives, not a
      fraction of the breakaway level.

    Both are compensated times the scale s of the aged actuator, like the network.
    """

    breakaway: float
    """Breakaway level read off the dead-zone experiment [N*m]."""
    breakaway_step: float
    """Amplitude step of that experiment near the breakaway level: its resolution [N*m]."""
    coulomb: float
    """Coulomb level of the least-squares fit on the sliding patterns [N*m]."""
    viscous: float
    """Viscous coefficient of the same fit [N*m*s/rad]."""
    patterns: int
    """Sliding patterns the fit used [-]."""

    def level(self, key: str) -> float:
        """The identified level of the run ``key`` (:data:`COULOMB_AT_FS` or :data:`COULOMB_AT_FC`) [N*m]."""
        return {COULOMB_AT_FS: self.breakaway, COULOMB_AT_FC: self.coulomb}[
            v.choice("key", key, (COULOMB_AT_FS, COULOMB_AT_FC))]


def coulomb_levels(network: PaperNetwork) -> CoulombLevels:
    """The breakaway and Coulomb levels identified on ``network``'s bench records (:class:`CoulombLevels`)."""
    dz = uncompensated_dead_zone(network.params)
    fs = dz.dead_zone
    if not np.isfinite(fs):
        raise ValueError("the dead-zone experiment never moved the joint: no breakaway level to "
                         "compensate")
    i = int(np.searchsorted(dz.amplitudes, fs))
    step = float(fs - dz.amplitudes[i - 1]) if i > 0 else float(fs)
    pats = network.patterns
    sliding = ~pats.at_rest & (pats.omega != 0.0)
    w = pats.omega[sliding]
    if np.unique(np.sign(w)).size < 2:
        raise ValueError("the friction patterns hold no sliding samples in both directions: no "
                         "Coulomb level to identify")
    (fc, b), *_ = np.linalg.lstsq(np.column_stack([np.sign(w), w]), pats.friction[sliding], rcond=None)
    return CoulombLevels(breakaway=float(fs), breakaway_step=step, coulomb=float(fc), viscous=float(b),
                         patterns=int(w.size))


@dataclass(frozen=True, eq=False, kw_only=True)
class LinkRuns:
    """The actuator with the link under one PD law: no compensation, NN x s, Coulomb x s.

    Attributes
    ----------
    runs : ``{"none", "NN x <s>", COULOMB_AT_FS, COULOMB_AT_FC}`` -> run (NN: the pipeline's
        compensation, :meth:`PaperNetwork.compensator`; Coulomb: at the identified levels x s)
    design : the PD design used
    coulomb_levels : the identified levels of the two Coulomb runs
    """

    runs: dict
    design: Design
    coulomb_levels: CoulombLevels


def link_runs(network: PaperNetwork, design_key: str, reference, duration: float,
              friction_scale: float, scale: float) -> LinkRuns:
    """The actuator with link and friction x ``friction_scale``, compensated x ``scale`` (Figs. 16-17),
    each run with the bench's sensing (:func:`sensed`)."""
    p = network.bench.linked_actuator
    d = designs(network.bench)[design_key]
    levels = coulomb_levels(network)
    comps = {"none": NoCompensation(),
             f"NN x {scale:g}": network.compensator(scale),
             **{k: CoulombCompensator.symmetric(levels.level(k), scale=scale)
                for k in (COULOMB_AT_FS, COULOMB_AT_FC)}}
    fr = p.friction_model().scaled(friction_scale)
    c = ctl.pd_control(d.kp, d.kd, reference)
    # one run each (each its own simulate call: the runs' records stay separate)
    label = f"link {design_key} {reference.description}"
    return LinkRuns(runs={k: simulate(p, c, comp, duration=duration,
                                      **sensed(network, f"{label} {k}", fr))
                          for k, comp in comps.items()}, design=d, coulomb_levels=levels)


@dataclass(frozen=True, eq=False, kw_only=True)
class OpenLoopChecks:
    """What an open-loop figure's compensated claims require (Figs. 9-10): the wind-up and
    reversal checks of its compensated run and the network's coast test.

    Attributes
    ----------
    wind_up, reversal : runaway checks of the compensated run
    coast : the network's coast test
    """

    wind_up: RunawayCheck
    reversal: RunawayCheck
    coast: CoastResult

    @property
    def checks(self) -> tuple:
        """The runaway checks every compensated claim of the figure requires."""
        return (self.wind_up, self.reversal, self.coast.decay)


@dataclass(frozen=True, eq=False, kw_only=True)
class LinkFigure:
    """A figure made of :func:`link_runs` (Figs. 16-17).

    Attributes
    ----------
    runs : ``{"none", "NN x <s>", COULOMB_AT_FS, COULOMB_AT_FC}`` -> run
    design : the PD design used
    coulomb_levels : the identified levels of the Coulomb runs (before the scale s)
    wind_up : runaway check of the NN run
    coast : the network's coast test
    """

    runs: dict
    design: Design
    coulomb_levels: CoulombLevels
    wind_up: RunawayCheck
    coast: CoastResult

    @property
    def nn_key(self) -> str:
        """The key of the NN-compensated run in ``runs``."""
        return next(k for k in self.runs if k.startswith("NN"))
