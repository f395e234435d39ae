"""``benchmarks/bench_claims.py --ripple FRACTION`` (issue 22): the amplitude of the drive's torque
ripple for one run of the claims benchmark, without touching the shipped bench.

References: the bench's own maximum torque (the amplitude is a fraction of it, read back from the
bench and from the friction a run receives), the ripple-free bench (``with_sensing(torque_ripple=0)``)
as the control for A = 0, and a short closed-loop run on the plant, which must be the ripple-free
one's bit for bit at A = 0 and differ from it at A > 0.  The script is loaded from its file (the
``benchmarks`` folder is not a package), by a path relative to this file, not to the working
directory.
"""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest

import fricctl.controllers as ctl
from fricctl.paper.benches import bench
from fricctl.paper.common import designs
from fricctl.simulate import simulate

_SCRIPT = Path(__file__).resolve().parents[1] / "benchmarks" / "bench_claims.py"


@pytest.fixture(scope="module")
def bc():
    spec = importlib.util.spec_from_file_location("bench_claims", _SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.parametrize("bad", [-0.01, -1e-12, math.nan, math.inf, 1.5, "0.01", None, [0.01]])
def test_ripple_rejects_bad_values_naming_the_option(bc, bad):
    # None means "the bench's own" only for bench_for; the checker itself refuses it
    with pytest.raises(ValueError, match="--ripple"):
        bc.ripple_fraction(bad)
    if bad is not None:
        with pytest.raises(ValueError, match="--ripple"):
            bc.bench_for("consistent", bad)


@pytest.mark.parametrize("text", ["-0.01", "nan", "NaN", "inf", "abc", "", "1.5", "0x1", "1_0"])
def test_ripple_on_the_command_line_exits_2_naming_it(bc, capsys, text):
    with pytest.raises(SystemExit) as e:
        bc.main(["--bench", "consistent", f"--ripple={text}"])
    assert e.value.code == 2
    assert "argument --ripple" in capsys.readouterr().err


def test_a_negative_value_after_a_space_is_read_and_refused(bc, capsys):
    # argparse reads "-0.01" as the option's value (not as an unknown option) and the check refuses it
    with pytest.raises(SystemExit) as e:
        bc.main(["--ripple", "-0.01"])
    assert e.value.code == 2
    assert "--ripple must lie in [0, 1]" in capsys.readouterr().err


def _step_run(b, seed: int):
    """A 1.5 s PD step of Figs. 16-17's design on bench ``b``'s linked plant, with its sensing."""
    p, d = b.linked_actuator, designs(b)["fig16-17"]
    opts = b.sensing.options(np.random.default_rng(seed), p.friction_model())
    return simulate(p, ctl.pd_control(d.kp, d.kd, ctl.step(np.deg2rad(30.0))), duration=1.5, **opts), opts


@pytest.mark.parametrize("fraction", [0.001, 0.005, 0.02])
def test_ripple_sets_the_amplitude_the_plant_receives(bc, fraction):
    shipped = bench("consistent")
    b = bc.bench_for("consistent", fraction)
    tmax = shipped.model.max_torque
    assert b.sensing.torque_ripple == pytest.approx(fraction * tmax, rel=1e-15)  # A = f * Tmax, one product
    # the rest of the bench is the shipped one: plant, settings, the ripple's period and phase, the noise
    assert b.model == shipped.model and b.settings == shipped.settings
    for name in ("encoder_jitter", "torque_noise", "torque_ripple_period", "torque_ripple_phase",
                 "velocity_estimate"):
        assert b.sensing.entries[name] == shipped.sensing.entries[name]
    assert "sensitivity study" in b.sensing.entries["torque_ripple"].note
    # the friction a run receives holds a position ripple of that amplitude
    _, opts = _step_run(b, 0)
    assert opts["friction"].ripple_amplitude == pytest.approx(fraction * tmax, rel=1e-15)
    # the shipped bench is untouched (its own 1 % of Tmax, read once and cached)
    assert bench("consistent").sensing.torque_ripple == shipped.sensing.torque_ripple
    assert bc.bench_for("consistent") is shipped


def test_ripple_zero_is_the_ripple_free_bench(bc):
    b0 = bc.bench_for("consistent", 0.0)
    free = bench("consistent").with_sensing("the ripple-free control", torque_ripple=0.0)
    values = {n: e.value for n, e in b0.sensing.entries.items()}
    assert values == {n: e.value for n, e in free.sensing.entries.items()}
    assert b0.sensing.torque_ripple == 0.0 and b0.sensing.ripple(np.random.default_rng(0)) is None
    # a closed-loop run with the bench's noise: bit for bit the ripple-free bench's at A = 0, and not
    # at A = 1 % of Tmax (the shipped amplitude) with the same noise seed
    r0, o0 = _step_run(b0, 7)
    rf, of = _step_run(free, 7)
    assert o0["friction"].ripple_amplitude == of["friction"].ripple_amplitude == 0.0
    np.testing.assert_array_equal(r0.q_meas, rf.q_meas)
    np.testing.assert_array_equal(r0.torque_motor, rf.torque_motor)
    r1, _ = _step_run(bc.bench_for("consistent", 0.01), 7)
    assert not np.array_equal(r1.q, r0.q)


@pytest.mark.parametrize("text", ["0", "-3", "2.5", "abc", "", "1001"])
def test_seeds_on_the_command_line_exit_2_naming_it(bc, capsys, text):
    # refused when the command is parsed (it failed deep in the run before, --seeds 0 included)
    with pytest.raises(SystemExit) as e:
        bc.main([f"--seeds={text}"])
    assert e.value.code == 2
    assert "argument --seeds" in capsys.readouterr().err


def test_ripple_minus_zero_is_zero(bc):
    # "--ripple -0" was printed "-0 x the maximum torque": it is read as 0
    r = bc.bench_for("consistent", -0.0).sensing.torque_ripple
    assert r == 0.0 and math.copysign(1.0, r) == 1.0
