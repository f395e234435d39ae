import json

import numpy as np
import pytest

from fricctl import estimation as E
from fricctl import identify as I

TS = 0.002
GRID = 3.14e-5
# paper-like load-side values (fricctl.params): inertia, viscous 0.0169, Coulomb 0.144, static 0.18
TRUE = dict(inertia=0.0046, viscous=0.0169, coulomb=0.144, offset=0.003)
TRUE_ASYM = dict(inertia=0.0046, viscous_pos=0.015, coulomb_pos=0.13, viscous_neg=0.02,
                 coulomb_neg=0.16)
TRUE_STRIBECK = dict(inertia=0.0046, viscous=0.0169, coulomb=0.144, static=0.18,
                     stribeck_velocity=0.05, offset=0.003)


def _motion(duration=8.0):
    """Exact velocity/acceleration of a smooth trajectory that changes direction (closed form)."""
    t = np.arange(0.0, duration, TS)
    q = 1.2 * np.sin(1.3 * t) + 0.4 * np.sin(3.1 * t + 0.5)
    w = 1.2 * 1.3 * np.cos(1.3 * t) + 0.4 * 3.1 * np.cos(3.1 * t + 0.5)
    a = -1.2 * 1.3 ** 2 * np.sin(1.3 * t) - 0.4 * 3.1 ** 2 * np.sin(3.1 * t + 0.5)
    return t, q, w, a


def _law(p, w, a):
    """Independent numpy statement of the friction laws (module docstring of identify)."""
    tau = p["inertia"] * a + p.get("offset", 0.0)
    if "viscous_pos" in p:
        return tau + np.where(w > 0, p["viscous_pos"] * w + p["coulomb_pos"], 0) \
                   + np.where(w < 0, p["viscous_neg"] * w - p["coulomb_neg"], 0)
    tau = tau + p["viscous"] * w + p["coulomb"] * np.sign(w)
    if "static" in p:
        tau = tau + (p["static"] - p["coulomb"]) * np.exp(-(w / p["stribeck_velocity"]) ** 2) * np.sign(w)
    return tau


@pytest.mark.parametrize("model,true", [("coulomb_viscous", TRUE), ("asymmetric", TRUE_ASYM),
                                        ("stribeck", TRUE_STRIBECK)])
def test_noise_free_recovery(model, true):
    # noise-free data with the exact acceleration: parameters back to 1e-6 relative
    _, _, w, a = _motion()
    res = I.fit_friction(w, a, _law(true, w, a), model=model)
    assert res.names == I.model_names(model)
    for name, value in true.items():
        assert res.parameters[name] == pytest.approx(value, rel=1e-6), name
    assert res.relative_error < 1e-5


@pytest.mark.parametrize("model", ["coulomb_viscous", "asymmetric"])
def test_linear_case_matches_lstsq(model):
    # independent implementation: numpy.linalg.lstsq on the same regressor, to 1e-8
    rng = np.random.default_rng(7)
    _, _, w, a = _motion()
    true = TRUE if model == "coulomb_viscous" else TRUE_ASYM
    y = _law(true, w, a) + rng.normal(0.0, 0.02, w.size)
    res = I.fit_friction(w, a, y, model=model)
    X = I.regressor(model, w, a)
    ref, *_ = np.linalg.lstsq(X, y, rcond=None)
    np.testing.assert_allclose(res.estimates, ref, rtol=1e-8)
    # std errors: sigma^2 (X^T X)^-1 with sigma the sample std of the residual (IDIM-LS)
    e = y - X @ ref
    std = np.std(e, ddof=1) * np.sqrt(np.diag(np.linalg.inv(X.T @ X)))
    np.testing.assert_allclose(res.std, std, rtol=1e-6)
    assert res.condition_number == pytest.approx(np.linalg.cond(X), rel=1e-12)
    # relative error as EMPS eq. (11)
    assert res.relative_error == pytest.approx(100 * np.linalg.norm(e) / np.linalg.norm(y), rel=1e-6)


@pytest.mark.parametrize("estimator,opts", [("polynomial_segments", {}),
                                            ("butterworth_central", {"cutoff": 20.0})])
def test_noisy_encoder_within_four_std(estimator, opts):
    # seeded torque noise + encoder quantisation, derivatives from section-3 estimators:
    # every estimate within 4 standard errors of the truth
    rng = np.random.default_rng(2024)
    t, q, w, a = _motion(20.0)
    tau = _law(TRUE, w, a) + rng.normal(0.0, 0.01, t.size)
    qe = np.round(q / GRID) * GRID
    from fricctl.datasets import Run

    run = Run(t=t, torque=tau, position=qe, source="synthetic")
    res = I.identify_run(run, estimator=estimator, estimator_options=opts)
    for name, value in TRUE.items():
        k = res.names.index(name)
        assert abs(res.estimates[k] - value) < 4 * res.std[k], (name, res.estimates[k], res.std[k])


def test_stribeck_noisy_within_four_std():
    rng = np.random.default_rng(11)
    _, _, w, a = _motion(20.0)
    y = _law(TRUE_STRIBECK, w, a) + rng.normal(0.0, 0.005, w.size)
    res = I.fit_friction(w, a, y, model="stribeck")
    for name, value in TRUE_STRIBECK.items():
        k = res.names.index(name)
        assert abs(res.estimates[k] - value) < 4 * res.std[k], name


def test_generic_fit_nonlinear():
    # y = A exp(-x/tau): exact data, recovery to 1e-6 (noise-free)
    import casadi as ca

    x = np.linspace(0, 5, 200)
    y = 3.0 * np.exp(-x / 1.7)
    res = I.fit_least_squares(lambda th, r: th[0] * ca.exp(-r[0] / th[1]), x[:, None], y,
                              names=("A", "tau"), initial=[1.0, 1.0], lower=[0, 1e-3])
    np.testing.assert_allclose(res.estimates, [3.0, 1.7], rtol=1e-6)
    with pytest.raises(ValueError, match="no friction model"):
        res.predict([1.0], [0.0])


def test_result_report_predict_json():
    _, _, w, a = _motion()
    res = I.fit_friction(w, a, _law(TRUE, w, a), units="linear")
    text = res.report()
    for needle in ("Parameter inertia", "Condition number of the observation matrix",
                   "Relative error (%)", "Deviation of error", "[N*s/m]"):
        assert needle in text
    np.testing.assert_allclose(res.predict(w, a), _law(TRUE, w, a), atol=1e-9)
    d = json.loads(res.to_json())
    assert set(d["parameters"]) == set(TRUE)
    assert d["parameters"]["coulomb"]["value"] == pytest.approx(0.144, rel=1e-6)
    assert {"fit_percent", "condition_number"} <= set(d)
    assert res.fit_percent > 99.99  # noise-free


def test_inverse_dynamics_sign_convention():
    # friction has the sign of velocity: with a = 0 the torque opposes... i.e. equals friction
    p = dict(inertia=1.0, viscous_pos=1.0, coulomb_pos=2.0, viscous_neg=3.0, coulomb_neg=4.0)
    np.testing.assert_allclose(I.inverse_dynamics("asymmetric", p, [1.0, -1.0, 0.0], [0, 0, 0]),
                               [3.0, -7.0, 0.0])


def test_bad_input():
    _, _, w, a = _motion(1.0)
    y = _law(TRUE, w, a)
    with pytest.raises(ValueError, match="model must be one of"):
        I.fit_friction(w, a, y, model="lugre")
    with pytest.raises(ValueError, match="do not excite inertia"):
        I.fit_friction(w, np.zeros_like(a), y)
    bad = y.copy(); bad[3] = np.nan
    with pytest.raises(ValueError, match=r"torque holds NaN or inf \(nan\) at index 3"):
        I.fit_friction(w, a, bad)
    with pytest.raises(ValueError, match=f"acceleration must have {w.size} elements"):
        I.fit_friction(w, a[:-1], y)
    with pytest.raises(ValueError, match="initial: unknown"):
        I.fit_friction(w, a, y, initial={"mass": 1.0})
    with pytest.raises(ValueError, match="not linear"):
        I.regressor("stribeck", w, a)
    with pytest.raises(ValueError, match="rank deficient"):
        # offset with the asymmetric model and no rest samples: collinear columns
        I.fit_friction(w, a, y, model="asymmetric", offset=True)
    with pytest.raises(ValueError, match="parameters: expected"):
        I.inverse_dynamics("coulomb_viscous", {"inertia": 1.0}, w, a)


def test_plot_identification():
    from fricctl.figures import plot_identification

    t, _, w, a = _motion(1.0)
    res = I.fit_friction(w, a, _law(TRUE, w, a))
    ax = plot_identification(res, t=t)
    lines = ax.get_lines()
    assert len(lines) == 3
    np.testing.assert_array_equal(lines[0].get_ydata(), res.measured)
    np.testing.assert_array_equal(lines[2].get_ydata(), res.residual)
    assert "[N*m]" in ax.get_ylabel() and "[s]" in ax.get_xlabel()
    with pytest.raises(ValueError, match=f"t must have {res.n_samples} elements"):
        plot_identification(res, t=t[:-1])


def test_units_of_parameters_come_from_fricctl_units():
    # labels are fricctl.units' (one table for the package): linear axis -> N, N*s/m, m/s
    from fricctl.units import UNITS

    _, _, w, a = _motion()
    res = I.fit_friction(w, a, _law(TRUE_STRIBECK, w, a), model="stribeck", units="linear")
    unit = {n: p["unit"] for n, p in res.as_dict()["parameters"].items()}
    lin = UNITS["linear"]
    assert unit == {"inertia": lin.inertia, "viscous": lin.viscous, "coulomb": lin.torque,
                    "static": lin.torque, "stribeck_velocity": lin.velocity, "offset": lin.torque}
    assert I.parameter_unit("coulomb_neg", "rotary") == UNITS["rotary"].torque
    with pytest.raises(ValueError, match="units must be one of"):
        I.fit_friction(w, a, _law(TRUE, w, a), units="metric")


def test_argument_checks_name_the_argument():
    _, _, w, a = _motion(1.0)
    y = _law(TRUE, w, a)
    # NumPy scalars are real numbers: same prediction as Python floats (exact)
    p64 = {k: np.float64(x) for k, x in TRUE.items()}
    np.testing.assert_array_equal(I.inverse_dynamics("coulomb_viscous", p64, w, a),
                                  I.inverse_dynamics("coulomb_viscous", TRUE, w, a))
    assert I.IdimRecipe(filter_order=np.int64(2)).filter_order == 2
    with pytest.raises(ValueError, match="decimation must be an integer >= 1"):
        I.IdimRecipe(decimation=0)
    with pytest.raises(ValueError, match="cutoff must be > 0"):
        I.IdimRecipe(cutoff=-1.0)
    with pytest.raises(ValueError, match="lower holds NaN at index 1"):
        I.fit_least_squares(I.linear_prediction, I.regressor("coulomb_viscous", w, a), y,
                            names=I.model_names("coulomb_viscous"), initial=np.zeros(4),
                            lower=[0.0, np.nan, 0.0, -np.inf])
    with pytest.raises(ValueError, match="run must be a fricctl.datasets.Run"):
        I.identify_run({"t": w})
    with pytest.raises(ValueError, match="offset must be True or False"):
        I.model_names("stribeck", offset="yes")


def test_linear_prediction_is_the_regressor_product():
    # CasADi graph of linear_prediction evaluated numerically = X @ theta (numpy, 1e-12)
    import casadi as ca

    _, _, w, a = _motion(1.0)
    X = I.regressor("asymmetric", w, a)
    theta = np.array([TRUE_ASYM[n] for n in I.model_names("asymmetric")])
    th = ca.MX.sym("th", X.shape[1])
    rows = [ca.MX.sym(f"x{j}", 1, X.shape[0]) for j in range(X.shape[1])]
    f = ca.Function("f", [th, *rows], [I.linear_prediction(th, rows)])
    out = np.asarray(f(theta, *[X[:, j][None, :] for j in range(X.shape[1])])).ravel()
    np.testing.assert_allclose(out, X @ theta, rtol=1e-12, atol=1e-15)


def test_a_record_pushing_a_coefficient_negative_leaves_it_at_its_bound_flagged():
    # issue 15: bounds were applied in scaled space and relaxed by IPOPT, so inertia and viscous
    # came out negative.  Data whose least-squares viscous term is negative (-0.02): the
    # estimate must stay at 0, flagged as at its bound and not identified, and the JSON says so.
    import json

    from fricctl.identify import fit_friction

    rng = np.random.default_rng(7)
    w = rng.uniform(-2, 2, 3000)
    a = rng.normal(0, 5, 3000)
    y = 0.003 * a - 0.02 * w + 0.1 * np.sign(w) + rng.normal(0, 0.002, 3000)
    res = fit_friction(w, a, y, model="coulomb_viscous")
    p = res.parameters
    assert p["viscous"] == 0.0 and p["inertia"] > 0 and p["coulomb"] > 0
    i = res.names.index("viscous")
    assert res.at_bound[i] and not res.identified[i] and "bound" in res.notes()[i]
    d = json.loads(res.to_json())
    assert d["parameters"]["viscous"]["at_bound"] is True
    assert d["parameters"]["coulomb"]["identified"] is True


def test_a_constant_torque_record_is_refused():
    from fricctl.identify import fit_friction

    w = np.linspace(-1, 1, 200)
    with pytest.raises(ValueError, match="constant"):
        fit_friction(w, np.cos(w), np.zeros_like(w), model="coulomb_viscous")


def test_identify_run_drops_the_encoders_rest_for_a_filtering_estimator():
    # A sinusoid above breakaway on the paper's bench sticks at every reversal.  A Butterworth
    # velocity is never exactly 0, so only the encoder can say the joint is at rest; without
    # that test (rest_guard=None) the holding torques pull the Coulomb level down.
    from fricctl import controllers as ctl
    from fricctl.params import paper_actuator
    from fricctl.simulate import simulate

    p = paper_actuator()
    run = simulate(p, ctl.open_loop(ctl.sinusoid(0.3, 1.0)), duration=4.0).to_run()
    opts = {"cutoff": 20.0}
    fit = I.identify_run(run, estimator="butterworth_central", estimator_options=opts)
    kept = I.identify_run(run, estimator="butterworth_central", estimator_options=opts,
                          rest_guard=None)
    rest = E.at_rest(run.position)[50:run.n_samples - 50]
    assert kept.n_samples - fit.n_samples == rest.sum() > 50
    assert fit.parameters["coulomb"] == pytest.approx(p.coulomb, rel=0.1)
    assert fit.parameters["viscous"] == pytest.approx(p.viscous, rel=0.1)
    assert kept.parameters["coulomb"] < 0.7 * p.coulomb
    with pytest.raises(ValueError, match="rest_guard"):
        I.identify_run(run, rest_guard=0)


def test_an_estimate_of_zero_with_no_std_prints_no_nan_and_warns_nothing():
    # audit B: a coefficient at its bound with a std of 0 gave 0/0 in the relative std: "nan %"
    # in the report and a numpy "invalid value encountered in divide" warning on the CLI
    import dataclasses
    import warnings

    _, _, w, a = _motion()
    res = I.fit_friction(w, a, _law(TRUE, w, a), units="linear")
    i = res.names.index("viscous")
    est, std = res.estimates.copy(), res.std.copy()
    est[i], std[i] = 0.0, 0.0
    zero = dataclasses.replace(res, estimates=est, std=std)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        text = zero.report()
        assert np.isnan(zero.relative_std[i])
    line = next(x for x in text.splitlines() if x.startswith("Parameter viscous"))
    assert "nan" not in line and " - " in line


def test_identify_run_std_holds_for_a_coloured_residual():
    # audit C 6: identify_run's std was sigma*sqrt(diag((X^T X)^-1)), which assumes a white
    # residual; the filtered motion against the raw torque leaves one correlated over many
    # samples (the PD loop's dither at 5 kHz), and the std was then several times too small.
    # Reference: the same samples refitted by fit_friction (the white formula), and the block
    # covariance of fricctl.identify.uncertainty on its residual
    from dataclasses import replace

    from fricctl import controllers as ctl, friction as fr
    from fricctl.estimation import at_rest, estimate
    from fricctl.identify.uncertainty import block_covariance
    from fricctl.params import paper_actuator
    from fricctl.simulate import simulate

    p = paper_actuator()
    loop = ctl.pd_control(2.0, 0.05, ctl.sinusoid(1.0, 0.4) + ctl.sinusoid(0.3, 1.7))
    run = simulate(replace(p, sample_time=2e-4), loop, duration=4.0,
                   friction=fr.Viscous(p.viscous) + fr.Coulomb(p.coulomb), noise_std=0.005,
                   rng=np.random.default_rng(1)).to_run()
    res = I.identify_run(run)
    est = estimate(run.t, run.position, "butterworth_central")
    sl = slice(50, run.n_samples - 50)
    w, a = est.velocity[sl], est.acceleration[sl]
    keep = ~at_rest(run.position, guard=2)[sl] & (w != 0)
    white = I.fit_friction(w[keep], a[keep], run.torque[sl][keep])
    np.testing.assert_allclose(res.estimates, white.estimates, rtol=1e-9)
    block = block_covariance(I.regressor("coulomb_viscous", w[keep], a[keep]), white.residual)
    np.testing.assert_allclose(res.std, np.maximum(white.std, block.std), rtol=1e-9)
    assert res.std[0] > 1.5 * white.std[0]  # the inertia's (1.7x here): the residual is coloured
