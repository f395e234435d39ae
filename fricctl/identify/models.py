r"""The friction models of the inverse dynamic identification model (IDIM).

One axis, rotary convention (for a linear axis read force [N], mass [kg], [m], [m/s]):

.. math::

    \tau = I\,\ddot q + F_f(\dot q) + \text{offset},

with the friction laws (``w`` = velocity, friction has the sign of ``w``)

* ``"coulomb_viscous"``: ``F_f = b*w + Fc*sign(w)``;
  parameters ``inertia, viscous, coulomb, offset``;
* ``"asymmetric"`` (EMPS eq. 12): ``b+ * w + Fc+`` for ``w > 0`` and
  ``b- * w - Fc-`` for ``w < 0``, two positive magnitudes per direction;
  parameters ``inertia, viscous_pos, coulomb_pos, viscous_neg, coulomb_neg``
  (``offset`` only on request: without rest samples it is collinear with the two
  Coulomb columns);
* ``"stribeck"``: ``b*w + sign(w)*(Fc + (Fs - Fc)*exp(-(w/vs)^2))``;
  parameters ``inertia, viscous, coulomb, static, stribeck_velocity, offset``.

This module states the models once, in numpy: their parameter names, units and
bounds, the observation matrix of the linear ones (:func:`regressor`, its friction
columns those the registered friction laws declare: ``Law.regressors``) and the
torque every model predicts (:func:`inverse_dynamics`).  ``static`` is the absolute
breakaway level ``Fs`` here as everywhere in fricctl (the ``Static`` law's coefficient is
the excess ``static_excess = Fs - Fc``).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from .. import _validate as v
from ..friction import LAWS
from ..units import units as units_of

__all__ = [
    "MODELS",
    "LINEAR_MODELS",
    "NONNEGATIVE",
    "model_names",
    "parameter_unit",
    "lower_bounds",
    "regressor",
    "inverse_dynamics",
    "check_directions",
    "implausible",
]

#: Parameter names of each model (``offset`` included where it is the default).
MODELS = {
    "coulomb_viscous": ("inertia", "viscous", "coulomb", "offset"),
    "asymmetric": ("inertia", "viscous_pos", "coulomb_pos", "viscous_neg", "coulomb_neg"),
    "stribeck": ("inertia", "viscous", "coulomb", "static", "stribeck_velocity", "offset"),
}
#: The models that are linear in their parameters (they have a :func:`regressor`).
LINEAR_MODELS = ("coulomb_viscous", "asymmetric")
#: Parameters bounded below by 0 in every fit (magnitudes, per the sign convention).
NONNEGATIVE = frozenset({"inertia", "viscous", "coulomb", "viscous_pos", "coulomb_pos",
                         "viscous_neg", "coulomb_neg", "static"})
#: The quantity of each parameter (a field of :class:`fricctl.units.Units`).
_QUANTITY = {"inertia": "inertia", "viscous": "viscous", "coulomb": "torque",
             "offset": "torque", "static": "torque", "stribeck_velocity": "velocity"}


def _model(model) -> str:
    return v.choice("model", model, MODELS)


def model_names(model: str, offset: bool | None = None) -> tuple[str, ...]:
    """Parameter names of ``model``, with or without ``offset``.

    Examples
    --------
    >>> model_names("asymmetric", offset=True)
    ('inertia', 'viscous_pos', 'coulomb_pos', 'viscous_neg', 'coulomb_neg', 'offset')
    """
    names = MODELS[_model(model)]
    if offset is not None:
        offset = v.flag("offset", offset)
    has = "offset" in names
    if offset is None or offset == has:
        return names
    return names + ("offset",) if offset else tuple(n for n in names if n != "offset")


def parameter_unit(name: str, kind: str = "rotary") -> str:
    """Unit label of a friction-model parameter (``""`` for a name of no model).

    Parameters
    ----------
    name : str
        Parameter name, e.g. ``"viscous_neg"``.
    kind : {"rotary", "linear"}
        Kind of axis (:mod:`fricctl.units`).

    Examples
    --------
    >>> parameter_unit("viscous_neg", "linear"), parameter_unit("stribeck_velocity")
    ('N*s/m', 'rad/s')
    """
    labels = units_of(kind)
    name = v.text("name", name)
    quantity = _QUANTITY.get(name.replace("_pos", "").replace("_neg", ""))
    return "" if quantity is None else getattr(labels, quantity)


def lower_bounds(names) -> np.ndarray:
    """Lower bounds of a fit over ``names``: 0 for :data:`NONNEGATIVE`, else ``-inf``."""
    if isinstance(names, str) or not isinstance(names, (list, tuple)):
        raise ValueError(f"names must be a list or tuple of parameter names, got "
                         f"{type(names).__name__}")
    names = [v.text(f"names[{i}]", nm) for i, nm in enumerate(names)]
    return np.array([0.0 if nm in NONNEGATIVE else -np.inf for nm in names])


def regressor(model: str, velocity, acceleration, *, offset: bool | None = None) -> np.ndarray:
    """Observation matrix of a linear-in-parameters model, columns in :func:`model_names` order.

    Parameters
    ----------
    model : {"coulomb_viscous", "asymmetric"}
        Linear model.
    velocity, acceleration : array_like, shape (N,)
        Joint velocity [rad/s] and acceleration [rad/s^2] (or [m/s], [m/s^2]).
    offset : bool, optional
        Include the constant column (default: as in :data:`MODELS`).

    Examples
    --------
    >>> regressor("coulomb_viscous", [2.0, -1.0], [0.5, 0.0]).tolist()
    [[0.5, 2.0, 1.0, 1.0], [0.0, -1.0, -1.0, 1.0]]
    """
    if _model(model) not in LINEAR_MODELS:
        raise ValueError(f"model: {model!r} is not linear in its parameters; no regressor matrix")
    w = v.array("velocity", velocity)
    a = v.array("acceleration", acceleration, size=w.size)
    cols = {"inertia": a, "offset": np.ones_like(w)}
    for law in LAWS.values():  # each friction law linear in its coefficients gives its columns
        if law.regressors is not None:
            cols.update(law.regressors(w, model == "coulomb_viscous"))
    return np.column_stack([cols[n] for n in model_names(model, offset)])


def inverse_dynamics(model: str, parameters: Mapping, velocity, acceleration) -> np.ndarray:
    """Torque [N*m] (or force [N]) the model predicts for given motion.

    Parameters
    ----------
    model : str
        One of :data:`MODELS`.
    parameters : dict
        Name -> value; exactly the names of the model, ``offset`` optional.
    velocity, acceleration : array_like, shape (N,)
        [rad/s], [rad/s^2] (or [m/s], [m/s^2]).

    Examples
    --------
    >>> p = dict(inertia=2.0, viscous=0.5, coulomb=1.0, offset=0.0)
    >>> inverse_dynamics("coulomb_viscous", p, [2.0, -2.0], [1.0, 1.0]).tolist()
    [4.0, 0.0]
    """
    names = set(MODELS[_model(model)]) - {"offset"}
    v.instance("parameters", parameters, Mapping, "a mapping of parameter names to values")
    given = set(parameters)
    if not names <= given or not given <= names | {"offset"}:
        raise ValueError(f"parameters: expected {sorted(names)} (+ optional offset), got {sorted(given)}")
    p = {k: v.real(f"parameters[{k!r}]", x) for k, x in parameters.items()}
    w = v.array("velocity", velocity)
    a = v.array("acceleration", acceleration, size=w.size)
    s = np.sign(w)
    tau = p["inertia"] * a + p.get("offset", 0.0)
    if model == "coulomb_viscous":
        return tau + p["viscous"] * w + p["coulomb"] * s
    if model == "asymmetric":
        pos, neg = w > 0, w < 0
        return tau + np.where(pos, p["viscous_pos"] * w + p["coulomb_pos"], 0.0) \
                   + np.where(neg, p["viscous_neg"] * w - p["coulomb_neg"], 0.0)
    excess = (p["static"] - p["coulomb"]) * np.exp(-(w / p["stribeck_velocity"]) ** 2)
    return tau + p["viscous"] * w + s * (p["coulomb"] + excess)


def check_directions(names, forward: int, backward: int, need: int, reach: str) -> None:
    """Refuse a fit of ``names`` on a record that slides one way only.

    While the joint slides one way, a Coulomb level and a constant offset are one constant
    torque: no record of that motion tells them apart; and the other direction's
    coefficients of the asymmetric model never act.  A direction counts as excited when it
    holds at least ``need`` sliding samples: with fewer, its columns differ from a constant
    only by what the recipe's filters smear into them, and a fit that separates them reports
    numbers the record cannot vouch for.

    Parameters
    ----------
    names : sequence of str
        Parameter names of the fit (:func:`model_names`).
    forward, backward : int
        Sliding samples the fit reads in each direction [samples].
    need : int
        Fewest sliding samples that excite a direction, decided by the record's own
        processing (its filters' reach) [samples].
    reach : str
        What ``need`` is, for the message.

    Raises
    ------
    ValueError
        A direction below ``need`` where ``names`` needs it, naming the parameters and why.
    """
    counts = {"forward": int(forward), "backward": int(backward)}
    lacking = [d for d, c in counts.items() if c < need]
    if not lacking:
        return
    suffix = {"forward": "_pos", "backward": "_neg"}
    why = [f"{' and '.join(own)} act only while it slides {d}" for d in lacking
           if (own := [n for n in names if n.endswith(suffix[d])])]
    if "offset" in names:
        present = [d for d in counts if d not in lacking] or list(counts)
        levels = [n for n in names if n == "coulomb"
                  or any(n == "coulomb" + suffix[d] for d in present)]
        if levels:
            why.append(f"{' and '.join(levels)} and offset are one constant torque while it "
                       f"slides {' or '.join(present)} only, and cannot be told apart")
    if not why:
        return
    hint = ("record motion both ways, or fit without the offset (--no-offset) if the drive "
            "has none" if "offset" in names and not any(n.endswith(("_pos", "_neg"))
                                                        for n in names)
            else "record motion both ways")
    raise ValueError(f"the record slides {counts['forward']} samples forward and "
                     f"{counts['backward']} backward, and a direction needs {need} ({reach}): "
                     + "; ".join(why) + f"; {hint}")


def implausible(model: str | None, parameters: Mapping) -> dict:
    """Name -> why its estimate is not physical, for the estimates of a fit of ``model``.

    A Stribeck curve falls from its breakaway level ``static`` to the Coulomb level: a
    ``static`` below ``coulomb`` is a dip the law cannot mean (a model file refuses it).

    Examples
    --------
    >>> implausible("stribeck", dict(coulomb=0.2, static=0.1))
    {'static': 'breakaway level 0.1 below the Coulomb level 0.2, non-physical'}
    """
    if model != "stribeck" or not {"static", "coulomb"} <= set(parameters):
        return {}
    fs, fc = float(parameters["static"]), float(parameters["coulomb"])
    if fs >= fc:
        return {}
    return {"static": f"breakaway level {fs:.4g} below the Coulomb level {fc:.4g}, non-physical"}
