"""Fig. 10: a sinusoid at 10 % of Tmax (inside the dead zone), and the dead zone itself."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import controllers as ctl
from ..bench.experiments import DeadZone, DeadZonePrediction, dead_zone, predicted_dead_zone
from ..compensators import NNCompensator, NoCompensation
from ..simulate import SimResult, simulate
from .claims import Claim
from .network import PaperNetwork, check_network
from .registry import PaperFigure

__all__ = ["Fig10Result", "run", "claim_dead_zone", "claim_fig10_motion", "FIGURE"]


@dataclass(frozen=True, eq=False, kw_only=True)
class Fig10Result:
    """Fig. 10: sinusoid at 10 % of Tmax (inside the dead zone), and the dead zone itself.

    Attributes
    ----------
    without, with_nn : open-loop runs at 10 % of Tmax
    dead_zone_without, dead_zone_with : measured dead zones (sinusoid batches)
    predicted : dead zone predicted from the net alone (DeadZonePrediction) [N*m]
    gain_at_rest : g of the net [-]
    """

    without: SimResult
    with_nn: SimResult
    dead_zone_without: DeadZone
    dead_zone_with: DeadZone
    predicted: DeadZonePrediction
    gain_at_rest: float

    @property
    def factor(self) -> float:
        """Dead-zone reduction factor, without / with compensation [-]."""
        return self.dead_zone_without.dead_zone / self.dead_zone_with.dead_zone

    @property
    def predicted_factor(self) -> float:
        """Breakaway level over the larger predicted dead zone [-]."""
        dz = self.predicted.largest
        fs = float(self.without.info.params.static)
        return fs / dz if dz > 0 else math.inf


def run(network: PaperNetwork, *, fraction: float = 0.10, frequency: float = 1.0,
        duration: float = 3.0) -> Fig10Result:
    """Control vs motor torque at 10 % of Tmax with compensation, and the dead zones (Fig. 10)."""
    net = check_network(network)
    p = net.params
    c = ctl.open_loop(ctl.sinusoid(fraction * p.max_torque, frequency))
    nn = NNCompensator(net.net)
    return Fig10Result(without=simulate(p, c, NoCompensation(), duration=duration),
                       with_nn=simulate(p, c, nn, duration=duration), dead_zone_without=dead_zone(p),
                       dead_zone_with=dead_zone(p, nn), predicted=predicted_dead_zone(net.net, p.static),
                       gain_at_rest=net.net.gain_at_rest())


def claim_dead_zone(r: Fig10Result, params=None) -> Claim:
    f0 = r.dead_zone_without.fraction
    ok = abs(100 * f0 - 12.7) <= 1.0 and r.factor >= 4.0
    return Claim(
        id="dead-zone", claim="The torque dead zone of 12.7 % of the maximum torque is reduced by NN "
        "compensation (here: uncompensated dead zone within 1 % of Tmax of 12.7 %, reduction factor >= 4)",
        paper="12.7 % of Tmax, factor ~6",
        measured=f"{100 * f0:.2f} % -> {100 * r.dead_zone_with.fraction:.2f} % of Tmax, factor "
        f"{r.factor:.1f} (g = {r.gain_at_rest:.2f}; predicted from the net alone: factor "
        f"{r.predicted_factor:.1f})", passed=ok, figure="Fig. 10",
        note="The 12.7 % half holds by construction (Tmax is defined as Fs/0.127); the measured part is the "
        "factor, judged by the issue's >= 4 (the paper's ~6 is one run of one net). It is set by the net's "
        "gain at rest g: the stuck loop settles at Tm = Tc/(1 - g) while g < 1, and at the fixed point "
        "Tm = Tc + T^at(Tm, 0) below Fs otherwise; g depends on the training seed and the estimator "
        "window (Chapter 5), so the factor does too."
        + ("" if ok else " Here it is below 4."))


def claim_fig10_motion(r: Fig10Result, params=None) -> Claim:
    c0, c1 = r.without.displacement_counts(), r.with_nn.displacement_counts()
    thr = r.dead_zone_with.threshold_counts
    ok = c0 <= thr < c1
    return Claim(
        id="fig10-motion", claim="A sinusoidal control torque of 10 % of Tmax, inside the dead zone, moves "
        f"the joint with compensation and not without (here: encoder motion > {thr} counts)",
        paper="moves with, still without",
        measured=f"{c0} counts without, {c1} counts with; peak |Tm| "
        f"{np.abs(r.with_nn.torque_motor).max():.3f} N*m for peak |Tc| "
        f"{np.abs(r.with_nn.torque_cmd).max():.3f} N*m", passed=ok, figure="Fig. 10",
        note=("the loop winds the motor torque up to several times the control torque (g > 1 at rest): the "
              "joint moves, but it runs away rather than following the small control torque"
              if ok and np.abs(r.with_nn.torque_motor).max() > 2 * np.abs(r.with_nn.torque_cmd).max() else
              "" if ok else "the compensated motor torque stays below the breakaway level"))


FIGURE = PaperFigure(number=10, title="inside the dead zone: 10 % of Tmax, and the dead zones", run=run,
                     result_type=Fig10Result, claims=(claim_dead_zone, claim_fig10_motion))
