"""The record's effect-free twin: what the measuring chain alone lets a candidate "explain".

A term can lower the equation-error residual without any physical effect: the
encoder's quantisation, the filter, the timing of reversals and stops leave a
residual near every event, and a flexible term (a short presliding length, a
resonance, a sub-sample shift) fits part of it.  How much depends on the record (its
rate, encoder, excitation, feedback, noise), so it is measured on the record itself.

The twin: the model as it stands (the baseline fitted on all data, or the nominal
one, with the causes named so far; its constant offset included) is simulated in the sampled loop
(:func:`fricctl.simulate.simulate_schedule`, exact stick-slip) driven by the recorded
torque, plus a slow proportional correction toward the measured position that keeps
it on the record's motion (its bandwidth a fiftieth of the diagnosis's cut-off), and
read through an encoder of the record's resolution.  Where the record was made in
closed loop its torque holds the controller's reaction to the encoder
(``- Kd*w_hat``): the gain is estimated window by window from that reaction above the
excitation's band, where the encoder shows its own quantisation and the torque the
controller's answer to it (:func:`feedback_gains`), and the twin's loop applies it to
its own encoder in place of the record's.  The twin's torque is what its joint
received, corrections included, so its model holds on it exactly: it has the record's
excitation, feedback and measuring chain and no further effect.  Torque noise at the
joint (not in the recorded torque) is added at the level that gives the twin the
held-out residual the record keeps once the candidate's term is in (what is left
besides it: chain, noise and any other effect); noise moves every breakaway and stop,
which the chain turns into a residual far above the noise's own.  The noise is drawn
from a fixed seed: a diagnosis is reproducible.

The candidate is scored on the twin by the same blocked cross-validation, after the
causes already named (:func:`chain_shares`); the held-out fraction of the residual it
removes there -- the chain's share -- is taken off its score on the record, as a fraction of
the record's chain residual (:func:`fricctl.diagnose.selection.net_of_chain`).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np
from scipy import signal

from .. import _validate as v
from ..datasets import Run
from ..plant import JointModel
from ..simulate import Schedule, simulate_schedule
from .causes import Baseline
from .crossval import Problem, advance, cross_validate, empty_variant, full_fit, settle
from .signals import Signals, delay_in_samples, estimate_signals

__all__ = ["Twin", "FeedbackGains", "effect_free_twin", "feedback_gains", "chain_shares",
           "stable_velocity_gain", "TWIN_SEED", "FEEDBACK_SHARE", "MIN_COUNTS", "GAIN_MARGIN"]


@dataclass(frozen=True, kw_only=True, eq=False)
class Twin:
    """The effect-free twin of a record and the residual the chain leaves on it."""

    run: Run
    """The twin record: the recorded torque, the re-simulated encoder position."""
    base: Baseline
    """The baseline as every candidate sees it on the twin."""
    problem: Problem
    """The twin's normal equations."""
    test: np.ndarray
    """Held-out torque residual (sum of squares) per block of the baseline on the twin
    [N^2*m^2]."""
    ran_away: bool = False
    """The twin's torque reached the bound its simulation clips it to (ten times what the
    record and the loop's corrections need): the twin did not stay on the record's motion,
    and its residual is not the measuring chain's (:attr:`rms` is then NaN)."""

    @property
    def rms(self) -> float:
        """Held-out torque residual RMS the measuring chain alone leaves [N*m]; NaN when the
        twin ran away (:attr:`ran_away`)."""
        if self.ran_away:
            return math.nan
        n = max(int(self.base.sig.moving.sum()), 1)
        return math.sqrt(float(np.nansum(self.test)) / n)


#: Seed of the twin's noise sequence (a diagnosis is a function of the record).
TWIN_SEED = 12
#: A window's feedback gains count when they explain this share of the torque's variation
#: above the excitation's band [-].
FEEDBACK_SHARE = 0.3
#: Count changes a window needs for its feedback to be estimated [-].
MIN_COUNTS = 20
#: Gain margin of the twin's loop [-]: its velocity gain is at most the gain at which its
#: sampled loop loses stability (:func:`stable_velocity_gain`) over this factor -- 6 dB, the
#: least margin a designed loop is given.
GAIN_MARGIN = 2.0


@functools.lru_cache(maxsize=None)
def stable_velocity_gain(delay: int = 0) -> float:
    """The velocity gain ``c = Kd*Ts/I`` at which the twin's sampled loop loses stability [-].

    The twin's loop (:func:`_make_twin`, :func:`feedback_gains`): a rigid inertia ``I``
    under a zero-order-hold torque that acts one sample after it is computed, plus
    ``delay`` samples (a named delay), from the encoder's backward difference
    ``Kd*(y[k] - y[k-1])/Ts`` and the proportional gain that goes with it, ``Kp =
    (Kd/1.4)^2/I``.  In the normalised variables ``x = q``, ``v = w*Ts``, ``u*Ts^2/I`` the
    loop depends on ``c`` and ``delay`` alone; the boundary is where its spectral radius
    reaches 1 (bisection to 1e-6; friction and the twin's slow correction, a fiftieth of the
    cut-off, left out).  A rigid analysis: a twin of an elastic model (a named compliance or
    backlash) may lose stability elsewhere; what guards it there is :attr:`Twin.ran_away`.
    The bound ``I/Ts`` (``c = 1``) the twin used until 2026-11-28 is beyond it: ``c`` = 0.518
    without a delay, 0.343 with one sample.

    Examples
    --------
    >>> round(stable_velocity_gain(0), 3), round(stable_velocity_gain(1), 3)
    (0.518, 0.343)
    """
    delay = v.integer("delay", delay, low=0)

    def radius(c: float) -> float:
        p = (c / 1.4) ** 2
        n = 4 + delay  # x_k, v_k, x_{k-1} .. x_{k-2-delay}
        a = np.zeros((n, n))
        u = np.zeros(n)
        u[2 + delay] -= c + p  # the torque of sample k: from x_{k-1-delay} ..
        u[3 + delay] += c  # .. and x_{k-2-delay}
        a[0, :2] = 1.0
        a[0] += 0.5 * u
        a[1, 1] = 1.0
        a[1] += u
        a[2, 0] = 1.0
        for i in range(3, n):
            a[i, i - 1] = 1.0
        return float(np.max(np.abs(np.linalg.eigvals(a))))

    lo, hi = 1e-3, 1e-3
    while radius(hi) <= 1.0 + 1e-12:
        lo, hi = hi, 2.0 * hi
    while hi - lo > 1e-6:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if radius(mid) <= 1.0 + 1e-12 else (lo, mid)
    return lo


@dataclass(frozen=True, kw_only=True, eq=False)
class FeedbackGains:
    """The record's position feedback, per sample (zero where the loop was open)."""

    kp: np.ndarray
    """Proportional gain [N*m/rad] (taken from :attr:`kd`, see :func:`feedback_gains`)."""
    kd: np.ndarray
    """Gain on the backward-difference velocity of the encoder [N*m*s/rad]."""


def feedback_gains(sig: Signals, inertia: float, window: float = 0.5,
                   delay: int = 0) -> FeedbackGains:
    """Estimate the record's velocity feedback ``Tm[k+1] = ... - Kd*(y[k] - y[k-1])/Ts``
    window by window, and a proportional gain to go with it.

    Above the excitation's band (the diagnosis's cut-off) the encoder reading is its own
    quantisation and a closed loop's torque is the controller's answer to it; a window's
    least-squares ``Kd`` counts when the encoder changes count at least :data:`MIN_COUNTS`
    times in it, it explains :data:`FEEDBACK_SHARE` of the torque's variation there and is
    positive (else the window ran open loop, or stood still), held to a twin's loop that stays
    stable with a margin: at most ``I/Ts`` times :func:`stable_velocity_gain` of the
    twin's ``delay`` [samples] over :data:`GAIN_MARGIN`.  (The bound was ``I/Ts``, beyond
    the twin's stability: on a compliant joint of the independent bench, closed loop at
    200 Hz, whose rigid fit holds a third of the inertia, the twin's torque ran to 4907 N*m
    against the record's 1.6, the floor read 6.0 N*m, and a residual of 0.30 N*m with a
    wrong cause was called "explained within noise, 0.05 times the floor".)
    ``Kp`` is not estimated (a set-point step moves the torque and the
    encoder together and biases it): the twin takes the gain of a loop damped at 0.7 with
    that ``Kd``, ``Kp = (Kd/1.4)^2/I``.
    """
    inertia = v.real("inertia", inertia, nonneg=True)
    window = v.real("window", window, positive=True, unit="s")
    delay = v.integer("delay", delay, low=0)
    kd_max = inertia / sig.ts * stable_velocity_gain(delay) / GAIN_MARGIN
    n = sig.t.size
    y = sig.q - sig.q[0]
    wh = np.zeros(n)
    wh[1:] = np.diff(y) / sig.ts
    u = np.concatenate([sig.tm[1:], sig.tm[-1:]])
    nyq = 0.5 / sig.ts
    kd = np.zeros(n)
    if sig.cutoff < 0.9 * nyq and n >= 64 and inertia > 0:
        b, a = signal.butter(2, sig.cutoff / nyq, btype="high")
        hu, hw = signal.filtfilt(b, a, u), signal.filtfilt(b, a, wh)
        length = max(int(round(window / sig.ts)), 32)
        moves = np.concatenate([[0], np.cumsum(np.diff(y) != 0)])
        for k0 in range(0, n, length):
            sl = slice(k0, min(k0 + length, n))
            sww, swu, suu = float(hw[sl] @ hw[sl]), float(hw[sl] @ hu[sl]), float(hu[sl] @ hu[sl])
            if moves[sl.stop - 1] - moves[sl.start] < MIN_COUNTS or sww <= 0 or suu <= 0:
                continue
            gd = -swu / sww
            if gd > 0 and swu * swu / (sww * suu) >= FEEDBACK_SHARE:
                kd[sl] = min(gd, kd_max)
    return FeedbackGains(kp=(kd / 1.4) ** 2 / max(inertia, 1e-300), kd=kd)


def effect_free_twin(base: Baseline, target_sse: float | None = None, *,
                     model: JointModel | None = None, still: Twin | None = None) -> Twin:
    """The record re-made by ``model`` (default: the baseline fitted on all data, or the
    nominal model), through the record's encoder, with the joint torque noise that gives it
    the held-out residual ``target_sse`` (sum of squares) when that exceeds what the chain
    alone leaves (module notes).

    ``still`` is the twin this function returns for the same ``base`` and ``model`` without
    ``target_sse`` (no noise), when the caller has it: it starts every search for the noise,
    so a diagnosis that asks several residuals of one model makes it once (it is returned
    itself when the chain alone leaves ``target_sse``)."""
    sig = base.sig
    model = base.fitted if model is None else model
    if still is not None:
        v.instance("still", still, Twin, "the noise-free Twin of this model (or None)")
    xi = np.random.default_rng(TWIN_SEED).standard_normal(sig.t.size)
    gains = feedback_gains(sig, model.inertia, delay=int(round(delay_in_samples(model, sig.ts))))
    twin = still if still is not None else _make_twin(base, model, np.zeros(sig.t.size), gains)
    sse0 = float(np.sum(twin.test))
    if target_sse is None or not target_sse > sse0 * 1.02:
        return twin
    m = max(int(sig.moving.sum()), 1)
    sigma = math.sqrt((target_sse - sse0) / m)
    # the residual grows as sigma^2 (noise, and the breakaways and stops it moves):
    # one probe gives the slope, the second twin has the record's residual
    for _ in range(2):
        probe = _make_twin(base, model, sigma * xi, gains)
        slope = (float(np.sum(probe.test)) - sse0) / sigma ** 2
        if not slope > 0:
            return probe
        new = math.sqrt((target_sse - sse0) / slope)
        if abs(new / sigma - 1) < 0.1:
            return probe
        sigma = min(new, 10.0 * float(np.std(sig.tm)))
    return _make_twin(base, model, sigma * xi, gains)


def _make_twin(base: Baseline, model: JointModel, noise: np.ndarray,
               gains: FeedbackGains) -> Twin:
    sig = base.sig
    n = sig.t.size
    wn = 2 * math.pi * sig.cutoff / 50.0
    kp_slow = model.inertia * wn ** 2
    y = sig.q - sig.q[0]
    wh = np.zeros(n)
    wh[1:] = np.diff(y) / sig.ts
    # the loop's torque acts one sample after it is computed: feed the recorded torque early;
    # the record's own reaction to its encoder (-Kd*w_hat) is given back, the twin's loop
    # reacts to its own encoder instead
    ff = np.concatenate([sig.tm[1:], sig.tm[-1:]]) + gains.kd * wh
    start = np.zeros(n, dtype=bool)
    start[0] = True
    kp = gains.kp + kp_slow
    tmax = 10.0 * (float(np.max(np.abs(sig.tm))) + float(np.max(kp)) * float(np.ptp(y))
                   + float(np.max(gains.kd * np.abs(wh)))) + 1e-9
    # the joint receives Tm - offset (JointModel.offset): the model's constant torque enters
    # as a constant term of the joint's noise, as fricctl.simulate.simulate_model applies it
    # (left out, the twin's joint lacked the offset its model predicts, and the offset stood
    # in the twin's "measuring chain" residual: on EMPS with the IDIM-LS model the floor was
    # 3.23 N = hypot(3.16, 0.66) instead of 0.66 N, and the record was "explained")
    sim = simulate_schedule(model.joint(), Schedule(kp=kp, kd=gains.kd, reference=y,
                                                     feedforward=ff, segment_start=start),
                            sample_time=sig.ts, max_torque=tmax,
                            encoder_resolution=sig.resolution,
                            delay=int(round(delay_in_samples(model, sig.ts))),
                            noise=noise - model.offset)
    run = Run(t=sig.t, torque=sim.torque_motor, position=sim.q_meas + sig.q[0], units=sig.units,
              source="effect-free twin of the record")
    # read as the record is: its filter, and its end stops' contacts left out
    tsig = estimate_signals(run, sig.n_folds, cutoff=sig.cutoff, exclude=sig.excluded)
    tbase = _twin_baseline(tsig, base)
    problem = Problem(tsig, tbase.columns)
    cv = cross_validate(problem, lambda f: [empty_variant(tbase.target)])
    ran_away = bool(np.max(np.abs(sim.torque_motor)) >= tmax * (1.0 - 1e-9))
    return Twin(run=run, base=tbase, problem=problem, test=np.nan_to_num(cv.test),
                ran_away=ran_away)


def _twin_baseline(tsig: Signals, base: Baseline) -> Baseline:
    if not base.fit_mode:
        return Baseline(tsig, base.nominal, None)
    probe = Baseline(tsig, None, np.zeros(3))
    fit = full_fit(Problem(tsig, probe.columns), [empty_variant(probe.target)])
    return Baseline(tsig, None, fit.theta.copy())


def chain_shares(twin: Twin, named: Sequence) -> Callable:
    """``share(cause)``: the held-out fraction of the twin's residual the term of ``cause``
    removes when it is added after the causes ``named`` [-]; NaN for every cause when the
    twin ran away (:attr:`Twin.ran_away`).

    The twin walks the record's path: each named cause is added in turn, its variant
    chosen on the twin's own training blocks as on the record's, so that a candidate is
    measured against what the same steps leave on a record without effects.
    """
    if twin.ran_away:  # its residual is not the chain's: nothing to measure on it
        return lambda cause: math.nan
    problem, tb = twin.problem, twin.base
    test = twin.test
    chosen: list = []  # per named cause, the variant chosen per fold (None: no variant)

    def fixed(f):
        return tuple(c[f] for c in chosen if c[f] is not None)

    done: tuple = ()
    fitted: list = []  # the named causes with an all-data fit, and their index in ``chosen``
    for cause in named:
        cv = cross_validate(problem, lambda f, c=cause, b=tb: b.variants(c, f), fixed)
        test = np.where(np.isnan(cv.test), test, cv.test)
        chosen.append([fit.variant if fit is not None else None for fit in cv.fits])
        full = full_fit(problem, tb.variants(cause, None), done)
        if full is not None:
            fitted.append((cause, len(chosen) - 1))
            before = done + (full.variant,)
            settled, _, stb = settle(problem, tb, [c for c, _ in fitted], before, full.theta)
            remade = [(k, new) for (_, k), old, new in zip(fitted, before, settled)
                      if new is not old]
            if remade:  # a column read from the model's torque, kept where no worse held out
                kept = [list(c) for c in chosen]  # (the record's rule less its re-simulation)
                for k, new in remade:
                    chosen[k] = [new if v is not None else None for v in chosen[k]]
                cv = cross_validate(problem, lambda f: [empty_variant(stb.target)], fixed)
                now = np.where(np.isnan(cv.test), test, cv.test)
                if float(np.sum(now)) > float(np.sum(test)):
                    chosen[:] = kept
                    done, tb = before, advance(tb, problem, before, full.theta)
                    continue
                test = now
            done, tb = settled, stb
    base_sse = float(np.sum(test))
    shares: dict = {}

    def share(cause) -> float:
        if cause.name not in shares:
            cv = cross_validate(problem, lambda f: tb.variants(cause, f), fixed)
            after = float(np.sum(np.where(np.isnan(cv.test), test, cv.test)))
            shares[cause.name] = 1.0 - after / base_sse if base_sse > 0 else 0.0
        return shares[cause.name]
    return share
