"""Physics of the joint: exact stick, located stops, convergence, flexible joint."""
import math

import numpy as np
import pytest

from fricctl.friction import Coulomb, LuGre, PositionRipple, Static, Viscous
from fricctl.params import paper_actuator
from fricctl.plant import FlexibleJoint, RigidJoint

P = paper_actuator()


def test_below_breakaway_no_motion_above_it_moves():
    joint = RigidJoint.from_params(P)
    brk = joint.friction.breakaway(1)
    for sign in (1, -1):
        st = joint.advance(joint.initial_state(), sign * 0.999 * brk, 0.0, 1.0, substeps=50)
        assert st[0] == 0.0 and st[1] == 0.0  # exactly zero displacement
        st = joint.advance(joint.initial_state(), sign * 1.01 * brk, 0.0, 1.0, substeps=50)
        assert sign * st[0] > 0 and sign * st[1] > 0


def test_ripple_shifts_the_breakaway_band():
    # the joint sits where the ripple pushes with +0.05 N*m: it needs Fs - 0.05 more to start... and
    # breaks loose backwards with (Fs + 0.05) less than that
    fr = Coulomb(0.1) + PositionRipple(0.05, 0.4, 0.0)
    joint = RigidJoint(inertia=1e-3, friction=fr)
    q0 = 0.1  # ripple(0.1) = 0.05 sin(pi/2) = 0.05
    st = joint.advance(joint.initial_state(q0), 0.149, 0.0, 0.1, substeps=10)
    assert st[0] == q0  # net 0.099 < 0.1
    st = joint.advance(joint.initial_state(q0), 0.151, 0.0, 0.1, substeps=10)
    assert st[0] > q0
    st = joint.advance(joint.initial_state(q0), -0.049, 0.0, 0.1, substeps=10)
    assert st[0] == q0  # net -0.099
    st = joint.advance(joint.initial_state(q0), -0.051, 0.0, 0.1, substeps=10)
    assert st[0] < q0


def test_stop_inside_a_step_is_located():
    # closed form for I w' = -b w - Fc from w0 > 0: stops at t* = tau ln(1 + b w0/Fc),
    # at q* = tau w0 - (Fc/b) t*, tau = I/b; then stays (no torque, Fs = Fc)
    inertia, b, fc, w0 = 2.865e-3, 0.0169, 0.144, 3.0
    joint = RigidJoint(inertia=inertia, friction=Viscous(b) + Coulomb(fc))
    tau = inertia / b
    t_stop = tau * math.log(1 + b * w0 / fc)
    q_stop = tau * w0 - fc / b * t_stop
    assert t_stop < 0.1  # the stop lies inside the single interval simulated below
    st = joint.advance(joint.initial_state(0.0, w0), 0.0, 0.0, 0.1, substeps=100)
    assert st[1] == 0.0
    assert st[0] == pytest.approx(q_stop, rel=1e-9)  # RK4 error (1 ms / 0.17 s)^4 ~ 1e-9


def test_reversal_inside_a_step():
    # moving backwards with a large forward torque: the joint stops and reverses in the interval
    joint = RigidJoint(inertia=1e-3, friction=Coulomb(0.1))
    st = joint.advance(joint.initial_state(0.0, -0.05), 1.0, 0.0, 0.002, substeps=1)
    # closed form: decelerates at (1 + 0.1)/I, stops at t1 = 0.05 I / 1.1, then accelerates at 0.9/I
    t1 = 0.05 * 1e-3 / 1.1
    w_end = 0.9 / 1e-3 * (0.002 - t1)
    assert st[1] == pytest.approx(w_end, rel=1e-12)  # piecewise-constant acceleration: RK4 exact


def _random_torque_run(friction, m):
    joint = RigidJoint(inertia=P.inertia, friction=friction)
    torques = np.random.default_rng(0).uniform(-0.5, 0.5, 200)  # many stops and reversals
    st = joint.initial_state()
    out = []
    for k, tq in enumerate(torques):
        st = joint.advance(st, tq, k * 0.002, 0.002, substeps=m)
        out.append(st[0])
    return np.array(out)


def test_fourth_order_convergence_with_located_stops():
    # static + Coulomb + viscous: RK4 with exact event location converges at 4th order
    fr = Viscous(0.0169) + Coulomb(0.144) + Static(0.036)
    ref = _random_torque_run(fr, 512)
    errs = np.array([np.max(np.abs(_random_torque_run(fr, m) - ref)) for m in (1, 2, 4)])
    assert np.all(errs[:-1] / errs[1:] > 10)  # 2^4 = 16 per halving, allow for round-off
    assert errs[-1] < 1e-12


def test_convergence_with_stribeck():
    # the Stribeck dip (vs = 0.02 rad/s) destabilises slow sliding, so errors are larger and the
    # first refinements are not monotone, but the run converges
    fr = P.friction_model()
    ref = _random_torque_run(fr, 512)
    errs = [np.max(np.abs(_random_torque_run(fr, m) - ref)) for m in (1, 8, 32)]
    assert errs[2] < errs[1] < errs[0]
    assert errs[2] < 1e-8


def test_flexible_joint_stuck_motor_lets_the_load_ring():
    # motor held by stiction, load oscillates at sqrt(K/Jl) (undamped)
    joint = FlexibleJoint(motor_inertia=3e-3, load_inertia=4.6e-3, stiffness=2000.0, damping=0.0,
                          friction=Coulomb(0.1) + Static(1.0))
    st = joint.initial_state()
    st[2] = 1e-4  # load displaced: spring torque 0.2 N*m < breakaway 1.1 N*m
    wl = math.sqrt(2000.0 / 4.6e-3)
    t_end = 0.01
    st = joint.advance(st, 0.0, 0.0, t_end, substeps=200)
    assert st[0] == 0.0 and st[1] == 0.0
    assert st[2] == pytest.approx(1e-4 * math.cos(wl * t_end), abs=1e-11)


def test_flexible_joint_tends_to_rigid_when_stiff():
    fr = Viscous(0.0169) + Coulomb(0.05)
    rigid = RigidJoint(inertia=3e-3 + 4.6e-3, friction=fr)
    errs = []
    for k in (1e4, 1e5):
        flex = FlexibleJoint(motor_inertia=3e-3, load_inertia=4.6e-3, stiffness=k, damping=2 * math.sqrt(k * 2e-3),
                             friction=fr)
        a, b = rigid.initial_state(), flex.initial_state()
        for i in range(50):
            a = rigid.advance(a, 0.3, i * 0.002, 0.002, substeps=40)
            b = flex.advance(b, 0.3, i * 0.002, 0.002, substeps=40)
        errs.append(abs(a[0] - b[0]) / abs(a[0]))
    assert errs[1] < errs[0] < 0.01


def test_lugre_presliding_creeps_below_breakaway():
    # LuGre: below breakaway the joint deflects elastically ~ T/sigma0 instead of sticking exactly
    fr = Viscous(0.0169) + Coulomb(0.144) + LuGre(1440.0, 1.0)
    joint = RigidJoint(inertia=P.inertia, friction=fr)
    def final_position(torque):
        st = joint.initial_state()
        for i in range(250):
            st = joint.advance(st, torque, i * 0.002, 0.002, substeps=40)
        return st[0]

    below, above = final_position(0.1), final_position(0.2)
    assert 0 < below < 0.01 * above  # creeps (LuGre drift), where the exact-stick joint would not move
    assert below > 0.1 / 1440.0  # at least the bristle deflection T/sigma0


def test_bad_state_and_substeps():
    joint = RigidJoint.from_params(P)
    with pytest.raises(ValueError, match="shape"):
        joint.advance([0.0, 0.0], 0.1, 0.0, 0.002)
    with pytest.raises(ValueError, match="substeps"):
        joint.advance(joint.initial_state(), 0.1, 0.0, 0.002, substeps=0)
    with pytest.raises(ValueError, match="NaN"):
        joint.advance([np.nan, 0, 0, 0, 0], 0.1, 0.0, 0.002)
    with pytest.raises(ValueError, match="inertia"):
        RigidJoint(inertia=-1.0, friction=Coulomb(0.1).model())
    with pytest.raises(ValueError, match="link_inertia"):
        FlexibleJoint.from_params(P)
