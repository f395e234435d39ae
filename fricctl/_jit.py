"""Compiled kernels whose on-disk cache is never stale: :func:`jit`.

numba's own cache (``@njit(cache=True)``) checks only the file of the cached function: a
kernel that calls a friction law compiled from another file kept the *old* law after the law
was edited (issue 19: peak speed 18.83 rad/s, friction 0.46 N*m where the model said 7.55),
until ``__pycache__`` was deleted.  Every fricctl kernel is compiled through :func:`jit`
instead, whose cache entries are stamped with :func:`compiled_digest`, the digest of *every*
source a kernel compiles from:

* every module of the package that compiles with :func:`jit` (it imports this module),
* every module of :mod:`fricctl.friction` (the laws and the coefficient layout the kernels
  read as compile-time constants) and of :mod:`fricctl.compensators` (each compensator's
  compiled step, which the generated dispatcher calls),
* every package module those import directly (the constants a kernel freezes into its code,
  such as the network layout of :mod:`fricctl.netlayout`),

so that an edit of any of them recompiles every kernel on its next use.

Where the entries live: in ``$NUMBA_CACHE_DIR`` when that variable is set (numba's own rule:
a user-provided folder comes first); else beside the source (``__pycache__``, numba's default)
when that folder is writable; else in ``<cache>/numba`` (:func:`fricctl._cache.cache_dir`);
else nowhere (a read-only install with a read-only home compiles in memory in each process,
instead of failing with numba's "no locator available").  ``FRICCTL_CACHE=off`` keeps compiled
code in memory too.
"""

from __future__ import annotations

import ast
import functools
import os
import re
import sys
from pathlib import Path

from numba import njit
from numba.core import config as numba_config
from numba.core.caching import CompileResultCacheImpl, FunctionCache, _CacheLocator

from ._cache import PACKAGE_ROOT, cache_dir, source_digest

__all__ = ["jit", "compiled_digest", "compiled_sources"]

#: A module compiles through this one when it imports it (``from .._jit import jit``).
_USES_JIT = re.compile(r"^\s*from\s+(\.+|fricctl\.)_jit\s+import\s", re.M)


def _package_imports(f: Path) -> set[Path]:
    """The package modules ``f`` imports by relative imports (their files)."""
    out = set()
    for node in ast.walk(ast.parse(f.read_text(encoding="utf-8"))):
        if not isinstance(node, ast.ImportFrom) or node.level == 0:
            continue
        base = f.parent
        for _ in range(node.level - 1):
            base = base.parent
        parts = node.module.split(".") if node.module else []
        target = base.joinpath(*parts)
        names = [target / a.name for a in node.names] if not parts or target.is_dir() else []
        for cand in [target, *names]:
            if (cand / "__init__.py").is_file():
                out.add((cand / "__init__.py").resolve())
            elif cand.with_suffix(".py").is_file():
                out.add(cand.with_suffix(".py").resolve())
    return out


def compiled_sources() -> list[Path]:
    """Every source a compiled kernel is built from (see the module docstring)."""
    out = {Path(__file__).resolve()}
    for f in PACKAGE_ROOT.rglob("*.py"):
        f = f.resolve()
        if PACKAGE_ROOT / "friction" in f.parents or PACKAGE_ROOT / "compensators" in f.parents:
            out.add(f)
            if _USES_JIT.search(f.read_text(encoding="utf-8")):
                out |= _package_imports(f)
        elif _USES_JIT.search(f.read_text(encoding="utf-8")):
            out.add(f)
            out |= _package_imports(f)
    return sorted(out)


@functools.lru_cache(maxsize=1)
def compiled_digest() -> str:
    """SHA-256 of :func:`compiled_sources` and of the Python running them (read once per process)."""
    return f"{source_digest(compiled_sources())}-py{sys.version_info[0]}{sys.version_info[1]}"


class _DigestLocator(_CacheLocator):
    """numba cache locator whose source stamp is :func:`compiled_digest` (not the file's own)."""

    def __init__(self, py_func, py_file, path):
        self._lineno = py_func.__code__.co_firstlineno
        self._path = path

    def get_cache_path(self):
        return self._path

    def get_source_stamp(self):
        return compiled_digest()

    def get_disambiguator(self):
        return str(self._lineno)

    @classmethod
    def from_function(cls, py_func, py_file):
        places = []
        root = cache_dir()
        if numba_config.CACHE_DIR:  # NUMBA_CACHE_DIR, as numba's _UserProvidedCacheLocator reads it
            places.append(os.path.join(numba_config.CACHE_DIR, cls.get_suitable_cache_subpath(py_file)
                                       if os.path.exists(py_file) else "generated"))
        if os.path.exists(py_file):
            places.append(os.path.join(os.path.dirname(py_file), "__pycache__"))
            if root is not None:
                places.append(os.path.join(str(root), "numba", cls.get_suitable_cache_subpath(py_file)))
        elif root is not None:  # generated code (fricctl.friction.compiled): no file of its own
            places.append(os.path.join(str(root), "numba", "generated"))
        for path in places:
            self = cls(py_func, py_file, path)
            try:
                self.ensure_cache_path()
            except OSError:  # not writable (read-only install or home): try the next place
                continue
            return self
        return None


class _DigestImpl(CompileResultCacheImpl):
    _locator_classes = [_DigestLocator]


class _DigestCache(FunctionCache):
    _impl_class = _DigestImpl


def _enable_cache(dispatcher) -> None:
    """Give ``dispatcher`` the digest-stamped cache, or none where no place is writable."""
    if os.environ.get("FRICCTL_CACHE", "").strip().lower() in {"0", "off", "no", "false"}:
        return
    try:
        cache = _DigestCache(dispatcher.py_func)
    except RuntimeError:  # numba: "cannot cache function ...: no locator available"
        return
    # numba's own Dispatcher.enable_caching() does exactly this assignment with its FunctionCache
    dispatcher._cache = cache


def jit(func=None, **options):
    """``numba.njit`` with a cache keyed by :func:`compiled_digest`; ``@jit`` or ``@jit(parallel=True)``."""
    if "cache" in options:
        raise ValueError("jit: the cache is always on (keyed by the compiled sources' digest)")

    def wrap(f):
        dispatcher = njit(**options)(f)
        _enable_cache(dispatcher)
        return dispatcher

    return wrap if func is None else wrap(func)
