"""The model file (``fricctl.joint_model``, versions 1 and 2): round trips, strict reading,
the shipped paper actuator, and the CLI's one-line errors on bad files."""

import json
import math

import pytest

from fricctl._validate import strict_json
from fricctl.cli import main
from fricctl.data import PAPER_ACTUATOR_SOURCE, paper_actuator_file, paper_actuator_model
from fricctl.friction import Coulomb, Viscous
from fricctl.params import paper_actuator
from fricctl.plant import JointModel
from fricctl.plant.model import PROVENANCE_SOURCES, Provenance, provenance_keys


def _model(**kw):
    base = dict(inertia=95.1089, friction=(Viscous(203.5034) + Coulomb(20.3935)).model(),
                offset=-3.1648, units="linear", sample_time=0.001, encoder_resolution=5e-8,
                provenance={"inertia": Provenance(source="identified", std=0.1085, note="IDIM-LS"),
                            "friction.coulomb_pos": Provenance(source="identified", std=0.1012)})
    base.update(kw)
    return JointModel(**base)


def _v2(**changes):
    d = _model().as_dict()
    for k, x in changes.items():
        if x is _DROP:
            del d[k]
        else:
            d[k] = x
    return d


_DROP = object()


def test_round_trip_is_exact(tmp_path):
    m = _model()
    again = JointModel.load(m.save(tmp_path / "m.json"))
    assert again == m
    assert again.provenance["inertia"].std == 0.1085
    assert again.max_torque is None and again.velocity_quantum == pytest.approx(5e-5, rel=1e-12)
    d = json.loads((tmp_path / "m.json").read_text())
    assert d["version"] == 2 and d["max_torque"] is None


def test_version_1_still_reads():
    # a version-1 file as the diagnosis wrote it (no units key: rotary)
    v1 = {"format": "fricctl.joint_model", "version": 1, "inertia": 0.00745,
          "friction": {"viscous_pos": 0.0169, "viscous_neg": 0.0169, "coulomb_pos": 0.144,
                       "coulomb_neg": 0.144}, "offset": 0.01, "delay": 0.002, "source": "v1"}
    m = JointModel.from_json(json.dumps(v1))
    assert m.units == "rotary" and m.offset == 0.01 and m.sample_time is None
    assert m.provenance == {}
    assert JointModel.from_json(m.to_json()) == m  # rewritten as version 2
    with pytest.raises(ValueError, match="unknown key.*'sample_time'.*version 1"):
        JointModel.from_json(json.dumps({**v1, "sample_time": 0.002}))


def test_optional_keys_may_be_left_out():
    d = {"format": "fricctl.joint_model", "version": 2, "units": "rotary", "inertia": 1.0,
         "friction": {}}
    m = JointModel.from_dict(d)
    assert (m.offset, m.sample_time, m.encoder_resolution, m.max_torque) == (0.0, None, None, None)


def test_shipped_paper_actuator_is_generated_from_params():
    # regenerate from fricctl.params and compare the text: the file is never edited by hand
    assert paper_actuator_file().read_text(encoding="utf-8") == paper_actuator_model().to_json() + "\n"
    m = JointModel.load(paper_actuator_file())
    p = paper_actuator()
    assert m.inertia == p.total_inertia and m.sample_time == p.sample_time
    assert m.max_torque == p.max_torque and m.encoder_resolution == p.encoder_resolution
    assert m.friction == p.friction_model() and m.source == PAPER_ACTUATOR_SOURCE
    # breakaway = static (0.18 N*m, paper), sliding level = coulomb (assumption)
    assert m.friction.breakaway(+1) == pytest.approx(p.static, rel=1e-15)
    assert m.provenance["friction.viscous_pos"].source == "paper"
    assert m.provenance["friction.coulomb_pos"].source == "assumption"
    assert m.provenance["inertia"].source == "derived"


def test_from_params_flexible_needs_link():
    with pytest.raises(ValueError, match="link_inertia > 0"):
        JointModel.from_params(paper_actuator(), source="x", plant="flexible")
    m = JointModel.from_params(paper_actuator().with_link(), source="x", plant="flexible")
    assert m.elastic and m.load_inertia == 0.0046 and m.provenance["stiffness"].source == "assumption"


@pytest.mark.parametrize("changes,match", [
    (dict(inertia=_DROP), "missing key 'inertia'"),
    (dict(units=_DROP), "missing key 'units'"),
    (dict(friction=_DROP), "missing key 'friction'"),
    (dict(extra=1), "unknown key.*'extra'"),
    (dict(version=3), "version: unsupported 3"),
    (dict(version=True), "version: unsupported True"),
    (dict(version=2.0), "version: unsupported 2.0"),
    (dict(format="other"), "format: must be"),
    (dict(units="metric"), "units: must be one of"),
    (dict(inertia=-1.0), "inertia must be > 0 kg"),
    (dict(inertia=True), "inertia must be a real number"),
    (dict(inertia="95"), "inertia must be a real number"),
    (dict(sample_time=0.0), "sample_time must be > 0 s"),
    # audit A 4-6: values no actuator has, which design and simulate then got wrong silently
    (dict(sample_time=1e-20), r"sample_time must lie in \[1e-09, 3600\] s .*got 1e-20"),
    (dict(sample_time=1e100), r"sample_time must lie in \[1e-09, 3600\] s .*got 1e\+100"),
    (dict(stiffness=1000.0), "stiffness: a spring needs a load behind it .load_inertia > 0"),
    (dict(damping=1.0), "damping: a spring needs a load behind it"),
    (dict(units="rotary", encoder_resolution=100.0),
     r"encoder_resolution must be at most one revolution \(2\*pi rad\) on a rotary joint, "
     r"got 100.0 rad"),
    (dict(max_torque=-5), "max_torque must be > 0 N"),
    (dict(encoder_resolution=[1e-8]), "encoder_resolution must be a real number"),
    (dict(delay=-0.1), "delay must be >= 0"),
    (dict(friction={"viscous_pos": -1.0}), "friction.viscous_pos must be >= 0"),
    (dict(friction={"viscus": 1.0}), "friction: unknown field.*'viscus'"),
    (dict(friction={"coulomb_pos": False}), "friction.coulomb_pos must be a real number"),
    (dict(provenance={"inertai": {"source": "paper"}}), "provenance: unknown value name 'inertai'"),
    (dict(provenance={"inertia": {"source": "guess"}}), "provenance.inertia.source must be one of"),
    (dict(provenance={"inertia": {"std": 1.0}}), "provenance.inertia: missing key 'source'"),
    (dict(provenance={"inertia": {"source": "paper", "std": -1}}), "provenance.inertia.std must be >= 0"),
    (dict(provenance={"inertia": {"source": "paper", "sd": 1}}), "provenance.inertia: unknown key"),
    (dict(source=5), "source must be a string"),
])
def test_bad_content_names_the_key(changes, match):
    with pytest.raises(ValueError, match=match):
        JointModel.from_json(json.dumps(_v2(**changes)))


@pytest.mark.parametrize("changes,match", [
    # issue 25 item 3: the four failed tries of a first model file, each told what to write
    (dict(format=_DROP), r"missing key 'format': a model file starts \{\"format\": "
                         r"\"fricctl.joint_model\", \"version\": 2, .*docs/model_file.md"),
    (dict(version=_DROP), "missing key 'version' \\(2 for"),
    (dict(viscous=0.05), "'viscous' \\(per direction, two positive magnitudes: friction.viscous_pos "
                         "and friction.viscous_neg\\) in a version 2"),
    (dict(coulomb_pos=0.1), "'coulomb_pos' \\(a friction coefficient: it belongs under 'friction'\\)"),
    (dict(sampletime=0.002), "'sampletime' \\(did you mean 'sample_time'\\?\\)"),
    (dict(sample_time="none"), "sample_time must be a real number, got 'none' \\(or null when unknown\\)"),
    (dict(friction={"coulomb": 0.1}), "friction: unknown field\\(s\\) 'coulomb' \\(per direction, "
                                      "two positive magnitudes: coulomb_pos and coulomb_neg\\)"),
    (dict(friction={"static": 0.2}), "friction: unknown field.*'static' \\(the breakaway level Fs "
                                     "is stored as its excess over the Coulomb level: stribeck_pos"),
    (dict(friction={"viscus_pos": 1.0}), "'viscus_pos' \\(did you mean 'viscous_pos'\\?\\)"),
])
def test_bad_keys_say_where_they_belong(changes, match):
    with pytest.raises(ValueError, match=match):
        JointModel.from_json(json.dumps(_v2(**changes)))


@pytest.mark.parametrize("text,match", [
    ('{"format": "fricctl.joint_model", "version": 2, "version": 2}', "duplicate key 'version'"),
    ('{"inertia": NaN}', "NaN is not a number"),
    ('{"inertia": -Infinity}', "-Infinity is not a number"),
    ("[" * 100000 + "]" * 100000, "nested deeper"),
    ('{"a": "[[[[[[[[[[[[[[[[["}', "format"),  # brackets inside strings do not count
    ('{"inertia": 1' + "0" * 2000 + "}", "integer of 2001 digits"),
    ('{"inertia": 1', "not valid JSON"),
    ("[1, 2]", "expected a JSON object"),
])
def test_bad_json_is_a_value_error(text, match):
    with pytest.raises(ValueError, match=match):
        JointModel.from_json(text)


@pytest.mark.parametrize("literal,match", [
    ("9" * 400, "inertia is too large to be a number of double precision"),
    ("1e400", "inertia must be finite"),
])
def test_huge_number_names_the_key(literal, match):
    text = json.dumps(_v2()).replace('"inertia": 95.1089', '"inertia": ' + literal)
    assert literal in text
    with pytest.raises(ValueError, match=match):
        JointModel.from_json(text)


def test_library_checks():
    with pytest.raises(ValueError, match="provenance key must be one of"):
        _model(provenance={"mass": Provenance(source="paper")})
    with pytest.raises(ValueError, match="must be a Provenance"):
        _model(provenance={"inertia": {"source": "paper"}})
    with pytest.raises(ValueError, match=r"delay: 100 s is 1e\+07 samples"):
        _model(delay=100.0).delay_samples(1e-5)
    assert _model(delay=0.0021).delay_samples(0.001) == 2
    assert set(PROVENANCE_SOURCES) >= {"paper", "derived", "assumption", "identified"}
    assert "friction.coulomb_neg" in provenance_keys() and "max_torque" in provenance_keys()
    # the design's viscous coefficient: mean of both directions times the scale (hand value)
    fr = (Viscous(1.0) + Coulomb(0.0)).model()
    m = _model(friction=type(fr)(viscous_pos=100.0, viscous_neg=300.0, scale=0.5))
    assert m.viscous == 0.5 * 200.0
    assert strict_json('{"a": [1]}', max_depth=2) == {"a": [1]}


def test_save_refuses_to_overwrite_when_asked(tmp_path):
    p = _model().save(tmp_path / "m.json")
    with pytest.raises(FileExistsError):
        _model().save(p, overwrite=False)


# -- the CLI: one line, exit 2, naming the key -------------------------------------------
@pytest.mark.parametrize("changes,key", [
    (dict(inertia=_DROP), "'inertia'"),
    (dict(extra=1), "'extra'"),
    (dict(version=7), "version"),
    (dict(units="imperial"), "units"),
    (dict(inertia=-95.0), "inertia"),
    (dict(friction={"coulomb_pos": float("nan")}), "NaN"),
])
@pytest.mark.parametrize("command", [
    ["design", "pd", "--rise-time", "0.05", "--damping", "0.7"],
    ["simulate", "--controller", "pd", "--rise-time", "0.05", "--damping", "0.7",
     "--reference", "step:0.01", "--duration", "0.1"],
])
def test_cli_bad_model_file_one_line_exit_2(tmp_path, capsys, changes, key, command):
    p = tmp_path / "bad.json"
    text = json.dumps(_v2(**changes))
    p.write_text(text)  # json.dumps writes float("nan") as the literal NaN
    assert main([*command, "--model", str(p)]) == 2
    out, err = capsys.readouterr()
    assert err.count("\n") == 1 and key in err and "bad.json" in err, err
    assert out == ""


def test_cli_missing_model_file(tmp_path, capsys):
    assert main(["design", "pd", "--rise-time", "0.05", "--damping", "0.7", "--model",
                 str(tmp_path / "none.json")]) == 2
    err = capsys.readouterr().err
    assert "no such model file" in err and err.count("\n") == 1


def test_a_folder_given_as_a_file_is_said_to_be_a_folder(tmp_path, capsys):
    # audit A 9: "no such model file" for a folder that exists sent the user looking for it
    folder = tmp_path / "adir"
    folder.mkdir()
    for argv, what in ((["design", "pd", "--rise-time", "0.05", "--damping", "0.7", "--model"],
                        "model file"),
                       (["model", "show"], "model file"),
                       (["train", "--out", str(tmp_path / "n.json")], "patterns file"),
                       (["simulate", "--controller", "p", "--kp", "1", "--reference", "step:0.1",
                         "--compensation", "nn", "--net"], "network file")):
        assert main([*argv, str(folder)]) == 2, argv
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and err.endswith(f": error: {folder}: a folder, not a {what}\n"), err
    assert not (tmp_path / "n.json").exists()


def test_nan_in_json_dumps_is_refused():
    # the writer never produces NaN: a model cannot hold one
    with pytest.raises(ValueError, match="must be finite"):
        _model(offset=math.nan)


def test_physical_limits_keep_what_is_real():
    # the edges of the limits above are models: 1 ns and an hour, one count per revolution,
    # a linear axis's 100 m count (a length, not an angle), a spring with its load
    for kw in (dict(sample_time=1e-9), dict(sample_time=3600.0), dict(encoder_resolution=100.0),
               dict(units="rotary", encoder_resolution=2 * math.pi),
               dict(load_inertia=1.0, stiffness=1000.0, damping=1.0)):
        assert _model(**kw)
    with pytest.raises(ValueError, match="sample_time must lie in"):
        paper_actuator().replace(sample_time=1e-12)
