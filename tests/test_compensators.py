"""The compensators: registry, validation, each one's step against an independent
implementation replayed on the loop's own records, their physics, and their C export."""
import math
import shutil
import subprocess

import numpy as np
import pytest
from scipy.signal import lfilter

import fricctl.compensators as C
from fricctl.compensators import (CoulombCompensator, DisturbanceObserver, IntegralAction,
                                  LuGreObserver, NNCompensator, NoCompensation, StaticFeedforward,
                                  available, design_ki, make)
from fricctl.controllers import pd_control, sinusoid, step
from fricctl.design import LinearLoop
from fricctl.friction import FrictionModel, LuGre
from fricctl.plant import JointModel
from fricctl.params import paper_actuator
from fricctl.simulate import simulate, simulate_batch, simulate_model

P = paper_actuator()
# the paper's PD (rise time 0.3 s, damping 0.9; fricctl.design.paper_designs), rounded
KP, KD = 1.213, 0.0892
LOOP = LinearLoop(kp=KP, kd=KD, inertia=P.total_inertia, viscous=P.viscous,
                  sample_time=P.sample_time)
#: Options a compensator needs beyond the paper's actuator and its PD (no LuGre law there).
OPTIONS = {"lugre_observer": {"sigma0": 1000.0, "sigma1": 1.0}}
#: The compensators that run a trained network (they need the option ``net``).
NETS = ("nn", "nn_confirmed")
#: Every registered compensator that declares a state (read from the registry: a new one is
#: tested here without an edit); each must run in the compiled loop.
NEW = tuple(n for n in available() if n not in NETS
            and make(n, P, LOOP, **OPTIONS.get(n, {})).compiled().state.size > 0)
CC = shutil.which("gcc") or shutil.which("cc")


def _step_run(name, amplitude=0.2, duration=1.0, **options):
    comp = make(name, P, LOOP, **{**OPTIONS.get(name, {}), **options})
    return comp, simulate(P, pd_control(KP, KD, step(amplitude)), comp, duration=duration)


# ---------------------------------------------------------------- registry and validation
def test_registry_lists_every_module_once_with_its_kind():
    from pathlib import Path

    modules = {p.stem for p in Path(C.__file__).parent.glob("*.py")} - {"__init__", "base",
                                                                        "compiled", "c_export"}
    assert len(available()) == len(modules) == len(set(available()))
    assert [C.get(n).kind for n in available()] == sorted(C.get(n).kind for n in available())
    # the first three kinds keep their ids (their parameter vectors are pinned by the tests)
    assert (C.COMP_NONE, C.COMP_COULOMB, C.COMP_NN) == (0, 1, 2)


@pytest.mark.parametrize("name", [n for n in C.REGISTRY if n not in NETS])
def test_make_builds_each_compensator_of_its_kind(name):
    comp = make(name, P, LOOP, **OPTIONS.get(name, {}))
    assert isinstance(comp, C.get(name).cls)
    assert comp.compiled().kind == C.get(name).kind


def test_make_refuses_unknown_names_and_options():
    with pytest.raises(ValueError, match="unknown compensator 'pid'.*integral"):
        make("pid", P, LOOP)
    with pytest.raises(ValueError, match="dob.*bandwith"):
        make("dob", P, LOOP, bandwith=50.0)
    with pytest.raises(ValueError, match="integral: needs the PD design"):
        make("integral", P)
    with pytest.raises(ValueError, match="sigma0: the model has no LuGre law"):
        make("lugre_observer", P)
    with pytest.raises(ValueError, match="net must be a trained"):
        make("nn", P, net="net.json")


@pytest.mark.parametrize("build, match", [
    (lambda: StaticFeedforward(coulomb_pos=-0.1, coulomb_neg=0.1), "coulomb_pos"),
    (lambda: StaticFeedforward(coulomb_pos=0.1, coulomb_neg=0.1, stribeck_velocity=0.0),
     "stribeck_velocity"),
    (lambda: StaticFeedforward(coulomb_pos=0.1, coulomb_neg=0.1, velocity="desired"), "velocity"),
    (lambda: LuGreObserver(sigma0=0.0, coulomb_pos=0.1, coulomb_neg=0.1), "sigma0"),
    (lambda: LuGreObserver(sigma0=1e3, coulomb_pos=0.0, coulomb_neg=0.1), "coulomb_pos"),
    (lambda: LuGreObserver(sigma0=1e3, coulomb_pos=0.1, coulomb_neg=0.1, gain=-1.0), "gain"),
    (lambda: DisturbanceObserver(inertia=0.0, bandwidth=50.0), "inertia"),
    (lambda: DisturbanceObserver(inertia=1e-3, bandwidth=math.nan), "bandwidth"),
    (lambda: IntegralAction(ki=0.0), "ki"),
    (lambda: IntegralAction(ki=1.0, max_torque=-1.0), "max_torque"),
    (lambda: IntegralAction(ki=1.0, max_torque=math.nan), "max_torque"),
    (lambda: CoulombCompensator.from_model(P, level="peak"), "level"),
    (lambda: CoulombCompensator.from_model(FrictionModel()), "no coulomb level"),
    (lambda: design_ki(LinearLoop(kp=0.0, kd=0.1, inertia=1e-3, viscous=0.0, sample_time=1e-3)),
     "kp > 0"),
])
def test_non_physical_parameters_are_refused(build, match):
    with pytest.raises(ValueError, match=match):
        build()


def test_a_compensator_with_a_state_is_not_a_function_of_tm_and_omega():
    with pytest.raises(ValueError, match="has a state"):
        make("dob", P)(0.1, 0.2)
    # the memoryless feedforward is one: the identified curve, here at w = ws (hand value:
    # Fc + (Fs - Fc)/e + b*ws = 0.144 + 0.036/e + 0.0169*0.02)
    ff = make("feedforward", P)
    assert float(ff(0.0, 0.02)) == pytest.approx(0.144 + 0.036 / math.e + 0.0169 * 0.02, rel=1e-14)
    assert float(ff(0.0, 0.0)) == 0.0


def test_coulomb_levels_are_the_models_sliding_and_breakaway_levels():
    fr = P.friction_model().scaled(0.9)
    assert CoulombCompensator.from_model(fr).coulomb_pos == pytest.approx(0.9 * P.coulomb, rel=1e-15)
    assert CoulombCompensator.from_model(fr, level="breakaway").coulomb_neg == pytest.approx(
        0.9 * P.static, rel=1e-15)


def test_design_ki_places_the_zero_a_decade_below_the_bandwidth():
    # closed form of the -3 dB bandwidth of Kp/(I s^2 + (b+Kd) s + Kp): solve |T(jw)|^2 = 10^(-0.3)
    wn, zeta = LOOP.wn, LOOP.zeta
    c = 10 ** 0.3
    x = (-(4 * zeta ** 2 - 2) + math.sqrt((4 * zeta ** 2 - 2) ** 2 + 4 * (c - 1))) / 2
    wb = wn * math.sqrt(x)
    assert design_ki(LOOP) == pytest.approx(KP * wb / 10, rel=1e-4)  # control's search tolerance
    assert design_ki(LOOP, decade=5) == pytest.approx(2 * design_ki(LOOP), rel=1e-12)
    # Routh: I s^3 + (b+Kd) s^2 + Kp s + Ki is unstable for Ki > (b+Kd) Kp / I; a lightly
    # damped loop (wn = 10 rad/s, zeta = 0.05, wb = 15.5 rad/s) crosses it at decade 15.5
    light = LinearLoop(kp=1.0, kd=0.0, inertia=0.01, viscous=0.01, sample_time=1e-3)
    with pytest.raises(ValueError, match="unstable"):
        design_ki(light, decade=10.0)
    assert design_ki(light, decade=20.0) > 0


# ---------------------------------------------------- the compiled step against a reference
@pytest.mark.parametrize("name", NEW)
def test_each_new_compensator_runs_compiled_and_its_state_evolves(name):
    assert {"feedforward", "lugre_observer", "dob", "integral"} <= set(NEW)
    comp, r = _step_run(name)
    assert r.info.loop == "compiled" and r.info.compensator == comp.name
    assert comp.stateful or name == "feedforward"
    assert np.unique(r.friction_est).size > 10  # not a constant: the step ran, the state moved


def test_feedforward_is_the_friction_laws_own_curve_at_the_measured_velocity():
    # reference: FrictionModel.torque (the friction laws' numpy terms) while sliding, 0 at rest
    comp, r = _step_run("feedforward", amplitude=0.5)
    moving = r.omega_hat != 0.0
    assert moving.sum() > 50
    np.testing.assert_allclose(r.friction_est[moving],
                               P.friction_model().torque(r.omega_hat[moving]), rtol=1e-12, atol=0)
    assert np.all(r.friction_est[~moving] == 0.0)


def test_feedforward_at_the_reference_velocity():
    comp = make("feedforward", P, velocity="reference")
    r = simulate(P, pd_control(KP, KD, sinusoid(0.3, 0.5)), comp, duration=1.0)
    w = np.r_[0.0, np.diff(r.reference) / P.sample_time]  # 0 at the first sample (no r_{-1})
    expect = np.where(w != 0.0, P.friction_model().torque(w), 0.0)
    np.testing.assert_allclose(r.friction_est, expect, rtol=1e-9, atol=1e-15)


def test_dob_is_a_first_order_filter_of_the_raw_disturbance():
    # reference: scipy's lfilter of Q(z) = (1-a)/(1 - a z^-1) on the raw disturbance
    # (Tm_{k-1} + Tm_{k-2})/2 - J_n (w_k - w_{k-1})/Ts, rebuilt from the records
    comp, r = _step_run("dob")
    ts, a = P.sample_time, math.exp(-comp.bandwidth * P.sample_time)
    tm1 = np.r_[0.0, r.torque_motor[:-1]]
    tm2 = np.r_[0.0, 0.0, r.torque_motor[:-2]]
    raw = 0.5 * (tm1 + tm2) - comp.inertia * np.diff(np.r_[0.0, r.omega_hat]) / ts
    np.testing.assert_allclose(r.friction_est, lfilter([1 - a], [1, -a], raw), rtol=1e-9,
                               atol=1e-12 * P.max_torque)


def test_integral_action_is_ki_times_the_clamped_integral_of_the_error():
    comp, r = _step_run("integral", amplitude=0.3)
    e = r.reference - r.q_meas
    # no sample at the torque limit in this run: the clamp never acts, the integral is cumsum
    assert np.all(np.abs(r.torque_motor) < comp.max_torque)
    np.testing.assert_allclose(r.friction_est, comp.ki * P.sample_time * np.cumsum(e),
                               rtol=1e-9, atol=1e-12 * np.max(np.abs(r.friction_est)))


def test_integral_anti_windup_holds_the_integrator_at_the_torque_limit():
    # a step far beyond what the torque limit moves in the run: the command saturates, the
    # integrator must hold while saturated (clamping), never exceed Tmax, and stay below the
    # plain integral of the error (which winds up)
    comp = IntegralAction(ki=50.0, max_torque=P.max_torque)
    r = simulate(P, pd_control(KP, KD, step(20.0)), comp, duration=1.0)
    e = r.reference - r.q_meas
    sat = (np.abs(r.torque_motor) >= P.max_torque) & (e * r.torque_motor > 0)
    assert sat.sum() > 100
    held = np.flatnonzero(sat[1:])  # saturated at k, pushing further: no integration at k
    assert np.all(np.diff(r.friction_est)[held] == 0.0)
    assert np.max(np.abs(r.friction_est)) <= P.max_torque
    plain = comp.ki * P.sample_time * np.cumsum(r.reference - r.q_meas)
    assert np.max(np.abs(r.friction_est)) < 0.5 * np.max(np.abs(plain))


def _lugre_reference(comp, r, n):
    """The observer's ODE z' = u - lam z (w = omega_hat_k, e = y_k - r_k held over the
    interval) advanced by the matrix exponential of its augmented system [[-lam, u], [0, 0]]
    (scipy.linalg.expm: the exact solution as c2d computes it, not the closed form the
    step uses), then F_hat_k."""
    from scipy.linalg import expm

    z, out = 0.0, []
    for k in range(n):
        w, e = r.omega_hat[k], r.q_meas[k] - r.reference[k]
        fc, ds, b = ((comp.coulomb_pos, comp.stribeck_pos, comp.viscous_pos) if w >= 0 else
                     (comp.coulomb_neg, comp.stribeck_neg, comp.viscous_neg))
        g = fc + ds * math.exp(-(abs(w) / comp.stribeck_velocity) ** 2)
        lam, u = comp.sigma0 * abs(w) / g, w - comp.gain * e
        z = (expm(np.array([[-lam, u], [0.0, 0.0]]) * P.sample_time) @ [z, 1.0])[0]
        out.append(comp.sigma0 * z + comp.sigma1 * (u - lam * z) + b * w)
    return np.array(out)


@pytest.mark.parametrize("gain", [0.0, 20.0])
def test_lugre_observer_step_is_the_exact_solution_of_its_ode(gain):
    comp, r = _step_run("lugre_observer", amplitude=0.3, duration=0.4, gain=gain)
    n = 150
    assert np.count_nonzero(r.omega_hat[:n]) > 20
    np.testing.assert_allclose(r.friction_est[:n], _lugre_reference(comp, r, n), rtol=1e-7,
                               atol=1e-9 * P.static)


def test_a_batch_may_mix_compensators_and_each_run_is_its_single_run():
    comps = [NoCompensation(), make("dob", P), make("integral", P, LOOP),
             make("feedforward", P, velocity="reference"), make("coulomb", P)]
    c = pd_control(KP, KD, step(0.3))
    b = simulate_batch(P, c, comps, duration=0.6)
    for i, comp in enumerate(comps):
        one = simulate(P, c, comp, duration=0.6)
        assert b[i].info.loop == one.info.loop == "compiled"
        np.testing.assert_array_equal(b[i].friction_est, one.friction_est)
        np.testing.assert_array_equal(b[i].q, one.q)


def test_a_stateful_compensator_cannot_share_a_batch_with_a_python_estimator():
    with pytest.raises(ValueError, match="has a state: compiled loop only"):
        simulate_batch(P, pd_control(KP, KD, step(0.3)),
                       [NNCompensator(lambda tm, w: 0.0 * w), make("dob", P)], duration=0.1)


# ------------------------------------------------------------------------------ physics
def _load_plant(load):
    """The paper's joint without friction, a constant load torque ``load`` [N*m] (the
    model's offset: the joint receives Tm - offset)."""
    return JointModel(inertia=P.total_inertia, friction=FrictionModel(), offset=load,
                      sample_time=P.sample_time, encoder_resolution=P.encoder_resolution,
                      max_torque=P.max_torque)


@pytest.mark.parametrize("load", [0.05, -0.1])
def test_dob_removes_a_constant_load_at_steady_state(load):
    # reference: the PD alone settles at e = load/Kp (closed form of the linear loop); the
    # DOB estimates the load and cancels it: the error falls to the encoder's count
    m = _load_plant(load)
    c = pd_control(KP, KD, step(0.2))
    pd = simulate_model(m, c, duration=4.0)
    dob = simulate_model(m, c, make("dob", m), duration=4.0)
    assert dob.info.loop == "compiled"
    assert pd.reference[-1] - pd.q[-1] == pytest.approx(load / KP, abs=2 * P.encoder_resolution)
    assert abs(dob.reference[-1] - dob.q[-1]) <= 2 * P.encoder_resolution
    assert dob.friction_est[-1] == pytest.approx(load, rel=0.05)


@pytest.mark.parametrize("amplitude", [0.05, 0.2, 0.5236, -0.3])
def test_integral_action_drives_the_step_error_below_the_pds(amplitude):
    # on the paper's actuator (static friction 0.18 N*m) the PD stops in its dead zone
    # |e| <= Fs/Kp; the integral builds the torque friction holds against it
    c = pd_control(KP, KD, step(amplitude))
    pd = simulate(P, c, duration=4.0)
    pid = simulate(P, c, make("integral", P, LOOP), duration=4.0)
    assert abs(pid.steady_state_error(0.5)) < 0.5 * abs(pd.steady_state_error(0.5))


def test_integral_action_removes_a_constant_load():
    m = _load_plant(0.1)
    pid = simulate_model(m, pd_control(KP, KD, step(0.2)), make("integral", m, LOOP),
                         duration=6.0)
    assert abs(pid.reference[-1] - pid.q[-1]) <= 2 * P.encoder_resolution


@pytest.mark.parametrize("amplitude, frequency", [(0.2, 0.5), (0.05, 1.0), (0.5, 0.25)])
def test_lugre_observer_tracks_the_friction_of_a_lugre_plant(amplitude, frequency):
    # the plant's friction is LuGre (the paper's static curve + presliding bristles); the
    # observer built from the same identified model follows it far better than the static
    # sign estimate Fc*sign(omega_hat) does on the same record (the presliding and the
    # Stribeck dip are what the sign cannot see)
    fr = P.friction_model() + LuGre(1000.0, 1.0)
    obs = LuGreObserver.from_model(fr)
    r = simulate(P, pd_control(KP, KD, sinusoid(amplitude, frequency)), obs, friction=fr,
                 duration=4.0)
    assert r.info.loop == "compiled"
    sign = CoulombCompensator.from_model(fr)(0.0, r.omega_hat)
    rms_obs = np.sqrt(np.mean((r.friction_est - r.friction) ** 2))
    rms_sign = np.sqrt(np.mean((sign - r.friction) ** 2))
    assert rms_obs < 0.5 * rms_sign


# ----------------------------------------------------------------------------- C export
def _c_run(tmp_path, comp, r, name):
    from fricctl.compensators.c_export import c_header, c_source

    (tmp_path / f"{name}.c").write_text(c_source(comp, name=name))
    (tmp_path / f"{name}.h").write_text(c_header(comp, name=name))
    main = f"""#include <stdio.h>
#include "{name}.h"
int main(void) {{
    {name}_state st; double tm, w, y, r, tc;
    {name}_init(&st, {P.sample_time!r});
    while (scanf("%lf %lf %lf %lf %lf", &tm, &w, &y, &r, &tc) == 5)
        printf("%.17g\\n", {name}_step(&st, tm, w, y, r, tc));
    return 0;
}}
"""
    (tmp_path / "main.c").write_text(main)
    exe = tmp_path / "run"
    subprocess.run([CC, "-std=c99", "-Wall", "-Wextra", "-Werror", "-O2", "-o", str(exe),
                    str(tmp_path / "main.c"), str(tmp_path / f"{name}.c"), "-lm"], check=True,
                   capture_output=True, text=True)
    rows = np.column_stack([r.torque_motor, r.omega_hat, r.q_meas, r.reference, r.torque_cmd])
    text = "\n".join(" ".join(f"{x:.17g}" for x in row) for row in rows)
    out = subprocess.run([str(exe)], input=text, check=True, capture_output=True, text=True)
    return np.array(out.stdout.split(), dtype=float)


@pytest.mark.skipif(CC is None, reason="no C compiler (gcc or cc) on PATH")
@pytest.mark.parametrize("name, options", [("dob", {}), ("integral", {}), ("feedforward", {}),
                                           ("feedforward", {"velocity": "reference"}),
                                           ("lugre_observer", {**OPTIONS["lugre_observer"],
                                                               "gain": 20.0})])
def test_c_export_steps_as_the_compiled_loop_does(tmp_path, name, options):
    from fricctl.compensators.c_export import exportable

    assert {"dob", "integral", "feedforward", "lugre_observer"} <= set(exportable())
    comp = make(name, P, LOOP, **options)
    ref = sinusoid(0.3, 1.0) if options.get("velocity") else step(0.3)
    r = simulate(P, pd_control(KP, KD, ref), comp, duration=0.5)
    got = _c_run(tmp_path, comp, r, f"axis_{name}")
    assert got.size == r.t.size
    np.testing.assert_allclose(got, r.friction_est, rtol=1e-12, atol=1e-15)


def test_c_export_refuses_a_compensator_without_one():
    from fricctl.compensators.c_export import c_source

    with pytest.raises(ValueError, match="no C export.*dob"):
        c_source(make("coulomb", P))
    with pytest.raises(ValueError, match="C keyword"):
        c_source(make("dob", P), name="int")


# ------------------------------------------------------------------------------------ CLI
def test_cli_simulate_takes_every_registered_name_and_builds_it_from_the_model(capsys):
    import json

    from fricctl.cli import main
    from fricctl.cli.simulate import compensations

    assert compensations() == available()
    common = ["simulate", "--controller", "pd", "--kp", str(KP), "--kd", str(KD), "--reference",
              "step:0.2", "--duration", "3", "--json"]
    names = [n for n in available() if n not in (*NETS, "lugre_observer")]
    assert main([*common, "--compensation", ",".join(names)]) == 0
    runs = {r["compensator"]: r for r in json.loads(capsys.readouterr().out)["runs"]}
    assert set(runs) == {make(n, P, LOOP).name for n in names}
    # the same runs as the library's (the CLI builds them with make from the actuator and gains)
    for n in names:
        r = simulate(P, pd_control(KP, KD, step(0.2)), make(n, P, LOOP), duration=3.0)
        assert runs[make(n, P, LOOP).name]["steady_state_error"]["value"] == pytest.approx(
            r.steady_state_error(0.5), rel=1e-12, abs=1e-15)


@pytest.mark.parametrize("argv, words", [
    (["--compensation", "dobb"], "unknown compensation 'dobb'.*integral"),
    (["--compensation", "lugre_observer"], "lugre_observer: the model has no LuGre law.*--sigma0 \\[N\\*m/rad\\]"),
    (["--compensation", "coulomb", "--c-source", "x.c"], "applies to --compensation nn or to one"),
])
def test_cli_refusals_name_the_compensation(argv, words, capsys):
    import re

    from fricctl.cli import main

    assert main(["simulate", "--controller", "pd", "--kp", "1", "--kd", "0.1", "--reference",
                 "step:0.1", "--duration", "0.1", *argv]) == 2
    err = capsys.readouterr().err
    assert re.search(words, err) and err.count("\n") == 1  # one line, no traceback


def test_cli_open_loop_refuses_integral_action(capsys):
    from fricctl.cli import main

    assert main(["simulate", "--torque", "step:0.2", "--duration", "0.1", "--compensation",
                 "integral"]) == 2
    assert "extends a P/PD controller" in capsys.readouterr().err


@pytest.mark.skipif(CC is None, reason="no C compiler (gcc or cc) on PATH")
def test_cli_writes_the_c_source_of_a_dob(tmp_path, capsys):
    from fricctl.cli import main

    c = tmp_path / "axis_dob.c"
    assert main(["simulate", "--controller", "pd", "--kp", "1", "--kd", "0.1", "--reference",
                 "step:0.1", "--duration", "0.1", "--compensation", "dob", "--c-source",
                 str(c)]) == 0
    assert "double axis_dob_step(axis_dob_state *st" in c.with_suffix(".h").read_text()
    subprocess.run([CC, "-std=c99", "-Wall", "-Wextra", "-Werror", "-c", str(c), "-o",
                    str(tmp_path / "x.o")], check=True, cwd=tmp_path)


def test_c_header_states_the_compensation_scale():
    from fricctl.compensators import make
    from fricctl.compensators.c_export import c_header
    from fricctl.params import paper_actuator

    h = c_header(make("dob", paper_actuator(), scale=0.95), name="axis")
    assert "#define AXIS_SCALE 0.94999999999999996" in h
