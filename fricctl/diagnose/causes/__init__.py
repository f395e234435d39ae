"""The candidate causes of a diagnosis: one module per cause, found and ordered here.

Each module of this package (apart from :mod:`.base`) defines ``CAUSE``, a
:class:`~fricctl.diagnose.causes.base.Cause`: the name, a one-line physical
description, whether it needs a nominal model, its regressor variants, how it
extends a model, its evidence sentence and how the bench hides it.  The registry
below is built from the modules found in this folder, ordered by ``Cause.order``;
``none`` (nothing to add) is not a module: it is :data:`NONE`, handled here.

Adding a cause
--------------
1. Write ``fricctl/diagnose/causes/<name>.py`` with ``CAUSE = Cause(name="<name>", order=...,
   ...)`` (copy the closest cause; :mod:`.stribeck` is the shortest complete one).
2. Give it the next free ``order`` (ties in score go to the lower number).
3. Run ``tests/test_diagnose_causes.py``: every registered cause is hidden by the bench and
   must be named, and its extension must change the model.
4. If a supplied model can hold the effect (a model file's offset, Stribeck excess ...), give
   it ``remove=`` (the model without it): the diagnosis then judges the model's term by the
   same held-out tests instead of trusting it (:func:`fricctl.diagnose.judged_by_removal`).

Examples
--------
>>> CAUSES[:3]
('none', 'stribeck', 'asymmetry')
>>> get("position_ripple").params
('ripple_sin', 'ripple_cos')
>>> sorted(set(CAUSES[1:]) - {c.name for c in candidates(nominal=False)})  # nominal only
['friction_scale', 'inertia']
"""

from __future__ import annotations

import importlib
import pkgutil
from types import MappingProxyType

from .base import BenchActuator, Baseline, Cause, Injection, Term

__all__ = ["Cause", "Term", "Baseline", "BenchActuator", "Injection", "REGISTRY", "CAUSES",
           "NONE", "NOMINAL_ONLY", "get", "physical", "candidates", "inject"]

#: The name of "no cause": no candidate of the list improves on the baseline.
NONE = "none"
_NONE_PHYSICAL = "no cause of the list improves the held-out fit (whether the record is explained is the verdict's)"


def _discover() -> tuple:
    found = []
    for info in pkgutil.iter_modules(__path__):
        if info.name == "base" or info.name.startswith("_"):
            continue
        module = importlib.import_module(f"{__name__}.{info.name}")
        cause = getattr(module, "CAUSE", None)
        if not isinstance(cause, Cause):
            raise ImportError(f"{module.__name__} defines no CAUSE = Cause(...)")
        if cause.name != info.name:
            raise ImportError(f"{module.__name__}: CAUSE.name is {cause.name!r}, expected the "
                              f"module name {info.name!r}")
        found.append(cause)
    found.sort(key=lambda c: c.order)
    orders = [c.order for c in found]
    if len(set(orders)) != len(orders):
        raise ImportError(f"two causes share an order: {[(c.name, c.order) for c in found]}")
    return tuple(found)


#: name -> :class:`Cause`, in candidate order.
REGISTRY = MappingProxyType({c.name: c for c in _discover()})
#: Every cause a diagnosis can name, ``none`` first, then in candidate order.
CAUSES = (NONE,) + tuple(REGISTRY)
#: Causes that only exist against a supplied nominal model.
NOMINAL_ONLY = tuple(name for name, c in REGISTRY.items() if c.nominal_only)


def get(name: str) -> Cause:
    """The registered cause called ``name`` (ValueError for ``none`` or an unknown name)."""
    if name not in REGISTRY:
        raise ValueError(f"no cause {name!r}; registered: {', '.join(REGISTRY)}")
    return REGISTRY[name]


def physical(name: str) -> str:
    """The one-line physical description of ``name`` (``none`` included)."""
    return _NONE_PHYSICAL if name == NONE else get(name).physical


def candidates(*, nominal: bool) -> tuple:
    """The causes a diagnosis tries: all with a nominal model, else those that need none."""
    return tuple(c for c in REGISTRY.values() if nominal or not c.nominal_only)


def inject(name: str, rng, actuator: BenchActuator) -> Injection:
    """Hide ``name`` in ``actuator`` (``none``: the baseline actuator itself, no draw)."""
    if name == NONE:
        return actuator.rigid(magnitude={})
    return get(name).inject(rng, actuator)
