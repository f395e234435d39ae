"""Tests for fricctl.design (P/PD gain design on the linear viscous model)."""

import dataclasses
import json
import math
import warnings

import control
import numpy as np
import pytest
from scipy.linalg import expm

from fricctl.design import (
    Design,
    DesignWarning,
    LinearLoop,
    design_p,
    design_pd,
    design_table,
    linear_response,
    normalized_rise_time,
    paper_designs,
    plant_tf,
    sampled_loop,
    step_metrics,
)
from fricctl.design.second_order import dominant_damping
from fricctl.params import PAPER_LINK_INERTIA, paper_actuator

P0 = paper_actuator()
PL = P0.with_link()


def quiet(fn, *args, **kw):
    """Call fn ignoring DesignWarning (tests that look at other things)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DesignWarning)
        return fn(*args, **kw)


def ogata_wn(tr, zeta):
    """0-100 % rise time closed form (Ogata): wn = (pi - acos zeta)/(tr sqrt(1-zeta^2))."""
    return (math.pi - math.acos(zeta)) / (tr * math.sqrt(1.0 - zeta**2))


def reference_loop(kp, kd, inertia, viscous, ts, r, q0=0.0, substeps=1):
    """The core loop's timing written out literally, plant stepped with scipy expm.

    Independent of python-control: at t_k read y_k, omega_hat_k = (y_k - y_{k-1})/Ts
    with y_{-1} = y_0, Tc_k = Kp (r_k - y_k) - Kd omega_hat_k, applied over
    [t_{k+1}, t_{k+2}); torque over [t_0, t_1) is 0.  Returns q on t_k + j*Ts/substeps.
    """
    a = np.array([[0.0, 1.0], [0.0, -viscous / inertia]])
    b = np.array([0.0, 1.0 / inertia])
    h = ts / substeps
    m = np.zeros((3, 3))
    m[:2, :2], m[:2, 2] = a * h, b * h
    e = expm(m)
    ad, bd = e[:2, :2], e[:2, 2]
    x = np.array([q0, 0.0])
    y_prev = q0
    tm = 0.0
    out = []
    for rk in r:
        y = x[0]
        omega_hat = (y - y_prev) / ts
        tc = kp * (rk - y) - kd * omega_hat
        for _ in range(substeps):
            out.append(x[0])
            x = ad @ x + bd * tm
        tm, y_prev = tc, y
    return np.array(out)


# ---------------------------------------------------------------------------
# closed forms
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("params,tr,zeta", [(P0, 0.3, 0.9), (PL, 0.4, 0.85), (PL, 0.22, 0.5),
                                            (P0, 0.1, 0.7)])
def test_pd_gains_equal_closed_form(params, tr, zeta):
    d = quiet(design_pd, params, rise_time=tr, damping=zeta)
    wn = ogata_wn(tr, zeta)
    inertia = params.total_inertia
    # closed form Kp = I wn^2, Kd = 2 zeta wn I - b; only rounding differs (1e-12)
    assert d.kp == pytest.approx(inertia * wn**2, rel=1e-12)
    assert d.kd == pytest.approx(2 * zeta * wn * inertia - params.viscous, rel=1e-12)
    assert d.wn == pytest.approx(wn, rel=1e-12)
    assert d.zeta == pytest.approx(zeta, rel=1e-12)
    assert d.rise_time_definition == "0-100"
    # the closed loop is the no-zero second-order system Kp/(I s^2 + (b+Kd) s + Kp)
    num = np.asarray(d.closed_loop.num[0][0], float)
    den = np.asarray(d.closed_loop.den[0][0], float)
    np.testing.assert_allclose(num / den[0], [wn**2], rtol=1e-12)
    np.testing.assert_allclose(den / den[0], [1.0, 2 * zeta * wn, wn**2], rtol=1e-12)


def test_normalized_rise_time_reference_values():
    # 0-100 %: Ogata's closed form at zeta = 0.5: (pi - pi/3)/sqrt(0.75) (exact, 1e-12)
    assert normalized_rise_time(0.5, "0-100") == pytest.approx((2 * math.pi / 3) / math.sqrt(0.75),
                                                               rel=1e-12)
    # 10-90 % at zeta = 1: solve 1 - e^-t (1 + t) = 0.1 / 0.9 independently with numpy grid
    tau = np.linspace(0, 10, 2_000_001)
    y = 1 - np.exp(-tau) * (1 + tau)
    ref = tau[np.argmax(y >= 0.9)] - tau[np.argmax(y >= 0.1)]
    assert normalized_rise_time(1.0, "10-90") == pytest.approx(ref, abs=2e-5)  # grid step 5e-6
    # 10-90 % for zeta >> 1 tends to ln(9)/p_slow (first-order dominant pole); 1 % at zeta=10
    z = 10.0
    p_slow = z - math.sqrt(z * z - 1)
    assert normalized_rise_time(z, "10-90") == pytest.approx(math.log(9) / p_slow, rel=1e-2)


@pytest.mark.parametrize("zeta", [0.2, 0.5, 0.8, 1.0, 1.5, 3.0])
def test_normalized_rise_time_10_90_matches_step_info(zeta):
    # independent route: python-control step_info on wn = 1, grid step <= 4.5e-4 s
    # against rise times >= 1.0 s (rel 1e-3)
    sys = control.tf([1.0], [1.0, 2 * zeta, 1.0])
    t = np.linspace(0, 15 * max(zeta, 1), 100_001)
    info = control.step_info(sys, timepts=t, RiseTimeLimits=(0.1, 0.9))
    assert normalized_rise_time(zeta, "10-90") == pytest.approx(info["RiseTime"], rel=1e-3)


# ---------------------------------------------------------------------------
# verification with step_info
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("params,tr,zeta,definition", [
    (P0, 0.3, 0.9, None), (PL, 0.4, 0.85, None), (PL, 0.22, 0.5, None),
    (PL, 0.3, 0.5, "10-90"), (P0, 0.3, 1.0, "10-90"), (P0, 0.5, 1.6, "10-90"),
])
def test_pd_step_info_reproduces_specs_within_1_percent(params, tr, zeta, definition):
    d = quiet(design_pd, params, rise_time=tr, damping=zeta, rise_time_definition=definition)
    # requirement of issue 3: step_info on the designed loop within 1 %
    assert d.achieved.rise_time == pytest.approx(tr, rel=0.01)
    # re-measure independently of the stored metrics with control.step_info on the tf itself
    t = np.linspace(0, 10 * tr + 10 / (zeta * d.wn), 50_001)
    info = control.step_info(d.closed_loop, timepts=t, RiseTimeLimits=d.rise_time_limits)
    assert info["RiseTime"] == pytest.approx(tr, rel=0.01)
    if zeta < 1:
        # overshoot of the no-zero 2nd-order system: 100 exp(-pi zeta/sqrt(1-zeta^2));
        # its damping equivalent must equal the request (1 %)
        os_ref = 100 * math.exp(-math.pi * zeta / math.sqrt(1 - zeta**2))
        assert d.achieved.overshoot_percent == pytest.approx(os_ref, rel=0.01)
        assert d.achieved.overshoot_damping == pytest.approx(zeta, rel=0.01)
    else:
        assert d.achieved.overshoot_percent == pytest.approx(0.0, abs=1e-9)  # monotone step
    assert d.achieved.damping == pytest.approx(zeta, rel=1e-9)


def test_p_rise_time_priority():
    d = quiet(design_p, P0, rise_time=0.15)
    assert d.kd == 0.0 and d.priority is None
    assert d.achieved.rise_time == pytest.approx(0.15, rel=0.01)  # step_info, 1 %
    # one gain: 2 zeta wn = b/I is fixed (closed form, 1e-12)
    assert 2 * d.zeta * d.wn == pytest.approx(P0.viscous / P0.inertia, rel=1e-12)
    # step_info overshoot agrees with the loop's damping (no zero), 1 %
    assert d.achieved.overshoot_damping == pytest.approx(d.zeta, rel=0.01)


def test_p_damping_only_closed_form():
    d = quiet(design_p, P0, damping=0.4)
    # Kp = b^2 / (4 I zeta^2) (closed form, 1e-12)
    assert d.kp == pytest.approx(P0.viscous**2 / (4 * P0.inertia * 0.4**2), rel=1e-12)
    assert d.achieved.overshoot_damping == pytest.approx(0.4, rel=0.01)


def test_p_10_90_definition():
    d = quiet(design_p, P0, rise_time=0.3, rise_time_definition="10-90")
    assert d.rise_time_definition == "10-90"
    assert d.achieved.rise_time == pytest.approx(0.3, rel=0.01)  # step_info 10-90, 1 %


def test_p_with_both_specs_warns_when_other_misses():
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always", DesignWarning)
        d = design_p(P0, rise_time=0.1, damping=0.3, priority="rise_time")
    assert any(issubclass(w.category, DesignWarning) and "misses" in str(w.message) for w in rec)
    assert d.achieved.rise_time == pytest.approx(0.1, rel=0.01)  # priority spec met (1 %)
    assert abs(d.zeta - 0.3) / 0.3 > 0.10
    with pytest.warns(DesignWarning, match="rise time .* misses"):
        d = design_p(P0, rise_time=0.1, damping=0.3, priority="damping")
    assert d.zeta == pytest.approx(0.3, rel=1e-12)
    assert any("misses" in w for w in d.warnings)


def test_paper_p_design_is_self_consistent():
    # the paper actuator's inertia was derived from this design, so both specs hold
    with warnings.catch_warnings():
        warnings.simplefilter("error", DesignWarning)
        d = design_p(P0, rise_time=0.2, damping=0.3)
    assert d.achieved.rise_time == pytest.approx(0.2, rel=0.01)       # step_info, 1 %
    assert d.zeta == pytest.approx(0.3, rel=1e-6)                      # brentq tolerance
    assert d.achieved.overshoot_damping == pytest.approx(0.3, rel=0.01)
    assert d.warnings == ()


# ---------------------------------------------------------------------------
# sampled-data loop
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("key", ["fig11-12", "fig18"])
def test_sampled_loop_matches_literal_loop(key):
    d = quiet(paper_designs)[key]
    n = 600
    rng = np.random.default_rng(3)
    r = np.repeat(rng.uniform(-1, 1, n // 50), 50)
    ref = reference_loop(d.kp, d.kd, d.inertia, d.viscous, d.sample_time, r, q0=0.3)
    out = control.forced_response(sampled_loop(d), np.arange(n) * d.sample_time, r,
                                  initial_state=[0.3, 0.0, 0.0, 0.3]).outputs
    # independent implementation (expm vs c2d): agreement to rounding (1e-10 rad)
    np.testing.assert_allclose(out, ref, atol=1e-10)
    t = np.arange(n) * d.sample_time
    np.testing.assert_allclose(linear_response(d, t, r, q0=0.3, sampled=True), ref, atol=1e-10)
    # between samples: grid Ts/4, same literal loop with 4 plant sub-steps (1e-10 rad)
    t4 = np.arange(4 * n) * d.sample_time / 4
    q4 = linear_response(d, t4, np.repeat(r, 4), q0=0.3, sampled=True)
    ref4 = reference_loop(d.kp, d.kd, d.inertia, d.viscous, d.sample_time, r, q0=0.3, substeps=4)
    np.testing.assert_allclose(q4, ref4, atol=1e-10)


def test_sampled_loop_from_gains_equals_from_design():
    d = quiet(design_pd, PL, rise_time=0.22, damping=0.5)
    a = sampled_loop(d)
    b = sampled_loop(kp=d.kp, kd=d.kd, params=PL)
    np.testing.assert_array_equal(a.A, b.A)  # same construction, exact
    assert a.dt == PL.sample_time
    assert sampled_loop(d, torque_output=True).noutputs == 2



def test_viscous_compensated_zero_is_the_loop_without_compensation():
    d = quiet(paper_designs)["fig13-14"]
    loop = LinearLoop.of(d)
    a, b = loop.sampled(), loop.sampled(viscous_compensated=0.0)
    for m in ("A", "B", "C", "D"):
        np.testing.assert_array_equal(getattr(a, m), getattr(b, m))  # exactly the same loop
    # a compensated loop differs (the compensation acts through omega_hat)
    assert not np.array_equal(a.A, loop.sampled(viscous_compensated=1.0).A)
    with pytest.raises(ValueError, match="viscous_compensated must be >= 0"):
        loop.sampled(viscous_compensated=-0.5)
    with pytest.raises(ValueError, match="viscous_compensated must be finite"):
        sampled_loop(d, viscous_compensated=float("nan"))


@pytest.mark.parametrize("c", [0.5, 1.0])
def test_viscous_compensated_poles_from_the_loop_transfer_function(c):
    # independent construction: ZOH plant P(z) (python-control's tf c2d), one sample of
    # delay, controller Kp + (Kd - c b)(1 - z^-1)/Ts on the measured position;
    # closed-loop poles = roots of z (z - 1)... : 1 + z^-1 C(z) P(z) = 0
    d = quiet(paper_designs)["fig11-12"]
    ts, b = d.sample_time, d.viscous
    pz = control.c2d(control.tf([1.0], [d.inertia, b, 0.0]), ts, method="zoh")
    z = control.tf([1.0, 0.0], [1.0], ts)
    kv = d.kd - c * b
    cz = d.kp + kv * (1 - 1 / z) / ts
    char = control.feedback(1 / z * cz * pz, 1)
    ref = np.sort_complex(control.poles(control.minreal(char, verbose=False)))
    got = np.linalg.eigvals(sampled_loop(d, viscous_compensated=c).A)
    got = np.sort_complex(got[np.abs(got) > 1e-9])
    ref = ref[np.abs(ref) > 1e-9]
    np.testing.assert_allclose(got, ref, atol=1e-9)
    # full compensation of a P loop leaves no damping: a dominant pole on or outside |z| = 1
    if c == 1.0:
        assert np.max(np.abs(got)) > 1.0 - 1e-6


def test_viscous_compensated_equals_core_simulator_with_that_compensator():
    # independent implementation: the core simulator (RK4 plant, its own timing and
    # compensation code) with viscous-only friction, no quantisation, and a compensator
    # whose estimate is c*b*omega_hat
    from fricctl.compensators import NNCompensator
    from fricctl.controllers import p_control, step
    from fricctl.friction import Viscous
    from fricctl.simulate import simulate

    d = quiet(paper_designs)["fig11-12"]
    c = 0.6
    res = simulate(P0, p_control(d.kp, step(0.2)), NNCompensator(lambda tm, w: c * P0.viscous * w),
                   friction=Viscous(P0.viscous).model(), duration=1.0, quantize=False)
    assert np.max(np.abs(res.torque_motor)) < P0.max_torque
    n = res.t.size
    out = control.forced_response(sampled_loop(d, viscous_compensated=c), np.arange(n) * d.sample_time,
                                  res.reference, initial_state=[0.0, 0.0, 0.0, 0.0]).outputs
    np.testing.assert_allclose(res.q, out, atol=1e-9)

def test_linear_loop_closed_form_and_argument_checks():
    # wn = sqrt(Kp/I), zeta = (b + Kd)/(2 sqrt(Kp I)): 2 rad/s and 0.5 here (exact numbers);
    # NumPy scalars are real numbers like any other (fricctl._validate)
    loop = LinearLoop(kp=np.float32(4.0), kd=np.int64(1), inertia=1.0, viscous=1.0,
                      sample_time=0.01)
    assert loop.wn == 2.0 and loop.zeta == 0.5 and type(loop.kp) is float
    with pytest.raises(ValueError, match="inertia must be > 0"):
        LinearLoop(kp=1.0, inertia=0.0, viscous=0.1, sample_time=0.002)
    with pytest.raises(ValueError, match="kd must be finite"):
        sampled_loop(kp=1.0, kd=float("nan"), params=P0)
    with pytest.raises(ValueError, match="design must be a Design"):
        LinearLoop.of({"kp": 1.0})
    # at rest at q0 with r = q0 the sampled loop stays there (equilibrium, 1e-12), on Ts/4
    d = quiet(design_pd, PL, rise_time=0.22, damping=0.5)
    resp = LinearLoop.of(d).sampled_response(np.full(50, 0.3), q0=0.3, substeps=4)
    assert resp.t.shape == resp.q.shape == (200,)
    assert resp.t[1] == pytest.approx(d.sample_time / 4, rel=1e-12)
    np.testing.assert_allclose(resp.q, 0.3, atol=1e-12)


def test_numpy_scalar_specs_design_like_floats():
    # np.float32(0.25) is exactly 0.25: the same design as the Python floats (exact)
    a = quiet(design_pd, PL, rise_time=np.float32(0.25), damping=np.float64(0.5))
    b = quiet(design_pd, PL, rise_time=0.25, damping=0.5)
    assert a.kp == b.kp and a.kd == b.kd and type(a.requested_rise_time) is float


def test_sampled_metrics_of_step_match_literal_loop():
    d = quiet(design_pd, PL, rise_time=0.22, damping=0.5)
    n = int(2.0 / d.sample_time)
    q = reference_loop(d.kp, d.kd, d.inertia, d.viscous, d.sample_time, np.ones(n), substeps=20)
    t = np.arange(q.size) * d.sample_time / 20
    info = control.step_info(q, timepts=t, final_output=1.0, RiseTimeLimits=(0.0, 1.0))
    # same data up to rounding -> same metrics (one fine grid step 1e-4 s)
    assert d.sampled.rise_time == pytest.approx(info["RiseTime"], abs=1.1e-4)
    assert d.sampled.overshoot_percent == pytest.approx(info["Overshoot"], rel=1e-6)


def test_paper_designs_warn_where_the_literal_sampled_loop_differs():
    # Independent of the design code: the sampled loop written out literally (expm, 20
    # sub-steps per sample) measured with step_info, and the damping of its dominant
    # complex pole pair mapped by s = ln(z)/Ts (all four paper dampings are < 1).  The
    # documented rule (module docstring): warn iff rise time or damping moves > 10 %.
    warned = set()
    for key, d in quiet(paper_designs).items():
        n = int(1.5 / d.sample_time)
        q = reference_loop(d.kp, d.kd, d.inertia, d.viscous, d.sample_time, np.ones(n),
                           substeps=20)
        t = np.arange(q.size) * d.sample_time / 20
        info = control.step_info(q, timepts=t, final_output=1.0, RiseTimeLimits=(0.0, 1.0))
        z = np.linalg.eigvals(sampled_loop(d).A).astype(complex)
        s = np.log(z[np.abs(z) > 1e-12]) / d.sample_time       # z = 0: infinitely fast
        s = s[np.abs(s.imag) > 1e-9]
        p = s[np.argmin(np.abs(s))]
        zeta_s = -p.real / abs(p)
        # the design's sampled metrics are these (rise: one fine grid step 1e-4 s; damping 1e-9)
        assert d.sampled.rise_time == pytest.approx(info["RiseTime"], abs=1.1e-4), key
        assert d.sampled.damping == pytest.approx(zeta_s, rel=1e-9), key
        moved = max(abs(info["RiseTime"] / d.achieved.rise_time - 1), abs(zeta_s / d.zeta - 1))
        if any("sampled loop" in w for w in d.warnings):
            warned.add(key)
            assert moved > 0.10, key
        else:
            assert moved < 0.10, key
    # only the 0.3 s / 0.9 PD warns: its 0-100 % rise time is ill-conditioned (0.15 % overshoot)
    assert warned == {"fig13-14"}


def test_dominant_damping_orders_poles_by_decay_not_magnitude():
    # the audit's sampled loop: a real pole at -160 rad/s decays 5.8x faster than the pair
    # -27.5 +- 280j, which is the slow one although |p| = 281 > 160 (closed form -Re p/|p|)
    p = [-160.0, -27.5 + 280j, -27.5 - 280j, -537.0 + 1571j]
    assert dominant_damping(p) == pytest.approx(27.5 / abs(-27.5 + 280j), rel=1e-12)
    # two slowest reals (-1, -4) beneath a fast, lightly damped pair: s^2 + 5 s + 4 -> 1.25
    assert dominant_damping([-4.0, -1.0, -50 + 900j, -50 - 900j]) == pytest.approx(1.25, rel=1e-12)


def test_fast_design_is_not_second_order_and_unstable_design_warns():
    # auditC item 5: design pd --rise-time 0.02 --damping 0.7 printed damping 1 for the sampled
    # loop beside 28 % overshoot.  Independent of the design code: the literal loop's poles
    # (expm ZOH, backward difference, one-sample delay) have a slowest pair with zeta ~0.1
    # that alone would overshoot ~73 %; its step overshoots 28 %: no pair dominates.
    with pytest.warns(DesignWarning, match="sampled loop") as rec:
        d = design_pd(P0, rise_time=0.02, damping=0.7)
    a_c = np.array([[0.0, 1.0], [0.0, -d.viscous / d.inertia]])
    big = np.zeros((3, 3))
    big[:2, :2] = a_c
    big[1, 2] = 1.0 / d.inertia
    e = expm(big * d.sample_time)
    m = np.zeros((4, 4))             # state (q, omega, q_prev, u_prev); u applied one sample late
    m[:2, :2], m[:2, 3] = e[:2, :2], e[:2, 2]
    m[2, 0] = 1.0
    m[3, 0], m[3, 2] = -d.kp - d.kd / d.sample_time, d.kd / d.sample_time
    s = np.log(np.linalg.eigvals(m).astype(complex)) / d.sample_time
    slow = s[np.argmax(s.real)]
    assert -slow.real / abs(slow) == pytest.approx(0.098, abs=0.002)
    assert d.sampled.overshoot_percent == pytest.approx(28.4, abs=0.1)   # the audit's value
    assert math.isnan(d.sampled.damping)
    assert any("not second-order" in str(w.message) and "0.0977" in str(w.message) for w in rec)
    assert not any("damping 1 " in str(w.message) for w in rec)
    assert "not second-order" in d.report() and d.as_dict()["sampled"]["damping"]["value"] is None
    with pytest.warns(DesignWarning, match="unstable"):
        d = design_pd(P0, rise_time=0.004, damping=0.7)
    assert math.isnan(d.sampled.rise_time)
    assert np.max(np.abs(np.linalg.eigvals(d.sampled_closed_loop.A))) >= 1.0


def test_paper_designs_table():
    ds = quiet(paper_designs)
    assert list(ds) == ["fig11-12", "fig13-14", "fig16-17", "fig18"]
    spec = {"fig11-12": ("p", 0.2, 0.3, 0.0), "fig13-14": ("pd", 0.3, 0.9, 0.0),
            "fig16-17": ("pd", 0.4, 0.85, PAPER_LINK_INERTIA),
            "fig18": ("pd", 0.22, 0.5, PAPER_LINK_INERTIA)}
    for key, (law, tr, zeta, link) in spec.items():
        d = ds[key]
        assert d.law == law
        assert d.inertia == pytest.approx(P0.inertia + link, rel=1e-15)
        # paper table (issue 3): both specs met within 1 % by step_info / loop poles
        assert d.achieved.rise_time == pytest.approx(tr, rel=0.01)
        assert d.zeta == pytest.approx(zeta, rel=0.01)
        assert d.achieved.overshoot_damping == pytest.approx(zeta, rel=0.01)
    table = design_table(ds)
    assert table.count("\n") == 5 and "fig16-17" in table


# ---------------------------------------------------------------------------
# linear response, error PD, step_metrics
# ---------------------------------------------------------------------------
def test_linear_response_continuous():
    d = quiet(design_pd, PL, rise_time=0.22, damping=0.5)
    t = np.linspace(0, 1.0, 1001)
    q = linear_response(d, t, np.ones_like(t))
    _, y = control.step_response(d.closed_loop, t)
    np.testing.assert_allclose(q, y, atol=1e-9)  # same model, two realisations
    # at rest at q0 with r = q0 it stays there (equilibrium, 1e-12)
    np.testing.assert_allclose(linear_response(d, t, np.full_like(t, 0.7), q0=0.7), 0.7,
                               atol=1e-12)
    np.testing.assert_allclose(linear_response(d, t, np.full_like(t, 0.7), q0=0.7,
                                               sampled=True), 0.7, atol=1e-12)


def test_error_pd_zero_adds_overshoot():
    d = quiet(design_pd, PL, rise_time=0.22, damping=0.5)
    g = d.error_pd_closed_loop()
    np.testing.assert_allclose(np.sort(control.poles(g)), np.sort(control.poles(d.closed_loop)),
                               rtol=1e-9)                     # same poles
    np.testing.assert_allclose(control.zeros(g), [-d.kp / d.kd], rtol=1e-9)  # zero -Kp/Kd
    m = step_metrics(g, "0-100")
    assert m.overshoot_percent > d.achieved.overshoot_percent + 1.0
    assert m.damping == pytest.approx(0.5, rel=1e-9)          # pole damping unchanged
    assert m.rise_time < d.achieved.rise_time


def test_step_metrics_real_pole_pair_damping():
    # (s+1)(s+4): s^2 + 5 s + 4 -> zeta = 5 / (2*2) = 1.25 (closed form)
    m = step_metrics(control.tf([4.0], [1.0, 5.0, 4.0]), "10-90")
    assert m.damping == pytest.approx(1.25, rel=1e-12)
    assert m.overshoot_percent == 0.0
    assert math.isnan(m.overshoot_damping)


def test_plant_tf():
    g = plant_tf(PL)
    np.testing.assert_allclose(np.asarray(g.den[0][0], float), [PL.total_inertia, PL.viscous, 0])


# ---------------------------------------------------------------------------
# invalid input
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("kw,match", [
    ({"rise_time": 0.3, "damping": 0.0}, "damping must be > 0"),
    ({"rise_time": 0.3, "damping": -0.5}, "damping must be > 0"),
    ({"rise_time": 0.0, "damping": 0.5}, "rise_time must be > 0"),
    ({"rise_time": -1.0, "damping": 0.5}, "rise_time must be > 0"),
    ({"rise_time": float("nan"), "damping": 0.5}, "rise_time must be finite"),
    ({"rise_time": 0.3, "damping": float("nan")}, "damping must be finite"),
    ({"rise_time": 0.3, "damping": float("inf")}, "damping must be finite"),
    ({"rise_time": True, "damping": 0.5}, "rise_time must be a real number"),
    ({"rise_time": 1.0, "damping": 0.1}, "negative Kd"),
    ({"rise_time": 0.3, "damping": 1.2}, None),  # ok: 10-90 chosen by default
    ({"rise_time": 0.3, "damping": 1.2, "rise_time_definition": "0-100"}, "10-90"),
    ({"rise_time": 0.3, "damping": 0.5, "rise_time_definition": "5-95"}, "rise_time_definition"),
    ({"rise_time": None, "damping": 0.5}, "needs both"),
])
def test_pd_invalid_specs(kw, match):
    if match is None:
        d = quiet(design_pd, P0, **kw)
        assert d.rise_time_definition == "10-90"
        return
    with pytest.raises(ValueError, match=match):
        design_pd(P0, **kw)


def test_p_invalid_specs():
    with pytest.raises(ValueError, match="needs rise_time, damping, or both"):
        design_p(P0)
    with pytest.raises(ValueError, match="priority"):
        design_p(P0, rise_time=0.2, damping=0.3, priority="speed")
    with pytest.raises(ValueError, match="viscous b > 0"):
        design_p(P0.replace(viscous=0.0), rise_time=0.2)
    with pytest.raises(ValueError, match="params must be an ActuatorParams"):
        design_p({"inertia": 1.0}, rise_time=0.2)
    with pytest.raises(ValueError, match="10-90"):
        design_p(P0, damping=1.5, rise_time_definition="0-100")


def test_linear_response_invalid():
    d = quiet(design_pd, PL, rise_time=0.22, damping=0.5)
    t = np.arange(0, 0.1, 0.002)
    with pytest.raises(ValueError, match=r"reference must have shape \(50,\)"):
        linear_response(d, t, np.ones(3))
    with pytest.raises(ValueError, match="uniform"):
        linear_response(d, np.r_[0.0, 0.001, 0.003], np.ones(3))
    with pytest.raises(ValueError, match="reference holds NaN"):
        linear_response(d, t, np.full_like(t, np.nan))
    with pytest.raises(ValueError, match="Ts/m"):
        linear_response(d, np.arange(0, 0.1, 0.003), np.ones(34), sampled=True)
    with pytest.raises(ValueError, match="q0"):
        linear_response(d, t, np.ones_like(t), q0=float("nan"))


# ---------------------------------------------------------------------------
# result object
# ---------------------------------------------------------------------------
def test_design_result_is_frozen_and_serialises():
    d = quiet(design_p, P0, rise_time=0.2, damping=0.3)
    assert isinstance(d, Design)
    with pytest.raises(dataclasses.FrozenInstanceError):
        d.kp = 1.0
    obj = json.loads(json.dumps(d.as_dict(), allow_nan=False))
    assert obj["kd"] == {"value": 0.0, "unit": "N*m*s/rad"} and obj["kp"]["value"] == d.kp
    assert obj["requested"] == {"rise_time": {"value": 0.2, "unit": "s"},
                                "damping": {"value": 0.3, "unit": "-"}, "priority": "rise_time"}
    for key in ("achieved", "sampled"):
        assert set(obj[key]) == {"rise_time", "damping", "overshoot_percent", "settling_time"}
    text = d.report()
    assert "Kp = 0.276885" in text and "continuous" in text and "Ts=0.002 s" in text


# ---------------------------------------------------------------------------
# figures (Agg; inspect artists and data, not pixels)
# ---------------------------------------------------------------------------
def test_plot_root_locus_marks_design_poles():
    from fricctl.figures import plot_root_locus

    d = quiet(design_pd, PL, rise_time=0.22, damping=0.5)
    ax = plot_root_locus(d)
    design_line = [ln for ln in ax.get_lines() if ln.get_label().startswith("design")]
    assert len(design_line) == 1
    pts = np.sort_complex(design_line[0].get_xdata() + 1j * design_line[0].get_ydata())
    # design point = closed-loop poles -zeta wn +- j wn sqrt(1-zeta^2) (closed form, 1e-9)
    wd = d.wn * math.sqrt(1 - d.zeta**2)
    np.testing.assert_allclose(pts, np.sort_complex([-d.zeta * d.wn - 1j * wd,
                                                     -d.zeta * d.wn + 1j * wd]), rtol=1e-9)
    locus = [ln for ln in ax.get_lines() if ln.get_color() == "C0"]
    # the complex branch of Kp/(s(Is + b + Kd)) is the vertical line Re s = -(b+Kd)/(2I)
    x = np.concatenate([ln.get_xdata() for ln in locus])
    y = np.concatenate([ln.get_ydata() for ln in locus])
    np.testing.assert_allclose(x[np.abs(y) > 1e-6], -(d.viscous + d.kd) / (2 * d.inertia),
                               rtol=1e-6)
    assert "[rad/s]" in ax.get_xlabel() and "[rad/s]" in ax.get_ylabel()


def test_plot_step_markers():
    from fricctl.figures import plot_step

    d = quiet(design_p, P0, rise_time=0.2, damping=0.3)
    ax = plot_step(d)
    labels = {ln.get_label(): ln for ln in ax.get_lines()}
    assert labels["reference r"].get_drawstyle() == "steps-post"
    cont = labels["continuous"]
    samp = labels[f"sampled, Ts = {d.sample_time:g} s"]
    # the plotted data are the design's predictions (same function, exact)
    t = cont.get_xdata()
    np.testing.assert_array_equal(cont.get_ydata(), linear_response(d, t, np.ones_like(t)))
    np.testing.assert_array_equal(samp.get_ydata(),
                                  linear_response(d, t, np.ones_like(t), sampled=True))
    rise = [ln for k, ln in labels.items() if k.startswith("rise time")][0]
    assert rise.get_xdata()[0] == d.achieved.rise_time
    over = [ln for k, ln in labels.items() if k.startswith("overshoot")][0]
    assert over.get_ydata()[0] == pytest.approx(1 + d.achieved.overshoot_percent / 100, rel=1e-12)
    settle = [ln for k, ln in labels.items() if k.startswith("settling")][0]
    assert settle.get_xdata()[0] == d.achieved.settling_time
    assert ax.get_xlabel() == "$t$ [s]" and "[-]" in ax.get_ylabel()


def test_plot_rejects_non_design():
    from fricctl.figures import plot_step

    with pytest.raises(ValueError, match="Design"):
        plot_step({"kp": 1.0})


def test_ill_conditioned_0_100_rise_time_is_explained():
    # paper Fig. 13-14 design: zeta = 0.9 overshoots by only 0.15 %, so the 0-100 % rise
    # time of the sampled loop moves > 10 %; the warning gives the 10-90 % comparison
    with pytest.warns(DesignWarning, match="ill-conditioned") as rec:
        d = design_pd(P0, rise_time=0.3, damping=0.9)
    assert abs(d.sampled.rise_time / d.achieved.rise_time - 1) > 0.10
    assert abs(d.sampled.damping / d.achieved.damping - 1) < 0.10
    assert len(rec) == 1


@pytest.mark.parametrize("key", ["fig11-12", "fig18"])
def test_sampled_prediction_equals_core_simulator_with_viscous_friction(key):
    # independent implementation: the core simulator (fricctl.simulate, RK4 plant, its own
    # timing code) with viscous-only friction and no quantisation is the linear sampled
    # loop; torques stay below Tmax, so saturation never acts.  RK4 with 4 sub-steps at
    # 0.5 ms on poles below 25 rad/s is exact to ~1e-10 rad.
    from fricctl.controllers import pd_control, step
    from fricctl.friction import Viscous
    from fricctl.simulate import simulate

    d = quiet(paper_designs)[key]
    params = PL if d.inertia > P0.inertia else P0
    res = simulate(params, pd_control(d.kp, d.kd, step(0.5)),
                   friction=Viscous(params.viscous).model(), duration=2.0, quantize=False)
    assert np.max(np.abs(res.torque_motor)) < params.max_torque
    q = linear_response(d, res.t, res.reference, sampled=True)
    np.testing.assert_allclose(res.q, q, atol=1e-9)
    # the continuous prediction is close but not equal: the delay and ZOH matter (> 1 mrad)
    assert np.max(np.abs(res.q - linear_response(d, res.t, res.reference))) > 1e-3


@pytest.mark.parametrize("wn,zeta,definition", [(10.0, 0.5, "0-100"), (10.0, 0.3, "0-100"),
                                                (3.0, 0.9, "0-100"), (3.0, 1.0, "10-90"),
                                                (3.0, 2.5, "10-90"), (7.0, 0.05, "10-90")])
def test_closed_form_metrics_equal_step_info_on_a_fine_grid(wn, zeta, definition):
    # independent implementation: python-control's step_info on a 200 000-point grid (its
    # resolution, 60/(zeta*wn)/2e5, bounds the agreement)
    from fricctl.design.second_order import second_order_metrics

    m = second_order_metrics(wn, zeta, definition)
    sys = control.tf([wn * wn], [1.0, 2 * zeta * wn, wn * wn])
    t = np.linspace(0.0, 60.0 / (zeta * wn), 200_001)
    limits = {"0-100": (0.0, 1.0), "10-90": (0.1, 0.9)}[definition]
    info = control.step_info(sys, T=t, RiseTimeLimits=limits)
    dt = t[1]
    assert m.rise_time == pytest.approx(info["RiseTime"], abs=2 * dt)
    assert m.settling_time == pytest.approx(info["SettlingTime"], abs=2 * dt)
    assert m.overshoot_percent == pytest.approx(info["Overshoot"], rel=1e-4, abs=1e-9)


@pytest.mark.parametrize("law,spec", [
    ("p", dict(rise_time=1e-5)),            # took 22 GB: a grid of tr/2000 over the slow decay
    ("p", dict(rise_time=100.0)),           # IndexError inside step_info (never reaches 100 %)
    ("pd", dict(rise_time=0.3, damping=100.0)),
    ("pd", dict(rise_time=0.3, damping=0.999999999)),
    ("pd", dict(rise_time=1e-6, damping=0.5)),
    ("pd", dict(rise_time=0.3, damping=1e6)),
])
def test_extreme_specs_give_a_design_or_a_clear_error_quickly(law, spec):
    # issue 15: these exhausted memory or raised inside python-control; the continuous
    # metrics are closed forms now and the sampled check is bounded (MAX_POINTS)
    fn = design_p if law == "p" else design_pd
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DesignWarning)
        d = fn(paper_actuator(), **spec)
    assert math.isfinite(d.kp) and math.isfinite(d.achieved.settling_time)


def test_report_shows_an_undefined_sampled_metric_as_a_dash():
    # a design faster than Ts allows: the sampled loop is unstable, its metrics undefined
    import warnings

    from fricctl.params import paper_actuator

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        d = design_p(paper_actuator(), rise_time=0.0005, damping=0.3, priority="rise_time")
    assert math.isnan(d.sampled.rise_time)
    row = next(line for line in d.report().splitlines() if line.strip().startswith("Ts="))
    assert "nan" not in row and row.split()[-4:] == ["-", "-", "-", "-"]
