"""Where fricctl keeps what it can recompute (trained networks, compiled code), and digests of sources.

Package-private and at the bottom of the layers: :mod:`fricctl._jit` (compiled kernels) and
:mod:`fricctl.nn.cache` (trained networks) both key their entries by a digest of the source
text they were made from, so an edited source is never served from a stale entry.

Where: the folder named by the environment variable ``FRICCTL_CACHE``, or ``~/.cache/fricctl``
by default; ``FRICCTL_CACHE=off`` switches every on-disk cache off (the work is then redone in
each process).
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path
from typing import Iterable

__all__ = ["cache_dir", "source_digest", "PACKAGE_ROOT"]

_OFF = {"0", "off", "no", "false"}

#: The folder of the fricctl package (its ``__init__.py``).
PACKAGE_ROOT = Path(__file__).resolve().parent


def cache_dir() -> Path | None:
    """The cache folder, or None when ``FRICCTL_CACHE`` switches the caches off."""
    env = os.environ.get("FRICCTL_CACHE")
    if env is not None and env.strip().lower() in _OFF:
        return None
    return Path(env).expanduser() if env else Path.home() / ".cache" / "fricctl"


def source_digest(files: Iterable[Path]) -> str:
    """SHA-256 of the files' names (relative to the package) and contents, in sorted order."""
    h = hashlib.sha256()
    for f in sorted(Path(p).resolve() for p in files):
        try:
            name = f.relative_to(PACKAGE_ROOT)
        except ValueError:
            name = f
        h.update(str(name).encode())
        h.update(b"\0")
        h.update(f.read_bytes())
        h.update(b"\0")
    return h.hexdigest()
