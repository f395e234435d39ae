"""Neural (or any learned) friction compensation ``s * T^at(Tm, omega_hat)`` (paper Eq. 3):
a :class:`fricctl.nn.FrictionNet` runs inside the compiled loop, any other estimator callable
in the (slower) Python loop.  The network's parameter vector and its offsets are
:mod:`fricctl.netlayout`'s (:func:`~fricctl.netlayout.pack_compiled`, evaluated by
:func:`~fricctl.netlayout.forward_packed`)."""

from __future__ import annotations

from dataclasses import KW_ONLY, dataclass
from typing import Callable

import numpy as np

from .. import _validate as v
from ..netlayout import NET_ATTRIBUTES, forward_packed, pack_compiled
from .base import Compensator, CompiledCompensator, Entry

__all__ = ["NNCompensator", "ENTRY"]

#: Kind id in the compiled loop.
KIND = 2


@dataclass(frozen=True)
class NNCompensator(Compensator):
    """Neural (or any learned) friction compensation ``s * T^at(Tm, omega_hat)``.

    Parameters
    ----------
    estimator : callable
        ``estimator(tm, omega) -> T^at`` [N*m], vectorised.  A
        :class:`fricctl.nn.FrictionNet` (or any object with its weight and
        scaling attributes, :data:`fricctl.nn.layout.NET_ATTRIBUTES`) is evaluated
        inside the compiled loop.  The only positional argument.
    scale : float
        s [-]: 1 for the trained actuator, 0.95 for the aged one (Fig. 16,
        without retraining).
    clip : bool
        Clip the inputs to the net's training envelope before evaluation.
    """

    estimator: Callable
    """``(tm [N*m], omega [rad/s]) -> T^at [N*m]``, vectorised."""
    _: KW_ONLY
    scale: float = 1.0
    """Compensation scale s [-]."""
    clip: bool = False
    """Clip the inputs to the net's training envelope (nets only)."""
    name: str = "NN"
    """Label in results and plots."""

    def __post_init__(self):
        if not callable(self.estimator):
            raise ValueError("estimator must be callable (tm, omega) -> friction estimate")
        v.real("scale", self.scale, nonneg=True)
        v.flag("clip", self.clip)
        v.text("name", self.name)

    def _is_net(self) -> bool:
        return all(hasattr(self.estimator, a) for a in NET_ATTRIBUTES)

    @property
    def units(self) -> str | None:
        """The axis the network was trained on (:attr:`fricctl.nn.FrictionNet.units`); None
        for an estimator that does not say."""
        kind = getattr(self.estimator, "units", None)
        return kind if isinstance(kind, str) else None

    def __call__(self, tm, omega_hat):
        if self.clip and self._is_net():
            return np.asarray(self.estimator(tm, omega_hat, clip=True), dtype=float)
        return np.asarray(self.estimator(tm, omega_hat), dtype=float)

    def compiled(self):
        if not self._is_net():
            return None
        return CompiledCompensator(kind=KIND, params=pack_compiled(self.estimator, self.clip))


def step(p, tm, wh):
    """Memoryless: the network of :func:`~fricctl.netlayout.forward_packed` at (Tm_k, omega_hat_k)."""
    return forward_packed(p, tm, wh)


def _make(model, design, sample_time, *, net, clip: bool = False, scale: float = 1.0):
    """``net``: a trained :class:`~fricctl.nn.FrictionNet` (``fricctl.nn.load_net(path)`` reads
    one; either pipeline of :mod:`fricctl.nn.pipelines`)."""
    if not all(hasattr(net, a) for a in NET_ATTRIBUTES):
        raise ValueError("nn: net must be a trained fricctl.nn.FrictionNet (fricctl.nn.load_net "
                         f"reads one from its JSON file), got {type(net).__name__}")
    return NNCompensator(net, clip=clip, scale=scale)


ENTRY = Entry(name="nn", kind=KIND, cls=NNCompensator, make=_make, step=step,
              description="the friction network T^at(Tm, omega_hat) of the paper (Eq. 3)")
