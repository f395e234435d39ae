"""The smooth Coulomb law (``fricctl/friction/laws/smooth_coulomb.py``): Fc*tanh(|w|/ws)."""

import numpy as np
import pytest

from fricctl.friction import FrictionModel, SmoothCoulomb, Viscous
from fricctl.plant.stability import friction_slope


def test_smooth_coulomb_torque_closed_form():
    m = Viscous(0.01) + SmoothCoulomb(pos=0.1, neg=0.2, velocity=0.5)
    w = np.array([-1.0, -0.1, 0.1, 1.0])
    expect = 0.01 * w + np.where(w > 0, 0.1, 0.2) * np.tanh(np.abs(w) / 0.5) * np.sign(w)
    assert m.torque(w) == pytest.approx(expect, rel=1e-14)
    # no breakaway: the level at rest is 0; friction_scale multiplies it like Coulomb's
    assert m.breakaway(1) == 0.0 and m.breakaway(-1) == 0.0
    # the integrator's slope: Fc/ws at rest, plus the viscous coefficient
    assert friction_slope(m) == pytest.approx(0.01 + 0.2 / 0.5, rel=1e-14)
    with pytest.raises(ValueError, match="velocity"):
        SmoothCoulomb(0.1)
    with pytest.raises(ValueError, match="different velocities"):
        SmoothCoulomb(0.1, 0.5) + SmoothCoulomb(0.1, 0.6)


def test_smooth_coulomb_slides_below_its_level():
    # a torque below the level moves the joint (no stiction) to the speed where
    # T = Fc*tanh(w/ws): closed form w = ws*atanh(T/Fc); the model file keeps the law
    from fricctl.plant import RigidJoint

    m = SmoothCoulomb(0.1, 0.2).model()
    joint = RigidJoint(inertia=1e-3, friction=m)
    st = np.zeros(5)
    for k in range(2000):
        st = joint.advance(st, 0.05, t0=k * 0.002, dt=0.002, substeps=4)
    assert st[1] == pytest.approx(0.2 * np.arctanh(0.5), rel=1e-6)
    assert FrictionModel.from_dict(m.as_dict()) == m
