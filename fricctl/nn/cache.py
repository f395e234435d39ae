"""A cache of trained networks on disk, keyed by everything that determines them.

Training a network is the slow step of a chapter or of ``fricctl reproduce``; the
same configuration (pipeline, seed, experiments, estimator, actuator) always gives the
same network, so it is trained once and read back afterwards.  Entries are JSON (no
pickle), written atomically (a temporary file renamed into place).  A process that needs a
network another process is training waits for it and reads it back, instead of training it a
second time (an advisory ``flock`` on ``<entry>.lock``, where the platform has one: the book
runs ``fricctl reproduce`` and chapters that train the same networks side by side); without
``fcntl`` (Windows) or in a read-only folder, concurrent processes at worst train the same
network twice.

The key is the caller's configuration and the code that could change the result:

* with ``patterns=`` (the training patterns, as :func:`fricctl.paper.train_paper_network`
  passes them): a digest of those patterns -- every field, bit for bit -- and of
  :func:`trainer_sources`, the modules that turn patterns into a network (every module of
  :mod:`fricctl.nn` and what they import).  The code that *made* the patterns (the plant,
  the simulation, the experiments, the estimators) is covered by the patterns themselves:
  an edit that changes them changes the key, an edit that does not (a figure, a claim, the
  diagnosis, the command line) keeps it.  NumPy's, CasADi's and Python's versions are in
  the key too (a trainer's arithmetic);
* without: a digest of every Python source of the package (:func:`code_digest`), as before:
  any change to the library retrains.

Where: the folder named by the environment variable ``FRICCTL_CACHE``, or
``~/.cache/fricctl`` by default; ``FRICCTL_CACHE=off`` disables the cache.
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import hashlib
import json
import sys
from pathlib import Path
from typing import Callable, Iterator

import numpy as np

from .._atomic import write_text
from .._cache import PACKAGE_ROOT, cache_dir, source_digest
from .pipelines import PipelineNet

__all__ = ["cache_dir", "code_digest", "trainer_sources", "trainer_digest", "patterns_digest",
           "cache_key", "cached_pipeline_net"]


@functools.lru_cache(maxsize=1)
def code_digest() -> str:
    """SHA-256 of every Python source file of the installed fricctl package."""
    return source_digest(PACKAGE_ROOT.rglob("*.py"))


def trainer_sources(package: Path = PACKAGE_ROOT) -> list[Path]:
    """Every source that turns training patterns into a network.

    Every module of :mod:`fricctl.nn` (the pipelines, the trainers, the network and its
    layout) and, transitively, every package module they import (relative imports, also
    those inside functions).  A package that discovers its members (``pkgutil``: the
    trainers, the friction laws) counts with all its modules, since importing it imports
    them.  ``package``: the fricctl folder to read (a copy, in the tests).
    """
    from .._jit import _package_imports  # the one reader of a module's package imports

    todo = [f.resolve() for f in (Path(package) / "nn").rglob("*.py")]
    seen: set[Path] = set()
    while todo:
        f = todo.pop()
        if f in seen:
            continue
        seen.add(f)
        todo.extend(_package_imports(f))
        if f.name == "__init__.py" and "pkgutil" in f.read_text(encoding="utf-8"):
            todo.extend(p.resolve() for p in f.parent.glob("*.py"))
    return sorted(seen)


@functools.lru_cache(maxsize=1)
def trainer_digest() -> str:
    """SHA-256 of :func:`trainer_sources` and of the versions of Python, NumPy, CasADi and numba
    (the back-propagation kernels are numba-compiled)."""
    import casadi
    import numba

    return (f"{source_digest(trainer_sources())}-py{sys.version_info[0]}.{sys.version_info[1]}"
            f"-numpy{np.__version__}-casadi{casadi.__version__}-numba{numba.__version__}")


def patterns_digest(patterns) -> str:
    """SHA-256 of every field of ``patterns`` (a :class:`~fricctl.datasets.FrictionPatterns`
    or a subclass): each array's dtype, shape and bytes, every other field as JSON."""
    if not dataclasses.is_dataclass(patterns) or isinstance(patterns, type):
        raise ValueError(f"patterns must be FrictionPatterns, got {type(patterns).__name__}")
    h = hashlib.sha256()
    for f in dataclasses.fields(patterns):
        value = getattr(patterns, f.name)
        h.update(f.name.encode() + b"\0")
        if isinstance(value, np.ndarray):
            a = np.ascontiguousarray(value)
            if a.dtype.hasobject:  # its bytes would be addresses, different in every process
                raise ValueError(f"patterns.{f.name} holds Python objects; a key needs numbers")
            h.update(f"{a.dtype.str}{a.shape}".encode() + b"\0")
            h.update(a.tobytes())
        else:
            h.update(json.dumps(value if not hasattr(value, "items") else dict(value),
                                sort_keys=True, allow_nan=True).encode())
        h.update(b"\0")
    return h.hexdigest()


def cache_key(key: dict, patterns=None) -> str:
    """The file name (without ``.json``) of ``key``'s entry: see the module docstring."""
    if patterns is None:
        entry = {"key": key, "code": code_digest()}
    else:
        entry = {"key": key, "patterns": patterns_digest(patterns), "trainer": trainer_digest()}
    text = json.dumps(entry, sort_keys=True, allow_nan=False)
    return hashlib.sha256(text.encode()).hexdigest()[:32]


def cached_pipeline_net(key: dict, make: Callable[[], PipelineNet], *, patterns=None) -> PipelineNet:
    """``make()``'s network for configuration ``key`` (JSON-serialisable), from the cache if there.

    ``patterns``: the patterns ``make`` trains on (then the key holds them and the trainer's
    sources instead of the whole package's: see the module docstring).  An unreadable or
    stale entry is trained again and replaced.
    """
    folder = cache_dir()
    if folder is None:
        return make()
    path = folder / "nets" / (cache_key(key, patterns) + ".json")
    net = _read(path)
    if net is not None:
        return net
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError:  # a read-only home: train, lock nothing, keep nothing
        pass
    with _training(path):
        net = _read(path)  # trained by the process that held the lock while this one waited
        if net is not None:
            return net
        net = make()
        try:
            write_text(path, json.dumps(net.as_dict(), allow_nan=False))  # no temporary file left
        except OSError:  # a read-only home or a full disk: the cache is an optimisation, never a need
            pass
    return net


def _read(path: Path) -> PipelineNet | None:
    try:
        return PipelineNet.from_dict(json.loads(path.read_text(encoding="utf-8")))
    except (OSError, ValueError, KeyError, TypeError, RecursionError):  # missing or damaged: retrain
        return None


@contextlib.contextmanager
def _training(path: Path) -> Iterator[None]:
    """Held while this process trains the network of ``path``: an exclusive ``flock`` on
    ``<path>.lock`` (released by the OS if the process dies), so another process asking for the
    same network waits for it.  No lock where there is no ``fcntl`` or the folder is not
    writable."""
    try:
        import fcntl
    except ImportError:  # Windows
        yield
        return
    try:
        lock = open(path.with_suffix(".lock"), "a")
    except OSError:
        yield
        return
    with lock:
        try:
            fcntl.flock(lock, fcntl.LOCK_EX)
        except OSError:  # a file system without locks (some NFS mounts): train without one
            pass
        yield  # closing the file releases the lock
