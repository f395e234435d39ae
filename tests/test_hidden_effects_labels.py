"""The labels of the hidden-effect records (:meth:`HiddenEffectRecord.weights` and
:meth:`~HiddenEffectRecord.expected`): what the benchmarks and the rate tests count as the
right answer.

Seeds ``[2123, i]``, chosen before the rule was written: record 0 of the closed-loop loads
holds a load that is a constant over its travel, the others a shape.
"""

from dataclasses import replace

import numpy as np
import pytest

from fricctl.bench.hidden_effects import hidden_effect_record
from fricctl.diagnose import diagnose
from fricctl.friction import FrictionModel


def _shifted(model, di=0.1, db=0.005, dc=0.02):
    """The model with its baseline (I, b, Fc) moved: a change the refitted baseline takes up."""
    d = model.friction.as_dict()
    for k in ("viscous_pos", "viscous_neg"):
        d[k] += db
    for k in ("coulomb_pos", "coulomb_neg"):
        d[k] += dc
    return replace(model, inertia=model.inertia * (1 + di), friction=FrictionModel.from_dict(d))


@pytest.mark.parametrize("cause", [("asymmetry", "time_delay"), ("stribeck", "position_ripple")])
def test_weights_read_both_residuals_alike(cause):
    # with no nominal model the diagnosis refits the baseline: a weight must not depend on the
    # truth's baseline parameters.  Before the truth's residual was projected as the other one
    # was, moving them moved the weights (and a stribeck beside a delay read -12 %).  Causes
    # that scale the friction (drift, load dependence) are left out: there the baseline
    # parameters are not additive
    rec = hidden_effect_record(np.random.default_rng([2123, 9]), cause=cause, duration=20.0)
    assert rec.nominal is None
    moved = replace(rec, truth=_shifted(rec.truth), effect_free=_shifted(rec.effect_free))
    w, wm = rec.weights(), moved.weights()
    assert set(w) == set(cause)
    for c in cause:
        # (the old reading gave -4.6 and -69 here; the Coulomb column is not exactly linear
        # in Fc on every sliding sample: 3e-4)
        assert wm[c] == pytest.approx(w[c], abs=1e-3), (c, w, wm)


def test_a_load_constant_over_the_travel_is_expected_as_an_offset():
    # closed loop over a short travel: gravity weighs 99.9 % on record 0, but over its travel
    # it is a constant; the diagnosis names the offset (position_load's identifiability rule)
    # and the label agrees; on records 1-2 the shape is told and both say position_load
    for i, want in ((0, {"offset"}), (1, {"position_load"}), (2, {"position_load"})):
        rec = hidden_effect_record(np.random.default_rng([2123, i]), cause="position_load",
                                   excitation="closed_loop", duration=20.0)
        assert rec.weights()["position_load"] > 0.9
        assert rec.expected() == want, i
        assert set(diagnose(rec.run, rec.nominal).causes) == want, i


def test_expected_applies_the_line():
    # a weak effect is not expected (below MIN_SCORE), a strong one beside it is: a Stribeck
    # hump at a tenth of its size weighs 0.4 % beside a delay's 83 % (measured)
    from fricctl.diagnose import MIN_SCORE
    rec = hidden_effect_record(np.random.default_rng([2123, 9]), cause=("stribeck", "time_delay"),
                               duration=20.0, strength=0.1)
    w = rec.weights()
    assert w["stribeck"] < MIN_SCORE <= w["time_delay"]
    assert rec.expected() == {"time_delay"}
    assert rec.expected(weights=w) == {"time_delay"}  # the weights at hand, not made again


def test_a_stribeck_hump_beside_presliding_weighs():
    # the truth of a presliding (LuGre) record with a Stribeck hump is read along the motion
    # with the hump (fricctl.friction.presliding.level_along): undoing the hump changes the
    # residual.  Read without it, the hump of every such record weighed 0 % (the pairs
    # benchmark's two records: 0.00 and 0.00, now 0.23 and 0.59) and a diagnosis naming it was
    # counted a false cause.  This seed's hump weighs 0.49 (0.00 before): expected
    from fricctl.diagnose import MIN_SCORE
    rec = hidden_effect_record(np.random.default_rng([2123, 11]), cause=("stribeck", "presliding"),
                               duration=20.0)
    excess = rec.truth.friction.stribeck_pos
    assert excess > 0.2 * rec.truth.friction.coulomb_pos  # a hump the record carries
    w = rec.weights()
    assert w["stribeck"] >= MIN_SCORE, w


def test_an_offset_beside_a_load_whose_wave_holds_a_constant_is_not_expected():
    # seeds [2123, 20 + i], the first two looked at: a closed loop over a short linear travel
    # (0.06 of the load's period: a wave is a constant and a line there) and a rotary record
    # over 0.45 of it.  Both effects weigh over 90 % on each; the truth removes 0.2 % of what
    # the best single wave of the load's search leaves in place of load and offset on the
    # first (the offset not expected: the old labels expected it), 57 % on the second
    from fricctl.diagnose import MIN_SCORE
    from fricctl.diagnose.causes import position_load as pl

    for i, exc, axis, want in ((0, "closed_loop", "linear", {"position_load"}),
                               (1, "mixed", "rotary", {"position_load", "offset"})):
        rec = hidden_effect_record(np.random.default_rng([2123, 20 + i]),
                                   cause=("position_load", "offset"), excitation=exc, axis=axis,
                                   duration=20.0)
        assert rec.nominal is None  # fit mode: the baseline's columns are projected off
        w = rec.weights()
        assert min(w.values()) > 0.9, (i, w)
        assert rec.expected(weights=w) == want, i
        # the rule recomputed the long way: every period of a grid of 0.01 cycle over the
        # search's range, the baseline's columns refitted, numpy's least squares
        read = rec._reader(8)
        m, sig = read.moving, read.sig
        lo, hi = pl._travel(sig)
        base = np.column_stack([sig.a, sig.filt(sig.w), sig.filt(sig.seff)])[m]

        def sse(r, *extra):
            cols = np.column_stack([base, *extra])
            return float(np.sum((r - cols @ np.linalg.lstsq(cols, r, rcond=None)[0]) ** 2))

        both = read.residual(rec._undone("position_load", "offset"))
        alone = min(sse(both, pl.wave(sig, (hi - lo) / c)[m])
                    for c in np.arange(1 / 16, pl.MAX_CYCLES, 0.01))
        told = 1 - sse(read.residual(rec.truth)) / alone
        assert (told >= MIN_SCORE) == ("offset" in want), (i, told)
    # and the diagnosis of the first names the load alone, its evidence saying why
    rec = hidden_effect_record(np.random.default_rng([2123, 20]), cause=("position_load", "offset"),
                               excitation="closed_loop", axis="linear", duration=20.0)
    d = diagnose(rec.run, rec.nominal)
    assert set(d.causes) == {"position_load"}
    assert "a constant torque is part of its wave" in d.evidence


def test_the_wave_holds_a_constant_over_a_short_part_of_its_period():
    # position_load.constant_held on a record's own signals and travel: a wave of 16 travels'
    # period is a constant and a line over the travel (it takes up more than 1 - MIN_SHAPE_SHARE
    # of a constant's column, where the evidence says so); over 1.5 periods a constant is
    # mostly outside the wave (sine and cosine average out over each full period)
    from types import SimpleNamespace

    from fricctl.diagnose.causes import position_load as pl

    rec = hidden_effect_record(np.random.default_rng([2123, 21]), cause=("position_load", "offset"),
                               excitation="mixed", axis="rotary", duration=20.0)
    sig = rec._reader(8).sig
    lo, hi = pl._travel(sig)
    base = SimpleNamespace(sig=sig, columns=np.column_stack([sig.a, sig.filt(sig.w),
                                                             sig.filt(sig.seff)]))
    held = {c: pl.constant_held(base, (hi - lo) / c) for c in (1 / 16, 1.5)}
    assert held[1 / 16] > 1 - pl.MIN_SHAPE_SHARE > held[1.5], held
