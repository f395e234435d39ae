"""The position load law (``fricctl/friction/laws/position_load.py``): A*sin(2*pi*q/P + phase),
end to end through the registry."""

import math

import numpy as np
import pytest

from fricctl.friction import Coulomb, FrictionModel, PositionLoad, PositionRipple, Viscous


def test_load_is_a_torque_of_position_added_unscaled():
    # closed form: Fc*sign(w) + A*sin(2*pi*q/P + phase), the same both ways, not scaled with
    # friction (gravity does not wear); it adds to a ripple (a joint can have both)
    m = Coulomb(0.1) + PositionLoad(0.4, 2 * math.pi, 0.3) + PositionRipple(0.02, 0.1)
    q = np.array([-2.0, 0.0, 1.0, 5.0])
    load = 0.4 * np.sin(q + 0.3) + 0.02 * np.sin(2 * np.pi * q / 0.1)
    assert m.torque(1.0, q=q) == pytest.approx(0.1 + load, rel=1e-13)
    assert m.torque(-1.0, q=q) == pytest.approx(-0.1 + load, rel=1e-13)
    assert m.scaled(2.0).torque(1.0, q=q) == pytest.approx(0.2 + load, rel=1e-13)
    assert m.breakaway(1, q=1.0) == pytest.approx(0.1)  # it adds to the drive torque instead
    assert FrictionModel.from_dict(m.as_dict()) == m
    with pytest.raises(ValueError, match="one PositionLoad"):
        m + PositionLoad(0.1, 20.0)
    with pytest.raises(ValueError, match="period"):
        PositionLoad(0.1, 0.0)


def test_joint_settles_where_the_drive_holds_the_load():
    # a damped joint (viscous only) under a constant torque T settles where the load equals it
    # on its rising side: A*sin(q) = T, q = asin(T/A) (closed form) -- the compiled kernel
    # integrates the law
    from fricctl.plant import RigidJoint

    m = Viscous(0.05) + PositionLoad(0.5, 2 * math.pi, 0.0)
    joint = RigidJoint(inertia=2e-3, friction=m)
    st = np.zeros(5)
    for k in range(3000):
        st = joint.advance(st, 0.3, t0=k * 0.002, dt=0.002, substeps=4)
    assert st[0] == pytest.approx(math.asin(0.3 / 0.5), abs=1e-9) and abs(st[1]) < 1e-9


def test_top_speed_counts_the_load_at_its_worst():
    # the load can push with its amplitude: the top speed under T is (T + A)/b (closed form)
    from fricctl.plant.stability import speed_bound

    m = (Viscous(0.02) + PositionLoad(0.3, 30.0, 1.0)).model()
    assert speed_bound(m, 1.0) == pytest.approx((1.0 + 0.3) / 0.02, rel=1e-9)
