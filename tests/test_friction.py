import numpy as np
import pytest

from fricctl.friction import (Coulomb, FrictionModel, LoadDependent, LuGre, PositionRipple, Static,
                              Stribeck, Viscous)
from fricctl.params import paper_actuator


def test_laws_compose_by_addition():
    law = Viscous(0.0169) + Coulomb(0.144) + Stribeck(0.036, 0.02)
    # breakaway = Fc + (Fs - Fc) = 0.18; at 1 rad/s: b*w + Fc + excess*exp(-(1/0.02)^2) ~ 0.1609
    assert law.breakaway(1) == pytest.approx(0.18)
    assert law.torque(1.0) == pytest.approx(0.0169 + 0.144, abs=1e-12)
    assert law.torque(-1.0) == pytest.approx(-(0.0169 + 0.144), abs=1e-12)
    assert (Coulomb(0.1) + Coulomb(0.05)).coulomb_pos == pytest.approx(0.15)
    assert sum([Viscous(1.0), Coulomb(2.0)]).breakaway(-1) == 2.0


def test_direction_dependent_magnitudes():
    law = Coulomb(pos=0.2, neg=0.1) + Viscous(pos=0.01, neg=0.03) + Static(pos=0.05, neg=0.02)
    assert law.breakaway(1) == pytest.approx(0.25) and law.breakaway(-1) == pytest.approx(0.12)
    assert law.torque(2.0) == pytest.approx(0.2 + 0.02)
    assert law.torque(-2.0) == pytest.approx(-0.1 - 0.06)
    with pytest.raises(ValueError, match="pos= and neg="):
        Coulomb(pos=0.2)
    with pytest.raises(ValueError, match="Coulomb"):
        Coulomb(-0.1)


def test_friction_dissipates():
    # property: omega * Tat >= 0 for every dissipative law (ripple excluded)
    rng = np.random.default_rng(1)
    law = (Viscous(pos=0.01, neg=0.02) + Coulomb(pos=0.1, neg=0.15) + Stribeck(0.05, 0.03, exponent=1.5)
           + LoadDependent(0.1)).scaled(1.1).with_drift(0.01)
    w = rng.normal(0, 2, 10_000)
    f = law.torque(w, tm=rng.normal(0, 1, w.size), t=rng.uniform(0, 10, w.size))
    assert np.all(w * f >= 0)


def test_stribeck_decays_from_static_to_coulomb():
    law = paper_actuator().friction_model()
    w = np.array([1e-6, 0.02, 0.1, 10.0])
    f = law.torque(w) - 0.0169 * w
    # closed form: Fc + (Fs - Fc) exp(-(w/vs)^2)
    assert f == pytest.approx(0.144 + 0.036 * np.exp(-(w / 0.02) ** 2), rel=1e-12)
    assert np.all(np.diff(f) < 0)


def test_load_dependent_and_ripple_and_drift():
    law = Coulomb(0.1) + LoadDependent(0.2) + PositionRipple(0.03, 0.5, 0.0)
    assert law.breakaway(1, tm=1.0) == pytest.approx(0.3)
    assert law.torque(1.0, q=0.125, tm=-1.0) == pytest.approx(0.3 + 0.03)
    d = Coulomb(0.1).model().with_drift(0.01)
    assert d.breakaway(1, t=10.0) == pytest.approx(0.11)


def test_model_validation():
    with pytest.raises(ValueError, match="LuGre"):
        Coulomb(0.1) + Static(0.05) + LuGre(1e3, 1.0)
    with pytest.raises(ValueError, match="Stribeck"):
        Stribeck(0.1, 0.02) + Stribeck(0.1, 0.05)
    with pytest.raises(ValueError, match="unknown friction field"):
        FrictionModel.from_dict({"coulmb_pos": 1.0})
    with pytest.raises(ValueError, match="scale"):
        Coulomb(0.1).model().scaled(-1.0)
    m = paper_actuator().friction_model()
    assert FrictionModel.from_dict(m.as_dict()) == m


def _random_model(rng):
    """A random mix of laws (each present with probability 1/2), per-direction magnitudes."""
    m = FrictionModel()
    if rng.random() < 0.5:
        m = m + Viscous(pos=rng.uniform(0, 0.05), neg=rng.uniform(0, 0.05))
    m = m + Coulomb(pos=rng.uniform(0.01, 0.3), neg=rng.uniform(0.01, 0.3))
    if rng.random() < 0.5:
        m = m + Stribeck(pos=rng.uniform(0, 0.2), neg=rng.uniform(0, 0.2),
                         velocity=rng.uniform(0.005, 0.5), exponent=rng.choice([2.0, rng.uniform(0.5, 3)]))
    if rng.random() < 0.5:
        m = m + Static(pos=rng.uniform(0, 0.1), neg=rng.uniform(0, 0.1))
    if rng.random() < 0.5:
        m = m + LoadDependent(rng.uniform(0, 0.3))
    if rng.random() < 0.5:
        m = m + PositionRipple(rng.uniform(0, 0.1), rng.uniform(0.01, 1.0), rng.uniform(-3, 3))
    if rng.random() < 0.5:
        m = m.scaled(rng.uniform(0.5, 1.5)).with_drift(rng.uniform(-0.01, 0.01))
    return m


def test_compiled_kernel_equals_friction_model():
    # the numba primitives the plant integrates and FrictionModel's numpy evaluation are two
    # implementations of one law: pinned together on random law mixes (1e-12 relative)
    from fricctl.friction import kernels

    rng = np.random.default_rng(2024)
    for _ in range(200):
        m = _random_model(rng)
        fp = m.vector()
        for _ in range(5):
            w = rng.choice([-1, 1]) * 10 ** rng.uniform(-4, 1.5)
            q, tm, t = rng.uniform(-10, 10), rng.uniform(-1.5, 1.5), rng.uniform(0, 30)
            s = 1.0 if w > 0 else -1.0
            numpy_t = m.torque(w, q, tm, t)
            kernel_t = kernels.sliding(fp, w, s, tm, t) + kernels.ripple(fp, q)
            assert kernel_t == pytest.approx(numpy_t, rel=1e-12, abs=1e-15)
            for d in (1, -1):
                assert kernels.breakaway(fp, float(d), tm, t) == pytest.approx(
                    m.breakaway(d, q, tm, t), rel=1e-12, abs=1e-15)
            assert kernels.scale_at(fp, t) == pytest.approx(float(m.scale_at(t)), rel=1e-15)


def test_layout_matches_the_model_fields():
    from dataclasses import fields

    from fricctl.friction import FIELDS, IDX, NPARAM

    assert tuple(f.name for f in fields(FrictionModel)) == FIELDS
    v = (Viscous(0.1) + Coulomb(0.2)).vector()
    assert v.size == NPARAM and v[IDX["viscous_pos"]] == 0.1 and v[IDX["coulomb_neg"]] == 0.2
