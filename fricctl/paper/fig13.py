"""Fig. 13: PD step of 30 deg without compensation; the net's view of the residual torque."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..compensators import NoCompensation
from ..design import Design
from ..simulate import SimResult
from .claims import Claim
from .common import SS_WINDOW, deg, designs, sensed, step_run
from .network import PaperNetwork, check_network
from .registry import PaperFigure

__all__ = ["Fig13Result", "run", "claim_fig13", "FIGURE"]


@dataclass(frozen=True, eq=False, kw_only=True)
class Fig13Result:
    """Fig. 13: PD step of 30 deg without compensation; the net's view of the residual torque.

    Attributes
    ----------
    run, linear, design : the run, the linear prediction [rad], the PD (0.3 s, 0.9)
    steady_state_error : [rad]
    torque_at_rest : motor torque held at the end [N*m]
    nn_at_rest : the pipeline's full friction estimate at ``(torque_at_rest, 0)`` [N*m]
    nn_rmse : held-out RMSE of the net (its own accuracy) [N*m]
    """

    run: SimResult
    linear: np.ndarray
    design: Design
    steady_state_error: float
    torque_at_rest: float
    nn_at_rest: float
    nn_rmse: float


def run(network: PaperNetwork, *, step_deg: float = 30.0, duration: float = 3.0) -> Fig13Result:
    """PD step without compensation; residual motor torque against the NN estimate (Fig. 13)."""
    net = check_network(network)
    d = designs(net.bench)["fig13-14"]
    s = step_run(net.params, d, np.deg2rad(step_deg), NoCompensation(), duration,
                 sensing=sensed(net, "fig13 none", net.params))
    tm = float(s.run.torque_motor[-1])
    return Fig13Result(run=s.run, linear=s.linear, design=d,
                       steady_state_error=s.run.steady_state_error(SS_WINDOW), torque_at_rest=tm,
                       nn_at_rest=float(net.estimate(tm, 0.0)), nn_rmse=net.fit_held_out.rmse)


def claim_fig13(r: Fig13Result, params=None) -> Claim:
    diff = abs(r.torque_at_rest - r.nn_at_rest)
    ok = diff <= 0.2 * abs(r.torque_at_rest)
    rel = 100 * diff / abs(r.torque_at_rest) if r.torque_at_rest != 0 else math.nan
    return Claim(
        id="fig13-residual", claim="PD step of 30 deg without compensation: the residual steady motor "
        "torque is close to the NN friction estimate (here: |Tm - T^at(Tm, 0)| at rest <= 20 % of Tm)",
        paper="Tm ~ NN estimate", measured=f"Tm {r.torque_at_rest:.4f} N*m, net {r.nn_at_rest:.4f} N*m "
        f"(difference {diff:.4f} N*m, {rel:.0f} %; RMSE {r.nn_rmse:.4f} "
        f"N*m); e_ss {deg(r.steady_state_error):.2f} deg", passed=ok, figure="Fig. 13", value=rel,
        unit="% of Tm",
        note="" if ok else "the joint holds no torque at rest: the relative difference is undefined"
        if math.isnan(rel) else "the net's estimate at rest differs from the held torque by more than 20 %")


FIGURE = PaperFigure(number=13, title="PD step without compensation: residual torque and the NN estimate",
                     run=run, result_type=Fig13Result, claims=(claim_fig13,))
