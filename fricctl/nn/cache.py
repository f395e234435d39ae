"""A cache of trained networks on disk, keyed by everything that determines them.

Training a network is the slow step of a chapter or of ``fricctl reproduce``; the
same configuration (pipeline, seed, experiments, estimator, actuator) always gives the
same network, so it is trained once and read back afterwards.  The key is a hash of
the caller's configuration *and of fricctl's own source code*: any change to the
library retrains.  Entries are JSON (no pickle), written atomically (a temporary file
renamed into place).  A process that needs a network another process is training waits for
it and reads it back, instead of training it a second time (an advisory ``flock`` on
``<entry>.lock``, where the platform has one: the book runs ``fricctl reproduce`` and chapters
that train the same networks side by side); without ``fcntl`` (Windows) or in a read-only
folder, concurrent processes at worst train the same network twice.

Where: the folder named by the environment variable ``FRICCTL_CACHE``, or
``~/.cache/fricctl`` by default; ``FRICCTL_CACHE=off`` disables the cache.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import json
from pathlib import Path
from typing import Callable, Iterator

from .._atomic import write_text
from .._cache import PACKAGE_ROOT, cache_dir, source_digest
from .pipelines import PipelineNet

__all__ = ["cache_dir", "code_digest", "cached_pipeline_net"]


@functools.lru_cache(maxsize=1)
def code_digest() -> str:
    """SHA-256 of every Python source file of the installed fricctl package."""
    return source_digest(PACKAGE_ROOT.rglob("*.py"))


def cached_pipeline_net(key: dict, make: Callable[[], PipelineNet]) -> PipelineNet:
    """``make()``'s network for configuration ``key`` (JSON-serialisable), from the cache if there.

    An unreadable or stale entry is trained again and replaced.
    """
    folder = cache_dir()
    if folder is None:
        return make()
    text = json.dumps({"key": key, "code": code_digest()}, sort_keys=True, allow_nan=False)
    path = folder / "nets" / (hashlib.sha256(text.encode()).hexdigest()[:32] + ".json")
    net = _read(path)
    if net is not None:
        return net
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
        path.parent.mkdir(parents=True, exist_ok=True)
        lock = open(path.with_suffix(".lock"), "a")
    except OSError:
        yield
        return
    with lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        yield  # closing the file releases the lock
