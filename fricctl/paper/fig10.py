"""Fig. 10: a sinusoid at 10 % of Tmax (inside the dead zone), and the dead zone itself.

Both claims involve compensation and require the runaway checks of the 10 %-of-Tmax
run (wind-up, reversal) and the network's coast test.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from .. import controllers as ctl
from ..bench.experiments import DeadZone, DeadZonePrediction, dead_zone, predicted_dead_zone
from ..compensators import NoCompensation
from ..simulate import SimResult, simulate
from . import coast as coast_test
from .claims import Claim, gate
from .common import OpenLoopChecks, deg, designs, read_only, sensed, uncompensated_dead_zone
from .network import PaperNetwork, check_network
from .registry import PaperFigure
from .runaway import reversal, wind_up

__all__ = ["Fig10Result", "run", "claim_dead_zone", "claim_fig10_motion", "FIGURE"]


@dataclass(frozen=True, eq=False, kw_only=True)
class Fig10Result(OpenLoopChecks):
    """Fig. 10: sinusoid at 10 % of Tmax (inside the dead zone), and the dead zone itself.

    Attributes
    ----------
    without, with_nn : open-loop runs at 10 % of Tmax
    dead_zone_without, dead_zone_with : measured dead zones (sinusoid batches)
    predicted : dead zone predicted from the net alone (DeadZonePrediction) [N*m]
    gain_at_rest : g of the net [-]
    frequency : of the sinusoid [Hz]
    wind_up, reversal : runaway checks of ``with_nn``
    coast : the network's coast test
    """

    without: SimResult
    with_nn: SimResult
    dead_zone_without: DeadZone
    dead_zone_with: DeadZone
    predicted: DeadZonePrediction
    gain_at_rest: float
    frequency: float

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


@functools.lru_cache(maxsize=4)
def _uncompensated(params, fraction, frequency, duration, network=None):
    """The run and the dead zone without compensation: the same for every network on a
    bench without noise or ripple (``network`` None; else the run's sensing is the network's
    bench's, its noise drawn from the network's seed by :func:`~fricctl.paper.common.sensed`)
    (memoised, read-only)."""
    c = ctl.open_loop(ctl.sinusoid(fraction * params.max_torque, frequency))
    r0 = simulate(params, c, NoCompensation(), duration=duration,
                  **({} if network is None else sensed(network, "fig10 none", params)))
    read_only(r0)
    return r0, uncompensated_dead_zone(params)


def run(network: PaperNetwork, *, fraction: float = 0.10, frequency: float = 1.0,
        duration: float = 3.0) -> Fig10Result:
    """Control vs motor torque at 10 % of Tmax with compensation, and the dead zones (Fig. 10)."""
    net = check_network(network)
    p = net.params
    c = ctl.open_loop(ctl.sinusoid(fraction * p.max_torque, frequency))
    nn = net.compensator()
    r1 = simulate(p, c, nn, duration=duration, **sensed(net, "fig10 NN", p))
    # the network itself keys the memo when its bench senses noise or ripple (its seed draws the
    # noise; its bench holds the ripple)
    r0, dz0 = _uncompensated(p, float(fraction), float(frequency), float(duration),
                             None if net.bench.sensing.ideal else net)
    return Fig10Result(without=r0, with_nn=r1, dead_zone_without=dz0,
                       dead_zone_with=dead_zone(p, nn), predicted=predicted_dead_zone(net.net, p.static),
                       gain_at_rest=net.net.gain_at_rest(), frequency=float(frequency), wind_up=wind_up(r1),
                       reversal=reversal(r1, 1.0 / frequency), coast=coast_test.run(net))


def claim_dead_zone(r: Fig10Result, bench=None) -> Claim:
    from .benches import as_bench

    b = as_bench(bench)
    params = b.actuator
    f0 = r.dead_zone_without.fraction
    ok = abs(100 * f0 - 12.7) <= 1.0 and r.factor >= 4.0
    floor = r.dead_zone_with.at_grid_floor
    kp = designs(b)["fig13-14"].kp
    band = r.dead_zone_with.dead_zone / kp
    return gate(Claim(
        id="dead-zone", claim="The torque dead zone of 12.7 % of the maximum torque is reduced by NN "
        "compensation (here: uncompensated dead zone within 1 % of Tmax of 12.7 %, reduction factor >= 4)",
        paper="12.7 % of Tmax, factor ~6",
        measured=f"{100 * f0:.2f} % -> {100 * r.dead_zone_with.fraction:.2f} % of Tmax, factor "
        f"{'>= ' if floor else ''}{r.factor:.1f} (g = {r.gain_at_rest:.3f}; predicted from the net alone: "
        f"factor {r.predicted_factor:.1f})", passed=ok, figure="Fig. 10", value=r.factor, unit="x",
        note="The 12.7 % half holds by construction (Tmax is defined as Fs/0.127); the measured part is the "
        "factor, judged by the issue's >= 4 (the paper's ~6 is one run of one net). It is set by the net's "
        "gain at rest g: the stuck loop settles at Tm = Tc/(1 - g) while g < 1, and at the fixed point "
        "Tm = Tc + T^at(Tm, 0) below Fs otherwise. The trade-off: a residual dead zone DZ lets a stuck PD "
        f"loop stop anywhere within +-DZ/Kp of the reference, here +-{deg(band):.3f} deg with Fig. 14's "
        f"Kp = {kp:.3f} N*m/rad (the paper's ~6x would leave +-{deg(params.static / 6 / kp):.2f} deg, "
        "above its own 0.3 deg)."
        + (" The residual dead zone is at the measuring grid's floor (0.25 % of Tmax): the factor is a "
           "lower bound." if floor else "")
        + ("" if ok else " Here the factor is below 4.")), r.checks)


def claim_fig10_motion(r: Fig10Result, params=None) -> Claim:
    c0, c1 = r.without.displacement_counts(), r.with_nn.displacement_counts()
    thr = r.dead_zone_with.threshold_counts
    ok = c0 <= thr < c1
    return gate(Claim(
        id="fig10-motion", claim="A sinusoidal control torque of 10 % of Tmax, inside the dead zone, moves "
        f"the joint with compensation and not without (here: encoder motion > {thr} counts)",
        paper="moves with, still without",
        measured=f"{c0} counts without, {c1} counts with; peak |Tm| "
        f"{np.abs(r.with_nn.torque_motor).max():.3f} N*m for peak |Tc| "
        f"{np.abs(r.with_nn.torque_cmd).max():.3f} N*m", passed=ok, figure="Fig. 10", value=c1,
        unit="counts with",
        note="" if ok else "the compensated motor torque stays below the breakaway level"), r.checks)


FIGURE = PaperFigure(number=10, title="inside the dead zone: 10 % of Tmax, and the dead zones", run=run,
                     result_type=Fig10Result, claims=(claim_dead_zone, claim_fig10_motion))
