"""Hypothesis properties of the physics and the file formats (issue 15), in the default run.

Small example counts (``max_examples`` 10-30, no deadline: a loaded machine is slow, not
wrong); the whole file runs in well under a minute.  Each property is physics or an
identity, never a tuned number:

* a rigid joint left alone (no torque) only loses kinetic energy, and its friction
  opposes the motion at every sample (``omega * Tat >= 0``);
* a closed loop with random valid parameters returns finite records or refuses the
  run with a ValueError that says it diverged; never NaN or inf;
* every friction law opposes motion: ``omega * (Tat(omega) - ripple(q)) >= 0``
  (the position ripple is a torque of the position, not of the motion);
* a network saved and loaded is the same network bit for bit, and its C export
  computes what it computes (1e-12 N*m; compiled only where a C compiler exists);
* a record (``Run``) and a model file read back what was written, exactly.
"""

import math
import string

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, event, given, settings
from hypothesis import strategies as st

from fricctl.controllers import pd_control, step
from fricctl.datasets import Run
from fricctl.friction import LAWS, FrictionModel
from fricctl.nn.io import load_net, net_from_json, net_to_json, save_net
from fricctl.params import paper_actuator
from fricctl.plant import JointModel, RigidJoint
from fricctl.plant.model import Provenance
from fricctl.simulate import replay, simulate
from test_nn import CC, _c_library, _random_net  # the C export test's helpers

SETTINGS = dict(deadline=None, derandomize=True,
                suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])


def _pos(lo, hi):
    """A positive magnitude drawn log-uniformly between lo and hi."""
    return st.floats(math.log10(lo), math.log10(hi)).map(lambda e: 10.0 ** e)


#: Magnitudes drawn per unit (log-uniform); other coefficients in [1e-3, 1] of their unit.
_RANGES = {"N*m/rad": (10.0, 1e4), "rad": (0.01, 6.3), "N*m": (1e-4, 0.5)}


def _coefficient(c):
    """A strategy for one law coefficient inside its declared bounds."""
    if c.signed:
        return st.floats(-3.0, 3.0)
    if math.isfinite(c.upper):
        return st.floats(max(c.lower, 1e-3), c.upper)
    return _pos(*_RANGES.get(c.unit, (1e-3, 1.0)))


@st.composite
def friction_models(draw, *, lugre=True, ripple=True):
    """A random sum of the registered friction laws (each present or not, asymmetric levels),
    every coefficient inside its declared bounds (:data:`fricctl.friction.LAWS`): a new law
    is drawn without editing this test.  ``lugre``: a presliding (state) law may be drawn."""
    values = {"coulomb_pos": draw(_pos(1e-3, 1.0)), "coulomb_neg": draw(_pos(1e-3, 1.0))}
    states = [law for law in LAWS.values() if law.role == "state"]
    chosen = draw(st.sampled_from([None] + states)) if lugre else None
    for law in LAWS.values():
        if law.role == "scale" or law.name == "coulomb" or (law.role == "state" and law is not chosen):
            continue
        if (law.role == "position" and not ripple) or (law.role != "state" and not draw(st.booleans())):
            continue
        values.update({c.name: draw(_coefficient(c)) for c in law.coefficients})
    try:
        return FrictionModel(**values)
    except ValueError:  # a mix a law refuses (a presliding law with stiction): not a model
        assume(False)


# -- the joint alone dissipates -----------------------------------------------------------
@settings(max_examples=30, **SETTINGS)
@given(friction=friction_models(lugre=False, ripple=False), inertia=_pos(1e-4, 1.0),
       omega0=st.floats(-50.0, 50.0), ts=_pos(1e-4, 1e-2))
def test_a_joint_left_alone_only_loses_energy(friction, inertia, omega0, ts):
    out = replay(RigidJoint(inertia=inertia, friction=friction), np.zeros(300), ts, omega0=omega0)
    assert np.all(np.isfinite(out.q)) and np.all(np.isfinite(out.omega))
    energy = 0.5 * inertia * out.omega ** 2
    # kinetic energy never grows (RK4 round-off allowance: 1e-12 relative)
    assert np.all(np.diff(energy) <= 1e-12 * energy[:-1] + 1e-300)
    # friction has the sign of the velocity (the sign convention I*qdd = Tm - Tat)
    assert np.all(out.omega * out.friction >= 0.0)


# -- a closed loop stays finite or says it diverged ---------------------------------------
@settings(max_examples=20, **SETTINGS)
@given(friction=friction_models(), kp=_pos(0.01, 100.0), kd=_pos(1e-4, 1.0),
       target=st.floats(-2.0, 2.0), plant=st.sampled_from(["rigid", "flexible"]))
def test_a_closed_loop_is_finite_or_refused_as_diverged(friction, kp, kd, target, plant):
    if plant == "flexible" and friction.has_state:
        plant = "rigid"  # presliding laws run on the rigid joint only (JointModel says so)
    params = paper_actuator().with_link() if plant == "flexible" else paper_actuator()
    try:
        res = simulate(params, pd_control(kp, kd, step(target)), duration=0.4,
                       friction=friction, plant=plant)
    except ValueError as exc:
        assert "diverged" in str(exc) or "unstable" in str(exc) or "encoder" in str(exc), exc
        event("refused as diverged")
        return
    event("finite run")
    for name in ("q", "omega", "torque_cmd", "torque_motor", "friction"):
        assert np.all(np.isfinite(getattr(res, name))), name


# -- every law opposes motion -------------------------------------------------------------
@settings(max_examples=30, **SETTINGS)
@given(friction=friction_models(),
       omega=st.lists(st.floats(-1e3, 1e3), min_size=1, max_size=20),
       q=st.floats(-100.0, 100.0), tm=st.floats(-10.0, 10.0), t=st.floats(0.0, 100.0))
def test_friction_opposes_motion_for_every_law(friction, omega, q, tm, t):
    w = np.array(omega)
    tat = friction.torque(w, q, tm, t) - friction.ripple(q)
    assert np.all(w * tat >= 0.0)
    assert np.all(tat[w == 0.0] == 0.0)  # at rest the friction is a reaction, not a torque of w
    assert friction.breakaway(+1, q, tm, t) >= 0.0 and friction.breakaway(-1, q, tm, t) >= 0.0


# -- network files and the C export -------------------------------------------------------
@settings(max_examples=20, **SETTINGS)
@given(seed=st.integers(0, 2 ** 32 - 1), hidden=st.integers(1, 8))
def test_a_saved_net_loads_bit_for_bit(tmp_path_factory, seed, hidden):
    net = _random_net(np.random.default_rng(seed), hidden).replace(
        metadata={"seed": seed, "nested": {"list": [1, 2.5, None, "x"]}})
    back = load_net(save_net(net, tmp_path_factory.mktemp("net") / "net.json"))
    for name in ("w1", "b1", "w2", "input_offset", "input_scale", "envelope_low",
                 "envelope_high"):
        assert np.array_equal(getattr(back, name), getattr(net, name)), name
    assert (back.b2, back.output_offset, back.output_scale) == (net.b2, net.output_offset,
                                                                net.output_scale)
    assert dict(back.metadata) == dict(net.metadata)
    assert net_to_json(net_from_json(net_to_json(net))) == net_to_json(net)


_JSON = st.recursive(st.none() | st.booleans() | st.integers(-10 ** 400, 10 ** 400)
                     | st.floats(allow_nan=False, allow_infinity=False) | st.text(max_size=5),
                     lambda inner: st.lists(inner, max_size=4)
                     | st.dictionaries(st.text(max_size=5), inner, max_size=4), max_leaves=12)


@settings(max_examples=30, **SETTINGS)
@given(seed=st.integers(0, 2 ** 32 - 1), key=st.sampled_from(
    ["format", "version", "hidden", "w1", "b1", "w2", "b2", "input_offset", "input_scale",
     "output_offset", "output_scale", "envelope_low", "envelope_high", "units", "metadata",
     "extra"]), value=_JSON)
def test_a_damaged_net_file_is_read_or_refused_with_a_value_error(seed, key, value):
    # any entry replaced by any JSON value: a FrictionNet or a ValueError, never another error
    import json

    from fricctl.nn.io import net_to_dict

    d = net_to_dict(_random_net(np.random.default_rng(seed), 2))
    d[key] = value
    try:
        net = net_from_json(json.dumps(d))
    except ValueError:
        return
    assert np.all(np.isfinite(net(np.linspace(-1, 1, 5), np.linspace(-1, 1, 5))))


@pytest.mark.skipif(CC is None, reason="no C compiler (cc or gcc) on PATH")
@settings(max_examples=10, **SETTINGS)
@given(seed=st.integers(0, 2 ** 32 - 1), hidden=st.integers(1, 8), clip=st.booleans())
def test_the_c_export_computes_what_the_net_computes(tmp_path_factory, seed, hidden, clip):
    rng = np.random.default_rng(seed)
    net = _random_net(rng, hidden)
    lo, hi = net.envelope_low, net.envelope_high
    tm = rng.uniform(lo[0] - (hi[0] - lo[0]), hi[0] + (hi[0] - lo[0]), 50)
    om = rng.uniform(lo[1] - (hi[1] - lo[1]), hi[1] + (hi[1] - lo[1]), 50)
    batch = _c_library(net, tmp_path_factory.mktemp("c"), "prop")
    # reference: FrictionNet.__call__; libm's tanh and the summation order differ by ~1e-16
    np.testing.assert_allclose(batch(tm, om, clip), net(tm, om, clip=clip), rtol=0, atol=1e-12)


# -- records and model files round trip ---------------------------------------------------
_TEXT = st.text(string.ascii_letters + string.digits + " _-.,", max_size=30).map(str.strip)


@settings(max_examples=20, **SETTINGS)
@given(n=st.integers(10, 200), ts=_pos(1e-5, 0.1), t0=st.floats(-100.0, 100.0),
       seed=st.integers(0, 2 ** 32 - 1), units=st.sampled_from(["rotary", "linear"]),
       with_reference=st.booleans(), source=_TEXT)
def test_a_record_reads_back_what_was_written(tmp_path_factory, n, ts, t0, seed, units,
                                              with_reference, source):
    rng = np.random.default_rng(seed)
    t = t0 + np.arange(n) * ts
    pos = np.cumsum(rng.normal(size=n)) * rng.uniform(1e-6, 1e3)
    ref = rng.normal(size=n) if with_reference else None
    run = Run(t=t, torque=rng.normal(size=n) * 10.0 ** rng.uniform(-6, 6), position=pos,
              reference=ref, units=units, source=source)
    back = Run.from_csv(run.to_csv(tmp_path_factory.mktemp("run") / "r.csv"))
    for name in ("t", "torque", "position"):
        assert np.array_equal(getattr(back, name), getattr(run, name)), name
    assert (back.reference is None) == (ref is None)
    if ref is not None:
        assert np.array_equal(back.reference, run.reference)
    assert back.units == units and back.source == (source or back.source)


@settings(max_examples=20, **SETTINGS)
@given(friction=friction_models(), inertia=_pos(1e-5, 1e3), offset=st.floats(-10.0, 10.0),
       delay=st.floats(0.0, 0.01), elastic=st.booleans(), units=st.sampled_from(["rotary",
                                                                                  "linear"]),
       sample_time=st.one_of(st.none(), _pos(1e-5, 0.1)), std=st.one_of(st.none(), _pos(1e-9, 1.0)),
       source=_TEXT)
def test_a_model_file_reads_back_what_was_written(friction, inertia, offset, delay, elastic,
                                                  units, sample_time, std, source):
    elastic = elastic and not friction.has_state
    extra = dict(load_inertia=0.5 * inertia, stiffness=1e3, damping=0.1) if elastic else {}
    model = JointModel(inertia=inertia, friction=friction, offset=offset, delay=delay,
                       units=units, source=source, sample_time=sample_time, **extra,
                       provenance={"inertia": Provenance(source="assumption", std=std,
                                                         note=source)})
    assert JointModel.from_json(model.to_json()) == model
    assert isinstance(model.friction, FrictionModel)


@settings(max_examples=30, **SETTINGS)
@given(key=st.sampled_from(["format", "version", "units", "inertia", "friction", "offset",
                            "delay", "load_inertia", "stiffness", "damping", "sample_time",
                            "encoder_resolution", "max_torque", "source", "provenance", "extra"]),
       value=_JSON)
def test_a_damaged_model_file_is_read_or_refused_with_a_value_error(key, value):
    import json

    d = JointModel.from_params(paper_actuator(), source="paper").as_dict()
    d[key] = value
    try:
        model = JointModel.from_json(json.dumps(d))
    except ValueError:
        return
    assert model.inertia > 0 and math.isfinite(model.friction.breakaway(+1))
