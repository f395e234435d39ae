"""Snapshot of fricctl's observable behaviour, for refactors that must not change it.

Usage::

    python tools/behaviour_snapshot.py make-records DIR   # once: hidden-effect CSV records
    python tools/behaviour_snapshot.py snapshot DIR OUT.json
    python tools/behaviour_snapshot.py compare A.json B.json

``snapshot`` runs only the command line (whose interface a refactor keeps):
``fricctl reproduce`` (fast and full, seeds 0 and 1) -> every number of claims.json;
``fricctl diagnose --json`` on the records of ``make-records`` (and on one with
its nominal model); ``fricctl design`` for the paper's four designs and the link;
``fricctl simulate --json`` for an open-loop, a P and a compensated PD run.
``compare`` prints every value that differs beyond printing precision
(relative 1e-9 for floats) and exits 1 if any does.
"""

from __future__ import annotations

import json
import math
import re
import subprocess
import sys
import tempfile
from pathlib import Path

CAUSES = ("none", "stribeck", "asymmetry", "load_dependent", "position_ripple", "time_delay",
          "thermal_drift", "compliance", "presliding")
SEEDS = (3, 11)
FRICCTL = [sys.executable, "-m", "fricctl"]


def make_records(folder: Path) -> None:
    import numpy as np

    try:  # the generator moves during the layout refactor; records are made once, before it
        from fricctl.hidden_effects import hidden_effect_record
    except ImportError:
        from fricctl.bench.hidden_effects import hidden_effect_record
    folder.mkdir(parents=True, exist_ok=True)
    for cause in CAUSES + ("inertia",):
        for seed in SEEDS:
            rec = hidden_effect_record(np.random.default_rng(seed), cause=cause, duration=20.0)
            rec.run.to_csv(folder / f"{cause}-{seed}.csv")
            if rec.nominal is not None:
                (folder / f"{cause}-{seed}.model.json").write_text(rec.nominal.to_json())


def _run(args, cwd=None) -> str:
    proc = subprocess.run(FRICCTL + args, capture_output=True, text=True, cwd=cwd)
    if proc.returncode != 0:
        raise SystemExit(f"fricctl {' '.join(args)} failed:\n{proc.stderr}")
    return proc.stdout


def snapshot(records: Path, out: Path) -> None:
    snap = {}
    with tempfile.TemporaryDirectory() as tmp:
        for mode in ("fast", "full"):
            d = Path(tmp) / mode
            _run(["reproduce", "--out", str(d), "--seeds", "2"] + (["--fast"] if mode == "fast" else []))
            snap[f"reproduce-{mode}"] = json.loads((d / "claims.json").read_text())
    for csv in sorted(records.glob("*.csv")):
        args = ["diagnose", str(csv), "--json"]
        model = csv.with_suffix(".model.json")
        if model.is_file():
            args += ["--model", str(model)]
        snap[f"diagnose-{csv.stem}"] = json.loads(_run(args))
    for name, args in {"p": ["p", "--rise-time", "0.2", "--damping", "0.3"],
                       "pd": ["pd", "--rise-time", "0.3", "--damping", "0.9"],
                       "pd-link": ["pd", "--rise-time", "0.4", "--damping", "0.85", "--link"],
                       "pd-link-fast": ["pd", "--rise-time", "0.22", "--damping", "0.5", "--link"]}.items():
        snap[f"design-{name}"] = json.loads(_run(["design"] + args + ["--json"]))
    sims = {"open": ["--torque", "sinusoid:0.2,1", "--duration", "2"],
            "p": ["--controller", "p", "--rise-time", "0.2", "--damping", "0.3", "--duration", "3"],
            "pd-coulomb": ["--controller", "pd", "--rise-time", "0.4", "--damping", "0.85", "--link",
                           "--reference", "step:0.08", "--compensation", "coulomb", "--scale", "0.95",
                           "--friction-scale", "0.95", "--duration", "3"]}
    for name, args in sims.items():
        snap[f"simulate-{name}"] = json.loads(_run(["simulate"] + args + ["--json"]))
    out.write_text(json.dumps(snap, indent=1, sort_keys=True) + "\n")


_NUM = re.compile(r"-?\d+\.?\d*(?:[eE][-+]?\d+)?")


def _diff(a, b, path, out):
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                out.append(f"{path}/{k}: only in {'second' if k not in a else 'first'}")
            else:
                _diff(a[k], b[k], f"{path}/{k}", out)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            out.append(f"{path}: length {len(a)} != {len(b)}")
        for i, (x, y) in enumerate(zip(a, b)):
            _diff(x, y, f"{path}[{i}]", out)
    elif isinstance(a, float) and isinstance(b, (int, float)) or isinstance(b, float) and isinstance(a, (int, float)):
        if not (a == b or (math.isnan(a) and math.isnan(b)) or abs(a - b) <= 1e-9 * max(abs(a), abs(b))):
            out.append(f"{path}: {a!r} != {b!r}")
    elif a != b:
        out.append(f"{path}: {a!r} != {b!r}")


def compare(a: Path, b: Path) -> int:
    out = []
    _diff(json.loads(a.read_text()), json.loads(b.read_text()), "", out)
    for line in out:
        print(line)
    print(f"{len(out)} difference(s)")
    return 1 if out else 0


if __name__ == "__main__":
    cmd = sys.argv[1] if len(sys.argv) > 1 else ""
    if cmd == "make-records" and len(sys.argv) == 3:
        make_records(Path(sys.argv[2]))
    elif cmd == "snapshot" and len(sys.argv) == 4:
        snapshot(Path(sys.argv[2]), Path(sys.argv[3]))
    elif cmd == "compare" and len(sys.argv) == 4:
        sys.exit(compare(Path(sys.argv[2]), Path(sys.argv[3])))
    else:
        sys.exit(__doc__)
