"""Compiled code is never served stale: fricctl._jit keys numba's cache by every compiled source.

Issue 19: with numba's own cache a kernel that inlined a friction law kept the old law after
the law's file was edited.  These tests edit a law in a scratch copy of the package and show
the next process computes the new physics.
"""

import os
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

import fricctl
from fricctl import _jit

PACKAGE = Path(fricctl.__file__).resolve().parent

# the compiled rigid joint under a constant torque: its velocity after 0.2 s (viscous only,
# closed form w = T/b * (1 - exp(-b t / J)))
_PROBE = textwrap.dedent("""
    import numpy as np
    from fricctl.friction import Viscous
    from fricctl.plant import RigidJoint
    st = RigidJoint(inertia=1e-3, friction=Viscous(0.01).model()).advance(
        np.zeros(5), 0.02, t0=0.0, dt=0.2, substeps=200)
    print(repr(float(st[1])))
""")


def _copy_package(tmp_path: Path) -> Path:
    root = tmp_path / "pkg"
    shutil.copytree(PACKAGE, root / "fricctl",
                    ignore=shutil.ignore_patterns("__pycache__", "*.nbi", "*.nbc"))
    return root


def _probe(root: Path, home: Path) -> float:
    env = dict(os.environ, PYTHONPATH=str(root), FRICCTL_CACHE=str(home))
    # cwd: not this repository, whose own fricctl would come first on sys.path
    out = subprocess.run([sys.executable, "-c", _PROBE], env=env, capture_output=True, text=True,
                         check=True, cwd=home.parent)
    return float(out.stdout.strip())


def test_an_edited_law_is_compiled_again_not_served_from_the_cache(tmp_path):
    import math

    root = _copy_package(tmp_path)
    first = _probe(root, tmp_path / "cache")
    assert first == pytest.approx(0.02 / 0.01 * (1 - math.exp(-0.01 * 0.2 / 1e-3)), rel=1e-6)
    cached = list((root / "fricctl").rglob("*.nbi"))
    assert cached, "the compiled kernels were cached on disk"
    # edit the viscous law's compiled term only (twice the torque); the plant kernel that
    # inlines it lives in another file, whose own text did not change
    law = root / "fricctl" / "friction" / "laws" / "viscous.py"
    text = law.read_text()
    edited = text.replace("return (viscous_pos if s > 0 else viscous_neg) * w",
                          "return 2.0 * (viscous_pos if s > 0 else viscous_neg) * w")
    assert edited != text
    law.write_text(edited)
    second = _probe(root, tmp_path / "cache")
    assert second == pytest.approx(0.02 / 0.02 * (1 - math.exp(-0.02 * 0.2 / 1e-3)), rel=1e-6)


def test_digest_covers_every_compiled_source_and_the_laws():
    names = {str(p.relative_to(PACKAGE)) for p in _jit.compiled_sources()}
    assert {"plant/kernels.py", "simulate/loop.py", "friction/compiled.py", "netlayout.py",
            "compensators/compiled.py"} <= names
    laws = {f"friction/laws/{p.name}" for p in (PACKAGE / "friction" / "laws").glob("*.py")}
    assert laws <= names
    # every compensator module: the generated dispatcher compiles each one's step
    comps = {f"compensators/{p.name}" for p in (PACKAGE / "compensators").glob("*.py")}
    assert comps <= names
    assert "cli/simulate.py" not in names  # not compiled: an edit there recompiles nothing


# a light probe for the cache-place tests: a generated friction kernel (compiles in seconds)
_LIGHT = ("from fricctl.friction import Viscous, compiled; "
          "print(compiled.sliding(Viscous(0.01).model().vector(), 2.0, 1.0, 0.0, 0.0))")


def test_no_writable_cache_place_compiles_in_memory(tmp_path):
    # a read-only install with a read-only home: every place a cache could go is unusable
    # (here each __pycache__ is a plain file, which stops root too); the kernels still run
    # (numba's own cache raised "cannot cache function ...: no locator available")
    root = _copy_package(tmp_path)
    for d in [p for p in (root / "fricctl").rglob("*") if p.is_dir()] + [root / "fricctl"]:
        (d / "__pycache__").write_text("not a folder")
    (tmp_path / "home").write_text("not a folder either")
    env = dict(os.environ, PYTHONPATH=str(root), FRICCTL_CACHE=str(tmp_path / "home" / "cache"),
               PYTHONDONTWRITEBYTECODE="1")
    out = subprocess.run([sys.executable, "-c", _LIGHT], env=env, capture_output=True, text=True,
                         cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert float(out.stdout) == pytest.approx(0.02, rel=1e-15)


def test_cache_off_compiles_in_memory(tmp_path):
    root = _copy_package(tmp_path)
    env = dict(os.environ, PYTHONPATH=str(root), FRICCTL_CACHE="off")
    out = subprocess.run([sys.executable, "-c", _LIGHT], env=env, capture_output=True, text=True,
                         check=True, cwd=tmp_path)
    assert float(out.stdout) == pytest.approx(0.02, rel=1e-15)
    assert not list((root / "fricctl").rglob("*.nbi"))


def test_numba_cache_dir_holds_the_compiled_code_when_set(tmp_path):
    # numba's own rule (NUMBA_CACHE_DIR first): a fresh clone's cold start can be measured from a
    # worktree whose __pycache__ already holds compiled code, by pointing this at an empty folder
    root = _copy_package(tmp_path)
    env = dict(os.environ, PYTHONPATH=str(root), FRICCTL_CACHE=str(tmp_path / "cache"),
               NUMBA_CACHE_DIR=str(tmp_path / "numba"), PYTHONDONTWRITEBYTECODE="1")
    out = subprocess.run([sys.executable, "-c", _LIGHT], env=env, capture_output=True, text=True,
                         check=True, cwd=tmp_path)
    assert float(out.stdout) == pytest.approx(0.02, rel=1e-15)
    assert list((tmp_path / "numba").rglob("*.nbi"))
    assert not list((root / "fricctl").rglob("*.nbi")) and not (tmp_path / "cache" / "numba").exists()
