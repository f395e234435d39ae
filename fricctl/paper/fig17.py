"""Fig. 17: a small step of 0.08 rad on the aged actuator with the link, as in Fig. 16."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import controllers as ctl
from . import coast as coast_test
from .claims import Claim, gate
from .common import ACCURACY_DEG, AGED_SCALE, SS_WINDOW, LinkFigure, deg, link_runs
from .network import PaperNetwork, check_network
from .registry import PaperFigure
from .runaway import wind_up

__all__ = ["Fig17Result", "run", "claim_fig17_none", "claim_fig17_nn", "FIGURE"]


@dataclass(frozen=True, eq=False, kw_only=True)
class Fig17Result(LinkFigure):
    """Fig. 17: small step of 0.08 rad, same actuator and compensation as Fig. 16.

    Attributes
    ----------
    runs : ``{"none", "NN x 0.95", "Coulomb at Fs", "Coulomb at Fc"}`` -> run
    design : the PD design with the link
    coulomb_levels : the identified levels of the Coulomb runs (before the scale s)
    step : [rad]
    steady_state_error : per run [rad]
    max_motion : per run, peak |q| [rad]
    wind_up : runaway check of the NN run
    coast : the network's coast test
    """

    step: float
    steady_state_error: dict
    max_motion: dict


def run(network: PaperNetwork, *, step: float = 0.08, duration: float = 3.0,
        friction_scale: float = AGED_SCALE, scale: float = AGED_SCALE) -> Fig17Result:
    """Step of 0.08 rad with the link, without and with compensation (Fig. 17)."""
    net = check_network(network)
    lr = link_runs(net, "fig16-17", ctl.step(step), duration, friction_scale, scale)
    return Fig17Result(runs=lr.runs, design=lr.design, coulomb_levels=lr.coulomb_levels, step=float(step),
                       steady_state_error={k: r.steady_state_error(SS_WINDOW) for k, r in lr.runs.items()},
                       max_motion={k: float(np.abs(r.q).max()) for k, r in lr.runs.items()},
                       wind_up=wind_up(lr.runs[f"NN x {scale:g}"]), coast=coast_test.run(net))


def claim_fig17_none(r: Fig17Result, bench=None) -> Claim:
    from .benches import as_bench

    resolution = as_bench(bench).actuator.encoder_resolution
    m = r.max_motion["none"]
    ok = m <= resolution
    return Claim(
        id="fig17-none", claim="Step of 0.08 rad without compensation: no motion (here: peak |q| <= 1 "
        "encoder count)", paper="no motion",
        measured=f"peak |q| {m:.2e} rad (1 count = {resolution:.2e} rad)", passed=ok, figure="Fig. 17",
        value=m / resolution, unit="counts",
        note=f"Passes trivially: Kp*0.08 rad = {r.design.kp * r.step:.3f} N*m is below the breakaway level."
        if ok else "the joint moved")


def claim_fig17_nn(r: Fig17Result, params=None) -> Claim:
    k = r.nn_key
    e = abs(r.steady_state_error[k])
    ok = deg(e) < ACCURACY_DEG
    return gate(Claim(
        id="fig17-nn", claim="Step of 0.08 rad with NN compensation: small steady-state error (here: < 0.3 "
        "deg, the paper's Fig. 14 accuracy)", paper="small error", measured=f"|e_ss| {deg(e):.3f} deg "
        f"({100 * e / r.step:.0f} % of the step)", passed=ok, figure="Fig. 17", value=deg(e), unit="deg",
        note="" if ok else "same cause as Fig. 14: the residual dead zone lets the joint stop within "
        "+-DZ/Kp of the reference; with s = 0.95 the stuck loop's gain is s*g (see 'why' below)."),
        (r.wind_up, r.coast.decay))


FIGURE = PaperFigure(
    number=17, title="small step of 0.08 rad with the link", run=run, result_type=Fig17Result,
    claims=(claim_fig17_none, claim_fig17_nn),
    assumptions=("runs on the same aged actuator and compensation as Fig. 16",))
