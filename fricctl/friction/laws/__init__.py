"""The friction laws, one module each, registered by the ``LAW`` each module defines.

Adding a law is adding its module here (``LAW = Law(...)`` and its public class; see
:mod:`fricctl.friction.law` for what it declares): the coefficient layout, the model's
fields and evaluation, the compiled kernels, the integrator's sub-steps, the diagnosis's
torque along a measured motion and identification's regressor columns are built from
:data:`LAWS`.

Examples
--------
>>> [law.name for law in LAWS.values()][:3]
['viscous', 'coulomb', 'static']
>>> LAWS["viscous"].role, LAWS["viscous"].field_names
('rate', ('viscous_pos', 'viscous_neg'))
"""

from __future__ import annotations

import importlib
import pkgutil
import types

from ..law import Law

__all__ = ["LAWS", "laws_with_role", "law_of_field"]


def _registry() -> types.MappingProxyType:
    found = []
    for info in pkgutil.iter_modules(__path__):
        module = importlib.import_module(f"{__name__}.{info.name}")
        entry = getattr(module, "LAW", None)
        if entry is None:
            continue
        if not isinstance(entry, Law):
            raise ValueError(f"{module.__name__}.LAW must be a fricctl.friction.law.Law")
        if entry.name != info.name:
            raise ValueError(f"{module.__name__}.LAW is named {entry.name!r}: a law is named "
                             "as its module")
        found.append(entry)
    found.sort(key=lambda law: law.order)
    orders = [law.order for law in found]
    if len(set(orders)) != len(orders):
        raise ValueError(f"two laws share an order: {orders}")
    names = [c.name for law in found for c in law.coefficients]
    if len(set(names)) != len(names):
        raise ValueError("two laws declare a coefficient of the same name")
    if sum(law.role == "scale" for law in found) != 1:
        raise ValueError("exactly one law has the role 'scale'")
    return types.MappingProxyType({law.name: law for law in found})


#: Every registered law by name, in layout order (read-only).
LAWS = _registry()


def laws_with_role(role: str) -> tuple:
    """The registered laws of one role, in layout order."""
    return tuple(law for law in LAWS.values() if law.role == role)


def law_of_field(name: str) -> Law:
    """The law that declares the coefficient ``name``."""
    for law in LAWS.values():
        if name in law.field_names:
            return law
    raise ValueError(f"no friction law has a coefficient named {name!r}")
