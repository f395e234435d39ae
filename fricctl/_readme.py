"""Blocks of README.md that are generated from the code (and checked by tests/test_readme.py).

``python -m fricctl._readme`` rewrites every block between
``<!-- BEGIN name -->`` and ``<!-- END name -->`` markers in README.md.
"""

from __future__ import annotations

import re
import sys
import warnings
from dataclasses import fields
from pathlib import Path


def parameters() -> str:
    from .params import ActuatorParams, paper_actuator

    p = paper_actuator()
    rows = ["| field | value | unit | source |", "|---|---|---|---|"]
    for f in fields(ActuatorParams):
        rows.append(f"| `{f.name}` | {getattr(p, f.name):.6g} | `{f.metadata['unit']}` | {f.metadata['source']} |")
    return "\n".join(rows)


def designs() -> str:
    from .design import DesignWarning, design_table, paper_designs

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DesignWarning)
        return design_table(paper_designs())


def emps_estimators() -> str:
    """Every estimator of ``fricctl identify`` on ``DATA_EMPS.mat``, validated on
    ``DATA_EMPS_PULSES.mat`` (needs ``FRICCTL_DATA``)."""
    from .controllers import constant, pd_control
    from .datasets import emps
    from .identify.compare import compare_estimators, estimator_table

    est, val = emps(kind="estimation"), emps(kind="validation")
    pd = pd_control(est.gtau * est.kp * est.kv, est.gtau * est.kv, constant(0.0))
    return estimator_table(compare_estimators(est.run, val.run, controller=pd))


BLOCKS = {"parameters": parameters, "designs": designs, "emps-estimators": emps_estimators}
#: The blocks that read the EMPS data (``FRICCTL_DATA``); tests/test_readme.py renders them
#: where the data are.
DATA_BLOCKS = ("emps-estimators",)


def render(text: str, names=None) -> str:
    """``text`` with the generated blocks ``names`` (default: all) replaced by their
    current content."""
    for name, fn in BLOCKS.items():
        if names is not None and name not in names:
            continue
        pattern = re.compile(rf"(<!-- BEGIN {name} -->\n)(?:.*?\n)?(<!-- END {name} -->)", re.S)
        if not pattern.search(text):
            raise ValueError(f"README has no block {name!r}")
        text = pattern.sub(lambda m: m.group(1) + fn() + "\n" + m.group(2), text)
    return text


if __name__ == "__main__":  # pragma: no cover
    path = Path(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).resolve().parents[1] / "README.md")
    path.write_text(render(path.read_text()))
