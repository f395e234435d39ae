"""``fricctl.cli._painters``: figures drawn in forked processes -- who draws, errors raised in
the command, every process reaped, the serial fallback's conditions."""

import os
import threading
import time
from pathlib import Path

import pytest

from fricctl.cli._painters import Painters, forked_painters, parallel_available

pytestmark = pytest.mark.skipif(not hasattr(os, "fork"), reason="POSIX only")
linux = pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="reads /proc")


def _pid_writer(result, names, folder: Path, *, overwrite: bool) -> None:
    """A stand-in for the figures: each file says which process wrote it and what it got."""
    for name in names:
        (folder / name).write_text(f"{os.getpid()} {result} {overwrite}")


def _gone(pid: int) -> bool:
    """``pid`` is no child of this process any more (reaped)."""
    try:
        os.waitpid(pid, os.WNOHANG)
    except ChildProcessError:
        return True
    return False


def test_each_share_drawn_in_its_own_forked_process(tmp_path):
    painters = Painters((("a",), ("b", "c")), _pid_writer, lambda: None)
    pids = [p.pid for p in painters._all]
    painters.draw({"x": 1}, tmp_path, overwrite=False)
    painters.wait()
    got = {n: (tmp_path / n).read_text().split(" ", 1) for n in "abc"}
    assert got["a"][1] == got["b"][1] == "{'x': 1} False"  # the job as sent (pickled)
    assert int(got["a"][0]) == pids[0] and int(got["b"][0]) == int(got["c"][0]) == pids[1]
    assert os.getpid() not in pids and pids[0] != pids[1]
    assert all(_gone(pid) for pid in pids)
    painters.stop()  # after wait: nothing left to end, no error


def _fails(result, names, folder, *, overwrite):
    if "b" in names:
        raise FileExistsError(f"{folder / 'b'} exists")
    _pid_writer(result, names, folder, overwrite=overwrite)


def test_a_painters_error_is_raised_in_the_command_and_all_are_reaped(tmp_path):
    painters = Painters((("a",), ("b",)), _fails, lambda: None)
    pids = [p.pid for p in painters._all]
    painters.draw(0, tmp_path, overwrite=True)
    with pytest.raises(FileExistsError, match="/b exists"):
        painters.wait()
    assert (tmp_path / "a").is_file()  # the other painter finished its share
    assert all(_gone(pid) for pid in pids)


def _failed_import():
    raise ImportError("no matplotlib here")


def test_a_failed_import_is_raised_when_the_job_comes(tmp_path):
    painters = Painters((("a",),), _pid_writer, _failed_import)
    painters.draw(0, tmp_path, overwrite=True)
    with pytest.raises(ImportError, match="no matplotlib here"):
        painters.wait()
    assert not (tmp_path / "a").exists()


def _dies(result, names, folder, *, overwrite):
    os._exit(3)


def test_a_painter_that_ends_without_a_word_is_an_error_naming_its_figures(tmp_path):
    painters = Painters((("a", "b"),), _dies, lambda: None)
    painters.draw(0, tmp_path, overwrite=True)
    with pytest.raises(RuntimeError,
                       match=r"drawing a, b ended without finishing \(exit status 3\)"):
        painters.wait()


def _slow(result, names, folder, *, overwrite):
    (folder / "started").write_text("")
    time.sleep(60)  # ended by stop() long before


def test_stop_ends_waiting_and_drawing_painters(tmp_path):
    waiting = Painters((("a",), ("b",)), _pid_writer, lambda: None)  # no job ever sent
    pids = [p.pid for p in waiting._all]
    waiting.stop()
    assert all(_gone(pid) for pid in pids)
    drawing = Painters((("a",),), _slow, lambda: None)
    drawing.draw(0, tmp_path, overwrite=True)
    while not (tmp_path / "started").exists():
        time.sleep(0.01)
    t0 = time.monotonic()
    drawing.stop()  # SIGTERM: returns once the painter is reaped, not after its 60 s
    assert time.monotonic() - t0 < 30 and _gone(drawing._all[0].pid)


def test_forked_painters_reaps_on_an_error_in_the_block(tmp_path):
    with pytest.raises(ValueError, match="bad record"):
        with forked_painters((("a",),), _pid_writer, lambda: None) as painters:
            if painters is None:
                pytest.skip("no fork here (one core, or another Python thread runs: tqdm's monitor in the full suite): serial")
            pids = [p.pid for p in painters._all]
            raise ValueError("bad record")
    assert all(_gone(pid) for pid in pids)


def test_serial_where_one_core_or_another_thread(monkeypatch):
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0, 1})
    # this thread alone, as in the command's process (a test session may keep threads an earlier
    # test left, e.g. tqdm's monitor: the full suite read False here)
    with monkeypatch.context() as m:
        m.setattr(threading, "active_count", lambda: 1)
        assert parallel_available()
    stop = threading.Event()
    other = threading.Thread(target=stop.wait)
    other.start()
    try:  # a fork would copy only this thread, and a lock the other one held
        assert not parallel_available()
    finally:
        stop.set()
        other.join()
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0})
    assert not parallel_available()
    with forked_painters((("a",),), _pid_writer, lambda: None) as painters:
        assert painters is None
    with forked_painters((("a",),), _pid_writer, lambda: None, wanted=False) as painters:
        assert painters is None


def test_painters_prepare_one_after_the_other(tmp_path):
    def prepare():  # a slow import: the next painter starts its own after this one ends
        start = time.monotonic()
        time.sleep(0.3)
        (tmp_path / f"prep-{os.getpid()}").write_text(f"{start} {time.monotonic()}")

    painters = Painters((("a",), ("b",), ("c",)), _pid_writer, prepare)
    pids = [p.pid for p in painters._all]
    painters.draw(0, tmp_path, overwrite=True)
    painters.wait()
    spans = [tuple(map(float, (tmp_path / f"prep-{pid}").read_text().split())) for pid in pids]
    assert all(spans[i + 1][0] >= spans[i][1] for i in range(2)), spans  # CLOCK_MONOTONIC


@linux
def test_a_painter_killed_before_the_job_is_an_error_naming_its_figures(tmp_path):
    painters = Painters((("a",), ("b", "c")), _pid_writer, lambda: None)
    pid = painters._all[1].pid
    os.kill(pid, 9)
    while Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z":
        time.sleep(0.01)  # dead (not yet reaped): its end of the pipe is closed
    with pytest.raises(RuntimeError, match=r"drawing b, c ended before the figures were ready "
                                           r"\(signal 9\)"):
        painters.draw(0, tmp_path, overwrite=True)
    painters.stop()
    assert all(_gone(p.pid) for p in painters._all)


def test_painters_prepare_only_once_started(tmp_path):
    def prepare():
        (tmp_path / f"prep-{os.getpid()}").write_text("")

    painters = Painters((("a",), ("b",)), _pid_writer, prepare)
    time.sleep(0.5)
    assert not list(tmp_path.glob("prep-*"))  # the diagnosis's baseline thread still runs
    painters.start()
    painters.start()  # idempotent
    while len(list(tmp_path.glob("prep-*"))) < 2:
        time.sleep(0.01)
    painters.stop()
    assert all(_gone(p.pid) for p in painters._all)
