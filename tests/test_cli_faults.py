"""Fault injection on the command line (issue 26): what a lab does to a tool.

Each writing command is interrupted (SIGINT, SIGTERM) at a seeded random moment, cut by a
file-size limit (``RLIMIT_FSIZE``, what ``ulimit -f`` or a full quota does), raced by a
second run writing the same file, and handed an output that is a hard link to its input.
After each: the exit code is the documented one (0, 2 for an error, 130 for Ctrl-C, 143 for
SIGTERM), stderr is one line without a traceback, the destination is absent or equals a
complete version (the previous one, or the one this command writes: compared byte for byte
with a reference run, then parsed by fricctl's reader), and no temporary file is left.

The reference is fricctl's own output of the same call made in this process: the outputs are
deterministic (seeded training, no time stamps).  A signal that lands while Python is still
loading fricctl (the first few tenths of a second) ends the process as Python does
(status -signal); the files are untouched then too, which is asserted.
"""

import os
import resource
import signal
import stat
import subprocess
import sys
import time
import zlib
from pathlib import Path

import numpy as np
import pytest

from fricctl._atomic import TEMP_MARK, atomic_folder, atomic_path, write_text
from fricctl.cli import Terminated, main
from fricctl.controllers import pd_control, sinusoid
from fricctl.datasets import Run, read_patterns
from fricctl.nn import load_net
from fricctl.params import paper_actuator
from fricctl.plant import JointModel
from fricctl.simulate import simulate

ROOT = Path(__file__).resolve().parents[1]

#: Each writing command: argv writing ``out`` (``variant`` 0: the call under test, 1: another
#: call, whose output is the "previous version"), the reader that parses its output, and a
#: file size limit [bytes] below the size of its output.
COMMANDS = {
    "simulate": (lambda out, variant: ["simulate", "--controller", "pd", "--rise-time", "0.3",
                                       "--damping", "0.9", "--reference", "sinusoid:0.5,1",
                                       "--duration", ("16", "8")[variant], "--csv", out],
                 Run.from_csv, 64_000),
    "identify": (lambda out, variant: ["identify", "record.csv", "--model",
                                       ("coulomb_viscous", "asymmetric")[variant], "--out", out],
                 JointModel.load, 1_000),
    "patterns": (lambda out, variant: ["patterns", "record.csv", "--model", "model.json",
                                       "--border", ("5", "9")[variant], "--out", out],
                 read_patterns, 64_000),
    "train": (lambda out, variant: ["train", "patterns.csv", "--trainer", "backprop", "--epochs",
                                    "100", "--restarts", "1", "--seed", ("0", "1")[variant],
                                    "--out", out],
              load_net, 1_000),
}
SUFFIX = {"simulate": ".csv", "identify": ".json", "patterns": ".csv", "train": ".json"}
#: Exit code and stderr of an interrupted command (docs/limits.md, fricctl.cli).
INTERRUPTED = {signal.SIGINT: (130, "interrupted (Ctrl-C)"),
               signal.SIGTERM: (143, "terminated (SIGTERM)")}


@pytest.fixture(scope="module")
def work(tmp_path_factory):
    """A folder with a record, its model, its patterns, and each command's two reference
    outputs (``ref/<command>-<variant>``)."""
    d = tmp_path_factory.mktemp("faults")
    p = paper_actuator()
    run = simulate(p, pd_control(2.0, 0.1, sinusoid(0.5, 1.0)), duration=8.0).to_run(source="bench")
    run.to_csv(d / "record.csv")
    cwd = os.getcwd()
    os.chdir(d)  # the commands are given names relative to the folder, as in the subprocesses
    try:
        assert main(["identify", "record.csv", "--out", "model.json"]) == 0
        assert main(["patterns", "record.csv", "--model", "model.json", "--out", "patterns.csv"]) == 0
        (d / "ref").mkdir()
        for name, (argv, _, _) in COMMANDS.items():
            for variant in (0, 1):
                # same base name as the runs under test (train writes the patterns' name only)
                assert main(argv(f"ref/{name}-{variant}{SUFFIX[name]}", variant)) == 0
    finally:
        os.chdir(cwd)
    return d


def _reference(work, name, variant) -> bytes:
    return (work / "ref" / f"{name}-{variant}{SUFFIX[name]}").read_bytes()


def _start(work, argv, *, fsize=None, new_session=False):
    env = dict(os.environ, MPLBACKEND="Agg",
               PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]))

    def limit():  # in the child, before exec: ulimit -f
        resource.setrlimit(resource.RLIMIT_FSIZE, (fsize, fsize))

    return subprocess.Popen([sys.executable, "-m", "fricctl", *argv], cwd=work, env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                            preexec_fn=None if fsize is None else limit,
                            start_new_session=new_session)


def _leftovers(folder: Path) -> list:
    return sorted(p.name for p in folder.rglob(f"*{TEMP_MARK}*"))


def _out(work, name, tag) -> Path:
    """A fresh destination in a folder of its own (temporary files are looked for there)."""
    folder = work / f"{name}-{tag}"
    folder.mkdir()
    return folder / f"{name}-0{SUFFIX[name]}"


def _assert_complete_or_as_before(work, name, dest: Path, before: bytes | None) -> None:
    """``dest`` is what it was (absent when ``before`` is None) or this call's complete output."""
    if not dest.exists():
        assert before is None, f"{dest.name}: the previous version was removed"
    else:
        got = dest.read_bytes()
        assert got in (before, _reference(work, name, 0)), f"{dest.name}: a partial or mixed file"
        COMMANDS[name][1](dest)  # and fricctl reads it
    assert _leftovers(dest.parent) == []


def _one_line(err: str, start: str) -> None:
    assert err.count("\n") == 1 and err.startswith(start) and "Traceback" not in err, err


# -- the helper itself ----------------------------------------------------------------------
@pytest.mark.parametrize("exc", [OSError(27, "File too large"), KeyboardInterrupt(), Terminated(),
                                 RuntimeError("a bug")])
def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path, exc):
    dest = tmp_path / "out.json"
    dest.write_text("old")
    with pytest.raises(type(exc)) as info:
        with atomic_path(dest) as tmp:
            tmp.write_text("half of the n")
            raise exc
    assert dest.read_text() == "old" and _leftovers(tmp_path) == []
    if isinstance(exc, OSError):  # a full disk's error names the user's file, not the temporary
        assert info.value.filename == str(dest)


def test_without_overwrite_a_file_created_meanwhile_is_kept(tmp_path):
    dest = tmp_path / "net.json"
    with pytest.raises(FileExistsError, match="meanwhile"):
        with atomic_path(dest, overwrite=False) as tmp:
            tmp.write_text("mine")
            dest.write_text("the other run's")  # a second run finished first
    assert dest.read_text() == "the other run's" and _leftovers(tmp_path) == []
    write_text(dest, "replaced whole")  # overwrite=True: os.replace
    assert dest.read_text() == "replaced whole"


def test_a_new_folder_appears_whole_or_not_at_all(tmp_path):
    with pytest.raises(KeyboardInterrupt):
        with atomic_folder(tmp_path / "report") as where:
            write_text(where / "a.md", "a")
            raise KeyboardInterrupt
    assert list(tmp_path.iterdir()) == []
    with atomic_folder(tmp_path / "report") as where:
        write_text(where / "a.md", "a")
    assert [p.name for p in tmp_path.iterdir()] == ["report"]
    assert (tmp_path / "report" / "a.md").read_text() == "a"


def test_a_symlinked_output_is_written_through_and_new_files_get_the_umask(tmp_path):
    target = tmp_path / "target.json"
    target.write_text("old")
    os.chmod(target, 0o640)
    (tmp_path / "link.json").symlink_to(target)
    write_text(tmp_path / "link.json", "new")
    assert (tmp_path / "link.json").is_symlink() and target.read_text() == "new"
    assert target.stat().st_mode & 0o777 == 0o640  # an existing file keeps its mode
    umask = os.umask(0o022)
    os.umask(umask)
    assert write_text(tmp_path / "fresh.txt", "x").stat().st_mode & 0o777 == 0o666 & ~umask


# -- hard links: the same file under two names -----------------------------------------------
@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_an_output_hard_linked_to_an_input_is_refused(work, tmp_path, capsys, name):
    inputs = {"simulate": "model.json", "identify": "record.csv", "patterns": "record.csv",
              "train": "patterns.csv"}
    src = work / inputs[name]
    before = src.read_bytes()
    link = tmp_path / f"link{SUFFIX[name]}"
    os.link(src, link)
    argv = COMMANDS[name][0](str(link), 0)
    if name == "simulate":  # the model file is simulate's input
        argv = ["simulate", "--model", str(src), "--controller", "p", "--kp", "1",
                "--reference", "step:0.1", "--csv", str(link)]
    cwd = os.getcwd()
    os.chdir(work)
    try:
        assert main([*argv, "--force"]) == 2
    finally:
        os.chdir(cwd)
    err = capsys.readouterr().err
    _one_line(err, f"fricctl {name}: error:")
    assert "hard link" in err and src.name in err and link.name in err
    assert src.read_bytes() == before


def test_a_report_file_hard_linked_to_the_record_is_refused(work, tmp_path, capsys):
    report = tmp_path / "report"
    report.mkdir()
    os.link(work / "record.csv", report / "report.md")
    assert main(["diagnose", str(work / "record.csv"), "--report", str(report), "--force"]) == 2
    _one_line(capsys.readouterr().err, "fricctl diagnose: error: --report (report.md)")


# -- a file size limit (ulimit -f, a full quota) ----------------------------------------------
def _cut_by_a_file_size_limit(work, name):
    argv, _, limit = COMMANDS[name]
    dest = _out(work, name, "fsize")
    old = _reference(work, name, 1)
    dest.write_bytes(old)
    proc = _start(work, [*argv(str(dest), 0), "--force"], fsize=limit)
    err = proc.communicate()[1]
    assert proc.returncode == 2, err
    # the error is one line, the last, naming the user's file; before it, the command's own
    # warnings about its result (identify: the record's estimates) may stand, one line each
    *warnings, last = err.splitlines()
    _one_line(last + "\n", f"fricctl {name}: error: {dest}")
    assert all(w.startswith(f"fricctl {name}: warning: ") for w in warnings), err
    assert dest.read_bytes() == old and _leftovers(dest.parent) == []


@pytest.mark.parametrize("name", ["simulate", "patterns"])
def test_a_file_size_limit_leaves_the_previous_version(work, name):
    _cut_by_a_file_size_limit(work, name)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["identify", "train"])
def test_a_file_size_limit_leaves_the_previous_version_slow(work, name):
    _cut_by_a_file_size_limit(work, name)


# -- interrupts at a random moment ------------------------------------------------------------
def _interrupt(work, name, sig, seed):
    rng = np.random.default_rng([seed, zlib.crc32(name.encode()), int(sig)])
    previous = bool(rng.integers(2))  # over an older version (--force), or into nothing
    dest = _out(work, name, f"{sig.name}-{seed}")
    before = _reference(work, name, 1) if previous else None
    if previous:
        dest.write_bytes(before)
    argv = COMMANDS[name][0](str(dest), 0) + (["--force"] if previous else [])
    proc = _start(work, argv)
    time.sleep(rng.uniform(0.5, 6.0))  # a command here takes 3 to 8 s
    proc.send_signal(sig)
    err = proc.communicate()[1]
    code, what = INTERRUPTED[sig]
    if proc.returncode == 0:  # it finished first
        assert dest.read_bytes() == _reference(work, name, 0)
    elif proc.returncode == code:
        _one_line(err, f"fricctl {name}: {what}")
    else:  # still loading the fricctl package, before its main: Python's own ending (docs/
        # limits.md), a Ctrl-C possibly wrapped by a compiled module's import; nothing touched
        assert proc.returncode == -sig or (sig == signal.SIGINT and proc.returncode == 1
                                           and "KeyboardInterrupt" in err), err
    _assert_complete_or_as_before(work, name, dest, before)


@pytest.mark.parametrize("name, sig", [("patterns", signal.SIGINT), ("train", signal.SIGTERM)])
def test_an_interrupt_leaves_no_partial_output(work, name, sig):
    _interrupt(work, name, sig, seed=0)


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_an_interrupt_leaves_no_partial_output_slow(work, name, sig, seed):
    _interrupt(work, name, sig, seed=seed + 1)


# -- two runs writing the same file -----------------------------------------------------------
def test_two_runs_to_the_same_out_without_force_one_is_refused(work):
    argv = COMMANDS["train"][0]
    dest = _out(work, "train", "race")
    procs = [_start(work, argv(str(dest), variant)) for variant in (0, 1)]
    errs = [p.communicate()[1] for p in procs]
    codes = [p.returncode for p in procs]
    assert sorted(codes) == [0, 2], errs
    winner = codes.index(0)
    _one_line(errs[1 - winner], "fricctl train: error:")
    assert "exists" in errs[1 - winner]
    assert dest.read_bytes() == _reference(work, "train", winner)  # the winner's, whole
    assert _leftovers(dest.parent) == []


@pytest.mark.slow
def test_two_runs_to_the_same_out_with_force_never_interleave(work):
    argv = COMMANDS["patterns"][0]
    dest = _out(work, "patterns", "race-force")
    procs = [_start(work, [*argv(str(dest), variant), "--force"]) for variant in (0, 1)]
    errs = [p.communicate()[1] for p in procs]
    assert [p.returncode for p in procs] == [0, 0], errs
    assert dest.read_bytes() in (_reference(work, "patterns", 0), _reference(work, "patterns", 1))
    assert _leftovers(dest.parent) == []


# -- diagnose --report and reproduce ----------------------------------------------------------
@pytest.mark.slow
@pytest.mark.parametrize("seed", range(3))
def test_an_interrupted_report_leaves_no_folder(work, seed):
    rng = np.random.default_rng(seed)
    report = work / f"report-{seed}"
    proc = _start(work, ["diagnose", "record.csv", "--report", str(report)])
    time.sleep(rng.uniform(2.0, 12.0))
    proc.send_signal(signal.SIGINT)
    err = proc.communicate()[1]
    assert proc.returncode in (0, 130, -signal.SIGINT), err
    if report.exists():  # the whole folder or none: also when the signal came after the report
        # was in place (status 130 while the text was printed; -2 during the interpreter's
        # shutdown, 0.4-0.7 s after the command returned, where Python's default SIGINT is back)
        assert sorted(p.name for p in report.iterdir()) == sorted(
            ["residuals.png", "simulation.png", "spectrum.png", "steps.png", "report.md",
             "extended_model.json"])
    else:
        assert proc.returncode != 0, err
    assert _leftovers(work) == []


@pytest.mark.slow
def test_a_report_cut_by_a_file_size_limit_leaves_no_folder(work):
    report = work / "report-fsize"
    proc = _start(work, ["diagnose", "record.csv", "--report", str(report)], fsize=20_000)
    err = proc.communicate()[1]
    assert proc.returncode == 2, err
    _one_line(err, f"fricctl diagnose: error: {report}{os.sep}")  # the file, not a temporary
    assert not report.exists() and _leftovers(work) == []


def _alive(pids) -> list:
    out = []
    for pid in pids:
        try:
            state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
        except OSError:
            continue
        if state != "Z":
            out.append(pid)
    return out


def _children(pid) -> list:
    return subprocess.run(["pgrep", "-P", str(pid)], capture_output=True, text=True).stdout.split()


@pytest.mark.slow
@pytest.mark.skipif(not Path("/proc").is_dir(), reason="reads /proc")
@pytest.mark.parametrize("how", ["ctrl-c", "kill-9"])
def test_reproduce_workers_die_with_their_parent(work, how):
    out = work / f"reproduce-{how}"
    proc = _start(work, ["reproduce", "--out", str(out), "--fast", "--seeds", "2", "--workers",
                         "2", "--pipelines", "fricctl"], new_session=True)
    while len(_children(proc.pid)) < 2 and proc.poll() is None:  # the workers have started
        time.sleep(0.2)
    time.sleep(2.0)
    kids = _children(proc.pid)
    assert proc.poll() is None and kids
    if how == "ctrl-c":  # a terminal sends SIGINT to the whole foreground process group
        os.killpg(proc.pid, signal.SIGINT)
    else:
        proc.kill()
    err = proc.communicate()[1]
    if how == "ctrl-c":
        assert proc.returncode == 130, err
        assert "Traceback" not in err and err.rstrip().endswith(
            "fricctl reproduce: interrupted (Ctrl-C); outputs not yet complete were not written")
    for _ in range(600):  # the workers notice within 0.2 s; a loaded machine may take longer
        if not _alive(kids):
            break
        time.sleep(0.1)
    assert _alive(kids) == []
    if how == "kill-9":  # runs no clean-up: the unfinished tree is left beside DIR, never in it
        assert not out.exists()
        assert [p.name for p in work.glob(f"*{TEMP_MARK}*")] in ([], [p.name for p in work.glob(
            f".{out.name}.*{TEMP_MARK}")])
    else:
        assert _leftovers(work) == []


# -- files from elsewhere ---------------------------------------------------------------------
def _bad_file(tmp_path, name, content: bytes) -> Path:
    path = tmp_path / name
    path.write_bytes(content)
    return path


def _mat_v73(tmp_path) -> Path:
    """The 128-byte header of a MATLAB v7.3 file (HDF5 inside): version 0x0200."""
    text = b"MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: Mon Jan  1 00:00:00 2024 HDF5"
    return _bad_file(tmp_path, "v73.mat", text.ljust(116) + bytes(8) + b"\x00\x02IM" + bytes(512))


def _mat_corrupt(tmp_path) -> Path:
    from scipy.io import savemat

    n = 500
    t = np.arange(n) * 1e-3
    path = tmp_path / "corrupt.mat"
    savemat(path, {"t": t, "qm": np.sin(t), "qg": np.sin(t), "vir": np.cos(t), "gtau": 1.0,
                   "kp": 1.0, "kv": 1.0}, do_compression=True)
    raw = bytearray(path.read_bytes())
    raw[1000:1040] = b"\x13" * 40  # inside the compressed data of a variable
    path.write_bytes(bytes(raw))
    return path


@pytest.mark.parametrize("make, words", [
    (lambda d: _bad_file(d, "nul.csv", bytes(3000)), "NUL byte"),
    (lambda d: _bad_file(d, "long.csv", b"t,torque,position\n" + b"1" * 200_000 + b"\n"),
     "200000 characters"),
    (_mat_v73, "save it with -v7"),
    (_mat_corrupt, "corrupt MATLAB file"),
])
@pytest.mark.parametrize("command", ["identify", "diagnose"])
def test_a_foreign_file_is_refused_in_one_line_naming_it_once(tmp_path, capsys, make, words,
                                                              command):
    path = make(tmp_path)
    assert main([command, str(path)]) == 2
    err = capsys.readouterr().err
    _one_line(err, f"fricctl {command}: error:")
    assert words in err and err.count(path.name) == 1, err


def test_a_utf8_byte_order_mark_is_accepted(work, tmp_path, capsys):
    bom = tmp_path / "excel.csv"
    bom.write_bytes(b"\xef\xbb\xbf" + (work / "record.csv").read_bytes())
    assert main(["identify", str(bom), "--json"]) == 0
    with_bom = capsys.readouterr().out
    assert main(["identify", str(work / "record.csv"), "--json"]) == 0
    assert capsys.readouterr().out == with_bom
    plain = tmp_path / "excel-header.csv"  # a BOM before the header itself (no '#' lines)
    text = (work / "record.csv").read_text().splitlines()
    plain.write_bytes(b"\xef\xbb\xbf" + "\n".join(x for x in text if not x.startswith("#")).encode())
    assert Run.from_csv(plain).n_samples == Run.from_csv(work / "record.csv").n_samples


def test_a_dangling_output_link_names_its_target_folder(work, tmp_path, capsys):
    link = tmp_path / "model.json"
    link.symlink_to(tmp_path / "missing" / "model.json")
    assert main(["identify", str(work / "record.csv"), "--out", str(link)]) == 2
    err = capsys.readouterr().err
    _one_line(err, "fricctl identify: error: --out:")
    assert str(tmp_path / "missing") in err


# -- messages (issue 26) ----------------------------------------------------------------------
@pytest.mark.parametrize("folder", ["atomic_folder", "replace_folder"])
def test_a_full_disk_in_a_new_folder_names_the_file_not_the_temporary(tmp_path, folder):
    import errno

    from fricctl import _atomic

    dest = tmp_path / "report"
    with pytest.raises(OSError) as info:
        with getattr(_atomic, folder)(dest) as where:
            with atomic_path(where / "residuals.png"):
                raise OSError(errno.ENOSPC, "No space left on device")  # names no file
    assert info.value.errno == errno.ENOSPC and info.value.filename == str(dest / "residuals.png")
    assert list(tmp_path.iterdir()) == []


def test_a_folder_holding_a_mount_point_is_not_replaced(tmp_path, monkeypatch):
    # carried into the new folder, a mount's files would be copied (no hard links across
    # devices) and then removed with the old folder: refused, the folder left as it was
    import os

    from fricctl import _atomic

    dest = tmp_path / "report"
    (dest / "mnt").mkdir(parents=True)
    (dest / "mnt" / "data.bin").write_text("theirs")
    mount = str(dest / "mnt")
    real = os.path.ismount
    monkeypatch.setattr(os.path, "ismount", lambda p: os.fspath(p) == mount or real(p))
    with pytest.raises(ValueError, match="holds the mount point .*mnt"):
        with _atomic.replace_folder(dest, overwrite=True) as where:
            (where / "report.md").write_text("new")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["report"]
    assert sorted(p.name for p in dest.iterdir()) == ["mnt"]
    assert (dest / "mnt" / "data.bin").read_text() == "theirs"


@pytest.mark.parametrize("argv", [["diagnose", "{record}", "--report", "{out}", "--force"],
                                  ["reproduce", "--out", "{out}", "--force", "--fast", "--seeds",
                                   "1"]])
@pytest.mark.parametrize("where", ["itself", "inside", "linked"])
def test_a_mount_point_in_a_replaced_folder_is_refused_before_any_work(work, tmp_path, capsys,
                                                                        monkeypatch, argv, where):
    # the folder is replaced as a whole when the run ends: a mount point there (the folder
    # itself, which cannot be renamed, or one inside it) was refused only then, after the
    # whole diagnosis or reproduction (review R12); the option naming a link to a mount point
    # is the mount point the swap meets (review R13)
    import fricctl.diagnose
    import fricctl.paper

    out = tmp_path / "out"
    (out / "mnt").mkdir(parents=True)
    (out / "old.txt").write_text("old")
    mount = str(out if where != "inside" else out / "mnt")
    if where == "linked":
        (tmp_path / "link").symlink_to(out)
    real = os.path.ismount
    monkeypatch.setattr(os.path, "ismount", lambda p: os.fspath(p) == mount or real(p))

    def no_work(*args, **kwargs):
        raise AssertionError("the run started")

    monkeypatch.setattr(fricctl.diagnose, "diagnose", no_work)
    monkeypatch.setattr(fricctl.paper, "reproduce_paper", no_work)
    given = tmp_path / "link" if where == "linked" else out
    args = [a.format(record=work / "record.csv", out=given) for a in argv]
    assert main(args) == 2
    err = capsys.readouterr().err
    _one_line(err, f"fricctl {argv[0]}: error: ")
    assert f"{mount}: a mount point" in err or f"holds the mount point {mount}" in err
    assert (out / "old.txt").read_text() == "old"


def test_a_full_disk_names_the_output_file(tmp_path, capsys, monkeypatch):
    import errno

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(np, "savetxt", full)
    out = tmp_path / "run.csv"
    assert main(["simulate", "--torque", "constant:0.3", "--duration", "0.1", "--csv", str(out)]) == 2
    err = capsys.readouterr().err
    _one_line(err, f"fricctl simulate: error: {out}: No space left on device")
    assert not out.exists() and _leftovers(tmp_path) == []


@pytest.mark.parametrize("argv", [["diagnose", "{record}", "--report", "{link}"],
                                  ["reproduce", "--out", "{link}", "--fast", "--seeds", "1"]])
def test_a_dangling_output_folder_link_names_its_target_folder(work, tmp_path, capsys, argv):
    link = tmp_path / "out"
    link.symlink_to(tmp_path / "missing" / "out")
    argv = [a.format(record=work / "record.csv", link=link) for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err
    _one_line(err, f"fricctl {argv[0]}: error: --")
    assert f"symbolic link into the folder {tmp_path / 'missing'}, which does not exist" in err
    assert TEMP_MARK not in err and _leftovers(tmp_path) == []


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no named pipes")
def test_a_named_pipe_or_device_output_is_written_into_not_replaced(tmp_path, capsys):
    # a FIFO (and so /dev/null, as root) was replaced by a regular file: os.replace onto it
    import threading

    fifo = tmp_path / "run.csv"
    os.mkfifo(fifo)
    got = []
    reader = threading.Thread(target=lambda: got.append(fifo.read_bytes()), daemon=True)
    reader.start()
    assert main(["simulate", "--torque", "constant:0.3", "--duration", "0.1", "--csv", str(fifo),
                 "--force"]) == 0
    reader.join(timeout=60)
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)  # still the pipe
    assert got and got[0].startswith(b"# source: fricctl simulate") and got[0].count(b"\n") == 53
    assert _leftovers(tmp_path) == []


def test_diagnose_refuses_a_huge_record_by_count_before_reading_it(tmp_path, monkeypatch, capsys):
    # issue 26: a 25-million-sample record died of MemoryError after 141 s of parsing; the
    # count is taken first (8 MB chunks, no parsing): rows past the limit are never read,
    # so garbage there cannot be what the message is about
    import fricctl.diagnose as dg
    from fricctl.cli import main
    from fricctl.datasets import record_length

    monkeypatch.setattr(dg, "MAX_SAMPLES", 1000)
    path = tmp_path / "huge.csv"
    rows = "".join(f"{0.001 * k:.3f},0.1,{1e-4 * k:.6f}\n" for k in range(1200))
    path.write_text("# units: rotary\nt,torque,position\n" + rows + "not,a,number\n")
    assert record_length(path) == 1201
    assert main(["diagnose", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "1201 samples, more than the 1000" in err
    assert "decimate it by 2" in err


@pytest.mark.slow
def test_diagnose_at_its_sample_limit_stays_within_its_memory_budget(tmp_path):
    # issue 26: the limit is a measurement, checked at the limit: a record of exactly
    # MAX_SAMPLES (a 120 s, 2 kHz generator record tiled, continuous in time and position)
    # diagnosed by the CLI in a child process whose peak RSS (interpreter, CSV reading and
    # compiled code included) stays under MEMORY_BUDGET; one sample more is refused
    import subprocess
    import sys

    from fricctl.bench.hidden_effects import hidden_effect_record
    from fricctl.datasets import Run
    from fricctl.diagnose.api import MAX_SAMPLES, MEMORY_BUDGET

    r = hidden_effect_record(np.random.default_rng(7), cause="none", duration=120.0,
                             sample_time=0.0005).run
    k = -(-(MAX_SAMPLES + 1) // r.n_samples)
    t = np.concatenate([r.t + i * r.n_samples * r.sample_time for i in range(k)])
    q = np.concatenate([r.position + i * (r.position[-1] - r.position[0]) for i in range(k)])
    tm = np.tile(r.torque, k)
    for n, name in ((MAX_SAMPLES, "limit.csv"), (MAX_SAMPLES + 1, "over.csv")):
        Run(t=t[:n], torque=tm[:n], position=q[:n]).to_csv(tmp_path / name)
    code = ("import resource, sys; from fricctl.cli import main; "
            "rc = main(['diagnose', sys.argv[1], '--json']); "
            "print('RSS', rc, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024, "
            "file=sys.stderr)")
    out = subprocess.run([sys.executable, "-c", code, str(tmp_path / "limit.csv")],
                         capture_output=True, text=True)
    _, rc, rss = [ln for ln in out.stderr.splitlines() if ln.startswith("RSS")][0].split()
    assert rc == "0" and int(rss) < MEMORY_BUDGET, (rc, int(rss) / 1e9)
    over = subprocess.run([sys.executable, "-m", "fricctl", "diagnose",
                           str(tmp_path / "over.csv")], capture_output=True, text=True)
    assert over.returncode == 2 and f"more than the {MAX_SAMPLES}" in over.stderr


def test_a_reader_that_closes_stdout_is_not_an_error():
    # `fricctl simulate ... | head -3`: the reader leaves, the next write fails with EPIPE.  That
    # printed 'fricctl simulate: error: Broken pipe' and exit 2; now the command ends quietly with
    # 141 (128 + SIGPIPE, as a program stopped by the signal), its warnings still on stderr
    import subprocess
    import sys

    proc = subprocess.Popen([sys.executable, "-m", "fricctl", "simulate", "--controller", "pd",
                             "--rise-time", "0.3", "--damping", "0.9", "--duration", "0.2"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    proc.stdout.close()  # the reader is gone before the command writes
    err = proc.stderr.read()
    assert proc.wait() == 141, err
    # (its warnings may say "error": the 0.2 s run has not settled, and its warning says so)
    assert ": error:" not in err and "Traceback" not in err and "Exception ignored" not in err
    assert "Broken pipe" not in err
    assert "fricctl simulate: warning: sampled loop" in err  # the design's warning (0.3 s / 0.9)
