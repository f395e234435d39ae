import math

import pytest

from fricctl.params import (PAPER_LINK_INERTIA, ActuatorParams, derive_inertia_from_p_design,
                            paper_actuator, to_load_side, to_rotor_side)


def test_paper_values():
    p = paper_actuator()
    # paper: static 0.18 N*m is 12.7 % of the maximum torque
    assert p.static == 0.18
    assert p.static / p.max_torque == pytest.approx(0.127, rel=1e-12)
    assert p.viscous == 0.0169 and p.sample_time == 0.002
    assert p.with_link().link_inertia == PAPER_LINK_INERTIA == 0.0046
    assert ActuatorParams.source("inertia") == "derived"
    assert ActuatorParams.source("gear_ratio") == "assumption"
    assert ActuatorParams.unit("viscous") == "N*m*s/rad"


def test_inertia_makes_p_design_self_consistent():
    # hand calculation: wn = (pi - acos 0.3) / (0.2 sqrt(1 - 0.09)) = 9.8303 rad/s,
    # I = b / (2 zeta wn) = 0.0169 / (0.6 * 9.8303) = 2.8653e-3 kg m^2
    wn = (math.pi - math.acos(0.3)) / (0.2 * math.sqrt(0.91))
    assert wn == pytest.approx(9.8303, abs=1e-4)
    assert derive_inertia_from_p_design() == pytest.approx(0.0169 / (0.6 * wn), rel=1e-14)
    assert paper_actuator().inertia == pytest.approx(2.865e-3, rel=1e-3)


@pytest.mark.parametrize("field,value,words", [
    ("inertia", -1.0, "inertia"), ("static", 0.1, "static"), ("sample_time", 0.0, "sample_time"),
    ("viscous", float("nan"), "viscous"), ("max_torque", 0.1, "static"),
    ("encoder_counts", 0, "encoder_counts"), ("coulomb", "x", "coulomb"),
])
def test_invalid_params_name_the_field(field, value, words):
    with pytest.raises(ValueError, match=words):
        paper_actuator(**{field: value})


def test_unknown_field_raises():
    with pytest.raises(ValueError, match="unknown ActuatorParams field"):
        paper_actuator(inertai=1.0)


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
