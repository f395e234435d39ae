"""The report's figures drawn in forked processes: the second core of a small machine.

``fricctl diagnose --report DIR`` on a 40 s, 1 kHz record drew its four figures after the
diagnosis, one after another on one core: matplotlib's import (0.6-0.9 s) and the drawing and
PNG encoding (1.6-2.7 s), 2.4 s of the command's 11-12 s on an idle 2-core machine, while the
second core had nothing to do (the reported baseline's thread ends seconds before the
forward selection).  :func:`forked_painters` forks its processes *before* the diagnosis
starts that thread.  Each, while the diagnosis runs, imports matplotlib and the figure module
and draws a throw-away figure (:func:`fricctl.cli.diagnose.prepare_figures`): one painter after
the other, and only once that thread has ended (:meth:`Painters.start`, called by
:func:`~fricctl.diagnose.diagnose`'s ``on_baseline``), so that on a 2-core machine they take
the core the baseline's thread leaves, not the main thread's.  Then each waits for the result (pickled down a pipe), draws its share of the figures
(:data:`fricctl.cli.diagnose.PAINTER_SHARES`) with the serial path's own code
(:func:`fricctl.cli.diagnose.draw_figures`) and writes them atomically into the folder it is
sent (:func:`fricctl.cli._output.save_figure`): the same bytes as drawn in one process.

Serial (no process forked, the figures drawn by the command itself after the diagnosis)
where :func:`os.fork` is missing (not POSIX) or fails, where fewer than two cores are
available to the process (:func:`os.sched_getaffinity`), or where another Python thread runs:
a fork copies only the calling thread, and a lock another thread holds would stay held in the
child.  (The BLAS libraries' idle pool threads are not Python threads; OpenBLAS handles a
fork through its own ``pthread_atfork`` handler.)

Notes
-----
A process that fails to draw sends its exception back and the command raises it (a full
disk, ``FileExistsError`` of an exclusive write): what the serial path would raise.  A process
that ends without a word (killed) is an error naming it.  When the command ends otherwise (bad
input, an error or Ctrl-C in the diagnosis or the report), every process is sent SIGTERM
(one drawing unwinds its atomic write, its temporary file removed, before it exits) and
reaped before the report's folder is removed or renamed.  Ctrl-C is ignored in the processes (the command, which gets it
too, ends them).
"""

from __future__ import annotations

import contextlib
import os
import pickle
import signal
import sys
import threading
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator

__all__ = ["forked_painters", "parallel_available", "Painters"]


def parallel_available() -> bool:
    """Whether the figures may be drawn in forked processes: :func:`os.fork` exists, at least
    two cores are available to this process and no other Python thread runs."""
    if not hasattr(os, "fork"):  # pragma: no cover - Windows
        return False
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - macOS has no affinity
        cores = os.cpu_count() or 1
    return cores >= 2 and threading.active_count() == 1


class _Terminated(BaseException):
    """SIGTERM in a painter: unwinds an atomic write (its temporary file removed)."""


def _raise_terminated(signum, frame):
    raise _Terminated


def _send(fd: int, obj) -> None:
    """``obj`` pickled, written whole to ``fd``."""
    data = pickle.dumps(obj, protocol=pickle.HIGHEST_PROTOCOL)
    view = memoryview(len(data).to_bytes(8, "little") + data)
    while view:
        view = view[os.write(fd, view):]


def _receive(fd: int):
    """The next object :func:`_send` wrote to ``fd``'s pipe; EOFError when the other end
    closed first."""
    head = _read(fd, 8)
    return pickle.loads(_read(fd, int.from_bytes(head, "little")))


def _read(fd: int, n: int) -> bytes:
    parts, left = [], n
    while left:
        chunk = os.read(fd, min(left, 1 << 20))
        if not chunk:
            raise EOFError
        parts.append(chunk)
        left -= len(chunk)
    return b"".join(parts)


def _picklable(err: BaseException) -> BaseException:
    """``err`` itself when it pickles, else a RuntimeError that says what it was."""
    try:
        pickle.loads(pickle.dumps(err))
        return err
    except Exception:
        return RuntimeError(f"{type(err).__name__}: {err}")


def _paint(prepare, draw, names: tuple, jobs: int, replies: int, after: int, done: int) -> None:
    """A painter's life (in the forked process): prepare (import) once the painter before it
    has (``after`` closed; the first: once the command opens the gate), wait for the job,
    draw, reply."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the command gets Ctrl-C too and ends us
    signal.signal(signal.SIGTERM, _raise_terminated)
    err = None
    # one painter imports at a time, after the diagnosis's baseline thread: on a 2-core
    # machine, more would take the main thread's core
    os.read(after, 1)  # b"": the painter before has prepared (or ended), or the gate opened
    after = _close(after)
    try:  # now, while the diagnosis runs in the parent
        prepare()
    except Exception as e:  # said when the job comes, as the serial path would raise it
        err = e
    done = _close(done)
    result, folder, overwrite = _receive(jobs)
    if err is None:
        try:
            draw(result, names, Path(folder), overwrite=overwrite)
        except Exception as e:
            err = e
    _send(replies, None if err is None else _picklable(err))


@dataclass(eq=False)
class _Painter:
    """One forked process: its id, the figures it draws, the ends of its two pipes."""

    pid: int
    names: tuple
    jobs: int
    """The parent's end of the pipe the job goes down (-1 once closed)."""
    replies: int
    """The parent's end of the pipe the reply comes up (-1 once closed)."""
    busy: bool = False
    """Sent a job, no reply yet."""
    reaped: bool = False


def _close(fd: int) -> int:
    if fd >= 0:
        with contextlib.suppress(OSError):
            os.close(fd)
    return -1


class Painters:
    """Forked processes that draw the report's figures; see the module."""

    def __init__(self, shares, draw, prepare):
        """``shares``: the figure names each process draws; ``draw(result, names, folder, *,
        overwrite)``: what a process calls with its share; ``prepare()``: what it does at once
        (its imports).  Both inherited through the fork, never pickled."""
        self._draw = draw
        self._prepare = prepare
        self._all: list[_Painter] = []
        self._lock = threading.Lock()  # start() is called from the diagnosis's baseline thread
        sys.stdout.flush()  # nothing buffered is written twice
        sys.stderr.flush()
        # read end of the pipe the painter before closes once prepared; for the first, the
        # gate this process closes in start()
        after, self._gate = os.pipe()
        try:
            for share in shares:
                done_r, done_w = os.pipe()
                try:
                    self._all.append(self._fork(tuple(share), after, done_r, done_w))
                except BaseException:
                    _close(done_r)
                    raise
                finally:
                    _close(done_w)  # the new painter's alone
                _close(after)
                after = done_r
        except BaseException:
            self.stop()
            raise
        finally:
            _close(after)

    def _fork(self, names: tuple, after: int, done_r: int, done_w: int) -> _Painter:
        job_r, job_w = os.pipe()
        rep_r, rep_w = os.pipe()
        try:
            pid = os.fork()
        except BaseException:
            for fd in (job_r, job_w, rep_r, rep_w):
                _close(fd)
            raise
        if pid == 0:  # the painter: never returns
            status = 1
            try:
                for p in self._all:  # the earlier painters' pipes: theirs alone
                    _close(p.jobs)
                    _close(p.replies)
                for fd in (job_w, rep_r, done_r, self._gate):
                    _close(fd)
                _paint(self._prepare, self._draw, names, job_r, rep_w, after, done_w)
                status = 0
            except BaseException:  # the parent ended first, or SIGTERM: nothing to say
                pass
            finally:
                os._exit(status)
        os.close(job_r)
        os.close(rep_w)
        return _Painter(pid=pid, names=names, jobs=job_w, replies=rep_r)

    def start(self) -> None:
        """Let the painters prepare (import), one after the other, from now on (thread-safe,
        idempotent).  The command calls it when the diagnosis's baseline thread ends, so
        that the imports take the core that thread leaves, not the main thread's."""
        with self._lock:
            self._gate = _close(self._gate)

    def draw(self, result, folder, *, overwrite: bool) -> None:
        """Send every painter the job: ``result``'s figures into ``folder`` (returns at once;
        :meth:`wait` for them).  ``result`` is pickled."""
        self.start()  # if the diagnosis did not
        job = (result, os.fspath(folder), bool(overwrite))
        for p in self._all:
            p.busy = True
            try:
                _send(p.jobs, job)
            except BrokenPipeError:
                p.busy = False
                raise RuntimeError(f"--report: the process drawing {', '.join(p.names)} ended "
                                   f"before the figures were ready ({self._reap(p)})") from None
            p.jobs = _close(p.jobs)

    def wait(self) -> None:
        """Wait for every painter's reply and reap it; raise the first one's error."""
        first = None
        for p in self._all:
            try:
                err = _receive(p.replies)
            except EOFError:
                err = RuntimeError(f"--report: the process drawing {', '.join(p.names)} "
                                   f"ended without finishing ({self._reap(p)})")
            p.busy = False
            p.replies = _close(p.replies)
            self._reap(p)
            first = first or err
        if first is not None:
            raise first

    def _reap(self, p: _Painter) -> str:
        """Wait for ``p`` to end; how it ended, in words."""
        if p.reaped:
            return "reaped"
        _, status = os.waitpid(p.pid, 0)
        p.reaped = True
        if os.WIFSIGNALED(status):
            return f"signal {os.WTERMSIG(status)}"
        return f"exit status {os.WEXITSTATUS(status)}"

    def stop(self) -> None:
        """End every painter (SIGTERM: one drawing unwinds its atomic write, one waiting or
        importing stops there) and reap it."""
        self.start()  # the gate closed too
        for p in self._all:
            if not p.reaped:
                with contextlib.suppress(ProcessLookupError):
                    os.kill(p.pid, signal.SIGTERM)
            p.jobs = _close(p.jobs)
            p.replies = _close(p.replies)
        for p in self._all:
            self._reap(p)


@contextlib.contextmanager
def forked_painters(shares, draw, prepare, *, wanted: bool = True) -> Iterator[Painters | None]:
    """``Painters(shares, draw, prepare)`` forked now when ``wanted`` and
    :func:`parallel_available`, else None (the figures drawn serially); every painter is ended
    and reaped on leaving."""
    painters = None
    if wanted and parallel_available():
        try:
            painters = Painters(shares, draw, prepare)
        except OSError:  # no fork now (EAGAIN: a process limit; ENOMEM): drawn serially
            painters = None
    try:
        yield painters
    finally:
        if painters is not None:
            painters.stop()
