r"""The friction network fed a **direction-confirmed velocity**: ``s * T^at(Tm, omega_c)``, where
``omega_c`` is the backward-difference velocity when the encoder's difference goes the way of its
last nonzero difference, and 0 otherwise.

Why: at rest an encoder edge flickers (the state-width tolerance of an optical encoder, the
rotor's vibration under the current loop). The backward difference then reads
``+1, -1, +1 ...`` counts per sample, and a network whose estimate turns from ``g*Tm`` at rest
to ``+-Fc`` at one count per sample switches its torque with it: the joint's compensation
chatters like Coulomb compensation does. An edge that flickers between two counts moves back
and forth: each of its counts goes against the one before it. Motion, however slow, goes on
the way it went. So the rule reads a difference against the last nonzero difference's
direction as rest and passes everything else:

.. math::

   \omega_{c,k} = \begin{cases} \hat\omega_k & \Delta y_k\,d_{k-1} > 0 \\
   0 & \text{otherwise} \end{cases}

with ``Delta y_k = y_k - y_{k-1}`` and ``d_{k-1}`` the last nonzero difference before sample k.
The rule has no parameter (it compares directions, not sizes), so it cannot be set for another
encoder than the loop's. Motion slower than one count per sample (counts with zeros between)
is passed count by count, as the backward difference passes it. The cost: after a reversal,
or at a start against the last motion's direction, the network sees rest until the second
count confirms the direction -- one count interval, several samples at a slow breakaway. The
runaway check :func:`fricctl.paper.runaway.wind_up` does not allow for it: a torque beyond the
friction bound in that interval counts as it does for any compensator.

State: ``(d_{k-1})`` [rad], 0 before the first count (the first count is read as rest).
Parameters: the network's compiled vector (:func:`fricctl.netlayout.pack_compiled`).
"""

from __future__ import annotations

from dataclasses import KW_ONLY, dataclass
from typing import Callable

import numpy as np

from .. import _validate as v
from ..netlayout import NET_ATTRIBUTES, forward_packed, pack_compiled
from .base import Compensator, CompiledCompensator, Entry

__all__ = ["ConfirmedNNCompensator", "ENTRY", "VELOCITIES", "network_compensator"]

#: Kind id in the compiled loop.
KIND = 7
#: The velocities a network compensator can be fed: the backward difference (the paper's,
#: :class:`~fricctl.compensators.NNCompensator`) and the direction-confirmed one (this module's).
VELOCITIES = ("backward-difference", "confirmed")
X_DY_PREV = 0


@dataclass(frozen=True)
class ConfirmedNNCompensator(Compensator):
    """The friction network on the direction-confirmed velocity (module docstring).

    Parameters
    ----------
    estimator : FrictionNet
        A trained :class:`fricctl.nn.FrictionNet` (compiled loop only). The only positional
        argument.
    scale : float
        s [-].
    clip : bool
        Clip the inputs to the net's training envelope.
    """

    estimator: Callable
    _: KW_ONLY
    scale: float = 1.0
    clip: bool = False
    name: str = "NN (confirmed velocity)"
    stateful = True

    def __post_init__(self):
        if not all(hasattr(self.estimator, a) for a in NET_ATTRIBUTES):
            raise ValueError("estimator must be a trained fricctl.nn.FrictionNet, got "
                             f"{type(self.estimator).__name__}")
        v.real("scale", self.scale, nonneg=True)
        v.flag("clip", self.clip)
        v.text("name", self.name)

    @property
    def units(self) -> str | None:
        kind = getattr(self.estimator, "units", None)
        return kind if isinstance(kind, str) else None

    def compiled(self):
        return CompiledCompensator(kind=KIND, params=pack_compiled(self.estimator, self.clip),
                                   state=np.zeros(1))


def step(p, x, tm, wh, ts):
    """The network at (Tm_k, omega_c_k); ``x[0]`` holds the last nonzero encoder difference."""
    dy = wh * ts
    prev = x[X_DY_PREV]
    if dy != 0.0:
        x[X_DY_PREV] = dy
    if dy * prev > 0.0:
        return forward_packed(p, tm, wh)
    return forward_packed(p, tm, 0.0)


def network_compensator(net, velocity: str, *, scale: float = 1.0, **options) -> Compensator:
    """The compensator that feeds ``net`` the velocity ``velocity`` (one of :data:`VELOCITIES`):
    an :class:`~fricctl.compensators.NNCompensator` on the backward difference, or a
    :class:`ConfirmedNNCompensator`; ``options`` (``clip``, ``name``) go to it."""
    from .network import NNCompensator

    if v.choice("velocity", velocity, VELOCITIES) == "confirmed":
        return ConfirmedNNCompensator(net, scale=scale, **options)
    return NNCompensator(net, scale=scale, **options)


def _make(model, design, sample_time, *, net=None, clip: bool = False, scale: float = 1.0):
    """``net``: a trained FrictionNet (``fricctl.nn.load_net(path)`` reads one)."""
    if net is None or not all(hasattr(net, a) for a in NET_ATTRIBUTES):
        raise ValueError("nn_confirmed: net must be a trained fricctl.nn.FrictionNet (fricctl.nn.load_net "
                         f"reads one from its JSON file), got {type(net).__name__}")
    return ConfirmedNNCompensator(net, clip=clip, scale=scale)


ENTRY = Entry(name="nn_confirmed", kind=KIND, cls=ConfirmedNNCompensator, make=_make, step=step,
              description="the friction network on the direction-confirmed velocity (a count "
                          "against the last nonzero difference's direction is read as rest)")
