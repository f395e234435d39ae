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
limit_cycle     a 30 deg PD step held 6 s: oscillation over the last 2 s             Fig. 14
==============  ===================================================================  ===========

Open-loop experiments (dead zone, coast) build the compensator for the PD loop of Fig. 14 (a
compensator that needs the loop's gains gets those), and run it on the open-loop torque.

Notes
-----
The metrics are measured on the simulator's true position and torque (no measurement noise
unless the plant asks for it); the limit cycle is the true position's oscillation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, is_dataclass, replace
from types import MappingProxyType
from typing import Callable, Mapping

import numpy as np

from .. import controllers as ctl
from ..bench.experiments import dead_zone
from ..compensators import Compensator, NoCompensation
from ..paper import coast as coast_test
from ..paper.common import SS_WINDOW, designs, restarts
from ..paper.fig14 import STEPS_DEG
from ..paper.runaway import coast_decay, reversal, torque_check
from ..simulate import simulate, simulate_batch

__all__ = ["Experiment", "Outcome", "EXPERIMENTS", "METRICS", "HF_CUTOFF", "HF_TAIL", "LC_WINDOW",
           "effort_rms", "hf_share", "limit_cycle", "scaled", "experiment", "design_for"]

#: Above this frequency the motor torque's power counts as high-frequency content [Hz]: one
#: decade above the fastest of the paper's loops (rise time 0.22 s, a bandwidth of ~1.6 Hz)
#: and a tenth of the 250 Hz Nyquist frequency of Ts = 2 ms; chatter of a relay-like
#: compensator (sign(omega_hat) switching) lands above it.
HF_CUTOFF = 25.0
#: The window at the end of the limit-cycle run over which the oscillation is measured [s].
LC_WINDOW = 2.0
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
    "limit_cycle_amplitude": ("deg", f"half the peak-to-peak of q over the last {LC_WINDOW:g} s"),
    "limit_cycle_frequency": ("Hz", "half the rate of crossings of q through its mean over that window; 0 "
                              "below half an encoder count of amplitude or under three crossings"),
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
    """

    metrics: Mapping
    checks: tuple


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


def limit_cycle(t, q, resolution: float, window: float = LC_WINDOW) -> tuple[float, float]:
    """Amplitude [rad] and frequency [Hz] of the oscillation of ``q`` over the last ``window`` s.

    The amplitude is half the peak-to-peak; the frequency is half the rate of crossings of the
    window's mean between the first and the last crossing (a crossing counted only where ``q``
    is more than a quarter count from the mean).  Below half an encoder count of amplitude there
    is no limit cycle the controller could see, and fewer than three crossings are no full
    period: frequency 0.

    Examples
    --------
    >>> t = 0.002 * np.arange(3000)
    >>> a, f = limit_cycle(t, 1e-3 * np.sin(2 * np.pi * 5 * t), 1e-4)
    >>> round(a, 6), round(f, 2)
    (0.001, 5.0)
    """
    t, q = np.asarray(t, dtype=float), np.asarray(q, dtype=float)
    sel = t >= t[-1] - window + 1e-12
    ts, seg = t[sel], q[sel]
    amp = 0.5 * float(seg.max() - seg.min())
    if amp < 0.5 * resolution:
        return amp, 0.0
    x = seg - seg.mean()
    idx = np.flatnonzero(np.abs(x) > 0.25 * resolution)
    s = np.sign(x[idx])
    cross = idx[1:][s[1:] != s[:-1]]
    if cross.size < 3:
        return amp, 0.0
    return amp, float((cross.size - 1) / (2.0 * (ts[cross[-1]] - ts[cross[0]])))


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
                   checks=(torque_check(r, comp), reversal(r, 1.0)))


def _steps(bench, pl, comp, design, rng, steps, duration) -> Outcome:
    p = pl.params
    ctrls = [ctl.pd_control(design.kp, design.kd, ctl.step(float(x))) for x in steps]
    b = simulate_batch(p, ctrls, comp, duration=duration, **_loop(pl, rng))
    e = np.abs(np.asarray(b.steady_state_error(SS_WINDOW)))
    return Outcome(metrics={"steady_state_error": float(np.rad2deg(e.max())),
                            **_effort(b.torque_motor, p.sample_time)},
                   checks=tuple(torque_check(b[i], comp) for i in range(len(b))))


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
                   checks=(torque_check(r, comp),))


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
                   checks=(decay, torque_check(r, comp)))


def _limit_cycle(bench, pl, comp, design, rng) -> Outcome:
    p = pl.params
    c = ctl.pd_control(design.kp, design.kd, ctl.step(float(np.deg2rad(30.0))))
    r = simulate(p, c, comp, duration=6.0, **_loop(pl, rng))
    amp, freq = limit_cycle(r.t, r.q, p.encoder_resolution)
    return Outcome(metrics={"limit_cycle_amplitude": float(np.rad2deg(amp)), "limit_cycle_frequency": freq,
                            **_effort(r.torque_motor, p.sample_time)},
                   checks=(torque_check(r, comp),))


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
    Experiment(name="limit_cycle", description=f"PD step of 30 deg held 6 s, the last {LC_WINDOW:g} s "
               "(chatter, hunting)", design="fig13-14", linked=False,
               metrics=("limit_cycle_amplitude", "limit_cycle_frequency") + _EFFORT, run=_limit_cycle),
)})


def experiment(name: str) -> Experiment:
    """The experiment called ``name``; ``ValueError`` listing the names otherwise."""
    if not isinstance(name, str) or name not in EXPERIMENTS:
        raise ValueError(f"unknown experiment {name!r}; choose from {', '.join(EXPERIMENTS)}")
    return EXPERIMENTS[name]


def design_for(bench, name: str):
    """The design the experiment ``name`` runs on ``bench``."""
    return designs(bench)[experiment(name).design]
