"""Friction compensators behind one interface (paper Eq. 3), one module each, found here.

At sample k a compensator returns a friction estimate ``T^at(k)``; the loop then commands

    Tm(k+1) = clip(Tc(k) + s * T^at(k), -Tmax, +Tmax)

with ``s`` the compensator's ``scale`` (1, or 0.95 for the aged actuator of Fig. 16).
A compensator owns a parameter vector and a state vector and a compiled step
(:mod:`.base` says which signals a step may read: Tm, omega_hat, y, r, Tc, Ts); the
memoryless ones (none, Coulomb, the network) have an empty state and also a vectorised
``__call__(tm, omega_hat)``.  The registered kinds:

====================  =======================================================================
``none``              :class:`NoCompensation`, ``T^at = 0``
``coulomb``           :class:`CoulombCompensator`, ``Fc*sign(omega_hat)`` (Coulomb or breakaway)
``nn``                :class:`NNCompensator`, a network ``T^at(Tm, omega_hat)``; a
                      :class:`fricctl.nn.FrictionNet` runs compiled, any other callable in
                      the Python loop
``feedforward``       :class:`StaticFeedforward`, the identified Stribeck curve
``lugre_observer``    :class:`LuGreObserver`, Canudas de Wit et al. (1995)
``dob``               :class:`DisturbanceObserver`, Ohnishi's DOB
``integral``          :class:`IntegralAction`, PID with clamping anti-windup
``nn_confirmed``      :class:`ConfirmedNNCompensator`, the network on the direction-confirmed
                      velocity (the fricctl pipeline's: encoder flicker read as rest)
====================  =======================================================================

Adding a compensator
--------------------
Write ``fricctl/compensators/<name>.py`` with its public class (a
:class:`~.base.Compensator` whose ``compiled()`` gives its kind, parameters and initial
state), its compiled ``step`` and ``ENTRY = Entry(name=..., kind=<next free id>, ...)``;
the registry, the compiled loop's dispatch (:mod:`.compiled`), :func:`available`,
:func:`make` and ``fricctl simulate --compensation`` pick it up.

Examples
--------
>>> available()[:4]
('none', 'coulomb', 'nn', 'feedforward')
>>> from fricctl.params import paper_actuator
>>> make("coulomb", paper_actuator(), level="breakaway").coulomb_pos
0.18
"""

from __future__ import annotations

import importlib
import pkgutil
from types import MappingProxyType

from .base import CCode, Compensator, CompiledCompensator, Entry, joint_model
from .coulomb import CoulombCompensator
from .dob import DisturbanceObserver
from .feedforward import StaticFeedforward
from .integral import IntegralAction, design_ki
from .lugre_observer import LuGreObserver
from .network import NNCompensator
from .nn_confirmed import ConfirmedNNCompensator
from .none import NoCompensation

__all__ = ["Compensator", "NoCompensation", "CoulombCompensator", "NNCompensator",
           "ConfirmedNNCompensator", "StaticFeedforward", "LuGreObserver", "DisturbanceObserver",
           "IntegralAction",
           "CompiledCompensator", "Entry", "CCode", "REGISTRY", "available", "get", "make",
           "design_ki", "COMP_NONE", "COMP_COULOMB", "COMP_NN"]

_NOT_MEMBERS = {"base", "compiled", "c_export"}


def _discover() -> MappingProxyType:
    found = []
    for info in pkgutil.iter_modules(__path__):
        if info.name in _NOT_MEMBERS or info.name.startswith("_"):
            continue
        module = importlib.import_module(f"{__name__}.{info.name}")
        entry = getattr(module, "ENTRY", None)
        if not isinstance(entry, Entry):
            raise ImportError(f"{module.__name__} defines no ENTRY = Entry(...)")
        found.append(entry)
    found.sort(key=lambda e: e.kind)
    for what in ("name", "kind"):
        values = [getattr(e, what) for e in found]
        if len(set(values)) != len(values):
            raise ImportError(f"two compensators share a {what}: {values}")
    return MappingProxyType({e.name: e for e in found})


#: Every registered compensator by name, in kind order (read-only).
REGISTRY = _discover()

#: Kind ids of the memoryless compensators of the first version (kept for their readers).
COMP_NONE, COMP_COULOMB, COMP_NN = (REGISTRY[n].kind for n in ("none", "coulomb", "nn"))


def available() -> tuple:
    """The names of the registered compensators, in kind order."""
    return tuple(REGISTRY)


def get(name: str) -> Entry:
    """The registry entry of ``name`` (ValueError naming the choices if unknown)."""
    if name not in REGISTRY:
        raise ValueError(f"unknown compensator {name!r}; choose one of {', '.join(REGISTRY)}")
    return REGISTRY[name]


def make(name: str, model, design=None, sample_time: float | None = None, **options) -> Compensator:
    """Build the compensator ``name`` from what a user has.

    Parameters
    ----------
    name : str
        One of :func:`available`.
    model : JointModel or ActuatorParams
        The identified model (friction, inertia, torque limit, sample time).
    design : Design or LinearLoop, optional
        The PD design (needed by ``integral``; ignored by the others).
    sample_time : float, optional
        Ts [s]; default the model's (``ActuatorParams.sample_time``).
    **options
        The compensator's own (each module's ``_make``): ``scale`` (all);
        ``level``, ``deadband`` (coulomb); ``net``, ``clip`` (nn); ``velocity``,
        ``deadband`` (feedforward); ``sigma0``, ``sigma1``, ``gain`` (lugre_observer);
        ``bandwidth`` (dob); ``decade``, ``ki`` (integral).  An unknown one raises.

    Returns
    -------
    Compensator
    """
    from .. import _validate as v

    entry = get(name)
    m = joint_model(model)
    ts = m.sample_time if sample_time is None else sample_time
    if ts is None:
        raise ValueError("sample_time: the model has none; give sample_time=")
    ts = v.real("sample_time", ts, positive=True, unit="s")
    try:
        return entry.make(m, design, ts, **options)
    except TypeError as exc:
        if "unexpected keyword" in str(exc) or "required keyword" in str(exc):
            raise ValueError(f"compensator {name!r}: {exc}") from None
        raise
