"""Records from outside the package's generators that a read-only audit (audit B, 2026-11-28)
found the diagnosis answering confidently and wrongly, and the numbers it printed unflagged.

A rigid Coulomb-viscous joint (the package's simulator, PD control, an ordinary encoder) that
tracks a triangle moves at one speed between abrupt reversals; one that tracks a ramp never
reverses.  Neither holds any effect of the list.  Reference: the simulated joint (no cause).
"""

import math
import re

import numpy as np

from fricctl.diagnose import diagnose
from fricctl.diagnose.verdict import EXPLAINED_RATIO, verdict
from fricctl.friction import Coulomb, Viscous
from fricctl.plant import RigidJoint
from fricctl.simulate import Schedule, simulate_schedule

INERTIA, WN = 0.01, 2 * math.pi * 8


def _tracking(reference, counts=4096, seed=0, noise=0.002, duration=20.0, disturbance=None):
    """The joint tracking ``reference(t)``; ``disturbance(t)``: a torque it receives unrecorded."""
    t = np.arange(0, duration, 1e-3)
    n = t.size
    start = np.zeros(n, bool)
    start[0] = True
    sim = simulate_schedule(
        RigidJoint(inertia=INERTIA, friction=Viscous(0.02) + Coulomb(0.2)),
        Schedule(kp=np.full(n, INERTIA * WN ** 2), kd=np.full(n, 1.4 * INERTIA * WN),
                 reference=reference(t), feedforward=np.zeros(n), segment_start=start),
        sample_time=1e-3, max_torque=5.0, encoder_resolution=2 * math.pi / counts,
        noise=np.random.default_rng(seed).normal(0, noise, n)
        + (0.0 if disturbance is None else disturbance(t)))
    return sim.to_run()


def _triangle(t):
    ph = (t % 4.0) / 4.0
    return np.where(ph < 0.5, 4 * ph, 4 * (1 - ph))


def test_a_cause_named_from_a_biased_least_squares_fit_is_not_called_explained():
    # the triangle at 1 rad/s, 4096 counts: the least-squares baseline is biased (inertia 0.0067,
    # viscous 0; the simulation-error fit: 0.0099, 0.0156, 0.204), a backlash of 3 deg took up
    # that bias and the record was called "explained within noise" at 0.70 times the floor.
    # Now: whatever is named, the simulation-error baseline re-simulating the windows better
    # than the extended model is said, and the record is not called explained
    d = diagnose(_tracking(_triangle))
    v = d.verdict
    if d.causes == ("none",):  # nothing named (the right answer): nothing to caution about
        return
    assert not d.explained and v.caution, v.sentence()
    assert "re-simulates its windows better than the extended model" in v.caution
    assert v.residual_over_floor <= EXPLAINED_RATIO  # at the floor, and still not explained
    assert v.sentence().startswith("Not determined whether the record is explained")
    assert math.isnan(v.other_shape) and "another shape" not in v.sentence()  # at noise level
    out = d.as_dict()
    assert out["explained"] is False and "better than the extended" in out["verdict"]["caution"]
    assert "Explained within noise" not in d.report() and "Explained within noise" not in d.evidence


def test_a_record_with_an_effect_the_extended_model_re_simulates_better_has_no_caution():
    # the other side (reference: the package's generator, a time delay alone: its extended
    # model re-simulates the windows 80 times better than the simulation-error baseline)
    from fricctl.bench.hidden_effects import hidden_effect_record

    rec = hidden_effect_record(np.random.default_rng([12105, 305]), cause="time_delay",
                               duration=20.0)
    d = diagnose(rec.run)
    assert d.causes == ("time_delay",) and d.explained and not d.verdict.caution


def test_a_residual_far_below_the_floor_is_not_called_explained():
    # the verdict alone: a residual of a third of the floor with hundreds of effective degrees
    # of freedom says the twin is not this record's chain (audit B's ramp record: 0.005 times
    # the floor, "explained"); a residual at 0.9 of it is explained as before
    rng = np.random.default_rng(0)
    r = rng.standard_normal(4000)
    against = {k: rng.standard_normal(4000) for k in ("position", "velocity", "time", "torque")}
    low = verdict(1.0 / 3.0, 1.0, r, against)
    assert not low.explained and "below half of it" in low.reason
    assert low.sentence().startswith("Not determined whether the record is explained")
    assert verdict(0.9, 1.0, r, against).explained
    # the lower test is the F test's: a short residual a third of the floor cannot tell
    assert verdict(1.0 / 3.0, 1.0, r[:3], against={k: a[:3] for k, a in against.items()}).explained


def test_a_record_that_never_reverses_prints_no_nan_and_flags_bounds():
    # a ramp at 0.5 rad/s: no backward sliding sample, one speed.  Audit B found "+nan" in the
    # offset's, the drag's and the asymmetry's evidence, and the load coefficient printed at its
    # bound (0.5) as a fit
    d = diagnose(_tracking(lambda t: 0.5 * t))
    text = d.report()
    assert not re.search(r"\bnan\b", text, re.I)  # no NaN said as a number ("resonance" is fine)
    assert "no sliding sample" in text or "nothing moving backward" in text
    for e in d.below_line:
        if e.cause == "load_dependent" and e.parameters.get("load_coefficient", 0) >= 0.4995:
            assert "at the coefficient's bound" in e.evidence


def test_a_hump_fitted_below_every_sliding_speed_cannot_be_told():
    # the Stribeck velocity below the record's slowest sliding sample: the hump is fitted on its
    # tail (audit B: an excess of 11476 % of the Coulomb level, printed as a fit)
    from fricctl.diagnose.causes import REGISTRY, Baseline, Term
    from fricctl.diagnose.crossval import baseline_fit
    from fricctl.diagnose.signals import estimate_signals

    sig = estimate_signals(_tracking(_triangle), 8)
    base = Baseline(sig, None, baseline_fit(sig).estimates.copy())
    slowest = float(np.min(np.abs(sig.w[sig.moving])))
    cause = "stribeck"
    why = REGISTRY[cause].identifiable(base, Term(h=0.5 * slowest, coef=np.array([1.0])))
    assert why is not None and "below every sliding sample's speed" in why
    assert REGISTRY[cause].identifiable(base, Term(h=2.0 * slowest, coef=np.array([1.0]))) is None


def test_a_disturbance_in_time_at_one_speed_is_not_named_a_ripple():
    # the triangle at 1 rad/s with an unrecorded 3 Hz torque of 0.08 N*m: at one speed a period
    # in time is a period in position (0.33 rad), and audit B's record was named
    # `position_ripple` (not explained).  A sinusoid in time at the ripple's frequency at the
    # median speed removes as much (85 % against 38 %): not told, and said why
    run = _tracking(_triangle, counts=16384,
                    disturbance=lambda t: 0.08 * np.sin(2 * np.pi * 3 * t))
    d = diagnose(run)
    assert "position_ripple" not in d.causes and not d.explained
    assert "periodic in time at" in d.not_identifiable.get("position_ripple", ""), \
        d.not_identifiable


def test_the_true_model_supplied_names_nothing_and_leaks_no_numpy_warning():
    # the triangle with the simulated joint supplied: nothing named, explained; a Stribeck
    # variant whose column is nearly zero on the training blocks overflowed its held-out sum of
    # squares to inf (right) with numpy's overflow warnings printed to the user (audit B)
    import warnings

    from fricctl.plant import JointModel

    run = _tracking(_triangle)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        d = diagnose(run, JointModel(inertia=INERTIA, friction=Viscous(0.02) + Coulomb(0.2)))
    assert d.causes == ("none",) and d.explained


def test_a_ramp_whose_residual_is_far_below_the_floor_is_not_determined():
    # audit B's ramp at 0.5 rad/s with almost no noise (1e-6 N*m): the least-squares baseline's
    # inertia was 10 times the truth, the twin of it left a floor 200 times the record's
    # residual, and the record was called "explained" at 0.005 times the floor
    d = diagnose(_tracking(lambda t: 0.5 * t, counts=16384, noise=1e-6))
    v = d.verdict
    assert v.residual_over_floor < 1.0 / EXPLAINED_RATIO, v.sentence()
    assert not d.explained and "below half of it" in v.reason
    assert v.sentence().startswith("Not determined whether the record is explained")


def test_a_caution_above_twice_the_floor_follows_the_not_explained_sentence():
    # a true backlash of the generator (review R11's record: 2.2 times the floor): its
    # extended model, fitted on the equation error, re-simulates worse than the rigid DIDIM
    # fit; the caution is said after the verdict's own sentence, naming the one cause
    from fricctl.bench.hidden_effects import hidden_effect_record

    rec = hidden_effect_record(np.random.default_rng([12105, 306]), cause="backlash",
                               duration=20.0, strength=0.5)
    d = diagnose(rec.run)
    v = d.verdict
    assert d.causes == ("backlash",) and v.residual_over_floor > EXPLAINED_RATIO
    assert v.caution.startswith("the rigid baseline fricctl identify fits to the record by "
                                "simulation error (DIDIM)")
    assert "the cause named (backlash) is fitted on the equation error" in v.caution
    text = v.sentence()
    assert text.startswith("Not explained:") and text.endswith(v.caution[1:] + ".")


def test_the_caution_compares_with_didim_even_where_didim_lost_a_parameter(monkeypatch):
    # where DIDIM does not identify a parameter the least-squares fit reports the equation
    # error: the caution compares with DIDIM's own fit and says what it lost (before, no
    # caution: the triangle's false backlash would have been "explained" again); with no
    # DIDIM fit at all (the record not replayed) there is nothing to compare with.
    # The triangle's models, compared as DIDIM's, as the least-squares fit's, and with none
    from dataclasses import replace
    from types import SimpleNamespace

    from fricctl.diagnose import api

    seen = {}
    real = api._setup
    monkeypatch.setattr(api, "_setup", lambda *a: seen.setdefault("setup", real(*a)))
    run = _tracking(_triangle)
    d = diagnose(run)
    setup = seen["setup"]
    setup = replace(setup, ident=setup.ident.result())  # as the diagnosis resolves it
    sel = SimpleNamespace(selected=tuple(SimpleNamespace(cause=SimpleNamespace(name=c))
                                         for c in d.causes))
    assert setup.ident.result.method == "DIDIM" and d.causes != ("none",)
    made = []

    def rigid(r):  # DIDIM's fit as the diagnosis makes it a model
        made.append(r)
        return api._record_fields(api._identified(r, run), run, setup.sig, None)

    said = api._simulation_caution(setup, sel, d.baseline, d.extended, rigid)
    assert not made  # DIDIM's fit is the baseline reported
    assert said == d.verdict.caution != "" and "does not identify" not in said
    ident = setup.ident
    ls_result = replace(ident.start, method="IDIM-LS")  # as identify reports a lost parameter
    i = ident.refined.names.index("coulomb")
    std = ident.refined.std.copy()
    std[i] = 10 * abs(ident.refined.estimates[i]) + 1.0  # DIDIM no longer identifies it
    lost = replace(ident, result=ls_result, refined=replace(ident.refined, std=std))
    said = api._simulation_caution(replace(setup, ident=lost), sel, d.baseline, d.extended,
                                   rigid)
    assert made and made[0] is lost.refined
    assert "it does not identify coulomb on this record" in said and "backlash" in said
    none = replace(ident, result=ls_result, refined=None)
    assert api._simulation_caution(replace(setup, ident=none), sel, d.baseline, d.extended,
                                   rigid) == ""


def test_an_overflowing_sum_of_squares_is_inf_never_nan():
    # both products of a huge coefficient overflow: inf - inf.  A NaN held out read as "no
    # variant valid" (no change), and as the first variant's training error it kept every
    # later variant from being compared below it (review R10)
    from types import SimpleNamespace

    from fricctl.diagnose.crossval import Problem, cross_validate

    huge, G1 = np.array([1e200]), np.array([[1.0]])
    assert Problem.sse(huge, G1, np.array([1e200]), 1.0) == math.inf
    assert Problem.sse(np.array([2.0]), G1, np.array([1.0]), 1.0) == 1.0  # 1 - 4 + 4

    # two folds; variant "bad" comes first and overflows in training, "good" fits exactly
    def stats(parts):
        v = parts[-1]
        g = np.array([[1e200], [1e200]]) if v.h == "bad" else np.array([[1.0], [1.0]])
        st = SimpleNamespace(G=np.array([[[1.0]], [[1.0]]]), g=g, s=np.array([1.0, 1.0]),
                             scale=np.array([1.0]))
        return None, None, st

    problem = SimpleNamespace(sig=SimpleNamespace(n_folds=2), stats_of=stats,
                              bounded=lambda lo, hi, st, G, g: np.linalg.solve(G, g))
    cv = cross_validate(problem, lambda f: [SimpleNamespace(h="bad"), SimpleNamespace(h="good")])
    assert [ff.h for ff in cv.fits] == ["good", "good"]
    assert np.allclose(cv.test, 0.0)


def test_a_cause_whose_term_vanishes_in_the_final_refit_is_not_named(monkeypatch):
    # a nominal model whose only error is the inertia (development seed, mostly at rest):
    # step 1 named `compliance` (a spring at the grid's lowest frequency decouples the load:
    # less inertia), step 2 `inertia`, and refitted together the spring went to 0 -- the
    # extended model had no compliance, the report named it and called the record explained
    from fricctl.bench.hidden_effects import hidden_effect_record
    from fricctl.diagnose import api

    from fricctl.diagnose import below, selection

    rec = hidden_effect_record(np.random.default_rng([4242, 3]), cause="inertia",
                               sample_time=0.001, axis="rotary", excitation="stuck",
                               duration=30.0)
    # with the chain's share taken of the chain's residual (selection.net_of_chain) the
    # inertia outranks the spring at step 1 (net 99.7 % against 98.5 %, measured) and the
    # spring is never named; the rule is tested where the spring comes first, under the
    # earlier net score (gross - chain), which took 1.6 % off the inertia's 99.7 %
    d = diagnose(rec.run, rec.nominal)
    assert d.causes == ("inertia",) and d.steps[0].cause == "inertia"
    assert "compliance" not in d.not_identifiable
    for module in (selection, below):
        monkeypatch.setattr(module, "net_of_chain", lambda gross, chain: gross - chain)
    d = diagnose(rec.run, rec.nominal)
    assert d.causes == ("inertia",)
    why = d.not_identifiable["compliance"]
    assert why.startswith("tried, rejected: named at step 1") and "load_inertia" in why
    assert "compliance: tried, rejected: named at step 1" in d.report()
    assert d.extended.load_inertia == 0.0
    monkeypatch.setattr(api, "_vanished", lambda sel, ext: {})  # the rule off: as it was
    before = diagnose(rec.run, rec.nominal)
    assert before.causes == ("compliance", "inertia") and before.extended.load_inertia < 1e-9
