import math
import re

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


def test_parse_quantity_converts_suffixes_to_si():
    from fricctl.units import parse_quantity

    # hand conversions: 20 deg = 20*pi/180 rad, 5 mm = 0.005 m, 500 ms = 0.5 s
    assert parse_quantity("20deg", "position") == pytest.approx(20 * math.pi / 180, rel=1e-15)
    assert parse_quantity("20 deg", "position") == parse_quantity("20deg", "position")
    assert parse_quantity("-3mrad", "position") == pytest.approx(-3e-3, rel=1e-15)
    assert parse_quantity("0.4rad", "position") == 0.4 == parse_quantity("0.4", "position")
    assert parse_quantity("5mm", "position", "linear") == pytest.approx(5e-3, rel=1e-15)
    assert parse_quantity("1e-3m", "position", "linear") == 1e-3
    assert parse_quantity("500ms", "time") == 0.5
    assert parse_quantity("0.2N*m", "torque") == 0.2


@pytest.mark.parametrize("text,kind,words", [
    ("20degs", "rotary", "radians (rad); accepted units: rad, mrad, deg"),
    ("5mm", "rotary", "radians"),             # a linear unit on a rotary axis
    ("20deg", "linear", "metres (m); accepted units: m, cm, mm, um"),
    ("x", "rotary", "not a number"),
])
def test_parse_quantity_names_the_default_unit_and_the_accepted_ones(text, kind, words):
    from fricctl.units import parse_quantity

    with pytest.raises(ValueError, match=re.escape(words)):
        parse_quantity(text, "position", kind)
