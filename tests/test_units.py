import pytest

from fricctl.units import UNITS, to_load_side, to_rotor_side, units


def test_gear_conversion_round_trip():
    # inertia and viscous scale with n^2, torque with n, angle with 1/n
    out = to_load_side(gear_ratio=50, inertia=2e-6, viscous=1e-5, torque=0.02, angle=1.0)
    assert out == pytest.approx({"inertia": 5e-3, "viscous": 2.5e-2, "torque": 1.0, "angle": 0.02})
    back = to_rotor_side(gear_ratio=50, **out)
    assert back == pytest.approx({"inertia": 2e-6, "viscous": 1e-5, "torque": 0.02, "angle": 1.0})
    with pytest.raises(ValueError, match="gear_ratio"):
        to_load_side(gear_ratio=0, inertia=1.0)
    with pytest.raises(ValueError, match="inertia"):
        to_load_side(gear_ratio=100, inertia=-1.0)
    with pytest.raises(ValueError, match="torque"):
        to_load_side(gear_ratio=100, torque=float("nan"))
    with pytest.raises(ValueError, match="unknown"):
        to_rotor_side(gear_ratio=100, coulomb=0.1)
    assert to_load_side(gear_ratio=10, torque=-0.5) == {"torque": -5.0}  # a torque may be negative


def test_unit_labels():
    assert units("rotary").torque == "N*m" and units("linear").torque == "N"
    assert UNITS["linear"].viscous == "N*s/m"
    with pytest.raises(ValueError, match="units must be one of"):
        units("metric")
