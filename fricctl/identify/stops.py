"""End stops: impacts against a hard limit, found in a record so that identification and
diagnosis can leave them out.

A rigid model ``I*q'' = Tm - F`` has no stop: when the joint hits one, the momentum the
stop takes away in a sample or two appears in the equation error as a torque nobody
applied, and the re-simulation runs through the limit.  :func:`end_stops` finds the stops
from what the record shows (never from a bench's magnitudes) and gives the samples of
every contact, which :func:`fricctl.identify.signals.estimate_signals` leaves out of the
equation error (its ``exclude``, with the filter's reach around them);
:func:`fricctl.identify.identify_record` replays only the segments clear of them and the
diagnosis (:mod:`fricctl.diagnose.stops`, the same module) drops the re-simulation windows
that hold one; both say so.  The stop is detected and excluded, not modelled.

The rule, in the record's own terms
-----------------------------------
1. **The drive's own braking.**  The rigid baseline ``I, b, Fc`` is fitted by least
   squares on the record's signals (the diagnosis's processing, one block), trimmed twice
   of samples whose residual exceeds :data:`TRIM` robust standard deviations (an impact
   is such an outlier).  Over two samples, a joint moving at ``w`` towards a side can
   lose at most ``2*Ts*(Fc + b*|w| + T)/I`` of its velocity, ``T`` the largest recorded
   torque *pulling back* within :data:`TORQUE_REACH` samples (a delay of a few samples
   kept inside; a torque pushing on brakes nothing, so the limit is at least friction's).
2. **An abrupt stop.**  Sample ``k`` is an abrupt stop when the velocity of the interval
   before the previous one, ``u_in = (q[k-1] - q[k-2])/Ts``, and of the interval after
   it, ``u_out = (q[k+1] - q[k])/Ts``, differ by more than :data:`MARGIN` times that limit
   plus the encoder's own error on the difference (``2*res/Ts``, one count on each
   velocity), the joint moved towards an extreme and went no further (``u_out`` at most
   one count per sample onwards).
3. **At an extreme, again and again.**  The abrupt stops whose position lies within
   :data:`TOLERANCE` counts of the record's largest (smallest) reading are impacts on the
   upper (lower) stop; a side with at least :data:`MIN_IMPACTS` of them has a stop, at
   that extreme reading, and so has a side hit once by a stop :data:`LONE` times beyond
   the drive's braking (more violent than anything a drive without a stop shows).
4. **Every contact.**  Once a stop is found, every arrival at it (a reading within
   :data:`TOLERANCE` counts, coming from inside) is a contact, abrupt or not (a slow
   arrival is an impact the limit of step 1 cannot tell from the drive's own braking);
   the contact lasts until the joint leaves the tolerance again.  The mask holds each
   contact and the two samples of its approach.

Notes
-----
Left out: a stop reached only once below :data:`LONE` (step 3 wants a repetition: one
abrupt stop at the extreme could be a backlash pick-up or an unexplained jolt), a stop whose contact
position moves by more than :data:`TOLERANCE` counts between impacts (a soft stop
penetrated by more or less depending on the speed), a stop inside the record's range (a
limit the joint passes is not a stop), and impacts slower than the drive's own braking on
a side with fewer than :data:`MIN_IMPACTS` abrupt ones.  The stop's reaction while the
joint presses into it is not modelled: those samples are at rest (already out of the
equation error) or in the mask.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _validate as v
from .._json import json_safe
from ..datasets import Run
from .signals import estimate_signals

__all__ = ["EndStops", "end_stops", "MARGIN", "TOLERANCE", "MIN_IMPACTS", "TORQUE_REACH", "TRIM", "LONE"]

#: An abrupt stop changes the velocity by more than this many times what the recorded torque
#: and the fitted friction can change it over the same two samples [-].
MARGIN = 3.0
#: Contacts with a stop lie within this many encoder counts of the record's extreme
#: reading [counts].
TOLERANCE = 2
#: Abrupt stops at the same extreme needed to call it a stop [-].
MIN_IMPACTS = 2
#: A side hit only once is a stop when that one abrupt stop takes this many times more
#: velocity than torque and friction can.  The largest such ratio at an extreme of a record
#: without a stop: 0.99 over 78 bench records (seeds 8000-8012, every cause, the three
#: excitations, fixed and drawn sensors), 0.78 on EMPS; ten times that.  (It was 30: lone
#: impacts of 17-27x on bench records with stops went unseen, and the impacts left in
#: the record kept every cause of those records from being named.) [-]
LONE = 10.0
#: Samples either side of an abrupt stop over which the largest recorded torque is taken
#: (a torque that acts a few samples late stays inside) [samples].
TORQUE_REACH = 3
#: Samples whose residual exceeds this many robust standard deviations (1.4826 x the median
#: absolute residual) are left out of the rigid fit that sets the drive's limit [-].
TRIM = 4.0


@dataclass(frozen=True, kw_only=True, eq=False)
class EndStops:
    """The end stops of a record (:func:`end_stops`).

    A record without stops has empty :attr:`positions` and :attr:`impacts` and an all-False
    :attr:`mask`; :attr:`description` says what was looked for.
    """

    positions: tuple
    """The stops' positions, lower first: the record's extreme readings where they are [rad]
    ([m] on a linear axis)."""
    sides: tuple
    """-1 (lower) or +1 (upper), per stop of :attr:`positions`."""
    impacts: np.ndarray
    """First sample of every contact with a stop (arrivals, abrupt or not), ascending."""
    abrupt: np.ndarray
    """Per impact: whether the arrival itself was an abrupt stop (rule 2) (bool)."""
    ratio: np.ndarray
    """Per impact: the velocity change over the limit of what torque and friction can do
    (rule 1; encoder error removed) [-]; an abrupt stop has more than :data:`MARGIN`."""
    mask: np.ndarray
    """Samples of the contacts and their approaches (bool per sample): the ``exclude`` of
    :func:`~fricctl.diagnose.signals.estimate_signals`."""
    inertia: float
    """Inertia of the trimmed rigid fit that sets the drive's limit [kg*m^2] ([kg]), NaN
    when the record could not be checked."""
    description: str
    """One sentence for the report: the stops, their impacts and what was left out, or
    that none was found."""

    @property
    def found(self) -> bool:
        """True when the record has at least one stop."""
        return bool(self.positions)

    def as_dict(self) -> dict:
        """The result as JSON-ready values (no per-sample mask: its count)."""
        return json_safe({"positions": list(self.positions), "sides": list(self.sides),
                          "impacts": self.impacts.tolist(), "abrupt": self.abrupt.tolist(),
                          "ratio": self.ratio.tolist(), "excluded_samples": int(self.mask.sum()),
                          "inertia": self.inertia, "description": self.description})


def _rigid_fit(run: Run):
    """(I, b, Fc) of the rigid baseline by trimmed least squares on the record's signals."""
    sig = estimate_signals(run, 1)
    X = np.column_stack([sig.a, sig.filt(sig.w), sig.filt(sig.seff)])
    y = sig.torque_target()
    keep = sig.moving.copy()
    theta = np.zeros(3)
    for _ in range(3):
        theta = np.linalg.lstsq(X[keep], y[keep], rcond=None)[0]
        r = y - X @ theta
        scale = 1.4826 * float(np.median(np.abs(r[sig.moving])))
        keep = sig.moving & (np.abs(r) <= TRIM * scale)
    return float(theta[0]), max(float(theta[1]), 0.0), abs(float(theta[2]))


def _braking(tm: np.ndarray, k: np.ndarray, side: int, friction: np.ndarray,
             gain: float) -> np.ndarray:
    """The most velocity the drive can take away over two samples at samples ``k`` moving
    towards ``side``: friction plus the recorded torque that pulls back (the largest within
    :data:`TORQUE_REACH` samples; a torque pushing on helps nothing), times ``gain`` =
    2*Ts/I [rad/s]."""
    n = tm.size
    back = np.zeros(k.size)
    for d in range(-TORQUE_REACH, TORQUE_REACH + 1):
        back = np.maximum(back, -side * tm[np.clip(k + d, 0, n - 1)])
    return gain * (friction + back)


def _none(n: int, inertia: float, why: str) -> EndStops:
    return EndStops(positions=(), sides=(), impacts=np.zeros(0, int), abrupt=np.zeros(0, bool),
                    ratio=np.zeros(0), mask=np.zeros(n, bool), inertia=inertia,
                    description=why)


def end_stops(run: Run) -> EndStops:
    """Find the end stops of ``run``: repeated abrupt stops at an extreme of its positions.

    Parameters
    ----------
    run : Run
        The measured record.

    Returns
    -------
    EndStops

    Notes
    -----
    The rule and its thresholds are in the module notes; every threshold is read off the
    record (its torque, encoder count, sample time and rigid fit).  A record whose signals
    cannot be estimated (too little motion) is returned without stops, saying why.

    Examples
    --------
    >>> import numpy as np
    >>> from fricctl.bench.hidden_effects import hidden_effect_record
    >>> rec = hidden_effect_record(np.random.default_rng(3), cause="none", duration=20.0)
    >>> end_stops(rec.run).found
    False
    """
    run = v.instance("run", run, Run, "a fricctl.datasets.Run")
    q = np.asarray(run.position, float)
    tm = np.asarray(run.torque, float)
    n = q.size
    unit = run.position_unit
    steps = np.abs(np.diff(q))
    res = float(np.min(steps[steps > 0])) if np.any(steps > 0) else 0.0
    if res == 0.0 or n < 8:
        return _none(n, float("nan"), "end stops not checked: the joint does not move")
    try:
        inertia, viscous, coulomb = _rigid_fit(run)
    except ValueError as err:
        return _none(n, float("nan"), f"end stops not checked: {err}")
    if not inertia > 0:
        return _none(n, inertia, "end stops not checked: the rigid fit's inertia is not positive")
    ts = run.sample_time
    u = np.diff(q) / ts                       # velocity of each interval [k, k+1]
    k = np.arange(2, n - 1)
    u_in, u_out = u[k - 2], u[k]
    change = np.abs(u_out - u_in) - 2 * res / ts
    count = res / ts * 1.01
    tol = TOLERANCE * res * 1.01
    ratio = np.zeros(n)
    sides, positions = [], []
    for side, extreme in ((-1, float(q.min())), (1, float(q.max()))):
        towards = side * u_in > 0
        stopped = side * u_out <= count
        at = np.abs(q[k] - extreme) <= tol
        sel = towards & stopped & at
        ratio[k[sel]] = change[sel] / _braking(tm, k[sel], side, coulomb + viscous * np.abs(
            u_in[sel]), 2 * ts / inertia)
        hit = k[sel][ratio[k[sel]] > MARGIN]
        # one impact is a run of abrupt samples a few samples apart
        events = hit[np.concatenate([[True], np.diff(hit) > 2 * TORQUE_REACH])] if hit.size else hit
        if events.size >= MIN_IMPACTS or (events.size and ratio[events].max() >= LONE):
            sides.append(side)
            positions.append(extreme)
    if not sides:
        return _none(n, inertia, f"no end stop: no {MIN_IMPACTS} abrupt stops (velocity change "
                                 f"> {MARGIN:g}x what torque and friction can do), nor one "
                                 f"> {LONE:g}x, at either extreme of the positions")
    mask = np.zeros(n, bool)
    impacts, abrupt, ratios = [], [], []
    for side, stop in zip(sides, positions):
        on = np.abs(q - stop) <= tol
        arrive = np.flatnonzero(on[1:] & ~on[:-1]) + 1
        if on[0]:
            arrive = np.concatenate([[0], arrive])
        leave = np.flatnonzero(~on[1:] & on[:-1]) + 1
        for a in arrive:
            after = leave[leave > a]
            end = int(after[0]) if after.size else n
            mask[max(a - 2, 0):end] = True
            impacts.append(int(a))
            near = ratio[a:min(a + 2, n)]
            abrupt.append(bool(np.any(near > MARGIN)))
            ratios.append(float(near.max()) if near.size else 0.0)
    order = np.argsort(impacts)
    impacts_a = np.asarray(impacts, int)[order]
    abrupt_a = np.asarray(abrupt, bool)[order]
    ratio_a = np.asarray(ratios, float)[order]
    per_stop = [sum(1 for i in impacts_a if abs(q[i] - p) <= tol) for p in positions]
    where = " and ".join(f"{p:+.5g} {unit} ({k} impact{'s' if k != 1 else ''})"
                         for p, k in zip(positions, per_stop))
    text = (f"end stop{'s' if len(positions) > 1 else ''} at {where}: {impacts_a.size} contacts "
            f"({int(abrupt_a.sum())} abrupt, the velocity changing up to "
            f"{float(ratio_a.max()):.3g}x faster than torque and friction can change it), "
            f"{int(mask.sum())} samples in contact or approach "
            f"({100.0 * mask.sum() / n:.2g} % of the record) left out of the fit with the "
            f"filter's reach around them; the model has no stop")
    return EndStops(positions=tuple(float(p) for p in positions), sides=tuple(sides),
                    impacts=impacts_a, abrupt=abrupt_a, ratio=ratio_a, mask=mask,
                    inertia=inertia, description=text)
