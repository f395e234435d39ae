"""Fig. 18: sawtooth tracking with the link, without and with NN compensation, plus a stick-slip extra."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _validate as v
from .. import controllers as ctl
from ..compensators import NoCompensation
from ..design import Design
from ..simulate import SimResult, simulate
from . import coast as coast_test
from .claims import EXTRA, Claim, gate
from .common import (FIG18_PERIODS, STICK_MIN_DURATION, designs, linear_prediction, periods_with_motion,
                     restarts, sensed)
from .network import PaperNetwork, check_network
from .registry import PaperFigure
from .runaway import RunawayCheck, wind_up

__all__ = ["Fig18Result", "run", "claim_fig18_without", "claim_fig18_with", "claim_fig18_extra",
           "FIGURE"]


@dataclass(frozen=True, eq=False, kw_only=True)
class Fig18Result:
    """Fig. 18: sawtooth of 0.1 rad, PD (0.22 s, 0.5) with the link, without and with NN.

    Attributes
    ----------
    without, with_nn : the runs
    linear : linear viscous prediction [rad]
    design : the PD design with the link
    amplitude, period : sawtooth [rad], [s]
    periods : periods run [-]
    restarts_without : stick-slip cycles without compensation [-]
    moving_periods_without : periods in which the joint moves without compensation [-]
    max_motion_without : peak |q| without compensation [rad]
    rms_deviation_with : RMS of q - q_linear with compensation [rad]
    extra_without : a larger, slower sawtooth (extra, not in the paper) without compensation
    extra_amplitude, extra_period : [rad], [s]
    extra_restarts : its stick-slip cycles [-]
    wind_up : runaway check of ``with_nn``
    coast : the network's coast test
    slow_friction, slow_estimate : mean true friction and mean compensation (signed along the
        friction) over the samples of ``with_nn`` that slide no faster than twice the ramp's
        speed [N*m]: how much of the friction the compensation cancels where the joint may
        stick again
    """

    without: SimResult
    with_nn: SimResult
    linear: np.ndarray
    design: Design
    amplitude: float
    period: float
    periods: int
    restarts_without: int
    moving_periods_without: int
    max_motion_without: float
    rms_deviation_with: float
    extra_without: SimResult
    extra_amplitude: float
    extra_period: float
    extra_restarts: int
    wind_up: RunawayCheck
    coast: coast_test.CoastResult
    slow_friction: float
    slow_estimate: float

    @property
    def slow_share(self) -> float:
        """The share of the friction the compensation cancels while sliding slowly [-] (nan if
        the compensated joint never slid that slowly)."""
        return self.slow_estimate / self.slow_friction if self.slow_friction > 0 else float("nan")


def _slow_sliding(run: SimResult, speed: float) -> tuple[float, float]:
    """Mean |Tat| and mean T^at*sign(Tat) over sliding samples with 0 < |omega| <= 2*speed."""
    sel = ~run.stuck & (np.abs(run.omega) > 0) & (np.abs(run.omega) <= 2 * speed)
    if not sel.any():
        return 0.0, 0.0
    return (float(np.mean(np.abs(run.friction[sel]))),
            float(np.mean(run.friction_est[sel] * np.sign(run.friction[sel]))))


def run(network: PaperNetwork, *, amplitude: float | None = None, period: float | None = None,
        periods: int = FIG18_PERIODS, extra_amplitude: float = 0.5, extra_period: float = 8.0) -> Fig18Result:
    """Sawtooth tracking without and with NN compensation (Fig. 18), plus a stick-slip extra.

    ``amplitude`` [rad] and ``period`` [s] default to the bench's (``fig18_amplitude``,
    ``fig18_period``: the paper's "sawtooth of 0.1 rad" is a reading, its period unknown);
    ``periods`` to :data:`~fricctl.paper.common.FIG18_PERIODS` (the figure's two and one more).
    """
    periods = v.integer("periods", periods, low=1)
    net = check_network(network)
    amplitude = net.bench.fig18_amplitude if amplitude is None else amplitude
    period = net.bench.fig18_period if period is None else period
    p = net.bench.linked_actuator
    d = designs(net.bench)["fig18"]
    c = ctl.pd_control(d.kp, d.kd, ctl.sawtooth(amplitude, period))
    r0 = simulate(p, c, NoCompensation(), duration=periods * period,
                  **sensed(net, "fig18 none", p))
    r1 = simulate(p, c, net.compensator(), duration=periods * period,
                  **sensed(net, "fig18 NN", p))
    lin = linear_prediction(d, r1, ("sawtooth", float(amplitude), float(period)))
    ce = ctl.pd_control(d.kp, d.kd, ctl.sawtooth(extra_amplitude, extra_period))
    rx = simulate(p, ce, NoCompensation(), duration=extra_period, **sensed(net, "fig18 extra", p))
    slow_friction, slow_estimate = _slow_sliding(r1, amplitude / period)
    return Fig18Result(without=r0, with_nn=r1, linear=lin, design=d, amplitude=float(amplitude),
                       period=float(period), periods=periods, restarts_without=restarts(r0),
                       moving_periods_without=periods_with_motion(r0, float(period), periods),
                       max_motion_without=float(np.abs(r0.q).max()),
                       rms_deviation_with=float(np.sqrt(np.mean((r1.q - lin) ** 2))), extra_without=rx,
                       extra_amplitude=float(extra_amplitude), extra_period=float(extra_period),
                       extra_restarts=restarts(rx), wind_up=wind_up(r1), coast=coast_test.run(net),
                       slow_friction=slow_friction, slow_estimate=slow_estimate)


def claim_fig18_without(r: Fig18Result, params=None) -> Claim:
    ok = r.restarts_without >= 2 and r.moving_periods_without == r.periods
    return Claim(
        id="fig18-without", claim=f"Sawtooth of {r.amplitude:g} rad without compensation: stick-slip (here: "
        f"over {r.periods} periods, >= 2 rests of >= {1e3 * STICK_MIN_DURATION:.0f} ms followed by motion, "
        f"and motion in every period; period {r.period:g} s assumed)", paper="stick-slip",
        measured=f"{r.restarts_without} stick-slip cycles, motion in {r.moving_periods_without} of "
        f"{r.periods} periods, peak |q| {r.max_motion_without:.2e} rad",
        passed=ok, figure="Fig. 18", value=r.restarts_without, unit="cycles",
        note="" if ok else _why_no_stick_slip(r))


def _why_no_stick_slip(r: Fig18Result) -> str:
    """The measured reason the uncompensated sawtooth shows no stick-slip."""
    if r.max_motion_without <= r.without.info.encoder_resolution:
        return (f"With the Fig.-18 gain Kp = {r.design.kp:.3f} N*m/rad the whole sawtooth asks for at most "
                f"Kp*{r.amplitude:g} rad = {r.design.kp * r.amplitude:.3f} N*m, below the breakaway level: "
                "the joint never moves at all. Stick-slip does appear for a larger, slower ramp "
                f"({r.extra_amplitude:g} rad over {r.extra_period:g} s: {r.extra_restarts} cycles; see "
                "fig18-extra).")
    if r.restarts_without < 2:
        return (f"The joint moves, but only {r.restarts_without} rest(s) of >= "
                f"{1e3 * STICK_MIN_DURATION:.0f} ms end in motion: it slides through the ramps.")
    return (f"The joint stick-slips, then parks: motion in {r.moving_periods_without} of {r.periods} "
            "periods only.")


def claim_fig18_with(r: Fig18Result, params=None) -> Claim:
    tol = 0.1 * r.amplitude
    ok = r.rms_deviation_with <= tol
    return gate(Claim(
        id="fig18-with", claim="Sawtooth with NN compensation: the joint tracks the reference (here: RMS of "
        f"q - q_linear <= 10 % of the amplitude = {tol:.3f} rad)", paper="tracks",
        measured=f"RMS deviation from the linear viscous loop {r.rms_deviation_with:.4f} rad; "
        f"{restarts(r.with_nn)} stick-slip cycles", passed=ok, figure="Fig. 18",
        value=100 * r.rms_deviation_with / r.amplitude, unit="% of the amplitude",
        note="" if ok else _why_not_tracking(r)), (r.wind_up, r.coast.decay))


def _why_not_tracking(r: Fig18Result) -> str:
    """The measured reason a compensated sawtooth is not tracked: slow sliding under-compensated."""
    cycles = restarts(r.with_nn)
    speed = r.amplitude / r.period
    if not r.slow_friction > 0:
        return f"The compensated joint never slid at or below twice the ramp's speed {speed:g} rad/s."
    short = r.slow_friction - r.slow_estimate
    return (f"The compensated joint moves, but itself in stick-slip ({cycles} cycles, a staircase): "
            f"while sliding at up to twice the ramp's speed ({2 * speed:g} rad/s) the compensation "
            f"cancels {100 * r.slow_share:.0f} % of the friction ({r.slow_estimate:.3f} of "
            f"{r.slow_friction:.3f} N*m, mean), so the joint slows and sticks, and waits until "
            f"Kp*e has grown by about the {short:.3f} N*m left uncompensated "
            f"({np.rad2deg(short / r.design.kp):.2f} deg at Kp = {r.design.kp:.3f} N*m/rad).")


def claim_fig18_extra(r: Fig18Result, params=None) -> Claim:
    ok = r.extra_restarts >= 2
    return Claim(
        id="fig18-extra", claim="(Extra, not in the paper.) A larger, slower sawtooth "
        f"({r.extra_amplitude:g} rad over {r.extra_period:g} s) without compensation shows stick-slip "
        "(>= 2 cycles)",
        paper=EXTRA, measured=f"{r.extra_restarts} stick-slip cycles", passed=ok, figure="Fig. 18",
        value=r.extra_restarts, unit="cycles",
        note="" if ok else "the joint creeps without sticking at this ramp rate")


FIGURE = PaperFigure(
    number=18, title="sawtooth tracking with the link", run=run, result_type=Fig18Result,
    claims=(claim_fig18_without, claim_fig18_with, claim_fig18_extra),
    assumptions=("the sawtooth's span and period are the bench's (fig18_amplitude, fig18_period; "
                 "literal: 0 to 0.1 rad over 1 s), three periods (the figure's two and one more)",))
