"""The README's "Your own actuator" section works as written on EMPS, and every number it prints is recomputed.

The commands are parsed from the document (each ```sh block is one command; the ```text block
right after it lists lines its output must contain, in order; a ```c file=NAME block lists lines
the file NAME -- written by that step or an earlier one -- must contain), so the document and this test cannot drift apart.  They run in a
fresh temporary folder through ``bash`` with ``FRICCTL_DATA`` set and the ``fricctl`` script of
this interpreter first on the PATH.  Then each printed number is recomputed through the library,
and each number of the prose is checked against its recomputation.
"""

from __future__ import annotations

import math
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

#: Where the section lives: the README (its "## Your own actuator" section;
#: only the "## Your own actuator" section of the file is read).
DOC = Path(__file__).resolve().parents[1] / "README.md"
_SECTION = re.compile(r"^## Your own actuator\n(.*?)(?=^## |\Z)", re.S | re.M)
_BLOCK = re.compile(r"^```(\w+)([^\n]*)\n(.*?)^```", re.S | re.M)
_NUMBER = re.compile(r"[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?")


def section(text: str) -> str:
    """The "## Your own actuator" section of a markdown text (up to the next ``## `` heading)."""
    m = _SECTION.search(text)
    assert m, "no '## Your own actuator' section"
    return m.group(1)


def parse(text: str) -> list[dict]:
    """The section's steps: ``{"command", "expected": [lines], "files": {name: [lines]}}``."""
    steps: list[dict] = []
    for kind, info, body in _BLOCK.findall(section(text)):
        lines = [ln for ln in body.splitlines() if ln.strip()]
        if kind == "sh":
            assert len(lines) == 1 and lines[0].startswith("fricctl "), f"one command per block: {body!r}"
            steps.append({"command": lines[0], "expected": [], "files": {}})
        elif kind == "text":
            assert steps and not steps[-1]["expected"], "a text block follows its command"
            steps[-1]["expected"] = lines
        elif kind == "c":
            name = re.fullmatch(r"\s*file=(\S+)\s*", info)
            assert name and steps, "a c block names its file: ```c file=NAME"
            steps[-1]["files"][name.group(1)] = lines
    return steps


def _skeleton(line: str) -> str:
    return _NUMBER.sub("#", line.strip())


def _matches(expected: str, actual: str, net_dependent: bool) -> bool:
    if expected.strip() == actual.strip():
        return True
    if not net_dependent or _skeleton(expected) != _skeleton(actual):
        return False
    # outputs of the trained net: the same seed gives the same net on one machine; another BLAS
    # may round IPOPT's steps differently, so allow 0.2 % on those numbers only
    a = [float(x) for x in _NUMBER.findall(expected)]
    b = [float(x) for x in _NUMBER.findall(actual)]
    return all(math.isclose(x, y, rel_tol=2e-3, abs_tol=1e-12) for x, y in zip(a, b))


def test_document_parses():
    steps = parse(DOC.read_text(encoding="utf-8"))
    commands = [s["command"].split()[1] for s in steps]
    # the chain: identify, design, patterns, train, simulate (both), held out, C source
    assert commands == ["identify", "design", "patterns", "train", "simulate", "simulate", "patterns"]
    assert all(s["expected"] for s in steps)
    # the C header is checked after the step it follows (the files of the steps before it exist)
    assert any("emps_friction.h" in s["files"] for s in steps)


@pytest.fixture(scope="module")
def worked(tmp_path_factory):
    d = os.environ.get("FRICCTL_DATA")
    if not d or not (Path(d) / "emps" / "DATA_EMPS.mat").is_file():
        pytest.skip("EMPS data not found: set FRICCTL_DATA to the folder holding emps/DATA_EMPS.mat")
    bindir = str(Path(sys.executable).parent)
    path = bindir + os.pathsep + os.environ.get("PATH", "")
    if shutil.which("fricctl", path=path) is None:
        pytest.skip("no `fricctl` script next to this interpreter (pip install -e . makes one)")
    folder = tmp_path_factory.mktemp("your_own_actuator")
    env = dict(os.environ, PATH=path, FRICCTL_DATA=str(Path(d).resolve()), MPLBACKEND="Agg")
    text = DOC.read_text(encoding="utf-8")
    outputs = []
    for step in parse(text):
        proc = subprocess.run(["bash", "-c", step["command"]], cwd=folder, env=env,
                              capture_output=True, text=True)
        assert proc.returncode == 0, f"{step['command']}\n{proc.stderr}"
        outputs.append(proc.stdout)
    return {"folder": folder, "text": section(text), "steps": parse(text), "outputs": outputs,
            "data": Path(d)}


def test_outputs_are_what_the_document_shows(worked):
    for step, out in zip(worked["steps"], worked["outputs"]):
        net_dependent = "net.json" in step["command"]
        actual = out.splitlines()
        i = 0
        for line in step["expected"]:
            while i < len(actual) and not _matches(line, actual[i], net_dependent):
                i += 1
            assert i < len(actual), f"{step['command']}: no line like\n  {line}\nin\n{out}"
            i += 1
        for name, lines in step["files"].items():
            content = (worked["folder"] / name).read_text()
            for line in lines:
                assert line in content, f"{name} lacks {line!r}"


def _load(worked):
    from fricctl.nn import load_net
    from fricctl.plant import JointModel

    f = worked["folder"]
    return JointModel.load(f / "emps.json"), load_net(f / "net.json")


def test_identification_is_the_published_one(worked):
    from fricctl.datasets import load_record
    from fricctl.identify import idim_ls

    model, _ = _load(worked)
    res = idim_ls(load_record(worked["data"] / "emps" / "DATA_EMPS.mat"))
    # published IDIM-LS (Janot, Gautier & Brunot 2019, sec. 3.4; data README), 4 decimals
    published = {"inertia": (95.1089, 0.1085), "viscous": (203.5034, 1.1460),
                 "coulomb": (20.3935, 0.1012), "offset": (-3.1648, 0.0444)}
    for (name, (value, std)), x, s in zip(published.items(), res.estimates, res.std):
        assert round(float(x), 4) == value and round(float(s), 4) == std, name
    assert round(res.relative_error, 4) == 4.0834 and round(res.condition_number, 2) == 25.99
    assert model.inertia == res.parameters["inertia"]
    assert model.provenance["friction.coulomb_pos"].std == float(res.std[2])
    # the prose: sample time, encoder count (data README: 1 kHz, 5e-8 m), no torque limit
    text = worked["text"]
    assert f"sample time of the record ({model.sample_time:g} s)" in text
    assert f"encoder count its positions lie on ({model.encoder_resolution:.0e} m)" in text
    assert model.max_torque is None and '"max_torque": null' in text


def _design(model):
    import warnings

    from fricctl.design import design_pd

    with warnings.catch_warnings():  # the CLI prints the same DesignWarnings once; not tested here
        warnings.simplefilter("ignore")
        return design_pd(model, rise_time=0.05, damping=0.7)


def test_design_is_the_closed_form(worked):
    model, _ = _load(worked)
    d = _design(model)
    wn = (math.pi - math.acos(0.7)) / (0.05 * math.sqrt(1 - 0.7 ** 2))  # 0-100 % rise time
    assert d.kp == pytest.approx(model.inertia * wn ** 2, rel=1e-12)
    assert d.kd == pytest.approx(2 * 0.7 * wn * model.inertia - model.viscous, rel=1e-12)
    assert f"Kp = {d.kp:.6g} N/m, Kd = {d.kd:.6g} N*s/m" in worked["outputs"][1]


def test_patterns_and_the_net_fit(worked):
    from fricctl.datasets import read_patterns
    from fricctl.nn import fit_report

    model, net = _load(worked)
    p = read_patterns(worked["folder"] / "patterns.csv").patterns
    assert len(p) == 24841 - 2 * 5 and not p.at_rest.any()  # 24841 samples, 5-sample borders
    assert p.velocity_quantum == pytest.approx(5e-8 / 1e-3, rel=1e-9)
    assert f"friction RMS {np.sqrt(np.mean(p.friction ** 2)):.4g} N" in worked["outputs"][2]
    rep = fit_report(p.friction, net=net, tm=p.tm, omega=p.omega)
    out = worked["outputs"][3]
    assert f"fit           {rep.fit_percent:.2f} %" in out
    assert f"R^2           {rep.r_squared:.5f}" in out
    assert f"gain at rest dTat/dTm  {net.gain_at_rest():.4f}" in out
    # the prose: a gain above 1
    assert net.gain_at_rest() > 1


def test_steps_of_the_identified_axis(worked):
    from fricctl.compensators import NNCompensator
    from fricctl.controllers import pd_control, step
    from fricctl.simulate import simulate_model

    model, net = _load(worked)
    d = _design(model)
    ctrl = pd_control(d.kp, d.kd, step(0.0005))
    plain = simulate_model(model, ctrl, duration=1.0)
    comp = simulate_model(model, ctrl, NNCompensator(net, clip=True), duration=1.0)
    for res, out in ((plain, worked["outputs"][4]), (comp, worked["outputs"][5])):
        assert f"final_error                {res.reference[-1] - res.q[-1]:.6g} m" in out
        assert f"max_abs_torque             {np.max(np.abs(res.torque_motor)):.6g} N" in out
    # the prose: the uncompensated stopping band, stuck where offset - Fc < Kp e < offset + Fc
    fc, off = model.friction.coulomb_pos, model.offset
    lo, hi = 1e6 * (off - fc) / d.kp, 1e6 * (off + fc) / d.kp
    text = worked["text"]
    assert f"errors from {lo:.1f} um to +{hi:.1f} um" in text
    e_plain = 1e6 * (plain.reference[-1] - plain.q[-1])
    assert plain.stuck[-1] and lo <= e_plain <= hi
    e_comp = 1e6 * (comp.reference[-1] - comp.q[-1])
    assert f"stops closer ({e_comp:.1f} um)" in text and abs(e_comp) < abs(e_plain)
    assert np.sign(e_comp) != np.sign(e_plain)  # "on the other side"
    # "drives the force to the edge of breakaway": the joint holds Tm - offset within 10 % of Fc
    assert comp.stuck[-1] and abs(comp.torque_motor[-1] - off) > 0.9 * fc


def test_held_out_fit(worked):
    from fricctl.datasets import read_patterns
    from fricctl.nn import fit_report

    model, net = _load(worked)
    held = read_patterns(worked["folder"] / "pulses.csv").patterns
    train = read_patterns(worked["folder"] / "patterns.csv").patterns
    rep = fit_report(held.friction, net=net, tm=held.tm, omega=held.omega)
    assert f"fit {rep.fit_percent:.2f} %, R^2 {rep.r_squared:.5f}, RMSE {rep.rmse:.4g} N" \
        in worked["outputs"][6]
    assert f"{rep.outside_envelope} outside the training envelope" in worked["outputs"][6]
    fit_train = fit_report(train.friction, net=net, tm=train.tm, omega=train.omega).fit_percent
    assert f"drops from {fit_train:.2f} % to {rep.fit_percent:.2f} %" in worked["text"]
    # "the identified four-parameter law fits these patterns no better"
    law = fit_report(held.friction, model.friction.torque(held.omega) + model.offset)
    assert law.fit_percent <= rep.fit_percent
