"""Effects that are not causes (issue 21, item 5): the bench hides an effect no cause of the
list represents (:data:`fricctl.bench.hidden_effects.FOREIGN`), the diagnosis must name no
cause for it and must not call the record explained while its residual stays above twice
the floor.

A cause named on such a record is wrong unless its extension is the foreign effect's physics;
no cause of the registry models a torque disturbance in time or a scale error of the torque
sensor, so *every* cause named on these records is counted wrong (``thermal_drift`` on a time
sinusoid, ``inertia`` + ``friction_scale`` or ``load_dependent`` on a torque gain, ``inertia``
+ ``drag`` on a position gain: each fits part of it, none is what happened).  Nor does any
cause model a friction law of another shape (a sub-linear viscous law, a Coulomb level reached
smoothly with speed): ``stribeck``, ``drag`` or ``presliding`` named on them is wrong too.

Seeds: ``[7100, i]``, ``[7300, i]``, ``[7600, i]`` and ``[7700, i]`` were used while building
the method (not here), and ``[7500, i]``: the first sweep, which found ``load_dependent``
named on a torque gain when the drive never brakes (its column is then the nominal torque
itself; fixed in the cause's identifiability); ``[7400, i]`` for the fast cases, ``[7800, i]``
for the slow sweep (not looked at before the fix).  The foreign friction laws: ``[7900, i, m]``
while building (the sweep that found ``presliding`` named on a smooth Coulomb law at the
longest presliding length searched; fixed in the cause's identifiability); ``[8000, i, m]``,
meant for the slow sweep, then found ``position_load``, ``presliding`` and ``thermal_drift``
named on three smooth Coulomb records (fixed in the selection: a candidate must beat a
generic friction curve, :func:`fricctl.diagnose.selection.speed_curve`) and became building
seeds too; ``[8100, i, m]`` for the slow sweep (run once, after both fixes).
"""

import math
import re

import numpy as np
import pytest

from fricctl.bench.hidden_effects import EXCITATIONS, FOREIGN, hidden_effect_record
from fricctl.diagnose import MIN_SCORE, diagnose
from fricctl.diagnose.verdict import EXPLAINED_RATIO, SHAPE_SHARE

#: The foreign effects of the bench (``none`` is not one).
NAMES = tuple(name for name in FOREIGN if name != "none")
#: The foreign friction laws: they replace one of the drawn laws.
LAWS = ("power_viscous", "smooth_coulomb")


def _wrong(d) -> set:
    """The causes a diagnosis named on a record whose only effect is foreign: all of them."""
    return set(d.causes) - {"none"}


def _honest(d) -> bool:
    """The verdict keeps the issue's rule: never explained above twice the floor."""
    return not (d.explained and d.verdict.residual_over_floor > EXPLAINED_RATIO)


# ----------------------------------------------------------------------------- the bench
def test_foreign_effects_are_drawn_after_everything_else():
    # the same seed without and with a torque gain: the same actuator, excitation and noise,
    # so the same motion, and the recorded torque exactly (1 + e) times the other (no
    # measurement noise on the default sensors): a closed form, to round-off
    rng_args = [7400, 99]
    plain = hidden_effect_record(np.random.default_rng(rng_args), cause="none", duration=10.0,
                                 nominal=True)
    gained = hidden_effect_record(np.random.default_rng(rng_args), cause="none", duration=10.0,
                                  foreign="torque_gain")
    e = gained.foreign_magnitude["error"]
    assert 0.05 <= abs(e) <= 0.15
    assert gained.nominal is not None and gained.causes == ("none",)  # implies a nominal model
    assert gained.foreign == "torque_gain" and plain.foreign == "none"
    np.testing.assert_array_equal(gained.run.position, plain.run.position)
    np.testing.assert_allclose(gained.run.torque, (1.0 + e) * plain.run.torque, rtol=1e-12,
                               atol=0.0)
    # a position gain: the same torque, the positions (and reference) scaled
    scaled = hidden_effect_record(np.random.default_rng(rng_args), cause="none", duration=10.0,
                                  foreign="position_gain")
    ep = scaled.foreign_magnitude["error"]
    assert 0.05 <= abs(ep) <= 0.15 and scaled.nominal is not None
    np.testing.assert_array_equal(scaled.run.torque, plain.run.torque)
    np.testing.assert_allclose(scaled.run.position, (1.0 + ep) * plain.run.position, rtol=1e-12,
                               atol=0.0)
    # a disturbance in time moves the joint; what was drawn before it is the same
    sine = hidden_effect_record(np.random.default_rng(rng_args), cause="none", duration=10.0,
                                foreign="time_sine")
    m = sine.foreign_magnitude
    fc = sine.effect_free.friction.coulomb_pos
    assert 0.2 * fc <= m["amplitude"] <= 0.5 * fc and 0.3 <= m["frequency"] <= 3.0
    assert sine.excitation == plain.excitation and sine.truth == plain.truth
    assert sine.nominal is None
    assert not np.array_equal(sine.run.position, plain.run.position)


def test_a_foreign_friction_law_replaces_the_drawn_one():
    # the same seed without and with a foreign law: the same actuator and excitation; the
    # law replaces the drawn one, sized at the record's RMS speed v (closed forms, round-off)
    rng_args = [7400, 98]
    plain = hidden_effect_record(np.random.default_rng(rng_args), cause="none", duration=10.0)
    power = hidden_effect_record(np.random.default_rng(rng_args), cause="none", duration=10.0,
                                 foreign="power_viscous")
    drawn = plain.truth.friction
    assert power.without_foreign == plain.truth and power.excitation == plain.excitation
    m, fr = power.foreign_magnitude, power.truth.friction
    p, v = m["exponent"], m["rms_speed"]
    assert 0.4 <= p <= 0.7 and fr.power_viscous_exponent == p
    assert fr.viscous_pos == fr.viscous_neg == 0.0  # in place of b*w, not on top of it
    # c*v**p = b*v: the drawn viscous torque at the record's RMS speed
    assert fr.power_viscous_pos * v ** p == pytest.approx(drawn.viscous_pos * v, rel=1e-12)
    assert power.truth.inertia == plain.truth.inertia and fr.coulomb_pos == drawn.coulomb_pos
    smooth = hidden_effect_record(np.random.default_rng(rng_args), cause="none", duration=10.0,
                                  foreign="smooth_coulomb")
    m, fr = smooth.foreign_magnitude, smooth.truth.friction
    assert fr.coulomb_pos == fr.coulomb_neg == 0.0 and fr.breakaway(1) == 0.0
    assert fr.smooth_coulomb_pos == drawn.coulomb_pos and fr.viscous_pos == drawn.viscous_pos
    assert 0.2 <= fr.smooth_coulomb_velocity / m["rms_speed"] <= 0.4
    # v is the RMS of the true velocity of the record simulated without the law (the plain
    # one): the recorded positions' finite difference agrees within a few percent
    w = np.diff(plain.run.position) / np.diff(plain.run.t)
    assert v == pytest.approx(float(np.sqrt(np.mean(w ** 2))), rel=0.05)
    assert smooth.foreign_magnitude["rms_speed"] == v
    # the foreign weight is only defined for a friction law
    with pytest.raises(ValueError, match="not a friction law"):
        hidden_effect_record(np.random.default_rng(rng_args), cause="none", duration=10.0,
                             foreign="time_sine").foreign_weight()


def test_an_unknown_foreign_effect_is_refused():
    with pytest.raises(ValueError, match="foreign must be one of"):
        hidden_effect_record(np.random.default_rng(0), foreign="backlash")


# ----------------------------------------------------------------------------- the diagnosis
@pytest.mark.parametrize("seed", range(2))
@pytest.mark.parametrize("name", NAMES)
def test_no_cause_for_a_foreign_effect(name, seed):
    rec = hidden_effect_record(np.random.default_rng([7400, seed]), cause="none",
                               duration=20.0, foreign=name)
    d = diagnose(rec.run, rec.nominal)
    assert not _wrong(d), d.report()
    assert _honest(d), d.report()
    if not d.explained:
        assert "within noise" not in d.evidence and "within noise" not in d.report()
    if FOREIGN[name].nominal:
        # a sensor's scale error: the candidates that reached the score were tried against a
        # scale of that sensor and rejected, the fitted scale within 1 % of the true one
        # (torque noise 1-3 % of Fc)
        gain = 1.0 + rec.foreign_magnitude["error"]
        sensor = "scale error of the recorded " + name.split("_")[0]  # torque, position
        scale = [r for r in d.not_identifiable.values() if sensor in r]
        assert scale, d.report()
        fitted = float(re.search(r" x (\d+\.\d+)", scale[0]).group(1))
        assert fitted == pytest.approx(gain, rel=0.01)


def test_a_torque_gain_on_a_drive_that_never_brakes():
    # torque triangles and pulses just above breakaway (the "stuck" excitation): the recorded
    # torque never opposes the motion, so load_dependent's column |T|*sign(w) is the nominal
    # torque itself -- exactly what a torque gain scales; it cannot be told from it
    rec = hidden_effect_record(np.random.default_rng([7400, 2]), cause="none", duration=20.0,
                               foreign="torque_gain", excitation="stuck")
    d = diagnose(rec.run, rec.nominal)
    assert not _wrong(d), d.report()
    assert _honest(d), d.report()
    why = d.not_identifiable.get("load_dependent", "")
    assert "scale error of the recorded torque" in why, d.report()


def test_a_smooth_coulomb_law_is_not_read_as_presliding():
    # the record of the first sweep ([7900, 9, 1]: a linear axis, a smooth Coulomb law over
    # 6 % of its RMS speed) where presliding was named at the longest presliding length
    # searched (150 counts), removing 24 % of the residual and leaving it 6.8 x the floor
    rec = hidden_effect_record(np.random.default_rng([7900, 9, 1]), cause="none",
                               duration=20.0, foreign="smooth_coulomb", axis="linear",
                               sample_time=0.002, strength=0.3)
    assert rec.foreign_weight() > MIN_SCORE  # it weighs on the record
    d = diagnose(rec.run, rec.nominal)
    assert not _wrong(d), d.report()
    assert not d.explained, d.report()
    assert "longest searched" in d.not_identifiable.get("presliding", ""), d.report()


def test_a_smooth_coulomb_law_is_not_read_as_a_position_load():
    # [8000, 0, 1]: a smooth Coulomb level over 22 % of the RMS speed on a rotary joint; a
    # load of position fitted there removed 19 % of the residual (the best candidate) and was
    # named, while a generic friction curve of velocity removes nearly all of it
    rec = hidden_effect_record(np.random.default_rng([8000, 0, 1]), cause="none",
                               duration=20.0, foreign="smooth_coulomb", sample_time=0.002)
    d = diagnose(rec.run, rec.nominal)
    assert not _wrong(d), d.report()
    assert not d.explained and d.verdict.residual_over_floor > EXPLAINED_RATIO, d.report()
    why = d.not_identifiable.get("position_load", "")
    assert "a friction law of another shape" in why, d.report()
    # the verdict says where the rest lives: a generic friction curve of velocity removes
    # nearly all of it held out (measured 0.94-0.96 on [8300, 0..1]), in the text and the JSON
    assert d.verdict.other_shape > 0.8, d.report()
    assert "the friction-speed curve may have another shape" in d.verdict.sentence()
    assert d.as_dict()["verdict"]["other_shape_share"] == pytest.approx(d.verdict.other_shape)


def test_the_verdict_does_not_blame_the_friction_curve_for_what_it_is_not():
    # a dead band between motor and load left unexplained (its impacts): a friction curve of
    # velocity does not remove the rest, and the verdict does not say it does
    rec = hidden_effect_record(np.random.default_rng(5), cause="backlash", duration=20.0)
    d = diagnose(rec.run)
    assert d.causes == ("backlash",) and not d.explained, d.report()
    assert d.verdict.other_shape < SHAPE_SHARE, d.report()
    assert "another shape" not in d.verdict.sentence()


@pytest.mark.slow
def test_foreign_friction_laws_sweep():
    # >= 12 records per foreign friction law (16), seeds [8100, i, m] run once after the
    # fixes; every excitation, both axes, three sample rates, full and reduced
    # strength.  Target of issue 21: 0 wrong causes, 0 "explained" verdicts with a residual
    # above twice the floor; and the laws weigh on most records (else the test tests nothing)
    rows = []
    for m, name in enumerate(LAWS):
        for i in range(16):
            rec = hidden_effect_record(
                np.random.default_rng([8100, i, m]), cause="none", duration=20.0, foreign=name,
                excitation=tuple(EXCITATIONS)[i % len(EXCITATIONS)],
                axis="linear" if i % 4 == 1 else "rotary",
                sample_time=(0.002, 0.001, 0.004)[(i // 3) % 3], strength=(1.0, 0.3)[i % 2])
            d = diagnose(rec.run, rec.nominal)
            rows.append((name, i, rec.foreign_weight(), tuple(sorted(_wrong(d))), d.explained,
                         d.verdict.residual_over_floor))
    for name in LAWS:
        mine = [r for r in rows if r[0] == name]
        print(f"{name}: {len(mine)} records, foreign weight "
              f"{min(r[2] for r in mine):.2f} .. {max(r[2] for r in mine):.2f} "
              f"({sum(r[2] >= MIN_SCORE for r in mine)} above the 10 % line), "
              f"{sum(bool(r[3]) for r in mine)} with a wrong cause "
              f"{sorted({c for r in mine for c in r[3]})}, {sum(r[4] for r in mine)} explained, "
              f"residual/floor {min(r[5] for r in mine):.2f} .. {max(r[5] for r in mine):.2f}")
        assert len(mine) >= 12 and sum(r[2] >= MIN_SCORE for r in mine) >= len(mine) // 2
    assert not [r for r in rows if r[3]], rows
    assert not [r for r in rows if r[4] and r[5] > EXPLAINED_RATIO], rows
    assert all(math.isfinite(r[5]) for r in rows), rows


@pytest.mark.slow
def test_foreign_effects_sweep():
    # >= 8 records per foreign effect (10), seeds [7800, i] never looked at while building;
    # every excitation of the bench, both axes, full and reduced strength (an effect near the
    # floor is where an "explained" verdict could be wrong); the time disturbance also
    # against a nominal model.  Target of issue 21: 0 wrong causes, 0 "explained" verdicts
    # with a residual above twice the floor.
    settings = [(name, False) for name in NAMES] + [("time_sine", True)]
    rows = []
    for name, nominal in settings:
        for i in range(10):
            rec = hidden_effect_record(
                np.random.default_rng([7800, i]), cause="none", duration=20.0, foreign=name,
                nominal=nominal, excitation=tuple(EXCITATIONS)[i % len(EXCITATIONS)],
                axis="linear" if i % 4 == 1 else "rotary", strength=(1.0, 0.3)[i % 2])
            d = diagnose(rec.run, rec.nominal)
            rows.append((name, rec.nominal is not None, i, tuple(sorted(_wrong(d))), d.explained,
                         d.verdict.residual_over_floor))
    for name, nominal in sorted(set((r[0], r[1]) for r in rows)):
        mine = [r for r in rows if r[:2] == (name, nominal)]
        ratios = [r[5] for r in mine]
        print(f"{name} (nominal model: {nominal}): {len(mine)} records, "
              f"{sum(bool(r[3]) for r in mine)} with a wrong cause "
              f"{sorted({c for r in mine for c in r[3]})}, {sum(r[4] for r in mine)} explained, "
              f"residual/floor {min(ratios):.2f} .. {max(ratios):.2f}")
    assert all(len([r for r in rows if r[0] == name]) >= 8 for name in NAMES)
    assert not [r for r in rows if r[3]], rows
    assert not [r for r in rows if r[4] and r[5] > EXPLAINED_RATIO], rows
    assert all(math.isfinite(r[5]) for r in rows), rows
