r"""The friction network fed a **direction-confirmed velocity**: ``s * T^at(Tm, omega_c)``, where
``omega_c`` is the backward-difference velocity when the encoder's difference goes the way of its
last nonzero difference (or moves two counts or more), and 0 otherwise.

Why: at rest an encoder edge flickers (the state-width tolerance of an optical encoder, the
rotor's vibration under the current loop). The backward difference then reads
``+1, -1, +1 ...`` counts per sample, and a network whose estimate turns from ``g*Tm`` at rest
to ``+-Fc`` at one count per sample switches its torque with it: the joint's compensation
chatters like Coulomb compensation does. An edge that flickers between two counts moves back
and forth: each of its counts goes against the one before it. Motion, however slow, goes on
the way it went. So the rule rejects a single count against the last nonzero difference's
direction and passes everything else:

.. math::

   \omega_{c,k} = \begin{cases} \hat\omega_k & |\Delta y_k| \ge 2\,\delta
   \ \text{or}\ \Delta y_k\,d_{k-1} > 0 \\ 0 & \text{otherwise} \end{cases}

with ``Delta y_k = y_k - y_{k-1}``, ``d_{k-1}`` the last nonzero difference before sample k
and ``delta`` one encoder count. Motion slower than one count per sample (counts with zeros
between) is passed count by count, as the backward difference passes it. The cost is one
sample of delay on the first count after a reversal, or of a start against the last motion's
direction (the second count confirms it). The threshold is the encoder's count, a property
of the record, not a tuned value.

State: ``(d_{k-1})`` [rad], 0 before the first count. Parameters: the network's compiled vector
(:func:`fricctl.netlayout.pack_compiled`) followed by one count [rad].
"""

from __future__ import annotations

from dataclasses import KW_ONLY, dataclass
from typing import Callable

import numpy as np

from .. import _validate as v
from ..netlayout import NET_ATTRIBUTES, forward_packed, pack_compiled
from .base import Compensator, CompiledCompensator, Entry

__all__ = ["ConfirmedNNCompensator", "ENTRY", "VELOCITIES"]

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
    count : float
        One encoder count [rad] (> 0): the joint model's encoder resolution.
    scale : float
        s [-].
    clip : bool
        Clip the inputs to the net's training envelope.
    """

    estimator: Callable
    _: KW_ONLY
    count: float
    scale: float = 1.0
    clip: bool = False
    name: str = "NN (confirmed velocity)"
    stateful = True
    velocity_lag = 1  # the first count after a reversal waits for the second

    def __post_init__(self):
        if not all(hasattr(self.estimator, a) for a in NET_ATTRIBUTES):
            raise ValueError("estimator must be a trained fricctl.nn.FrictionNet, got "
                             f"{type(self.estimator).__name__}")
        v.real("count", self.count, positive=True, unit="rad")
        v.real("scale", self.scale, nonneg=True)
        v.flag("clip", self.clip)
        v.text("name", self.name)

    @property
    def units(self) -> str | None:
        kind = getattr(self.estimator, "units", None)
        return kind if isinstance(kind, str) else None

    def compiled(self):
        p = np.append(pack_compiled(self.estimator, self.clip), float(self.count))
        return CompiledCompensator(kind=KIND, params=p, state=np.zeros(1))


def step(p, x, tm, wh, ts):
    """The network at (Tm_k, omega_c_k); ``x[0]`` holds the last nonzero encoder difference."""
    count = p[p.size - 1]
    dy = wh * ts
    prev = x[X_DY_PREV]
    if dy != 0.0:
        x[X_DY_PREV] = dy
    if abs(dy) >= 1.5 * count or dy * prev > 0.0:
        return forward_packed(p, tm, wh)
    return forward_packed(p, tm, 0.0)


def _make(model, design, sample_time, *, net, clip: bool = False, scale: float = 1.0):
    """``net``: a trained FrictionNet; one count is the model's encoder resolution."""
    from .base import joint_model

    count = joint_model(model).encoder_resolution
    if count is None or not count > 0:
        raise ValueError("nn_confirmed: the model has no encoder resolution (one count [rad]) "
                         "to confirm a direction with")
    return ConfirmedNNCompensator(net, count=float(count), clip=clip, scale=scale)


ENTRY = Entry(name="nn_confirmed", kind=KIND, cls=ConfirmedNNCompensator, make=_make, step=step,
              description="the friction network on the direction-confirmed velocity (a count "
                          "against the last nonzero difference's direction is read as rest)")
