"""No pass by runaway: three checks that a compensated joint follows its control torque.

A compensated run can meet a claim's criterion for the wrong reason: a net whose
gain at rest is above one winds the motor torque up, the joint runs away, and
"no stick interval" or "the joint moved" then holds trivially.  Every claim whose
measurement involves the network's compensation also requires these checks (see
:func:`fricctl.paper.claims.gate`); a claim that meets its own criterion but fails
one of them fails, with the check's reason in its note.

* :func:`wind_up` -- the motor torque may exceed the control torque only by the
  largest friction the joint can have at its speed (for a compensator that estimates
  friction);
* :func:`divergence` -- for a compensator that is *not* a friction estimate (a disturbance
  observer, integral action), which may exceed that bound in a bounded transient: the torque
  beyond the bound must die out by the last part of the run (no episode that does not end,
  no envelope that is sustained or grows);
* :func:`torque_check` -- the one of the two a compensator's ``estimates_friction`` asks for;
* :func:`reversal` -- under a sinusoidal control torque, a joint that moves must
  reverse in every full period after the first;
* :func:`coast_decay` -- after a torque pulse, with ``Tc = 0``, the compensated
  joint must coast down at least like the linear viscous actuator the compensation
  is meant to leave (the experiment itself is :mod:`fricctl.paper.coast`).

Each returns a :class:`RunawayCheck`: the number it measured, the limit, pass/fail
and a one-line reason.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _validate as v
from ..simulate import SimResult
from ..units import units as _units_of

__all__ = ["RunawayCheck", "wind_up", "divergence", "torque_check", "reversal", "coast_decay",
           "WIND_UP_SAMPLES", "SETTLE_SHARE", "DECAY", "STEADY", "MOTION_COUNTS", "LINEAR_TOLERANCE"]

#: Longest run of samples over which the motor torque may exceed the control torque by
#: more than the joint's largest friction [samples].  The compensator sees a change of
#: friction (a breakaway, a stop) at most ~2 samples late: the torque it computes at
#: sample k acts from k+1 on (one-sample delay), and the backward-difference velocity
#: reports a motion one sample after it starts.  5 samples leaves that margin twice over
#: and is still 10 ms, far shorter than any wind-up the paper pipeline shows (hundreds
#: of samples).  A compensator whose velocity reports a start later still (the
#: direction-confirmed velocity after a reversal: a count interval) gets no more: its excess
#: in that interval counts.
WIND_UP_SAMPLES = 5
#: Share of a run, at its end, in which the torque beyond the friction bound must have died
#: out for a compensator that is not a friction estimate (:func:`divergence`) [-].  The
#: experiments of :mod:`fricctl.compare` ask their joint to settle (a step from t = 0, held
#: to the end) or track a reference whose last corner is at half the run (the sawtooth's two
#: periods): a transient they start has at least a quarter of the run to die out before the
#: last quarter begins.  (Under the open-loop sinusoid the excitation goes on in the last
#: quarter: see :func:`divergence`'s Notes.)  A runaway (a loop made unstable, an integral or
#: an estimate that holds the drive at saturation) is still beyond the bound there.
SETTLE_SHARE = 0.25
#: Ratio of the excess beyond the friction bound in that last share to the largest excess
#: before it, from which the excess counts as not decayed (:func:`divergence`) [-].  The loops
#: judged are damped (the paper's PD designs: damping ratio 0.85-0.9) and the last share
#: starts after three quarters of the run: a transient that dies out has shrunk there far
#: below half of its peak; a sustained oscillation or a saturated drive keeps it (ratio ~1),
#: a growing one exceeds it.  Half sits between the two.
DECAY = 0.5
#: Ratio of the largest excess in the second half of that last share to the largest in its first
#: half from which an envelope counts as sustained, not decaying (:func:`divergence`) [-].  A
#: choice, read against what the record shows rather than against any loop's damping: a steady
#: oscillation repeats its peak in both halves up to the sampling of that peak (a sinusoid of
#: N samples per period is sampled within a factor cos(pi/N) of its peak: < 2 % from N = 16 on)
#: and the noise; 0.9 leaves five times that.  A transient that decays by less than a tenth
#: over half of the last share is, over this record, not told from a sustained one and fails
#: (a longer run tells them apart).  Without it, :data:`DECAY` alone passes a limit cycle that
#: follows a large first transient: a 30 s PID run at 1.1 x its Routh limit rings at a steady
#: 4 % of its first excess (tests/test_paper.py, the review of this check).
STEADY = 0.9
#: Growth of the largest error between the two halves from a late first excess to a run's end,
#: with the reference held and the joint swinging, from which the joint counts as driven away
#: (:func:`divergence`) [-].  A loop that hunts at a steady amplitude keeps its largest error
#: (ratio ~1) and one that closes on its reference shrinks it; a drive saturated away from its
#: reference grows it without bound.  Twice sits between them.
DRIVEN = 2.0
#: Torque beyond the friction bound that counts as an excess at all [N*m or N]: below it the
#: difference is the arithmetic's rounding, not a torque (one value for "none before" and for
#: the episodes, so that a rounding hair cannot decide between them).
EXCESS_TOL = 1e-9
#: A joint that moved this many encoder counts or fewer (peak to peak) has not moved:
#: nothing can run away [counts].  The same "few counts" as the dead-zone measurement.
MOTION_COUNTS = 3
#: Relative tolerance against the linear viscous actuator, shared by the coast test and
#: the Fig. 9 claim ``fig9-linear`` (the paper's "behaves like the linear model") [-].
LINEAR_TOLERANCE = 0.10


@dataclass(frozen=True, kw_only=True)
class RunawayCheck:
    """One runaway check of one run.

    Attributes
    ----------
    name : ``"wind-up"``, ``"divergence"``, ``"reversal"`` or ``"coast"``
    value : the number measured (``inf`` where the criterion has no finite measure)
    unit : its unit
    limit : the largest value that passes
    passed : ``value <= limit`` where the value was measured
    reason : one line: what was measured and why it passes or fails
    judged : False where the record is too short for part of the criterion (the reason says
        which, starting "too short to tell" where it is the whole verdict; ``passed`` is then
        what the rest of the criterion found): :func:`divergence` given a ``period`` its last
        share cannot hold twice, or whose first excess beyond the bound lies in its last share
        and does not grow there (``value`` NaN: no earlier excess to measure it against)
    """

    name: str
    value: float
    unit: str
    limit: float
    passed: bool
    reason: str
    judged: bool = True

    def __post_init__(self):
        v.text("name", self.name, empty=False)
        object.__setattr__(self, "value", v.real("value", self.value, finite=False))
        v.text("unit", self.unit)
        object.__setattr__(self, "limit", v.real("limit", self.limit))
        object.__setattr__(self, "passed", bool(self.passed))
        v.text("reason", self.reason, empty=False)
        object.__setattr__(self, "judged", bool(self.judged))

    def as_dict(self) -> dict:
        """JSON-ready (a non-finite value becomes None; the reason says why)."""
        return {"name": self.name, "value": self.value if math.isfinite(self.value) else None,
                "unit": self.unit, "limit": self.limit, "passed": self.passed, "reason": self.reason,
                "judged": self.judged}


def _run(run) -> SimResult:
    return v.instance("run", run, SimResult, "a SimResult (fricctl.simulate)")


def _units(r: SimResult):
    """The unit labels of the run's axis (``info.units``: [N*m], [rad/s] on a rotary joint,
    [N], [m/s] on a linear axis), so that a reason labels its numbers as the run's model does."""
    return _units_of(r.info.units)


def _held(r: SimResult, start: int) -> bool:
    """Whether the run is closed loop with its reference held from sample ``start`` to its end
    (the loop gets no new excitation there)."""
    return r.info.controller != "open loop" and not np.ptp(r.reference[start:]) > 0


def _diverged(limit: float, reason: str) -> RunawayCheck:
    """A failed :func:`divergence` check without a finite measure (``value`` inf)."""
    return RunawayCheck(name="divergence", value=math.inf, unit="%", limit=limit, passed=False,
                        reason=reason)


def _longest_true_run(mask: np.ndarray) -> tuple[int, int]:
    """(length, start index) of the longest run of consecutive True values (0, -1 if none;
    the first of equally long ones)."""
    start, length = max(_true_runs(mask, 0), key=lambda run: run[1], default=(-1, 0))
    return length, start


def _excess(r: SimResult) -> tuple[np.ndarray, np.ndarray]:
    """``(t_k, |Tm(k+1)| - (|Tc(k)| + Fs + b*|omega(k)| + ripple))`` of a run (see :func:`wind_up`)."""
    if r.t.size < 2:
        raise ValueError("run must hold at least 2 samples")
    fm = r.info.friction_model
    tm_next = r.torque_motor[1:]
    t = r.t[:-1]
    breakaway = np.maximum(fm.breakaway(1, tm=tm_next, t=t), fm.breakaway(-1, tm=tm_next, t=t))
    b = max(fm.viscous_pos, fm.viscous_neg) * fm.scale_at(t)
    bound = np.abs(r.torque_cmd[:-1]) + breakaway + b * np.abs(r.omega[:-1]) + fm.ripple_amplitude
    return t, np.abs(tm_next) - bound


def _true_runs(mask: np.ndarray, longer_than: int) -> list:
    """``(start, length)`` of every run of consecutive True values longer than ``longer_than``."""
    edges = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    return [(int(a), int(e - a)) for a, e in zip(starts, ends) if e - a > longer_than]


def wind_up(run: SimResult, *, max_samples: int = WIND_UP_SAMPLES) -> RunawayCheck:
    """Does the motor torque exceed the control torque by more than any friction could explain?

    The compensated loop commands ``Tm(k+1) = Tc(k) + s*T^at(k)``.  The friction of
    the joint (the bench's *true* model, ``run.info.friction_model``) is at most
    ``Fs + b*|omega|`` in magnitude (breakaway level plus the viscous term at the true
    speed, plus the position ripple's amplitude), so a compensation that estimates it
    keeps ``|Tm(k+1)| <= |Tc(k)| + Fs + b*|omega(k)|``.  A run of more than
    ``max_samples`` consecutive samples beyond that bound is a wind-up.

    Parameters
    ----------
    run : SimResult
        The compensated run.
    max_samples : int
        Longest run of samples allowed beyond the bound [samples] (see
        :data:`WIND_UP_SAMPLES` for why 5).

    Returns
    -------
    RunawayCheck
        ``value``: the longest run of consecutive samples beyond the bound [samples].

    Notes
    -----
    The bound holds for the stick-slip laws of :mod:`fricctl.friction`; LuGre's bristle
    damping can add a short transient above it, which this check would count.  It is written
    for a compensator whose ``T^at`` estimates friction; a disturbance observer (friction plus
    inertia error plus load) or integral action (an integral of the position error) exceed it
    in bounded transients: :func:`divergence` judges those.
    """
    r = _run(run)
    max_samples = v.integer("max_samples", max_samples, low=0)
    t, excess = _excess(r)
    n, start = _longest_true_run(excess > EXCESS_TOL)
    u = _units(r)
    ok = n <= max_samples
    if n == 0:
        reason = "no wind-up: |Tm(k+1)| never exceeds |Tc(k)| + Fs + b*|omega(k)|"
    else:
        seg = slice(start, start + n)
        reason = (f"{'no ' if ok else ''}wind-up: |Tm(k+1)| exceeds |Tc(k)| + Fs + b*|omega(k)| for "
                  f"{n} consecutive samples from t = {t[start]:.3f} s (by up to "
                  f"{float(excess[seg].max()):.3f} {u.torque}; allowed {max_samples})")
    return RunawayCheck(name="wind-up", value=float(n), unit="samples", limit=float(max_samples),
                        passed=ok, reason=reason)


def divergence(run: SimResult, *, settle_share: float = SETTLE_SHARE, decay: float = DECAY,
               steady: float = STEADY, max_samples: int = WIND_UP_SAMPLES,
               motion_counts: int = MOTION_COUNTS, period: float | None = None) -> RunawayCheck:
    """Does a torque beyond the friction bound die out?  The check of a compensator whose
    output is not a friction estimate.

    A disturbance observer supplies the torque of an inertia or a load it was not told about,
    integral action the torque of its integrated error: both may exceed the bound of
    :func:`wind_up` (``|Tc(k)| + Fs + b*|omega(k)|``) while the joint follows its reference, in a
    transient that dies out.  A runaway does not: a loop the compensator made unstable (a
    growing or a sustained oscillation, the drive at its saturation), an estimate that keeps
    the joint going.  An *episode* is a run of more than ``max_samples`` consecutive samples
    beyond the bound (shorter ones are the sample delays :func:`wind_up` allows too).  A
    closed-loop run whose reference is held through its last ``settle_share`` fails first if
    its joint is driven away from that reference, whatever the torque does: its error stays
    above :data:`DRIVEN` times the largest of its error at the start, the reference's distance
    from its final value and ``motion_counts`` counts through the whole last share, the joint
    moving there (a compensator slamming between the torque limits can stay within the bound,
    whose ``|Tc|`` grows with the error; a joint at rest is held by friction, not driven).
    Otherwise the run fails if an episode reaches into its last ``settle_share`` and either

    * has not ended: it began before that last share and lasts to the run's end; or
    * has not decayed: its largest excess is at least ``decay`` times the largest excess of
      the run before that last share (a sustained or growing envelope); or
    * grows where there is nothing before to compare it with: the run's first sample beyond the
      bound lies in the last share, and from it to the run's end the excess does not decay
      between the two halves (at least ``steady``), while the joint swings by more than
      ``motion_counts`` counts and, under a held reference, its error does not decay either
      (a loop that hunts wider at each slip, a drive that runs off); or, under a held
      reference, the joint swings and its largest error grows more than ``DRIVEN``-fold between
      the halves, whatever the excess does (a drive saturated away from its reference: the
      bound grows with ``|Tc|`` and ``|omega|``, so its excess can shrink).  Such a late first
      excess that does not grow is *not judged* (``judged`` False, ``passed`` True, ``value`` NaN;
      the reason starts "too short to tell"): a transient that starts late -- a DOB whose
      estimate integrates the held torque up to the breakaway level over seconds at rest, then
      creeps the joint to its reference -- has less record left than the last share gives every
      earlier transient to die out, and no earlier excess to be measured against (that DOB,
      ``fricctl simulate --link --controller pd --rise-time 0.4 --damping 0.85 --compensation
      dob``, passes over 5 s: its excess ends before the last quarter); or
    * is sustained: in a closed-loop run whose reference is held through that last share (the
      loop gets no new excitation there), both halves of the share hold an episode, the
      second half's largest excess is at least ``steady`` times the first's, and the joint
      swings by more than ``motion_counts`` encoder counts in the second half.  An
      oscillation the loop sustains by itself (a limit cycle after a large first transient)
      keeps its envelope between the halves, however small beside the first transient; a
      transient that dies out shrinks.

    Parameters
    ----------
    run : SimResult
        The compensated run (an experiment that asks its joint to settle, or that repeats its
        excitation, by the last ``settle_share`` of the run).
    settle_share : float
        Share of the run, at its end, in which a transient must have died out (0 < share < 1;
        see :data:`SETTLE_SHARE`) [-].
    decay : float
        Least ratio of the late excess to the earlier one that counts as not decayed (> 0;
        see :data:`DECAY`) [-].
    steady : float
        Least ratio of the largest excess in the last share's second half to that in its first
        half that counts as sustained (> 0; see :data:`STEADY`) [-].
    max_samples : int
        Longest run of samples beyond the bound that is not an episode [samples].
    motion_counts : int
        Peak-to-peak motion in the last share's second half up to which the joint counts as
        still, so that an envelope there is not an oscillation of the joint [counts].
    period : float, optional
        The slowest oscillation the caller knows the loop to have (a lightly damped mode of its
        design, a limit cycle measured on it) [s].  Where the last share holds episodes but
        fewer than two such periods, the steadiness test cannot judge it: the check says
        "too short to judge" and its ``judged`` is False (``passed`` is then the ``decay``
        test's).  None: not asked (the rule's blind spot, below, is not reported).

    Returns
    -------
    RunawayCheck
        ``value``: the largest excess beyond the bound in an episode of the last
        ``settle_share``, in % of the largest excess before it (0 without such an episode;
        ``inf`` for an episode that has not ended, an envelope that is sustained, or a first
        excess that grows; NaN for a first excess that does not: not judged) [%]; limit
        ``100*decay``.

    Notes
    -----
    A compensator that holds the joint at its breakaway level (a DOB hunting at rest, whose
    estimate integrates the held torque) exceeds the bound by a hair at each breakaway; those
    late, small episodes pass (the joint does not swing by more than ``motion_counts``).  An
    open-loop run under a torque that keeps accelerating the joint (a DOB with a wrong inertia,
    under a sinusoid) can show late episodes as large as the earlier ones; :func:`reversal`
    judges such a run too.  The steadiness test is not applied where the excitation goes on in
    the last share (an open-loop run, a reference that moves there): a periodic excess there may
    be the excitation's.

    **What the record cannot show.**  The steadiness test sees an oscillation only if each half
    of the last share holds one of its episodes: its period must be at most half of the last
    share, ``settle_share * T / 2`` for a run of ``T`` seconds (0.375 s of a 3 s run at the
    default quarter); to compare two of its peaks it needs about two periods there.  A slower
    oscillation is judged by ``decay`` alone, which passes a small sustained ring after a large
    first transient: such a run passes for want of record, not because it settles.  (A record
    can also be too short for an oscillation it does hold twice: a PID at 1.1 x its Routh limit
    rings at 0.3 s, but its ring still shrinks toward its steady amplitude over the first 3 s,
    and passes there; 30 s fail it, tests/test_paper.py.)  Give ``period`` to have the check say
    when its record is too short for the period.  The torque beyond the friction bound is what is
    judged: a limit cycle that stays within the bound (an integral or a DOB hunting around the
    breakaway level) passes at any length; :func:`fricctl.compare.oscillation` is the
    measurement that reports it.
    """
    r = _run(run)
    settle_share = v.real("settle_share", settle_share, positive=True)
    if settle_share >= 1.0:
        raise ValueError(f"settle_share must be < 1, got {settle_share:g}")
    decay = v.real("decay", decay, positive=True)
    steady = v.real("steady", steady, positive=True)
    max_samples = v.integer("max_samples", max_samples, low=0)
    motion_counts = v.integer("motion_counts", motion_counts, low=0)
    if period is not None:
        period = v.real("period", period, positive=True, unit="s")
    t, excess = _excess(r)
    u = _units(r)
    first = int(math.ceil((1.0 - settle_share) * t.size))
    if t.size - first <= max_samples:
        raise ValueError(f"run of {t.size + 1} samples: its last {settle_share:g} holds {t.size - first} "
                         f"samples, not more than max_samples = {max_samples}")
    away = _driven_away(r, first, motion_counts)
    if away is not None:
        return _diverged(100.0 * decay, away)
    episodes = _true_runs(excess > EXCESS_TOL, max_samples)
    late = [(a, n) for a, n in episodes if a + n > first]
    t_settle = float(t[first])
    limit = 100.0 * decay
    where = f"the run's last {100 * settle_share:g} % (from t = {t_settle:.3f} s)"
    if not late:
        if not episodes:
            reason = (f"no divergence: |Tm(k+1)| never exceeds |Tc(k)| + Fs + b*|omega(k)| for more "
                      f"than {max_samples} samples")
        else:
            a, n = max(episodes, key=lambda e: e[1])
            reason = (f"no divergence: {len(episodes)} transient(s) beyond |Tc(k)| + Fs + b*|omega(k)| "
                      f"(longest {n} samples from t = {t[a]:.3f} s, by up to "
                      f"{float(excess[a:a + n].max()):.3f} {u.torque}) ended before {where}")
        return RunawayCheck(name="divergence", value=0.0, unit="%", limit=limit, passed=True,
                            reason=reason)
    peak_late = max(float(excess[max(a, first):a + n].max()) for a, n in late)
    peak_before = float(excess[:first].max())
    a, n = late[-1]
    if a < first and a + n == t.size:
        return _diverged(limit, f"divergence: |Tm(k+1)| exceeds |Tc(k)| + Fs + b*|omega(k)| from "
                         f"t = {t[a]:.3f} s to the run's end ({n} samples, by up to "
                         f"{float(excess[a:].max()):.3f} {u.torque}): it has not ended in {where}")
    sustained = _sustained(r, excess, late, first, steady, motion_counts)
    if sustained is not None:
        return _diverged(limit, f"divergence: a sustained envelope in {where}: |Tm(k+1)| exceeds "
                         f"|Tc(k)| + Fs + b*|omega(k)| in both of its halves by up to "
                         f"{sustained[0]:.4f} and {sustained[1]:.4f} {u.torque} "
                         f"({100 * sustained[1] / sustained[0]:.0f} %, not decaying: at least "
                         f"{100 * steady:g} %) while the joint swings {sustained[2]} encoder counts "
                         f"with its reference held")
    n_late = sum(a + n - max(a, first) for a, n in late)
    head = (f"in {where} |Tm(k+1)| exceeds |Tc(k)| + Fs + b*|omega(k)| for {n_late} samples by up "
            f"to {peak_late:.4f} {u.torque}")
    span = float(t[-1] - t_settle) + r.sample_time
    short = ("" if period is None or span >= 2.0 * period else
             f"; too short to judge whether it is sustained: the last {span:.3g} s hold "
             f"{span / period:.2g} of the loop's period {period:.3g} s (fewer than 2)")
    if peak_before <= EXCESS_TOL:
        return _first_excess(r, t, excess, head, span, settle_share, limit, steady, motion_counts,
                             short)
    value = 100.0 * peak_late / peak_before
    ok = value <= limit
    reason = (f"{'no ' if ok else ''}divergence: {head}, {value:.0f} % of the largest excess before "
              f"({peak_before:.4f} {u.torque}; {'decayed: below' if ok else 'not decayed: allowed'} "
              f"{limit:g} %){short}")
    return RunawayCheck(name="divergence", value=value, unit="%", limit=limit, passed=ok, reason=reason,
                        judged=not short)


def _half_peaks(excess: np.ndarray, episodes: list, lo: int, hi: int) -> list:
    """The largest excess inside the episodes in each half of samples ``lo..hi-1`` (None for a
    half that holds no episode), and the index where the second half begins."""
    mid = lo + (hi - lo) // 2
    peaks = []
    for a0, a1 in ((lo, mid), (mid, hi)):
        inside = [excess[max(a, a0):min(a + b, a1)] for a, b in episodes if a < a1 and a + b > a0]
        peaks.append(float(max(x.max() for x in inside)) if inside else None)
    return [*peaks, mid]


def _driven_away(r: SimResult, first: int, motion_counts: int) -> str | None:
    """The reason of a closed-loop run whose joint ends driven away from its held reference, else
    None: through the whole last share (from sample ``first``) the joint moves by more than
    ``motion_counts`` counts and its error stays above :data:`DRIVEN` times the largest of its
    error at the start, the reference's largest distance from its final value, and
    ``motion_counts`` counts.

    Whatever the torque does -- a compensator slamming between the torque limits can stay within
    the friction bound (its ``|Tc|`` grows with the error) -- a loop that holds a reference does
    not keep its joint moving farther from it than the joint or the reference ever started.  A
    joint at rest in the last share is held by friction, not driven: a hunt's pause on the far
    side of a small step (an integral action or a DOB slipping from side to side) may outlast
    the last share, and is not judged here."""
    if not _held(r, first):
        return None  # no reference held there
    res = r.info.encoder_resolution
    swing = _swing(r, first)
    if swing == 0 or (res > 0 and swing <= motion_counts):  # without quantisation any motion counts
        return None  # at rest: parked, not driven
    moved = float(np.ptp(r.q_meas[first:]))
    target = float(r.reference[-1])
    e0 = abs(target - float(r.q_meas[0]))
    span = float(np.max(np.abs(r.reference - target)))
    floor = DRIVEN * max(e0, span, motion_counts * res)
    if floor <= 0.0:
        return None
    e = np.abs(target - r.q_meas[first:])
    if float(e.min()) <= floor:
        return None
    u = _units(r)
    return (f"divergence: the joint driven away from its held reference: through the run's last "
            f"{100 * (1 - first / max(r.q_meas.size - 1, 1)):.0f} % it moves over "
            f"{moved:.4g} {u.position} and its error stays above {float(e.min()):.4g} "
            f"{u.position}, more than {DRIVEN:g} x the largest of its error at the start "
            f"({e0:.4g} {u.position}), the reference's distance from its final value "
            f"({span:.4g} {u.position}) and {motion_counts} encoder counts")


def _swing(r: SimResult, start: int) -> int:
    """Peak-to-peak motion of the measured position from sample ``start`` to the run's end
    [encoder counts] (1 for any motion without quantisation)."""
    res = r.info.encoder_resolution
    span = float(np.ptp(r.q_meas[start:]))  # q_meas[k] for the judged k, and the last sample
    return int(round(span / res)) if res > 0 else int(span > 0)


def _sustained(r: SimResult, excess: np.ndarray, late: list, first: int, steady: float,
               motion_counts: int):
    """``(peak of the first half, peak of the second half, swing [counts])`` of the last share
    (from ``first``) if its envelope of episodes is sustained (see :func:`divergence`), else None."""
    if not _held(r, first):
        return None  # the excitation goes on: a repeated excess may be its own
    p1, p2, mid = _half_peaks(excess, late, first, excess.size)
    if p1 is None or p2 is None:
        return None
    swing = _swing(r, mid)
    if swing <= motion_counts or p2 < steady * p1:
        return None
    return p1, p2, swing


def _first_excess(r: SimResult, t: np.ndarray, excess: np.ndarray, head: str, given: float,
                  settle_share: float, limit: float, steady: float, motion_counts: int,
                  short: str) -> RunawayCheck:
    """:func:`divergence` of a run whose first excess beyond the bound lies in its last share.

    There is no earlier excess to say whether this one decayed, and less record after its
    start than the last share every earlier transient is given to die out.  What the record
    can still show is growth.  From the run's first sample beyond the bound to its end, split
    in two halves, the run fails (judged) if all of

    * the second half's largest excess is at least ``steady`` times the first's (any sample
      counts: the size of a growing envelope shows in short excursions too);
    * the joint swings more than ``motion_counts`` encoder counts in the second half;
    * with a reference held over that time, the largest position error of the second half is
      at least ``steady`` times the first's (the joint does not close on its reference)

    hold, or, with the reference held, the joint swings and its largest error grows more than
    :data:`DRIVEN`-fold (driven away, whatever the excess does); that is, a torque beyond the
    bound that does not decay while the joint is driven away or swings wider.  Anything else
    passes *not judged*: a transient that starts late (an observer that reaches the breakaway
    level after seconds at rest and creeps to the reference) is not told from the start of a
    runaway by so short a record."""
    u = _units(r)
    s = int(np.flatnonzero(excess > EXCESS_TOL)[0])
    n = excess.size
    mid = s + max(1, (n - s) // 2)
    p1, p2 = float(excess[s:mid].max()), float(excess[mid:].max()) if mid < n else -math.inf
    swing = _swing(r, mid)
    held = _held(r, s)
    e = np.abs(r.reference - r.q_meas)[:n]
    e1, e2 = float(e[s:mid].max()), float(e[mid:].max()) if mid < n else 0.0
    since = (f"the run's first excess beyond the bound is at t = {t[s]:.3f} s, "
             f"{float(t[-1] - t[s]) + r.sample_time:.3g} s before its end")
    res = r.info.encoder_resolution
    err = ("" if not held else
           f", its largest error {e2 / res:.0f} against {e1 / res:.0f} encoder counts" if res > 0 else
           f", its largest error {e2:.3g} against {e1:.3g} {u.position}")
    if p2 >= steady * p1 and swing > motion_counts and (not held or e2 >= steady * e1):
        return _diverged(limit, f"divergence: {head}, with none before (a torque that grew): {since}; "
                         f"over the second half of that time the excess grows to {p2:.4f} {u.torque} "
                         f"({100 * p2 / p1:.0f} % of the first half's {p1:.4f} {u.torque}; at least "
                         f"{100 * steady:g} % is not decaying) while the joint swings {swing} encoder "
                         f"counts{err}")
    if held and swing > motion_counts and e2 > DRIVEN * e1:
        # a saturated runaway can shrink its excess (the bound grows with |Tc| and |omega| as the
        # joint is driven off): the error says it, whatever the excess does
        return _diverged(limit, f"divergence: {head}, with none before (the joint driven away): "
                         f"{since}; over the second half of that time the joint swings {swing} encoder "
                         f"counts and its error grows more than {DRIVEN:g}-fold{err}")
    if p2 <= 0.0:
        seen = "it ended within the record"
    elif p2 < steady * p1:
        seen = (f"the second half of that time exceeds the bound by up to {p2:.4f} {u.torque} at any "
                f"sample, {100 * p2 / p1:.0f} % of the first half's {p1:.4f} {u.torque} (below "
                f"{100 * steady:g} %: not growing)")
    elif swing <= motion_counts:
        seen = (f"in the second half of that time the joint swings {swing} encoder counts "
                f"(at most {motion_counts}: not an oscillation of the joint)")
    else:
        seen = (f"the joint closes on its reference{err} (second half against first; below "
                f"{100 * steady:g} %)")
    return RunawayCheck(
        name="divergence", value=math.nan, unit="%", limit=limit, passed=True, judged=False,
        reason=(f"too short to tell: {head}, with none before: {since}, less than the "
                f"{given:.3g} s (the run's last {100 * settle_share:g} %) an earlier transient is "
                f"given to die out, and no earlier excess to compare it with; {seen}: not judged on "
                f"this record{short}"))


def torque_check(run: SimResult, compensator, *, period: float | None = None) -> RunawayCheck:
    """:func:`wind_up` for a compensator that estimates friction (its ``estimates_friction``),
    :func:`divergence` for one that does not (a disturbance observer, integral action);
    ``period`` [s] is :func:`divergence`'s (the wind-up bound has no steadiness test)."""
    from ..compensators import Compensator

    c = v.instance("compensator", compensator, Compensator, "a fricctl.compensators.Compensator")
    return wind_up(run) if c.estimates_friction else divergence(run, period=period)


def reversal(run: SimResult, period: float, *, motion_counts: int = MOTION_COUNTS) -> RunawayCheck:
    """Under a sinusoidal control torque of ``period``, does a moving joint reverse every period?

    A joint that follows ``Tc = A*sin(2*pi*t/period)`` moves back and forth; one that
    moves in one direction only over a whole period has run away (or ratchets).  The
    first period is the start-up transient and is not judged; a period in which the
    joint does not move at all is not a runaway.  A joint that moved ``motion_counts``
    encoder counts or fewer over the run passes.

    Parameters
    ----------
    run : SimResult
        The compensated run, ``Tc`` sinusoidal from t = 0.
    period : float
        Period of ``Tc`` [s].
    motion_counts : int
        Peak-to-peak motion up to which the joint counts as still [counts].

    Returns
    -------
    RunawayCheck
        ``value``: the number of full periods after the first in which the joint moved in
        one direction only [periods].
    """
    r = _run(run)
    period = v.real("period", period, positive=True, unit="s")
    motion_counts = v.integer("motion_counts", motion_counts, low=0)
    counts = r.displacement_counts()
    ts = r.sample_time if r.t.size > 1 else period
    full = int(math.floor((r.t[-1] + ts) / period + 1e-9))
    if counts <= motion_counts:
        return RunawayCheck(name="reversal", value=0.0, unit="periods", limit=0.0, passed=True,
                            reason=f"no runaway: the joint moved {counts} encoder counts "
                                   f"(<= {motion_counts})")
    if full < 2:
        raise ValueError(f"run of {r.t[-1] + ts:g} s holds fewer than 2 full periods of {period:g} s")
    one_way = []
    for j in range(1, full):
        w = r.omega[(r.t >= j * period - 1e-12) & (r.t < (j + 1) * period - 1e-12)]
        if np.any(w != 0.0) and not (np.any(w > 0.0) and np.any(w < 0.0)):
            one_way.append(j + 1)
    ok = not one_way
    reason = (f"the velocity reverses in each of the {full - 1} full periods after the first"
              if ok else
              f"runaway: the velocity never reverses in period(s) {', '.join(map(str, one_way))} of "
              f"{full} (Tc period {period:g} s, {counts} encoder counts of motion)")
    return RunawayCheck(name="reversal", value=float(len(one_way)), unit="periods", limit=0.0,
                        passed=ok, reason=reason)


def coast_decay(run: SimResult, t_end: float, *, tolerance: float = LINEAR_TOLERANCE) -> RunawayCheck:
    """After ``t_end`` (``Tc = 0`` from then on), does the joint coast down like a viscous one?

    The linear viscous actuator ``I*dw/dt = -b*w`` decays as ``|w_end|*exp(-(b/I)*(t -
    t_end))``.  The compensated joint passes if, at every sample after ``t_end``,
    ``|w(t)| <= |w_end|*exp(-(b/I)*(t - t_end)) + tolerance*|w_end|``: it slows down at
    least as fast, within ``tolerance`` of the speed it had (its Coulomb and Stribeck
    friction can only make it stop sooner).  ``b`` is the smaller viscous coefficient of
    the bench's true friction model, ``I`` the run's total inertia.

    Parameters
    ----------
    run : SimResult
        The run (rigid joint).
    t_end : float
        First instant with no pulse torque at the joint [s].
    tolerance : float
        Allowed excess over the decay, as a fraction of ``|w_end|`` [-].

    Returns
    -------
    RunawayCheck
        ``value``: the largest ``(|w| - |w_end|*exp(...))/|w_end|`` after ``t_end`` [%]
        (``inf`` if the joint was at rest at ``t_end`` and moved later).
    """
    r = _run(run)
    t_end = v.real("t_end", t_end, nonneg=True, unit="s")
    tolerance = v.real("tolerance", tolerance, nonneg=True)
    after = r.t >= t_end - 1e-12
    if np.count_nonzero(after) < 2:
        raise ValueError(f"t_end = {t_end:g} s leaves fewer than 2 samples of the run")
    fm = r.info.friction_model
    t, w = r.t[after], np.abs(r.omega[after])
    b = min(fm.viscous_pos, fm.viscous_neg) * float(np.min(fm.scale_at(t)))
    inertia = r.info.params.total_inertia
    w_end = w[0]
    limit = 100 * tolerance
    if w_end == 0.0:
        moved = bool(np.any(w > 0.0))
        return RunawayCheck(
            name="coast", value=math.inf if moved else 0.0, unit="%", limit=limit, passed=not moved,
            reason=("runaway: the joint was at rest when the pulse ended and then moved by itself"
                    if moved else "the pulse did not move the joint: nothing to coast"))
    excess = (w - w_end * np.exp(-(b / inertia) * (t - t[0]))) / w_end
    i = int(np.argmax(excess))
    worst = 100 * float(excess[i])
    ok = worst <= limit
    tau = inertia / b if b > 0 else math.inf
    u = _units(r)
    reason = (f"the joint coasts down at least like the linear viscous actuator (b = {b:.4g} {u.viscous}, "
              f"I/b = {tau:.3f} s): largest excess {worst:.1f} % of |omega_end| = {w_end:.2f} "
              f"{u.velocity} (allowed {limit:g} %)" if ok else
              f"runaway: after the pulse the joint does not coast down like the linear viscous actuator: "
              f"|omega| = {w[i]:.2f} {u.velocity} at t = {t[i]:.2f} s, {worst:.0f} % of |omega_end| = "
              f"{w_end:.2f} {u.velocity} above the decay exp(-(b/I)*t) (allowed {limit:g} %)")
    return RunawayCheck(name="coast", value=worst, unit="%", limit=limit, passed=ok, reason=reason)
