"""The sampled loop: exactness against closed forms, timing, stick-slip, batch, errors."""
import control as ct
import numpy as np
import pytest

from fricctl.compensators import CoulombCompensator, NNCompensator, NoCompensation
from fricctl.controllers import (constant, from_array, open_loop, p_control, pd_control, sawtooth,
                                 sequence, sinusoid, step)
from fricctl.friction import Coulomb, Static, Viscous
from fricctl.params import paper_actuator
from fricctl.simulate import simulate, simulate_batch

P = paper_actuator()


def test_viscous_plant_matches_exact_zoh_discretisation():
    # reference: python-control's exact ZOH discretisation of 1/(s (I s + b)) driven by the
    # recorded motor torque; RK4 with 4 substeps errs by ~(0.5 ms / 0.17 s)^4 relative
    rng = np.random.default_rng(3)
    t = np.arange(500) * P.sample_time
    torque = from_array(t, rng.uniform(-0.3, 0.3, t.size))
    res = simulate(P, open_loop(torque), friction=Viscous(P.viscous).model(), duration=1.0,
                   quantize=False)
    i, b = P.inertia, P.viscous
    sys = ct.ss([[0, 1], [0, -b / i]], [[0], [1 / i]], np.eye(2), [[0], [0]])
    sysd = ct.c2d(sys, P.sample_time, method="zoh")
    out = ct.forced_response(sysd, T=res.t, U=res.torque_motor, X0=[0, 0])
    assert np.max(np.abs(out.states[0] - res.q)) < 1e-9 * np.max(np.abs(res.q))
    assert np.max(np.abs(out.states[1] - res.omega)) < 1e-9 * np.max(np.abs(res.omega))


def test_loop_timing_one_sample_delay_and_saturation():
    res = simulate(P, pd_control(2.0, 0.05, step(1.0)), duration=0.5)
    # Tm(k+1) = clip(Tc(k), +-Tmax) with no compensation; Tm(0) = 0
    assert res.torque_motor[0] == 0.0
    np.testing.assert_array_equal(res.torque_motor[1:], np.clip(res.torque_cmd[:-1], -P.max_torque, P.max_torque))
    assert res.torque_cmd[0] == 2.0 and res.torque_motor[1] == P.max_torque
    # backward difference of the encoder reading
    np.testing.assert_allclose(res.omega_hat[1:], np.diff(res.q_meas) / P.sample_time, rtol=0, atol=1e-9)
    # encoder quantised to one count on the load side, truncating
    res_counts = res.q_meas / P.encoder_resolution
    np.testing.assert_allclose(res_counts, np.round(res_counts), atol=1e-6)
    assert np.all(res.q_meas <= res.q + 1e-15) and np.all(res.q - res.q_meas < P.encoder_resolution)


@pytest.mark.parametrize("kp,r", [(0.277, 0.436), (1.0, 0.5), (3.0, -0.2), (0.5, 1.0)])
def test_p_control_final_error_within_stiction_band(kp, r):
    # with Coulomb/static friction a P loop stops anywhere with |Kp e| <= Fs: |e| <= Fs/Kp
    res = simulate(P, p_control(kp, step(r)), duration=6.0)
    assert res.stuck[-1]
    assert abs(res.reference[-1] - res.q_meas[-1]) <= P.static / kp + P.encoder_resolution


def test_joint_does_not_move_below_breakaway_in_closed_loop():
    # Fig. 11 situation: the P design's first torque Kp * 25 deg = 0.121 N*m < Fs = 0.18 N*m
    res = simulate(P, p_control(0.2769, step(np.deg2rad(25))), duration=2.0)
    assert np.all(res.q == 0.0) and res.stuck.all()
    assert res.stuck_intervals() == [(0.0, res.t[-1])]


def test_friction_dissipates_and_stuck_means_still():
    res = simulate(P, pd_control(1.23, 0.0906, sawtooth(1.0, 2.0)), duration=4.0)
    assert np.all(res.omega * res.friction >= 0)
    s = res.stuck
    assert np.all(res.omega[s] == 0.0)
    assert s.any() and (~s).any()
    # no chattering: the true velocity keeps its sign between stops (sign changes only through rest)
    moving = res.omega[~s]
    segments = np.split(np.sign(res.omega), np.flatnonzero(s))
    changes = sum(int(np.sum(np.diff(seg[seg != 0]) != 0)) for seg in segments)
    assert changes <= len(res.stuck_intervals()) + 5 and moving.size > 0


def test_extra_delay_shifts_the_response():
    ctrl = open_loop(sequence([0.5, -0.5, 0.0], [0.1, 0.1, 0.3]))
    a = simulate(P, ctrl, duration=0.5)
    b = simulate(P, ctrl, duration=0.5, delay=3)
    np.testing.assert_array_equal(b.q[3:], a.q[:-3])
    np.testing.assert_array_equal(a.torque_motor, b.torque_motor)  # the record is unchanged


def test_noise_is_seeded():
    ctrl = open_loop(sinusoid(0.3, 1.0))
    a = simulate(P, ctrl, duration=1.0, noise_std=0.01, rng=np.random.default_rng(7))
    b = simulate(P, ctrl, duration=1.0, noise_std=0.01, rng=np.random.default_rng(7))
    c = simulate(P, ctrl, duration=1.0, noise_std=0.01, rng=np.random.default_rng(8))
    np.testing.assert_array_equal(a.q, b.q)
    assert np.any(a.q != c.q)
    with pytest.raises(ValueError, match="rng"):
        simulate(P, ctrl, duration=1.0, noise_std=0.01)


def test_position_noise_is_added_before_quantisation():
    # reference: the same draws made by hand -- torque noise first, then the position noise
    # (issue 22: encoder edge jitter); a joint held at rest (no torque) reads floor(e/res) counts
    res, sigma, k = P.encoder_resolution, 0.3 * P.encoder_resolution, 500
    r = simulate(P, open_loop(constant(0.0)), duration=k * P.sample_time, noise_std=0.001,
                 position_noise_std=sigma, rng=np.random.default_rng(4))
    rng = np.random.default_rng(4)
    rng.normal(0.0, 0.001, size=(1, k))
    e = rng.normal(0.0, sigma, size=(1, k))[0]
    assert np.all(r.q == 0.0)  # 0.001 N*m of noise never breaks the joint loose: q is exact
    np.testing.assert_array_equal(r.q_meas, res * np.floor(e / res))
    np.testing.assert_allclose(r.omega_hat[1:], np.diff(r.q_meas) / P.sample_time, rtol=0, atol=1e-9)
    assert r.info.position_noise_std == sigma and np.count_nonzero(r.omega_hat) > 100  # it flickers


class _PyCoulomb(CoulombCompensator):
    """The Coulomb compensator evaluated in Python (no compiled form)."""

    def compiled(self):
        return None


def test_position_noise_is_seeded_and_the_same_in_both_loops():
    kw = dict(duration=2.0, position_noise_std=0.3 * P.encoder_resolution, noise_std=0.002)
    ctrl, comp = pd_control(1.5, 0.05, step(0.3)), CoulombCompensator.symmetric(0.15)
    a = simulate(P, ctrl, comp, rng=np.random.default_rng(5), **kw)
    b = simulate(P, ctrl, _PyCoulomb.symmetric(0.15), rng=np.random.default_rng(5), **kw)
    c = simulate(P, ctrl, comp, rng=np.random.default_rng(6), **kw)
    assert a.info.loop == "compiled" and b.info.loop == "python"
    np.testing.assert_array_equal(a.q_meas, b.q_meas)
    assert np.any(a.q_meas != c.q_meas)
    # none (the default) is the exact encoder reading; 0 draws nothing
    d = simulate(P, ctrl, comp, duration=2.0)
    e = simulate(P, ctrl, comp, duration=2.0, position_noise_std=0.0)
    np.testing.assert_array_equal(d.q_meas, e.q_meas)
    np.testing.assert_array_equal(d.q_meas, P.encoder_resolution * np.floor(d.q / P.encoder_resolution))
    with pytest.raises(ValueError, match="position_noise_std > 0 needs rng"):
        simulate(P, ctrl, duration=1.0, position_noise_std=1e-6)
    with pytest.raises(ValueError, match="position_noise_std"):
        simulate(P, ctrl, duration=1.0, position_noise_std=-1e-6, rng=np.random.default_rng(0))


class _Net:
    """A tiny stand-in with the FrictionNet attributes (compiled path)."""

    w1 = np.array([[1.0, 2.0], [-0.5, 0.3]])
    b1 = np.array([0.1, -0.2])
    w2 = np.array([0.05, 0.08])
    b2 = 0.01
    input_offset = np.array([0.0, 0.0])
    input_scale = np.array([1.0, 2.0])
    output_offset = 0.0
    output_scale = 1.5
    envelope_low = np.array([-1.0, -5.0])
    envelope_high = np.array([1.0, 5.0])

    def __call__(self, tm, omega, clip=False):
        x = np.stack(np.broadcast_arrays(np.asarray(tm, float), np.asarray(omega, float)), axis=-1)
        if clip:
            x = np.clip(x, self.envelope_low, self.envelope_high)
        xn = (x - self.input_offset) / self.input_scale
        return (np.tanh(xn @ self.w1.T + self.b1) @ self.w2 + self.b2) * self.output_scale + self.output_offset


@pytest.mark.parametrize("comp", [
    NoCompensation(), CoulombCompensator.symmetric(0.144, deadband=0.05),
    NNCompensator(_Net(), scale=0.95), NNCompensator(_Net(), clip=True)])
def test_compiled_and_python_loops_agree(comp):
    # the Python loop (any callable) is an independent driver of the same plant kernel
    ctrl = pd_control(1.23, 0.0906, sawtooth(0.1, 0.5))
    fast = simulate(P, ctrl, comp, duration=2.0)
    slow_comp = NNCompensator(lambda tm, w: comp(tm, w), scale=comp.scale)
    slow = simulate(P, ctrl, slow_comp, duration=2.0)
    assert fast.info.loop == "compiled" and slow.info.loop == "python"
    np.testing.assert_allclose(slow.q, fast.q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(slow.friction_est, fast.friction_est, rtol=0, atol=1e-12)


def test_batch_equals_single_runs():
    ps = [P, P.replace(inertia=2 * P.inertia), P.with_link()]
    ctrl = pd_control(1.23, 0.0906, step(0.3))
    batch = simulate_batch(ps, ctrl, duration=2.0, friction=[p.friction_model().scaled(s) for p, s in
                                                             zip(ps, (1.0, 0.8, 1.2))])
    assert len(batch) == 3
    for i, p in enumerate(ps):
        one = simulate(p, ctrl, duration=2.0, friction=p.friction_model().scaled((1.0, 0.8, 1.2)[i]))
        np.testing.assert_array_equal(batch[i].q, one.q)
    np.testing.assert_allclose(batch.steady_state_error(), [batch[i].steady_state_error() for i in range(3)])


def test_one_numba_thread_runs_the_serial_kernel_with_the_same_records(monkeypatch):
    # fricctl reproduce's workers run one numba thread each: the batch must not need the parallel
    # kernel (never compiled there) and must give the records of the parallel one, bit for bit
    import numba

    from fricctl.simulate import loop

    ps = [P, P.replace(inertia=2 * P.inertia), P.with_link()]
    ctrl = pd_control(1.23, 0.0906, step(0.3))
    par = simulate_batch(ps, ctrl, duration=1.0)
    threads = numba.get_num_threads()

    def refuse(*args):
        raise AssertionError("the parallel kernel ran with one thread")

    monkeypatch.setattr(loop, "_runs_parallel", refuse)
    numba.set_num_threads(1)
    try:
        one = simulate_batch(ps, ctrl, duration=1.0)
    finally:
        numba.set_num_threads(threads)
    for i in range(len(ps)):
        for name in ("q", "q_load", "omega", "omega_hat", "torque_motor", "friction", "stuck"):
            np.testing.assert_array_equal(getattr(one[i], name), getattr(par[i], name))


def test_flexible_plant_runs_and_rings():
    # twist q - q_load after a torque step rings at the free-free resonance sqrt(K (1/Jm + 1/Jl))
    p = P.with_link().replace(joint_damping=0.0)
    res = simulate(p, open_loop(step(0.6)), plant="flexible", duration=0.3, quantize=False,
                   friction=Viscous(P.viscous).model(), substeps=40)
    assert res.q[-1] > 0 and res.q_load[-1] > 0
    twist = res.q - res.q_load
    twist = twist - np.mean(twist[res.t > 0.05])
    spec = np.abs(np.fft.rfft(twist[res.t > 0.05]))
    freqs = np.fft.rfftfreq(int(np.sum(res.t > 0.05)), P.sample_time)
    expected = np.sqrt(p.stiffness * (1 / p.inertia + 1 / p.link_inertia)) / (2 * np.pi)
    assert freqs[np.argmax(spec)] == pytest.approx(expected, abs=2 * freqs[1])  # within 2 FFT bins


@pytest.mark.parametrize("kwargs,words", [
    ({"duration": -1.0}, "duration"), ({"duration": 1.0, "plant": "soft"}, "plant"),
    ({"duration": 1.0, "substeps": 0}, "substeps"), ({"duration": 1.0, "delay": -1}, "delay"),
    ({"duration": 1.0, "q0": np.nan}, "q0"), ({"duration": 1.0, "noise_std": -1.0}, "noise_std"),
    ({"duration": 0.001}, "shorter"),
])
def test_bad_arguments_raise(kwargs, words):
    with pytest.raises(ValueError, match=words):
        simulate(P, open_loop(constant(0.1)), **kwargs)


def test_bad_objects_raise():
    with pytest.raises(ValueError, match="controller"):
        simulate(P, lambda t: 0.0, duration=1.0)
    with pytest.raises(ValueError, match="compensator"):
        simulate(P, open_loop(constant(0.1)), compensator=3, duration=1.0)
    with pytest.raises(ValueError, match="runs"):
        simulate_batch([P, P], open_loop(constant(0.1)), friction=[Coulomb(0.1).model()] * 3, duration=1.0)
    with pytest.raises(ValueError, match="strictly increasing"):
        from_array([0.0, 0.0], [1.0, 2.0])
    with pytest.raises(ValueError, match="kp must be >= 0"):
        p_control(-1.0, step(1.0))
    with pytest.raises(ValueError, match="NaN"):  # a Python estimator returning NaN is caught
        simulate(P, open_loop(constant(0.0)), NNCompensator(lambda a, b: np.full(np.shape(a), np.nan)),
                 duration=0.1)


def test_static_plus_coulomb_model_sticks_exactly():
    fr = Viscous(P.viscous) + Coulomb(0.144) + Static(0.036)
    res = simulate(P, open_loop(constant(0.1799)), friction=fr, duration=0.5)
    assert np.all(res.q == 0.0)
    res = simulate(P, open_loop(constant(0.1801)), friction=fr, duration=0.5)
    assert res.q[-1] > 0


def test_replay_reproduces_the_closed_loop_from_its_record():
    # driving the same joint open loop with the recorded torque gives back the same trajectory
    from fricctl.plant import RigidJoint
    from fricctl.simulate import replay

    res = simulate(P, pd_control(1.23, 0.0906, sawtooth(1.0, 2.0)), duration=2.0)
    rep = replay(RigidJoint.from_params(P), res.torque_motor, P.sample_time)
    q, w, f = rep.q, rep.omega, rep.friction
    np.testing.assert_array_equal(q, res.q)
    np.testing.assert_array_equal(f, res.friction)
    with pytest.raises(ValueError, match="NaN"):
        replay(RigidJoint.from_params(P), [0.0, np.nan], P.sample_time)


def test_friction_net_runs_compiled_exactly_as_in_python():
    # a real FrictionNet inside the compiled loop equals its own numpy evaluation in the Python loop
    from fricctl.nn import smooth_friction_patterns, train_casadi

    pats = smooth_friction_patterns(np.random.default_rng(0), n_sliding=200, n_stuck=50)
    tm, w, f = pats.tm, pats.omega, pats.friction
    net = train_casadi(tm, w, f, restarts=1, rng=np.random.default_rng(0)).net
    ctrl = pd_control(1.23, 0.0906, sawtooth(1.0, 2.0))
    for clip in (False, True):
        comp = NNCompensator(net, scale=0.95, clip=clip)
        fast = simulate(P, ctrl, comp, duration=1.0)
        slow = simulate(P, ctrl, NNCompensator(lambda a, b, c=comp: c(a, b), scale=0.95), duration=1.0)
        assert fast.info.loop == "compiled" and slow.info.loop == "python"
        np.testing.assert_allclose(fast.friction_est, slow.friction_est, rtol=0, atol=1e-12)
        np.testing.assert_allclose(fast.q, slow.q, rtol=0, atol=1e-12)


def test_guards_against_silent_nonsense():
    # a drift that would make friction negative, a NaN compensation scale, an absurd length
    ctrl = open_loop(constant(0.0))
    with pytest.raises(ValueError, match="drift"):
        simulate(P, ctrl, friction=P.friction_model().with_drift(-1.0), duration=2.0)
    with pytest.raises(ValueError, match="scale"):
        NoCompensation(scale=float("nan"))
    with pytest.raises(ValueError, match="samples"):
        simulate(P, ctrl, duration=1e12)
    with pytest.raises(ValueError, match="q0"):
        simulate(P, ctrl, duration=0.1, q0=[0.0, 1.0])
    from fricctl.plant import RigidJoint
    from fricctl.simulate import replay

    with pytest.raises(ValueError, match="substeps"):
        replay(RigidJoint.from_params(P), [0.1, 0.1], P.sample_time, substeps=0)
    # a negative drift that stays physical is fine, and friction still dissipates
    res = simulate(P, open_loop(sinusoid(0.3, 1.0)), friction=P.friction_model().with_drift(-0.2),
                   duration=2.0)
    assert np.all(res.omega * res.friction >= 0)


def test_schedule_with_constant_gains_is_the_pd_loop():
    # simulate_schedule (per-sample gains, the bench's entry) and simulate (a Controller)
    # run the same compiled steps: a PD step must agree to the last bit
    from fricctl.controllers import pd_control, step
    from fricctl.plant import RigidJoint
    from fricctl.simulate import Schedule, simulate_schedule

    res = simulate(P, pd_control(1.2, 0.09, step(0.5)), duration=1.0)
    k = res.t.size
    sched = Schedule(kp=np.full(k, 1.2), kd=np.full(k, 0.09), reference=np.full(k, 0.5),
                     feedforward=np.zeros(k), segment_start=np.zeros(k, dtype=bool))
    alt = simulate_schedule(RigidJoint.from_params(P), sched, sample_time=P.sample_time,
                            max_torque=P.max_torque, encoder_resolution=P.encoder_resolution)
    for name in ("q", "q_meas", "torque_motor", "friction", "reference"):
        np.testing.assert_array_equal(getattr(alt, name), getattr(res, name), err_msg=name)
    assert alt.info.params is None and alt.info.kp == 1.2


def test_schedule_segments_restart_the_reference_where_the_joint_is():
    # two PD segments each asking for +0.3 rad: the second's reference is 0.3 rad above
    # where the first left the encoder, and the joint stops within the dead band Fs/Kp of it
    from fricctl.plant import RigidJoint
    from fricctl.simulate import Schedule, simulate_schedule

    k = int(round(2.0 / P.sample_time))
    seg = np.zeros(k, dtype=bool)
    seg[0] = seg[k // 2] = True
    sched = Schedule(kp=np.full(k, 1.2), kd=np.full(k, 0.09), reference=np.full(k, 0.3),
                     feedforward=np.zeros(k), segment_start=seg)
    r = simulate_schedule(RigidJoint.from_params(P), sched, sample_time=P.sample_time,
                          max_torque=P.max_torque, encoder_resolution=P.encoder_resolution)
    assert r.reference[k // 2] == pytest.approx(r.q_meas[k // 2] + 0.3)
    assert r.reference[-1] == r.reference[k // 2] > 0.3 + 0.1
    assert abs(r.reference[-1] - r.q[-1]) <= P.static / 1.2
    with pytest.raises(ValueError, match="segment_start"):
        Schedule(kp=np.ones(k), kd=np.ones(k), reference=np.zeros(k), feedforward=np.zeros(k),
                 segment_start=np.zeros(k))


def test_substeps_follow_the_plants_fastest_rate_and_never_return_non_finite():
    # issue 15: a viscous coefficient of 20 N*m*s/rad on the paper actuator (b/I = 6980 1/s)
    # with the default 4 RK4 sub-steps gave |q| = 1.8e300; the rule h*rate <= 1 asks for
    # ceil(0.002*6980) = 14, and the run is then a bounded open-loop sinusoid response
    from fricctl.controllers import sinusoid

    fr = (Viscous(20.0) + Coulomb(0.01)).model()
    r = simulate(P, open_loop(sinusoid(1.4, 1.0)), duration=1.0, friction=fr)
    assert r.info.substeps == 14
    # the steady response of I q'' + b q' = A sin(wt) has speed amplitude <= A/b = 0.07 rad/s
    assert np.all(np.isfinite(r.q)) and np.abs(r.omega).max() <= 1.4 / 20.0 * 1.01
    with pytest.raises(ValueError, match="needs at least 14 RK4 sub-steps"):
        simulate(P, open_loop(sinusoid(1.4, 1.0)), duration=1.0, friction=fr, substeps=4)
    # a stiff spring: sqrt(K (1/Jm + 1/Jl)) = 23 800 rad/s at K = 1e6 -> 48 sub-steps
    stiff = P.with_link().replace(stiffness=1e6)
    r = simulate(stiff, p_control(1.0, step(0.3)), duration=0.5, plant="flexible")
    assert r.info.substeps == 48 and np.all(np.isfinite(r.q_load))
    with pytest.raises(ValueError, match="too stiff for this sample time"):
        simulate(P.with_link().replace(stiffness=1e14), p_control(1.0, step(0.3)), duration=0.5,
                 plant="flexible")


def test_every_field_of_the_loops_specs_says_what_it_is():
    # the typed records the compiled loop reads (issue 19): a new plant parameter or loop
    # setting is one field, and its meaning and unit live in the class docstring
    import re
    import typing

    from fricctl.simulate import spec

    classes = [getattr(spec, name) for name in spec.__all__]
    assert all(issubclass(c, tuple) and c._fields for c in classes)  # NamedTuples: numba compiles them
    for cls in classes:
        hints = typing.get_type_hints(cls)
        for name in cls._fields:
            entry = re.search(rf"^    {name} : .+\n        \S.*", cls.__doc__, re.M)
            assert entry, f"{cls.__name__}.{name} is not documented"
            assert name in hints, f"{cls.__name__}.{name} has no type"


def test_a_net_of_another_kind_of_axis_is_refused():
    # issue 26: a net trained on a linear axis (N, m/s) ran on a rotary joint, and the reverse
    from dataclasses import replace

    from fricctl.data import paper_actuator_model
    from fricctl.nn import FrictionNet
    from fricctl.simulate import simulate_model

    def net(units):
        return FrictionNet(w1=[[1.0, 0.0]], b1=[0.0], w2=[0.1], b2=0.0, input_offset=[0, 0],
                           input_scale=[1, 1], output_offset=0.0, output_scale=1.0,
                           envelope_low=[-1, -1], envelope_high=[1, 1], metadata={"units": units})

    ctl = open_loop(constant(0.1))
    with pytest.raises(ValueError, match=r"compensator: its network was trained on a linear axis "
                                         r"\(N, m/s\); the model is a rotary axis"):
        simulate_model(paper_actuator_model(), ctl, NNCompensator(net("linear")), duration=0.1)
    with pytest.raises(ValueError, match="the actuator .ActuatorParams. is a rotary axis"):
        simulate(paper_actuator(), ctl, NNCompensator(net("linear")), duration=0.1)
    linear = replace(paper_actuator_model(), units="linear")
    with pytest.raises(ValueError, match="trained on a rotary axis .N.m, rad/s.; the model is a linear"):
        simulate_model(linear, ctl, NNCompensator(net("rotary")), duration=0.1)
    for units, model in (("rotary", paper_actuator_model()), ("linear", linear)):
        simulate_model(model, ctl, NNCompensator(net(units)), duration=0.1)  # the same axis runs


def test_a_reference_above_the_nyquist_frequency_warns():
    # issue 26: sinusoid 0.1 at 300 Hz, Ts = 2 ms (Nyquist 250 Hz): the loop follows its
    # 200 Hz alias (|300 - 500|) and reported a steady-state error of 6.6e-15 deg, no warning
    from fricctl.simulate import sampling_warnings

    p = paper_actuator()
    assert p.sample_time == 0.002
    with pytest.warns(RuntimeWarning, match=r"the reference \(sinusoid 0.1 at 300 Hz\) is at or "
                                            r"above the Nyquist frequency 250 Hz .* at 200 Hz"):
        simulate(p, pd_control(2.0, 0.1, sinusoid(0.1, 300.0)), duration=0.1)
    with pytest.warns(RuntimeWarning, match=r"torque profile .* at 0 Hz"):  # 500 Hz: a constant
        simulate(p, open_loop(sinusoid(0.1, 500.0)), duration=0.1)
    assert sampling_warnings(pd_control(2.0, 0.1, sinusoid(0.1, 249.0)), 0.002) == []
    assert len(sampling_warnings(pd_control(2.0, 0.1, sinusoid(0.1, 250.0)), 0.002)) == 1
    # a sum of signals: its highest frequency; a sawtooth: its fundamental 1/period
    assert (sinusoid(1.0, 3.0) + sinusoid(1.0, 300.0) + constant(1.0)).frequency == 300.0
    assert sawtooth(1.0, 0.001).frequency == 1000.0 and constant(1.0).frequency is None
