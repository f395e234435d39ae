"""Issue 15, library side: hostile inputs get a ValueError naming what is wrong.

Net files as strict as model files (one reader, :func:`fricctl._validate.strict_json`),
CSV cells read strictly, records and patterns of real numbers only, filters that
would return NaN refused with their limit, and every friction evaluation finite.
Each test is a regression test of one finding of the issue (its item in the comment).
"""

import json
import re

import numpy as np
import pytest

from fricctl import _validate as v
from fricctl.nn import FrictionNet
from fricctl.nn.io import load_net, net_from_json, net_to_dict


def _net():
    return FrictionNet(w1=[[1.0, 0.5], [-0.3, 2.0]], b1=[0.1, -0.2], w2=[0.7, -1.1], b2=0.05,
                       input_offset=[0.0, 0.1], input_scale=[1.0, 2.0], output_offset=0.01,
                       output_scale=0.2, envelope_low=[-1.0, -3.0], envelope_high=[1.0, 3.0],
                       metadata={"trainer": "by hand", "seed": 3})


def _text(**changes):
    d = net_to_dict(_net())
    d.update(changes)
    return json.dumps(d)


# -- net files (items 5 and 7) -----------------------------------------------------------
@pytest.mark.parametrize("text, match", [
    ('{"a":' * 100_000 + "1" + "}" * 100_000, "nested deeper than"),     # was RecursionError
    (_text(b2=10 ** 400), "b2 is too large"),                           # was OverflowError
    (_text(w2=[10 ** 400, 1.0]), r"w2\[0\] is too large"),
    (_text(w1=[[True, 0.5], [-0.3, 2.0]]), r"w1\[0\]\[0\] must be a real number, got True"),
    (_text(b1=["0.1", -0.2]), r"b1\[0\] must be a real number, got '0.1'"),
    (_text(b2=False), "b2 must be a real number"),
    (_text(w2=[0.7, None]), r"w2\[1\] must be a real number, got None"),
    (_text(version=True), "version"),
    (_text(version=1.0), "version"),
    (_text(hidden=2.0), "hidden must be an integer"),
    (_text(units={"inputs": ["N", "m/s"], "output": "N", "side": "load"}), "units"),
    (_text(units="SI"), "units"),
    (_text()[:-1] + ', "b2": 5.0}', "duplicate key 'b2'"),
    (_text().replace('"b2": 0.05', '"b2": NaN'), "b2: NaN is not a number"),
    (_text().replace('"b2": 0.05', '"b2": -Infinity'), "b2: -Infinity is not a number"),
    (_text(w1=[[1.0, 0.5], [-0.3]]), r"w1\[1\] must have 2 entries"),
])
def test_net_file_refuses_what_a_model_file_refuses(text, match):
    with pytest.raises(ValueError, match=match):
        net_from_json(text)


def test_net_file_errors_name_the_file(tmp_path):
    p = tmp_path / "net.json"
    p.write_text(_text(version=True))
    with pytest.raises(ValueError, match="net.json: version"):
        load_net(p)


def test_net_file_reads_what_it_writes_including_nested_metadata():
    net = _net().replace(metadata={"rng_state": {"state": {"state": 2 ** 127, "inc": 5}}})
    back = net_from_json(json.dumps(net_to_dict(net)))
    assert back.metadata["rng_state"]["state"]["state"] == 2 ** 127
    assert np.array_equal(back.w1, net.w1) and back.b2 == net.b2


def test_one_strict_reader_for_model_and_net_files():
    # the model file's reader is the shared one: its duplicate-key refusal names the key
    from fricctl.plant import JointModel

    with pytest.raises(ValueError, match="duplicate key 'inertia'"):
        JointModel.from_json('{"format": "fricctl.joint_model", "version": 2, "inertia": 1, '
                             '"inertia": 2}')
    with pytest.raises(ValueError, match="friction.coulomb_pos: NaN is not a number"):
        JointModel.from_json('{"format": "fricctl.joint_model", "version": 2, "units": "rotary",'
                             ' "inertia": 1, "friction": {"coulomb_pos": NaN}}')


def test_weights_given_as_booleans_in_python_lists_are_refused():
    # numpy reads [True, 0.5] as [1.0, 0.5]; the shared array check does not
    with pytest.raises(ValueError, match="b1 must hold real numbers, got a boolean"):
        _net().replace(b1=[True, 0.5])
    with pytest.raises(ValueError, match="x must hold real numbers"):
        v.array("x", [[0.5, 1.0], [np.bool_(True), 2.0]], ndim=2)
    assert v.array("x", [1, 2.5]).tolist() == [1.0, 2.5]


# -- CSV, records, patterns (item 7) -----------------------------------------------------
@pytest.mark.parametrize("cell", ["0.00_2", "1_000", "0x10", "1,5", "", "1e400", "nan", "-inf",
                                  "1.5.2", "٣"])
def test_csv_cells_are_decimal_numbers_only(tmp_path, cell):
    from fricctl.datasets.table import read_columns

    p = tmp_path / "r.csv"
    p.write_text(f'a,b\n1,2\n3,"{cell}"\n', encoding="utf-8")
    with pytest.raises(ValueError, match=r"r.csv, line 3, column 'b': "):
        read_columns(p, required=("a", "b"))


def test_csv_reads_every_plain_decimal_form(tmp_path):
    from fricctl.datasets.table import read_columns

    p = tmp_path / "r.csv"
    p.write_text("a\n1\n-2.5\n+.5\n3.\n1e-3\n 7E+02 \n", encoding="utf-8")
    assert read_columns(p, required=("a",))["a"].tolist() == [1.0, -2.5, 0.5, 3.0, 1e-3, 700.0]


def test_patterns_file_velocity_quantum_is_read_strictly(tmp_path):
    from fricctl.datasets import read_patterns

    p = tmp_path / "p.csv"
    p.write_text("# velocity_quantum: 1_0\ntm,omega,friction\n1,2,3\n4,5,6\n")
    with pytest.raises(ValueError, match="velocity_quantum: not a number: '1_0'"):
        read_patterns(p)


@pytest.mark.parametrize("torque, match", [
    (np.array(["1.0"] * 20), "torque must hold real numbers, got an array of text"),
    (np.ones(20) + 0j, "torque must hold real numbers, got an array of complex"),
    ([1.0] * 19 + [True], "torque must hold real numbers, got a boolean"),
    (np.array([1.0] * 20, dtype=object), "torque must hold real numbers"),
])
def test_run_refuses_text_complex_and_boolean_arrays(torque, match):
    from fricctl.datasets import Run

    t = np.arange(20) * 0.002
    with pytest.raises(ValueError, match=match):
        Run(t=t, torque=torque, position=t ** 2)


def test_smooth_patterns_refuse_static_below_coulomb():
    from fricctl.nn.patterns import smooth_friction_patterns

    rng = np.random.default_rng(0)
    with pytest.raises(ValueError, match="static must be >= coulomb.*static=0.1.*coulomb=1"):
        smooth_friction_patterns(rng, coulomb=1, static=0.1)
    with pytest.raises(ValueError, match="at least 1"):
        smooth_friction_patterns(rng, n_sliding=0, n_stuck=0)
    p = smooth_friction_patterns(rng, coulomb=0.1, static=0.1, n_sliding=5, n_stuck=5)
    assert np.all(np.abs(p.tm[5:]) <= 0.1)


# -- signal processing and friction: no silent NaN, errors of the right kind (item 11) ----
def test_butterworth_order_beyond_its_numerical_limit_is_refused_with_the_limit():
    from fricctl.estimation import butterworth_central

    t = np.arange(2000) * 0.001
    q = np.sin(6 * t)
    with pytest.raises(ValueError, match="order must be an integer in 1 .. 20, got 50"):
        butterworth_central(t, q, cutoff=100.0, order=50)       # was all-NaN velocities
    # 1 Hz at 1 kHz is 0.002 of Nyquist: order 8 in (b, a) form is round-off, order 4 is not
    with pytest.raises(ValueError, match="order must be at most 4"):
        butterworth_central(t, q, cutoff=1.0, order=8)
    est = butterworth_central(t, q, cutoff=1.0, order=4)
    # the filtered sine (6 rad/s ~ 0.95 Hz, near the cut-off) stays finite and bounded by the input
    assert np.all(np.isfinite(est.velocity)) and np.max(np.abs(est.position)) <= 1.0 + 1e-9


def test_decimation_limit_is_where_the_filter_stays_accurate():
    from scipy import signal

    from fricctl import estimation as e

    # the constant's reference: the (b, a) form matches the sections design at 17, not at 18
    assert e._ba_accurate(signal.cheby1, 8, 0.05, 0.8 / e.MAX_DECIMATION)
    assert not e._ba_accurate(signal.cheby1, 8, 0.05, 0.8 / (e.MAX_DECIMATION + 1))
    x = np.sin(np.arange(2000) * 0.006)
    with pytest.raises(ValueError, match="factor must be at most 17.*got 100"):
        e.decimate(x, 100)                                   # was a sine of amplitude 16
    with pytest.raises(ValueError, match="factor must be an integer, got inf"):
        e.decimate(x, np.inf)
    y = e.decimate(x, 17)
    assert np.max(np.abs(y)) < 1.0 + 1e-3                    # passband ripple 0.05 dB


@pytest.mark.parametrize("call, match", [
    (lambda e: e.central_difference([1.0, np.nan, 3.0, 4.0], 1.0), r"x holds NaN or inf \(nan\) at index 1"),
    (lambda e: e.central_difference([1e300, -1e300, 3.0], 1e-10), "overflows double precision"),
    (lambda e: e.zero_phase_filter([1.0], [1.0, -2.0], np.ones(50)), "unstable"),
    (lambda e: e.zero_phase_filter([1.0], [0.0, 1.0], np.ones(50)), r"a\[0\] must not be 0"),
])
def test_signal_helpers_refuse_what_would_be_nan(call, match):
    from fricctl import estimation as e

    with pytest.raises(ValueError, match=match):
        call(e)


def test_an_estimate_is_never_silently_non_finite():
    from fricctl.estimation import DerivativeEstimate

    with pytest.raises(ValueError, match="savitzky_golay: the acceleration estimate is not finite "
                                         "at sample 2"):
        DerivativeEstimate(t=np.arange(3.0), position=np.zeros(3), velocity=np.zeros(3),
                           acceleration=[0.0, 0.0, np.inf], method="savitzky_golay")


@pytest.mark.parametrize("args, match", [
    ((np.nan,), r"omega holds NaN or inf"),
    (([0.1, np.inf],), r"omega holds NaN or inf \(inf\) at index 1"),
    (("a",), "omega must be an array of real numbers"),
    ((True,), "omega must hold real numbers"),
    ((1.0, np.nan), "q holds NaN"),
    ((1.0, 0.0, np.nan), "tm holds NaN"),
    ((1.0, 0.0, 0.0, np.nan), "t holds NaN"),
    ((np.ones(3), np.zeros(2)), "do not broadcast"),
    ((1e300,), "overflows double precision"),
])
def test_friction_torque_refuses_nan_and_overflow(args, match):
    from fricctl.friction import Coulomb, Viscous

    model = (Viscous(1e10) + Coulomb(0.144)).model()
    with pytest.raises(ValueError, match=match):
        model.torque(*args)


def test_friction_breakaway_inputs_are_checked_too():
    from fricctl.friction import Coulomb, LoadDependent

    model = (Coulomb(0.1) + LoadDependent(0.2)).model()
    with pytest.raises(ValueError, match="tm holds NaN"):
        model.breakaway(+1, tm=np.nan)
    assert model.breakaway(+1, tm=-1.0) == pytest.approx(0.1 + 0.2)  # hand calculation


# -- siblings found by a fuzz pass over the same modules (item 11) -------------------------
def test_sibling_argument_checks_raise_value_errors_naming_the_argument():
    from fricctl.datasets import record_patterns
    from fricctl.identify import lower_bounds, parameter_unit
    from fricctl.units import to_load_side

    with pytest.raises(ValueError, match="name must be a string"):
        parameter_unit(None)                                  # was AttributeError
    with pytest.raises(ValueError, match="names must be a list or tuple"):
        lower_bounds(3)                                       # was TypeError
    with pytest.raises(ValueError, match="names must be a list or tuple"):
        lower_bounds("inertia")                               # was one bound per character
    with pytest.raises(ValueError, match=r"names\[1\] must be a string"):
        lower_bounds(["inertia", None])
    with pytest.raises(ValueError, match="runs must be a Run or a list of Run, got NoneType"):
        record_patterns(None, inertia=1.0)                    # was TypeError
    with pytest.raises(ValueError, match="inertia on the load side"):
        to_load_side(gear_ratio=1e300, inertia=1.0)           # was OverflowError
    assert lower_bounds(("inertia", "offset")).tolist() == [0.0, -np.inf]


def test_simulation_and_bench_arguments_are_checked():
    from fricctl.bench import experiments as x
    from fricctl.controllers import pd_control, step
    from fricctl.params import paper_actuator
    from fricctl.simulate import simulate

    ctrl = pd_control(1.0, 0.05, step(0.5))
    with pytest.raises(ValueError, match="an empty list was given for a batch argument"):
        simulate(paper_actuator(), ctrl, duration=0.2, friction=[])     # was KeyError
    with pytest.raises(ValueError, match="delay of ~1e400 samples .beyond double precision."):
        simulate(paper_actuator(), ctrl, duration=0.2, delay=10 ** 400)  # was OverflowError
    with pytest.raises(ValueError, match="t must hold real numbers"):
        step(1.0)(1 + 1j)                                                # was TypeError
    with pytest.raises(ValueError, match="params must be a fricctl.params.ActuatorParams"):
        x.dead_zone(None)                                                # was AttributeError
    with pytest.raises(ValueError, match="params must be"):
        x.training_experiments("paper")
    with pytest.raises(ValueError, match="experiments must be a list of Experiment, got NoneType"):
        x.true_patterns(None)
    with pytest.raises(ValueError, match=r"experiments\[0\] must be an Experiment"):
        x.friction_patterns([1], paper_actuator())
    with pytest.raises(ValueError, match="experiment must be an Experiment"):
        x.compare_estimators(None, paper_actuator())
    with pytest.raises(ValueError, match="estimator must be a function"):
        x.predicted_dead_zone(None, 0.18)


def test_the_issues_wrong_kind_errors_are_value_errors_naming_the_argument():
    # issue 15 item 11 as listed (TypeError, AttributeError, OverflowError before)
    from fricctl.controllers import p_control, step
    from fricctl.datasets import Run
    from fricctl.identify import identify_run, inverse_dynamics
    from fricctl.params import paper_actuator
    from fricctl.simulate import replay, simulate

    with pytest.raises(ValueError, match="noise_std must be a real number, got 'a'"):
        simulate(paper_actuator(), p_control(1.0, step(0.1)), duration=0.1, noise_std="a")
    with pytest.raises(ValueError, match="joint must be a RigidJoint or FlexibleJoint, got None"):
        replay(None, np.ones(10), 0.002)
    t = np.arange(2000) * 0.002
    run = Run(t=t, torque=np.sign(np.cos(3 * t)), position=np.round(np.sin(3 * t), 4))
    with pytest.raises(ValueError, match="border must be an integer, got 2.5"):
        identify_run(run, border=2.5)
    with pytest.raises(ValueError, match=r"parameters\['inertia'\] must be finite, got nan"):
        inverse_dynamics("coulomb_viscous", {"inertia": np.nan, "viscous": 0.0169,
                                             "coulomb": 0.144}, np.ones(3), np.ones(3))


def test_a_damaged_cache_entry_is_trained_again_not_a_traceback(tmp_path, monkeypatch):
    import hashlib

    from fricctl.nn import cache

    monkeypatch.setenv("FRICCTL_CACHE", str(tmp_path))
    key = {"test": "damaged entry"}
    text = json.dumps({"key": key, "code": cache.code_digest()}, sort_keys=True)
    path = tmp_path / "nets" / (hashlib.sha256(text.encode()).hexdigest()[:32] + ".json")
    path.parent.mkdir()
    path.write_text("[" * 100_000 + "]" * 100_000)            # was a RecursionError

    class Retrained(Exception):
        pass

    def make():
        raise Retrained

    with pytest.raises(Retrained):
        cache.cached_pipeline_net(key, make)


def test_polynomial_orders_beyond_double_precision_are_refused_with_the_limit():
    # siblings of butterworth_central(order=50): a rank-deficient fit warned and went on
    from fricctl.estimation import polynomial_segments, savitzky_golay

    t = np.arange(2000) * 0.001
    q = np.round(np.sin(6 * t) / 1e-4) * 1e-4
    with pytest.raises(ValueError, match=r"order 40 is not determined .* order must be at most \d+"):
        polynomial_segments(t, q, order=40)
    with pytest.raises(ValueError, match=r"polyorder 40 is not determined .* at most \d+"):
        savitzky_golay(t, q, window_length=51, polyorder=40)
    with pytest.raises(ValueError, match=r"polyorder 1998 .* at most \d+"):   # was a traceback
        savitzky_golay(t, q, window_length=1999, polyorder=1998)
    # the limit the message names works, and the paper's order 6 is far from it
    try:
        savitzky_golay(t, q, window_length=51, polyorder=40)
    except ValueError as exc:
        top = int(re.search(r"at most (\d+)", str(exc)).group(1))
    assert top >= 6
    assert np.all(np.isfinite(savitzky_golay(t, q, window_length=51, polyorder=top).velocity))


def test_a_bad_element_of_a_matrix_is_named_by_plain_indices():
    # the index is printed as (0, 1), not as numpy scalars (np.int64(0), np.int64(1))
    from fricctl import _validate as v

    with pytest.raises(ValueError, match=r"^w holds NaN or inf \(nan\) at index \(0, 1\)$"):
        v.array("w", [[1.0, np.nan]], ndim=2)
