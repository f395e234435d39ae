"""Records with one hidden effect, made on the virtual bench (seeded).

:func:`hidden_effect_record` builds a measured record (:class:`~fricctl.datasets.Run`)
of a randomly drawn actuator (baseline: rigid joint, viscous + Coulomb friction with
stiction at the Coulomb level, the model :func:`fricctl.diagnose.diagnose` fits)
with **one** effect added from :data:`HIDDEN_CAUSES`, under a randomly drawn
excitation.  It is the test bench of the diagnosis: tests hand the record (and, for
the nominal-model causes, the nominal model an engineer would have) to
``diagnose`` and require it to name the effect; they never read the answer from
the returned metadata.

Baseline actuator (drawn per record, load side, around the paper's actuator)
-----------------------------------------------------------------------------
=====================  ===========================  ==============================
quantity               range (uniform)              note
=====================  ===========================  ==============================
actuator inertia       1.5e-3 .. 4.5e-3 kg*m^2      paper: 2.87e-3 (derived)
link inertia           0 .. 6e-3 kg*m^2             paper's SCARA link: 4.6e-3
viscous b              0.008 .. 0.030 N*m*s/rad     paper: 0.0169
Coulomb Fc             0.08 .. 0.25 N*m             paper: 0.144 (assumed 0.8*Fs)
torque noise (joint)   1 .. 3 % of Fc (std)         white, N*m
encoder                3.14e-5 rad per count        paper actuator (2000 counts, n=100)
torque limit           12 * Fc                      paper: Fs = 12.7 % of Tmax
=====================  ===========================  ==============================

Hidden effects and their magnitudes
-----------------------------------
Each cause module of :mod:`fricctl.diagnose.causes` says how the bench hides its
effect (its ``inject`` function, ranges in its docstring's "Bench:" line):
:data:`HIDDEN_CAUSES` and :data:`NOMINAL_CAUSES` come from that registry, so a new
cause module is hidden here without an edit.  ``none`` adds nothing.

The lower ends are the sizes the issue requires to be found (ripple 20 % of Fc,
Stribeck excess 50 %, delay 4 samples, 25 % drift); each range starts where the
effect lowers the held-out torque residual or windowed simulation error by well
over 10 % on these excitations (measured in ``benchmarks/bench_diagnose.py``).

Excitation (drawn per record)
-----------------------------
The record is a random sequence of segments, every kind present once in each
half of the record (so that blocked cross-validation sees it in more than one
block), in random order, with random durations and levels: open-loop torque steps in both
directions (1.3-2.5 x breakaway, with pauses), an open-loop torque sinusoid,
PD tracking of a slow sinusoid (peak speed 0.03-0.4 rad/s, stick-slip), PD
tracking of a fast one (peak speed 2-8 rad/s), and PD tracking of a trapezoidal
(constant speed 0.1-3 rad/s) reference.  PD gains are drawn for a closed-loop
natural frequency of 2-4.5 Hz, damping 0.7.  The loop has the timing of
:mod:`fricctl.simulate` (ZOH at Ts, one sample of computation delay, backward
difference velocity, quantised encoder).

Notes
-----
Left out: measurement noise on the recorded torque (only process noise at the
joint), a position-dependent inertia or gravity, combined effects (exactly one is
hidden; chapter 08 shows the paper's combined inertia + 0.95 case by hand).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .. import _validate as v
from ..datasets import Run
from ..plant import JointModel
from ..simulate import Schedule, simulate_schedule
# The bench reads the cause registry: each cause module says how the bench hides it.
# Layering: this generator is the diagnosis's test bench and sits beside it, above
# fricctl.diagnose (which never imports fricctl.bench); fricctl.bench.experiments does not
# import it, so the paper's experiments stay below the diagnosis.
from ..diagnose import causes

__all__ = ["HIDDEN_CAUSES", "NOMINAL_CAUSES", "HiddenEffectRecord", "hidden_effect_record",
           "ENCODER_RESOLUTION"]

#: Effects the generator hides without a nominal model (``none`` included), from the registry.
HIDDEN_CAUSES = (causes.NONE,) + tuple(c.name for c in causes.candidates(nominal=False))
#: Effects that only exist against a supplied nominal model.
NOMINAL_CAUSES = causes.NOMINAL_ONLY

#: Load-side encoder count of the paper actuator [rad] (2000 counts/rev, n = 100).
ENCODER_RESOLUTION = 2.0 * math.pi / (2000 * 100)


@dataclass(frozen=True, kw_only=True, eq=False)
class HiddenEffectRecord:
    """A generated record and what was hidden in it.

    Attributes
    ----------
    run : Run
        The measured record (t, recorded torque, encoder position, reference).
    nominal : JointModel or None
        The nominal model an engineer would hold (the true baseline actuator) for
        the nominal-model causes and ``none`` drawn with ``nominal=True``; else None.
    cause : str
        The hidden cause (ground truth; tests must not pass it to the diagnosis).
    magnitude : dict
        Parameters of the hidden effect (SI units).
    truth : JointModel
        The complete true model (baseline + effect).
    excitation : tuple of str
        The segments, in order.
    """

    run: Run
    nominal: JointModel | None
    cause: str
    magnitude: dict = field(default_factory=dict)
    truth: JointModel
    excitation: tuple = ()


# ----------------------------------------------------------------------------- excitation
_SEGMENTS = ("torque_steps", "torque_sine", "slow_tracking", "fast_tracking", "ramps")


def _segment(kind, rng, n, ts, inertia, breakaway, viscous, tmax):
    """(kp, kd, ref, ff) arrays of one segment of n samples."""
    t = np.arange(n) * ts
    zeros = np.zeros(n)
    if kind in ("torque_steps", "torque_sine"):
        kp = kd = zeros
        ref = zeros
        if kind == "torque_steps":
            ff = np.zeros(n)
            k = 0
            sign = rng.choice((-1.0, 1.0))
            while k < n:
                on = int(rng.uniform(0.25, 0.8) / ts)
                off = int(rng.uniform(0.15, 0.4) / ts)
                ff[k:k + on] = sign * rng.uniform(1.3, 2.5) * breakaway
                sign = -sign if rng.random() < 0.8 else sign
                k += on + off
        else:
            amp = rng.uniform(1.3, 2.5) * breakaway
            f = rng.uniform(0.4, 1.5)
            ff = amp * np.sin(2 * np.pi * f * t) * np.minimum(1.0, t / 0.2)
            ff[-int(0.2 / ts):] = 0.0  # let it coast to rest
        return kp, kd, ref, ff
    wn = 2 * np.pi * rng.uniform(2.0, 4.5)
    kp = np.full(n, inertia * wn ** 2)
    kd = np.full(n, max(2 * 0.7 * wn * inertia - viscous, 0.0))
    ff = zeros
    if kind == "slow_tracking":
        vpk = rng.uniform(0.03, 0.4)
        f = rng.uniform(0.1, 0.4)
        amp = vpk / (2 * np.pi * f)
        ref = amp * (1 - np.cos(2 * np.pi * f * t)) * rng.choice((-1.0, 1.0))
    elif kind == "fast_tracking":
        f = rng.uniform(0.5, 1.5)
        vpk = rng.uniform(2.0, 8.0)
        amax = 0.5 * (tmax - 1.5 * breakaway) / inertia
        vpk = min(vpk, amax / (2 * np.pi * f))
        amp = vpk / (2 * np.pi * f)
        ref = amp * (1 - np.cos(2 * np.pi * f * t)) * rng.choice((-1.0, 1.0))
    else:  # trapezoids: constant-speed plateaus both ways, random speeds
        ref = np.zeros(n)
        v = np.zeros(n)
        k = 0
        sign = rng.choice((-1.0, 1.0))
        while k < n:
            m = int(rng.uniform(0.6, 1.5) / ts)
            v[k:k + m] = sign * math.exp(rng.uniform(math.log(0.1), math.log(3.0)))
            sign = -sign
            k += m
        # smooth the speed steps (0.1 s) so the reference is trackable
        w = max(int(0.1 / ts), 1)
        v = np.convolve(v, np.ones(w) / w, mode="same")
        ref = np.cumsum(v) * ts
    return kp, kd, ref, ff


def _excitation(rng, n, ts, inertia, breakaway, viscous, tmax):
    # Every kind twice, once in each half of the record, so that the excitation that reveals an
    # effect never lives in a single block of the blocked cross-validation (a term fitted
    # without that block is then unidentifiable and its held-out error explodes).
    first, second = list(_SEGMENTS), list(_SEGMENTS)
    rng.shuffle(first)
    rng.shuffle(second)
    kinds = first + second
    weights = rng.uniform(0.6, 1.4, size=len(kinds))
    lengths = np.floor(weights / weights.sum() * n).astype(int)
    lengths[-1] = n - lengths[:-1].sum()
    parts = [_segment(k, rng, int(m), ts, inertia, breakaway, viscous, tmax)
             for k, m in zip(kinds, lengths)]
    kp, kd, ref, ff = (np.concatenate([p[i] for p in parts]) for i in range(4))
    start = np.zeros(n, dtype=np.bool_)
    start[np.concatenate([[0], np.cumsum(lengths)[:-1]])] = True
    return tuple(kinds), kp, kd, ref, ff, start


# ----------------------------------------------------------------------------- generator
def hidden_effect_record(rng: np.random.Generator, *, cause: str | None = None,
                         duration: float = 40.0, sample_time: float = 0.002,
                         nominal: bool = False, noise: bool = True) -> HiddenEffectRecord:
    """Simulate one record with one hidden effect drawn at random.

    Parameters
    ----------
    rng : numpy.random.Generator
        All randomness (actuator, effect, magnitude, excitation, noise).
    cause : str, optional
        Force this cause (a name of :data:`HIDDEN_CAUSES` or :data:`NOMINAL_CAUSES`);
        default: drawn uniformly from :data:`HIDDEN_CAUSES`, or from ``("none",) +
        NOMINAL_CAUSES`` when ``nominal`` is true.
    duration : float
        Record length [s], 10 .. 120.
    sample_time : float
        Ts [s], 0.0005 .. 0.005.
    nominal : bool
        Also return the nominal model (the true baseline actuator).  Implied by
        the nominal-model causes.
    noise : bool
        Torque noise at the joint on (default) or off (the draws are made either
        way, so a seed gives the same record apart from the noise).

    Returns
    -------
    HiddenEffectRecord

    Notes
    -----
    The draws come in a fixed sequence: the cause (when not forced), the actuator
    (Jm, Jl, b, Fc, noise level), the effect's magnitudes (the cause module's
    ``inject``), the excitation, the noise.

    Examples
    --------
    >>> import numpy as np
    >>> rec = hidden_effect_record(np.random.default_rng(1), cause="none", duration=10.0)
    >>> rec.run.n_samples, rec.nominal is None
    (5000, True)
    """
    v.rng("rng", rng)
    duration = v.real("duration", duration, low=10.0, high=120.0, unit="s")
    ts = v.real("sample_time", sample_time, low=5e-4, high=5e-3, unit="s")
    nominal = v.flag("nominal", nominal)
    noise = v.flag("noise", noise)
    if cause is None:
        pool = (causes.NONE,) + NOMINAL_CAUSES if nominal else HIDDEN_CAUSES
        cause = str(rng.choice(pool))
    cause = v.choice("cause", cause, HIDDEN_CAUSES + NOMINAL_CAUSES)
    nominal = nominal or cause in NOMINAL_CAUSES

    n = int(round(duration / ts))
    jm = rng.uniform(1.5e-3, 4.5e-3)
    jl = rng.uniform(0.0, 6e-3)
    b = rng.uniform(0.008, 0.030)
    fc = rng.uniform(0.08, 0.25)
    noise_std = rng.uniform(0.01, 0.03) * fc
    tmax = 12.0 * fc
    actuator = causes.BenchActuator(motor_inertia=jm, link_inertia=jl, viscous=b, coulomb=fc,
                                     sample_time=ts, duration=duration,
                                     encoder_resolution=ENCODER_RESOLUTION)
    effect = causes.inject(cause, rng, actuator)

    # the excitation is sized for the heavier of the true and the nominal inertia
    kinds, kp, kd, ref, ff, start = _excitation(
        rng, n, ts, max(effect.truth.inertia, effect.nominal.inertia), effect.breakaway, b, tmax)
    torque_noise = rng.normal(0.0, noise_std, n) * (1.0 if noise else 0.0)
    sim = simulate_schedule(effect.joint, Schedule(kp=kp, kd=kd, reference=ref, feedforward=ff,
                                                   segment_start=start),
                            sample_time=ts, max_torque=tmax, encoder_resolution=ENCODER_RESOLUTION,
                            substeps=int(effect.substeps), delay=int(effect.delay),
                            noise=torque_noise)
    if not (np.all(np.isfinite(sim.q_meas)) and np.all(np.isfinite(sim.torque_motor))):
        raise ValueError("the bench simulation diverged (report this seed)")
    run = Run(t=sim.t, torque=sim.torque_motor, position=sim.q_meas, reference=sim.reference,
              source=f"fricctl virtual bench, hidden effect record ({n} samples)")
    return HiddenEffectRecord(run=run, nominal=effect.nominal if nominal else None, cause=cause,
                              magnitude=effect.magnitude, truth=effect.truth, excitation=kinds)
