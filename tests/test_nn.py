"""Tests of fricctl.nn: the 2-H-1 friction network, its trainers, I/O and C export."""

import concurrent.futures
import ctypes
import dataclasses
import inspect
import json
import math
import shutil
import subprocess
import sys

import numpy as np
import pytest

from fricctl.compensators import NNCompensator
from fricctl.nn import (FORMAT_VERSION, TRAINERS, FrictionNet, TrainingResult, c_source,
                        fit_percent, fit_report, load_net, r_squared, save_net,
                        smooth_friction_patterns, train_backprop, train_casadi)
from fricctl.nn import layout
from fricctl.nn.train import Recipe, Scaling, TrainerOption, initial_theta, trainer
from fricctl.nn.train.backprop import (CONVERGING, SCHEDULES, epoch, learning_rates,
                                      loss_gradient)
from fricctl.nn.train.lm import clear_cache, residual_functions


def one_unit_net(**changes):
    kw = dict(w1=[[0.8, -0.3]], b1=[0.1], w2=[1.5], b2=-0.2, input_offset=[0.1, -0.5],
              input_scale=[0.5, 2.0], output_offset=0.05, output_scale=0.3,
              envelope_low=[-0.4, -2.5], envelope_high=[0.6, 1.5])
    kw.update(changes)
    return FrictionNet(**kw)


@pytest.fixture(scope="module")
def sliding():
    """Noise-free sliding patterns of the smooth law, train and held-out."""
    rng = np.random.default_rng(0)
    train = smooth_friction_patterns(rng, n_sliding=400, n_stuck=0)
    test = smooth_friction_patterns(rng, n_sliding=400, n_stuck=0)
    return ((train.tm, train.omega, train.friction), (test.tm, test.omega, test.friction))


@pytest.fixture(scope="module")
def casadi_net(sliding):
    (tm, om, f), _ = sliding
    return train_casadi(tm, om, f, rng=np.random.default_rng(1))


# -- evaluation ----------------------------------------------------------------
def _numpy_momentum(tm, om, f, hidden, epochs, rate, mom):
    """Reference full-batch gradient descent with momentum in numpy (analytic gradient):
    the parameters after ``epochs`` steps of learning rate ``rate(k)``."""
    scaling = Scaling.of(tm, om, f)
    xn, tn = scaling.inputs(tm, om), scaling.target(f)
    theta = initial_theta(hidden, np.random.default_rng(5))
    v = np.zeros_like(theta)
    for k in range(epochs):
        w = layout.unpack(theta, hidden)
        hid = np.tanh(w.w1 @ xn + w.b1[:, None])
        e = w.w2 @ hid + w.b2 - tn
        d = (w.w2[:, None] * (1 - hid**2)) * e
        g = layout.pack(d @ xn.T, d.sum(axis=1), hid @ e, e.sum()) / tn.size
        v = mom * v - rate(k) * g
        theta = theta + v
    return theta


def test_call_matches_closed_form_one_unit():
    # reference: the formula of the module docstring written out by hand for H = 1
    net = one_unit_net()
    tm = np.array([-0.3, 0.0, 0.45])
    om = np.array([1.0, 0.0, -2.0])
    xn0 = (tm - 0.1) / 0.5
    xn1 = (om + 0.5) / 2.0
    expected = (1.5 * np.tanh(0.8 * xn0 - 0.3 * xn1 + 0.1) - 0.2) * 0.3 + 0.05
    np.testing.assert_allclose(net(tm, om), expected, rtol=0, atol=1e-15)  # same formula
    assert net(0.1, 2.0).shape == ()
    assert net(np.zeros((3, 4)), 0.5).shape == (3, 4)


def test_clip_and_envelope_flags():
    net = one_unit_net()
    tm = np.array([-1.0, 0.0, 0.6, 0.61, 0.0, 0.0])
    om = np.array([0.0, 0.0, 1.5, 0.0, -3.0, 1.6])
    np.testing.assert_array_equal(net.outside_envelope(tm, om),
                                  [True, False, False, True, True, True])
    # reference: clipping by hand to the box, then the unclipped evaluation
    tm_c = np.clip(tm, -0.4, 0.6)
    om_c = np.clip(om, -2.5, 1.5)
    np.testing.assert_array_equal(net(tm, om, clip=True), net(tm_c, om_c))
    inside = ~net.outside_envelope(tm, om)
    np.testing.assert_array_equal(net(tm, om, clip=True)[inside], net(tm, om)[inside])


def test_torque_gain_against_finite_difference():
    net = one_unit_net(w1=[[0.8, -0.3], [-1.2, 0.7]], b1=[0.1, 0.4], w2=[1.5, -0.6])
    h = 1e-6
    for tm, om in ((0.0, 0.0), (0.3, -1.0), (-0.2, 0.8)):
        fd = (net(tm + h, om) - net(tm - h, om)) / (2 * h)
        # reference: central difference, truncation O(h^2) ~ 1e-12, rounding ~ 1e-10
        assert net.torque_gain(tm, om) == pytest.approx(fd, abs=1e-8)
    assert net.gain_at_rest() == pytest.approx(float(net.torque_gain(0.0, 0.0)), abs=0)


def test_net_is_immutable_and_validated():
    net = one_unit_net()
    with pytest.raises(dataclasses.FrozenInstanceError):
        net.b2 = 1.0
    with pytest.raises(ValueError):
        net.w1[0, 0] = 2.0  # read-only array
    with pytest.raises(TypeError):
        net.metadata["x"] = 1
    with pytest.raises(ValueError, match="w1"):
        one_unit_net(w1=[[1.0, 2.0, 3.0]])
    with pytest.raises(ValueError, match="b1"):
        one_unit_net(b1=[0.1, 0.2])
    with pytest.raises(ValueError, match="w2"):
        one_unit_net(w2=[np.nan])
    with pytest.raises(ValueError, match="input_scale"):
        one_unit_net(input_scale=[0.0, 1.0])
    with pytest.raises(ValueError, match="output_scale"):
        one_unit_net(output_scale=-1.0)
    with pytest.raises(ValueError, match="envelope_low"):
        one_unit_net(envelope_low=[1.0, 0.0], envelope_high=[0.0, 1.0])
    with pytest.raises(ValueError, match="metadata"):
        one_unit_net(metadata={"x": object()})
    with pytest.raises(ValueError, match="tm holds NaN"):
        net(np.nan, 0.0)
    with pytest.raises(ValueError, match="broadcast"):
        net(np.zeros(3), np.zeros(4))
    with pytest.raises(ValueError, match="unknown"):
        net.replace(w3=1.0)


# -- metrics -------------------------------------------------------------------
def test_fit_and_r2_closed_forms():
    y = np.array([1.0, 2.0, 3.0, 4.0])
    yhat = np.array([1.0, 2.0, 3.0, 5.0])
    # by hand: ||e|| = 1, ||y - mean|| = sqrt(5)
    assert fit_percent(y, yhat) == pytest.approx(100 * (1 - 1 / math.sqrt(5)), rel=1e-14)
    assert r_squared(y, yhat) == pytest.approx(1 - 1 / 5, rel=1e-14)
    rep = fit_report(y, yhat)
    assert rep.rmse == pytest.approx(0.5, rel=1e-14) and rep.max_abs_error == 1.0
    # the identity fit = 100*(1 - sqrt(1 - R^2)); R^2 = 0.98 is a fit of 85.86 %
    assert rep.fit_percent == pytest.approx(100 * (1 - math.sqrt(1 - rep.r_squared)), rel=1e-12)
    assert "fit" in rep.report() and "R^2" in rep.report()
    with pytest.raises(ValueError, match="constant"):
        fit_percent([1.0, 1.0], [1.0, 2.0])
    with pytest.raises(ValueError, match="same length"):
        r_squared([1.0, 2.0], [1.0])
    with pytest.raises(ValueError, match="y holds NaN"):
        fit_percent([1.0, np.nan], [1.0, 2.0])


# -- back-propagation ----------------------------------------------------------
def _scaled_loss(theta, hidden, xn, tn):
    """Loss mean(0.5*(yn - tn)^2) through FrictionNet (the numpy path, not numba)."""
    w = layout.unpack(theta, hidden)
    net = FrictionNet(w1=w.w1, b1=w.b1, w2=w.w2, b2=w.b2, input_offset=[0, 0], input_scale=[1, 1],
                      output_offset=0.0, output_scale=1.0, envelope_low=[-1, -1],
                      envelope_high=[1, 1])
    return float(np.mean(0.5 * (net(xn[0], xn[1]) - tn) ** 2))


def test_backprop_gradient_against_finite_differences():
    rng = np.random.default_rng(3)
    hidden = 4
    xn = rng.uniform(-1, 1, (2, 50))
    tn = rng.normal(size=50)
    theta = initial_theta(hidden, rng)
    grad = np.empty_like(theta)
    loss = loss_gradient(theta, xn, tn, hidden, grad)
    assert loss == pytest.approx(_scaled_loss(theta, hidden, xn, tn), rel=1e-13)
    h = 1e-6
    fd = np.empty_like(theta)
    for k in range(theta.size):
        e = np.zeros_like(theta)
        e[k] = h
        fd[k] = (_scaled_loss(theta + e, hidden, xn, tn)
                 - _scaled_loss(theta - e, hidden, xn, tn)) / (2 * h)
    # reference: central differences of an independent evaluation; truncation
    # O(h^2) ~ 1e-12 and rounding ~ 1e-16/h ~ 1e-10
    np.testing.assert_allclose(grad, fd, rtol=1e-7, atol=1e-9)


def test_full_batch_backprop_matches_plain_numpy_momentum(sliding):
    # reference: gradient descent with momentum written in numpy with the
    # analytic gradient; with batch_size = N the pattern order does not matter
    (tm, om, f), _ = sliding
    lr, mom, epochs, hidden = 0.1, 0.8, 20, 3
    res = train_backprop(tm, om, f, hidden=hidden, learning_rate=lr, momentum=mom,
                         epochs=epochs, batch_size=tm.size, rng=np.random.default_rng(5))
    net, hist = res.net, res.history
    theta = _numpy_momentum(tm, om, f, hidden, epochs, lambda k: lr, mom)
    np.testing.assert_allclose(layout.pack(net.w1, net.b1, net.w2, net.b2), theta,
                               rtol=1e-10, atol=1e-12)  # summation-order rounding only
    assert hist.loss.shape == (epochs + 1,) and hist.step == "epoch"


def test_backprop_per_pattern_learns_and_is_seeded(sliding):
    (tm, om, f), (tm2, om2, f2) = sliding
    kw = dict(learning_rate=0.01, momentum=0.9, epochs=300)
    res = train_backprop(tm, om, f, rng=np.random.default_rng(2), **kw)
    net, hist = res.net, res.history
    again = train_backprop(tm, om, f, rng=np.random.default_rng(2), **kw).net
    np.testing.assert_array_equal(net(tm, om), again(tm, om))  # same seed -> same net
    # the loss history is in physical units: its last entry is the MSE of the net
    assert hist.loss[-1] == pytest.approx(np.mean((net(tm, om) - f) ** 2), rel=1e-9)
    # Honest level, not a pass mark tuned to 99 %: the paper's on-line trainer
    # reaches a held-out fit of ~94 % after 300 epochs on this law (measured); 85 % fails
    # for a broken update and passes for a working but slow one.
    assert fit_percent(f2, net(tm2, om2)) > 85.0
    assert hist.loss[-1] < 0.1 * hist.loss[0]
    assert net.metadata["trainer"] == "backprop" and net.metadata["epochs"] == 300


def test_backprop_rejects_bad_input(sliding):
    (tm, om, f), _ = sliding
    rng = np.random.default_rng(0)
    with pytest.raises(ValueError, match="rng"):
        train_backprop(tm, om, f, rng=0)
    with pytest.raises(ValueError, match="same length"):
        train_backprop(tm, om[:-1], f, rng=rng)
    with pytest.raises(ValueError, match="tm holds NaN"):
        train_backprop(np.where(tm > 0, np.nan, tm), om, f, rng=rng)
    with pytest.raises(ValueError, match="learning_rate"):
        train_backprop(tm, om, f, learning_rate=0.0, rng=rng)
    with pytest.raises(ValueError, match="momentum"):
        train_backprop(tm, om, f, momentum=1.0, rng=rng)
    with pytest.raises(ValueError, match="hidden"):
        train_backprop(tm, om, f, hidden=0, rng=rng)
    with pytest.raises(ValueError, match="omega is constant"):
        train_backprop(tm, np.zeros_like(om), f, rng=rng)
    with pytest.raises(ValueError, match="diverged"):
        train_backprop(tm, om, f, learning_rate=1e6, epochs=5, rng=rng)


# -- back-prop's schedule, restarts and velocity scale (issue 11) ---------------------
def test_learning_rates_follow_their_formulas():
    # reference: the formulas of the docstring evaluated by hand
    np.testing.assert_array_equal(learning_rates("constant", 0.05, 3), [0.05, 0.05, 0.05])
    lr = learning_rates("cosine", 0.02, 8)
    assert lr[0] == 0.02  # cos 0 = 1 exactly
    assert lr[4] == pytest.approx(0.01, rel=1e-15)  # half-way: cos(pi/2) = 0
    assert lr[2] == pytest.approx(0.01 * (1 + math.sqrt(0.5)), rel=1e-15)  # cos(pi/4)
    assert lr[7] == pytest.approx(0.01 * (1 + math.cos(7 * math.pi / 8)), rel=1e-15)
    assert np.all(np.diff(lr) < 0) and lr[-1] > 0
    assert SCHEDULES == ("constant", "cosine")
    with pytest.raises(ValueError, match="schedule"):
        learning_rates("linear", 0.01, 3)
    with pytest.raises(ValueError, match="epochs"):
        learning_rates("cosine", 0.01, 0)


def test_constant_schedule_is_the_plain_loop_bit_for_bit(sliding):
    # reference: the loop this trainer ran before it had schedules, restarts and a velocity
    # scale, written out with its kernels: initial weights, then one permutation per epoch
    (tm, om, f), _ = sliding
    for hidden, batch, seed in ((4, 1, 0), (3, 7, 1)):
        res = train_backprop(tm, om, f, hidden=hidden, learning_rate=0.02, momentum=0.8,
                             epochs=15, batch_size=batch, rng=np.random.default_rng(seed))
        scaling = Scaling.of(tm, om, f)
        xn, tn = scaling.inputs(tm, om), scaling.target(f)
        rng = np.random.default_rng(seed)
        theta = initial_theta(hidden, rng)
        vel = np.zeros_like(theta)
        loss = [loss_gradient(theta, xn, tn, hidden, np.empty_like(theta))]
        for _ in range(15):
            loss.append(epoch(theta, vel, xn, tn, rng.permutation(tm.size), batch, 0.02, 0.8,
                              hidden))
        np.testing.assert_array_equal(layout.pack(res.net.w1, res.net.b1, res.net.w2,
                                                  res.net.b2), theta)
        np.testing.assert_array_equal(res.history.loss,
                                      2 * np.array(loss) * scaling.output_scale ** 2)
        meta = res.net.metadata
        assert (meta["schedule"], meta["restarts"], meta["velocity_scale"]) == ("constant", 1, None)


def test_cosine_schedule_matches_plain_numpy_momentum(sliding):
    # reference: full-batch gradient descent with momentum in numpy, the rate of epoch k
    # written out as lr*(1 + cos(pi*k/E))/2
    (tm, om, f), _ = sliding
    lr, mom, epochs, hidden = 0.3, 0.8, 12, 3
    res = train_backprop(tm, om, f, hidden=hidden, learning_rate=lr, momentum=mom,
                         epochs=epochs, batch_size=tm.size, schedule="cosine",
                         rng=np.random.default_rng(5))
    theta = _numpy_momentum(tm, om, f, hidden, epochs,
                            lambda k: 0.5 * lr * (1 + math.cos(math.pi * k / epochs)), mom)
    np.testing.assert_allclose(layout.pack(res.net.w1, res.net.b1, res.net.w2, res.net.b2),
                               theta, rtol=1e-10, atol=1e-12)  # summation-order rounding only


def test_velocity_scale_trains_the_net_of_the_rescaled_seam(sliding):
    # reference: the same descent reached through the seam instead of the loop -- a Scaling
    # whose velocity input is omega / velocity_scale and torque input is the default one;
    # the two differ only by the rounding of the rescaled input (a few ulp), which 5 epochs
    # of per-pattern updates do not amplify beyond 1e-9
    (tm, om, f), _ = sliding
    vs = 0.4  # [rad/s]
    res = train_backprop(tm, om, f, epochs=5, learning_rate=0.01, velocity_scale=vs,
                         rng=np.random.default_rng(3))
    base = Scaling.of(tm, om, f)
    seam = Scaling(input_offset=np.array([base.input_offset[0], 0.0]),
                   input_scale=np.array([base.input_scale[0], vs]),
                   output_offset=base.output_offset, output_scale=base.output_scale,
                   envelope_low=base.envelope_low, envelope_high=base.envelope_high)
    ref = trainer("backprop").train(tm, om, f, epochs=5, learning_rate=0.01, scaling=seam,
                                    rng=np.random.default_rng(3))
    # the stored net keeps the default scaling and is the same function
    np.testing.assert_array_equal(res.net.input_scale, base.input_scale)
    np.testing.assert_allclose(res.net(tm, om), ref.net(tm, om), rtol=0, atol=1e-9)
    np.testing.assert_allclose(res.history.loss, ref.history.loss, rtol=1e-9)
    assert res.history.loss[-1] == pytest.approx(np.mean((res.net(tm, om) - f) ** 2), rel=1e-9)


def test_restarts_keep_the_best_start(sliding):
    (tm, om, f), _ = sliding
    tm, om, f = tm[:150], om[:150], f[:150]
    epochs = 20
    res = train_backprop(tm, om, f, hidden=2, epochs=epochs, restarts=4, learning_rate=0.01,
                         schedule="cosine", rng=np.random.default_rng(6))
    meta, loss = res.net.metadata, res.history.loss
    assert loss.shape == (4 * epochs + 1,)
    finals = np.array(meta["restart_mse"])
    assert meta["best_restart"] == int(np.argmin(finals)) and finals.size == 4
    # reference: the returned net's MSE recomputed; it is the best start's final loss
    assert finals.min() == pytest.approx(np.mean((res.net(tm, om) - f) ** 2), rel=1e-9)
    assert loss[-1] == finals.min()
    for r in range(1, 4):  # after a start ends, no entry is above the best finished start
        assert np.all(loss[r * epochs + 1:] <= finals[:r].min())
    # the first start's weights are the first draw of the generator, as for LM's first start
    first = train_backprop(tm, om, f, hidden=2, epochs=1, learning_rate=1e-12,
                           rng=np.random.default_rng(6))
    again = train_casadi(tm, om, f, hidden=2, restarts=1, max_iterations=1,
                         rng=np.random.default_rng(6))
    assert first.history.loss[0] == pytest.approx(again.history.loss[0], rel=1e-12)


def test_new_backprop_options_are_checked_and_listed(sliding):
    (tm, om, f), _ = sliding
    rng = np.random.default_rng(0)
    opts = trainer("backprop").options()
    assert (opts["schedule"], opts["restarts"], opts["velocity_scale"]) == ("constant", 1, None)
    assert set(CONVERGING) <= set(opts)
    for kw, match in ((dict(schedule="step"), "schedule"), (dict(schedule=1), "schedule"),
                      (dict(restarts=0), "restarts"), (dict(restarts=2.0), "restarts"),
                      (dict(velocity_scale=0.0), "velocity_scale"),
                      (dict(velocity_scale="1"), "velocity_scale"),
                      (dict(velocity_scale=np.inf), "velocity_scale")):
        with pytest.raises(ValueError, match=match):
            train_backprop(tm, om, f, epochs=1, rng=rng, **kw)
    res = train_backprop(tm, om, f, epochs=2, velocity_scale=np.float32(0.5), restarts=np.int64(2),
                         rng=rng)
    assert res.net.metadata["velocity_scale"] == 0.5 and res.net.metadata["restarts"] == 2
    json.dumps(dict(res.net.metadata), allow_nan=False)  # stored with the net


@pytest.fixture(scope="module")
def paper_patterns():
    """The paper pipeline's training patterns, fast mode, seed 0, on the literal bench (where the
    ratios below were measured)."""
    from fricctl.paper import train_paper_network

    return train_paper_network(bench="literal", fast=True, seed=0).train


def _lm_and_backprop(train, seed):
    from fricctl.bench.experiments import train_network

    # both on the same <= 4000 patterns (the subset is the generator's first draw)
    lm = train_network(train, rng=np.random.default_rng(seed))
    bp = train_network(train, trainer="backprop", rng=np.random.default_rng(seed), **CONVERGING)
    return lm.history.loss[-1], bp.history.loss[-1]


def test_converging_backprop_reaches_lm_on_paper_patterns(paper_patterns):
    # The claim of issue 11, on three trainer seeds of the fast-mode patterns: back-prop with
    # CONVERGING ends within 5 % of the Levenberg-Marquardt loss (LM's 3 starts) on the same
    # patterns.  Measured on these seeds: 0.75, 0.69, 0.78 of LM's loss; over seeds 0-7 6/8
    # reach (benchmarks/README.md: 8/10 on fast-mode seeds, 18/20 in full mode).
    ratios = np.array([bp / lm for lm, bp in (_lm_and_backprop(paper_patterns, s)
                                              for s in range(3))])
    assert np.sum(ratios <= 1.05) >= 2
    assert np.median(ratios) <= 1.05


@pytest.mark.slow
def test_converging_backprop_reaches_lm_over_ten_paper_seeds():
    # Full mode (the paper's patterns), 10 seeds of the whole pipeline (split, subset,
    # initial weights).  Measured: 9/10 reach LM's loss within 5 %, median 0.69 of it
    # (benchmarks/README.md).  8/10 leaves one more seed to a different basin; the paper's
    # constant rate (0.05, momentum 0.9) stays far above LM in every seed (measured 11-276x
    # after 300 epochs, 9-85x after 2000; 3x is the pass mark).
    from fricctl.bench.experiments import train_network
    from fricctl.paper import train_paper_network

    ratios, const = [], []
    for seed in range(10):
        train = train_paper_network(bench="literal", seed=seed).train
        lm, bp = _lm_and_backprop(train, seed)
        ratios.append(bp / lm)
        c = train_network(train, trainer="backprop", epochs=300, rng=np.random.default_rng(seed))
        const.append(c.history.loss[-1] / lm)
    ratios = np.array(ratios)
    assert np.sum(ratios <= 1.05) >= 8
    assert np.median(ratios) <= 1.0
    assert min(const) > 3.0


# -- CasADi trainer -------------------------------------------------------------
def test_casadi_fits_smooth_law_above_99_percent(casadi_net, sliding):
    # reference: noise-free patterns of b*w + Fc*tanh(w/v), representable by a
    # 2-4-1 tanh net; training and held-out fit > 99 % (measured ~99.99 %)
    net, hist = casadi_net.net, casadi_net.history
    (tm, om, f), (tm2, om2, f2) = sliding
    assert fit_percent(f, net(tm, om)) > 99.0
    held = fit_report(f2, net=net, tm=tm2, omega=om2)
    assert held.fit_percent > 99.0
    assert net.metadata["trainer"] == "casadi"
    assert net.metadata["fit_percent"] == pytest.approx(fit_percent(f, net(tm, om)), rel=1e-12)
    assert np.all(np.diff(hist.loss) <= 0)  # best-so-far loss never increases
    assert hist.loss[-1] == pytest.approx(np.mean((net(tm, om) - f) ** 2), rel=1e-9)


def test_casadi_beats_backprop_loss(casadi_net, sliding):
    # the second-order trainer's final loss is below the paper's trainer's
    (tm, om, f), _ = sliding
    hist = casadi_net.history
    bp = train_backprop(tm, om, f, learning_rate=0.01, epochs=100,
                        rng=np.random.default_rng(1)).history
    assert hist.loss[-1] < bp.loss[-1]
    assert math.isfinite(hist.time_to_reach(bp.loss[-1]))
    assert hist.time_to_reach(-1.0) == math.inf


def test_stuck_patterns_give_a_gain_near_one_at_rest():
    # While stuck the patterns are Tat = Tm, so dTat_hat/dTm at rest is close
    # to 1; the tolerance 0.3 allows for the sliding patterns near omega = 0,
    # which pull the other way (their friction does not depend on Tm).
    rng = np.random.default_rng(4)
    pats = smooth_friction_patterns(rng, n_sliding=300, n_stuck=150)
    tm, om, f = pats.tm, pats.omega, pats.friction
    net = train_casadi(tm, om, f, restarts=2, rng=np.random.default_rng(6)).net
    assert net.gain_at_rest() == pytest.approx(1.0, abs=0.3)


# -- JSON -----------------------------------------------------------------------
def test_save_load_round_trip_is_exact(casadi_net, tmp_path, sliding):
    net = casadi_net.net
    (tm, om, _), _ = sliding
    path = save_net(net, tmp_path / "net.json")
    back = load_net(path)
    np.testing.assert_array_equal(back(tm, om), net(tm, om))  # bit-identical
    for name in ("w1", "b1", "w2", "input_offset", "input_scale", "envelope_low",
                 "envelope_high"):
        np.testing.assert_array_equal(getattr(back, name), getattr(net, name))
    assert dict(back.metadata) == dict(net.metadata)
    assert json.loads(path.read_text())["version"] == FORMAT_VERSION


def test_load_rejects_malformed_and_wrong_version(tmp_path):
    good = one_unit_net().to_dict()
    cases = {
        "bad json": "{not json",
        "format": json.dumps(good | {"format": "something.else"}),
        "version": json.dumps(good | {"version": FORMAT_VERSION + 1}),
        "missing": json.dumps({k: v for k, v in good.items() if k != "b1"}),
        "unknown": json.dumps(good | {"w3": [1.0]}),
        "hidden": json.dumps(good | {"hidden": 7}),
        "shape": json.dumps(good | {"w2": [1.0, 2.0]}),
        "nan": json.dumps(good).replace('"b2": -0.2', '"b2": NaN'),
        "list": "[1, 2, 3]",
    }
    messages = {"bad json": "malformed", "format": "not a FrictionNet", "version": "version",
                "missing": "missing", "unknown": "unknown", "hidden": "hidden", "shape": "w2",
                "nan": "b2", "list": "JSON object"}
    for key, text in cases.items():
        p = tmp_path / f"{key.replace(' ', '_')}.json"
        p.write_text(text)
        with pytest.raises(ValueError, match=messages[key]):
            load_net(p)
    with pytest.raises(FileNotFoundError):
        load_net(tmp_path / "absent.json")


# -- C export -------------------------------------------------------------------
CC = shutil.which("cc") or shutil.which("gcc")


@pytest.mark.skipif(CC is None, reason="no C compiler (cc or gcc) on PATH")
def test_c_export_matches_python(casadi_net, tmp_path):
    net = casadi_net.net
    src = tmp_path / "fricnet.c"
    src.write_text(c_source(net, name="fricnet"))
    lib = tmp_path / "libfricnet.so"
    subprocess.run([CC, "-O2", "-shared", "-fPIC", "-std=c99", str(src), "-o", str(lib), "-lm"],
                   check=True, capture_output=True)
    so = ctypes.CDLL(str(lib))
    so.fricnet.restype = ctypes.c_double
    so.fricnet.argtypes = [ctypes.c_double, ctypes.c_double, ctypes.c_int]
    so.fricnet_outside.restype = ctypes.c_int
    so.fricnet_outside.argtypes = [ctypes.c_double, ctypes.c_double]
    dp = ctypes.POINTER(ctypes.c_double)
    so.fricnet_batch.argtypes = [dp, dp, dp, ctypes.c_long, ctypes.c_int]

    rng = np.random.default_rng(7)
    lo, hi = net.envelope_low, net.envelope_high
    span = hi - lo
    tm = rng.uniform(lo[0] - 0.5 * span[0], hi[0] + 0.5 * span[0], 2000)
    om = rng.uniform(lo[1] - 0.5 * span[1], hi[1] + 0.5 * span[1], 2000)
    for clip in (False, True):
        out = np.empty_like(tm)
        so.fricnet_batch(tm.ctypes.data_as(dp), om.ctypes.data_as(dp), out.ctypes.data_as(dp),
                         tm.size, int(clip))
        # reference: the Python evaluation; difference only from libm tanh and
        # summation rounding (~1e-16), tolerance 1e-12 from the issue
        np.testing.assert_allclose(out, net(tm, om, clip=clip), rtol=0, atol=1e-12)
    single = [so.fricnet(float(a), float(b), 0) for a, b in zip(tm[:20], om[:20])]
    np.testing.assert_allclose(single, net(tm[:20], om[:20]), rtol=0, atol=1e-12)
    flags = [bool(so.fricnet_outside(float(a), float(b))) for a, b in zip(tm, om)]
    np.testing.assert_array_equal(flags, net.outside_envelope(tm, om))


def _random_net(rng, hidden):
    lo = rng.uniform(-1.0, 0.0, 2)
    return FrictionNet(w1=rng.normal(size=(hidden, 2)), b1=rng.normal(size=hidden),
                       w2=rng.normal(size=hidden), b2=float(rng.normal()),
                       input_offset=rng.normal(size=2), input_scale=rng.uniform(0.2, 3.0, 2),
                       output_offset=float(rng.normal()), output_scale=float(rng.uniform(0.05, 2.0)),
                       envelope_low=lo, envelope_high=lo + rng.uniform(0.5, 2.0, 2))


def _c_library(net, tmp_path, name):
    src = tmp_path / f"{name}.c"
    src.write_text(c_source(net, name=name))
    lib = tmp_path / f"lib{name}.so"
    subprocess.run([CC, "-O2", "-shared", "-fPIC", "-std=c99", str(src), "-o", str(lib), "-lm"],
                   check=True, capture_output=True)
    so = ctypes.CDLL(str(lib))
    dp = ctypes.POINTER(ctypes.c_double)
    fun = getattr(so, f"{name}_batch")
    fun.argtypes = [dp, dp, dp, ctypes.c_long, ctypes.c_int]

    def batch(tm, om, clip):
        out = np.empty_like(tm)
        fun(tm.ctypes.data_as(dp), om.ctypes.data_as(dp), out.ctypes.data_as(dp), tm.size,
            int(clip))
        return out
    return batch


def test_five_forward_passes_agree_on_random_nets(tmp_path):
    # The network's formula is written five times: FrictionNet.__call__ (numpy), the numba
    # training forward on theta, the compiled-loop forward on the packed vector, the CasADi
    # graph of the LM trainer, and the exported C.  Reference: FrictionNet.__call__; the
    # others differ only by the summation order and libm's tanh (~1e-16 relative), so
    # 1e-12 N*m fails for any wrong index, offset or scaling.
    rng = np.random.default_rng(11)
    for k, hidden in enumerate((1, 4, 7)):
        net = _random_net(rng, hidden)
        lo, hi = net.envelope_low, net.envelope_high
        span = hi - lo
        n = 300  # half of the inputs outside the envelope, so that clipping matters
        tm = rng.uniform(lo[0] - span[0], hi[0] + span[0], n)
        om = rng.uniform(lo[1] - span[1], hi[1] + span[1], n)
        theta = layout.pack(net.w1, net.b1, net.w2, net.b2)
        for clip in (False, True):
            ref = net(tm, om, clip=clip)
            x0 = np.clip(tm, lo[0], hi[0]) if clip else tm
            x1 = np.clip(om, lo[1], hi[1]) if clip else om
            xn0 = (x0 - net.input_offset[0]) / net.input_scale[0]
            xn1 = (x1 - net.input_offset[1]) / net.input_scale[1]
            unscale = lambda yn: np.asarray(yn) * net.output_scale + net.output_offset  # noqa: E731
            hid = np.empty(hidden)
            numba_train = unscale([layout.forward_theta(theta, hidden, a, b, hid)
                                   for a, b in zip(xn0, xn1)])
            p = layout.pack_compiled(net, clip)
            packed = np.array([layout.forward_packed(p, a, b) for a, b in zip(tm, om)])
            fr = residual_functions(hidden, n).residuals
            casadi_graph = unscale(np.asarray(fr(theta, np.vstack([xn0, xn1]), np.zeros((1, n))))
                                   .ravel())
            for name, got in (("numba training forward", numba_train),
                              ("forward_packed", packed), ("CasADi graph", casadi_graph)):
                np.testing.assert_allclose(got, ref, rtol=0, atol=1e-12, err_msg=f"{name}, "
                                           f"H={hidden}, clip={clip}")
            if CC is not None:
                c_batch = _c_library(net, tmp_path, f"net{k}") if not clip else c_batch
                np.testing.assert_allclose(c_batch(tm, om, clip), ref, rtol=0, atol=1e-12,
                                           err_msg=f"C export, H={hidden}, clip={clip}")
    if CC is None:
        pytest.skip("four of five forward passes agree; the C export was not compiled: "
                    "no C compiler (cc or gcc) on PATH")


def test_compiled_vector_has_the_named_layout():
    # reference: the layout table of fricctl.nn.layout, entry by entry
    net = one_unit_net(w1=[[0.8, -0.3], [-1.2, 0.7]], b1=[0.1, 0.4], w2=[1.5, -0.6])
    p = layout.pack_compiled(net, True)
    assert p.size == layout.compiled_size(2) == layout.P_W1 + 8
    assert p[layout.P_HIDDEN] == 2 and p[layout.P_CLIP] == 1.0
    assert p[layout.P_B2] == net.b2 and p[layout.P_OUTPUT_SCALE] == net.output_scale
    assert p[layout.P_OUTPUT_OFFSET] == net.output_offset
    np.testing.assert_array_equal(p[layout.P_INPUT_OFFSET:layout.P_INPUT_OFFSET + 2],
                                  net.input_offset)
    np.testing.assert_array_equal(p[layout.P_ENVELOPE_HIGH:layout.P_ENVELOPE_HIGH + 2],
                                  net.envelope_high)
    theta = layout.pack(net.w1, net.b1, net.w2, net.b2)
    np.testing.assert_array_equal(p[layout.P_W1:], theta[:-1])  # the tail is theta without b2
    compiled = NNCompensator(net, clip=True).compiled()
    kind, params = compiled.kind, compiled.params
    np.testing.assert_array_equal(params, p)
    assert layout.pack_compiled(net, False)[layout.P_CLIP] == 0.0
    w = layout.unpack(theta, 2)
    np.testing.assert_array_equal(w.w1, net.w1)
    assert w.b2 == net.b2 and theta.size == layout.theta_size(2)
    with pytest.raises(ValueError, match="theta"):
        layout.unpack(theta[:-1], 2)
    with pytest.raises(ValueError, match="missing"):
        layout.pack_compiled(lambda a, b: a, False)


# -- the trainers' seam ---------------------------------------------------------------
# Parametrised over the registry: a new trainer module is tested here without an edit.
@pytest.mark.parametrize("name", list(TRAINERS))
def test_each_trainer_is_its_modules_entry_and_declares_itself(name):
    t = TRAINERS[name]
    module = sys.modules[t.loop.__module__]
    assert module.__name__.startswith("fricctl.nn.train.") and module.TRAINER is t
    assert t.name == name and t.description and "\n" not in t.description and t.step
    options = t.options()
    for opt in t.flags:
        assert opt.name in options and opt.flag == "--" + opt.name.replace("_", "-")
    for recipe in t.recipes:
        assert recipe.description and set(recipe.options) <= set(options)
        assert t.defaults(recipe.name) == {**options, **recipe.options}
    # what a command line runs when no recipe is named: the first recipe, else the loop's defaults
    assert t.defaults() == {**options, **(t.recipes[0].options if t.recipes else {})}
    assert t.requires is None or (t.requires and "\n" not in t.requires)


@pytest.mark.parametrize("name", list(TRAINERS))
def test_each_trainer_trains_tiny_patterns_or_refuses_them_for_its_reason(name, sliding):
    t = TRAINERS[name]
    (tm, om, f), _ = sliding
    tm, om, f = tm[:60], om[:60], f[:60]
    if t.requires is not None:
        # the reason it gives is real: bare patterns (the seam's range scaling) are refused
        with pytest.raises(ValueError):
            t.train(tm, om, f, hidden=2, rng=np.random.default_rng(0), **t.defaults())
        return
    # the options a command line starts from (its first recipe, else the loop's defaults)
    res = t.train(tm, om, f, hidden=2, rng=np.random.default_rng(0), **t.defaults())
    net = res.net
    assert all(np.all(np.isfinite(w)) for w in (net.w1, net.b1, net.w2, net.b2))
    assert res.history.trainer == net.metadata["trainer"] == name and res.history.step == t.step
    loss = res.history.loss
    assert np.all(np.isfinite(loss)) and loss.shape == res.history.elapsed.shape
    # it learns: the smooth law's training loss ends below that of the initial weights
    assert loss[-1] < loss[0]


@pytest.mark.parametrize("name, option", [(name, opt.name) for name, t in TRAINERS.items()
                                          if t.requires is None
                                          for opt in t.flags if opt.high is not None])
def test_each_declared_largest_value_is_enforced_by_the_loop(name, option, sliding):
    # --help states the largest value; the loop refuses the next one, naming the option, before
    # it trains
    t = TRAINERS[name]
    opt = next(o for o in t.flags if o.name == option)
    beyond = int(opt.high) + 1 if opt.type is int else float(np.nextafter(opt.high, np.inf))
    (tm, om, f), _ = sliding
    with pytest.raises(ValueError, match=option):
        t.train(tm[:60], om[:60], f[:60], hidden=2, rng=np.random.default_rng(0),
                **{**t.defaults(), option: beyond})


def test_trainer_registry_checks_names_and_options(sliding):
    # the public functions' defaults are the inner loops' defaults
    for fun, name in ((train_backprop, "backprop"), (train_casadi, "casadi")):
        params = inspect.signature(fun).parameters
        for option, default in trainer(name).options().items():
            assert params[option].default == default, (name, option)
    with pytest.raises(ValueError, match="backprop"):
        trainer("adam")
    (tm, om, f), _ = sliding
    with pytest.raises(ValueError, match="unknown option.*epochs"):
        trainer("casadi").train(tm, om, f, rng=np.random.default_rng(0), epochs=3)
    with pytest.raises(ValueError, match="not an option of its loop"):
        dataclasses.replace(trainer("casadi"), flags=(TrainerOption(name="epochs", type=int,
                                                                    help="x"),))
    with pytest.raises(ValueError, match="not an option of its loop"):
        dataclasses.replace(trainer("casadi"), recipes=(Recipe(name="r", description="x",
                                                               options={"epochs": 3}),))
    with pytest.raises(ValueError, match="must be int, float or str"):
        TrainerOption(name="restarts", type=list, help="x")
    with pytest.raises(ValueError, match="recipe of trainer 'backprop'"):
        trainer("backprop").defaults("bogus")


def test_training_result_is_a_frozen_record_not_a_tuple(sliding):
    (tm, om, f), _ = sliding
    res = trainer("backprop").train(tm[:50], om[:50], f[:50], hidden=2, epochs=3,
                                    rng=np.random.default_rng(0), metadata={"seed": 0})
    assert isinstance(res, TrainingResult) and res.history.loss.shape == (4,)
    assert res.net.metadata["trainer"] == "backprop" and res.net.metadata["seed"] == 0
    with pytest.raises(TypeError):
        net, hist = res
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.net = None
    with pytest.raises(TypeError):
        TrainingResult(res.net, res.history)  # keyword-only


def test_trainers_in_threads_give_the_serial_results(sliding):
    # reference: the same seeds run one after the other; the CasADi cache is cleared first so
    # that the threads race to build the functions (the lock makes one build them)
    (tm, om, f), _ = sliding
    tm, om, f = tm[:120], om[:120], f[:120]
    jobs = [(train_casadi, dict(restarts=1, max_iterations=30)),
            (train_backprop, dict(epochs=5))] * 3

    def run(i):
        fun, kw = jobs[i]
        return fun(tm, om, f, hidden=3, rng=np.random.default_rng(i), **kw).net(tm, om)

    serial = [run(i) for i in range(len(jobs))]
    clear_cache()
    with concurrent.futures.ThreadPoolExecutor(max_workers=4) as ex:
        threaded = list(ex.map(run, range(len(jobs))))
    for a, b in zip(serial, threaded):
        np.testing.assert_array_equal(a, b)  # same seed, same arithmetic: same bits


def test_c_source_rejects_bad_name():
    with pytest.raises(ValueError, match="identifier"):
        c_source(one_unit_net(), name="1bad name")


def test_smooth_patterns_obey_the_law():
    rng = np.random.default_rng(0)
    pats = smooth_friction_patterns(rng, n_sliding=50, n_stuck=20)
    tm, om, f = pats.tm, pats.omega, pats.friction
    np.testing.assert_allclose(f[:50], 0.0169 * om[:50] + 0.144 * np.tanh(om[:50] / 0.05),
                               rtol=1e-15)  # definition
    np.testing.assert_array_equal(f[50:], tm[50:])  # stuck: Tat = Tm
    np.testing.assert_array_equal(om[50:], 0.0)
    np.testing.assert_array_equal(pats.at_rest, np.arange(70) >= 50)  # the stuck ones, by construction
    assert np.all(om[:50] * f[:50] >= 0)  # friction dissipates
    with pytest.raises(ValueError, match="n_stuck"):
        smooth_friction_patterns(rng, n_stuck=-1)


# -- figures (Agg; inspect artists, not pixels) ---------------------------------
def test_plot_friction_map_draws_curves_and_envelope(casadi_net):
    from fricctl.figures.network import plot_friction_map

    net = casadi_net.net
    ax = plot_friction_map(net, tm_values=[0.0, 0.1])
    solid = [ln for ln in ax.get_lines() if ln.get_linestyle() == "-" and ln.get_label()
             .startswith("$T_m$")]  # "$T_m$ = 0.1 N·m": typeset (issue 24)
    assert len(solid) == 2
    x, y = solid[1].get_data()
    inside = np.isfinite(y)
    np.testing.assert_allclose(y[inside], net(0.1, x[inside]), rtol=0, atol=0)  # same values
    assert not inside.all()  # the margin outside the envelope is not solid
    assert len(ax.patches) == 1  # the shaded envelope
    assert "[rad/s]" in ax.get_xlabel() and "[N*m]" in ax.get_ylabel()


def test_plot_history_and_fit(casadi_net, sliding):
    from fricctl.figures.network import plot_fit, plot_training_history

    net, hist = casadi_net.net, casadi_net.history
    ax = plot_training_history(hist, against="time")
    np.testing.assert_array_equal(ax.get_lines()[0].get_ydata(), hist.loss)
    assert ax.get_yscale() == "log" and "[s]" in ax.get_xlabel()
    (tm, om, f), _ = sliding
    ax = plot_fit(f, net(tm, om))
    assert len(ax.get_lines()) == 2 and "fit" in ax.get_title()
    with pytest.raises(ValueError, match="same length"):
        plot_fit(f, f[:-1])
    with pytest.raises(ValueError, match="against"):
        plot_training_history(hist, against="epochs")


def test_a_net_file_says_the_units_of_the_axis_it_was_trained_on(tmp_path):
    # issue 26: a linear axis's net said N*m, rad/s in its units entry
    lin = save_net(one_unit_net(metadata={"units": "linear"}), tmp_path / "lin.json")
    rot = save_net(one_unit_net(), tmp_path / "rot.json")
    data = json.loads(lin.read_text())
    assert data["units"] == {"inputs": ["N", "m/s"], "output": "N", "side": "load"}
    assert json.loads(rot.read_text())["units"] == {"inputs": ["N*m", "rad/s"], "output": "N*m",
                                                    "side": "load"}
    assert load_net(lin).units == "linear" and load_net(rot).units == "rotary"
    # an entry that contradicts the metadata is refused, naming the key
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(dict(data, metadata={"units": "rotary"})))
    with pytest.raises(ValueError, match="units: the file's units entry is a linear axis's"):
        load_net(bad)
    # a linear net written before the fix (rotary entry, "linear" metadata): read as linear
    old = tmp_path / "old.json"
    old.write_text(json.dumps(dict(data, units=json.loads(rot.read_text())["units"])))
    assert load_net(old).units == "linear"
    with pytest.raises(ValueError, match=r"metadata\['units'\] must be one of"):
        one_unit_net(metadata={"units": "metric"})
