"""The signals an identification reads off a record, computed once: the record's own processing.

Velocity and acceleration come from the zero-phase Butterworth + central
difference estimator (:func:`fricctl.estimation.butterworth_central`, cut-off
``fc`` = the band the excitation reaches above the encoder's quantisation noise,
:func:`motion_band`, at most half the Nyquist frequency): the filter is chosen from
what the record shows (its sample rate, encoder step and excitation), never from a
bench's magnitudes.  The torque is first centred on the sample grid
(``(Tm[k-1] + Tm[k])/2``: a held torque acts half a sample before the
central-difference acceleration it causes) and low-passed with the same filter;
every regressor column is low-passed too ("parallel filtering"), so
``LP(Tm) = I*LP(q'') + LP(F)`` holds sample by sample.  Samples at rest (encoder
constant) and a guard of ``1/fc`` around them carry no sliding-friction
information and are left out of the equation error.

These are the signals of :func:`fricctl.identify.identify_record` (the equation-error
start of ``fricctl identify``) and of every diagnosis (:mod:`fricctl.diagnose`): one
processing, so both fit the same numbers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy import signal

from .. import _validate as v
from ..datasets import Run
from ..estimation import ZeroPhaseFilter, butterworth_central, zero_phase_filter
from ..plant import JointModel

__all__ = ["Signals", "estimate_signals", "centred", "delayed", "delay_in_samples", "motion_band",
           "BAND_MARGIN", "MAX_CUTOFF", "SAMPLE_TIME_RANGE"]

#: The excitation's band ends where the encoder's acceleration spectrum (a third of an octave
#: averaged) last stands this many times above its own quantisation noise
#: (:func:`motion_band`) [-].
BAND_MARGIN = 10.0
#: Highest low-pass cut-off, as a fraction of the sample rate: half the Nyquist frequency
#: (the zero-phase 4th-order Butterworth still attenuates 48 dB at Nyquist there) [-].
MAX_CUTOFF = 0.25
#: Samples left out (``exclude`` of :func:`estimate_signals`: an end stop's impacts) take with
#: them every sample at which the low-pass's response to an impulse there still exceeds this
#: fraction of its peak [-].  An impact is a momentum step far above the drive's own braking
#: (3-40 times on the package's bench), and the filtered torque residual it leaves rings at
#: the cut-off: within 1/fc of it (the rest guard) the residual measured 9-12 times the
#: record's elsewhere on two seeded stop records, 2.3-2.7 times within 2/fc, at the record's
#: level beyond 3/fc; the ringing read as a resonance.  At 1e-3 the reach is 2.5-3.8/fc.
EXCLUDE_LEVEL = 1e-3
#: Sample times a diagnosis reads [s]: 1 us to 10 s (a drive's record is sampled at 0.1 Hz to
#: 1 MHz; beyond, the acceleration's 1/Ts^2 and the filters' products leave double precision).
SAMPLE_TIME_RANGE = (1e-6, 10.0)


def delayed(x: np.ndarray, delay: float) -> np.ndarray:
    """``x`` delayed by ``delay`` samples, a fraction by linear interpolation.

    For a torque held over each sample, the interpolated value is the mean torque the
    joint receives over the interval when it acts ``delay`` samples late (exact for the
    momentum it transfers); the first value is held before the record starts.
    """
    x = v.array("x", x, min_size=1)
    delay = v.real("delay", delay, nonneg=True)
    if delay == 0:
        return x.copy()
    i = int(math.floor(delay))
    f = delay - i
    n = x.size
    idx = np.arange(n) - i
    a = x[np.clip(idx, 0, n - 1)]
    if f == 0.0:
        return a
    b = x[np.clip(idx - 1, 0, n - 1)]
    return (1.0 - f) * a + f * b


def centred(tm: np.ndarray, delay: float = 0.0) -> np.ndarray:
    """The torque centred on the sample grid, ``(Tm[k-1] + Tm[k])/2``, delayed by ``delay``
    samples (a fraction of a sample by linear interpolation, :func:`delayed`)."""
    u = np.empty_like(tm)
    u[1:] = 0.5 * (tm[1:] + tm[:-1])
    u[0] = tm[0]
    return delayed(u, delay)


def delay_in_samples(model: JointModel, sample_time: float) -> float:
    """The model's delay in samples of ``sample_time``, a fraction kept [-]."""
    return float(model.delay / sample_time)


@dataclass(frozen=True, kw_only=True, eq=False)
class Signals:
    """Everything the equation error and the windows need, computed once (:func:`estimate_signals`)."""

    t: np.ndarray
    """Sample instants [s]."""
    ts: float
    """Sample time [s]."""
    tm: np.ndarray
    """Recorded torque [N*m]."""
    q: np.ndarray
    """Encoder position [rad]."""
    qf: np.ndarray
    """Filtered position [rad]."""
    w: np.ndarray
    """Velocity estimate, its sign taken from the encoder [rad/s]."""
    seff: np.ndarray
    """Effective sign of the motion per sample (fractional at reversals) [-]."""
    a: np.ndarray
    """Acceleration estimate [rad/s^2]."""
    lp: tuple
    """``(b, a)`` of the low-pass."""
    slide: np.ndarray
    """1.0 where the joint slides, 0.0 at rest (encoder constant)."""
    moving: np.ndarray
    """Samples used by the equation error (bool)."""
    rest: np.ndarray
    """Samples at rest, encoder constant around them (bool)."""
    folds: np.ndarray
    """Block (fold) index per sample."""
    n_folds: int
    """Blocks of the blocked cross-validation."""
    resolution: float
    """Smallest position step seen [rad]."""
    cutoff: float
    """Cut-off of the low-pass [Hz]: the excitation's band, at most half the Nyquist
    frequency."""
    band: float
    """The band the excitation reaches (:func:`motion_band`) [Hz]."""
    units: str
    """``"rotary"`` or ``"linear"``."""
    excluded: np.ndarray | None = None
    """The samples left out of the equation error by the caller (``exclude`` of
    :func:`estimate_signals`: an end stop's contacts), or None; a twin of the record is
    read with the same exclusion."""

    def filt(self, x):
        """Low-pass of ``x`` with the samples at rest zeroed.

        At rest the friction is the reaction that holds the joint, equal to the torque
        it receives (q'' = 0): so the torque and every friction column are zeroed there
        before filtering, and ``LP(Tm*S) = I*LP(q'') + sum_j theta_j*LP(f_j*S)`` holds at
        every sample (S = 1 while sliding), with no filter smear across stops.
        """
        return self._lowpass(np.asarray(x, dtype=float) * self.slide)

    @cached_property
    def _lowpass(self) -> ZeroPhaseFilter:
        """:attr:`lp` checked once (a diagnosis filters a thousand columns through it)."""
        return ZeroPhaseFilter(*self.lp)

    def torque_target(self, delay: float = 0.0, offset: float = 0.0) -> np.ndarray:
        """LP of the sample-centred torque the joint receives, delayed by ``delay`` samples."""
        return self.filt(centred(self.tm, delay)) - offset

    @property
    def sample_rate(self) -> float:
        """1/Ts [Hz]."""
        return 1.0 / self.ts

    def centred(self, delay: float = 0.0) -> np.ndarray:
        """The sample-centred recorded torque, delayed by ``delay`` samples."""
        return centred(self.tm, delay)


def motion_band(q: np.ndarray, ts: float, resolution: float, *,
                margin: float = BAND_MARGIN) -> float:
    """The band the excitation reaches: the highest frequency at which the encoder's motion
    stands above its quantisation noise [Hz].

    The second difference of the encoder record (an acceleration, whitened so that slow
    motion does not leak into high frequencies) is compared per frequency with that of
    white quantisation noise of one count (variance ``res^2/12``), the ratio averaged
    over a third of an octave around each frequency (so that one narrow line -- mains
    pick-up -- does not count as motion, while a resonance does); the band ends at the
    last frequency where that average reaches ``margin``.  Above it an acceleration
    estimate is mostly encoder noise, whatever the sample rate.
    """
    q = v.array("q", q, min_size=3)
    fs = 1.0 / v.real("ts", ts, positive=True, unit="s")
    resolution = v.real("resolution", resolution, nonneg=True)
    margin = v.real("margin", margin, positive=True)
    dd = np.diff(q, 2)
    if resolution <= 0 or dd.size < 64 or not np.any(dd):
        return 0.5 * fs
    nper = int(min(4096, 2 ** math.floor(math.log2(dd.size / 8))))
    f, p = signal.welch(dd, fs=fs, nperseg=nper, detrend=False)
    noise = resolution ** 2 / (6.0 * fs) * (2 * np.sin(np.pi * f / fs)) ** 4
    low = f > 4.0 * fs / nper  # the first few bins hold the record's slow trends
    ratio = np.where(low, p / np.maximum(noise, 1e-300), 0.0)
    csum = np.concatenate([[0.0], np.cumsum(ratio)])
    count = np.concatenate([[0], np.cumsum(low)])
    lo = np.searchsorted(f, f * 2.0 ** (-1.0 / 6.0))
    hi = np.searchsorted(f, f * 2.0 ** (1.0 / 6.0), side="right")
    smooth = (csum[hi] - csum[lo]) / np.maximum(count[hi] - count[lo], 1)
    above = np.flatnonzero(low & (smooth >= margin))
    return float(f[above[-1]]) if above.size else float(f[np.argmax(low)])


def _impulse_reach(b, a, fc_ts: float) -> int:
    """Samples either side of an impulse over which the zero-phase low-pass ``(b, a)``
    responds above :data:`EXCLUDE_LEVEL` of its peak (``fc_ts``: cut-off over sample rate)."""
    half = int(math.ceil(20.0 / fc_ts)) + 8
    x = np.zeros(2 * half + 1)
    x[half] = 1.0
    h = np.abs(zero_phase_filter(b, a, x))
    return int(np.max(np.abs(np.flatnonzero(h > EXCLUDE_LEVEL * h.max()) - half)))


def estimate_signals(run: Run, n_folds: int, *, exclude: np.ndarray | None = None,
                     cutoff: float | None = None) -> Signals:
    """Velocity, acceleration, direction, rest and the blocks of ``run`` (see the module notes).

    The low-pass cut-off is the band the excitation reaches (:func:`motion_band`: above
    it the encoder sees its own quantisation more than the motion), at most
    :data:`MAX_CUTOFF` times the sample rate (or ``cutoff`` [Hz] when given: a twin of a
    record is read through the record's own filter).  ``exclude`` (bool per sample) leaves
    samples out of the equation error, with the filter's reach around them (where its
    response to an impulse exceeds :data:`EXCLUDE_LEVEL` of its peak).
    """
    lo, hi = SAMPLE_TIME_RANGE
    ts = v.real("the record's sample time (time column in seconds)", run.sample_time,
                low=lo, high=hi, unit="s")
    q = np.asarray(run.position, dtype=float)
    n = q.size
    steps = np.abs(np.diff(q))
    nz = steps[steps > 0]
    res = float(np.min(nz)) if nz.size else 0.0
    band = motion_band(q, ts, res)
    if cutoff is None:  # at least 50 cycles of the cut-off over the record, whatever the band
        cutoff = min(MAX_CUTOFF / ts, max(band, 50.0 / (q.size * ts)))
    est = butterworth_central(run.t, run.position, cutoff=cutoff)
    b, a = signal.butter(4, cutoff * 2 * ts)
    # at rest: no encoder change across a sample on either side
    still = np.zeros(n, dtype=bool)
    same = steps == 0.0
    still[1:-1] = same[:-1] & same[1:]
    guard = max(int(math.ceil(1.0 / (cutoff * ts))), 1)
    edge = np.zeros(n, dtype=bool)
    border = max(5 * guard, 20)
    edge[:border] = edge[-border:] = True
    moving = (~still) & (~edge)
    if exclude is not None:
        exclude = np.asarray(exclude, dtype=bool)
        if exclude.shape != (n,):
            raise ValueError(f"exclude: one flag per sample ({n}), got shape {exclude.shape}")
        span = max(_impulse_reach(b, a, cutoff * ts), guard)
        reach = np.convolve(exclude.astype(float), np.ones(2 * span + 1), mode="same") > 0
        moving &= ~reach
    if moving.sum() < 50 * n_folds:
        raise ValueError(f"too little motion: {int(moving.sum())} sliding samples for {n_folds} "
                         f"blocks (need at least {50 * n_folds}); record longer or move more")
    folds = np.minimum((np.arange(n) * n_folds) // n, n_folds - 1)
    active = sum(int(moving[folds == f].sum() >= 20) for f in range(n_folds))
    if active < min(3, n_folds):
        raise ValueError(f"the joint slides in only {active} of {n_folds} blocks of the record; "
                         f"cross-validation needs motion in at least 3")
    # Direction of motion from the encoder, not from the filtered velocity: at a
    # reversal the velocity is kinked (friction flips), and the zero-phase filter
    # moves its zero crossing by a sample or more -- a 2*Fc error there.
    w = np.asarray(est.velocity, dtype=float)
    dq = np.zeros(n)
    dq[1:-1] = q[2:] - q[:-2]
    direction = np.where(dq != 0, np.sign(dq), np.sign(w))
    w = direction * np.abs(w)
    seff = _reversal_signs(q, direction)
    # Acceleration by the narrow second difference of the filtered position: under a
    # held torque it equals the mean of the two torques around the sample exactly
    # ((Tm[k-1] + Tm[k])/2, the centred torque), where central differences applied
    # twice would spread it over four samples with weights 1,3,3,1 and leave a
    # mismatch at every torque or friction jump.
    qf = np.asarray(est.position, dtype=float)
    acc = np.empty(n)
    acc[1:-1] = (qf[2:] - 2 * qf[1:-1] + qf[:-2]) / ts ** 2
    acc[0], acc[-1] = acc[1], acc[-2]
    return Signals(t=np.asarray(run.t, float), ts=ts, tm=np.asarray(run.torque, float), q=q,
                   qf=qf, w=w, seff=seff, a=acc, lp=(b, a), slide=(~still).astype(float),
                   moving=moving, rest=still, folds=folds, n_folds=n_folds, resolution=res,
                   cutoff=cutoff, band=band, units=run.units,
                   excluded=None if exclude is None else np.asarray(exclude, bool).copy())


def _reversal_signs(q: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """The sign of the motion per sample, fractional at the samples around a reversal.

    At a reversal between samples k-1 and k the friction flips inside a sample.
    The reversal instant t* is where the decelerating motion before it stops: the
    vertex of a parabola through the encoder readings k-9 .. k-1 (the motion after
    the reversal is often much slower, and filters or short fits straddling the
    kink place t* late).  Each sample near t* gets the triangle-weighted mean of
    the sign over +-Ts, the weighting of the second difference used for the
    acceleration.
    """
    n = q.size
    seff = direction.copy()
    flips = np.flatnonzero((direction[1:] != direction[:-1]) & (direction[1:] != 0)
                           & (direction[:-1] != 0)) + 1
    flips = flips[(flips >= 10) & (flips <= n - 3)]
    if flips.size:
        loc = np.arange(-9.0, 0.0)          # samples k-9 .. k-1, relative to k
        V = np.column_stack([loc ** 2, loc, np.ones(loc.size)])
        coef = np.linalg.lstsq(V, np.stack([q[k - 9:k] for k in flips]).T, rcond=None)[0]
        with np.errstate(divide="ignore", invalid="ignore"):
            tv = -coef[1] / (2 * coef[0])
        tstar = np.clip(np.nan_to_num(tv, nan=-0.5), -2.0, 1.0)   # relative to k
        for k, ts_ in zip(flips, tstar):
            sb = direction[k - 1]
            for j in range(k - 2, k + 2):
                x = ts_ - (j - k)           # t* relative to sample j
                if x <= -1:
                    wb = 0.0
                elif x <= 0:
                    wb = (x + 1) ** 2 / 2
                elif x < 1:
                    wb = 1 - (1 - x) ** 2 / 2
                else:
                    wb = 1.0
                if direction[j] != 0:
                    seff[j] = sb * (2 * wb - 1)
    return seff
