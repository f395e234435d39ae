"""Tests of ``fricctl train``."""

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import fricctl
from fricctl.cli import main
from fricctl.nn import TRAINERS, fit_percent, load_net, smooth_friction_patterns
from fricctl.nn.pipelines import PIPELINES
from fricctl.nn.train import DEFAULT_TRAINER, Trainer


@pytest.fixture()
def patterns_csv(tmp_path):
    pats = smooth_friction_patterns(np.random.default_rng(0), n_sliding=300, n_stuck=0)
    tm, om, f = pats.tm, pats.omega, pats.friction
    path = tmp_path / "patterns.csv"
    # columns in a different order than tm,omega,friction: read by name
    np.savetxt(path, np.column_stack([om, f, tm]), delimiter=",", header="omega,friction,tm",
               comments="", fmt="%.17g")
    return path, (tm, om, f)


def test_train_casadi_writes_net_and_prints_fit(patterns_csv, tmp_path, capsys):
    path, (tm, om, f) = patterns_csv
    out = tmp_path / "net.json"
    csrc = tmp_path / "net.c"
    assert main(["train", str(path), "--out", str(out), "--seed", "1", "--restarts", "1",
                 "--c-source", str(csrc), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    net = load_net(out)
    # reference: the fit recomputed from the saved net (noise-free smooth law, > 99 %)
    assert report["fit"]["fit_percent"] == pytest.approx(fit_percent(f, net(tm, om)), rel=1e-12)
    assert report["fit"]["fit_percent"] > 99.0
    assert report["hidden"] == 4 and report["n_patterns"] == tm.size
    assert net.metadata["seed"] == 1 and net.metadata["trainer"] == "casadi"
    assert report["envelope"]["tm"] == [tm.min(), tm.max()]
    # the keys are the ones the command's help lists (it had left out warnings)
    import re

    import fricctl.cli.train as train_cli

    listed = " ".join(train_cli.__doc__.split()).split("prints one JSON object instead: ``")[1]
    listed = re.sub(r"\{[^}]*\}", "", listed.split("``")[0])
    assert set(report) == {k.strip() for k in listed.split(",")}
    assert "double fricctl_friction_net(double tm, double omega, int clip)" in csrc.read_text()
    assert (tmp_path / "net.h").is_file()


def test_train_backprop_text_output(patterns_csv, tmp_path, capsys):
    path, _ = patterns_csv
    out = tmp_path / "bp.json"
    assert main(["train", str(path), "--out", str(out), "--trainer", "backprop",
                 "--epochs", "20", "--hidden", "3"]) == 0
    text = capsys.readouterr().out
    assert "fit" in text and "R^2" in text and "backprop" in text
    net = load_net(out)
    assert net.hidden == 3 and net.metadata["epochs"] == 20


@pytest.mark.parametrize("content, message", [
    ("tm,omega,torque\n1,2,3\n4,5,6\n", "unknown column"),
    ("tm,omega\n1,2\n3,4\n", "header"),
    ("tm,omega,friction\n1,2,x\n4,5,6\n", "line 2"),
    ("tm,omega,friction\n1,2,3\n4,nan,6\n", "NaN"),
    ("tm,omega,friction\n1,2,3\n4,5\n", "fields"),
    ("tm,omega,friction\n1,2,3\n", "at least 2"),
    ("", "empty"),
])
def test_bad_patterns_give_one_line_and_exit_2(tmp_path, capsys, content, message):
    path = tmp_path / "bad.csv"
    path.write_text(content)
    assert main(["train", str(path), "--out", str(tmp_path / "n.json")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err and err.startswith("fricctl train: error:")
    assert not (tmp_path / "n.json").exists()


def test_missing_file_and_bad_option_exit_2(patterns_csv, tmp_path, capsys):
    path, _ = patterns_csv
    assert main(["train", str(tmp_path / "absent.csv"), "--out", str(tmp_path / "n.json")]) == 2
    assert "absent.csv" in capsys.readouterr().err
    assert main(["train", str(path), "--out", str(tmp_path / "n.json"), "--hidden", "0"]) == 2
    assert "hidden" in capsys.readouterr().err


def test_a_folder_or_a_missing_file_is_named_as_the_patterns_file(tmp_path, capsys):
    # audit C24 4: "a folder, not a CSV file" / "no such file" did not say which file was
    # meant; the model and network files are named ("no such model file")
    folder = tmp_path / "adir"
    folder.mkdir()
    for given, said in ((folder, "a folder, not a patterns file"),
                        (tmp_path / "absent.csv", "no such patterns file")):
        assert main(["train", str(given), "--out", str(tmp_path / "n.json")]) == 2
        assert capsys.readouterr().err == f"fricctl train: error: {given}: {said}\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["adir"]


@pytest.fixture()
def lattice_patterns_csv(tmp_path):
    """Patterns as `fricctl patterns` writes them: at_rest column and the velocity quantum."""
    from fricctl.datasets import FrictionPatterns, write_patterns

    q = 0.0157
    pats = smooth_friction_patterns(np.random.default_rng(4), n_sliding=500, n_stuck=250)
    om = np.round(pats.omega / q) * q          # the loop's velocity lattice
    path = tmp_path / "lattice.csv"
    write_patterns(path, FrictionPatterns(tm=pats.tm, omega=om, friction=pats.friction,
                                          at_rest=om == 0, units="rotary", velocity_quantum=q,
                                          meta={}))
    return path


@pytest.mark.parametrize("omega_max, narrow", [(2.0, False), (0.0157 * 1.5, True)])
def test_patterns_of_a_narrow_band_of_speeds_warn(tmp_path, capsys, omega_max, narrow):
    # auditC item 9: patterns within +-1 count per sample trained to a 97 % fit, no warning,
    # and the net then ran at 8x its speeds.  The same smooth law on the loop's velocity
    # lattice (q = 0.0157 rad/s per count per sample), up to 127 counts (no warning) or 1.5
    # (rounded to +-1 count: the warning, saying it in counts per sample)
    from fricctl.datasets import FrictionPatterns, write_patterns
    from fricctl.nn.patterns import smooth_friction_patterns

    q = 0.0157
    pats = smooth_friction_patterns(np.random.default_rng(4), n_sliding=500, n_stuck=250,
                                    omega_max=omega_max, smoothing_velocity=min(0.05, q))
    om = np.round(pats.omega / q) * q
    path = tmp_path / "p.csv"
    write_patterns(path, FrictionPatterns(tm=pats.tm, omega=om, friction=pats.friction,
                                          at_rest=om == 0, units="rotary", velocity_quantum=q,
                                          meta={}))
    assert main(["train", str(path), "--pipeline", "fricctl", "--out", str(tmp_path / "n.json"),
                 "--progress", "off", "--json"]) == 0
    out, err = capsys.readouterr()
    rep = json.loads(out)
    said = [w for w in rep["warnings"] if "narrow band of speeds" in w]
    top = max(abs(x) for x in rep["envelope"]["omega"])          # the stored envelope
    assert (top / q <= 1 + 1e-9) is narrow
    assert len(said) == int(narrow) and ("narrow band of speeds" in err) is narrow
    if narrow:
        assert f"|omega| <= {top:.4g} rad/s, 1 encoder count(s) per sample" in said[0]


def test_train_fricctl_pipeline_certifies_its_gain_band(lattice_patterns_csv, tmp_path, capsys):
    out, csrc = tmp_path / "n.json", tmp_path / "comp.c"
    assert main(["train", str(lattice_patterns_csv), "--pipeline", "fricctl", "--gain-band",
                 "0.95,0.98", "--out", str(out), "--c-source", str(csrc), "--json"]) == 0
    rep = json.loads(capsys.readouterr().out)
    net = load_net(out)
    # the certificate is re-checked on the saved net by finite differences at rest
    tm = np.linspace(-rep["certificate"]["rest_torque"], rep["certificate"]["rest_torque"], 1001)
    g = (net(tm + 1e-6, 0 * tm) - net(tm - 1e-6, 0 * tm)) / 2e-6
    assert 0.95 - 1e-5 <= g.min() and g.max() <= 0.98 + 1e-5
    assert rep["pipeline"] == "fricctl" and rep["trainer"] == "certified"
    assert rep["certificate"]["passed"] and rep["certificate"]["gain_band"] == [0.95, 0.98]
    assert rep["viscous_removed"] > 0 and net.metadata["viscous_removed"] == rep["viscous_removed"]
    assert (tmp_path / "comp.h").is_file() and "compensation" in csrc.read_text()


@pytest.mark.parametrize("args,message", [
    (["--pipeline", "fricctl", "--gain-band", "0.9"], "--gain-band must be LO,HI"),
    (["--pipeline", "fricctl", "--gain-band", "0.95,1.0"], "lo <= hi < 1"),
    (["--pipeline", "fricctl", "--trainer", "casadi"], "does not go with --pipeline"),
    (["--gain-band", "0.9,0.95"], "go with --pipeline"),
])
def test_train_pipeline_arguments_are_checked(lattice_patterns_csv, tmp_path, capsys, args, message):
    assert main(["train", str(lattice_patterns_csv), "--out", str(tmp_path / "n.json")] + args) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1


def test_train_refuses_to_clobber(patterns_csv, lattice_patterns_csv, tmp_path, capsys):
    path, _ = patterns_csv
    # a file without the at_rest column and the quantum cannot feed the fricctl pipeline
    assert main(["train", str(path), "--pipeline", "fricctl", "--out", str(tmp_path / "a.json")]) == 2
    assert "velocity_quantum" in capsys.readouterr().err
    assert main(["train", str(path), "--out", str(path)]) == 2            # its own input
    assert "is an input" in capsys.readouterr().err
    out = tmp_path / "b.json"
    out.write_text("keep me")
    assert main(["train", str(path), "--out", str(out), "--restarts", "1"]) == 2
    assert out.read_text() == "keep me" and "--force" in capsys.readouterr().err
    assert main(["train", str(path), "--out", str(out), "--restarts", "1", "--force"]) == 0
    assert load_net(out).hidden == 4


def test_train_pipeline_shows_its_trainers_progress_when_asked(lattice_patterns_csv, tmp_path, capsys):
    argv = ["train", str(lattice_patterns_csv), "--pipeline", "fricctl", "--gain-band", "0.95,0.98"]
    assert main([*argv, "--out", str(tmp_path / "a.json"), "--progress", "on"]) == 0
    err = capsys.readouterr().err
    assert "attempt" in err                  # the certified trainer's step, on stderr
    assert main([*argv, "--out", str(tmp_path / "b.json"), "--progress", "off"]) == 0
    assert capsys.readouterr().err == ""


# -- the trainers come from the registry ------------------------------------------------------
# Parametrised over fricctl.nn.TRAINERS: a new trainer module is tested here without an edit.
BARE = [name for name, t in TRAINERS.items() if t.requires is None]
#: a value of each option type (the loop is not run: the options are only recorded)
TEXT = {int: "7", float: "0.5", str: "x"}


def _recorded_options(monkeypatch, argv):
    """The trainer and options ``fricctl train ARGV`` hands to ``Trainer.train`` (not run)."""
    seen = []

    def record(self, tm, omega, target, **kw):
        seen.append((self.name, {k: v for k, v in kw.items()
                                 if k not in ("hidden", "rng", "metadata", "progress")}))
        raise ValueError("recorded")

    monkeypatch.setattr(Trainer, "train", record)
    assert main(["train", *argv]) == 2 and len(seen) == 1
    return seen[0]


@pytest.mark.parametrize("name, flag", [(name, opt.flag) for name in BARE
                                        for opt in TRAINERS[name].flags] + [(n, None) for n in BARE])
def test_each_trainer_option_reaches_the_trainer(patterns_csv, tmp_path, monkeypatch, capsys, name,
                                                 flag):
    path, _ = patterns_csv
    t = TRAINERS[name]
    argv = [str(path), "--out", str(tmp_path / "n.json"), "--trainer", name]
    if flag is None:  # no flag: the trainer's defaults (its first recipe, else its loop's)
        assert _recorded_options(monkeypatch, argv) == (name, t.defaults())
        for recipe in t.recipes:
            assert _recorded_options(monkeypatch, [*argv, "--recipe", recipe.name]) == (
                name, t.defaults(recipe.name))
        return
    opt = next(o for o in t.flags if o.flag == flag)
    got = _recorded_options(monkeypatch, [*argv, flag, TEXT[opt.type]])
    assert got == (name, {**t.defaults(), opt.name: opt.type(TEXT[opt.type])})
    assert "recorded" in capsys.readouterr().err
    # a flag another trainer does not declare is refused with that trainer, naming the owners
    for other in BARE:
        if opt.name not in {o.name for o in TRAINERS[other].flags}:
            assert main(["train", *argv[:-1], other, flag, TEXT[opt.type]]) == 2
            assert f"{flag} applies to --trainer" in capsys.readouterr().err


def _squash(text: str) -> str:
    return "".join(text.split())  # argparse wraps lines, also after a hyphen


def test_train_help_lists_every_trainer_and_its_options(capsys):
    assert main(["train", "--help"]) == 0
    text = _squash(capsys.readouterr().out)
    choices = re.search(r"--trainer\{([^}]*)\}", text).group(1).split(",")
    assert choices == BARE and DEFAULT_TRAINER in BARE
    for name, t in TRAINERS.items():
        if t.requires is None:
            assert _squash(f"{name}: {t.description}") in text and _squash(t.limits) in text
            assert all(f"[{opt.flag}" in text for opt in t.flags)
            assert all(_squash(f"{name} {r.name}") in text for r in t.recipes)
        else:  # not offered, and --help says why
            assert _squash(f"{name} (only in a pipeline: it needs {t.requires})") in text
    pipelines = re.search(r"--pipeline\{([^}]*)\}", text).group(1).split(",")
    assert pipelines == list(PIPELINES)


DUMMY = '''"""A trainer dropped in by a test: keeps the initial weights."""
import numpy as np

from .core import LoopResult, Trainer, TrainerOption


def loop(problem, *, spread: float = 1.0):
    theta = problem.initial_theta() * spread
    loss = np.full(2, 0.5)
    return LoopResult(theta=theta, loss=loss, elapsed=np.zeros(2), metadata={"spread": spread})


TRAINER = Trainer(name="dummy", description="keeps the initial weights", step="nothing",
                  loop=loop, flags=(TrainerOption(name="spread", type=float,
                                                  help="initial weights times this [-]"),))
'''


def test_a_new_trainer_module_appears_in_the_command_with_its_options(patterns_csv, tmp_path):
    # issue 19: adding a trainer is adding its module; nothing in fricctl train is edited
    path, _ = patterns_csv
    scratch = tmp_path / "scratch"
    # with the byte code (copy2 keeps the times it is checked against): no recompiling
    shutil.copytree(Path(fricctl.__file__).parent, scratch / "fricctl")
    (scratch / "fricctl" / "nn" / "train" / "dummy.py").write_text(DUMMY)
    out = tmp_path / "dummy.json"
    script = ("import json, sys\nfrom fricctl.cli import main\nfrom fricctl.nn import TRAINERS\n"
              "print(json.dumps(list(TRAINERS)))\nmain(['train', '--help'])\nprint('====')\n"
              f"sys.exit(main(['train', {str(path)!r}, '--out', {str(out)!r}, '--trainer', 'dummy', "
              "'--spread', '0.25', '--json']))\n")
    env = {**os.environ, "PYTHONPATH": str(scratch), "MPLBACKEND": "Agg"}
    proc = subprocess.run([sys.executable, "-c", script], env=env, cwd=tmp_path,
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    names, rest = proc.stdout.split("\n", 1)
    helptext, report = rest.split("====\n")
    assert "dummy" in json.loads(names)
    helptext = _squash(helptext)
    assert "dummy" in re.search(r"--trainer\{([^}]*)\}", helptext).group(1).split(",")
    assert _squash("dummy: keeps the initial weights") in helptext
    assert _squash("--spread SPREAD dummy: initial weights times this [-] (default 1)") in helptext
    assert json.loads(report)["trainer"] == "dummy"
    assert load_net(out).metadata["spread"] == 0.25  # the option reached the loop


def test_train_warns_on_a_gain_at_rest_of_one_or_more():
    # issue 25: g >= 1 cannot hold the joint at rest (no fixed point of Tm = Tc + s*g*Tm)
    from fricctl.cli.train import _gain_warnings
    from fricctl.nn import FrictionNet

    def net(scale):
        return FrictionNet(w1=[[1.0, 0.0]], b1=[0.0], w2=[1.0], b2=0.0, input_offset=[0, 0],
                           input_scale=[1, 1], output_offset=0.0, output_scale=scale,
                           envelope_low=[-1, -1], envelope_high=[1, 1])

    assert _gain_warnings(net(0.98)) == []
    (w,) = _gain_warnings(net(1.3))
    assert "1.3 >= 1" in w and "winds its torque up" in w
