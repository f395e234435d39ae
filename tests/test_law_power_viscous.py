"""The power-law viscous law (``fricctl/friction/laws/power_viscous.py``): c*|w|^p, 0 < p <= 1."""

import numpy as np
import pytest

from fricctl.friction import Coulomb, FrictionModel, PowerViscous, Viscous
from fricctl.plant.stability import friction_slope


def test_power_viscous_torque_closed_form():
    m = Coulomb(0.1) + PowerViscous(pos=0.02, neg=0.03, exponent=0.5)
    w = np.array([-4.0, -0.25, 0.25, 4.0])
    # closed form: Fc*sign(w) + c_dir*|w|**p*sign(w)
    expect = np.array([-0.1 - 0.03 * 2.0, -0.1 - 0.03 * 0.5, 0.1 + 0.02 * 0.5, 0.1 + 0.02 * 2.0])
    assert m.torque(w) == pytest.approx(expect, rel=1e-14)
    assert m.breakaway(1) == pytest.approx(0.1)  # no breakaway of its own
    # p = 1 is the viscous law
    assert (Coulomb(0.1) + PowerViscous(0.02, 1.0)).torque(w) == pytest.approx(
        (Coulomb(0.1) + Viscous(0.02)).torque(w), rel=1e-14)


def test_power_viscous_refuses_what_it_is_not():
    with pytest.raises(ValueError, match="exponent must be in"):
        PowerViscous(0.02, 1.5)
    with pytest.raises(ValueError, match="exponent"):
        PowerViscous(0.02)
    with pytest.raises(ValueError, match="different exponents"):
        PowerViscous(0.02, 0.5) + PowerViscous(0.01, 0.6)
    # no slope for the integrator (unbounded at rest): it declares none
    assert friction_slope((Viscous(0.01) + PowerViscous(0.02, 0.5)).model(), 5.0) == 0.01


def test_power_viscous_runs_in_the_compiled_joint():
    # a free joint under constant torque reaches the speed where T = Fc + c*w**p (closed
    # form w = ((T - Fc)/c)**(1/p)); the model file round trip keeps the law
    from fricctl.plant import RigidJoint

    m = (Coulomb(0.05) + PowerViscous(0.04, 0.5)).model()
    joint = RigidJoint(inertia=1e-3, friction=m)
    st = np.zeros(5)
    for k in range(3000):
        st = joint.advance(st, 0.15, t0=k * 0.002, dt=0.002, substeps=4)
    assert st[1] == pytest.approx(((0.15 - 0.05) / 0.04) ** 2, rel=1e-6)
    assert FrictionModel.from_dict(m.as_dict()) == m
    # released, it comes to rest exactly (the kernel's stop at w = 0), never reversing
    for k in range(3000):
        st = joint.advance(st, 0.0, t0=k * 0.002, dt=0.002, substeps=4)
        assert st[1] >= 0.0
    assert st[1] == 0.0
