"""Reproduce the published IDIM-LS results of the EMPS benchmark.

Reference: A. Janot, M. Gautier, M. Brunot, "Data Set and Reference Models of EMPS",
Workshop on Nonlinear System Identification Benchmarks, 2019 (EMPS_Description.pdf,
sec. 3.4 and 4.2; values printed there with 4 decimals).
"""

import numpy as np
import pytest

from fricctl import datasets, identify


@pytest.fixture(scope="module")
def est_run(data_dir):
    return datasets.emps(data_dir).run


@pytest.fixture(scope="module")
def idim(est_run):
    return identify.idim_ls(est_run)


def _close(value, published, tol=1e-4):
    # published numbers carry 4 decimals: agree to the last printed digit (+ rounding)
    return abs(value - published) <= tol + 5e-5


def test_symmetric_model_matches_published(idim):
    published = {"inertia": (95.1089, 0.1085), "viscous": (203.5034, 1.1460),
                 "coulomb": (20.3935, 0.1012), "offset": (-3.1648, 0.0444)}
    for name, (value, std) in published.items():
        k = idim.names.index(name)
        assert _close(idim.estimates[k], value), name   # issue asks 0.1 %; we get 4 decimals
        assert _close(idim.std[k], std), name
    assert _close(idim.relative_error, 4.0834)
    assert _close(idim.condition_number, 25.9883)
    assert _close(idim.error_norm, 108.7569)
    assert _close(idim.error_std, 2.1843)
    np.testing.assert_allclose(idim.abs_diag_r, [64.1376, 13.9005, 69.1706, 157.4483], atol=1.5e-4)
    assert idim.n_samples == 2480


def test_cross_validation_on_pulses(idim, data_dir):
    ctv = identify.cross_validate(idim, datasets.emps(data_dir, kind="validation").run)
    # Script_IDIM_LS_CTV output: relative error 5.9824 %, cond 26.0217, error norm 169.4876
    assert _close(ctv.relative_error, 5.9824)
    assert _close(ctv.condition_number, 26.0217)
    assert _close(ctv.error_norm, 169.4876)
    assert _close(ctv.error_std, 3.4039)


def test_asymmetric_model_matches_published(est_run):
    res = identify.idim_ls(est_run, model="asymmetric")
    published = {"inertia": (95.1540, 0.0827), "viscous_pos": (166.7061, 1.2326),
                 "coulomb_pos": (20.1440, 0.1088), "viscous_neg": (240.4236, 1.2346),
                 "coulomb_neg": (20.6277, 0.1091)}
    for name, (value, std) in published.items():
        k = res.names.index(name)
        assert _close(res.estimates[k], value), name
        assert _close(res.std[k], std), name
    assert _close(res.relative_error, 3.1117)
    assert _close(res.condition_number, 26.0197)


def test_plain_least_squares_within_one_percent(est_run):
    # issue 4, sec. 6: no decimation, default estimator: within 1 % of the published values
    res = identify.identify_run(est_run)
    for name, value in {"inertia": 95.1089, "viscous": 203.5034, "coulomb": 20.3935,
                        "offset": -3.1648}.items():
        assert res.parameters[name] == pytest.approx(value, rel=0.01), name
