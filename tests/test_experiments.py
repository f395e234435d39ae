"""The paper's pipeline on the virtual bench: experiments -> patterns -> network -> dead zone."""
import numpy as np
import pytest

from fricctl.compensators import NNCompensator
from fricctl.bench.experiments import (compare_estimators, dead_zone, friction_patterns, paper_gains,
                                 predicted_dead_zone, train_network, training_experiments)
from fricctl.friction import Coulomb, Viscous
from fricctl.params import paper_actuator

P = paper_actuator()


@pytest.fixture(scope="module")
def experiments():
    return training_experiments(P, fast=True)


def test_training_experiments_cover_table_2(experiments):
    names = [e.name for e in experiments]
    assert names == ["open-loop steps", "P steps", "PD steps"]
    ol = experiments[0]
    # open-loop steps reach the maximum torque in both directions, with null-torque intervals
    assert np.abs(ol.run.torque).max() == pytest.approx(P.max_torque)
    assert ol.run.torque.max() > 0.75 * P.max_torque and ol.run.torque.min() < -0.75 * P.max_torque
    assert np.mean(ol.run.torque == 0.0) > 0.5
    # the truth is the simulator's: the record is its measured part
    np.testing.assert_array_equal(ol.run.position, ol.truth.q_meas)
    # deterministic
    again = training_experiments(P, fast=True)
    np.testing.assert_array_equal(again[2].run.position, experiments[2].run.position)


def test_patterns_equal_truth_with_exact_acceleration(experiments):
    # Tat = Tm - I*alpha: with the simulator's own acceleration the patterns are the true friction
    ex = experiments[1]
    tat = ex.truth.torque_motor - P.total_inertia * ex.truth.accel
    np.testing.assert_allclose(tat, ex.truth.friction, atol=1e-12)
    pats = friction_patterns(experiments, P)
    assert len(pats) == sum(e.run.n_samples - 10 for e in experiments)
    # at rest the estimated acceleration is zero, so the pattern is Tat = Tm exactly
    rest = pats.omega == 0
    np.testing.assert_array_equal(pats.friction[rest], pats.tm[rest])
    with pytest.raises(ValueError, match="unknown estimator"):
        friction_patterns(experiments, P, method="magic")


def test_estimator_comparison_reports_every_method(experiments):
    errs = compare_estimators(experiments[1], P)  # slow closed-loop motions (P steps)
    assert {e.method for e in errs} == {"backward_difference", "polynomial_segments", "savitzky_golay",
                                        "butterworth_central"}
    by = {e.method: e for e in errs}
    # the paper's polynomial fit beats the raw backward difference by far on slow motions
    # (median errors over moving samples; the backward difference is one count per sample coarse)
    assert by["polynomial_segments"].velocity_median < 0.1 * by["backward_difference"].velocity_median
    assert by["polynomial_segments"].friction_median < 0.1 * by["backward_difference"].friction_median


def test_dead_zone_without_compensation_is_the_static_friction():
    dz = dead_zone(P)
    # paper: the dead zone is the static friction, 12.7 % of Tmax; resolution of the grid 0.1 % Tmax
    assert dz.fraction == pytest.approx(0.127, abs=0.002)
    assert dz.dead_zone >= P.static


def test_predicted_dead_zone_closed_form():
    # linear estimate g*Tm at rest: predicted dead zone Fs*(1 - s*g)
    for g, s in ((0.5, 1.0), (0.8, 0.95), (1.2, 1.0)):
        pred = predicted_dead_zone(lambda tm, w: g * tm, 0.18, scale=s)
        pos, neg = pred.positive, pred.negative
        assert pos == pytest.approx(max(0.18 * (1 - s * g), 0.0), abs=1e-12)
        assert neg == pytest.approx(pos, abs=1e-12)


def test_linear_estimator_reduces_the_dead_zone_by_one_over_one_minus_g():
    # the mechanism of the paper's dead-zone reduction, with an estimator T^at = g*Tm at rest
    # (plus a Coulomb-like term when moving): measured factor ~ 1/(1 - g) within the grid step
    g = 0.8
    est = NNCompensator(lambda tm, w: np.where(np.asarray(w) == 0, g * np.asarray(tm), 0.0))
    dz0 = dead_zone(P)
    dz1 = dead_zone(P, est, amplitudes=np.linspace(0.001, 0.1, 400) * P.max_torque)
    assert dz0.dead_zone / dz1.dead_zone == pytest.approx(1 / (1 - g), rel=0.05)
    pos = predicted_dead_zone(est, P.static).positive
    assert dz1.dead_zone == pytest.approx(pos, rel=0.03)


def test_trained_network_reduces_the_dead_zone(experiments):
    pats = friction_patterns(experiments, P)
    net = train_network(pats, rng=np.random.default_rng(0), max_patterns=1500).net
    dz0 = dead_zone(P)
    dz1 = dead_zone(P, NNCompensator(net))
    pred = predicted_dead_zone(net, P.static)
    pos, neg = pred.positive, pred.negative
    assert dz0.dead_zone / dz1.dead_zone > 2
    # the fixed-point prediction from the net alone matches the measured dead zone within 25 %
    assert dz1.dead_zone == pytest.approx(min(pos, neg), rel=0.25)


def test_paper_gains_are_the_designs():
    g = paper_gains(P)
    # closed forms: P: Kp = I*wn^2 with wn = (pi - acos 0.3)/(0.2*sqrt(1 - 0.09)) = 9.8303 rad/s;
    # PD (0.3 s, 0.9): wn = (pi - acos 0.9)/(0.3*sqrt(1 - 0.81)), Kp = I*wn^2, Kd = 2*0.9*wn*I - b
    assert g.p_kp == pytest.approx(P.inertia * 9.8303**2, rel=1e-4)
    wn = (np.pi - np.arccos(0.9)) / (0.3 * np.sqrt(1 - 0.81))
    assert g.pd_kp == pytest.approx(P.inertia * wn**2, rel=1e-9)
    assert g.pd_kd == pytest.approx(2 * 0.9 * wn * P.inertia - P.viscous, rel=1e-9)


def test_dead_zone_rejects_bad_amplitudes():
    with pytest.raises(ValueError, match="amplitudes"):
        dead_zone(P, amplitudes=[0.1, 0.05])
    with pytest.raises(ValueError, match="breakaway"):
        predicted_dead_zone(lambda a, b: a, -1.0)
    friction = Viscous(0.01) + Coulomb(0.1)
    assert dead_zone(P, friction=friction).dead_zone == pytest.approx(0.1, abs=0.003 * P.max_torque)
