"""The diagnosis under hostile or unusual input (issue 15): refused with a clear ValueError, or
handled, never a traceback of another kind, an Infinity/NaN in JSON or a `nan` in a report."""

import json
import re
from dataclasses import replace

import numpy as np
import pytest

from fricctl.bench.hidden_effects import hidden_effect_record
from fricctl.datasets import Run
from fricctl.diagnose import api, diagnose
from fricctl.diagnose.windows import MIN_WINDOW_SAMPLES
from fricctl.friction import Coulomb, Viscous
from fricctl.plant import JointModel


@pytest.fixture(scope="module")
def delay_record():
    return hidden_effect_record(np.random.default_rng([2026, 90]), cause="time_delay",
                                duration=20.0)


@pytest.mark.parametrize("window", [1e-9, 0.0, -1.0])
def test_window_shorter_than_one_sample_is_refused(delay_record, window):
    with pytest.raises(ValueError, match="window"):
        diagnose(delay_record.run, window=window)


def test_window_below_the_shortest_is_refused_with_the_number(delay_record):
    ts = delay_record.run.sample_time
    with pytest.raises(ValueError, match=f"at least {MIN_WINDOW_SAMPLES} samples"):
        diagnose(delay_record.run, window=3 * ts)


def test_time_column_times_1e300_is_a_clear_value_error(delay_record):
    r = delay_record.run
    huge = Run(t=r.t * 1e300, torque=r.torque, position=r.position)
    with pytest.raises(ValueError, match="sample time"):
        diagnose(huge)


def test_rigid_lugre_model_is_not_refused():
    # a valid rigid LuGre nominal model on a record with an elastic joint: the compliance
    # candidate's term cannot sit in a LuGre model (no elastic joint with bristles), so it is
    # "not applicable" for that model -- the model itself is diagnosed, not refused
    rec = hidden_effect_record(np.random.default_rng([2026, 79]), cause="compliance",
                               duration=20.0)
    tr = rec.truth
    s0 = 1e4 * tr.friction.coulomb_pos  # bristles 1e-4 rad long at the Coulomb level
    lugre = replace(tr.friction, lugre_sigma0=s0, lugre_sigma1=2 * np.sqrt(s0 * tr.inertia))
    nominal = JointModel(inertia=tr.inertia, friction=lugre, units=tr.units)
    d = diagnose(rec.run, nominal)
    assert "compliance" not in d.causes
    assert "cannot be added to this model" in d.not_identifiable["compliance"]
    assert "LuGre" in d.not_identifiable["compliance"]
    assert "compliance" in d.report()  # the report says why


def test_report_tables_have_no_nan(delay_record):
    d = diagnose(delay_record.run)
    assert d.causes == ("time_delay",)
    text = d.report()
    assert not re.search(r"\bnan\b", text, re.I)
    # the baseline has no delay: '-' and the note, not nan
    row = next(ln for ln in text.splitlines() if ln.startswith("| delay |"))
    assert row.split("|")[2].strip() == "-"
    assert "'-': the model has no such term" in text


def test_undefined_numbers_are_null_with_a_reason(delay_record):
    d = diagnose(delay_record.run)
    own = d.as_dict()["undefined"]
    bad = replace(d, gain=replace(d.gain, simulation_rms_after=float("inf")),
                  notes={**d.notes, "gain": "the model cannot be re-simulated on this record (test)"})
    out = bad.as_dict()
    text = json.dumps(out, allow_nan=False)  # raises on NaN/Infinity
    assert out["gain"]["simulation_rms_after"] is None
    assert out["undefined"] == {
        **own, "gain.simulation_rms_after": "the model cannot be re-simulated on this record (test)"}
    assert "Infinity" not in text
    # on an ordinary record a null is a number not computed (a candidate below the line the
    # test rejects on its gross share: its chain's share and simulation), each with its reason
    assert all(k.startswith("below_line[") for k in own)
    assert not any("overflow or 0/0" in r for r in own.values())
    assert "| n/a |" in bad.report() or "n/a" in bad.report()


def test_a_candidate_that_cannot_be_simulated_leaves_null_and_a_reason(delay_record, monkeypatch):
    # the delay's extended model refused by the simulator (as a too-stiff or diverging model
    # is): the diagnosis goes on, the simulation numbers of that step are null with the reason
    real = api.simulate_windows

    def refusing(model, *a, **kw):
        if model.delay > 0:
            raise ValueError("this would take 200000 RK4 sub-steps per sample (test)")
        return real(model, *a, **kw)

    monkeypatch.setattr(api, "simulate_windows", refusing)
    d = diagnose(delay_record.run)
    assert d.causes == ("time_delay",)  # named on the torque evidence
    out = d.as_dict()
    json.dumps(out, allow_nan=False)
    assert out["steps"][0]["simulation_rms_after"] is None
    assert "200000 RK4 sub-steps" in out["undefined"]["steps[0].simulation_rms_after"]
    assert out["gain"]["simulation_rms_after"] is None
    assert "cannot be re-simulated" in out["undefined"]["gain.simulation_rms_after"]
    assert not re.search(r"\bnan\b", d.report(), re.I)


@pytest.mark.parametrize("change", [
    dict(load_inertia=0.5, stiffness=1e13),   # a stiff spring
    dict(inertia=1e-9),                       # a tiny inertia
])
def test_a_nominal_model_too_stiff_for_the_record_is_refused(delay_record, change):
    nom = JointModel(inertia=delay_record.truth.inertia, friction=delay_record.truth.friction)
    if "load_inertia" in change:
        change = dict(change, load_inertia=change["load_inertia"] * nom.inertia)
    else:
        change = dict(inertia=change["inertia"] * nom.inertia)
    with pytest.raises(ValueError, match="model: cannot be re-simulated.*sub-steps"):
        diagnose(delay_record.run, replace(nom, **change))


def test_a_model_that_cannot_move_is_refused_naming_the_model(delay_record):
    nom = JointModel(inertia=delay_record.truth.inertia, friction=Viscous(0.01) + Coulomb(1e100))
    with pytest.raises(ValueError, match="^model: its effect-free twin"):
        diagnose(delay_record.run, nom)


def test_a_record_beyond_the_sample_budget_is_refused_with_the_number(delay_record, monkeypatch):
    n = delay_record.run.n_samples
    monkeypatch.setattr(api, "MAX_SAMPLES", n - 1)
    with pytest.raises(ValueError, match=f"{n} samples.*at most {n - 1} samples.*decimate it by 2"):
        diagnose(delay_record.run)


def test_a_long_record_is_refused_before_any_work():
    # the budget is the measured bytes per sample times the samples (benchmarks/README.md)
    assert api.MAX_SAMPLES * api.BYTES_PER_SAMPLE <= api.MEMORY_BUDGET
    n = api.MAX_SAMPLES + 1
    t = np.arange(n) * 1e-3
    run = Run(t=t, torque=np.sin(t), position=1e-6 * np.round(1e5 * np.sin(t)))
    with pytest.raises(ValueError, match=f"run: {n} samples.*GB budget"):
        diagnose(run)


def test_progress_on_stderr_only_when_asked_or_a_terminal(delay_record, capsys):
    diagnose(delay_record.run, progress=True)
    assert "diagnose" in capsys.readouterr().err
    diagnose(delay_record.run)  # stderr is not a terminal under pytest
    assert capsys.readouterr().err == ""
    with pytest.raises(ValueError, match="progress"):
        diagnose(delay_record.run, progress="yes")


def test_extended_model_carries_provenance(delay_record):
    d = diagnose(delay_record.run)
    ext, base = d.extended, d.baseline
    assert ext.provenance["delay"].source == "diagnosed"
    assert "time_delay" in ext.provenance["delay"].note
    # fit mode: the baseline's values are identified by the diagnosis's own fit
    assert base.provenance["inertia"].source == "identified"
    assert ext.sample_time == pytest.approx(delay_record.run.sample_time, rel=1e-12)
    assert ext.provenance["sample_time"].source == "measured"
    assert ext.encoder_resolution == pytest.approx(delay_record.run.encoder_grid(), rel=1e-12)
    # every value that differs from the baseline is marked diagnosed, and only those
    pb, pe = base.parameters(), ext.parameters()
    for k in set(pb) | set(pe):
        key = f"friction.{k}" if k not in ("inertia", "delay", "offset") else k
        src = ext.provenance[key].source
        assert (src == "diagnosed") == (pb.get(k, 0.0) != pe.get(k, 0.0)), k
    assert JointModel.from_json(ext.to_json()) == ext


def test_a_model_of_another_sampling_or_encoder_is_refused(delay_record):
    run = delay_record.run
    nom = JointModel(inertia=delay_record.truth.inertia, friction=delay_record.truth.friction)
    with pytest.raises(ValueError, match="^model: sample_time 0.004 s differs"):
        diagnose(run, replace(nom, sample_time=2 * run.sample_time))
    with pytest.raises(ValueError, match="^model: encoder_resolution"):
        diagnose(run, replace(nom, encoder_resolution=2 * run.encoder_grid()))
    # agreeing values (to 1e-3) are accepted
    ok = replace(nom, sample_time=run.sample_time * (1 + 1e-4), encoder_resolution=run.encoder_grid())
    assert diagnose(run, ok).causes == ("time_delay",)


def test_check_model_agrees_refuses_wrong_types_naming_the_argument():
    # issue 26: AttributeError for wrong-typed arguments (the other library calls: ValueError)
    from fricctl.data import paper_actuator_model

    model = paper_actuator_model()
    t = np.arange(100) * 0.002
    res = model.encoder_resolution
    run = Run(t=t, torque=np.ones(100), position=res * np.round(t ** 2 / res))  # on its grid
    api.check_model_agrees(model, run)  # the right types: no complaint
    for args, words in (((None, run), "model must be a fricctl.plant.JointModel, got NoneType"),
                        (("model.json", run), "model must be a fricctl.plant.JointModel, got str"),
                        ((model, "run.csv"), "run must be a fricctl.datasets.Run, got str"),
                        ((model, {"t": t}), "run must be a fricctl.datasets.Run, got dict"),
                        ((run, model), "model must be")):
        with pytest.raises(ValueError, match=words):
            api.check_model_agrees(*args)
    with pytest.raises(ValueError, match="name must be a string"):
        api.check_model_agrees(model, run, name=3)
