"""Records with hidden effects, made on the virtual bench (seeded).

:func:`hidden_effect_record` builds a measured record (:class:`~fricctl.datasets.Run`)
of a randomly drawn actuator (baseline: rigid joint, viscous + Coulomb friction with
stiction at the Coulomb level, the model :func:`fricctl.diagnose.diagnose` fits)
with one effect from :data:`HIDDEN_CAUSES` (or two, a :func:`compatible` pair) added,
under a randomly drawn excitation.  It is the test bench of the diagnosis: tests hand
the record (and, for the nominal-model causes, the nominal model an engineer would
have) to ``diagnose`` and require it to name the effects; they never read the answer
from the returned metadata.

Baseline actuator (drawn per record, load side)
-----------------------------------------------
=====================  ===========================  ==============================
quantity               rotary joint (default)       linear axis (``axis="linear"``)
=====================  ===========================  ==============================
actuator inertia/mass  1.5e-3 .. 4.5e-3 kg*m^2      20 .. 120 kg
link inertia/payload   0 .. 6e-3 kg*m^2             0 .. 80 kg
viscous b              0.008 .. 0.030 N*m*s/rad     50 .. 300 N*s/m
Coulomb Fc             0.08 .. 0.25 N*m             5 .. 40 N
torque noise (joint)   1 .. 3 % of Fc (std)         same
encoder count          3.14e-5 rad (paper)          1e-6 m
torque limit           12 * Fc                      12 * Fc
=====================  ===========================  ==============================

The paper's actuator: 2.87e-3 kg*m^2, link 4.6e-3, b 0.0169, Fc 0.144 (assumed 0.8*Fs),
2000 counts and n = 100; EMPS (a linear axis): 95 kg, 203 N*s/m, 20 N.  With
``sensors="drawn"`` the encoder count, the process noise and a measurement noise on the
recorded torque are drawn too (see :func:`hidden_effect_record`).

Hidden effects and their magnitudes
-----------------------------------
Each cause module of :mod:`fricctl.diagnose.causes` says how the bench hides its
effect (its ``inject`` function, ranges in its docstring's "Bench:" line, times
``strength``; periods and velocities times the axis's :data:`TRAVEL`; an effect growing
with speed sized at the actuator's top speed, ``BenchActuator.top_speed``):
:data:`HIDDEN_CAUSES` and :data:`NOMINAL_CAUSES` come from that registry, so a new
cause module is hidden here without an edit.  ``none`` adds nothing.  Two effects
are hidden together by setting each one's changed parameters on the same nominal
model (:data:`PAIRS` lists the fit-mode pairs).

Excitation (drawn per record)
-----------------------------
The record is a random sequence of segments of the kinds of :data:`EXCITATIONS`,
every kind present once in each half of the record (so that blocked cross-validation
sees it in more than one block), in random order, with random durations and levels.
``mixed``: open-loop torque steps in both directions (1.3-2.5 x breakaway, with
pauses), an open-loop torque sinusoid, PD tracking of a slow sinusoid (peak speed
0.03-0.4 rad/s, stick-slip), PD tracking of a fast one (peak speed 2-8 rad/s), and
PD tracking of a trapezoidal (constant speed 0.1-3 rad/s) reference.
``closed_loop``: the three PD tracking kinds and a PD loop holding position
(set-point steps of 1.5-4 dead zones Fs/Kp).  ``stuck``: open-loop torque triangles
peaking at 1.05-1.6 x breakaway, short torque pulses (5-30 ms, 2-4 x breakaway) and
the PD loop holding position: the joint slides a small part of the time.  PD gains
are drawn for a closed-loop natural frequency of 2-4.5 Hz, damping 0.7.  The loop
has the timing of :mod:`fricctl.simulate` (ZOH at Ts, one sample of computation
delay, backward difference velocity, quantised encoder).

Foreign effects (not causes)
----------------------------
``foreign=`` hides, on top, one effect of :data:`FOREIGN` that no cause of the registry
represents (issue 21, item 5: the diagnosis must name no cause for it and must not call the
record explained while the residual stays above the floor).  Its magnitudes are drawn after
every other draw, so a seed gives the same record with or without it, apart from the effect:

* ``time_sine``: a periodic torque disturbance in *time*, unrelated to position or speed,
  received by the joint and absent from the recorded torque (a vibrating base, a periodic
  external load): ``A*sin(2*pi*f*t + phi)``, A 0.2 .. 0.5 Fc (times ``strength``), f 0.3 ..
  3 Hz, phi uniform;
* ``torque_gain``: a torque-sensor (or torque-constant) scale error, recorded torque =
  ``(1 + e) *`` the torque the drive applies, ``|e|`` 5 .. 15 % (times ``strength``), either
  sign.  Without a nominal model the baseline's I, b and Fc would absorb it exactly: it
  implies ``nominal=True`` (it is foreign against the nominal model);
* ``position_gain``: a position-sensor scale error (a wrong encoder count or gear ratio),
  recorded position (and reference) = ``(1 + e) *`` the encoder's reading, ``|e|`` 5 .. 15 %
  (times ``strength``), either sign; the refitted I and b would absorb it: it implies
  ``nominal=True`` too;
* ``power_viscous``: a friction law of another shape, in place of the viscous law: viscous
  friction growing sub-linearly with speed, ``c*|w|**p*sign(w)``
  (:class:`~fricctl.friction.PowerViscous`), ``1 - p`` 0.3 .. 0.6 (times ``strength``, at most
  1.5: p 0.4 .. 0.7 at full strength), ``c = b*v**(1 - p)`` so that it gives the drawn ``b*v``
  at the record's RMS speed ``v``: more friction below that speed, less above;
* ``smooth_coulomb``: a friction law of another shape, in place of the Coulomb law: the
  drawn Coulomb levels reached smoothly, ``Fc*tanh(|w|/ws)*sign(w)``
  (:class:`~fricctl.friction.SmoothCoulomb`), no breakaway, ``ws`` 0.2 .. 0.4 (times
  ``strength``) of the record's RMS speed: less friction at low speed, the opposite of a
  Stribeck excess.

A foreign friction law is sized on the record's own speeds: the record is simulated without
it (the drawn law), its RMS speed ``v`` (true velocity, every sample) measured, and the
record simulated again with the law in place (the same excitation and noise, no draw added);
:attr:`HiddenEffectRecord.truth` holds the foreign law, :attr:`~HiddenEffectRecord.without_foreign`
the law it replaced, and :meth:`~HiddenEffectRecord.foreign_weight` says how much it weighs on
the record (the 10 % line of the causes).

Notes
-----
Left out: a position-dependent inertia (gravity is ``position_load``'s injection); sub-sample delays (the bench's
delay is whole samples); more than two effects at once.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from .. import _validate as v
from ..datasets import Run
from ..plant import JointModel, RigidJoint
from ..plant.stability import fastest_rate, required_substeps
from ..simulate import Schedule, simulate_schedule
from .end_stops import simulate_with_stops
# The bench reads the cause registry: each cause module says how the bench hides it.
# Layering: this generator is the diagnosis's test bench and sits beside it, above
# fricctl.diagnose (which never imports fricctl.bench); fricctl.bench.experiments does not
# import it, so the paper's experiments stay below the diagnosis.
from ..diagnose import causes

__all__ = ["HIDDEN_CAUSES", "NOMINAL_CAUSES", "HiddenEffectRecord", "hidden_effect_record",
           "ENCODER_RESOLUTION", "LINEAR_ENCODER_RESOLUTION", "EXCITATIONS", "AXES", "TRAVEL",
           "PAIRS", "compatible", "TORQUE_LIMIT", "TOP_SPEED", "FOREIGN",
           "ForeignEffect"]

#: Effects the generator hides without a nominal model (``none`` included), from the registry.
HIDDEN_CAUSES = (causes.NONE,) + tuple(c.name for c in causes.candidates(nominal=False))
#: Effects that only exist against a supplied nominal model.
NOMINAL_CAUSES = causes.NOMINAL_ONLY

#: Torque limit of the bench's drive, times the drawn Coulomb level Fc [-].
TORQUE_LIMIT = 12.0
#: Largest speed at which the bench sizes an effect growing with speed, in travel per second:
#: the 95th percentile of ``abs(w)`` on its effect-free rotary records is 3.9-14.7 rad/s with the
#: mixed excitation (median 7) and 3.1-7.1 rad/s in closed loop (10 records each) [-].
TOP_SPEED = 6.0

#: Load-side encoder count of the paper actuator [rad] (2000 counts/rev, n = 100).
ENCODER_RESOLUTION = 2.0 * math.pi / (2000 * 100)
#: Encoder count of the bench's linear axis [m] (EMPS: 5e-8 m).
LINEAR_ENCODER_RESOLUTION = 1e-6


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
        The hidden cause (ground truth; tests must not pass it to the diagnosis); the first
        of :attr:`causes`.
    causes : tuple of str
        Every hidden cause, in registry order (``("none",)`` when nothing is hidden).
    magnitude : dict
        Parameters of the hidden effect (SI units); for two effects, one dict per cause.
    truth : JointModel
        The complete true model (baseline + effect).
    excitation : tuple of str
        The segments, in order.
    effect_free : JointModel or None
        The true actuator without the hidden effects (ground truth, also when ``nominal``
        is None): with :attr:`truth` it tells how much each effect weighs on the record.
    stops : tuple of float
        Positions of the ideal end stops the joint hit (``end_stops`` of
        :func:`hidden_effect_record`; ground truth), lower first, in the record's position
        (scaled as the record is by a foreign position-sensor gain); ``()`` when none.
    impacts : ndarray of int
        Samples at which the joint arrived on a stop with speed (first sample of each
        contact; ground truth); empty when none.
    foreign : str
        The foreign effect hidden on top (a name of :data:`FOREIGN`; ``"none"``: none).  Not
        a cause: it is not in :attr:`causes`.
    foreign_magnitude : dict
        Its parameters (SI units; empty for ``"none"``).
    without_foreign : JointModel or None
        For a foreign friction law, the true model with the drawn law it replaced (ground
        truth; :attr:`truth` holds the foreign law); None for the other foreign effects.
    """

    run: Run
    nominal: JointModel | None
    cause: str
    causes: tuple = ()
    magnitude: dict = field(default_factory=dict)
    truth: JointModel
    excitation: tuple = ()
    effect_free: JointModel | None = None
    stops: tuple = ()
    impacts: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    foreign: str = "none"
    foreign_magnitude: dict = field(default_factory=dict)
    without_foreign: JointModel | None = None

    def foreign_weight(self, folds: int = 8) -> float:
        """How much a foreign friction law weighs on this record: the share of the torque
        residual (sum of squares, sliding samples) that knowing it removes, every hidden cause
        known, the baseline refitted when the record has no nominal model -- as
        :meth:`weights` for a cause (the same 10 % line).  Only for a foreign effect that is a
        friction law (:attr:`without_foreign` set); else ``ValueError``.
        """
        if self.without_foreign is None:
            raise ValueError(f"foreign_weight: the foreign effect {self.foreign!r} is not a "
                             "friction law of the true model")
        read = self._reader(folds, exclude_stops=False)
        return read.share(read.residual(self.without_foreign))

    def weights(self, folds: int = 8) -> dict:
        """How much each hidden effect weighs on this record: per cause, the share of the
        torque residual (sum of squares, sliding samples, all data) that knowing it removes
        once every other hidden effect is known -- the baseline refitted when the record
        has no nominal model (ground truth read through the diagnosis's own signals).

        Both residuals, the truth's and the one with the effect undone, are read the same
        way: with the baseline's columns (``I*a``, ``b*w``, ``Fc*sign(w)``) projected off
        both when the baseline is refitted (projected off the second alone, the truth's own
        misfit on the measured signals, which the refitted baseline partly takes up, counted
        against the effect: weights of -4 % to -36 % for effects the diagnosis names).

        An effect below :data:`fricctl.diagnose.MIN_SCORE` does not lower the residual by
        10 % of its RMS on this record: the diagnosis is not expected to name it
        (:meth:`expected`).  Contacts with end stops are left out as the diagnosis leaves
        them out (their impacts are no effect's: with them in, every weight read negative).
        """
        return self._weights(self._reader(folds))

    def expected(self, folds: int = 8, weights: dict | None = None) -> set:
        """The causes the diagnosis is expected to name on this record: each hidden cause
        that weighs at least :data:`fricctl.diagnose.MIN_SCORE` (:meth:`weights`; pass them
        as ``weights`` where they are at hand), where a position load whose shape over the
        record's travel no record could tell from a constant is expected as the ``offset`` it
        is on this record (where that constant weighs at the line itself).

        That is :mod:`fricctl.diagnose.causes.position_load`'s identifiability rule read on
        the ground truth: the true load, against the best constant torque in its place,
        removes less than ``MIN_SHAPE_SHARE`` (the 10 % line) of what that constant leaves, or
        the travel spans fewer than ``MIN_COUNTS`` encoder counts.
        A record that only holds position (a closed loop over a short travel) sees gravity
        as a constant; naming it a position load would be a guess.

        The same rule the other way: an offset hidden beside a position load that is expected
        is expected only where the record tells a constant beside the load's wave -- where the
        truth removes ``MIN_SCORE`` of what the best single wave leaves in place of the load
        and the offset (both undone, every other effect known; the wave's sine and cosine
        free, its period the best of position_load's search: ``CYCLES``, then ``FINE`` around
        the best of them; :func:`fricctl.diagnose.causes.position_load.wave`).  That is the
        question the diagnosis asks before it chooses the load's period beside a constant
        (:mod:`fricctl.diagnose.causes.position_load`).  Over a travel that covers a small
        part of the load's period a wave holds a constant, and no record of that travel tells
        an offset beside it; the period is the record's to find, so a wave of another period
        that holds load and offset together counts against the offset as well.  What the
        offset must remove is measured with the truth (its load and offset), not with the best
        wave and constant a diagnosis could fit in their place: a rule on what the record
        holds, stricter than the diagnosis's in-sample fit.
        """
        from ..diagnose import MIN_SCORE
        from ..diagnose.causes import position_load as pl

        read = None
        if weights is None:
            read = self._reader(folds)
            weights = self._weights(read)
        out = {c for c, w in weights.items() if w >= MIN_SCORE}
        if "position_load" in out:
            read = read or self._reader(folds)
            lo, hi = pl._travel(read.sig)
            undone = read.residual(self._undone("position_load"))
            if (read.sig.resolution > 0 and hi - lo < pl.MIN_COUNTS * read.sig.resolution
                    or read.share(undone, constant=True) < pl.MIN_SHAPE_SHARE):
                out = out - {"position_load"}
                # the constant in the load's place is expected only where it weighs at the
                # line itself (an offset hidden too is expected on its own weight)
                if read.constant(undone) >= MIN_SCORE:
                    out = out | {"offset"}
        if {"position_load", "offset"} <= out and "offset" in self.causes:
            # the offset hidden beside a load told as a load: told only where the truth removes
            # MIN_SCORE of what the best single wave of the load's period search leaves in place
            # of load and offset (the period is the record's to find, not the truth's)
            read = read or self._reader(folds)
            sig, m = read.sig, read.moving
            lo, hi = pl._travel(sig)
            both = read.residual(self._undone("position_load", "offset"))

            def alone(cycles):
                return read.sse(both, pl.wave(sig, (hi - lo) / cycles)[m])

            coarse = {c: alone(c) for c in pl.CYCLES}
            first = min(coarse, key=coarse.get)
            best = min([coarse[first]] + [alone(first + d) for d in pl.FINE
                                          if 0 < first + d <= pl.MAX_CYCLES])
            if not (best > 0 and 1.0 - read.sse(read.truth) / best >= MIN_SCORE):
                out = out - {"offset"}
        return out

    def _weights(self, read: "_Reader") -> dict:
        return {name: read.share(read.residual(self._undone(name)))
                for name in self.causes if name != causes.NONE}

    def _undone(self, *names: str) -> JointModel:
        """The true model with the effects ``names`` undone, the others kept."""
        d = _full_dict(self.truth)
        free = _full_dict(self.effect_free)
        for key in (k for name in names for k in causes.get(name).changes):
            if key in d["friction"]:
                d["friction"][key] = free["friction"][key]
            elif key in d:
                d[key] = free[key]
        return JointModel.from_dict(d)

    def _reader(self, folds: int, exclude_stops: bool = True) -> "_Reader":
        """The record read through the diagnosis's signals, its end stops' contacts left out
        (unless ``exclude_stops`` is False), for :meth:`weights` and the like."""
        from ..diagnose.stops import end_stops

        stops = end_stops(self.run) if exclude_stops else None
        exclude = stops.mask if stops is not None and stops.found else None
        return _Reader(self, v.integer("folds", folds, low=3, high=20), exclude)


class _Reader:
    """A hidden-effect record's torque residuals on its sliding samples, the way the labels
    read them: ``residual(model)``; ``share(r)``, the share of residual ``r`` (sum of squares)
    that the truth's removes, both with the refitted baseline's columns projected off when
    the record has no nominal model, and ``constant=True`` a constant torque too (what the
    truth removes beyond the best constant in place of what ``r``'s model lacks);
    ``constant(r)``, the share of ``r`` the best constant torque removes; ``sse(r, extra)``,
    what ``r`` leaves with those columns and ``extra`` projected off; ``truth``, the true
    model's residual; ``moving``, the sliding samples."""

    def __init__(self, record: HiddenEffectRecord, folds: int, exclude):
        from ..diagnose.signals import estimate_signals

        self.sig = sig = estimate_signals(record.run, folds, exclude=exclude)
        self.moving = self._m = m = sig.moving
        base = np.column_stack([sig.a, sig.filt(sig.w), sig.filt(sig.seff)])[m]
        self._cols = base if record.nominal is None else base[:, :0]
        self._with_one = np.column_stack([self._cols, sig.filt(np.ones(sig.t.size))[m]])
        self._truth = self.residual(record.truth)

    def residual(self, model: JointModel) -> np.ndarray:
        from ..diagnose.signals import predict

        return predict(model, self.sig).residual[self._m]

    @staticmethod
    def _sse(r: np.ndarray, cols: np.ndarray) -> float:
        if cols.shape[1]:
            r = r - cols @ np.linalg.lstsq(cols, r, rcond=None)[0]
        return float(np.sum(r ** 2))

    @property
    def truth(self) -> np.ndarray:
        """The true model's residual (sliding samples)."""
        return self._truth

    def sse(self, r: np.ndarray, extra: np.ndarray | None = None) -> float:
        """What ``r`` leaves (sum of squares) with the baseline's columns (fit mode) and the
        ``extra`` columns (sliding samples) projected off."""
        return self._sse(r, self._cols if extra is None else np.column_stack([self._cols, extra]))

    def share(self, r: np.ndarray, constant: bool = False) -> float:
        cols = self._with_one if constant else self._cols
        return 1.0 - self._sse(self._truth, cols) / self._sse(r, cols)

    def constant(self, r: np.ndarray) -> float:
        return 1.0 - self._sse(r, self._with_one) / self._sse(r, self._cols)


# ----------------------------------------------------------------------------- excitation
#: The segment kinds of each excitation (each kind once in each half of the record).
EXCITATIONS = {
    "mixed": ("torque_steps", "torque_sine", "slow_tracking", "fast_tracking", "ramps"),
    "closed_loop": ("slow_tracking", "fast_tracking", "ramps", "hold"),
    "stuck": ("torque_ramps", "pulses", "hold"),
}
#: The two kinds of axis the bench draws.
AXES = ("rotary", "linear")
#: Position unit of the motion per axis (speeds, periods as multiples of it) [rad] / [m].
TRAVEL = {"rotary": 1.0, "linear": 0.04}


def _pulse_train(rng, n, ts, width, gap, level):
    """Open-loop torque: pulses of ``width()`` s and ``level()``, gaps of ``gap()`` s, signs
    alternating (80 %) -- torque steps, triangles or short pulses."""
    ff = np.zeros(n)
    k = 0
    sign = rng.choice((-1.0, 1.0))
    while k < n:
        shape = width()
        m = min(shape.size, n - k)
        ff[k:k + m] = sign * level() * shape[:m]
        sign = -sign if rng.random() < 0.8 else sign
        k += shape.size + int(gap() / ts)
    return ff


def _segment(kind, rng, n, ts, inertia, breakaway, viscous, tmax, travel):
    """(kp, kd, ref, ff) arrays of one segment of n samples."""
    t = np.arange(n) * ts
    zeros = np.zeros(n)
    if kind in ("torque_steps", "torque_sine", "torque_ramps", "pulses"):
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
        elif kind == "torque_sine":
            amp = rng.uniform(1.3, 2.5) * breakaway
            f = rng.uniform(0.4, 1.5)
            ff = amp * np.sin(2 * np.pi * f * t) * np.minimum(1.0, t / 0.2)
            ff[-int(0.2 / ts):] = 0.0  # let it coast to rest
        elif kind == "torque_ramps":  # triangles just above breakaway: short slides, long rests
            def tri():
                m = max(int(rng.uniform(0.3, 1.0) / ts), 2)
                return np.concatenate([np.linspace(0.0, 1.0, m), np.linspace(1.0, 0.0, m)])
            ff = _pulse_train(rng, n, ts, tri, lambda: rng.uniform(0.1, 0.4),
                              lambda: rng.uniform(1.05, 1.6) * breakaway)
        else:  # short pulses: a jerk, a slide, a stop
            ff = _pulse_train(rng, n, ts, lambda: np.ones(max(int(rng.uniform(0.005, 0.03) / ts), 2)),
                              lambda: rng.uniform(0.2, 0.6),
                              lambda: rng.uniform(2.0, 4.0) * breakaway)
        return zeros, zeros, zeros, np.clip(ff, -0.9 * tmax, 0.9 * tmax)
    wn = 2 * np.pi * rng.uniform(2.0, 4.5)
    kp = np.full(n, inertia * wn ** 2)
    kd = np.full(n, max(2 * 0.7 * wn * inertia - viscous, 0.0))
    ff = zeros
    if kind == "slow_tracking":
        vpk = rng.uniform(0.03, 0.4) * travel
        f = rng.uniform(0.1, 0.4)
        amp = vpk / (2 * np.pi * f)
        ref = amp * (1 - np.cos(2 * np.pi * f * t)) * rng.choice((-1.0, 1.0))
    elif kind == "fast_tracking":
        f = rng.uniform(0.5, 1.5)
        vpk = rng.uniform(2.0, 8.0) * travel
        amax = 0.5 * (tmax - 1.5 * breakaway) / inertia
        vpk = min(vpk, amax / (2 * np.pi * f))
        amp = vpk / (2 * np.pi * f)
        ref = amp * (1 - np.cos(2 * np.pi * f * t)) * rng.choice((-1.0, 1.0))
    elif kind == "hold":  # holding position: set-point steps of 1.5-4 dead zones (Fs/Kp)
        ref = np.zeros(n)
        k, level = 0, 0.0
        while k < n:
            m = int(rng.uniform(0.4, 1.2) / ts)
            level += rng.choice((-1.0, 1.0)) * rng.uniform(1.5, 4.0) * breakaway / kp[0]
            ref[k:k + m] = level
            k += m
    else:  # trapezoids: constant-speed plateaus both ways, random speeds
        ref = np.zeros(n)
        v = np.zeros(n)
        k = 0
        sign = rng.choice((-1.0, 1.0))
        while k < n:
            m = int(rng.uniform(0.6, 1.5) / ts)
            v[k:k + m] = sign * math.exp(rng.uniform(math.log(0.1), math.log(3.0))) * travel
            sign = -sign
            k += m
        # smooth the speed steps (0.1 s) so the reference is trackable
        w = max(int(0.1 / ts), 1)
        v = np.convolve(v, np.ones(w) / w, mode="same")
        ref = np.cumsum(v) * ts
    return kp, kd, ref, ff


def _excitation(rng, n, ts, inertia, breakaway, viscous, tmax, kinds, travel):
    # Every kind twice, once in each half of the record, so that the excitation that reveals an
    # effect never lives in a single block of the blocked cross-validation (a term fitted
    # without that block is then unidentifiable and its held-out error explodes).
    first, second = list(kinds), list(kinds)
    rng.shuffle(first)
    rng.shuffle(second)
    kinds = first + second
    weights = rng.uniform(0.6, 1.4, size=len(kinds))
    lengths = np.floor(weights / weights.sum() * n).astype(int)
    lengths[-1] = n - lengths[:-1].sum()
    parts = [_segment(k, rng, int(m), ts, inertia, breakaway, viscous, tmax, travel)
             for k, m in zip(kinds, lengths)]
    kp, kd, ref, ff = (np.concatenate([p[i] for p in parts]) for i in range(4))
    start = np.zeros(n, dtype=np.bool_)
    start[np.concatenate([[0], np.cumsum(lengths)[:-1]])] = True
    return tuple(kinds), kp, kd, ref, ff, start


# ----------------------------------------------------------------------------- several effects
def compatible(first: str, second: str) -> bool:
    """True when the bench can hide ``first`` and ``second`` together: two different causes
    acting on disjoint model parameters (LuGre bristles exist on the rigid joint only)."""
    a, b = causes.get(first), causes.get(second)

    def elastic(c):  # the injection puts a load behind a spring or a gap
        return "load_inertia" in c.changes

    def bristles(c):  # the injection gives the friction a presliding state
        return any(k.startswith("lugre_") for k in c.changes)

    return (a is not b and not set(a.changes) & set(b.changes)
            and not (elastic(a) and bristles(b)) and not (elastic(b) and bristles(a)))


#: Every pair of fit-mode causes the bench hides together, in registry order.
PAIRS = tuple((a, b) for i, a in enumerate(HIDDEN_CAUSES[1:]) for b in HIDDEN_CAUSES[2 + i:]
              if compatible(a, b))


def _full_dict(model: JointModel) -> dict:
    """The model file's content with every friction coefficient and the backlash (the file
    writes the changed ones and a backlash only when there is one)."""
    return {**model.as_dict(), "backlash": model.backlash, "friction": model.friction.as_dict()}


def _merge(effects: dict, actuator):
    """One injection from several (name -> Injection): each effect's changed model parameters
    set on one nominal model."""
    items = list(effects.values())
    nominal = next((e.nominal for e in items if e.nominal != actuator.nominal()),
                   items[0].nominal)  # compliance redraws the link: its nominal holds it
    merged = _full_dict(nominal)
    for e in items:
        got, ref = _full_dict(e.truth), _full_dict(e.nominal)
        for key, value in got.items():
            if key == "friction":
                merged["friction"].update({k: x for k, x in value.items() if x != ref[key][k]})
            elif value != ref[key]:
                merged[key] = value
    truth = JointModel.from_dict(merged)
    return causes.Injection(joint=truth.joint(), truth=truth, nominal=nominal,
                            magnitude={name: e.magnitude for name, e in effects.items()},
                            breakaway=max(e.breakaway for e in items),
                            delay=max(e.delay for e in items),
                            substeps=max(e.substeps for e in items))


def _actuator(rng, axis, ts, duration, strength, sensors):
    """Draw the baseline actuator, its noise levels and encoder (a fixed sequence of draws)."""
    if axis == "rotary":
        jm, jl = rng.uniform(1.5e-3, 4.5e-3), rng.uniform(0.0, 6e-3)
        b, fc = rng.uniform(0.008, 0.030), rng.uniform(0.08, 0.25)
        res = ENCODER_RESOLUTION
    else:  # a ball-screw or belt axis: carriage, payload, viscous, Coulomb (EMPS: 95 kg, 200, 20)
        jm, jl = rng.uniform(20.0, 120.0), rng.uniform(0.0, 80.0)
        b, fc = rng.uniform(50.0, 300.0), rng.uniform(5.0, 40.0)
        res = LINEAR_ENCODER_RESOLUTION
    process = rng.uniform(0.01, 0.03) * fc
    measured = 0.0
    if sensors == "drawn":  # as they come: encoder 0.3-10 counts of the default, noise levels
        res *= math.exp(rng.uniform(math.log(0.3), math.log(10.0)))
        process *= rng.uniform(0.3, 2.0)
        measured = rng.uniform(0.0, 0.03) * fc
    # the fast tracking's peak speed is held to what the torque limit accelerates at 1 Hz, its
    # middle frequency (_segment): a heavy linear axis moves slower than TOP_SPEED (measured:
    # the 95th percentile of |w| is 0.5-1.6 x this top speed on effect-free linear records,
    # 0.17-0.92 x TOP_SPEED alone)
    top = min(TOP_SPEED * TRAVEL[axis],
              0.5 * (TORQUE_LIMIT - 1.5) * fc / (jm + jl) / (2.0 * math.pi))
    act = causes.BenchActuator(motor_inertia=jm, link_inertia=jl, viscous=b, coulomb=fc,
                               sample_time=ts, duration=duration, encoder_resolution=res,
                               travel=TRAVEL[axis], strength=strength, units=axis, top_speed=top)
    return act, process, measured


# ----------------------------------------------------------------------------- foreign effects
@dataclass(frozen=True, kw_only=True, eq=False)
class _Foreign:
    """A foreign effect drawn for one record: a torque the joint receives on top of the loop's,
    and a gain on the recorded torque."""

    disturbance: np.ndarray | None
    """Torque added to what the joint receives, per sample [N*m], or None."""
    gain: float
    """Recorded torque over the torque the drive applies [-]."""
    position_gain: float = 1.0
    """Recorded position over the encoder's true reading [-]."""
    magnitude: dict
    """The drawn parameters (SI)."""
    friction: object = None
    """``friction(model, speed) -> (model, parameters)``: a friction law put in place of one of
    the drawn model's, sized at ``speed``, the RMS speed of the record simulated without it
    [rad/s] or [m/s]; None: the friction is left alone."""


def _time_sine(rng, act, t):
    amp = float(rng.uniform(0.2, 0.5) * act.coulomb * act.strength)
    freq = float(rng.uniform(0.3, 3.0))
    phase = float(rng.uniform(0.0, 2.0 * math.pi))
    return _Foreign(disturbance=amp * np.sin(2.0 * math.pi * freq * t + phase), gain=1.0,
                    magnitude=dict(amplitude=amp, frequency=freq, phase=phase))


def _torque_gain(rng, act, t):
    error = float(rng.uniform(0.05, 0.15) * rng.choice((-1.0, 1.0)) * act.strength)
    return _Foreign(disturbance=None, gain=1.0 + error, magnitude=dict(error=error))


def _position_gain(rng, act, t):
    error = float(rng.uniform(0.05, 0.15) * rng.choice((-1.0, 1.0)) * act.strength)
    return _Foreign(disturbance=None, gain=1.0, position_gain=1.0 + error,
                    magnitude=dict(error=error))


def _power_viscous(rng, act, t):
    # the exponent's distance from 1 (the viscous line) times the strength
    p = float(1.0 - rng.uniform(0.3, 0.6) * min(act.strength, 1.5))

    def law(friction, speed):
        # c*|w|**p with c*speed**p = b*speed: the drawn viscous torque at the record's RMS speed,
        # more below it, less above it; the viscous law removed
        k = speed ** (1.0 - p)
        pos, neg = friction.viscous_pos * k, friction.viscous_neg * k
        new = replace(friction, viscous_pos=0.0, viscous_neg=0.0, power_viscous_pos=pos,
                      power_viscous_neg=neg, power_viscous_exponent=p)
        return new, dict(coefficient_pos=pos, coefficient_neg=neg, rms_speed=speed)

    return _Foreign(disturbance=None, gain=1.0, friction=law, magnitude=dict(exponent=p))


def _smooth_coulomb(rng, act, t):
    ratio = float(rng.uniform(0.2, 0.4) * act.strength)

    def law(friction, speed):
        # Fc*tanh(|w|/ws), ws a fraction of the record's RMS speed: the drawn Coulomb levels
        # reached smoothly, no breakaway; the Coulomb law removed
        new = replace(friction, coulomb_pos=0.0, coulomb_neg=0.0,
                      smooth_coulomb_pos=friction.coulomb_pos,
                      smooth_coulomb_neg=friction.coulomb_neg,
                      smooth_coulomb_velocity=ratio * speed)
        return new, dict(velocity=ratio * speed, rms_speed=speed)

    return _Foreign(disturbance=None, gain=1.0, friction=law, magnitude=dict(ratio=ratio))


@dataclass(frozen=True, kw_only=True)
class ForeignEffect:
    """An effect the bench hides that is not a cause of the registry."""

    name: str
    """Its name, the value of ``foreign=``."""
    physical: str
    """The effect in one line."""
    draw: object
    """``draw(rng, actuator, t)`` -> the drawn effect (None for ``"none"``)."""
    nominal: bool = False
    """True when it is foreign only against a nominal model (the refitted baseline absorbs
    it): it implies ``nominal=True``."""


#: Effects the bench hides that are not causes of the registry (``foreign=`` of
#: :func:`hidden_effect_record`; the module notes give their ranges), by name.
FOREIGN = {f.name: f for f in (
    ForeignEffect(name="none", physical="nothing foreign", draw=None),
    ForeignEffect(name="time_sine", draw=_time_sine,
                  physical="a periodic torque disturbance in time, received by the joint, "
                           "unrelated to position or speed"),
    ForeignEffect(name="torque_gain", draw=_torque_gain, nominal=True,
                  physical="a torque-sensor scale error: the recorded torque is (1 + e) times "
                           "the applied one"),
    ForeignEffect(name="position_gain", draw=_position_gain, nominal=True,
                  physical="a position-sensor scale error (encoder count, gear ratio): the "
                           "recorded position is (1 + e) times the encoder's reading"),
    ForeignEffect(name="power_viscous", draw=_power_viscous,
                  physical="viscous friction growing sub-linearly with speed, c*|w|**p*sign(w), "
                           "in place of b*w"),
    ForeignEffect(name="smooth_coulomb", draw=_smooth_coulomb,
                  physical="the Coulomb level reached smoothly, Fc*tanh(w/ws), no breakaway, in "
                           "place of Fc*sign(w)"),
)}


# ----------------------------------------------------------------------------- generator
def hidden_effect_record(rng: np.random.Generator, *, cause=None, duration: float = 40.0,
                         sample_time: float = 0.002, nominal: bool = False, noise: bool = True,
                         axis: str = "rotary", excitation: str = "mixed", strength: float = 1.0,
                         sensors: str = "fixed", end_stops: float = 0.0,
                         foreign: str = "none") -> HiddenEffectRecord:
    """Simulate one record with hidden effects (one drawn at random, or the ones named).

    Parameters
    ----------
    rng : numpy.random.Generator
        All randomness (actuator, effect, magnitude, excitation, noise).
    cause : str or tuple of str, optional
        Force this cause (a name of :data:`HIDDEN_CAUSES` or :data:`NOMINAL_CAUSES`), or
        two causes hidden together (a :func:`compatible` pair); default: one drawn uniformly
        from :data:`HIDDEN_CAUSES`, or from ``("none",) + NOMINAL_CAUSES`` when ``nominal``.
    duration : float
        Record length [s], 10 .. 120.
    sample_time : float
        Ts [s], 0.0005 .. 0.005 (2 kHz .. 200 Hz).
    nominal : bool
        Also return the nominal model (the true baseline actuator).  Implied by
        the nominal-model causes and by a foreign effect foreign only against it.
    noise : bool
        Torque noise on (default) or off (the draws are made either way, so a seed
        gives the same record apart from the noise).
    axis : {"rotary", "linear"}
        A rotary joint around the paper's actuator, or a linear axis (carriage 20-200 kg,
        viscous 50-300 N*s/m, Coulomb 5-40 N, 1 um encoder; the motion scaled by
        :data:`TRAVEL`): the record and the models carry the axis's units.
    excitation : {"mixed", "closed_loop", "stuck"}
        The segment kinds of :data:`EXCITATIONS`: open and closed loop mixed (default),
        closed loop only (PD tracking and holding position), or mostly stuck (torque ramps
        just above breakaway, short pulses, a PD loop holding position).
    strength : float
        Factor on the size of the hidden effect (``BenchActuator.strength``), 0.05 .. 2.
    sensors : {"fixed", "drawn"}
        The axis's default encoder and process noise (1-3 % of Fc), or drawn as they come:
        encoder count 0.3-10 x the default, process noise 0.3-6 % of Fc, and white noise of
        0-3 % of Fc on the *recorded* torque (a current measurement).
    end_stops : float
        0 (default): no stops.  Else, 0.02 .. 0.45: ideal rigid end stops
        (:mod:`fricctl.bench.end_stops`) where the stop-free record spends this fraction of
        its time beyond each (its quantiles; a stop kept 5 % of the travel clear of the
        start), and the record simulated again with them (no draw added: a seed draws what
        it draws without stops).  Joints with a
        spring or a friction state are refused (the stop is idealised on a rigid joint).
        The record says where the stops are and when the joint hit them (:attr:`stops`,
        :attr:`impacts`); its ``causes`` are the hidden causes (``end_stop`` is not a cause
        of the registry: :func:`fricctl.diagnose.stops.end_stops` detects it).
    foreign : str
        A name of :data:`FOREIGN`: an effect no cause represents, hidden on top of the
        causes (see the module notes; default ``"none"``).  Its draws come after all others.

    Returns
    -------
    HiddenEffectRecord

    Notes
    -----
    The draws come in a fixed sequence: the cause (when not forced), the actuator
    (Jm, Jl, b, Fc, noise level, then the drawn sensors), each effect's magnitudes (the
    cause module's ``inject``), the excitation, the noise (process, then measurement), the
    foreign effect.  With the defaults a seed gives the record it gave before the options
    existed.

    Examples
    --------
    >>> import numpy as np
    >>> rec = hidden_effect_record(np.random.default_rng(1), cause="none", duration=10.0)
    >>> rec.run.n_samples, rec.nominal is None, rec.causes
    (5000, True, ('none',))
    """
    v.rng("rng", rng)
    duration = v.real("duration", duration, low=10.0, high=120.0, unit="s")
    ts = v.real("sample_time", sample_time, low=5e-4, high=5e-3, unit="s")
    nominal = v.flag("nominal", nominal)
    noise = v.flag("noise", noise)
    axis = v.choice("axis", axis, AXES)
    kinds = EXCITATIONS[v.choice("excitation", excitation, tuple(EXCITATIONS))]
    strength = v.real("strength", strength, low=0.05, high=2.0)
    sensors = v.choice("sensors", sensors, ("fixed", "drawn"))
    end_stops = v.real("end_stops", end_stops, nonneg=True)
    if end_stops and not 0.02 <= end_stops <= 0.45:
        raise ValueError(f"end_stops must be 0 or in [0.02, 0.45], got {end_stops:g}")
    foreign = v.choice("foreign", foreign, tuple(FOREIGN))
    if cause is None:
        pool = (causes.NONE,) + NOMINAL_CAUSES if nominal else HIDDEN_CAUSES
        cause = str(rng.choice(pool))
    names = (cause,) if isinstance(cause, str) else tuple(cause)
    if not 1 <= len(names) <= 2:
        raise ValueError(f"cause must be one name or a pair of names, got {cause!r}")
    names = tuple(v.choice("cause", c, HIDDEN_CAUSES + NOMINAL_CAUSES) for c in names)
    if len(names) == 2 and not (causes.NONE not in names and compatible(*names)):
        raise ValueError(f"cause: the bench cannot hide {names[0]!r} and {names[1]!r} together "
                         f"(see compatible())")
    nominal = nominal or any(c in NOMINAL_CAUSES for c in names) or FOREIGN[foreign].nominal

    n = int(round(duration / ts))
    actuator, noise_std, meas_std = _actuator(rng, axis, ts, duration, strength, sensors)
    b, fc = actuator.viscous, actuator.coulomb
    tmax = TORQUE_LIMIT * fc
    effects = [causes.inject(c, rng, actuator) for c in names]
    effect = _merge(dict(zip(names, effects)), actuator) if len(effects) > 1 else effects[0]

    # the excitation is sized for the heavier of the true and the nominal inertia
    segs, kp, kd, ref, ff, start = _excitation(
        rng, n, ts, max(effect.truth.inertia, effect.nominal.inertia), effect.breakaway, b, tmax,
        kinds, actuator.travel)
    torque_noise = rng.normal(0.0, noise_std, n) * (1.0 if noise else 0.0)
    # the simulation draws nothing: the measurement noise is drawn here, then the foreign effect
    meas_noise = (rng.normal(0.0, meas_std, n) * (1.0 if noise else 0.0) if meas_std > 0
                  else None)
    alien = (_Foreign(disturbance=None, gain=1.0, magnitude={}) if foreign == "none"
             else FOREIGN[foreign].draw(rng, actuator, np.arange(n) * ts))
    if alien.disturbance is not None:
        torque_noise = torque_noise + alien.disturbance
    # a constant torque (the truth's offset) acts at the joint with the noise: it receives
    # Tm - offset (the recorded torque is Tm)
    at_joint = torque_noise - effect.truth.offset
    sim = simulate_schedule(effect.joint, Schedule(kp=kp, kd=kd, reference=ref, feedforward=ff,
                                                   segment_start=start),
                            sample_time=ts, max_torque=tmax,
                            encoder_resolution=actuator.encoder_resolution,
                            substeps=int(effect.substeps), delay=int(effect.delay),
                            noise=at_joint)
    joint, truth, substeps, without_foreign = effect.joint, effect.truth, int(effect.substeps), None
    if alien.friction is not None:  # a friction law in place of the drawn one, sized at the RMS
        # speed of the record simulated without it (the excitation is the same), run again
        speed = float(np.sqrt(np.mean(sim.omega ** 2)))
        friction, sized = alien.friction(truth.friction, speed)
        alien = replace(alien, magnitude={**alien.magnitude, **sized})
        without_foreign, truth = truth, replace(truth, friction=friction)
        joint = truth.joint()
        substeps = max(substeps, required_substeps(sample_time=ts, rate=fastest_rate(
            inertia=truth.inertia - truth.load_inertia, friction=friction)))
        sim = simulate_schedule(joint, Schedule(kp=kp, kd=kd, reference=ref, feedforward=ff,
                                                segment_start=start),
                                sample_time=ts, max_torque=tmax,
                                encoder_resolution=actuator.encoder_resolution,
                                substeps=substeps, delay=int(effect.delay), noise=at_joint)
    if not (np.all(np.isfinite(sim.q_meas)) and np.all(np.isfinite(sim.torque_motor))):
        raise ValueError("the bench simulation diverged (report this seed)")
    stops, impacts = (), np.zeros(0, dtype=int)
    if end_stops:  # stops where the stop-free motion spends `end_stops` of its time beyond
        # each, the start (0) kept 5 % of the travel inside; the loop run again with them
        lo, hi = (float(x) for x in np.quantile(sim.q, [end_stops, 1.0 - end_stops]))
        lo, hi = min(lo, -0.05 * (hi - lo)), max(hi, 0.05 * (hi - lo))
        if not isinstance(joint, RigidJoint) or joint.friction.state_law is not None:
            raise ValueError(f"end_stops: the bench's ideal stop is simulated on a rigid joint "
                             f"without a friction state, not with {names}")
        sim = simulate_with_stops(
            joint, Schedule(kp=kp, kd=kd, reference=ref, feedforward=ff,
                            segment_start=start),
            sample_time=ts, max_torque=tmax, encoder_resolution=actuator.encoder_resolution,
            substeps=sim.info.substeps, delay=int(effect.delay), noise=at_joint,
            lower=lo, upper=hi)
        impacts = sim.impacts
        stops = tuple(lim for side, lim in ((-1, sim.lower), (1, sim.upper))
                      if np.any(sim.impact_side == side))
    recorded = sim.torque_motor * alien.gain
    if meas_noise is not None:
        recorded = recorded + meas_noise
    stops = tuple(lim * alien.position_gain for lim in stops)  # where the record sees them
    run = Run(t=sim.t, torque=recorded, position=sim.q_meas * alien.position_gain,
              reference=sim.reference * alien.position_gain, units=axis,
              source=f"fricctl virtual bench, hidden effect record ({n} samples)")
    ordered = tuple(c for c in causes.CAUSES if c in names)
    return HiddenEffectRecord(run=run, nominal=effect.nominal if nominal else None,
                              cause=ordered[0], causes=ordered, magnitude=effect.magnitude,
                              truth=truth, excitation=segs, effect_free=effect.nominal,
                              stops=stops, impacts=impacts, foreign=foreign,
                              foreign_magnitude=alien.magnitude, without_foreign=without_foreign)
