"""IDIM-IV and DIDIM (issue 20): recovery where IDIM-LS is biased, closed loop, EMPS, CLI.

Records come from the package's own sampled loop on the paper's actuator at 1 kHz with a
Coulomb + viscous joint (the identified model class, so the truth is known exactly).
"""

import json
from dataclasses import replace

import numpy as np
import pytest

from fricctl import controllers as ctl
from fricctl import friction as fr
from fricctl import identify as I
from fricctl.identify.simulation import record_loop
from fricctl.params import paper_actuator
from fricctl.simulate import simulate

_P = paper_actuator()
# 1 kHz, 2000 counts per load revolution: the worst case (IDIM-LS inertia -70 %)
HARD = replace(_P, sample_time=0.001, encoder_counts=20)
LAW = fr.Viscous(_P.viscous) + fr.Coulomb(_P.coulomb)
TRUTH = dict(inertia=HARD.total_inertia, viscous=_P.viscous, coulomb=_P.coulomb)
OPEN = ctl.open_loop(ctl.sinusoid(0.4, 0.5) + ctl.sinusoid(0.15, 2.3))
CLOSED = ctl.pd_control(2.0, 0.05, ctl.sinusoid(1.0, 0.4) + ctl.sinusoid(0.3, 1.7))


def _record(controller, *, noisy: bool, seed: int = 1):
    return simulate(HARD, controller, duration=20.0, friction=LAW, quantize=noisy,
                    noise_std=0.005 if noisy else 0.0,
                    rng=np.random.default_rng(seed)).to_run()


def _errors(res) -> dict:
    return {k: res.parameters[k] / x - 1.0 for k, x in TRUTH.items()}


def _within_targets(res):
    # issue 20's targets: inertia and Coulomb within 5 %, viscous within 10 %
    e = _errors(res)
    assert abs(e["inertia"]) < 0.05 and abs(e["coulomb"]) < 0.05 and abs(e["viscous"]) < 0.10, e


@pytest.fixture(scope="module")
def noisy_open():
    return _record(OPEN, noisy=True)


@pytest.fixture(scope="module")
def noisy_closed():
    return _record(CLOSED, noisy=True)


def test_noise_free_open_loop_recovery():
    run = _record(OPEN, noisy=False)
    assert not record_loop(run).closed  # constant reference: the torque is replayed
    # DIDIM simulates exactly what generated the record: the truth to 1e-6
    dd = I.didim(run)
    for k, x in TRUTH.items():
        assert dd.parameters[k] == pytest.approx(x, rel=1e-6), k
    assert dd.method == "DIDIM" and dd.fit_percent > 99.9999
    # a position error correlated over more than a twentieth of the record: said
    assert len(dd.warnings) == 1 and "lower bounds" in dd.warnings[0]
    # IDIM-IV keeps the recipe's observations (Butterworth 100 Hz, decimation by 10): their
    # own error at the friction jumps is what is left, 0.6 % on this record; 1 % bound
    iv = I.idim_iv(run)
    for k, x in TRUTH.items():
        assert iv.parameters[k] == pytest.approx(x, rel=0.01), k
    assert iv.method == "IDIM-IV" and iv.warnings == ()


def test_quantised_noisy_open_loop_least_squares_biased_iv_didim_not(noisy_open):
    # the problem: the default estimator's least squares loses half the inertia or more
    ls = I.identify_run(noisy_open)
    assert _errors(ls)["inertia"] < -0.3
    iv = I.idim_iv(noisy_open)
    dd = I.didim(noisy_open)
    _within_targets(iv)
    _within_targets(dd)
    for k, x in TRUTH.items():  # IV: within 4 standard errors of the truth (seeded noise)
        j = iv.names.index(k)
        assert abs(iv.estimates[j] - x) < 4 * iv.std[j], k
    # DIDIM's std from the residual summed over blocks holds for a replayed position (the
    # white-error formula was 36 times too small here): the truth within 4 of them (seeded;
    # |z| < 1.6 on seeds 1-3), where the white formula put it 50 away
    for k, x in TRUTH.items():
        j = dd.names.index(k)
        assert abs(dd.estimates[j] - x) < 4 * dd.std[j], k


def test_quantised_noisy_closed_loop(noisy_closed):
    loop = record_loop(noisy_closed)
    # the PD gains, fitted to the record's torque in the loop's timing, are the controller's
    assert loop.closed and loop.kp == pytest.approx(2.0, rel=1e-9)
    assert loop.kd == pytest.approx(0.05, rel=1e-9)
    assert _errors(I.identify_run(noisy_closed))["inertia"] < -0.3
    iv = I.idim_iv(noisy_closed)
    dd = I.didim(noisy_closed)
    _within_targets(iv)
    _within_targets(dd)
    assert "closed loop" in iv.solver_status and "torque error" in dd.solver_status


def test_iv_covariance_is_the_papers(noisy_open):
    # std = sigma * sqrt(diag((Z^T X)^-1 Z^T Z (X^T Z)^-1)) rebuilt from the same instruments
    from fricctl.identify.iv import moving_rows
    from fricctl.identify.simulation import simulate_record

    iv = I.idim_iv(noisy_open)
    recipe = I.IdimRecipe()
    keep = moving_rows(noisy_open, recipe)
    obs = I.idim_observations(noisy_open, "coulomb_viscous", None, recipe)
    X, y = obs.decimated[keep], obs.torque[keep]
    # one more instrument update at the estimate moves it by less than its std / 10
    sim = simulate_record(noisy_open, iv.parameters, record_loop(noisy_open),
                          initial_velocity=0.0)
    from fricctl.datasets import Run

    Z = I.idim_observations(Run(t=noisy_open.t, torque=sim.torque, position=sim.position),
                            "coulomb_viscous", None, recipe).decimated[keep]
    theta = np.linalg.solve(Z.T @ X, Z.T @ y)
    assert np.all(np.abs(theta - iv.estimates) < 0.1 * iv.std)
    sigma = np.std(y - X @ iv.estimates, ddof=1)
    A = np.linalg.inv(Z.T @ X)
    np.testing.assert_allclose(iv.std, sigma * np.sqrt(np.diag(A @ Z.T @ Z @ A.T)), rtol=0.05)


def test_json_shape_is_identify_s(noisy_open):
    ls = I.idim_ls(noisy_open)
    for res in (I.idim_iv(noisy_open, max_iterations=2), ):
        d = json.loads(res.to_json())
        assert set(d) == set(json.loads(ls.to_json()))
        assert d["method"] == "IDIM-IV" and isinstance(d["warnings"], list)
        assert res.report().startswith("IDIM-IV: model coulomb_viscous")


def test_no_reference_column_falls_back_to_open_loop_with_a_warning(noisy_closed):
    from fricctl.datasets import Run

    bare = Run(t=noisy_closed.t, torque=noisy_closed.torque, position=noisy_closed.position)
    loop = record_loop(bare)
    assert not loop.closed and "no reference column" in loop.warnings[0]
    res = I.idim_iv(bare, max_iterations=2)
    assert any("no reference column" in w for w in res.warnings)


def test_bad_input_names_the_argument(noisy_open):
    with pytest.raises(ValueError, match="model: IDIM-IV needs a linear model"):
        I.idim_iv(noisy_open, model="stribeck")
    with pytest.raises(ValueError, match="model: DIDIM"):
        I.didim(noisy_open, model="stribeck")
    with pytest.raises(ValueError, match="output: 'torque' needs a closed-loop"):
        I.didim(noisy_open, output="torque")
    with pytest.raises(ValueError, match="output must be one of"):
        I.didim(noisy_open, output="velocity")
    with pytest.raises(ValueError, match="max_iterations"):
        I.idim_iv(noisy_open, max_iterations=0)
    with pytest.raises(ValueError, match="run must be a fricctl.datasets.Run"):
        I.didim({"t": [0.0]})
    from fricctl.datasets import Run

    bare = Run(t=noisy_open.t, torque=noisy_open.torque, position=noisy_open.position)
    with pytest.raises(ValueError, match="controller: the record has no reference"):
        record_loop(bare, CLOSED)


def test_cli_recipes(tmp_path, capsys, noisy_closed):
    from fricctl.cli import main

    path = noisy_closed.to_csv(tmp_path / "run.csv")
    assert main(["identify", str(path), "--recipe", "idim_iv", "--json",
                 "--controller", "2.0", "0.05"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["recipe"] == "idim_iv" and out["method"] == "IDIM-IV"
    assert abs(out["parameters"]["inertia"]["value"] / TRUTH["inertia"] - 1) < 0.05
    assert "given" in out["solver_status"]
    assert main(["identify", str(path), "--recipe", "plain", "--controller", "1", "1"]) == 2
    assert "--controller has no effect" in capsys.readouterr().err


@pytest.fixture(scope="module")
def emps_pair(data_dir):
    from fricctl import datasets

    return datasets.emps(data_dir), datasets.emps(data_dir, kind="validation")


def test_emps_iv_and_didim(emps_pair):
    est, val = emps_pair
    # EMPS's PD (README of the data): F = gtau*(kp*kv*(qg - q) - kv*dq)
    pd = ctl.pd_control(est.gtau * est.kp * est.kv, est.gtau * est.kv, ctl.constant(0.0))
    ls = I.idim_ls(est.run)
    iv = I.idim_iv(est.run, controller=pd)
    dd = I.didim(est.run, controller=pd)
    # a 5e-8 m encoder at 1 kHz: no errors in variables to speak of, so IV stays within
    # 1 std of the published IDIM-LS (M 95.1089 +- 0.1085 ...).  DIDIM simulates EMPS's PD
    # in the package's loop (a sample of delay, backward-difference velocity; EMPS has no
    # delay and a two-sample mean): 2 % on the mass (93.2 kg), within 3 % of LS
    for k in ls.names:
        j = ls.names.index(k)
        assert abs(iv.estimates[j] - ls.estimates[j]) < ls.std[j], k
        assert dd.estimates[j] == pytest.approx(ls.estimates[j], rel=0.03), k
    assert iv.warnings == () and dd.warnings == ()
    # cross-test validation on PULSES (predicted force, Script_IDIM_LS_CTV): as good as LS
    assert I.cross_validate(iv, val.run).relative_error < 6.1
    assert I.cross_validate(dd, val.run).relative_error < 6.1
