"""The cache of trained networks is keyed by what determines a network, not by the whole library.

Issue 22: the key hashed every source of the package, so an edit of a figure or of the command
line retrained all 30 networks of ``fricctl reproduce``.  With the training patterns in the key,
the key needs only the code that turns patterns into a network (fricctl.nn and its imports).
"""

import os
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

import fricctl
from fricctl._cache import source_digest
from fricctl.datasets import FrictionPatterns
from fricctl.nn import cache

PACKAGE = Path(fricctl.__file__).resolve().parent


def _copy_package(tmp_path: Path) -> Path:
    shutil.copytree(PACKAGE, tmp_path / "fricctl",
                    ignore=shutil.ignore_patterns("__pycache__", "*.nbi", "*.nbc"))
    return tmp_path / "fricctl"


def _edit(path: Path) -> None:
    path.write_text(path.read_text(encoding="utf-8") + "\n# an edit\n", encoding="utf-8")


def test_an_edit_outside_the_trainer_keeps_the_key_and_one_inside_changes_it(tmp_path):
    root = _copy_package(tmp_path)

    def digest():
        return source_digest(cache.trainer_sources(root))

    d0 = digest()
    # what made the patterns, and what reads the networks: in the key through the patterns only
    for outside in ("paper/fig04.py", "paper/claims.py", "cli/reproduce.py", "plant/kernels.py",
                    "simulate/loop.py", "bench/experiments.py", "diagnose/api.py", "figures/__init__.py"):
        _edit(root / outside)
        assert digest() == d0, outside
    # the pipelines, the trainers (discovered by pkgutil), the network, what they import
    for inside in ("nn/pipelines.py", "nn/train/lm.py", "nn/train/certified.py", "nn/net.py",
                   "nn/layout.py", "netlayout.py", "datasets/patterns.py", "_validate.py"):
        before = digest()
        _edit(root / inside)
        assert digest() != before, inside


def test_the_trainer_sources_are_a_minority_of_the_package():
    names = {str(p.relative_to(PACKAGE)) for p in cache.trainer_sources()}
    assert {f"nn/train/{p.name}" for p in (PACKAGE / "nn" / "train").glob("*.py")} <= names
    assert not any(n.startswith(("paper/", "cli/", "figures/", "plant/", "simulate/", "bench/",
                                 "diagnose/", "compare/")) for n in names)


# trains both pipelines on small patterns in a fresh process, then lists the fricctl modules it
# loaded: each must be a trainer source (the static reading of the imports missed none)
_LOADED = textwrap.dedent("""
    import sys
    import numpy as np
    from fricctl.datasets import FrictionPatterns
    from fricctl.nn import smooth_friction_patterns
    from fricctl.nn.pipelines import PIPELINES
    # tests/test_pipelines.py's patterns: a smooth law on the loop's velocity lattice
    p = smooth_friction_patterns(np.random.default_rng(0), n_sliding=300, n_stuck=150)
    om = np.round(p.omega / 0.0157) * 0.0157
    pats = FrictionPatterns(tm=p.tm, omega=om, friction=p.friction - 0.0169 * (p.omega - om),
                            at_rest=om == 0, velocity_quantum=0.0157)
    for name, recipe in PIPELINES.items():
        recipe.train(pats, rng=np.random.default_rng(0), max_patterns=300)
    for m in list(sys.modules.values()):
        f = getattr(m, "__file__", None) or ""
        if m.__name__.startswith("fricctl"):
            print(f)
""")


def test_every_module_training_loads_is_a_trainer_source(tmp_path):
    env = dict(os.environ, PYTHONPATH=str(PACKAGE.parent))
    out = subprocess.run([sys.executable, "-c", _LOADED], env=env, capture_output=True, text=True,
                         cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    loaded = {Path(f).resolve() for f in out.stdout.split()}
    assert len(loaded) > 10
    missed = loaded - set(cache.trainer_sources())
    assert not missed, sorted(str(p) for p in missed)


def _patterns(tm):
    om = np.linspace(-1.0, 1.0, tm.size)
    return FrictionPatterns(tm=tm, omega=om, friction=tm.copy(), at_rest=np.zeros(tm.size, bool),
                            velocity_quantum=0.01)


def test_the_key_holds_the_patterns_bit_for_bit():
    tm = np.linspace(0.0, 1.0, 50)
    key = {"what": "test"}
    a = cache.cache_key(key, _patterns(tm))
    assert cache.cache_key(key, _patterns(tm.copy())) == a                 # the same data
    tm2 = tm.copy()
    tm2[17] = np.nextafter(tm2[17], 2.0)                                   # one ulp of one pattern
    assert cache.cache_key(key, _patterns(tm2)) != a
    assert cache.cache_key({"what": "other"}, _patterns(tm)) != a          # the configuration
    assert cache.cache_key(key) != a                                       # no patterns: the whole package
    with pytest.raises(ValueError, match="patterns"):
        cache.patterns_digest(tm)
    objects = _patterns(tm)
    object.__setattr__(objects, "tm", np.array([object()] * tm.size))     # addresses, not numbers
    with pytest.raises(ValueError, match="patterns.tm holds Python objects"):
        cache.patterns_digest(objects)
