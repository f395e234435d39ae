"""Tests of :mod:`fricctl.paper` and :mod:`fricctl.figures.paper`.

One fast network of each pipeline (seed 0) is shared by the whole module.  Every
claim is recomputed here and the *physics* it rests on is asserted -- what the bench
robustly shows (the paper pipeline's g > 1 and runaway: 20 of 20 seeds in the issue's
measurement) -- not a verdict that depends on the seed: those are asserted as rates
over seeds in the slow test at the end.  The runaway checks and the aggregation over
seeds are tested on hand-made runs and claims against hand calculations.
"""

from __future__ import annotations

import importlib
import json
import math
import multiprocessing
import re
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor
from dataclasses import fields, is_dataclass, replace
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pytest

from fricctl import controllers as ctl
from fricctl import paper
from fricctl.bench.experiments import true_patterns
from fricctl.compensators import NNCompensator, NoCompensation
from fricctl.figures import paper as fp
from fricctl.friction import Viscous
from fricctl.nn import r_squared
from fricctl.paper.common import designs
from fricctl.params import paper_actuator
from fricctl.simulate import simulate

P = paper_actuator()
RES = P.encoder_resolution
#: Claims of the registry's figures (each maker makes one claim).
N_CLAIMS = sum(len(fig.claims) for fig in paper.paper_figures().values())


@pytest.fixture(scope="module")
def network():
    return paper.train_paper_network(P, fast=True, seed=0)


@pytest.fixture(scope="module")
def figs(network):
    return {n: fn(network) for n, fn in paper.FIGURES.items()}


@pytest.fixture(scope="module")
def claims(figs):
    return {c.id: c for c in paper.paper_claims(figs, P)}


@pytest.fixture(scope="module")
def fnetwork():
    return paper.train_paper_network(P, fast=True, seed=0, pipeline="fricctl")


@pytest.fixture(scope="module")
def ffigs(fnetwork):
    return {n: fn(fnetwork) for n, fn in paper.FIGURES.items()}


@pytest.fixture(scope="module")
def fclaims(ffigs):
    return {c.id: c for c in paper.paper_claims(ffigs, P)}


def _fit(y, y_hat):
    """The normalised fit written out by hand (the reference for fricctl.nn.fit_percent) [%]."""
    return 100 * (1 - np.linalg.norm(y - y_hat) / np.linalg.norm(y - np.mean(y)))


def _r2(y, y_hat):
    """R^2 written out by hand [-]."""
    return 1 - np.sum((y - y_hat) ** 2) / np.sum((y - np.mean(y)) ** 2)


def _assert_stuck_fixed_point(run, kp, scale, net, breakaway):
    """Hand calculation of the compensated loop at rest; returns the error the net alone predicts [rad].

    At rest omega_hat = 0, so the PD law is Tc = Kp*(r - y) and the compensation
    Tm(k+1) = Tc(k) + s*net(Tm(k), 0): a stuck joint holds a fixed point of that map,
    its true friction holds the motor torque exactly (I*alpha = 0) and |Tm| <= breakaway.
    The joint therefore stops where Kp*(r - y) = Tm - s*net(Tm, 0).
    """
    assert run.stuck[-1] and run.omega_hat[-1] == 0.0
    tm, tc = float(run.torque_motor[-1]), float(run.torque_cmd[-1])
    assert tc == pytest.approx(kp * (run.reference[-1] - run.q_meas[-1]), rel=1e-12)
    assert tm == pytest.approx(tc + scale * float(net(tm, 0.0)), abs=1e-12)  # a fixed point, to rounding
    assert abs(tm) <= breakaway
    assert run.friction[-1] == pytest.approx(tm, rel=1e-12)
    return (tm - scale * float(net(tm, 0.0))) / kp


# -- the network -------------------------------------------------------------
def test_network_fit_recomputed(network, figs, claims):
    ho, net = network.held_out, network.net
    # reference: both definitions written out by hand on the held-out patterns (1e-12: rounding)
    fit = _fit(ho.friction, net(ho.tm, ho.omega))
    r2 = _r2(ho.friction, net(ho.tm, ho.omega))
    assert network.fit_held_out.fit_percent == pytest.approx(fit, rel=1e-12)
    assert network.fit_held_out.r_squared == pytest.approx(r2, rel=1e-12)
    assert r_squared(ho.friction, net(ho.tm, ho.omega)) == pytest.approx(r2, rel=1e-12)
    # closed form linking the two definitions: fit = 100*(1 - sqrt(1 - R^2)), to rounding
    assert fit == pytest.approx(100 * (1 - np.sqrt(1 - r2)), abs=1e-9)
    # robust: the net explains most of the variance (R^2 > 0.8), but not to the paper's 98 % fit
    assert r2 > 0.8
    assert len(network.train) + len(network.held_out) == len(network.patterns)


def test_measuring_chain_caps_the_fit(network, claims):
    # Why nn-fit fails: the patterns Tm - I*alpha_hat carry the estimator's error. The
    # simulator's true friction, used as the predictor of the measured held-out patterns, is
    # the reference: its fit (by hand) is what a perfect friction model would score.
    ho = network.held_out
    ceiling = _fit(ho.friction, ho.friction_true)
    assert ceiling < 90.0  # measured ~68 %: the estimator's error alone is far from 98 %
    # the net cannot learn the held-out patterns' estimator error beyond its systematic part
    # (which depends on Tm and omega_hat): its fit stays within 10 points of the ceiling (~4 here)
    assert abs(network.fit_held_out.fit_percent - ceiling) < 10.0
    c = claims["nn-fit"]
    assert not c.passed and "measuring chain" in c.note
    assert f"fit {_fit(ho.friction, network.net(ho.tm, ho.omega)):.1f} %" in c.measured


def test_exact_patterns_bound_what_the_net_can_learn(network, figs, claims):
    # Reference: the exact patterns are the closed-form friction law, a function of (Tm, omega)
    # alone -- the law while sliding, the torque clipped at breakaway at rest (exact: 1e-12) --
    # so nothing but the 2-4-1 net's capacity limits the fit on them.
    ex = true_patterns(network.experiments)
    sliding = ex.omega != 0.0
    np.testing.assert_allclose(ex.friction[sliding], P.friction_model().torque(ex.omega[sliding]),
                               rtol=0, atol=1e-12)
    np.testing.assert_allclose(ex.friction[~sliding], np.clip(ex.tm[~sliding], -P.static, P.static),
                               rtol=0, atol=1e-12)
    # the same network, split and seed on them: the measuring chain, not the architecture,
    # costs most of the fit (robust margin: 10 points; measured ~27)
    r = figs[8]
    assert r.fit_exact.fit_percent > r.fit_held_out.fit_percent + 10
    assert r.fit_exact.r_squared > 0.99
    # and the closed form links the exact fit to its R^2 as for the measured one
    assert r.fit_exact.fit_percent == pytest.approx(100 * (1 - np.sqrt(1 - r.fit_exact.r_squared)), abs=1e-9)
    assert f"{r.fit_exact.fit_percent:.1f} %" in claims["nn-fit"].note
    assert f"fit {r.fit_exact.fit_percent:.1f} %" in claims["nn-fit-exact"].measured


def test_network_is_deterministic(network):
    again = paper.train_paper_network(P, fast=True, seed=0)
    np.testing.assert_array_equal(again.net.w1, network.net.w1)  # same seed, same net, bit for bit


# -- Figs. 4 and 5 ------------------------------------------------------------
def test_fig4_filtered_beats_raw(figs, claims):
    r = figs[4]
    # closed form: the backward difference on an encoder grid errs by up to one count per sample
    assert r.raw_rms <= RES / P.sample_time * 1.05
    assert r.filtered_rms < 0.5 * r.raw_rms  # robust margin, measured ~4x
    assert claims["fig4-filter"].passed


def test_fig5_patterns(figs):
    r = figs[5]
    assert np.abs(r.torque).max() == pytest.approx(P.max_torque, rel=1e-12)  # the sequence reaches Tmax
    at_rest = r.torque == 0
    # at zero torque and rest the pattern is exactly zero (Tat = Tm - I*0); allow samples still moving
    assert np.median(np.abs(r.friction[at_rest])) < 1e-3


# -- Figs. 9 and 10 -------------------------------------------------------------
def test_fig9_sticks_without_none_with(figs, claims):
    r = figs[9]
    assert len(r.sticks_without) >= 2  # 2 reversals per period at 0.5 Hz over 4 s
    assert r.sticks_with == []
    # the paper pipeline's joint no longer sticks because it runs away (g > 1): far faster than
    # the linear viscous actuator, its torque wound up or never reversing, and it does not coast
    # down; its own criterion is met, the claim fails
    assert r.peak_speed_with > 2 * r.peak_speed_linear
    assert not r.coast.passed and not (r.wind_up.passed and r.reversal.passed)
    c = claims["fig9-stick"]
    assert not c.passed and c.runaway and c.note.startswith("runaway: ")
    assert "Its own criterion was met" in c.note
    assert c.value == 0.0  # no stick interval with compensation: the number its criterion thresholds


def test_fig9_linear_actuator_reference(ffigs, fclaims):
    # Reference: the linear viscous actuator's steady sinusoidal response in closed form,
    # |w| = A / |b + j*I*2*pi*f|; its sampled run reaches it within 2 % by the last period.
    r = ffigs[9]
    amp = r.amplitude / abs(P.viscous + 1j * P.inertia * 2 * np.pi * r.frequency)
    last = r.linear.t >= r.linear.t[-1] - 1 / r.frequency
    assert np.abs(r.linear.omega[last]).max() == pytest.approx(amp, rel=0.02)
    dev = abs(r.peak_speed_with - r.peak_speed_linear) / r.peak_speed_linear
    c = fclaims["fig9-linear"]
    assert c.value == pytest.approx(100 * dev, rel=1e-12)
    assert c.passed == (dev <= 0.1 and not c.runaway)


def test_fig10_dead_zone(figs, claims, network):
    r = figs[10]
    # reference: Fs/Tmax = 0.127 (params); amplitude grid 0.1 % of Tmax plus sinusoid dynamics: 1 %
    assert abs(r.dead_zone_without.fraction - 0.127) <= 0.01
    assert r.factor >= 4.0
    # the fixed-point prediction from the net alone agrees within a factor 1.5 (grid and dynamics)
    assert 1 / 1.5 <= r.factor / r.predicted_factor <= 1.5
    # 10 % of Tmax < Fs: exact stick without compensation (zero motion), motion with
    assert r.without.displacement_counts() == 0
    assert r.with_nn.displacement_counts() > r.dead_zone_with.threshold_counts
    assert r.gain_at_rest == pytest.approx(network.net.gain_at_rest())
    # ... but the paper pipeline's joint moves by running away: the motor torque winds up far above
    # the +-0.14 N*m control torque (or the velocity never reverses), so both claims fail by runaway
    assert np.abs(r.with_nn.torque_motor).max() > 2 * np.abs(r.with_nn.torque_cmd).max()
    assert not (r.wind_up.passed and r.reversal.passed)
    for cid in ("dead-zone", "fig10-motion"):
        assert not claims[cid].passed and claims[cid].note.startswith("runaway: ")
        assert claims[cid].checks == r.checks


def test_fig10_fricctl_follows_the_control_torque(ffigs, fclaims, fnetwork):
    r = ffigs[10]
    g = fnetwork.net.gain_at_rest()
    assert 0.98 <= g <= 0.99 and fnetwork.trained.certificate.passed  # the certified band
    # the stuck loop amplifies Tc by 1/(1 - g) (the closed form): 10 % of Tmax breaks away
    assert r.with_nn.torque_cmd.max() / (1 - g) > P.static
    assert r.wind_up.passed and r.reversal.passed and r.coast.passed
    assert fclaims["fig10-motion"].passed and not fclaims["fig10-motion"].runaway
    # dead zone reduced at least to the fixed point's Fs*(1 - g), and the claim reports the factor
    assert r.dead_zone_with.dead_zone <= P.static * (1 - g) * 1.5 + 0.0025 * P.max_torque
    assert fclaims["dead-zone"].value == pytest.approx(r.factor, rel=1e-12)


# -- Figs. 11-14 ------------------------------------------------------------------
def test_fig11_never_moves(figs, claims):
    r = figs[11]
    step = np.deg2rad(25)
    assert r.design.kp * step < P.static  # closed form: the step asks for less than breakaway
    assert np.all(r.run.q == 0.0)
    assert r.steady_state_error == pytest.approx(step, rel=1e-12)
    assert claims["fig11-stuck"].passed and "trivially" in claims["fig11-stuck"].note


def _growth(run):
    """Peak |r - q| in the last second over the first, by hand [-]."""
    e = np.abs(run.reference - run.q)
    return e[run.t >= run.t[-1] - 1.0].max() / e[run.t <= 1.0].max()


def test_fig12_full_compensation_destabilises_p_loop(figs, claims):
    r = figs[12]
    step = np.deg2rad(25)
    # the P loop with full NN compensation oscillates and grows; the linear one settles
    assert r.growth > 1.0
    assert r.max_deviation > 0.1 * step
    assert abs(r.linear[-1] - step) < 0.02 * step  # the linear prediction settles (zeta 0.3, 3 s)
    c = claims["fig12-linear"]
    assert not c.passed and "damping" in c.note
    assert c.value == pytest.approx(np.rad2deg(r.max_deviation), rel=1e-12)


def test_fig12_variant_keeps_the_damping(network, figs, claims):
    # Reference: a separate simulation of the variant with the estimator written out here,
    # net(Tm, w) - b*w (same arithmetic as ViscousExcluded, so equal to the bit).
    r, d = figs[12], figs[12].design
    net, b = network.net, P.viscous
    run = simulate(P, ctl.p_control(d.kp, ctl.step(np.deg2rad(25))),
                   NNCompensator(lambda tm, w: net(tm, w) - b * np.asarray(w, dtype=float)), duration=3.0)
    np.testing.assert_array_equal(run.q, r.variant.q)
    assert _growth(run) == pytest.approx(r.variant_growth, rel=1e-12)
    assert np.abs(run.q - r.linear).max() == pytest.approx(r.variant_max_deviation, rel=1e-12)
    # physics: leaving b in the loop gives the P loop back the damping its design counts on --
    # the error decays (growth < 1) where full compensation makes it grow, and the swing shrinks
    assert _growth(run) < 1.0 < _growth(r.run)
    assert r.variant_max_deviation < 0.5 * r.max_deviation  # measured ~0.3x
    v = claims["fig12-variant"]
    assert "not in the paper" in v.claim.lower()
    assert f"max deviation {np.rad2deg(np.abs(run.q - r.linear).max()):.1f} deg" in v.measured
    # the variant needs only its own run's wind-up check (the coast test is of another compensation)
    assert [c.name for c in v.checks] == ["wind-up"]


def test_fig12_ideal_estimate_isolates_the_cause(figs, claims):
    # an ideal static estimator (exact sliding friction, Tat = Tm at rest) with full compensation
    # still grows; without its viscous term it follows the linear viscous prediction
    r = figs[12]
    step = np.deg2rad(25)
    assert r.ideal_growth > 1.0
    assert r.ideal_no_viscous_max_deviation < 0.1 * step
    assert claims["fig12-ideal"].passed and claims["fig12-ideal"].checks == ()


def test_fig12_fricctl_keeps_the_damping(ffigs, fclaims, fnetwork):
    # the fricctl net leaves b_hat*w in the loop (b_hat ~ the bench's b, least squares on the
    # sliding patterns): the P loop keeps its damping and settles, as the linear design predicts
    r = ffigs[12]
    assert r.viscous_left == fnetwork.trained.viscous_removed
    assert abs(r.viscous_left - P.viscous) < 0.2 * P.viscous
    assert r.growth < 1.0
    # the ideal-estimate runs do not depend on the network: the same (shared, read-only) arrays
    assert not r.ideal.q.flags.writeable


def test_fig13_residual_torque(figs, claims, network):
    r = figs[13]
    run = r.run
    assert run.stuck[-1]
    # the joint stops inside the dead band +-Fs/Kp (one count of encoder slack)
    assert abs(r.steady_state_error) <= P.static / r.design.kp + RES
    # the held torque is Kp*e of the encoder reading (the loop sees y, not q)
    assert r.torque_at_rest == pytest.approx(r.design.kp * (run.reference[-1] - run.q_meas[-1]), rel=1e-9)
    assert r.nn_at_rest == pytest.approx(float(network.estimate(r.torque_at_rest, 0.0)), rel=1e-12)
    assert r.nn_at_rest == pytest.approx(float(network.net(r.torque_at_rest, 0.0)), rel=1e-12)  # b_hat = 0
    # Reference for what the net should say there: a stuck joint's friction is the held motor
    # torque exactly (I*alpha = 0; the simulator's truth, 1e-12) and below breakaway.
    assert run.friction[-1] == pytest.approx(r.torque_at_rest, rel=1e-12)
    assert abs(r.torque_at_rest) <= P.static
    # The net learned the stuck patterns Tat = Tm (most of its training data): at rest it errs by
    # less than twice its held-out RMSE over all patterns (measured 0.004 N*m against 0.046).
    assert abs(r.nn_at_rest - run.friction[-1]) < 2 * r.nn_rmse
    assert claims["fig13-residual"].passed


def test_fig14_stops_in_residual_band(figs, claims, network):
    r14, r13 = figs[14], figs[13]
    assert r14.run.stuck[-1]
    # compensation shrinks the error by at least the dead-zone factor's lower bound (4)
    assert abs(r14.steady_state_error) < abs(r13.steady_state_error) / 4
    # it stops within the predicted residual band DZ/Kp (one count of slack)
    assert abs(r14.steady_state_error) <= r14.predicted_band + RES
    # where exactly: the fixed point of the stuck loop, computed by hand from the net alone,
    # gives the error to one encoder count (the loop sees y, the error is measured on q)
    e_hand = _assert_stuck_fixed_point(r14.run, r14.design.kp, 1.0, network.net, P.static)
    assert r14.steady_state_error == pytest.approx(e_hand, abs=RES)
    c = claims["fig14-accuracy"]
    assert f"|e_ss| {np.rad2deg(abs(r14.steady_state_error)):.3f} deg" in c.measured
    if not c.passed:
        assert "DZ/Kp" in c.note or c.runaway


def test_fig14_eight_steps(ffigs, fclaims, fnetwork):
    r = ffigs[14]
    assert len(r.steps) == 8 and np.all(np.abs(np.rad2deg(r.steps)) <= 40)
    d = r.design
    # reference: each of the eight is the single-run simulator's step with the same compensation
    i = 6
    one = simulate(P, ctl.pd_control(d.kp, d.kd, ctl.step(float(r.steps[i]))), fnetwork.compensator(),
                   duration=3.0)
    assert r.steps_error[i] == pytest.approx(one.steady_state_error(), abs=1e-12)
    # Where a stuck joint can stop, by hand: at rest Tc = Kp*(r - y) and Tm(k+1) = Tc + net(Tm(k), 0).
    # A joint stuck over [t(k), t(k+1)] held |Tm(k)| <= Fs, so
    # |Tc| = |Tm(k) - net(Tm(k), 0) + (Tm(k+1) - Tm(k))| <= max_{|Tm| <= Fs} |Tm - net(Tm, 0)| + |dTm|,
    # the maximum taken on a dense grid here (spacing 3.6e-5 N*m, the net's slope < 1: 1e-4 of slack).
    grid = np.linspace(-P.static, P.static, 10001)
    worst = float(np.max(np.abs(grid - fnetwork.net(grid, np.zeros_like(grid))))) + 1e-4
    assert worst < 0.1 * P.static  # g ~ 0.98: the dead zone shrinks ~50x (measured 0.003 N*m)
    for run, e in zip(r.steps_runs, r.steps_error):
        assert np.all(run.stuck[run.t >= run.t[-1] - 0.5])
        tm0, tm1, tc = (float(x) for x in (run.torque_motor[-2], run.torque_motor[-1], run.torque_cmd[-2]))
        assert tc == pytest.approx(d.kp * (run.reference[-2] - run.q_meas[-2]), rel=1e-12)
        assert tm1 == pytest.approx(tc + float(fnetwork.net(tm0, 0.0)), abs=1e-12)
        bound = worst + abs(tm1 - tm0)
        assert abs(tc) <= bound
        assert abs(e) <= bound / d.kp + RES  # one encoder count: the loop sees y, e is r - q
    c = fclaims["fig14-steps"]
    assert c.value == pytest.approx(np.rad2deg(np.abs(r.steps_error).max()), rel=1e-12)
    assert len(c.checks) == 9  # eight wind-up checks and the coast test


# -- Figs. 16-18 ------------------------------------------------------------------
def test_fig16_aged_actuator(figs, claims, network):
    r = figs[16]
    nn = next(k for k in r.runs if k.startswith("NN"))
    e = {k: abs(v) for k, v in r.steady_state_error.items()}
    # no compensation: stuck inside the aged dead band 0.95*Fs/Kp, well above 0.3 deg
    assert np.deg2rad(0.3) <= e["none"] <= 0.95 * P.static / r.design.kp + RES
    assert claims["fig16-none"].passed
    # NN x 0.95 without retraining: stable (no chatter at the end) and >= 4x better than none
    assert r.torque_sign_changes[nn] == 0 and e[nn] < e["none"] / 4
    # where it stops: the stuck loop's fixed point by hand, with s = 0.95 and the aged breakaway
    e_hand = _assert_stuck_fixed_point(r.runs[nn], r.design.kp, paper.AGED_SCALE, network.net,
                                       r.friction_scale * P.static)
    assert r.steady_state_error[nn] == pytest.approx(e_hand, abs=RES)  # one count: y against q
    # Coulomb, at the two levels identified on the bench's records (not its true parameters):
    from fricctl.paper.common import COULOMB_AT_FC, COULOMB_AT_FS, uncompensated_dead_zone

    lv = r.coulomb_levels
    # the breakaway level is the dead zone of the uncompensated dead-zone experiment (Fig. 10's),
    # within its amplitude step above the true breakaway level (closed form: the joint moves
    # once the amplitude exceeds Fs)
    assert lv.breakaway == uncompensated_dead_zone(network.params).dead_zone
    assert P.static < lv.breakaway <= P.static + lv.breakaway_step
    # the smaller level: least squares on the sliding patterns, recomputed by hand
    pats = network.patterns
    m = ~pats.at_rest & (pats.omega != 0)
    fc, b = np.linalg.lstsq(np.column_stack([np.sign(pats.omega[m]), pats.omega[m]]), pats.friction[m],
                            rcond=None)[0]
    assert (lv.coulomb, lv.viscous, lv.patterns) == pytest.approx((fc, b, m.sum()), rel=1e-9)
    # ... near the bench's true Fc (the measuring chain's bias, a few %: a seeded estimate)
    assert lv.coulomb == pytest.approx(P.coulomb, rel=0.05)
    for k in (COULOMB_AT_FS, COULOMB_AT_FC):
        cr = r.runs[k]
        # the compensated level is s x the identified one, in both directions
        assert np.abs(cr.friction_est).max() * r.scale == pytest.approx(r.coulomb_level(k), rel=1e-12)
        # sign(omega_hat) is 0 at rest, so the stuck joint gets no compensation: no chatter, no cycle
        assert cr.stuck[-1] and cr.friction_est[-1] == 0.0 and r.torque_sign_changes[k] == 0
        assert r.cycles[k].amplitude == 0.0 and r.cycles[k].counts == 0 and not r.cycles[k].sustained
        # a limit cycle or not, the Coulomb compensation stays within the friction: no runaway
        assert r.coulomb_wind_up[k].passed
    fs_claim, fc_claim = claims["fig16-coulomb-fs"], claims["fig16-coulomb-fc"]
    assert not fs_claim.passed and "sign(omega_hat)" in fs_claim.note and not fs_claim.runaway
    # "the oscillation disappears" needs one at the breakaway level: without it, not reproduced
    assert not fc_claim.passed and "nothing to disappear" in fc_claim.note and not fc_claim.runaway
    # the describing function on this loop: at s x Fs^ against 0.95 x the true friction, a cycle whose
    # pull stays below the aged breakaway (the joint sticks), reported in the claim; at s x Fc^ none
    from fricctl.design import LinearLoop, coulomb_limit_cycle

    cyc = coulomb_limit_cycle(LinearLoop.of(r.design), compensation=r.scale * lv.breakaway,
                              coulomb=r.friction_scale * P.coulomb, static=r.friction_scale * P.static)
    assert not cyc.sustained and f"{cyc.frequency:.2f} Hz" in fs_claim.measured
    assert r.predicted[COULOMB_AT_FS] == cyc
    assert "the joint sticks at its first turning point" in fs_claim.measured
    # s x Fc^ is below the aged Fc here (0.95 x 0.143 < 0.95 x 0.144): no relay left, no cycle
    assert r.scale * lv.coulomb < r.friction_scale * P.coulomb and r.predicted[COULOMB_AT_FC] is None
    assert "predicts no cycle" in fc_claim.measured
    # the flicker arithmetic of the notes, by hand: level + Kp*|e_ss| against the aged breakaway
    for k, claim, above in ((COULOMB_AT_FS, fs_claim, True), (COULOMB_AT_FC, fc_claim, False)):
        push = r.coulomb_level(k) + r.design.kp * abs(r.steady_state_error[k])
        assert (push > r.friction_scale * P.static) is above and f"= {push:.4f} N*m" in claim.note


def test_oscillation_measures_the_predicted_limit_cycle():
    # A loop where over-compensation sustains a cycle (chapter 7: a P loop twice as stiff, no Kd,
    # Coulomb at Fs against Coulomb friction Fc): the last second's oscillation against the
    # describing function -- amplitude within 3 % (chapter 7's check), frequency within 10 % (the
    # describing function keeps the relay's first harmonic only; here it reads 4.17 Hz for 3.97)
    from fricctl.compensators import CoulombCompensator
    from fricctl.design import LinearLoop, coulomb_limit_cycle
    from fricctl.friction import Coulomb
    from fricctl.paper.common import oscillation

    loop = LinearLoop(kp=2.0, kd=0.0, inertia=P.inertia, viscous=P.viscous, sample_time=P.sample_time)
    cyc = coulomb_limit_cycle(loop, compensation=P.static, coulomb=P.coulomb)
    run = simulate(P, ctl.pd_control(2.0, 0.0, ctl.step(0.2)), CoulombCompensator.symmetric(P.static),
                   duration=8.0, friction=Viscous(P.viscous) + Coulomb(P.coulomb))
    o = oscillation(run)
    assert cyc.sustained and o.sustained and o.crossings >= 6
    assert o.amplitude == pytest.approx(cyc.amplitude, rel=0.03)
    assert o.frequency == pytest.approx(cyc.frequency, rel=0.10)
    # the same cycle measured over a longer window: the same frequency to 1 %
    assert oscillation(run, 4.0).frequency == pytest.approx(o.frequency, rel=0.01)
    # peak to peak in counts: 2A over one count, to the count
    assert abs(o.counts - 2 * o.amplitude / RES) <= 1


def test_fig17_small_step(figs, claims, network):
    r = figs[17]
    assert r.design.kp * r.step < 0.95 * P.static  # closed form: below the aged breakaway
    assert r.max_motion["none"] == 0.0 and claims["fig17-none"].passed
    nn = next(k for k in r.runs if k.startswith("NN"))
    assert r.max_motion[nn] > 0.5 * r.step  # compensation moves the joint most of the way
    assert abs(r.steady_state_error[nn]) < 0.25 * r.step
    # it stops at the stuck loop's fixed point, by hand (aged breakaway, s = 0.95; one count)
    e_hand = _assert_stuck_fixed_point(r.runs[nn], r.design.kp, paper.AGED_SCALE, network.net,
                                       paper.AGED_SCALE * P.static)
    assert r.steady_state_error[nn] == pytest.approx(e_hand, abs=RES)


def test_fig18_sawtooth(figs, claims):
    r = figs[18]
    # closed form: Kp*0.1 rad < Fs, so without compensation the joint never moves (no stick-slip)
    assert r.design.kp * r.amplitude < P.static
    assert r.max_motion_without == 0.0 and r.restarts_without == 0
    c = claims["fig18-without"]
    assert not c.passed and "never moves" in c.note
    # with compensation the joint follows the ramp (reaches most of the amplitude)
    assert np.abs(r.with_nn.q).max() > 0.5 * r.amplitude
    # Reference for "tracks": a separate simulation of the linear viscous loop -- the bench itself
    # with viscous friction only -- matches r.linear (python-control) to one encoder count, its
    # only difference being the quantised feedback; the RMS by hand against it agrees to a count.
    pl = P.with_link()
    c = ctl.pd_control(r.design.kp, r.design.kd, ctl.sawtooth(r.amplitude, r.period))
    viscous = simulate(pl, c, NoCompensation(), duration=r.periods * r.period, friction=Viscous(P.viscous))
    np.testing.assert_allclose(viscous.q, r.linear, rtol=0, atol=RES)
    assert np.sqrt(np.mean((r.with_nn.q - viscous.q) ** 2)) == pytest.approx(r.rms_deviation_with, abs=RES)
    # physics of the failure: the compensated joint moves in stick-slip itself (a staircase)
    assert paper.restarts(r.with_nn) >= 2
    if not claims["fig18-with"].passed:
        assert "staircase" in claims["fig18-with"].note or claims["fig18-with"].runaway
    # the compensation's share of the friction while sliding slowly, by hand: the samples that
    # slide (true velocity nonzero) no faster than twice the ramp's speed
    w = r.with_nn
    speed = np.abs(w.omega)
    slow = (speed > 0) & (speed <= 2 * r.amplitude / r.period)
    assert slow.sum() > 10
    true_mean = np.abs(w.friction[slow]).mean()
    assert r.slow_friction == pytest.approx(true_mean, rel=1e-12)
    assert r.slow_share == pytest.approx((w.friction_est[slow] * np.sign(w.friction[slow])).mean()
                                         / true_mean, rel=1e-12)
    # the extra: a slower, larger ramp shows stick-slip without compensation
    assert r.extra_restarts >= 2 and claims["fig18-extra"].passed


# -- claims ----------------------------------------------------------------------
def test_claims_of_one_network(claims, fclaims):
    for cs in (claims, fclaims):
        # one claim per maker of the registry's figures, each id once (the dict would merge two)
        assert len(cs) == N_CLAIMS
        for c in cs.values():
            assert c.claim and c.paper and c.measured and c.unit and c.figure.startswith("Fig. ")
            assert isinstance(c.passed, bool) and isinstance(c.value, float)
            if not c.passed:
                assert c.note, f"{c.id} fails without a reason"
            if c.runaway:
                assert not c.passed and c.note.startswith("runaway: ")
    # every claim whose measurement involves the network's compensation carries the checks
    compensated = {"fig9-stick", "fig9-linear", "coast-decay", "dead-zone", "fig10-motion", "fig12-linear",
                   "fig12-variant", "fig14-accuracy", "fig14-steps", "fig16-nn", "fig17-nn", "fig18-with"}
    # ... and the Coulomb compensation's claims the wind-up check of their own run (a limit cycle
    # is not a runaway; a pass by runaway would be a failure)
    coulomb = {"fig16-coulomb-fs", "fig16-coulomb-fc"}
    assert {c.id for c in claims.values() if c.checks} == compensated | coulomb
    for cid in coulomb:
        assert [k.name for k in claims[cid].checks] == ["wind-up"] and not claims[cid].runaway
    # the coast test of the same network is among them (all but the Fig. 12 variant's)
    for cid in compensated - {"fig12-variant", "coast-decay"}:
        assert "coast" in [k.name for k in claims[cid].checks], cid
    # the paper pipeline runs away in every compensated claim (its g > 1: 20/20 seeds in the issue)
    assert all(claims[cid].runaway for cid in compensated - {"fig12-variant"})


def _claim(cid="x", passed=True, value=1.0, paper_value="p", note="", checks=()):
    return paper.Claim(id=cid, claim="c", paper=paper_value, measured=f"v = {value}", passed=passed,
                       figure="Fig. 9", value=value, unit="deg", note=note, checks=checks)


def _check(passed, reason="r"):
    return paper.RunawayCheck(name="wind-up", value=0.0 if passed else 9.0, unit="samples", limit=5.0,
                              passed=passed, reason=reason)


def test_gate_fails_a_claim_on_a_failed_runaway_check():
    ok, bad = _check(True), _check(False, "runaway: the velocity never reverses")
    c = paper.gate(_claim(), (ok,))
    assert c.passed and not c.runaway and c.checks == (ok,)
    c = paper.gate(_claim(), (ok, bad))
    assert not c.passed and c.runaway
    assert c.note.startswith("runaway: the velocity never reverses.") and "own criterion was met" in c.note
    c = paper.gate(_claim(passed=False, note="too far"), (bad,))
    assert not c.passed and c.note.endswith(". Too far") and c.note.startswith("runaway: ")  # a sentence
    with pytest.raises(ValueError, match="gate"):
        _claim(checks=(bad,))  # a claim cannot pass with a failed check


def _sim(omega, *, tc=None, tm=None, q=None, ts=P.sample_time):
    """A hand-made run: the arrays given, the bench's nominal friction in its info."""
    base = simulate(P, ctl.open_loop(ctl.constant(0.0)), duration=len(omega) * ts)
    n = base.t.size
    assert n == len(omega)
    z = np.zeros(n)
    q = np.cumsum(omega) * ts if q is None else np.asarray(q, dtype=float)
    return replace(base, omega=np.asarray(omega, dtype=float), q=q, q_meas=np.floor(q / RES) * RES,
                   torque_cmd=z if tc is None else np.asarray(tc, dtype=float),
                   torque_motor=z if tm is None else np.asarray(tm, dtype=float))


def test_wind_up_against_hand_made_runs():
    fs = P.static
    tm = np.zeros(100)
    # |Tm(k+1)| > |Tc(k)| + Fs + b*|omega(k)| (here Tc = 0, omega = 0) for 6 samples: a wind-up
    tm[40:46] = fs + 0.01
    w = paper.wind_up(_sim(np.zeros(100), tm=tm))
    assert w.value == 6 and not w.passed and "6 consecutive samples" in w.reason
    assert "t = 0.078 s" in w.reason  # the first excess Tm(40) is judged against sample k = 39
    # 5 samples: the loop's allowed lateness (one-sample delay + backward difference, twice over)
    tm[45] = 0.0
    w = paper.wind_up(_sim(np.zeros(100), tm=tm))
    assert w.value == 5 and w.passed
    # the bound moves with the speed and the control torque: b*|omega| + |Tc| covers the same Tm
    w = paper.wind_up(_sim(np.full(100, 1.0), tm=np.full(100, fs + P.viscous * 1.0 - 1e-6)))
    assert w.value == 0 and w.passed
    w = paper.wind_up(_sim(np.zeros(100), tc=np.full(100, 0.05), tm=np.full(100, fs + 0.05 + 1e-6)))
    assert w.value == 99 and not w.passed  # every pair (k, k+1) exceeds
    assert paper.wind_up(_sim(np.zeros(100), tm=np.full(100, fs - 1e-6))).value == 0


def test_divergence_against_hand_made_runs():
    # issue 23: the torque check of a compensator that is not a friction estimate.  100 samples,
    # 99 judged pairs (k, k+1); the last quarter (SETTLE_SHARE) from k = 75 (t = 0.150 s)
    fs = P.static
    assert paper.runaway.SETTLE_SHARE == 0.25 and paper.runaway.DECAY == 0.5
    tm = np.zeros(100)
    tm[10:40] = fs + 0.04  # a transient beyond the bound, 30 samples, 0.04 N*m, that ends
    d = paper.divergence(_sim(np.zeros(100), tm=tm))
    assert d.passed and d.value == 0 and "ended before the run's last 25 % (from t = 0.150 s)" in d.reason
    assert not paper.wind_up(_sim(np.zeros(100), tm=tm)).passed  # the friction bound fails it
    # a late episode (8 samples) that has decayed to a quarter of it: passes; to 5/8: fails
    tm[80:88] = fs + 0.01
    d = paper.divergence(_sim(np.zeros(100), tm=tm))
    assert d.passed and d.value == pytest.approx(25.0) and d.limit == 50.0
    tm[80:88] = fs + 0.025
    d = paper.divergence(_sim(np.zeros(100), tm=tm))
    assert not d.passed and d.value == pytest.approx(62.5) and "not decayed" in d.reason
    # 5 samples are the loop's lateness, as for wind_up: not an episode
    tm[85:88] = 0.0
    assert paper.divergence(_sim(np.zeros(100), tm=tm)).passed
    # a late episode with none before, a hair beyond the bound that ends, the joint still: nothing
    # before to measure it against and too little record after it -- not judged, never a runaway
    # (issue 25: a DOB reaching the breakaway level late in a 3 s run was called one)
    tm[:] = 0.0
    tm[80:88] = fs + 0.001
    d = paper.divergence(_sim(np.zeros(100), tm=tm))
    assert d.passed and not d.judged and math.isnan(d.value) and d.as_dict()["value"] is None
    assert d.reason.startswith("too short to tell") and "it ended within the record" in d.reason
    # held beyond the bound from before the last quarter to the end (a saturated drive)
    tm[:] = 0.0
    tm[10:40] = fs + 0.5
    tm[60:] = fs + 0.01
    d = paper.divergence(_sim(np.zeros(100), tm=tm))
    assert not d.passed and d.value == math.inf and "has not ended" in d.reason
    # a growing oscillation of the torque fails, a decaying one passes
    t = np.arange(100) * P.sample_time
    wave = fs * np.sin(2 * np.pi * t / 0.04)
    assert not paper.divergence(_sim(np.zeros(100), tm=2 * wave * np.exp(t / 0.1))).passed
    assert not paper.divergence(_sim(np.zeros(100), tm=2 * wave)).passed  # sustained
    assert paper.divergence(_sim(np.zeros(100), tm=4 * wave * np.exp(-t / 0.02))).passed
    for bad, match in (({"settle_share": 1.0}, "settle_share"), ({"settle_share": 0.0}, "settle_share"),
                       ({"settle_share": 0.05}, "max_samples"), ({"decay": 0.0}, "decay")):
        with pytest.raises(ValueError, match=match):
            paper.divergence(_sim(np.zeros(100)), **bad)


def _held(n, *, tm, q, controller="PD"):
    """A hand-made closed-loop run of ``n`` samples whose reference (zero) is held throughout."""
    r = _sim(np.zeros(n), tm=tm, q=q)
    return replace(r, info=replace(r.info, controller=controller))


def test_divergence_fails_a_sustained_envelope_after_a_large_transient():
    # the steadiness test (STEADY): 400 samples, 399 judged pairs; the last quarter from k = 300,
    # its halves k = 300..348 and 349..398.  A large first transient (0.5 N*m beyond the bound),
    # then a square wave beyond it by 0.05 N*m (8 of every 20 samples: episodes of 8 > 5
    # samples) to the end: 10 % of the first excess, which DECAY alone passes
    assert paper.runaway.STEADY == 0.9
    fs, n = P.static, 400
    k = np.arange(n)
    on = (k % 20) < 8
    swing = 10 * RES * np.sin(2 * np.pi * k / 20)  # the joint swings 20 counts peak to peak

    def wave(first_half, second_half):
        tm = np.zeros(n)
        tm[10:40] = fs + 0.5
        amp = np.where(k < 349, first_half, second_half)
        tm[60:] = np.where(on[60:], fs + amp[60:], 0.0)
        return tm

    d = paper.divergence(_held(n, tm=wave(0.05, 0.05), q=swing))
    assert not d.passed and d.value == math.inf and "sustained envelope" in d.reason
    assert "0.0500 and 0.0500 N*m" in d.reason and "swings 20 encoder counts" in d.reason
    # the old rule alone (decay) passes it: 10 % of the first excess, below 50 %
    assert paper.divergence(_held(n, tm=wave(0.05, 0.05), q=swing), steady=1e9).value == pytest.approx(10.0)
    # the envelope's ratio between the halves decides: 95 % is sustained, 85 % decays
    assert not paper.divergence(_held(n, tm=wave(0.05, 0.0475), q=swing)).passed
    d = paper.divergence(_held(n, tm=wave(0.05, 0.0425), q=swing))
    assert d.passed and d.value == pytest.approx(10.0)
    # a decaying wave passes: the excess shrinks by exp(-0.1 s / 0.1 s) between the halves
    tm = wave(0.05, 0.05)
    tm[60:] = np.where(on[60:], fs + 0.05 * np.exp(-(k[60:] - 60) * P.sample_time / 0.1), 0.0)
    assert paper.divergence(_held(n, tm=tm, q=swing)).passed
    # the same steady excess with the joint still (a hair beyond the breakaway level at rest,
    # 3 counts or fewer): no oscillation of the joint, passes
    assert paper.divergence(_held(n, tm=wave(0.05, 0.05), q=np.zeros(n))).passed
    assert paper.divergence(_held(n, tm=wave(0.05, 0.05), q=1.5 * RES * np.sin(2 * np.pi * k / 20))).passed
    # the excitation goes on (open loop, or a reference that moves in the last quarter): a repeated
    # excess may be the excitation's; decay alone judges
    assert paper.divergence(_held(n, tm=wave(0.05, 0.05), q=swing, controller="open loop")).passed
    r = _held(n, tm=wave(0.05, 0.05), q=swing)
    assert paper.divergence(replace(r, reference=0.01 * k * P.sample_time)).passed
    # an episode in one half only is not an envelope in both
    tm = wave(0.05, 0.05)
    tm[349:] = 0.0
    assert paper.divergence(_held(n, tm=tm, q=swing)).passed
    for bad, match in (({"steady": 0.0}, "steady"), ({"motion_counts": -1}, "motion_counts")):
        with pytest.raises(ValueError, match=match):
            paper.divergence(_held(n, tm=wave(0.05, 0.05), q=swing), **bad)


def test_divergence_fails_a_joint_driven_away_within_the_friction_bound():
    # the review: a DOB whose nominal inertia is 10x the plant's slams the torque between its
    # limits and parks the joint ~0.6 rad on the wrong side of a 30 deg step; the PD term grows
    # with the error, so |Tm| stays within |Tc| + Fs + b|omega| and the torque test alone read
    # "no divergence" over 3 s and 10 s
    from fricctl.compensators.dob import DisturbanceObserver

    p = P
    step = np.deg2rad(30.0)
    run = simulate(p, ctl.pd_control(1.125, 0.139, ctl.step(step)),
                   DisturbanceObserver(inertia=10 * p.inertia, bandwidth=2000.0), duration=3.0)
    d = paper.divergence(run)
    assert not d.passed and d.judged and "driven away from its held reference" in d.reason
    assert np.abs(run.reference[-1] - run.q_meas[-500:]).min() > 2 * step  # what the reason says
    # the matched DOB on the same step ends at its reference: not driven away
    ok = simulate(p, ctl.pd_control(1.125, 0.139, ctl.step(step)),
                  DisturbanceObserver(inertia=p.inertia, bandwidth=200.0), duration=3.0)
    assert "driven away" not in paper.divergence(ok).reason
    # ... also without quantisation, and after a reference that went out and came back to the
    # start (its error at the start 0: the reference's own travel sets the scale)
    out_and_back = ctl.sequence([step, 0.0], [0.5, 2.5])
    for ref, quantize in ((ctl.step(step), False), (out_and_back, True), (out_and_back, False)):
        r = simulate(p, ctl.pd_control(1.125, 0.139, ref), DisturbanceObserver(
            inertia=10 * p.inertia, bandwidth=2000.0), duration=3.0, quantize=quantize)
        assert "driven away from its held reference" in paper.divergence(r).reason
    # the second review: a DOB hunting by stick-slip around a 2 mrad step pauses 4.8 mrad past it
    # through the last quarter of 3 s -- parked, held by friction, not driven: no runaway
    from fricctl.compensators import make

    d14 = designs(p)["fig13-14"]
    hunt = simulate(p, ctl.pd_control(d14.kp, d14.kd, ctl.step(0.002)), make("dob", p, d14),
                    duration=3.0)
    last = hunt.q_meas[int(0.75 * hunt.q_meas.size):]
    assert np.abs(0.002 - last).min() > 2 * 0.002 and np.ptp(last) == 0.0  # parked past it
    d = paper.divergence(hunt)
    assert d.passed and "driven away" not in d.reason


def test_divergence_of_a_first_excess_in_the_last_share_fails_only_what_grows():
    # 100 samples, 99 judged pairs, the last quarter from k = 75; nothing beyond the bound before
    # k = 88 (Tm(89)), after the last quarter's first half (so the steadiness test, which needs an
    # episode in both of its halves, does not apply).  From the first excess to the end: halves
    # k = 88..92 and 93..98.  The excess grows as exp(k/4), 4.5x between the halves' peaks
    fs, n = P.static, 100
    k = np.arange(n)
    tm = np.where(k >= 89, fs + 1e-3 * np.exp((k - 89) / 4.0), 0.0)
    # the joint swings wider about its held reference (zero): 2 counts growing by exp(k/3)
    wider = np.where(k >= 89, 2 * RES * np.exp((k - 89) / 3.0) * np.sin(2 * np.pi * k / 4 + 1), 0.0)
    d = paper.divergence(_held(n, tm=tm, q=wider))
    assert not d.passed and d.judged and d.value == math.inf
    assert "with none before (a torque that grew)" in d.reason
    assert "first excess beyond the bound is at t = 0.176 s" in d.reason
    # open loop (no reference): the growing excess and the swing decide
    d = paper.divergence(_sim(np.zeros(n), tm=tm, q=wider))
    assert not d.passed and "a torque that grew" in d.reason
    # the same excess with the joint still: no runaway the record shows, not judged
    d = paper.divergence(_held(n, tm=tm, q=np.zeros(n)))
    assert d.passed and not d.judged and "swings 0 encoder counts" in d.reason
    # ... or with the joint closing on its reference from 40 counts away (e ~ exp(-k/4): the
    # second half's largest error 14 counts, below 90 % of the first's 40)
    closing = 40 * RES * np.exp(-np.maximum(k - 89, 0) / 4.0)
    d = paper.divergence(_held(n, tm=tm, q=closing))
    assert d.passed and not d.judged and "closes on its reference" in d.reason
    # an excess that shrinks between the halves (exp(-k/4)) while the joint swings wider about its
    # held reference (a drive saturated away from it: the bound grows with |Tc| and |omega|): the
    # error decides, a runaway (the review: this passed as "too short to tell")
    shrinking = np.where(k >= 89, fs + 1e-2 * np.exp(-(k - 89) / 4.0), 0.0)
    d = paper.divergence(_held(n, tm=shrinking, q=wider))
    assert not d.passed and d.judged and "the joint driven away" in d.reason
    # ... the same shrinking excess with the joint hunting at a steady amplitude (its largest error
    # kept, not doubled) is not judged: nothing grew
    steady = np.where(k >= 89, 5 * RES * np.sin(2 * np.pi * k / 4 + 1), 0.0)
    d = paper.divergence(_held(n, tm=shrinking, q=steady))
    assert d.passed and not d.judged and "not growing" in d.reason
    # with the excess from the last quarter's start, the steadiness test sees the growth first
    early = np.where(k >= 76, fs + 1e-3 * np.exp((k - 76) / 8.0), 0.0)
    swing = np.where(k >= 76, 2 * RES * np.exp((k - 76) / 10.0) * np.sin(2 * np.pi * k / 8), 0.0)
    d = paper.divergence(_held(n, tm=early, q=swing))
    assert not d.passed and "sustained envelope" in d.reason


def test_divergence_still_fails_an_integral_runaway_that_starts_late_in_a_short_run():
    # a real runaway whose first excess lies in the last quarter: literal bench, design fig13-14,
    # integral action at 1.5 x the Routh limit, a step of 20 encoder counts.  The PD torque alone
    # cannot break the joint away; the integral winds the held torque up to the breakaway level
    # (t ~ 4.25 s), and from there each slip overshoots further: a stick-slip hunt that grows
    from fricctl.compensators import IntegralAction
    from fricctl.paper.benches import bench

    b = bench("literal")
    d = designs(b)["fig13-14"]
    p = b.actuator
    ki = 1.5 * (d.viscous + d.kd) * d.kp / d.inertia
    run = simulate(p, ctl.pd_control(d.kp, d.kd, ctl.step(20 * p.encoder_resolution)),
                   IntegralAction(ki=ki, max_torque=p.max_torque), duration=5.5)
    t, excess = paper.runaway._excess(run)
    first = np.flatnonzero(excess > 1e-12)[0]
    assert t[first] > 0.75 * 5.5  # the record: its first excess in the last quarter ...
    e = (run.reference - run.q) / p.encoder_resolution
    # ... and a hunt that grows: the error's peak to peak over the last 0.5 s more than 1.5 x that
    # over the 0.5 s before, which already spans 50 x the 20-count step
    assert np.ptp(e[-250:]) > 1.5 * np.ptp(e[-500:-250]) > 1.5 * 50 * 20
    c = paper.divergence(run)
    assert not c.passed and c.judged and "with none before (a torque that grew)" in c.reason


def test_runaway_reasons_follow_the_runs_units():
    # issue 25: a run's reasons carry the units of its axis (SimInfo.units, set by simulate_model
    # from the model): N, m/s, N*s/m on a linear axis, never N*m or rad
    from fricctl.friction import FrictionModel
    from fricctl.plant import JointModel
    from fricctl.simulate import simulate_model

    table = JointModel(inertia=2.0, friction=FrictionModel(coulomb_pos=20.0, coulomb_neg=20.0,
                                                           viscous_pos=20.0, viscous_neg=20.0),
                       sample_time=1e-3, units="linear")
    run = simulate_model(table, ctl.open_loop(ctl.constant(30.0)), duration=0.1)
    assert run.info.units == "linear"
    assert simulate(P, ctl.open_loop(ctl.constant(0.0)), duration=0.01).info.units == "rotary"
    fs, n = P.static, 100
    tm = np.zeros(n)
    tm[10:40] = fs + 0.04
    tm[80:88] = fs + 0.025
    r = _sim(np.zeros(n), tm=tm)
    linear = replace(r, info=replace(r.info, units="linear"))
    for check in (paper.divergence, paper.wind_up):
        assert "N*m" in check(r).reason
        text = check(linear).reason
        assert "N*m" not in text and re.search(r"[\d.]+ N[;,)]", text), text
    w = np.where(np.arange(n) < 50, 1.0, 0.0)  # a pulse's speed, kept 0 after t_end: coasts
    rot = paper.coast_decay(_sim(w), t_end=0.09)
    lin = _sim(w)
    lin = paper.coast_decay(replace(lin, info=replace(lin.info, units="linear")), t_end=0.09)
    assert "N*m*s/rad" in rot.reason and "rad/s" in rot.reason
    assert "N*s/m" in lin.reason and "m/s" in lin.reason and "rad" not in lin.reason
    with pytest.raises(ValueError, match="units"):
        replace(r.info, units="angular")


def test_divergence_says_when_its_record_is_too_short_for_the_loops_period():
    # the last quarter of 400 samples (Ts = 2 ms) is k = 300..398 (99 judged pairs): 0.198 s.  A
    # large first transient, then an excess of 0.05 N*m beyond the bound in the last quarter's first
    # half only (one half holds no episode: the steadiness test cannot compare them), 10 % of the
    # first: decay passes it.  Told the loop's period, the check says whether 0.198 s hold two
    fs, n = P.static, 400
    k = np.arange(n)
    tm = np.zeros(n)
    tm[10:40] = fs + 0.5
    tm[60:349] = np.where((k[60:349] % 20) < 8, fs + 0.05, 0.0)
    run = _held(n, tm=tm, q=10 * RES * np.sin(2 * np.pi * k / 20))
    plain = paper.divergence(run)
    assert plain.passed and plain.judged and "too short" not in plain.reason
    slow = paper.divergence(run, period=0.2)  # 0.198 s hold 0.99 of it: not judged
    assert slow.passed == plain.passed and not slow.judged
    assert "too short to judge whether it is sustained: the last 0.198 s hold 0.99 of the loop's period 0.2 s" \
        in slow.reason and slow.as_dict()["judged"] is False
    fast = paper.divergence(run, period=0.09)  # 2.2 periods: judged
    assert fast.judged and fast.reason == plain.reason
    # no episode in the last quarter: nothing to judge there, whatever the period
    tm[200:] = 0.0
    assert paper.divergence(_held(n, tm=tm, q=np.zeros(n)), period=10.0).judged
    with pytest.raises(ValueError, match="period"):
        paper.divergence(run, period=0.0)


def test_divergence_fails_the_integral_limit_cycle_above_the_routh_limit():
    # the review's case: literal bench, design fig13-14, 30 deg step, IntegralAction at 1.1 x the
    # Routh limit Ki < (b + Kd) Kp / I, 30 s.  After a large first transient the error rings at a
    # steady amplitude (a limit cycle); the check must say so
    from fricctl.compensators import IntegralAction
    from fricctl.paper.benches import bench

    b = bench("literal")
    d = designs(b)["fig13-14"]
    p = b.actuator
    ki_max = (d.viscous + d.kd) * d.kp / d.inertia
    run = simulate(p, ctl.pd_control(d.kp, d.kd, ctl.step(float(np.deg2rad(30.0)))),
                   IntegralAction(ki=1.1 * ki_max, max_torque=p.max_torque), duration=30.0)
    # the record itself: the error's peak to peak per tenth of the run; the last four tenths the
    # same within 5 % (a steady oscillation), each under a fifth of the first tenth's
    e = run.reference - run.q
    ptp = np.array([np.ptp(x) for x in np.array_split(e, 10)])
    assert np.ptp(ptp[-4:]) < 0.05 * ptp[-1] and ptp[-1] < 0.2 * ptp[0]
    c = paper.divergence(run)
    assert not c.passed and c.value == math.inf and "sustained envelope" in c.reason
    # the decay test alone passed it (its late excess is a few % of the first transient's)
    assert paper.divergence(run, steady=1e9).passed


def test_torque_check_follows_the_compensators_flag():
    from fricctl.compensators import (CoulombCompensator, DisturbanceObserver, IntegralAction,
                                      NoCompensation)

    run = _sim(np.zeros(100))
    assert paper.runaway.torque_check(run, CoulombCompensator.symmetric(0.1)).name == "wind-up"
    assert paper.runaway.torque_check(run, NoCompensation()).name == "wind-up"
    assert paper.runaway.torque_check(run, DisturbanceObserver(inertia=1e-3, bandwidth=50.0)).name \
        == "divergence"
    assert paper.runaway.torque_check(run, IntegralAction(ki=1.0)).name == "divergence"
    with pytest.raises(ValueError, match="compensator must be"):
        paper.runaway.torque_check(run, object())


def test_reversal_against_hand_made_sinusoids():
    t = np.arange(1500) * P.sample_time  # 3 s, period 1 s: periods 2 and 3 are judged
    follows = _sim(np.sin(2 * np.pi * t))
    r = paper.reversal(follows, 1.0)
    assert r.passed and r.value == 0
    runaway = _sim(1.0 + 0.5 * np.sin(2 * np.pi * t))  # moves, never reverses
    r = paper.reversal(runaway, 1.0)
    assert not r.passed and r.value == 2 and "never reverses in period(s) 2, 3" in r.reason
    # reversing in period 2 but not in 3 (a ratchet): one period fails
    w = np.sin(2 * np.pi * t)
    w[t >= 2.0] = np.abs(w[t >= 2.0])
    r = paper.reversal(_sim(w), 1.0)
    assert r.value == 1 and "period(s) 3 " in r.reason
    # a joint that moved 3 counts or fewer has not moved: nothing can run away
    q = np.zeros(1500)
    q[100:] = 3 * RES
    still = _sim(np.full(1500, 1e-9), q=q)
    assert still.displacement_counts() == 3
    r = paper.reversal(still, 1.0)
    assert r.passed and "3 encoder counts" in r.reason
    with pytest.raises(ValueError, match="full periods"):
        paper.reversal(runaway, 2.0)


def test_periods_with_motion_against_hand_made_runs():
    from fricctl.paper.common import periods_with_motion

    t = np.arange(1500) * P.sample_time  # 3 s, period 1 s
    q = np.where(t < 1.0, 10 * RES * t, 10 * RES)  # moves 10 counts in period 1, then parks
    assert periods_with_motion(_sim(np.zeros(1500), q=q), 1.0, 3) == 1
    q = 10 * RES * np.abs(np.sin(np.pi * t))  # moves in every period
    assert periods_with_motion(_sim(np.zeros(1500), q=q), 1.0, 3) == 3
    q = np.where(t < 1.0, 0.0, 1.0 * RES)  # one count: not motion
    assert periods_with_motion(_sim(np.zeros(1500), q=q), 1.0, 3) == 0


def test_coast_decay_against_hand_made_runs():
    i_over_b = P.inertia / P.viscous
    t = np.arange(1000) * P.sample_time
    t_end = 0.3
    w0 = 10.0
    decay = np.where(t < t_end, w0, w0 * np.exp(-(t - t_end) / i_over_b))
    c = paper.coast_decay(_sim(decay), t_end)
    assert c.passed and c.value == pytest.approx(0.0, abs=1e-9)
    after = t > t_end + 1e-9  # |w_end| stays w0; the excess is added from the next sample on
    c = paper.coast_decay(_sim(decay + 0.09 * w0 * after), t_end)  # inside the 10 % tolerance
    assert c.passed and c.value == pytest.approx(9.0, rel=1e-9)
    c = paper.coast_decay(_sim(decay + 0.11 * w0 * after), t_end)
    assert not c.passed and c.value == pytest.approx(11.0, rel=1e-9)
    # a joint that keeps its speed: the excess at the last sample, by hand
    c = paper.coast_decay(_sim(np.full(1000, -w0)), t_end)
    t_last = t[-1] - t[t >= t_end - 1e-12][0]
    assert not c.passed and c.value == pytest.approx(100 * (1 - np.exp(-t_last / i_over_b)), rel=1e-9)
    assert c.reason.startswith("runaway: ")
    # at rest when the pulse ends, then moving by itself: unbounded
    w = np.zeros(1000)
    w[600:] = 0.5
    c = paper.coast_decay(_sim(w), t_end)
    assert not c.passed and math.isinf(c.value) and c.as_dict()["value"] is None


def test_coast_test_of_both_pipelines(figs, ffigs, network, fnetwork):
    fc, pc = ffigs[9].coast, figs[9].coast
    assert fc is paper.coast.run(fnetwork)  # one experiment per network, shared by the figures
    assert fc is ffigs[14].coast and pc is figs[12].coast
    # the pulse: 2*Fs for 0.3 s, acting on the joint until one sample after its last command
    assert fc.pulse_torque == pytest.approx(2 * P.static) and fc.t_end == pytest.approx(0.302)
    # the fricctl compensation leaves the linear viscous actuator: after the pulse the joint decays
    # within the tolerance; the paper pipeline's (full friction, g > 1) keeps it running
    assert fc.passed and fc.decay.value < 10
    assert not pc.passed and abs(pc.run.omega[-1]) > 0.5 * abs(pc.omega_end)
    # reference for the pulse phase: the linear viscous actuator reaches w = (2*Fs/b)*(1 - exp(-t*b/I))
    # up to the sampled loop's one-sample delay; the fricctl joint (its b_hat ~ b) is within 10 % of it
    tau = P.inertia / P.viscous
    w_lin = 2 * P.static / P.viscous * (1 - np.exp(-(fc.t_end - P.sample_time) / tau))
    assert abs(fc.linear.omega[fc.run.t == fc.t_end][0] - w_lin) < 0.02 * w_lin
    assert abs(fc.omega_end - w_lin) < 0.1 * w_lin


def test_gate_names_the_coast_test_without_its_pulse_text():
    # issue 25: a step claim's note read "after the pulse the joint does not coast down": the
    # coast test is another experiment; its claim (coast-decay) describes it, the others name it
    coast = paper.RunawayCheck(name="coast", value=67.0, unit="%", limit=10.0, passed=False,
                               reason="runaway: after the pulse the joint does not coast down")
    step_claim = paper.gate(_claim("fig14-accuracy"), (_check(True), coast))
    assert not step_claim.passed and step_claim.runaway
    assert step_claim.note == ("runaway: the network fails its coast test (claim coast-decay), which "
                               "every claim measured with compensation requires. Its own criterion "
                               "was met.")
    own = paper.gate(_claim("coast-decay", passed=False, note="keeps going"), (coast,))
    assert own.note == "runaway: after the pulse the joint does not coast down. Keeps going"
    # several runs failing the same check (Fig. 14's steps): one sentence, with the count
    steps = paper.gate(_claim("fig14-steps"), (_check(False, "wind-up: a"), _check(False, "wind-up: b"),
                                               _check(False, "wind-up: c")))
    assert steps.note.startswith("runaway: wind-up: a (and in 2 more of its runs). Its own")


def test_claims_markdown_reads_as_text():
    # issue 25: summary first, no escaped bars, verdicts in words
    per_seed = {("paper", s): [_claim("a", passed=s > 0, value=1.0),
                               paper.Claim(id="n", claim="fit 100*(1 - ||e||/||y||) with |w| <= 1",
                                           paper="98 %", measured="|e_ss| 0.5 deg", passed=False,
                                           figure="Fig. 8", value=0.5, unit="deg",
                                           note="|e_ss| too large")]
                for s in range(2)}
    md = paper.claims_markdown(paper.aggregate_claims(per_seed, {"paper": 0}))
    lines = md.splitlines()
    assert lines[2].startswith("- **paper pipeline: 0 of 2 claims of the paper reproduced**")
    assert "\\|" not in md
    # a product is a middle dot, not an emphasis marker (issue 24: 'N*m ... b*w' in italics)
    assert "| fit 100·(1 - ‖e‖/‖y‖) with abs(w) <= 1 |" in md and "| abs(e_ss) 0.5 deg |" in md
    # the summary table first: one row per claim, the verdict in words, seeds met
    glance = md.index("## At a glance")
    assert glance < md.index("## The claims in full") < md.index("| id | claim | paper |")
    assert "| a | Fig. 9 | **not reproduced**, 1 of 2 |" in md
    assert "| n | Fig. 8 | **not reproduced**, 0 of 2 |" in md
    assert "**not reproduced**: met in 1 of 2 seeds; median 1 [1, 1] deg" in md
    assert "| n | abs(e_ss) 0.5 deg | **not met** |" in md
    assert "- **n** (Fig. 8; met in 0 of 2 seeds; median 0.5 deg): (seed 0) |e_ss| too large" in md


def test_benches_glance_puts_each_bench_and_pipeline_in_a_column():
    # issue 22: the book's summary table, from each bench's claims.json (claims_json's objects)
    def stats(passed_a):
        per_seed = {(p, s): [_claim("a", passed=passed_a[p][s], value=1.0),
                             _claim("b", passed=True, value=0.0, paper_value=paper.EXTRA)]
                    for p in ("paper", "fricctl") for s in range(3)}
        return paper.aggregate_claims(per_seed, {"paper": 0, "fricctl": 0})

    consistent = json.loads(paper.claims_json(stats({"paper": [True] * 3, "fricctl": [True] * 3}),
                                              bench="consistent"))
    literal = json.loads(paper.claims_json(stats({"paper": [True, False, False],
                                                  "fricctl": [True, True, False]}), bench="literal"))
    md = paper.benches_glance({"consistent": consistent, "literal": literal})
    lines = md.splitlines()
    assert lines[0] == ("| claim | figure | consistent bench, paper pipeline | consistent bench, fricctl "
                        "pipeline | literal bench, paper pipeline | literal bench, fricctl pipeline |")
    # by hand: literal paper 1 of 3, fricctl 2 of 3 -- neither reaches 90 %
    assert lines[2] == ("| a | Fig. 9 | reproduced, 3 of 3 | reproduced, 3 of 3 | **not reproduced**, "
                        "1 of 3 | **not reproduced**, 2 of 3 |")
    assert lines[3].startswith("| b (extra) | Fig. 9 | reproduced, 3 of 3 |")
    assert lines[-1] == ("| **claims of the paper reproduced** | | **1 of 1** (extras: 1 of 1) | **1 of 1** "
                         "(extras: 1 of 1) | **0 of 1** (extras: 1 of 1) | **0 of 1** (extras: 1 of 1) |")
    # a claim a column did not rate reads --
    md = paper.benches_glance({"consistent": consistent, "literal": literal[:2]})
    assert md.splitlines()[3].endswith("| -- | -- |")
    with pytest.raises(ValueError, match="measured on bench 'consistent'"):
        paper.benches_glance({"literal": consistent})
    with pytest.raises(ValueError, match="without 'bench'"):
        paper.benches_glance({"consistent": json.loads(paper.claims_json(stats({"paper": [True] * 3,
                                                                                "fricctl": [True] * 3})))})
    with pytest.raises(ValueError, match="empty"):
        paper.benches_glance({"consistent": []})


def test_aggregation_against_a_hand_computation():
    # fake per-seed claims: pipeline "paper" seeds 0-3, pipeline "fricctl" seeds 0-9
    vals = [1.0, 2.0, 3.0, 10.0]
    per_seed = {("paper", s): [_claim("a", passed=s != 2, value=vals[s]),
                               _claim("b", passed=False, value=math.inf if s == 1 else 0.0,
                                      paper_value=paper.EXTRA)] for s in range(4)}
    per_seed.update({("fricctl", s): [_claim("a", passed=s != 7, value=float(s)),
                                      _claim("b", passed=True, value=math.nan, paper_value=paper.EXTRA)]
                     for s in range(10)})
    stats = paper.aggregate_claims(per_seed, {"paper": 1, "fricctl": 0})
    assert [(s.id, s.pipeline) for s in stats] == [("a", "paper"), ("a", "fricctl"), ("b", "paper"),
                                                   ("b", "fricctl")]
    a, fa, b, fb = stats
    # by hand: 3 of 4 pass; median of 1, 2, 3, 10 is 2.5
    assert (a.n_seeds, a.n_passed, a.pass_rate) == (4, 3, 0.75) and not a.holds
    assert (a.median, a.minimum, a.maximum) == (2.5, 1.0, 10.0)
    assert a.shown is per_seed[("paper", 1)][0]  # the representative seed's claim
    # 9 of 10 is exactly the 90 % a claim needs to hold; median of 0..9 is 4.5
    assert fa.pass_rate == 0.9 and fa.holds and (fa.median, fa.minimum, fa.maximum) == (4.5, 0.0, 9.0)
    assert fa.note.startswith("(seed 7)")
    # an unbounded value: the median stays defined (0, inf, 0, 0 -> 0), the max is null with a reason
    d = b.as_dict()
    assert d["measured_median"] == 0.0 and d["measured_max"] is None
    assert d["undefined"] == {"measured_max": "unbounded (+inf) in seed(s) 1"}
    assert [x["value"] for x in d["seeds"]] == [0.0, None, 0.0, 0.0]
    # undefined in every seed: all three statistics null, each with its reason
    d = fb.as_dict()
    assert d["measured_median"] is None and set(d["undefined"]) == {"measured_median", "measured_min",
                                                                     "measured_max"}
    # the JSON is strict (allow_nan=False) and has the keys
    data = json.loads(paper.claims_json(stats))
    keys = {"id", "claim", "paper", "measured", "passed", "figure", "note", "pipeline", "n_seeds",
            "pass_rate", "measured_median", "measured_min", "measured_max"}
    assert all(keys <= set(o) for o in data)
    assert [o["passed"] for o in data] == [False, True, False, True]
    md = paper.claims_markdown(stats, why=["a reason with a number: 0.6 deg"])
    assert "| id | claim | paper | paper pipeline | fricctl pipeline | figure |" in md
    assert ("- **paper pipeline: 0 of 1 claims of the paper reproduced** (each met in at least 90 % of "
            "the 4 training seeds); our extra checks, not in the paper: 0 of 1; figures from seed 1."
            in md)
    assert "reproduced: met in 9 of 10 seeds; median 4.5 [0, 9] deg" in md
    assert "- a reason with a number: 0.6 deg" in md
    with pytest.raises(ValueError, match="claims"):
        paper.aggregate_claims({("paper", 0): [_claim("a")], ("paper", 1): [_claim("c")]}, {"paper": 0})


def test_representative_seed():
    # by hand: counts 14, 17, 15, 15, 12 -> median 15; seeds 2 and 3 tie, the lowest wins
    assert paper.representative_seed({0: 14, 1: 17, 2: 15, 3: 15, 4: 12}) == 2
    # an even number of seeds: median 14.5, seeds 0 (14) and 2 (15) equally close -> 0
    assert paper.representative_seed({0: 14, 1: 17, 2: 15, 3: 12}) == 0


def test_claim_rejects_non_str():
    with pytest.raises(ValueError, match="Claim.measured"):
        paper.Claim(id="x", claim="c", paper="p", measured=1.0, passed=True, figure="Fig. 1", value=1.0,
                    unit="-")
    with pytest.raises(ValueError, match="Claim.value"):
        paper.Claim(id="x", claim="c", paper="p", measured="m", passed=True, figure="Fig. 1", value="1",
                    unit="-")


# -- robustness sweep ----------------------------------------------------------------
def test_sweep_executor_matches_serial_and_single_runs(network):
    kw = dict(friction_scales=(0.8, 1.2), link_inertias=(0.0, 0.0046), duration=2.0)
    serial = paper.robustness_sweep(network.net, P, **kw)
    with ThreadPoolExecutor(max_workers=2) as ex:
        threaded = paper.robustness_sweep(network.net, P, executor=ex, **kw)
    np.testing.assert_array_equal(serial.error_nn, threaded.error_nn)
    # reference: one cell re-run with the single-run simulator
    pl = P.replace(link_inertia=0.0046)
    r = simulate(pl, ctl.pd_control(serial.kp, serial.kd, ctl.step(serial.step)), NNCompensator(network.net),
                 duration=2.0, friction=pl.friction_model().scaled(1.2))
    assert serial.error_nn[1, 1] == pytest.approx(abs(r.steady_state_error()), abs=1e-9)
    # settled: the single run at rest over the whole last 0.5 s, by hand
    assert serial.settled_nn[1, 1] == bool(np.all(r.stuck[r.t >= r.t[-1] - 0.5 + 1e-12]))
    np.testing.assert_array_equal(serial.settled_nn, threaded.settled_nn)
    marks = serial.report().count("~")
    assert marks == 1 + int(np.count_nonzero(~serial.settled_nn))  # the legend's "~" and one per cell
    # physics: without compensation every run sticks inside its band scale*Fs/Kp
    bands = np.asarray(kw["friction_scales"]) * P.static / serial.kp
    assert np.all(serial.error_none <= bands[None, :] + RES)
    assert serial.within.shape == (2, 2)
    assert "met in" in serial.report()


@pytest.mark.parametrize("bad, match", [
    (dict(friction_scales=(0.0, 1.0)), "friction_scales"),
    (dict(link_inertias=(-1.0,)), "link_inertias"),
    (dict(step=float("nan")), "step"),
    (dict(executor=object()), "executor"),
])
def test_sweep_rejects_bad_input(network, bad, match):
    with pytest.raises(ValueError, match=match):
        paper.robustness_sweep(network.net, P, **bad)


def test_bad_inputs():
    with pytest.raises(ValueError, match="seed"):
        paper.train_paper_network(P, fast=True, seed=-1)
    with pytest.raises(ValueError, match="PaperNetwork"):
        paper.fig09.run(object())
    with pytest.raises(ValueError, match="FrictionNet"):
        paper.robustness_sweep("net")


# -- figures -------------------------------------------------------------------------
@pytest.mark.parametrize("num", sorted(fp.PAPER_PLOTS))
def test_plots(figs, num):
    out = fp.PAPER_PLOTS[num](figs[num])
    fig = getattr(out, "figure", out)
    axes = fig.axes
    lines = sum(len(a.get_lines()) for a in axes)
    assert lines >= 1
    for a in axes:
        if a.get_label() == "<colorbar>":
            continue
        assert "[" in a.get_xlabel() and "[" in a.get_ylabel(), (num, a.get_xlabel(), a.get_ylabel())
    plt.close(fig)


def test_plot_fig12_lines(figs):
    ax = fp.plot_fig12(figs[12])
    labels = [ln.get_label() for ln in ax.get_lines()]
    assert "linear viscous simulation" in labels and ax.get_lines()[0].get_linestyle() == "--"
    assert len(ax.get_lines()) == 6  # linear, reference, NN, NN - b*omega, ideal, ideal - b*omega
    np.testing.assert_allclose(ax.get_lines()[-1].get_ydata(), np.rad2deg(figs[12].ideal_no_viscous.q))


def test_plot_fig12_legend_covers_no_data(figs, ffigs, points_under_legend):
    """Issue 24 item 7: the six lines oscillate over the whole plot; the legend sits beside it."""
    for result in (figs[12], ffigs[12]):
        ax = fp.plot_fig12(result)
        assert len(ax.get_legend().get_texts()) == 6
        assert points_under_legend(ax) == 0


def test_plot_sweep_and_rejects(network):
    s = paper.robustness_sweep(network.net, P, friction_scales=(1.0,), link_inertias=(0.0,), duration=1.0)
    ax = fp.plot_sweep(s)
    assert "[deg]" in ax.figure.axes[-1].get_ylabel()
    with pytest.raises(ValueError, match="Fig9Result"):
        fp.plot_fig9(s)


# -- the registries --------------------------------------------------------------------
def test_registry_is_built_from_the_figure_modules():
    # reference: the figNN files of the package folder, listed independently of the discovery
    folder = Path(paper.__file__).parent
    numbers = sorted(int(m.group(1)) for f in folder.glob("fig*.py")
                     if (m := re.fullmatch(r"fig(\d\d)\.py", f.name)))
    assert list(paper.paper_figures()) == numbers and list(paper.FIGURES) == numbers
    with pytest.raises(TypeError):
        paper.FIGURES[99] = None  # read-only: nobody edits the registry by accident


# Parametrised over the registry: a new figure module is tested here without an edit.
@pytest.mark.parametrize("n", list(paper.paper_figures()))
def test_each_figure_is_its_modules_entry(n):
    fig = paper.paper_figures()[n]
    module = importlib.import_module(f"fricctl.paper.fig{n:02d}")
    assert module.FIGURE is fig and fig.number == n and fig.run is module.run
    assert paper.FIGURES[n] is fig.run
    assert getattr(paper, f"fig{n:02d}") is module  # the package attribute is the module
    assert fig.title.strip() and "\n" not in fig.title
    assert fp.PAPER_PLOTS[n] is not None  # its plot is registered


@pytest.mark.parametrize("n", list(paper.paper_figures()))
def test_each_figure_runs_to_its_result_type_and_makes_its_claims(n, figs, ffigs):
    fig = paper.paper_figures()[n]
    for results in (figs, ffigs):
        assert type(results[n]) is fig.result_type
        made = fig.make_claims(results[n], P)
        assert len(made) == len(fig.claims) and all(isinstance(c, paper.Claim) for c in made)
        assert all(c.figure == f"Fig. {n}" for c in made)
        # unique ids (over the whole table: test_claims_of_one_network), the same for either
        # pipeline's network
        ids = [c.id for c in made]
        assert len(set(ids)) == len(ids) and ids == [c.id for c in fig.make_claims(figs[n], P)]
        # paper_claims of this figure alone is its makers' list
        assert [c.id for c in paper.paper_claims({n: results[n]}, P)] == ids


def test_results_are_frozen_and_keyword_only():
    types = [fig.result_type for fig in paper.paper_figures().values()]
    types += [paper.SweepResult, paper.PaperResults, paper.PaperNetwork, paper.Claim, paper.ClaimStats,
              paper.SeedRun, paper.RunawayCheck, paper.coast.CoastResult]
    for cls in types:
        assert is_dataclass(cls) and cls.__dataclass_params__.frozen, cls
        assert all(f.kw_only for f in fields(cls)), cls


def test_assumptions_are_in_the_package_docstring():
    # the claims table points readers at fricctl.paper's docstring for the assumptions
    doc = " ".join(paper.__doc__.split())
    found = [a for fig in paper.paper_figures().values() for a in fig.assumptions]
    assert len(found) >= 6
    for a in found:
        assert " ".join(a.split()) in doc, a


def test_claims_come_from_the_registry(figs, claims):
    # every claim names the figure whose maker made it, in figure order
    order = []
    for n, fig in paper.paper_figures().items():
        made = fig.make_claims(figs[n], P)
        assert all(c.figure == f"Fig. {n}" for c in made)
        order += [c.id for c in made]
    assert order == list(claims) and len(set(order)) == len(order)
    # a figure result missing from the input is skipped (each figure alone:
    # test_each_figure_runs_to_its_result_type_and_makes_its_claims); a wrong result type is refused
    first, last = list(paper.paper_figures())[0], list(paper.paper_figures())[-1]
    assert [c.id for c in paper.paper_claims({first: figs[first], last: figs[last]}, P)] == [
        c.id for n in (first, last) for c in paper.paper_figures()[n].make_claims(figs[n], P)]
    with pytest.raises(ValueError, match="Fig9Result"):
        paper.paper_claims({9: figs[10]}, P)


def test_paper_figure_rejects_bad_entries():
    with pytest.raises(ValueError, match="run"):
        paper.PaperFigure(number=3, title="x", run=None, result_type=paper.fig09.Fig9Result)
    with pytest.raises(ValueError, match="claims"):
        paper.PaperFigure(number=3, title="x", run=paper.fig09.run, result_type=paper.fig09.Fig9Result, claims=[])
    with pytest.raises(ValueError, match="title"):
        paper.PaperFigure(number=3, title=" ", run=paper.fig09.run, result_type=paper.fig09.Fig9Result)


def test_every_figure_has_one_plot():
    assert list(fp.PAPER_PLOTS) == list(paper.paper_figures())
    with pytest.raises(ValueError, match="not registered"):
        fp.paper_plot(3)
    with pytest.raises(ValueError, match="already has a plot"):
        fp.paper_plot(9)(lambda result, ax=None: ax)
    assert fp.PAPER_PLOTS[9] is fp.plot_fig9


def test_figures_package_reexports_every_submodule():
    import fricctl.figures as figures

    # reference: every public module file of the package folder, listed independently
    folder = Path(figures.__file__).parent
    names = []
    for f in sorted(folder.glob("*.py")):
        if not f.name.startswith("_"):
            names += importlib.import_module(f"fricctl.figures.{f.stem}").__all__
    assert sorted(figures.__all__) == sorted(names) and len(set(names)) == len(names)
    assert all(getattr(figures, n) is not None for n in names)


# -- reproduce over seeds -----------------------------------------------------------------
def test_reproduce_paper_one_seed(fclaims):
    res = paper.reproduce_paper(P, fast=True, seeds=1, pipelines=("fricctl",))
    assert res.seeds == (0,) and res.pipelines == ("fricctl",) and res.representative["fricctl"] == 0
    run = res.runs[("fricctl", 0)]
    # the job's claims are those of the module's network (same pipeline, seed, fast: deterministic)
    assert [(c.id, c.passed, c.value) for c in run.claims] == [(c.id, c.passed, c.value)
                                                               for c in fclaims.values()]
    assert run.net.gain_at_rest() == pytest.approx(run.gain_at_rest, rel=1e-12)
    assert run.certificate["passed"] is True
    assert [s.n_seeds for s in res.stats] == [1] * N_CLAIMS
    assert res.summary().startswith("fricctl: ")
    md = res.markdown()
    assert "figures from seed 0" in md and "Fs*(1 - g)/Kp" in md and "paper_consistency.md" in md
    # the g that a 0.3 deg band needs at s = 0.95, by hand: 0.95*Fs*(1 - 0.95*g)/Kp = 0.3 deg
    kp = designs(P)["fig16-17"].kp
    g_aged = (1 - np.deg2rad(0.3) * kp / (0.95 * P.static)) / 0.95
    assert g_aged > 1 and f"g >= {g_aged:.3f}, above 1" in md and "no certificate of g" in md
    json.loads(res.json())
    with pytest.raises(ValueError, match="pipelines"):
        paper.reproduce_paper(P, fast=True, seeds=1, pipelines=("paper", "paper"))
    with pytest.raises(ValueError, match="seeds"):
        paper.reproduce_paper(P, fast=True, seeds=0)


@pytest.mark.slow
def test_fricctl_pipeline_targets_over_20_seeds():
    # The targets for the fricctl pipeline, measured over 20 seeds in full mode: certified
    # g < 1 and no runaway in 20/20; Fig. 9 within 10 % of the linear viscous actuator; Fig. 14 and
    # the eight PD steps < 0.3 deg in >= 90 % of the seeds.
    with ProcessPoolExecutor(max_workers=2, mp_context=multiprocessing.get_context("spawn")) as ex:
        res = paper.reproduce_paper(P, seeds=20, pipelines=("fricctl",), executor=ex)
    runs = [res.runs[("fricctl", s)] for s in res.seeds]
    assert all(r.certificate["passed"] and r.gain_at_rest < 1 for r in runs)
    stats = {s.id: s for s in res.stats}
    assert all(s.runaway_failures == 0 for s in stats.values()), \
        {k: s.runaway_failures for k, s in stats.items() if s.runaway_failures}
    assert stats["coast-decay"].pass_rate == 1.0
    assert stats["fig9-linear"].pass_rate == 1.0
    assert stats["fig14-accuracy"].pass_rate >= 0.9
    assert stats["fig14-steps"].pass_rate >= 0.9
