"""Property (issue 15): every ``fricctl`` command given random bad arguments exits 0 or 2 with
at most one line on stderr, never a traceback: a refusal (2) is one error line; a call that
completes (0) prints nothing on stderr but its warnings, one line each.

The values are those a hostile or careless user types: negative, zero, NaN, infinities,
huge and tiny numbers, text, empty strings, files that do not exist, folders, files of the
wrong kind.  The commands run in-process (:func:`fricctl.cli.main` returns argparse's exit
code too), so an exception that escapes ``main`` fails the property with its traceback.
Small example counts keep the file in the default run; the expensive successful paths (a
diagnosis, a reproduction) are reached only through cheap invalid calls.
"""

import contextlib
import io
import itertools
import os

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from fricctl.cli import main
from fricctl.controllers import p_control, sinusoid
from fricctl.friction import Coulomb, Viscous
from fricctl.nn import save_net, smooth_friction_patterns
from fricctl.nn.train import TRAINERS
from fricctl.params import paper_actuator
from fricctl.plant import JointModel
from fricctl.simulate import simulate

NUMBERS = ["-1", "0", "nan", "inf", "-inf", "1e300", "-1e300", "1e-300", "1e-9", "abc", "",
           "0.1", "3", "1e6", "0x10", "1_0", "１"]
# FRICCTL_FUZZ_EXAMPLES=500 FRICCTL_FUZZ_RANDOM=1 for a longer, fresh hunt
SETTINGS = settings(max_examples=int(os.environ.get("FRICCTL_FUZZ_EXAMPLES", "25")),
                    deadline=None, derandomize=os.environ.get("FRICCTL_FUZZ_RANDOM") != "1",
                    suppress_health_check=[HealthCheck.function_scoped_fixture,
                                           HealthCheck.too_slow])


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("fuzz")
    out = {"dir": str(d / "folder"), "missing": str(d / "missing" / "x.csv"),
           "empty": str(d / "empty.csv"), "garbage": str(d / "garbage.csv"),
           "badjson": str(d / "bad.json")}
    os.mkdir(out["dir"])
    open(out["empty"], "w").close()
    with open(out["garbage"], "w") as fh:
        fh.write("t,torque\n1,2,3\nx\n")
    with open(out["badjson"], "w") as fh:
        fh.write('{"format": [[[[')
    out["deep"] = str(d / "deep.json")  # a RecursionError in json.loads without a depth check
    with open(out["deep"], "w") as fh:
        fh.write("[" * 50_000 + "]" * 50_000)
    out["bigint"] = str(d / "bigint.json")  # Python's int() refuses > 4300 digits
    with open(out["bigint"], "w") as fh:
        fh.write('{"format": "fricctl.FrictionNet", "version": ' + "9" * 5000 + "}")
    r = simulate(paper_actuator(), p_control(1.0, sinusoid(0.5, 1.0)), duration=0.6)
    out["record"] = str(r.to_run(source="fuzz").to_csv(d / "rec.csv"))
    m = JointModel(inertia=0.0029, friction=(Viscous(0.0025) + Coulomb(0.144)).model(),
                   units="rotary", sample_time=0.002, encoder_resolution=2 * np.pi / 4096)
    out["model"] = str(m.save(d / "model.json"))
    pats = smooth_friction_patterns(np.random.default_rng(0), n_sliding=80, n_stuck=20)
    out["patterns"] = str(d / "pats.csv")
    np.savetxt(out["patterns"], np.column_stack([pats.tm, pats.omega, pats.friction]),
               delimiter=",", header="tm,omega,friction", comments="")
    for kind, factor in (("tinypats", 1e-300), ("hugepats", 1e300)):  # scaled out of range
        out[kind] = str(d / f"{kind}.csv")
        np.savetxt(out[kind], factor * np.column_stack([pats.tm, pats.omega, pats.friction]),
                   delimiter=",", header="tm,omega,friction", comments="")
    net = TRAINERS["backprop"].train(pats.tm, pats.omega, pats.friction, epochs=3,
                                     rng=np.random.default_rng(0)).net
    out["net"] = str(save_net(net, d / "net.json"))
    out["outdir"] = d
    return out


def _paths(files, *kinds):
    return st.sampled_from([files[k] for k in kinds])


BAD = st.sampled_from(NUMBERS)
_FRESH = itertools.count()


def _either(good, bad=BAD):
    """A value that is usually valid (so the call goes deep) and sometimes bad."""
    return st.one_of(good, good, bad)


def _options(draw, table):
    """A random subset of ``table`` (option -> strategy of its value, None for a flag)."""
    names = draw(st.lists(st.sampled_from(sorted(table)), unique=True, max_size=5))
    argv = []
    for name in names:
        value = table[name]
        argv += [name] if value is None else [name, draw(value)]
    return argv


def _out(files, suffix=".csv"):
    # mostly a fresh name in the temporary folder (so a success does not make the next
    # example's output exist); else the folder, a missing folder or an input
    fresh = st.builds(lambda: str(files["outdir"] / f"out{next(_FRESH)}{suffix}"))
    return st.one_of(fresh, fresh, st.sampled_from([files["dir"], files["missing"],
                                                    files["record"], str(files["outdir"] / "x")]))


def _num(*good):
    return _either(st.sampled_from(list(good)))


@st.composite
def design_args(draw, files):
    law = draw(st.sampled_from(["p", "pd", "pd", "pid"]))
    return ["design", law, "--rise-time", draw(_num("0.2", "0.05", "1")),
            "--damping", draw(_num("0.7", "1", "0.9")), *_options(draw, {
                "--model": _paths(files, "missing", "dir", "badjson", "model", "record", "deep",
                                  "bigint"),
                "--rise-time-definition": st.sampled_from(["0-100", "10-90", "x"]),
                "--json": None, "--link": None})]


@st.composite
def simulate_args(draw, files):
    ctl = draw(st.sampled_from(["open", "p", "pd"]))
    sig = _either(st.sampled_from(["step:0.3", "sinusoid:0.2,1", "sawtooth:0.1,0.5"]),
                  st.builds(lambda k, a: f"{k}:{a}", st.sampled_from(["step", "sinusoid", "x"]),
                            st.sampled_from(NUMBERS + ["1,nan", "1,1e300", "1,-1"])))
    base = ["simulate", "--controller", ctl, "--duration", draw(_num("0.2", "0.5"))]
    if ctl == "open":
        base += ["--torque", draw(sig)]
    else:
        base += ["--kp", draw(_num("1", "0.5")), "--reference", draw(sig)]
        base += ["--kd", draw(_num("0.05"))] if ctl == "pd" else []
    return base + _options(draw, {
        "--friction-scale": _num("1", "0.5"), "--scale": _num("0.9", "1"),
        "--compensation": st.sampled_from(["coulomb", "nn"]),
        "--net": _paths(files, "net", "net", "missing", "dir", "badjson", "record", "deep",
                        "bigint"),
        "--model": _paths(files, "model", "model", "missing", "dir", "badjson", "net", "deep",
                          "bigint"),
        "--csv": _out(files), "--figure": _out(files, ".png"), "--c-source": _out(files, ".c"),
        "--plant": st.sampled_from(["rigid", "flexible"]), "--clip": None, "--json": None,
        "--force": None})


@st.composite
def identify_args(draw, files):
    run = draw(_paths(files, "record", "record", "missing", "dir", "empty", "garbage", "model"))
    return ["identify", run, *_options(draw, {
        "--border": _num("5", "50", "1000"), "--max-torque": _num("0.5", "10"),
        "--out": _out(files, ".json"), "--recipe": st.sampled_from(["plain", "idim_ls"]),
        "--model": st.sampled_from(["coulomb_viscous", "stribeck"]),
        "--units": st.sampled_from(["rotary", "linear"]), "--json": None})]


@st.composite
def patterns_args(draw, files):
    run = draw(_paths(files, "record", "record", "missing", "dir", "empty", "garbage"))
    model = draw(_paths(files, "model", "model", "missing", "dir", "badjson", "record"))
    return ["patterns", run, "--model", model, "--out", draw(_out(files)), *_options(draw, {
        "--border": _num("5", "0", "100000"), "--guard": _num("2", "0", "100000"),
        "--net": _paths(files, "net", "missing", "badjson", "deep", "bigint"), "--json": None})]


@st.composite
def train_args(draw, files):
    pats = draw(_paths(files, "patterns", "patterns", "missing", "dir", "empty", "garbage",
                       "record", "tinypats", "hugepats"))
    trainer = draw(st.sampled_from(["casadi", "backprop", "backprop"]))
    argv = ["train", pats, "--out", draw(_out(files, ".json")), "--progress", "off",
            "--trainer", trainer, "--restarts", draw(_num("1", "2")),
            "--hidden", draw(_num("2", "4"))]
    if trainer == "backprop":
        argv += ["--epochs", draw(_num("2", "5")), *_options(draw, {
            "--learning-rate": _num("0.01", "10"), "--momentum": _num("0.9", "0"),
            "--batch-size": _num("1", "1000"), "--velocity-scale": _num("10"),
            "--schedule": st.sampled_from(["constant", "cosine", "x"]),
            "--recipe": st.sampled_from(["paper", "converging"])})]
    return argv + _options(draw, {"--seed": _num("0", "7"), "--c-source": _out(files, ".c"),
                                  "--json": None})


@st.composite
def diagnose_args(draw, files):
    # only files that cannot be diagnosed (a diagnosis of a real record takes seconds)
    run = draw(_paths(files, "missing", "dir", "empty", "garbage", "model"))
    return ["diagnose", run, *_options(draw, {
        "--window": _num("0.5"), "--motor-revolution": _num("0.0025"),
        "--model": _paths(files, "model", "missing", "dir", "badjson"),
        "--units": st.sampled_from(["rotary", "x"]), "--report": _out(files, ""),
        "--json": None})]


@st.composite
def reproduce_args(draw, files):
    # a cheap invalid call: a bad count (never a valid reproduction), or --help
    bad = st.sampled_from(["-1", "0", "nan", "abc", "", "1e300", "1.5", "100000"])
    return draw(st.sampled_from([["reproduce", "--help"],
                                 ["reproduce", "--seeds", draw(bad), "--out", files["dir"]],
                                 ["reproduce", "--workers", draw(bad), "--out", files["dir"]],
                                 ["reproduce", "--pipelines", draw(st.sampled_from(
                                     ["", ",", "x", "paper,paper"])), "--out", files["dir"]]]))


@st.composite
def compare_args(draw, files):
    # a cheap invalid call: a bad count, name list or executor (never a valid comparison), or --help
    bad = st.sampled_from(["-1", "0", "nan", "abc", "", "1e300", "1.5", "100000"])
    names = st.sampled_from(["", ",", "x", "none,none", "none,"])
    return draw(st.sampled_from([["compare", "--help"],
                                 ["compare", "--seeds", draw(bad), "--out", files["dir"]],
                                 ["compare", "--executor", "process", "--workers", draw(bad),
                                  "--out", files["dir"]],
                                 ["compare", "--executor", draw(st.sampled_from(["", "x", "threads"])),
                                  "--out", files["dir"]],
                                 ["compare", draw(st.sampled_from(["--compensators", "--experiments",
                                                                   "--plants"])), draw(names),
                                  "--out", files["dir"]]]))


COMMANDS = {"design": design_args, "simulate": simulate_args, "identify": identify_args,
            "patterns": patterns_args, "train": train_args, "diagnose": diagnose_args,
            "reproduce": reproduce_args, "compare": compare_args}


def _run(argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, err.getvalue()


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_bad_arguments_exit_0_or_2_with_one_line(command, files):
    @SETTINGS
    @given(argv=COMMANDS[command](files))
    def check(argv):
        code, err = _run(argv)
        if argv[-1] == "--help" or "--help" in argv:
            assert code == 0
            return
        assert code in (0, 2), (argv, code, err)
        assert "Traceback" not in err, (argv, err)
        lines = [line for line in err.splitlines() if line.strip()]
        if code == 2:  # refused: exactly one line, the error
            assert len(lines) == 1 and lines[0].startswith(f"fricctl {command}"), (argv, err)
        else:  # done: at most one line per warning (a design can miss two specs), nothing else
            assert all(line.startswith(f"fricctl {command}: warning: ") for line in lines), (argv, err)

    check()
