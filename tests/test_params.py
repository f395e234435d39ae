import math

import pytest

from fricctl.params import (PAPER_LINK_INERTIA, ActuatorParams, derive_inertia_from_p_design,
                            paper_actuator)


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


def test_numpy_scalars_are_numbers_and_bools_are_not():
    import numpy as np

    p = paper_actuator(inertia=np.float32(0.003), encoder_counts=np.int64(4000))
    assert isinstance(p.inertia, float) and isinstance(p.encoder_counts, int)
    assert p.encoder_counts == 4000
    for bad in (True, "0.003", 1j, None):
        with pytest.raises(ValueError, match="inertia must be a real number"):
            paper_actuator(inertia=bad)
    with pytest.raises(ValueError, match="encoder_counts must be an integer"):
        paper_actuator(encoder_counts=2000.0)
