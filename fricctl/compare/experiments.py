"""The experiments of the comparison: the paper's, run with any compensator on any plant.

Each experiment is the paper's figure experiment with its settings (its controller design from
:func:`fricctl.paper.common.designs`, its steps, sinusoid, sawtooth and durations from the
figure modules and the bench), made to take the compensator and the plant as arguments; each
returns an :class:`Outcome`: metrics with units (:data:`METRICS`) and the runaway checks of
:mod:`fricctl.paper.runaway` on its compensated runs (the torque's:
:func:`~fricctl.paper.runaway.torque_check`, the wind-up bound for a friction estimate, the
divergence criterion for a DOB or integral action).

==============  ===================================================================  ===========
name            what                                                                 from
==============  ===================================================================  ===========
dead_zone       open-loop sinusoid batches: the torque dead zone, with and without   Fig. 10
pd_steps        PD steps of -40 .. 40 deg, 3 s each: the steady-state error          Fig. 14
small_steps     steps of +-0.08 rad with the link, PD (0.4 s, 0.85)                  Fig. 17
sawtooth        the bench's sawtooth with the link, two periods: tracking            Fig. 18
coast           a torque pulse of 2 Fs for 0.3 s, then Tc = 0: does the joint coast  coast test
limit_cycle     a 30 deg PD step, held until the record judges: oscillation over     Fig. 14
                the run's last half (6 s, doubled up to 384 s)
==============  ===================================================================  ===========

Open-loop experiments (dead zone, coast) build the compensator for the PD loop of Fig. 14 (a
compensator that needs the loop's gains gets those), and run it on the open-loop torque.

Notes
-----
The metrics are measured on the simulator's true position and torque (no measurement noise
unless the plant asks for it); the limit cycle is the true position's oscillation.

The limit-cycle run has no fixed length: a stick-slip cycle (integral action or a DOB hunting
around the target) is as slow as its state is to wind the torque across the friction band
(tens of seconds for the paper's integral design), and a run shorter than two of its periods
shows a joint at rest, not a limit cycle.  The run is doubled from :data:`LC_DURATION` until
its last half either holds two sustained periods or a joint at rest whose torque no state
moves any more (:func:`oscillation`), up to :data:`LC_MAX_DURATION`; a loop still undecided
there is reported as not judged (no amplitude, and the row says why), never as "none".
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, fields, is_dataclass, replace
from types import MappingProxyType
from typing import Callable, Mapping

import numpy as np

from .. import _validate as v
from .. import controllers as ctl
from ..bench.experiments import dead_zone
from ..compensators import Compensator, NoCompensation
from ..paper import coast as coast_test
from ..paper.common import SS_WINDOW, designs, restarts
from ..paper.fig14 import STEPS_DEG
from ..paper.runaway import STEADY, coast_decay, reversal, torque_check
from ..simulate import SimResult, simulate, simulate_batch

__all__ = ["Experiment", "Outcome", "Oscillation", "EXPERIMENTS", "METRICS", "HF_CUTOFF", "HF_TAIL",
           "LC_DURATION", "LC_MAX_DURATION", "LC_PERIODS", "TORQUE_HELD", "effort_rms", "hf_share",
           "limit_cycle", "oscillation", "scaled", "experiment", "design_for"]

#: Above this frequency the motor torque's power counts as high-frequency content [Hz]: one
#: decade above the fastest of the paper's loops (rise time 0.22 s, a bandwidth of ~1.6 Hz)
#: and a tenth of the 250 Hz Nyquist frequency of Ts = 2 ms; chatter of a relay-like
#: compensator (sign(omega_hat) switching) lands above it.
HF_CUTOFF = 25.0
#: First length of the limit-cycle run [s]: Fig. 14's 3 s step twice over, so that the step's
#: transient (the PD design's slowest mode, tau = 1/min|Re p| = 0.05 s on the paper's bench; 0.55 s
#: with the integral's PID) has the run's first half to die out.  It is not the length the verdict
#: rests on: the run is doubled until :func:`oscillation` judges its last half.
LC_DURATION = 6.0
#: Longest limit-cycle run [s] (LC_DURATION doubled six times): a compute budget, not a property of
#: any loop (384 s at Ts = 2 ms is 192 000 samples, a fraction of a second in the compiled loop).  A
#: stick-slip cycle's period grows as its state winds more slowly (the integral's ~ 4 Fs/(Ki A) for
#: an amplitude A); one too slow for this budget is reported as not judged, with the reason.
LC_MAX_DURATION = 64 * LC_DURATION
#: Full periods the last half of the run must hold for a limit cycle to be measured [-]: two, so
#: that the amplitude of the first can be compared with that of the second (sustained, not a
#: decaying ring; :data:`fricctl.paper.runaway.STEADY` is the least ratio).
LC_PERIODS = 2
#: A motor torque that changes by at most this share of its largest magnitude over the run's last
#: half is held [-]: rounding level.  A joint at rest under a held torque stays at rest (the loop
#: is deterministic and its reference held); one whose torque still moves (an integral or a DOB
#: winding up against the stuck joint) will break away, so its rest is no verdict.
TORQUE_HELD = 1e-9
#: The high-frequency share is measured over the last this share of each run [-]: after the
#: transient, where chatter is what is left (a PD step's first sample holds the derivative kick,
#: a one-sample spike whose flat spectrum would otherwise count as high-frequency content).
HF_TAIL = 0.4

#: Metric -> (unit, what it measures).
METRICS = MappingProxyType({
    "dead_zone": ("% of Tmax", "open-loop torque dead zone with the compensator (sinusoid amplitudes "
                  "0.25-20 % of Tmax, 1 Hz; moves = more than 3 encoder counts)"),
    "dead_zone_factor": ("-", "dead zone without compensation / with it, on the same plant"),
    "steady_state_error": ("deg", "largest |mean(r - q)| over the last 0.5 s, over the experiment's steps"),
    "tracking_rms": ("deg", "RMS of r - q over the whole run"),
    "stick_slip_cycles": ("cycles", "rests of >= 20 ms after first motion that end in motion"),
    "coast_excess": ("%", "largest excess of |omega| over the viscous decay after the pulse, in % "
                     "of |omega| at its end (fricctl.paper.runaway.coast_decay)"),
    "limit_cycle_amplitude": ("deg", "half the peak-to-peak of q over the last half of the limit-cycle run, "
                              "once judged (fricctl.compare.oscillation): a sustained cycle's, 0 at rest; "
                              "none when not judged"),
    "limit_cycle_frequency": ("Hz", "half the rate of crossings of q through its mean over that half of a "
                              f"sustained cycle (at least {LC_PERIODS} full periods); 0 at rest or below half "
                              "an encoder count of amplitude; none when not judged"),
    "limit_cycle_duration": ("s", f"length of the limit-cycle run the verdict needed ({LC_DURATION:g} s "
                             f"doubled until judged, at most {LC_MAX_DURATION:g} s)"),
    "effort_rms": ("N*m", "RMS of the motor torque Tm over the run(s)"),
    "effort_hf_share": ("%", f"share of the motor torque's variance above {HF_CUTOFF:g} Hz over the last "
                        f"{100 * HF_TAIL:.0f} % of each run (mean over runs)"),
})


@dataclass(frozen=True, kw_only=True, eq=False)
class Outcome:
    """What one experiment measured with one compensator on one plant.

    Attributes
    ----------
    metrics : metric name -> value, in the unit of :data:`METRICS`
    checks : the runaway checks of its compensated runs (:class:`~fricctl.paper.RunawayCheck`)
    warnings : one line each: what the experiment could not judge, and where a network ran
        outside its training envelope (its row shows them)
    """

    metrics: Mapping
    checks: tuple
    warnings: tuple = ()


# --------------------------------------------------------------------------- measurements
def effort_rms(torque) -> float:
    """RMS of a torque record [N*m] (any shape: over every sample)."""
    x = np.asarray(torque, dtype=float)
    return float(np.sqrt(np.mean(x * x)))


def hf_share(torque, sample_time: float, cutoff: float = HF_CUTOFF) -> float:
    """Share of a torque record's variance above ``cutoff`` [Hz], in % (0 for a constant record).

    The mean is removed first (a held torque is not high-frequency content); the shares of the
    periodogram's bins above ``cutoff`` are summed.  A record whose standard deviation is at
    rounding level (below 1e-9 of its RMS) is constant: 0.

    Examples
    --------
    >>> t = 0.002 * np.arange(1000)
    >>> round(hf_share(np.sin(2 * np.pi * 100 * t), 0.002), 6)     # all at 100 Hz
    100.0
    >>> round(hf_share(1 + np.sin(2 * np.pi * 2 * t), 0.002), 6)    # all at 2 Hz
    0.0
    """
    x = np.asarray(torque, dtype=float)
    if not np.std(x) > 1e-9 * effort_rms(x):
        return 0.0
    x = x - x.mean()
    p = np.abs(np.fft.rfft(x)) ** 2
    f = np.fft.rfftfreq(x.size, sample_time)
    total = float(p[f > 0].sum())
    return 100.0 * float(p[f > cutoff].sum()) / total if total > 0 else 0.0


def _crossings(x: np.ndarray, resolution: float) -> np.ndarray:
    """Indices where ``x`` (a record minus its mean) changes sign, counted only where it is more
    than a quarter count from 0 (a hysteresis: the encoder's flicker is no crossing)."""
    idx = np.flatnonzero(np.abs(x) > 0.25 * resolution)
    s = np.sign(x[idx])
    return idx[1:][s[1:] != s[:-1]]


def limit_cycle(t, q, resolution: float, window: float | None = None) -> tuple[float, float]:
    """Amplitude [rad] and frequency [Hz] of the oscillation of ``q`` over the last ``window`` s.

    The amplitude is half the peak-to-peak; the frequency is half the rate of crossings of the
    window's mean between the first and the last crossing (a crossing counted only where ``q``
    is more than a quarter count from the mean).  Below half an encoder count of amplitude there
    is no limit cycle the controller could see, and fewer than three crossings are no full
    period: frequency 0.  ``window`` None: the record's last half.  (Whether the oscillation is
    sustained, and the record long enough to tell, is :func:`oscillation`'s question.)

    Examples
    --------
    >>> t = 0.002 * np.arange(3000)
    >>> a, f = limit_cycle(t, 1e-3 * np.sin(2 * np.pi * 5 * t), 1e-4, window=2.0)
    >>> round(a, 6), round(f, 2)
    (0.001, 5.0)
    """
    t, q = np.asarray(t, dtype=float), np.asarray(q, dtype=float)
    if window is None:
        sel = np.arange(t.size) >= t.size // 2
    else:
        sel = t >= t[-1] - v.real("window", window, positive=True, unit="s") + 1e-12
    ts, seg = t[sel], q[sel]
    amp = 0.5 * float(seg.max() - seg.min())
    if amp < 0.5 * resolution:
        return amp, 0.0
    cross = _crossings(seg - seg.mean(), resolution)
    if cross.size < 3:
        return amp, 0.0
    return amp, float((cross.size - 1) / (2.0 * (ts[cross[-1]] - ts[cross[0]])))


@dataclass(frozen=True, kw_only=True)
class Oscillation:
    """The verdict of :func:`oscillation` on one run's last half.

    Attributes
    ----------
    verdict : ``"limit cycle"`` (at least :data:`LC_PERIODS` sustained periods), ``"none"`` (the
        joint at rest under a held torque, or moving less than half an encoder count) or ``"not
        judged"`` (neither: a joint at rest whose torque still winds, a transient, a creep, a
        cycle slower than the record)
    amplitude : half the peak-to-peak of q over the last half [rad] (nan when not judged)
    frequency : the cycle's frequency [Hz] (0 for none, nan when not judged)
    duration : the run's length [s]
    reason : one line: what the record showed
    """

    verdict: str
    amplitude: float
    frequency: float
    duration: float
    reason: str


def oscillation(run: SimResult, *, periods: int = LC_PERIODS, steady: float = STEADY,
                held: float = TORQUE_HELD) -> Oscillation:
    """Is there a sustained limit cycle in the last half of ``run``, none, or can it not tell?

    Read on the run's last half (its first half is the transient's), in this order:

    * the true position moves less than half an encoder count: **none**, unless the encoder
      reads the joint at rest while the motor torque still changes (by more than ``held`` of
      its largest magnitude): a state winding up against a stuck joint (an integral, a DOB) is
      the stick phase of a stick-slip cycle, and the breakaway it leads to may come after the
      record ends -- **not judged**;
    * the position crosses its mean at least ``2*periods + 1`` times (``periods`` full periods)
      and the swing of the last two half-cycles is at least ``steady`` times that of the first
      two (sustained, or growing): **limit cycle**, its amplitude (half the peak-to-peak) and
      frequency (half the rate of crossings, :func:`limit_cycle`);
    * otherwise -- a swing of fewer periods, or one that decays -- **not judged**.

    Parameters
    ----------
    run : SimResult
        A closed-loop run whose reference is held over its last half.
    periods : int
        Full periods the last half must hold (>= 1; :data:`LC_PERIODS`) [-].
    steady : float
        Least ratio of the last two half-cycles' swing to the first two's that counts as
        sustained (> 0; :data:`fricctl.paper.runaway.STEADY`) [-].
    held : float
        Share of the largest ``|Tm|`` up to which the motor torque counts as held (>= 0;
        :data:`TORQUE_HELD`) [-].

    Returns
    -------
    Oscillation

    Notes
    -----
    A joint at rest under a held torque is at rest for good only because the loop is
    deterministic; with torque noise at the joint the held command is still the verdict's
    test (the noise is not in the commanded torque).  A cycle whose period is longer than half
    of the last half is not seen: the record is too short to judge it, and says so.
    """
    r = v.instance("run", run, SimResult, "a SimResult (fricctl.simulate)")
    periods = v.integer("periods", periods, low=1)
    steady = v.real("steady", steady, positive=True)
    held = v.real("held", held, nonneg=True)
    if r.t.size < 4:
        raise ValueError("run must hold at least 4 samples")
    res = r.info.encoder_resolution
    half = r.t.size // 2
    duration = round(r.t.size * r.sample_time, 9)  # the samples' span, not t[-1] + Ts's rounding
    q, y, tm = r.q[half:], r.q_meas[half:], r.torque_motor[half:]
    span = f"the last {duration - float(r.t[half]):.4g} s of a {duration:.4g} s run"
    amp, freq = limit_cycle(r.t, r.q, res)
    if amp < 0.5 * res:
        moved = float(np.ptp(tm))
        if np.ptp(y) == 0.0 and moved > held * float(np.max(np.abs(r.torque_motor))):
            return Oscillation(verdict="not judged", amplitude=math.nan, frequency=math.nan,
                               duration=duration,
                               reason=f"not judged: the joint is at rest over {span} while its motor torque "
                                      f"still changes by {moved:.3g} N*m (a state winding up against the "
                                      "stuck joint: a breakaway may come after the record)")
        what = "at rest under a held torque" if np.ptp(y) == 0.0 else \
            f"moving {amp / res:.2g} encoder count(s), under half a count"
        return Oscillation(verdict="none", amplitude=amp, frequency=0.0, duration=duration,
                           reason=f"no limit cycle: the joint is {what} over {span}")
    x = q - q.mean()
    cross = _crossings(x, res)
    if cross.size >= 2 * periods + 1:
        swing = [float(np.max(np.abs(x[a:b]))) for a, b in zip(cross[:-1], cross[1:])]
        first, last = swing[0] + swing[1], swing[-2] + swing[-1]
        if last >= steady * first:
            return Oscillation(verdict="limit cycle", amplitude=amp, frequency=freq, duration=duration,
                               reason=f"limit cycle: {(cross.size - 1) / 2:g} periods of {1 / freq:.3g} s "
                                      f"over {span}, swing held ({100 * last / first:.0f} % of the first "
                                      f"half-cycles'), amplitude {np.rad2deg(amp):.3g} deg")
        why = f"a swing that decays ({100 * last / first:.0f} % of its first half-cycles', under " \
              f"{100 * steady:g} %)"
    else:
        why = f"a swing with {max(cross.size - 1, 0) / 2:g} period(s), under {periods}"
    return Oscillation(verdict="not judged", amplitude=math.nan, frequency=math.nan, duration=duration,
                       reason=f"not judged: the joint moves {np.rad2deg(amp):.3g} deg over {span}: {why}")


def scaled(compensator: Compensator, scale: float) -> Compensator:
    """The compensator with its compensation scale s = ``scale`` (itself when s = 1).

    Raises
    ------
    ValueError
        For a compensator without a ``scale`` field (its output cannot be scaled here).
    """
    if scale == 1.0:
        return compensator
    if not (is_dataclass(compensator) and any(f.name == "scale" for f in fields(compensator))):
        raise ValueError(f"compensator {compensator.name!r} has no compensation scale to set to {scale:g}")
    return replace(compensator, scale=float(scale))


# --------------------------------------------------------------------------- the experiments
@dataclass(frozen=True, kw_only=True)
class Experiment:
    """One experiment of the comparison.

    Attributes
    ----------
    name : its name in rows and on the command line
    description : one line
    design : the key of :func:`fricctl.paper.common.designs` the compensator is made for (and,
        closed loop, the loop's controller)
    linked : whether it runs the paper's link (Figs. 16-18: the bench's ``linked_actuator``)
    closed_loop : whether a position loop runs (a reference to track); open loop (the dead zone,
        the coast test), a compensator that acts on the position error is not applicable
    metrics : the metrics it reports (keys of :data:`METRICS`)
    run : ``run(bench, realised, compensator, design, rng) -> Outcome`` (``rng``: the torque
        noise's generator, used only on a plant with noise)
    """

    name: str
    description: str
    design: str
    linked: bool
    metrics: tuple
    run: Callable
    closed_loop: bool = True


def _loop(pl, rng) -> dict:
    """The simulator's arguments of the plant: true friction, delay, torque noise."""
    return dict(friction=pl.friction, delay=pl.delay, noise_std=pl.noise_std,
                rng=rng if pl.noise_std > 0 else None)


def _envelope(comp, runs, ts) -> tuple:
    """Where a network compensator drove its net outside the net's training envelope over the
    experiment's runs: how long and how far (:func:`fricctl.nn.envelope.excursion_warnings`;
    inputs Tm_k and omega_hat_k).  Empty for any other compensator, or a run inside it."""
    from ..compensators.network import NNCompensator
    from ..compensators.nn_confirmed import ConfirmedNNCompensator
    from ..nn import FrictionNet
    from ..nn.envelope import excursion, excursion_warnings

    if not (isinstance(comp, (NNCompensator, ConfirmedNNCompensator))
            and isinstance(comp.estimator, FrictionNet)):
        return ()
    tm = np.concatenate([np.ravel(r.torque_motor) for r in runs])
    om = np.concatenate([np.ravel(r.omega_hat) for r in runs])
    return tuple(excursion_warnings(excursion(comp.estimator, tm, om, ts), clipped=comp.clip))


def _effort(runs_tm, ts) -> dict:
    tm = np.asarray(runs_tm, dtype=float)
    tm2 = tm.reshape(-1, tm.shape[-1])
    tail = tm2[:, int(round((1 - HF_TAIL) * tm2.shape[1])):]
    return {"effort_rms": effort_rms(tm2),
            "effort_hf_share": float(np.mean([hf_share(x, ts) for x in tail]))}


def _dead_zone(bench, pl, comp, design, rng) -> Outcome:
    p = pl.params
    dz1 = dead_zone(p, comp, **_loop(pl, rng))
    dz0 = dead_zone(p, NoCompensation(), **_loop(pl, rng))
    # Fig. 10's run: a sinusoid at 10 % of Tmax, 1 Hz, 3 s (its runaway checks and effort)
    c = ctl.open_loop(ctl.sinusoid(0.10 * p.max_torque, 1.0))
    r = simulate(p, c, comp, duration=3.0, **_loop(pl, rng))
    factor = dz0.dead_zone / dz1.dead_zone if dz1.dead_zone > 0 else math.inf
    return Outcome(metrics={"dead_zone": 100 * dz1.fraction, "dead_zone_factor": factor,
                            **_effort(r.torque_motor, p.sample_time)},
                   checks=(torque_check(r, comp), reversal(r, 1.0)),
                   warnings=_envelope(comp, [r], p.sample_time))


def _steps(bench, pl, comp, design, rng, steps, duration) -> Outcome:
    p = pl.params
    ctrls = [ctl.pd_control(design.kp, design.kd, ctl.step(float(x))) for x in steps]
    b = simulate_batch(p, ctrls, comp, duration=duration, **_loop(pl, rng))
    e = np.abs(np.asarray(b.steady_state_error(SS_WINDOW)))
    return Outcome(metrics={"steady_state_error": float(np.rad2deg(e.max())),
                            **_effort(b.torque_motor, p.sample_time)},
                   checks=tuple(torque_check(b[i], comp) for i in range(len(b))),
                   warnings=_envelope(comp, [b], p.sample_time))


def _pd_steps(bench, pl, comp, design, rng) -> Outcome:
    return _steps(bench, pl, comp, design, rng, np.deg2rad(np.asarray(STEPS_DEG)), 3.0)


def _small_steps(bench, pl, comp, design, rng) -> Outcome:
    return _steps(bench, pl, comp, design, rng, (-0.08, 0.08), 3.0)


def _sawtooth(bench, pl, comp, design, rng) -> Outcome:
    p = pl.params
    amp, period = bench.fig18_amplitude, bench.fig18_period
    c = ctl.pd_control(design.kp, design.kd, ctl.sawtooth(amp, period))
    r = simulate(p, c, comp, duration=2 * period, **_loop(pl, rng))
    return Outcome(metrics={"tracking_rms": float(np.rad2deg(np.sqrt(np.mean(r.error ** 2)))),
                            "stick_slip_cycles": float(restarts(r)),
                            **_effort(r.torque_motor, p.sample_time)},
                   checks=(torque_check(r, comp),), warnings=_envelope(comp, [r], p.sample_time))


def _coast(bench, pl, comp, design, rng) -> Outcome:
    p = pl.params
    amp = coast_test.PULSE_FACTOR * p.static
    c = ctl.open_loop(ctl.sequence([amp, 0.0], [coast_test.PULSE_DURATION, coast_test.COAST_DURATION]))
    r = simulate(p, c, comp, duration=coast_test.PULSE_DURATION + coast_test.COAST_DURATION,
                 **_loop(pl, rng))
    # Tc(k) reaches the joint as Tm(k+1+delay): the pulse acts until then (as fricctl.paper.coast)
    off = np.flatnonzero((r.t > 0) & (r.torque_cmd == 0.0))
    k_end = int(off[0]) + 1 + pl.delay
    decay = coast_decay(r, float(r.t[k_end]))
    return Outcome(metrics={"coast_excess": decay.value, **_effort(r.torque_motor, p.sample_time)},
                   checks=(decay, torque_check(r, comp)),
                   warnings=_envelope(comp, [r], p.sample_time))


def _limit_cycle(bench, pl, comp, design, rng) -> Outcome:
    p = pl.params
    c = ctl.pd_control(design.kp, design.kd, ctl.step(float(np.deg2rad(30.0))))
    duration = LC_DURATION
    while True:  # doubled until the record judges (see the module's Notes); each try the same noise
        r = simulate(p, c, comp, duration=duration, **_loop(pl, copy.deepcopy(rng)))
        osc = oscillation(r)
        if osc.verdict != "not judged" or 2 * duration > LC_MAX_DURATION:
            break
        duration *= 2
    return Outcome(metrics={"limit_cycle_amplitude": float(np.rad2deg(osc.amplitude)),
                            "limit_cycle_frequency": osc.frequency, "limit_cycle_duration": duration,
                            **_effort(r.torque_motor, p.sample_time)},
                   # the cycle measured is the slowest oscillation the divergence check must see
                   checks=(torque_check(r, comp, period=1.0 / osc.frequency if osc.frequency > 0 else None),),
                   warnings=((osc.reason,) if osc.verdict == "not judged" else ())
                   + _envelope(comp, [r], p.sample_time))


_EFFORT = ("effort_rms", "effort_hf_share")

#: Experiment name -> :class:`Experiment` (read-only), in table order.
EXPERIMENTS: Mapping[str, Experiment] = MappingProxyType({e.name: e for e in (
    Experiment(name="dead_zone", description="open-loop dead zone, and a sinusoid at 10 % of Tmax (Fig. 10)",
               design="fig13-14", linked=False, metrics=("dead_zone", "dead_zone_factor") + _EFFORT,
               run=_dead_zone, closed_loop=False),
    Experiment(name="pd_steps", description="PD (0.3 s, 0.9) steps of +-5 .. 40 deg, 3 s (Fig. 14)",
               design="fig13-14", linked=False, metrics=("steady_state_error",) + _EFFORT, run=_pd_steps),
    Experiment(name="small_steps", description="steps of +-0.08 rad with the link, PD (0.4 s, 0.85) "
               "(Fig. 17)", design="fig16-17", linked=True, metrics=("steady_state_error",) + _EFFORT,
               run=_small_steps),
    Experiment(name="sawtooth", description="the bench's sawtooth with the link, two periods (Fig. 18)",
               design="fig18", linked=True, metrics=("tracking_rms", "stick_slip_cycles") + _EFFORT,
               run=_sawtooth),
    Experiment(name="coast", description="open-loop pulse of 2 Fs for 0.3 s, then Tc = 0 for 2 s "
               "(the coast test)", design="fig13-14", linked=False, metrics=("coast_excess",) + _EFFORT,
               run=_coast, closed_loop=False),
    Experiment(name="limit_cycle", description=f"PD step of 30 deg held {LC_DURATION:g} s, doubled until the "
               f"last half judges (at most {LC_MAX_DURATION:g} s): chatter, hunting", design="fig13-14",
               linked=False, metrics=("limit_cycle_amplitude", "limit_cycle_frequency", "limit_cycle_duration")
               + _EFFORT, run=_limit_cycle),
)})


def experiment(name: str) -> Experiment:
    """The experiment called ``name``; ``ValueError`` listing the names otherwise."""
    if not isinstance(name, str) or name not in EXPERIMENTS:
        raise ValueError(f"unknown experiment {name!r}; choose from {', '.join(EXPERIMENTS)}")
    return EXPERIMENTS[name]


def design_for(bench, name: str):
    """The design the experiment ``name`` runs on ``bench``."""
    return designs(bench)[experiment(name).design]
