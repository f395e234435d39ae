"""The Dahl law (``fricctl/friction/laws/dahl.py``): presliding with a state, through the registry."""

import numpy as np
import pytest

from fricctl.friction import Coulomb, Dahl, FrictionModel, LuGre, Static, Viscous
from fricctl.friction.presliding import bristle_state


def test_dahl_is_lugre_without_damping_for_alpha_one():
    # Dahl with alpha = 1 is LuGre's bristle with sigma1 = 0: the compiled joint runs the same
    from fricctl.plant import RigidJoint

    base = Coulomb(0.1) + Viscous(0.01)
    runs = []
    for law in (Dahl(200.0), LuGre(200.0, 0.0)):
        joint = RigidJoint(inertia=1e-3, friction=base + law)
        st = np.zeros(5)
        for k in range(500):
            st = joint.advance(st, 0.15 * np.sin(2 * np.pi * k * 0.002), t0=k * 0.002, dt=0.002,
                               substeps=40)
        runs.append(st.copy())
    assert runs[0] == pytest.approx(runs[1], rel=1e-12, abs=1e-15)


def test_dahl_creeps_below_breakaway_by_its_deflection():
    # below the Coulomb level a presliding joint has no exact stick: it settles at the bristle
    # deflection z = T/sigma0 (closed form, alpha = 1: F = sigma0*z balances T)
    from fricctl.plant import RigidJoint

    joint = RigidJoint(inertia=1e-3, friction=(Coulomb(0.1) + Viscous(0.05) + Dahl(500.0)).model())
    st = np.zeros(5)
    for k in range(3000):
        st = joint.advance(st, 0.04, t0=k * 0.002, dt=0.002, substeps=40)
    assert st[4] == pytest.approx(0.04 / 500.0, rel=1e-3) and abs(st[1]) < 1e-6


def test_dahl_state_along_a_motion_exact_and_numeric_agree():
    # the exact per-step solution (alpha = 1) and the RK4 path for other alpha converge to
    # each other as alpha -> 1 (an independent integration of the same ODE)
    q = np.concatenate([np.linspace(0, 0.01, 200), np.linspace(0.01, -0.005, 300)])
    exact = bristle_state(q, 0.002, 0.0, 1.0)
    near = bristle_state(q, 0.002, 0.0, 1.0 + 1e-9)
    assert near == pytest.approx(exact, abs=1e-7)
    assert np.all(np.abs(bristle_state(q, 0.002, 0.0, 1.7)) <= 1.0 + 1e-12)


def test_dahl_refuses_what_it_cannot_hold():
    with pytest.raises(ValueError, match="Dahl.*Static"):
        Coulomb(0.1) + Static(0.02) + Dahl(100.0)
    with pytest.raises(ValueError, match="one presliding"):
        Coulomb(0.1) + Dahl(100.0) + LuGre(100.0, 1.0)
    with pytest.raises(ValueError, match="exponent"):
        Dahl(100.0, exponent=3.0)
    m = (Coulomb(0.1) + Dahl(100.0, exponent=1.5)).model()
    assert m.has_state and m.state_law.name == "dahl"
    assert FrictionModel.from_dict(m.as_dict()) == m
