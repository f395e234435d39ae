"""Fig. 11: P step of 25 deg without compensation."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..compensators import NoCompensation
from ..design import Design
from ..simulate import SimResult
from .claims import Claim
from .common import SS_WINDOW, deg, designs, step_run
from .network import PaperNetwork, check_network
from .registry import PaperFigure

__all__ = ["Fig11Result", "run", "claim_fig11", "FIGURE"]


@dataclass(frozen=True, eq=False, kw_only=True)
class Fig11Result:
    """Fig. 11: P step of 25 deg without compensation.

    Attributes
    ----------
    run : the run
    linear : linear viscous prediction on the same grid [rad]
    design : the P design (0.2 s, 0.3)
    steady_state_error : mean r - q over the last 0.5 s [rad]
    stuck_fraction : fraction of samples at rest [-]
    """

    run: SimResult
    linear: np.ndarray
    design: Design
    steady_state_error: float
    stuck_fraction: float


def run(network: PaperNetwork, *, step_deg: float = 25.0, duration: float = 3.0) -> Fig11Result:
    """P step without compensation (Fig. 11)."""
    net = check_network(network)
    d = designs(net.params)["fig11-12"]
    s = step_run(net.params, d, np.deg2rad(step_deg), NoCompensation(), duration)
    return Fig11Result(run=s.run, linear=s.linear, design=d,
                       steady_state_error=s.run.steady_state_error(SS_WINDOW),
                       stuck_fraction=float(np.mean(s.run.stuck)))


def claim_fig11(r: Fig11Result, params=None) -> Claim:
    step = r.run.reference[-1]
    ok = abs(r.steady_state_error) >= 0.5 * abs(step) and r.stuck_fraction >= 0.9
    return Claim(
        id="fig11-stuck", claim="P step of 25 deg without compensation: large steady-state error with the "
        "joint stuck (here: |e_ss| >= half the step, joint at rest >= 90 % of the run)",
        paper="large error, stuck", measured=f"e_ss {deg(r.steady_state_error):.2f} deg, at rest "
        f"{100 * r.stuck_fraction:.0f} % of the time", passed=ok, figure="Fig. 11",
        value=100 * abs(r.steady_state_error) / abs(step), unit="% of the step",
        note=f"Passes trivially: Kp*25 deg = {r.design.kp * abs(step):.3f} N*m is below the breakaway "
        f"level, so the joint never moves at all." if ok else "the joint moved")


FIGURE = PaperFigure(number=11, title="P step without compensation", run=run, result_type=Fig11Result,
                     claims=(claim_fig11,))
