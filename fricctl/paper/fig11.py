"""Fig. 11: P step of 25 deg without compensation.

The paper says the joint ends with a large error and "the rotor velocity goes to zero and
remains".  How that is judged is a reading, a setting of the bench
(:attr:`Bench.fig11_reading <fricctl.paper.benches.Bench>`), one of :data:`READINGS`:
``"stuck"`` (a large error with the joint at rest almost all the run: written for a bench on
which the P step never breaks loose) or ``"moves-then-rests"`` (the joint moves, then is at rest
to the end: no limit cycle).
"""

from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType
from typing import Callable

import numpy as np

from ..compensators import NoCompensation
from ..design import Design
from ..simulate import SimResult
from .claims import Claim
from .common import SS_WINDOW, deg, designs, sensed, stick_intervals_after_motion, step_run
from .network import PaperNetwork, check_network
from .registry import PaperFigure

__all__ = ["Fig11Result", "Fig11Reading", "READINGS", "run", "claim_fig11", "FIGURE"]


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
    d = designs(net.bench)["fig11-12"]
    s = step_run(net.params, d, np.deg2rad(step_deg), NoCompensation(), duration,
                 sensing=sensed(net, "fig11 none", net.params))
    return Fig11Result(run=s.run, linear=s.linear, design=d,
                       steady_state_error=s.run.steady_state_error(SS_WINDOW),
                       stuck_fraction=float(np.mean(s.run.stuck)))


@dataclass(frozen=True, kw_only=True)
class Fig11Reading:
    """One reading of Fig. 11's statement: its name, what it asks, and its judge.

    Attributes
    ----------
    name : the bench's ``fig11_reading``
    description : one line: what the reading asks of the run
    judge : ``judge(result) -> Claim``
    """

    name: str
    description: str
    judge: Callable[[Fig11Result], Claim]


def _stuck(r: Fig11Result) -> Claim:
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


def _moves_then_rests(r: Fig11Result) -> Claim:
    run_, step = r.run, r.run.reference[-1]
    travel = float(np.abs(run_.q).max())
    moved = travel > run_.info.encoder_resolution
    rests = stick_intervals_after_motion(run_)
    end = run_.t[-1]
    rest_from = rests[-1][0] if rests and rests[-1][1] >= end else float("nan")
    ok = moved and rest_from <= end - SS_WINDOW
    if not moved:
        note = (f"The joint never moves: Kp*25 deg = {r.design.kp * abs(step):.3f} N*m is below the "
                "breakaway level.")
    elif not ok:
        note = f"The joint is still moving in the last {SS_WINDOW:g} s of the run (a limit cycle)."
    else:
        note = (f"Kp*25 deg = {r.design.kp * abs(step):.3f} N*m breaks the joint loose; it stops where "
                "|Kp*e| no longer exceeds the breakaway level, and a P loop without compensation holds a "
                "constant torque while stuck, so it cannot restart.")
    return Claim(
        id="fig11-stuck", claim="P step of 25 deg without compensation: the rotor moves, then its velocity "
        "goes to zero and remains, with a steady-state error (here: moves more than one encoder count, "
        f"then at rest from >= {SS_WINDOW:g} s before the end of the run to its end)",
        paper="velocity goes to zero and remains",
        measured=f"moves {deg(travel):.1f} deg, " + (f"at rest from {rest_from:.3f} s on" if rest_from == rest_from
                                                  else "not at rest at the end")
        + f"; e_ss {deg(r.steady_state_error):.2f} deg", passed=ok, figure="Fig. 11",
        value=rest_from, unit="s (at rest from)", note=note)


#: The readings of Fig. 11's statement, by name (a bench's ``fig11_reading``).
READINGS = MappingProxyType({x.name: x for x in (
    Fig11Reading(name="stuck", description="a large steady-state error, the joint at rest >= 90 % of "
                 "the run (a joint that never moves passes)", judge=_stuck),
    Fig11Reading(name="moves-then-rests", description="the joint moves, then is at rest to the end of "
                 "the run (no limit cycle)", judge=_moves_then_rests),
)})


def claim_fig11(r: Fig11Result, bench=None) -> Claim:
    """Fig. 11's claim under the bench's reading (:data:`READINGS`)."""
    from .benches import as_bench

    return READINGS[as_bench(bench).fig11_reading].judge(r)


FIGURE = PaperFigure(number=11, title="P step without compensation", run=run, result_type=Fig11Result,
                     claims=(claim_fig11,))
