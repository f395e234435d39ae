"""Tests for fricctl.paper.consistency: each predicate against a hand calculation or an
independent simulation, the conflict proof and the proposed set, with their numbers."""

import math

import control
import numpy as np
import pytest

from fricctl import controllers as ctl
from fricctl.design import LinearLoop, normalized_rise_time
from fricctl.friction import Viscous
from fricctl.paper import consistency as cs
from fricctl.paper.common import restarts
from fricctl.params import derive_inertia_from_p_design, paper_actuator
from fricctl.simulate import simulate

B, FS, LINK = 0.0169, 0.18, 0.0046          # paper values
R25, R30 = math.radians(25.0), math.radians(30.0)
PEAK = math.pi / math.sqrt(1.0 - 0.09)       # wn * t_peak at zeta = 0.3, by hand


@pytest.fixture(scope="module")
def named():
    """The report's named candidate sets, evaluated once (~6 s: three readings' designs)."""
    return dict(zip(cs.NAMED, cs.evaluate(cs.NAMED.values())))


# --------------------------------------------------------------------------- readings, inertia
@pytest.mark.parametrize("zeta", [0.3, 0.5, 0.85])
def test_peak_reading_is_the_time_of_the_first_peak(zeta):
    # independent: the first maximum of python-control's step response at wn = 1, grid 1e-4
    t = np.arange(0.0, 10.0, 1e-4)
    y = np.asarray(control.step_response(control.tf([1.0], [1.0, 2 * zeta, 1.0]), t).outputs)
    assert cs.normalized_time(zeta, "peak") == pytest.approx(t[np.argmax(y)], abs=2e-4)
    assert cs.normalized_time(zeta, "0-100") == normalized_rise_time(zeta, "0-100")


def test_inertia_derived_from_the_p_design():
    # 0-100: the params module's own derivation (an independent implementation)
    assert cs.Unknowns().actuator_inertia == pytest.approx(derive_inertia_from_p_design(), rel=1e-12)
    # peak: I = b tr / (2 zeta c) by hand = 0.0169 * 0.2 / (0.6 * 3.29328) = 1.7106e-3
    assert cs.Unknowns(rise_time_reading="peak").actuator_inertia == pytest.approx(
        B * 0.2 / (0.6 * PEAK), rel=1e-12)
    assert cs.Unknowns(rise_time_reading="peak").actuator_inertia == pytest.approx(1.7106e-3, rel=1e-4)


def test_reading_designs_meet_the_specs_under_the_peak_reading():
    i = cs.Unknowns(rise_time_reading="peak").actuator_inertia
    d = cs.reading_designs("peak", i)
    # P: Kp = b^2 / (4 I zeta^2) by hand; its first peak at 0.2 s (python-control, grid 1e-5 s)
    assert d["fig11-12"].kp == pytest.approx(B * B / (4 * i * 0.09), rel=1e-9)
    for key, t_peak in (("fig11-12", 0.2), ("fig18", 0.22), ("fig16-17", 0.4)):
        t = np.arange(0.0, 3 * t_peak, 1e-5)
        y = np.asarray(control.step_response(d[key].closed_loop, t).outputs)
        assert t[np.argmax(y)] == pytest.approx(t_peak, abs=2e-5), key
    assert d["fig18"].zeta == pytest.approx(0.5, rel=1e-9)
    assert d["fig18"].inertia == pytest.approx(i + LINK, rel=1e-12)


# --------------------------------------------------------------------------- closed forms
def test_fig11_breakaway_torque_by_hand(named):
    # Kp r = b c(0.3) r / (2 zeta tr): 0.121 N*m under 0-100 (issue 11's number), 0.202 under peak
    hand = {r: B * cs.normalized_time(0.3, r) * R25 / (2 * 0.3 * 0.2) for r in ("0-100", "peak")}
    assert named["today"].check("fig11-moves").value == pytest.approx(hand["0-100"], rel=1e-6)
    assert hand["0-100"] == pytest.approx(0.1208, abs=1e-4)
    assert not named["today"].check("fig11-moves").satisfied
    assert named["proposed"].check("fig11-moves").value == pytest.approx(hand["peak"], rel=1e-6)
    assert hand["peak"] == pytest.approx(0.2024, abs=1e-4)
    assert named["proposed"].check("fig11-moves").satisfied


def test_fig17_and_fig18_breakaway_torques_by_hand(named):
    i0 = derive_inertia_from_p_design()
    w17, w18 = normalized_rise_time(0.85, "0-100") / 0.4, normalized_rise_time(0.5, "0-100") / 0.22
    # today: Kp*0.08 = 0.090 N*m (Fig. 17, no motion, holds) and Kp*0.1 = 0.090 N*m (Fig. 18)
    assert named["today"].check("fig17-no-motion").value == pytest.approx((i0 + LINK) * w17**2 * 0.08,
                                                                           rel=1e-6)
    assert named["today"].check("fig18-moves").value == pytest.approx((i0 + LINK) * w18**2 * 0.1, rel=1e-6)
    assert named["today"].check("fig18-moves").value == pytest.approx(0.0902, abs=1e-4)
    # peak reading: Kp18 * 0.1 = 0.172 < Fs but Kp18 * 0.2 = 0.343 > Fs
    ip = cs.Unknowns(rise_time_reading="peak").actuator_inertia
    kp18 = (ip + LINK) * (math.pi / math.sqrt(0.75) / 0.22) ** 2
    assert named["peak, 0 to 0.1 rad"].check("fig18-moves").value == pytest.approx(kp18 * 0.1, rel=1e-6)
    assert not named["peak, 0 to 0.1 rad"].check("fig18-moves").satisfied
    assert named["proposed"].check("fig18-moves").value == pytest.approx(kp18 * 0.2, rel=1e-6)


def test_max_torque_by_hand(named):
    # today the largest compensated start is Fig. 14: Kp13 * 30 deg + Fs, Kp13 = I wn^2
    kp13 = derive_inertia_from_p_design() * (normalized_rise_time(0.9, "0-100") / 0.3) ** 2
    assert named["today"].check("max-torque").value == pytest.approx(kp13 * R30 + FS, rel=1e-6)
    assert named["today"].check("max-torque").value < FS / 0.127


# --------------------------------------------------------------------------- simulations
def test_fig11_sticks_against_an_independent_run(named):
    u = cs.PROPOSED
    kp = cs.reading_designs(u.rise_time_reading, u.actuator_inertia)["fig11-12"].kp
    r = simulate(u.actuator(), ctl.p_control(kp, ctl.step(R25)), duration=3.0)
    chk = named["proposed"].check("fig11-sticks")
    assert chk.satisfied
    rest = np.flatnonzero(~r.stuck)[-1] + 1          # first sample of the final rest
    assert chk.value == pytest.approx(r.t[rest], abs=1e-12)
    assert r.stuck[rest:].all() and r.q[-1] > 0.0
    # the fixed point of a stuck P loop: |Kp (r - q)| <= Fs (hand physics)
    assert abs(kp * (R25 - r.q[-1])) <= FS
    # today: Kp r < Fs, the joint never moves at all
    kp0 = cs.reading_designs("0-100", cs.TODAY.actuator_inertia)["fig11-12"].kp
    r0 = simulate(cs.TODAY.actuator(), ctl.p_control(kp0, ctl.step(R25)), duration=1.0)
    assert np.all(r0.q == 0.0) and not named["today"].check("fig11-sticks").satisfied


def test_fig17_no_motion_in_an_independent_run(named):
    for name in ("today", "proposed"):
        u = cs.NAMED[name]
        d = cs.reading_designs(u.rise_time_reading, u.actuator_inertia)["fig16-17"]
        r = simulate(u.actuator().with_link(), ctl.pd_control(d.kp, d.kd, ctl.step(0.08)), duration=1.0)
        assert np.all(r.q == 0.0) and named[name].check("fig17-no-motion").satisfied


def test_fig18_stick_slip_against_independent_runs(named):
    def run(u):
        d = cs.reading_designs(u.rise_time_reading, u.actuator_inertia)["fig18"]
        per = u.sawtooth_period
        return d, per, simulate(u.actuator().with_link(), ctl.pd_control(
            d.kp, d.kd, ctl.sawtooth(u.sawtooth_span, per)), duration=3 * per)

    d, per, r = run(cs.PROPOSED)
    chk = named["proposed"].check("fig18-stick-slip")
    assert chk.satisfied and chk.value == restarts(r) >= 2
    for j in range(3):                                # motion in every period
        m = (r.t >= j * per) & (r.t < (j + 1) * per)
        assert np.ptp(r.q[m]) > 1e-3
    # Fc/Fs 0.8, 1 s: the joint parks after the first ramp where no reference value can move it:
    # Kp*q < Fs (reset to 0) and Kp*(0.2 - q) < Fs (top of the ramp), by hand
    d, per, r = run(cs.NAMED["peak, +-0.1 rad"])
    q = r.q[-1]
    assert np.ptp(r.q[r.t >= 2 * per]) == 0.0
    assert d.kp * q < FS and d.kp * (0.2 - q) < FS
    assert not named["peak, +-0.1 rad"].check("fig18-stick-slip").satisfied


def test_log_decrement_recovers_a_known_decay():
    t = np.arange(0.0, 2.0, 1e-4)
    sigma, wd, inertia = 4.0, 15.0, 2e-3
    e = 0.3 * np.exp(-sigma * t) * np.cos(wd * t)
    # the extrema of e^{-st} cos(wd t) are spaced pi/wd apart and shrink by e^{-s pi/wd}
    assert cs.log_decrement_viscous(t, e, inertia) == pytest.approx(2 * inertia * sigma, rel=1e-3)
    assert math.isnan(cs.log_decrement_viscous(t, np.exp(-t), inertia))


def test_viscous_identified_on_a_linear_bench_matches_the_sampled_loop():
    # bench with viscous friction only, no compensation: the decay is the sampled linear loop's
    # (the plant's RK4 kernel vs python-control's ZOH discretisation), within 1 %
    u = cs.PROPOSED
    i = u.actuator_inertia
    kp = cs.reading_designs(u.rise_time_reading, i)["fig11-12"].kp
    r = simulate(paper_actuator(inertia=i), ctl.p_control(kp, ctl.step(R25)), duration=1.5,
                 friction=Viscous(B), quantize=False)
    z = np.linalg.eigvals(LinearLoop(kp=kp, inertia=i, viscous=B, sample_time=0.002).sampled().A)
    sampled = -2 * i * math.log(np.abs(z).max()) / 0.002
    assert cs.log_decrement_viscous(r.t, r.error, i) == pytest.approx(sampled, rel=0.01)


def test_viscous_identified_numbers(named):
    # the sampled P loop and the compensation's lag bias the decay low: 0.0149 (-12 %) from a true
    # 0.0169 under the peak design; a true 0.019 reads 0.0169 (measured here, 5e-4 margin)
    assert named["proposed, b 0.0169"].check("viscous-identified").value == pytest.approx(0.0149, abs=5e-4)
    assert not named["proposed, b 0.0169"].check("viscous-identified").satisfied
    assert named["proposed"].check("viscous-identified").value == pytest.approx(0.0169, abs=5e-4)
    assert named["today"].check("viscous-identified").satisfied


# --------------------------------------------------------------------------- proof and proposal
def test_inertia_windows_by_hand_and_the_conflict_proof():
    w = {(x.reading, x.span): x for x in cs.inertia_windows()}
    upper11 = B * B * R25 / (4 * 0.09 * FS)           # Fig. 11 moves with zeta 0.3: I < 1.923e-3
    lower18 = {r: FS / (0.1 * (cs.normalized_time(0.5, r) / 0.22) ** 2) - LINK for r in ("0-100", "peak")}
    assert w[("peak", 0.2)].upper == pytest.approx(upper11, rel=1e-12)
    assert upper11 == pytest.approx(1.9232e-3, rel=1e-4)
    assert w[("0-100", 0.1)].lower == pytest.approx(lower18["0-100"], rel=1e-12)
    assert w[("peak", 0.1)].lower == pytest.approx(lower18["peak"], rel=1e-12)
    assert lower18["peak"] == pytest.approx(2.020e-3, rel=1e-3)
    # the proof: under 0-100 and 10-90 no inertia satisfies Figs. 11 and 18 together; under peak
    # only the +-0.1 rad reading leaves a window, and it holds the P design's exact inertia
    assert all(x.empty for x in w.values() if x.reading != "peak" or x.span == 0.1)
    assert w[("peak", 0.2)].allowed_low < cs.PROPOSED.actuator_inertia < w[("peak", 0.2)].allowed_high
    # even 10 % slack on both P specs leaves Fig. 11 below breakaway under 0-100 and 10-90: the
    # largest Kp r = b c(zeta) r / (2 zeta tr) is at the corner tr = 0.18 s, zeta = 0.27 (c/zeta
    # falls with zeta), by hand with the 0-100 closed form c = (pi - acos z) / sqrt(1 - z^2)
    c27 = (math.pi - math.acos(0.27)) / math.sqrt(1 - 0.27**2)
    corner = B * c27 * R25 / (2 * 0.27 * 0.18)
    assert cs.max_p_step_torque("0-100") == pytest.approx(corner, rel=1e-9)
    assert corner == pytest.approx(0.1453, abs=1e-4)
    assert corner < FS and cs.max_p_step_torque("10-90") < FS
    assert cs.max_p_step_torque("peak", 0.0) == pytest.approx(B * PEAK * R25 / 0.12, rel=1e-9)


def test_window_bound_flips_the_closed_form_check():
    # the Fig. 18 bound of the peak reading, 0.1 rad: just above it the joint breaks loose
    bound = [x for x in cs.inertia_windows(("peak",), (0.1,))][0].lower
    res = cs.evaluate([cs.Unknowns(rise_time_reading="peak", inertia=bound * f) for f in (0.999, 1.001)])
    assert [r.check("fig18-moves").satisfied for r in res] == [False, True]


def test_named_sets_conflicts_and_the_proposal(named):
    conflicts = {k: {c.key for c in r.conflicts} for k, r in named.items()}
    assert conflicts["today"] == {"fig11-moves", "fig11-sticks", "fig18-moves", "fig18-stick-slip"}
    assert conflicts["peak, 0 to 0.1 rad"] == {"fig18-moves", "fig18-stick-slip", "viscous-identified"}
    assert conflicts["proposed, b 0.0169"] == {"viscous-identified"}
    assert named["proposed"].consistent


def test_search_batches_like_single_evaluations_and_reports():
    grid = {"rise_time_reading": ("peak",), "sawtooth_span": (0.2,), "coulomb_ratio": (0.6, 0.8),
            "sawtooth_period": (2.0,), "viscous": (0.019,)}
    res = cs.search(grid, named={"proposed": cs.PROPOSED})
    assert len(res.grid) == 2 and res.named_result("proposed").consistent
    single = cs.evaluate([res.grid[1].unknowns])[0]
    assert single.checks == res.grid[1].checks
    text = res.report()
    assert "| statement | requires | proposed |" in text and "**consistent**" in text
    assert text.count("\n| ") >= len(cs.STATEMENTS) + 2
    with pytest.raises(ValueError, match="name"):
        res.named_result("nope")


@pytest.mark.parametrize("kw", [{"rise_time_reading": "5-95"}, {"coulomb_ratio": 1.5},
                                {"encoder_counts": 0}, {"sawtooth_span": -0.1}, {"inertia": 0.0}])
def test_unknowns_refuse_bad_values(kw):
    with pytest.raises(ValueError):
        cs.Unknowns(**kw)
