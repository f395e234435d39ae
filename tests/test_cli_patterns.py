"""``fricctl patterns``: friction patterns from records, for ``fricctl train``."""

import json

import numpy as np
import pytest

from fricctl.cli import main
from fricctl.datasets import Run, read_patterns, record_patterns
from fricctl.friction import Coulomb, Viscous
from fricctl.plant import JointModel


def _model(tmp_path, **kw):
    args = dict(inertia=0.25, friction=(Viscous(0.02) + Coulomb(0.1)).model(), units="rotary",
                sample_time=0.002, encoder_resolution=1e-4)
    args.update(kw)
    return JointModel(**args).save(tmp_path / "model.json")


def _record(tmp_path, name="run.csv", units="rotary"):
    # 200 samples at rest under 0.3 N*m, then a = 2 rad/s^2 under 1 N*m, on a 1e-4 rad grid
    n, ts = 600, 0.002
    t = np.arange(n) * ts
    tau = np.r_[np.full(200, 0.3), np.full(n - 200, 1.0)]
    q = 1e-4 * np.round(np.where(np.arange(n) < 200, 0.0, (t - t[199]) ** 2) / 1e-4)
    return Run(t=t, torque=tau, position=q, units=units, source=name).to_csv(tmp_path / name)


def test_patterns_file_is_the_library_recipe(tmp_path, capsys):
    import shutil

    model, rec = _model(tmp_path), _record(tmp_path)
    copy = shutil.copy(rec, tmp_path / "copy.csv")  # two records (one file twice is refused)
    out = tmp_path / "p.csv"
    assert main(["patterns", str(rec), str(copy), "--model", str(model), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    tab = read_patterns(out)
    ref = record_patterns([Run.from_csv(rec)] * 2, inertia=0.25, estimator="polynomial_segments",
                          estimator_options={"window": 50, "overlap": 25})
    for name in ("tm", "omega", "friction", "at_rest"):  # the same numbers, written exactly
        np.testing.assert_array_equal(getattr(tab.patterns, name), getattr(ref, name))
    # meta: units and one encoder count per sample, 1e-4 rad / 0.002 s = 0.05 rad/s
    assert tab.patterns.units == "rotary" and tab.patterns.velocity_quantum == pytest.approx(0.05)
    assert tab.meta["estimator"] == "polynomial_segments (window=50, overlap=25)"
    assert tab.meta["inertia"].startswith("0.25 (from model.json)")
    # at rest by hand: the first motion samples stay below half a count (4e-6 k^2 < 5e-5 for
    # k <= 3), so the encoder reads 0 up to sample 202; at rest are samples 2..200 (two equal
    # readings each side), 5..200 after the 5-sample border: 196 per record
    n_rest = 2 * 196
    assert int(tab.patterns.at_rest.sum()) == n_rest
    assert f"1180 patterns from 2 record(s)" in text and f"at rest: {n_rest} patterns" in text
    # at rest the friction is the reaction Tm (polynomial segments report zero acceleration);
    # at sample 200 the drive already pushes 1 N*m but the encoder has not counted yet
    rest = tab.patterns.at_rest
    np.testing.assert_array_equal(tab.patterns.friction[rest], tab.patterns.tm[rest])
    assert np.count_nonzero(tab.patterns.tm[rest] == 1.0) == 2


def test_json_and_held_out_net(tmp_path, capsys):
    from fricctl.nn import FrictionNet, fit_report, save_net

    net = FrictionNet(w1=[[0.0, 5.0]], b1=[0.0], w2=[1.0], b2=0.0, input_offset=[0, 0],
                      input_scale=[1, 1], output_offset=0.0, output_scale=0.1,
                      envelope_low=[-1, -1], envelope_high=[1, 1])
    netp = save_net(net, tmp_path / "net.json")
    out = tmp_path / "p.csv"
    assert main(["patterns", str(_record(tmp_path)), "--model", str(_model(tmp_path)),
                 "--out", str(out), "--net", str(netp), "--json",
                 "--estimator", "savitzky_golay"]) == 0
    obj = json.loads(capsys.readouterr().out)
    p = read_patterns(out).patterns
    ref = fit_report(p.friction, net=net, tm=p.tm, omega=p.omega)
    assert obj["net"] == {**ref.as_dict(), "viscous_removed": 0.0}
    assert obj["n_patterns"] == len(p) == 590
    assert obj["estimator"] == "savitzky_golay" and obj["units"] == "rotary"
    assert obj["friction_rms"] == pytest.approx(float(np.sqrt(np.mean(p.friction ** 2))))


def test_a_fricctl_pipeline_net_is_judged_with_its_viscous_term(tmp_path, capsys):
    # auditC item 7: a --pipeline fricctl net estimates Tat - b*omega (b in its metadata);
    # train reports the fit of net + b*omega, patterns --net judged the net alone (72 % -> 48 %
    # on the very patterns it was trained on).  Reference: fit_report on net + b*omega
    # computed here from the net's own evaluation.
    from fricctl.nn import FrictionNet, fit_report, save_net

    b = 0.4
    net = FrictionNet(w1=[[0.0, 5.0]], b1=[0.0], w2=[1.0], b2=0.0, input_offset=[0, 0],
                      input_scale=[1, 1], output_offset=0.0, output_scale=0.1,
                      envelope_low=[-1, -1], envelope_high=[1, 1],
                      metadata={"pipeline": "fricctl", "viscous_removed": b})
    netp = save_net(net, tmp_path / "net.json")
    argv = ["patterns", str(_record(tmp_path)), "--model", str(_model(tmp_path)),
            "--out", str(tmp_path / "p.csv"), "--net", str(netp)]
    assert main([*argv, "--json"]) == 0
    obj = json.loads(capsys.readouterr().out)
    p = read_patterns(tmp_path / "p.csv").patterns
    full = fit_report(p.friction, np.asarray(net(p.tm, p.omega)) + b * p.omega)
    alone = fit_report(p.friction, net=net, tm=p.tm, omega=p.omega)
    assert abs(full.fit_percent - alone.fit_percent) > 1.0      # the two readings differ here
    assert obj["net"]["fit_percent"] == pytest.approx(full.fit_percent, rel=1e-12)
    assert obj["net"]["rmse"] == pytest.approx(full.rmse, rel=1e-12)
    assert obj["net"]["outside_envelope"] == alone.outside_envelope
    assert obj["net"]["viscous_removed"] == b
    assert main([*argv, "--force"]) == 0
    text = capsys.readouterr().out
    assert f"(net + b*omega, b = 0.4 N*m*s/rad) on these patterns: fit {full.fit_percent:.2f} %" \
        in text


def test_linear_units_follow_the_model(tmp_path, capsys):
    model = _model(tmp_path, units="linear", inertia=95.0)  # 1e-4 m per count, 2 ms
    rec = _record(tmp_path, units="linear")
    out = tmp_path / "p.csv"
    assert main(["patterns", str(rec), "--model", str(model), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "I = 95 kg" in text and "velocity quantum 0.05 m/s" in text  # 1e-4 m / 0.002 s
    assert "# columns: tm [N], omega [m/s], friction [N], at_rest [0/1]" in out.read_text()


def test_a_record_that_never_rests_says_so(tmp_path, capsys):
    t = np.arange(300) * 0.002
    rec = Run(t=t, torque=np.ones(300), position=np.sin(t) + t).to_csv(tmp_path / "moving.csv")
    assert main(["patterns", str(rec), "--model", str(_model(tmp_path)),
                 "--out", str(tmp_path / "p.csv")]) == 0
    text = capsys.readouterr().out
    assert "at rest: 0 patterns" in text and "no pattern at rest" in text


@pytest.mark.parametrize("argv,words", [
    (["--out", "{rec}"], "is an input of this command"),
    (["--out", "{model}"], "is an input of this command"),
    (["--out", "{existing}"], "exists (use --force"),
    (["--out", "{tmp}/p.csv", "--border", "-1"], "border must be an integer >= 0"),
    (["--out", "{tmp}/p.csv", "--guard", "0"], "guard must be an integer >= 1"),
])
def test_bad_input_one_line(tmp_path, capsys, argv, words):
    rec, model = _record(tmp_path), _model(tmp_path)
    existing = tmp_path / "old.csv"
    existing.write_text("keep")
    fmt = dict(rec=rec, model=model, existing=existing, tmp=tmp_path)
    assert main(["patterns", str(rec), "--model", str(model),
                 *[a.format(**fmt) for a in argv]]) == 2
    err = capsys.readouterr().err
    assert words in err and err.count("\n") == 1, err
    assert existing.read_text() == "keep"


def test_units_mismatch_and_missing_model(tmp_path, capsys):
    rec = _record(tmp_path, units="linear")
    assert main(["patterns", str(rec), "--model", str(_model(tmp_path)),
                 "--out", str(tmp_path / "p.csv")]) == 2
    assert "a linear record for a rotary model" in capsys.readouterr().err
    assert main(["patterns", str(rec), "--model", str(tmp_path / "none.json"),
                 "--out", str(tmp_path / "p.csv")]) == 2
    assert "no such model file" in capsys.readouterr().err
    assert not (tmp_path / "p.csv").exists()


def test_a_net_of_another_axis_is_refused(tmp_path, capsys):
    # issue 26: a net trained on a linear axis (N, m/s) was accepted for a rotary model's patterns
    from fricctl.nn import FrictionNet, save_net

    net = FrictionNet(w1=[[0.0, 5.0]], b1=[0.0], w2=[1.0], b2=0.0, input_offset=[0, 0],
                      input_scale=[1, 1], output_offset=0.0, output_scale=0.1,
                      envelope_low=[-1, -1], envelope_high=[1, 1], metadata={"units": "linear"})
    netp = save_net(net, tmp_path / "lin-net.json")
    out = tmp_path / "p.csv"
    assert main(["patterns", str(_record(tmp_path)), "--model", str(_model(tmp_path)),
                 "--out", str(out), "--net", str(netp)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "lin-net.json: a network trained on a linear axis" in err
    assert not out.exists()


@pytest.mark.parametrize("change, words", [
    (dict(sample_time=0.001), "model.json: sample_time 0.001 s differs from the record's 0.002 s"),
    (dict(encoder_resolution=5e-4), "model.json: encoder_resolution 0.0005 differs from the grid"),
])
def test_a_model_of_another_sampling_or_encoder_is_refused(tmp_path, capsys, change, words):
    # issue 26: patterns wrote velocity_quantum = encoder / sample time of the wrong model
    # where diagnose refuses the same pair (fricctl.diagnose.check_model_agrees)
    out = tmp_path / "p.csv"
    assert main(["patterns", str(_record(tmp_path)), "--model", str(_model(tmp_path, **change)),
                 "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and words in err, err
    assert not out.exists()


def test_a_record_given_twice_is_refused(tmp_path, capsys):
    # audit A 10: "patterns rec.csv rec.csv" silently doubled the patterns
    import os

    rec, model = _record(tmp_path), _model(tmp_path)
    (tmp_path / "link.csv").symlink_to(rec)
    os.link(rec, tmp_path / "hard.csv")
    out = tmp_path / "p.csv"
    for other, how in ((str(rec), ""), (str(tmp_path / "." / "run.csv"), ""),
                       (str(tmp_path / "link.csv"), ""), (str(tmp_path / "hard.csv"), " (a hard link)")):
        assert main(["patterns", str(rec), other, "--model", str(model), "--out", str(out)]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and f"RUN: {other} and {rec} are the same record{how}; " in err
    assert not out.exists()
    other = _record(tmp_path, name="other.csv")  # another record of the same content is another run
    assert main(["patterns", str(rec), str(other), "--model", str(model), "--out", str(out)]) == 0
    one = tmp_path / "one.csv"
    assert main(["patterns", str(rec), "--model", str(model), "--out", str(one)]) == 0
    assert len(read_patterns(out).patterns) == 2 * len(read_patterns(one).patterns) > 0
