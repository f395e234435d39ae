"""Trainers of the friction network behind one seam, registered by name.

Each trainer is one module of this package with an inner loop and a module-level
``TRAINER = Trainer(name=..., description=..., step=..., loop=...)``; the
registry :data:`TRAINERS` is built from the modules found here, so adding a
trainer is adding its module.  Everything the trainers share (pattern checks,
scaling, initial weights, history, metadata, the final fit) is in
:mod:`fricctl.nn.train.core`.  Each module's docstring says its method, and its
entry what ``fricctl train`` shows of it: the options a command line sets
(:class:`TrainerOption`), named option sets (:class:`Recipe`), the work its loop
refuses, and what it ``requires`` beyond bare patterns (such a trainer is reached
through a pipeline of :mod:`fricctl.nn.pipelines`).  ``fricctl train --help`` lists
them all, read from this registry.

Examples
--------
>>> all(t.name == name and t.description for name, t in TRAINERS.items())
True
>>> TRAINERS[DEFAULT_TRAINER].requires is None
True
>>> trainer("casadi").options()
{'restarts': 3, 'max_iterations': 200, 'tolerance': 1e-10}
>>> trainer("backprop").defaults("converging")["schedule"]
'cosine'
"""

from __future__ import annotations

import importlib
import pkgutil
import types

from ... import _validate as v
from .backprop import train_backprop
from .core import (LoopResult, Recipe, Scaling, Trainer, TrainerOption, TrainingHistory,
                   TrainingProblem, TrainingResult, initial_theta)
from .lm import train_casadi

__all__ = ["TRAINERS", "DEFAULT_TRAINER", "trainer", "Trainer", "TrainerOption", "Recipe",
           "TrainingProblem", "LoopResult", "TrainingHistory",
           "TrainingResult", "Scaling", "initial_theta", "train_backprop", "train_casadi"]


def _registry() -> types.MappingProxyType:
    found = {}
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda m: m.name):
        module = importlib.import_module(f"{__name__}.{info.name}")
        entry = getattr(module, "TRAINER", None)  # the seam (core) defines none
        if entry is None:
            continue
        v.instance(f"{module.__name__}.TRAINER", entry, Trainer)
        if entry.name in found:
            raise ValueError(f"two trainers are named {entry.name!r}")
        found[entry.name] = entry
    return types.MappingProxyType(found)


#: The registered trainers by name (read-only).
TRAINERS = _registry()
#: The trainer used where none is named (``fricctl train`` without ``--trainer``):
#: Levenberg-Marquardt stops by itself at the least-squares loss, which the paper's
#: back-propagation at its constant rate does not reach (backprop.py, chapter 04).
DEFAULT_TRAINER = "casadi"
if DEFAULT_TRAINER not in TRAINERS or TRAINERS[DEFAULT_TRAINER].requires is not None:
    raise ImportError(f"DEFAULT_TRAINER {DEFAULT_TRAINER!r} must be a registered trainer that "
                      "trains on bare patterns")


def trainer(name: str) -> Trainer:
    """The registered :class:`Trainer` called ``name`` (a ``ValueError`` lists the names)."""
    return TRAINERS[v.choice("trainer", name, TRAINERS)]
