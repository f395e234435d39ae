"""Trainers of the friction network behind one seam, registered by name.

Each trainer is one module of this package with an inner loop and a module-level
``TRAINER = Trainer(name=..., description=..., step=..., loop=...)``; the
registry :data:`TRAINERS` is built from the modules found here, so adding a
trainer is adding its module.  Everything the trainers share (pattern checks,
scaling, initial weights, history, metadata, the final fit) is in
:mod:`fricctl.nn.train.core`.

=========  ==================================================================
name       trainer
=========  ==================================================================
backprop   :func:`~fricctl.nn.train.backprop.train_backprop`, the paper's
           back-propagation with momentum (numba inner loop)
casadi     :func:`~fricctl.nn.train.lm.train_casadi`, Levenberg-Marquardt
           with CasADi's exact Jacobian
certified  :mod:`~fricctl.nn.train.certified`, least squares under slope
           constraints: the gain at rest certified inside a band
=========  ==================================================================

Examples
--------
>>> sorted(TRAINERS)
['backprop', 'casadi', 'certified']
>>> trainer("casadi").options()
{'restarts': 3, 'max_iterations': 200, 'tolerance': 1e-10}
"""

from __future__ import annotations

import importlib
import pkgutil
import types

from ... import _validate as v
from .backprop import train_backprop
from .core import (LoopResult, Scaling, Trainer, TrainingHistory, TrainingProblem,
                   TrainingResult, initial_theta)
from .lm import train_casadi

__all__ = ["TRAINERS", "trainer", "Trainer", "TrainingProblem", "LoopResult", "TrainingHistory",
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


def trainer(name: str) -> Trainer:
    """The registered :class:`Trainer` called ``name`` (a ``ValueError`` lists the names)."""
    return TRAINERS[v.choice("trainer", name, TRAINERS)]
