"""Fig. 5: the open-loop training torque sequence and the friction patterns it gives."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .network import PaperNetwork, check_network
from .registry import PaperFigure

__all__ = ["Fig5Result", "run", "FIGURE"]


@dataclass(frozen=True, eq=False, kw_only=True)
class Fig5Result:
    """Fig. 5: the open-loop training torque sequence and the measured friction.

    Attributes
    ----------
    t : time [s]
    torque : motor torque Tm [N*m]
    friction : patterns ``Tm - I*alpha_hat`` [N*m]
    friction_true : the simulator's friction [N*m]
    max_torque : Tmax [N*m]
    """

    t: np.ndarray
    torque: np.ndarray
    friction: np.ndarray
    friction_true: np.ndarray
    max_torque: float


def run(network: PaperNetwork) -> Fig5Result:
    """Torque steps of growing amplitude and the friction patterns they give (Fig. 5)."""
    net = check_network(network)
    i = [e.name for e in net.experiments].index("open-loop steps")
    pats = net.patterns.subset(net.patterns.experiment == i)
    return Fig5Result(t=pats.t, torque=pats.tm, friction=pats.friction, friction_true=pats.friction_true,
                      max_torque=net.params.max_torque)


FIGURE = PaperFigure(number=5, title="open-loop training sequence and experimental friction", run=run,
                     result_type=Fig5Result)
