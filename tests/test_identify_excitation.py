"""What a record excites, and what a fit may call identified (audit C, items 1, 4 and 8).

Records come from the package's sampled loop on the paper's actuator at 1 kHz (Coulomb +
viscous, offset 0), or are written by hand from a friction law on an analytic trajectory.
Every test failed before its fix: a one-way record gave the default recipe a Coulomb level
and an offset of +-45 N*m to 0.01 % (truth 0.144 and 0); idim_iv raised an IndexError or
numpy's "Singular matrix"; the asymmetric model on a one-way record said "scale holds NaN or
inf"; a Stribeck fit printed a breakaway below the Coulomb level as identified.
"""

import json
from dataclasses import replace

import numpy as np
import pytest

from fricctl import controllers as ctl
from fricctl import friction as fr
from fricctl import identify as I
from fricctl.cli import main
from fricctl.datasets import Run
from fricctl.params import paper_actuator
from fricctl.simulate import simulate

_P = replace(paper_actuator(), sample_time=0.001)
LAW = fr.Viscous(_P.viscous) + fr.Coulomb(_P.coulomb)
#: a three-tone reference: the joint reverses within its first 0.2 s
TONES = ctl.pd_control(20.0, 0.5, ctl.sinusoid(1.0, 0.3) + ctl.sinusoid(0.4, 1.1, 1.0)
                       + ctl.sinusoid(0.2, 2.3, 2.0))


def _record(controller, duration: float) -> Run:
    return simulate(_P, controller, duration=duration, friction=LAW, noise_std=0.002,
                    rng=np.random.default_rng(3)).to_run()


@pytest.fixture(scope="module")
def one_way():
    # PD tracking a ramp of 2 rad/s from rest: the joint slides forward only, 3 s
    return _record(ctl.pd_control(5.0, 0.1, ctl.sawtooth(200.0, 100.0)), 3.0)


def test_default_refuses_coulomb_and_offset_on_a_one_way_record(one_way):
    # before: coulomb 45.01 +- 0.005 and offset -44.83 +- 0.005 N*m as identified (the
    # low-passed sign and constant columns differ by the filter's smear of the first sample)
    assert np.all(np.diff(one_way.position) >= 0)
    with pytest.raises(ValueError, match=r"slides \d+ samples forward and 0 backward, and a "
                                         r"direction needs \d+ .*: coulomb and offset are one "
                                         r"constant torque") as exc:
        I.identify_record(one_way, validate=False)
    assert "--no-offset" in str(exc.value)
    # without the offset the record says what it can: a Coulomb level (the truth within 3 std)
    res = I.identify_record(one_way, offset=False, validate=False).result
    fc, s = res.parameters["coulomb"], res.std[res.names.index("coulomb")]
    assert abs(fc - _P.coulomb) < 3 * s


def test_the_cli_refuses_it_in_one_line_and_writes_nothing(one_way, tmp_path, capsys):
    path = one_way.to_csv(tmp_path / "oneway.csv")
    out = tmp_path / "m.json"
    assert main(["identify", str(path), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "coulomb and offset are one constant torque" in err, err
    assert not out.exists()


@pytest.mark.parametrize("recipe", ["idim_ls", "didim", "idim_iv", "auto"])
def test_asymmetric_on_a_one_way_record_names_the_backward_parameters(one_way, tmp_path,
                                                                         capsys, recipe):
    # before: "scale holds NaN or inf (inf) at index 3" (idim_ls, didim, idim_iv)
    path = one_way.to_csv(tmp_path / "oneway.csv")
    assert main(["identify", str(path), "--model", "asymmetric", "--recipe", recipe]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert "viscous_neg and coulomb_neg act only while it slides backward" in err, err


def test_idim_iv_on_a_record_shorter_than_its_window_says_the_minimum():
    # before: IndexError (the rest window outgrew the record); 49 + 2*(20 + 40) + 1 samples
    run = _record(TONES, 0.12)
    with pytest.raises(ValueError, match=r"too short for the IDIM recipe's filters: 120 samples, "
                                         r"at least 170 needed \(0\.17 s"):
        I.idim_iv(run)


def test_idim_iv_with_too_few_rows_clear_of_rest_says_so():
    # before: numpy's "Singular matrix" (no row of the 0.25 s record is clear of rest)
    run = _record(TONES, 0.25)
    with pytest.raises(ValueError, match=r"IDIM-IV: \d of the record's 21 decimated rows lie "
                                         r"clear of rest .* fewer than the 5 needed to identify "
                                         r"inertia, viscous, coulomb, offset"):
        I.idim_iv(run)


def _dip_csv(path, static=0.1, coulomb=0.2):
    # a Stribeck law whose "breakaway" lies below its Coulomb level, on an analytic
    # trajectory: the fit recovers the dip, which no model file can hold
    t = np.arange(0.0, 10.0, 0.002)
    q = 1.2 * np.sin(1.3 * t)
    w = 1.2 * 1.3 * np.cos(1.3 * t)
    a = -1.2 * 1.3 ** 2 * np.sin(1.3 * t)
    tau = (0.0046 * a + 0.0169 * w
           + np.sign(w) * (coulomb + (static - coulomb) * np.exp(-(w / 0.3) ** 2)))
    return Run(t=t, torque=tau, position=q, source="dip").to_csv(path)


def test_a_breakaway_below_coulomb_is_flagged_where_it_is_printed(tmp_path, capsys):
    path = _dip_csv(tmp_path / "dip.csv")
    assert main(["identify", str(path), "--recipe", "plain", "--model", "stribeck",
                 "--json"]) == 0
    captured = capsys.readouterr()
    out = json.loads(captured.out)
    p = out["parameters"]
    assert p["static"]["value"] < p["coulomb"]["value"]  # the law's dip, recovered
    assert not p["static"]["identified"] and "non-physical" in p["static"]["note"]
    assert [w for w in out["warnings"] if w.startswith("static: breakaway level")]
    assert "warning: static: breakaway level" in captured.err
    # the table says it next to the estimate, and --out refuses the same fit
    assert main(["identify", str(path), "--recipe", "plain", "--model", "stribeck"]) == 0
    row = [ln for ln in capsys.readouterr().out.splitlines() if "Parameter static " in ln]
    assert "non-physical: not identified by this record" in row[0]
    assert main(["identify", str(path), "--recipe", "plain", "--model", "stribeck", "--out",
                 str(tmp_path / "m.json")]) == 2
    assert "lies below the Coulomb level" in capsys.readouterr().err


def test_a_breakaway_above_coulomb_is_not_flagged(tmp_path):
    res = I.identify_run(Run.from_csv(_dip_csv(tmp_path / "rise.csv", static=0.3)),
                         model="stribeck")
    assert res.parameters["static"] > res.parameters["coulomb"]
    assert not res.warnings and res.identified[res.names.index("static")]
