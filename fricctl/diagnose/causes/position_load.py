"""Position load: a smooth torque of position over the record's travel (gravity, a spring, a cable).

Regressors: ``LP(sin(2*pi*q/P))`` and ``LP(cos(2*pi*q/P))`` (free in sign) for the periods
``P`` of :data:`CYCLES`: the record's travel ``span`` (filtered position, sliding samples)
covers ``span/P`` = 1/16 .. 1.9 periods of the load (steps of 0.1 from 0.3); then a finer
grid (:data:`FINE`, steps of 0.01) around the best of them on the training residual of the
model as it stands (per block left out, again after each named cause).  A block left out
that reaches further beyond the other blocks' travel than that travel is long
(:data:`MAX_REACH`; a joint that drifts) is not tested by this cause -- it stays the model
as it stands, in the held-out residual and in the re-simulation: a wave fitted over one
travel does not tell the load that far beyond it.
Where the record tells a constant torque beside the load (per block left out: a wave and a
constant, the baseline's columns refitted, remove :data:`MIN_SHAPE_SHARE` of what the best
wave alone leaves on the training blocks), the period is chosen beside that constant and is
the one variant tried: chosen alone, a wave of a longer period bends to take up the
constant (issue 21's pair ``[12102, 61, 1]``: 0.30 of the fitted period over the travel
against the true 0.85, and the offset beside it went unnamed); the constant itself is left
to :mod:`.offset`.
Bench: ``m*g*r*sin(q/n + phi)``, gravity on an off-centre link behind a final ratio ``n`` =
4 .. 8 (period 25 .. 50 rad), ``m*g*r`` = 0.3 .. 0.8 Fc, random phase.

Notes
-----
Why one long wave, and not Legendre polynomials of the position normalised to the span: the
position ripple's periodogram searches periods up to half the travel (two periods or more in
the record: a ripple); this cause takes the periods above, so the two partition the period
axis at ``span/2`` and a load periodic within the travel stays the ripple's.  One sinusoid
of a period from ``span/1.9`` up is gravity on a link over 1-2 revolutions *exactly*
(``m*g*r`` and the period are the fitted amplitude and period; a cubic in the position
normalised to the span leaves 1-8 % of the variance of a sine over one period, 18-63 % over
1.5 periods and 71-94 % over two, by the phase), and at long periods it is a line with a
curvature over the travel (a spring, a cable); two coefficients per period keep its held-out
variance as low as the ripple's.  It is bounded outside the travel (a polynomial is not), so the
extended model re-simulates and travels beyond the record without running away.

What it does not tell: a constant torque (its long-period cosine is one) -- the
identifiability rule below leaves a load that is a constant over this travel to the offset
(:mod:`.offset`); a load with a sharper shape (a cam, a hard stop) is fitted by its
first wave only.  Nor a constant torque *beside* the load where its wave holds one: over a
travel that covers a small part of the period, the wave's sine and cosine are a constant and
a line there (:func:`constant_held`: on issue 21's pair record ``[12102, 61, 0]``, a travel
of 0.062 of the fitted period, they take up all but 0.002 % of a constant's column; the
evidence says so where they take up more than ``1 - MIN_SHAPE_SHARE``).  There a constant
beside the best wave does not remove :data:`MIN_SHAPE_SHARE` of what that wave leaves: the
period is chosen without it, the load named takes the constant in, and the offset scored
next removes less than the naming line ``MIN_SCORE``.  The benchmark's labels read the same
rule on the ground truth
(:meth:`fricctl.bench.hidden_effects.HiddenEffectRecord.expected`): an offset hidden beside
a load is expected only where the truth removes ``MIN_SCORE`` of what the best wave of this
cause's search leaves in place of the load and the offset.
"""

from __future__ import annotations

import functools
import math
import weakref
from dataclasses import replace

import numpy as np

from ...friction import PositionLoad
from .base import Cause, coulomb_level

#: Periods of the load the variants try first, as cycles over the record's travel (span/P):
#: long waves (a spring, a cable: a line and a curvature over the travel) to 1.9 cycles
#: (gravity over about two revolutions); two or more cycles are the position ripple's.
CYCLES = (1 / 16, 1 / 11, 1 / 8, 1 / 5.6, 1 / 4, *(round(0.3 + 0.1 * k, 2) for k in range(17)))
#: The finer grid around the best of :data:`CYCLES` on the training residual [cycles]: the
#: wave's phase at the ends of the travel then misses by at most pi*0.005 rad (1.6 % of the
#: amplitude; a grid of 0.05 cycle, 8 %, left a residual a ripple took up).
FINE = (-0.05, -0.04, -0.03, -0.02, -0.01, 0.01, 0.02, 0.03, 0.04, 0.05)
#: Most cycles over the travel a load may have (the ripple's periodogram starts at 2) [-].
MAX_CYCLES = 1.95
#: Least share of the residual a constant torque leaves that the load's shape over the travel
#: must remove to be told from that constant: the selection's 10 % line on the RMS [-].
MIN_SHAPE_SHARE = 1.0 - 0.9 ** 2
#: Fewest encoder counts the travel must span for a shape over it to be resolved [-].
MIN_COUNTS = 200
#: Farthest a held-out block's travel may reach beyond the training blocks' travel, in lengths
#: of that travel, for the block to test the load [-]: a wave fitted over a travel and carried
#: further beyond it than that travel is long tests the extrapolation, not the load (a long
#: wave over a short travel is nearly a line, its coefficients large).  Issue 21's pairs: a
#: drifting record's first block reached 2.7 training travels (24.5 rad beyond 9.2 rad), and the
#: fold's fit, 26 times the Coulomb level, made that block's held-out residual 20 times larger;
#: the blocks of eight records with the load hidden alone (tests' seeds) reach at most 0.81.
MAX_REACH = 1.0


def _travel(sig) -> tuple:
    """Lowest and highest filtered position of the sliding samples [rad]."""
    q = sig.qf[sig.moving] if np.any(sig.moving) else sig.qf
    return float(np.min(q)), float(np.max(q))


def wave(sig, period: float) -> np.ndarray:
    """The load's two columns at ``period`` [rad] or [m]: ``LP(sin(2*pi*q/P))`` and
    ``LP(cos(2*pi*q/P))`` of the filtered position, on every sample, shape (N, 2)."""
    ang = 2 * np.pi * sig.qf / period
    return np.column_stack([sig.filt(np.sin(ang)), sig.filt(np.cos(ang))])


#: Variants made for a record, by its signals (weakly: gone with the record) and by
#: (target, cycles): every fold and step shares one object per period, so the
#: cross-validation's per-variant products are computed once.
_MADE = weakref.WeakKeyDictionary()


def _variant(base, cycles, span):
    made = _MADE.setdefault(base.sig, {})
    key = (id(base.target), round(float(cycles), 6))
    if key not in made:
        period = span / float(cycles)
        made[key] = base.variant(period, wave(base.sig, period), (0, 0))
    return made[key]


def _per_step(compute):
    """``compute(base, span)`` once per step: kept with the record's variants, by the residual
    of the model as it stands (the array kept with the result: its id stays its own)."""
    @functools.wraps(compute)
    def cached(base, span):
        made = _MADE.setdefault(base.sig, {})
        r_all = base.current_residual
        key = (compute.__name__, id(r_all))
        if key not in made:
            made[key] = (r_all, compute(base, span))
        return made[key][1]
    return cached


@_per_step
def _best_cycles(base, span) -> dict:
    """Per block left out (and None: all data), the entry of :data:`CYCLES` that fits the
    residual of the model as it stands best on the training blocks (computed once per step:
    per-block normal equations, the training sums the total less the block's)."""
    sig = base.sig
    r_all = base.current_residual
    m = sig.moving
    rows = np.flatnonzero(m)
    folds, r = sig.folds[m], r_all[m]
    nf = sig.n_folds
    fit = []
    for c in CYCLES:
        x = np.take(_variant(base, c, span).extra, rows, axis=0)  # = extra[m], 15x faster
        prods = (x[:, 0] * x[:, 0], x[:, 0] * x[:, 1], x[:, 1] * x[:, 1], x[:, 0] * r, x[:, 1] * r)
        per = np.array([np.bincount(folds, weights=p, minlength=nf)[:nf] for p in prods])
        fit.append(np.column_stack([per.sum(axis=1)[:, None] - per, per.sum(axis=1)]))
    best = {}
    for j, fold in enumerate([*range(nf), None]):
        gain = []
        for sums in fit:  # r'x (x'x)^-1 x'r: what the two columns remove of the residual
            a, b, d, u, w = sums[:, j]
            det = a * d - b * b
            gain.append((d * u * u - 2 * b * u * w + a * w * w) / det if det > 0 else -np.inf)
        best[fold] = CYCLES[int(np.argmax(gain))]
    return best


def _moments(base, span, cycles, r, const) -> dict:
    """Per entry of ``cycles``: the moments ``Z'Z`` of ``Z`` = [the baseline's columns (fit
    mode), a constant, the wave's sine and cosine, ``r``] over the training blocks' sliding
    samples, per block left out and for all data (last), shape (blocks + 1, k, k); the
    regressors scaled to unit RMS (conditioning), ``r`` not."""
    sig = base.sig
    rows = np.flatnonzero(sig.moving)
    folds, nf = sig.folds[rows], sig.n_folds
    fixed = [const[:, None]] if base.columns is None else [base.columns[rows], const[:, None]]
    blocks = [np.flatnonzero(folds == f) for f in range(nf)]
    out = {}
    for c in cycles:
        x = np.column_stack(fixed + [np.take(_variant(base, c, span).extra, rows, axis=0)])
        z = np.column_stack([x / np.maximum(np.sqrt(np.mean(x ** 2, axis=0)), 1e-300), r])
        per = np.stack([z[b].T @ z[b] for b in blocks])
        total = per.sum(axis=0)
        out[c] = np.concatenate([total[None] - per, total[None]])
    return out


def _gains(moments, cols) -> np.ndarray:
    """Per block left out (and all data, last), what the regressors ``cols`` of
    :func:`_moments` remove of ``r``: ``g' G^-1 g`` [N^2*m^2] (-inf where singular)."""
    G = moments[:, cols][:, :, cols]
    g = moments[:, cols, -1]
    out = np.full(moments.shape[0], -np.inf)
    for j in range(moments.shape[0]):
        try:
            out[j] = float(g[j] @ np.linalg.solve(G[j], g[j]))
        except np.linalg.LinAlgError:
            pass
    return out


@_per_step
def _beside_constant(base, span) -> dict:
    """Per block left out (and None: all data), the cycles over the travel of the wave that,
    beside a free constant, fits the residual of the model as it stands best on the training
    blocks -- where it and the constant remove :data:`MIN_SHAPE_SHARE` of what the best wave
    alone leaves there (the record tells a constant beside the load); else None for that
    block.  Each searched over :data:`CYCLES`, then :data:`FINE` around the best of them, the
    baseline's columns refitted (fit mode); computed once per step."""
    sig = base.sig
    r_all = base.current_residual
    m = sig.moving
    nf = sig.n_folds
    nb = 0 if base.columns is None else base.columns.shape[1]
    wave_cols, const_col = [nb + 1, nb + 2], nb
    kinds = {"alone": list(range(nb)) + wave_cols,
             "beside": list(range(nb)) + [const_col] + wave_cols}
    const = sig.filt(np.ones(sig.t.size))[m]
    mom = _moments(base, span, CYCLES, r_all[m], const)
    gains = {k: np.array([_gains(mom[c], cols) for c in CYCLES]) for k, cols in kinds.items()}
    first = {k: [CYCLES[int(np.argmax(g[:, j]))] for j in range(nf + 1)]
             for k, g in gains.items()}
    fine = sorted({round(c + d, 6) for f in first.values() for c in f for d in FINE
                   if 0 < c + d <= MAX_CYCLES} - set(CYCLES))
    mom.update(_moments(base, span, fine, r_all[m], const))
    best = {k: [] for k in kinds}
    for k, cols in kinds.items():
        for j in range(nf + 1):
            near = [c for c in mom if abs(c - first[k][j]) < FINE[-1] + 1e-6]
            best[k].append(max((float(_gains(mom[c], cols)[j]), c) for c in near))
    out = {}
    for j, fold in enumerate([*range(nf), None]):
        rr = float(mom[CYCLES[0]][j, -1, -1])
        left_alone, left_both = rr - best["alone"][j][0], rr - best["beside"][j][0]
        told = left_alone > 0 and 1.0 - left_both / left_alone >= MIN_SHAPE_SHARE
        out[fold] = best["beside"][j][1] if told else None
    return out


def reach(sig, fold) -> float:
    """How far block ``fold``'s sliding samples reach beyond the travel of the other blocks'
    sliding samples (the training travel), in lengths of that travel [-] (filtered position;
    0 inside it, inf when the training travel has no length)."""
    m = sig.moving
    held, train = m & (sig.folds == fold), m & (sig.folds != fold)
    if not (np.any(held) and np.any(train)):
        return 0.0
    lo, hi = float(np.min(sig.qf[train])), float(np.max(sig.qf[train]))
    out = max(lo - float(np.min(sig.qf[held])), float(np.max(sig.qf[held])) - hi, 0.0)
    if out == 0.0:
        return 0.0
    return out / (hi - lo) if hi > lo else math.inf


def _variants(base, fold):
    """The wave chosen beside a constant where the record tells one on the training blocks
    (:func:`_beside_constant`); else :data:`CYCLES`, and :data:`FINE` around the one that fits
    the residual of the model as it stands best on the training blocks; none for a block
    left out that reaches further beyond the training travel than :data:`MAX_REACH` of its
    length: the block stays the model as it stands."""
    lo, hi = _travel(base.sig)
    span = hi - lo
    if not span > 0:
        return []
    if fold is not None and reach(base.sig, fold) > MAX_REACH:
        return []
    beside = _beside_constant(base, span)[fold]
    if beside is not None:  # a constant beside the wave is told: the period is the shape's
        return [_variant(base, beside, span)]
    coarse = [_variant(base, c, span) for c in CYCLES]
    best = _best_cycles(base, span)[fold]
    return coarse + [_variant(base, best + d, span) for d in FINE if 0 < best + d <= MAX_CYCLES]


def _extend(model, term, base):
    al, be = term.coef
    load = PositionLoad(float(math.hypot(al, be)), float(term.h), float(math.atan2(be, al)))
    return replace(model, friction=model.friction + load)


def _load(fr, q):
    return fr.position_load_amplitude * np.sin(2 * np.pi * q / fr.position_load_period
                                               + fr.position_load_phase)


def _evidence(base, term, extended):
    u = base.labels
    fr = extended.friction
    lo, hi = _travel(base.sig)
    q = np.linspace(lo, hi, 401)
    f = _load(fr, q)
    fc = coulomb_level(base.fitted)
    ptp = float(np.ptp(f))
    return (f"residual a smooth function of position over the travel q = {lo:.3g} .. {hi:.3g} "
            f"{u.position} ({(hi - lo) / fr.position_load_period:.2g} of the fitted period): a "
            f"load of {ptp:.3g} {u.torque} peak to peak ({100 * ptp / max(fc, 1e-12):.0f} % of "
            f"the Coulomb level), {f[0]:+.3g} {u.torque} at the low end, {f[-1]:+.3g} at the high "
            f"end, largest {f.max():+.3g} at q = {q[f.argmax()]:.3g}, smallest {f.min():+.3g} at "
            f"q = {q[f.argmin()]:.3g} {u.position}; fitted {fr.position_load_amplitude:.3g} "
            f"{u.torque} x sin(2*pi*q/{fr.position_load_period:.4g} "
            f"{'-' if fr.position_load_phase < 0 else '+'} {abs(fr.position_load_phase):.3g}) "
            f"(gravity: m*g*r = the amplitude, period "
            f"{fr.position_load_period / (2 * math.pi):.3g} x 2*pi)"
            + _constant_clause(base, fr.position_load_period))


def constant_held(base, period) -> float:
    """Share of a constant torque's column (``LP(1)``, sliding samples, the baseline's columns
    projected off) that the load's wave at ``period`` takes up [-]; NaN where the baseline's
    columns already span the constant (a record that moves one way)."""
    sig = base.sig
    m = sig.moving
    const = sig.filt(np.ones(sig.t.size))[m]
    cols = np.zeros((int(m.sum()), 0)) if base.columns is None else base.columns[m]
    sse = _left_beside(const, cols, wave(sig, period)[m])
    if not sse[0] > 1e-12 * float(np.sum(const ** 2)):
        return math.nan
    return 1.0 - sse[1] / sse[0]


def _constant_clause(base, period) -> str:
    """What the evidence says where the wave holds a constant over this travel: all but less
    than :data:`MIN_SHAPE_SHARE` of a constant's column (an offset beside the load is then
    told only by the rest: :mod:`.offset`); else nothing."""
    held = constant_held(base, period)
    if not held > 1.0 - MIN_SHAPE_SHARE:
        return ""
    return (f"; beside the load over this travel a constant torque is part of its wave (the "
            f"wave takes up {100 * held:.4g} % of a constant's column): an offset beside it is "
            f"told only by the {100 * (1 - held):.2g} % the wave leaves")


def _shape_share(base, period) -> float:
    """Share of the residual (sliding samples) that a constant torque leaves which the load's
    shape over the travel removes, fitted on all data with the baseline's columns [-]."""
    sig = base.sig
    m = sig.moving
    const = sig.filt(np.ones(sig.t.size))[:, None]
    cols = [const] if base.columns is None else [base.columns, const]
    sse = _left_beside(base.current_residual[m], np.column_stack(cols)[m], wave(sig, period)[m])
    return 1.0 - sse[1] / sse[0] if sse[0] > 0 else 0.0


def _left_beside(y, cols, load) -> tuple:
    """What ``y`` leaves (sum of squares) once the columns ``cols`` are fitted to it by least
    squares, and once ``cols`` and the load's wave columns ``load`` are (sliding samples)."""
    out = []
    for X in (cols, np.column_stack([cols, load])):
        r = y - X @ np.linalg.lstsq(X, y, rcond=None)[0] if X.shape[1] else y
        out.append(float(np.sum(r ** 2)))
    return tuple(out)


def _identifiable(base, term):
    """A shape over the travel: the travel spans :data:`MIN_COUNTS` encoder counts, and the
    load's shape removes :data:`MIN_SHAPE_SHARE` of what a constant torque leaves (else over
    this travel it is a constant: an offset, told by :mod:`.offset`)."""
    sig, u = base.sig, base.labels
    lo, hi = _travel(sig)
    if sig.resolution > 0 and hi - lo < MIN_COUNTS * sig.resolution:
        return (f"the travel ({hi - lo:.3g} {u.position}) spans fewer than {MIN_COUNTS} encoder "
                f"counts: no shape over it is resolved")
    share = _shape_share(base, term.h)
    if share < MIN_SHAPE_SHARE:
        return (f"over this record's travel (q = {lo:.3g} .. {hi:.3g} {u.position}) the fitted "
                f"load is a constant torque: its shape removes only {100 * share:.0f} % of the "
                f"residual a constant leaves (an offset, not a function of position)")
    return None


def _inject(rng, act):
    fc = act.coulomb
    # the position load covers less than one of its periods over the record's travel.
    # The bench's records with the load travel 14-39 rad (24 seeds): a period of 2*pi*n with
    # n = 4-8 gives 0.34-0.92 periods on them (n = 2-4 gave 0.55-2.07, a third above one
    # period and 3 of 24 at two or more: a ripple's record); gravity on the joint's own link
    # (period 2*pi) shows 2-6 periods on these travels: the ripple's case
    mag = dict(amplitude=rng.uniform(0.3, 0.8) * fc * act.strength,
               period=2 * math.pi * rng.uniform(4.0, 8.0) * act.travel,
               phase=rng.uniform(0, 2 * math.pi))
    load = PositionLoad(mag["amplitude"], mag["period"], mag["phase"])
    # below the Coulomb level, the link holds itself at rest where the open-loop segments pause
    return act.rigid(magnitude=mag, friction=act.friction() + load, breakaway=fc + mag["amplitude"])


CAUSE = Cause(
    name="position_load", order=130,
    physical="a smooth load of position over the travel (gravity on an off-centre link, a spring)",
    changes=("position_load_amplitude", "position_load_period", "position_load_phase"),
    params=("load_sin", "load_cos"), variants=_variants, per_fold=True, per_step=True,
    identifiable=_identifiable,
    extend=_extend, evidence=_evidence, inject=_inject)
