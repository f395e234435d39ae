"""The drag law (``fricctl/friction/laws/drag.py``): c*w*|w|, end to end through the registry."""

import numpy as np
import pytest

from fricctl.friction import Coulomb, Drag, FrictionModel, Viscous
from fricctl.plant.stability import friction_slope


def test_drag_torque_is_quadratic_and_dissipative():
    m = Coulomb(0.1) + Drag(pos=0.02, neg=0.03)
    w = np.array([-4.0, -0.5, 0.5, 4.0])
    # closed form: Fc*sign(w) + c_dir*w*|w|
    expect = np.array([-0.1 - 0.03 * 16, -0.1 - 0.03 * 0.25, 0.1 + 0.02 * 0.25, 0.1 + 0.02 * 16])
    assert m.torque(w) == pytest.approx(expect, rel=1e-14)
    assert m.breakaway(1) == pytest.approx(0.1) and m.drag_neg == 0.03


def test_drag_slope_grows_with_speed_for_the_integrator():
    m = (Viscous(0.01) + Drag(0.02)).model()
    assert friction_slope(m, speed=5.0) == pytest.approx(0.01 + 2 * 0.02 * 5.0)
    assert friction_slope(m) == pytest.approx(0.01)  # speed unknown: the speed-free part


def test_drag_runs_in_the_compiled_joint():
    # a free joint under constant torque reaches the speed where torque = Fc + c*w^2
    # (closed form w = sqrt((T - Fc)/c)); the same model file round trip keeps the law
    from fricctl.plant import RigidJoint

    m = (Coulomb(0.05) + Drag(0.02)).model()
    joint = RigidJoint(inertia=1e-3, friction=m)
    st = np.zeros(5)
    for k in range(2000):
        st = joint.advance(st, 0.25, t0=k * 0.002, dt=0.002, substeps=8)
    assert st[1] == pytest.approx(np.sqrt((0.25 - 0.05) / 0.02), rel=1e-6)
    assert FrictionModel.from_dict(m.as_dict()) == m


def test_drag_identification_columns():
    from fricctl.friction import LAWS

    w = np.array([-2.0, 0.0, 3.0])
    cols = LAWS["drag"].regressors(w, False)
    assert cols["drag_pos"].tolist() == [0.0, 0.0, 9.0] and cols["drag_neg"].tolist() == [-4.0, 0.0, 0.0]


def test_drag_sub_steps_follow_the_speed_the_run_can_reach():
    # a stiff drag on a light joint: the slope 2*c*|w| at the terminal speed sqrt(T/c) needs
    # many RK4 sub-steps; replaying a large torque sizes them from that speed (closed form)
    # and stays finite, dissipating (friction has the sign of the velocity)
    from fricctl.plant import RigidJoint
    from fricctl.plant.stability import speed_bound
    from fricctl.simulate import replay

    m = (Coulomb(0.01) + Drag(0.5)).model()
    assert speed_bound(m, 2.0) == pytest.approx(np.sqrt((2.0 - 0.01) / 0.5), rel=1e-9)
    out = replay(RigidJoint(inertia=1e-5, friction=m), np.full(200, 2.0), 0.002, omega0=-30.0)
    assert np.all(np.isfinite(out.omega)) and np.all(out.omega * out.friction >= 0)
    assert out.omega[-1] == pytest.approx(np.sqrt((2.0 - 0.01) / 0.5), rel=1e-6)


def test_speed_bound_past_a_falling_stribeck_level():
    # Stribeck friction first falls with speed: the top speed is where viscous friction makes
    # up the rest (closed form (T - Fc)/b = 500 rad/s), not the first crossing near rest
    from fricctl.friction import Stribeck
    from fricctl.plant.stability import speed_bound

    m = (Coulomb(1.0) + Stribeck(1.0, velocity=2.0) + Viscous(0.001)).model()
    assert speed_bound(m, 1.5, omega0=5.0) == pytest.approx(500.0, rel=1e-9)
