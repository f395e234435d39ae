"""Fig. 9: open-loop sinusoidal torque near breakaway, without and with NN compensation.

Two extras (not in the paper): the compensated joint against the linear viscous
actuator the compensation is meant to produce (``fig9-linear``), and the coast test
of the same network (``coast-decay``, :mod:`fricctl.paper.coast`), which every claim
with compensation requires.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import controllers as ctl
from ..compensators import NoCompensation
from ..friction import Viscous
from ..simulate import SimResult, simulate
from . import coast as coast_test
from .claims import EXTRA, Claim, gate
from .common import STICK_MIN_DURATION, OpenLoopChecks, sensed, stick_intervals_after_motion
from .network import PaperNetwork, check_network
from .registry import PaperFigure
from .runaway import LINEAR_TOLERANCE, reversal, wind_up

__all__ = ["Fig9Result", "run", "claim_fig9", "claim_fig9_linear", "claim_coast", "FIGURE"]


@dataclass(frozen=True, eq=False, kw_only=True)
class Fig9Result(OpenLoopChecks):
    """Fig. 9: open-loop sinusoidal torque near breakaway, without and with NN compensation.

    Attributes
    ----------
    without, with_nn : the two runs
    linear : the linear viscous actuator (the bench with its viscous friction only) under
        the same control torque (extra)
    amplitude : control torque amplitude [N*m]
    frequency : [Hz]
    sticks_without, sticks_with : rests >= STICK_MIN_DURATION after first motion, (start, end) [s]
    peak_speed_without, peak_speed_with, peak_speed_linear : max |omega| [rad/s]
    wind_up, reversal : runaway checks of ``with_nn``
    coast : the network's coast test (extra)
    """

    without: SimResult
    with_nn: SimResult
    linear: SimResult
    amplitude: float
    frequency: float
    sticks_without: list
    sticks_with: list
    peak_speed_without: float
    peak_speed_with: float
    peak_speed_linear: float


def run(network: PaperNetwork, *, amplitude_factor: float = 1.1, frequency: float = 0.5,
        duration: float = 4.0) -> Fig9Result:
    """Open-loop sinusoid of ``amplitude_factor * Fs`` without and with compensation (Fig. 9)."""
    net = check_network(network)
    p = net.params
    amp = amplitude_factor * p.static
    c = ctl.open_loop(ctl.sinusoid(amp, frequency))
    r0 = simulate(p, c, NoCompensation(), duration=duration, **sensed(net, "fig9 none", p))
    r1 = simulate(p, c, net.compensator(), duration=duration, **sensed(net, "fig9 NN", p))
    lin = simulate(p, c, NoCompensation(), duration=duration, friction=Viscous(p.viscous))
    return Fig9Result(without=r0, with_nn=r1, linear=lin, amplitude=amp, frequency=frequency,
                      sticks_without=stick_intervals_after_motion(r0),
                      sticks_with=stick_intervals_after_motion(r1),
                      peak_speed_without=float(np.abs(r0.omega).max()),
                      peak_speed_with=float(np.abs(r1.omega).max()),
                      peak_speed_linear=float(np.abs(lin.omega).max()),
                      wind_up=wind_up(r1), reversal=reversal(r1, 1.0 / frequency), coast=coast_test.run(net))


def claim_fig9(r: Fig9Result, params=None) -> Claim:
    n0, n1 = len(r.sticks_without), len(r.sticks_with)
    ok = n0 >= 1 and n1 == 0
    return gate(Claim(
        id="fig9-stick", claim=f"Open-loop sinusoidal torque near the static friction: stick intervals "
        f"without compensation, none with (here: rests >= {1e3 * STICK_MIN_DURATION:.0f} ms after the "
        f"first motion, amplitude {r.amplitude:.3f} N*m = 1.1*Fs, {r.frequency:g} Hz)",
        paper="sticks without, none with",
        measured=f"{n0} stick intervals without, {n1} with; peak speed {r.peak_speed_without:.2f} rad/s "
        f"without, {r.peak_speed_with:.1f} rad/s with", passed=ok, figure="Fig. 9", value=n1,
        unit="stick intervals with",
        note="" if ok else "no stick interval without compensation" if n0 == 0 else
        f"the compensated joint still stops at some velocity reversals for longer than "
        f"{1e3 * STICK_MIN_DURATION:.0f} ms"), r.checks)


def claim_fig9_linear(r: Fig9Result, params=None) -> Claim:
    dev = abs(r.peak_speed_with - r.peak_speed_linear) / r.peak_speed_linear
    ok = dev <= LINEAR_TOLERANCE
    return gate(Claim(
        id="fig9-linear", claim="(Extra, not in the paper.) With compensation the joint moves like the "
        "linear viscous actuator I*dw/dt = Tc - b*w the compensation is meant to produce (here: peak "
        f"speed within {100 * LINEAR_TOLERANCE:.0f} % of that actuator's under the same Tc)", paper=EXTRA,
        measured=f"peak speed {r.peak_speed_with:.2f} rad/s with compensation, {r.peak_speed_linear:.2f} "
        f"rad/s linear viscous ({100 * dev:.1f} % apart)", passed=ok, figure="Fig. 9", value=100 * dev,
        unit="%",
        note="" if ok else ("the compensated joint runs faster than the linear viscous actuator: the "
                            "compensation removes more than the friction the linear model leaves out"
                            if r.peak_speed_with > r.peak_speed_linear else
                            "the compensated joint runs slower than the linear viscous actuator: part "
                            "of the nonlinear friction is left uncompensated")), r.checks)


def claim_coast(r: Fig9Result, params=None) -> Claim:
    c = r.coast
    return gate(Claim(
        id="coast-decay", claim="(Extra, not in the paper.) After an open-loop pulse of "
        f"{c.pulse_torque:.2f} N*m for {c.pulse_duration:g} s, with Tc = 0, the compensated joint coasts "
        "down at least like the linear viscous actuator (here: |w(t)| <= |w_end|*exp(-(b/I)*t) + "
        f"{100 * LINEAR_TOLERANCE:.0f} % of |w_end| at every sample)", paper=EXTRA,
        measured=f"|w_end| {abs(c.omega_end):.2f} rad/s; largest excess over the viscous decay "
        f"{c.decay.value:.1f} % of |w_end|", passed=c.decay.passed, figure="Fig. 9", value=c.decay.value,
        unit="%", note="" if c.decay.passed else "the compensation keeps the joint going: it cancels "
        "more than the friction the linear viscous model leaves out"), (c.wind_up, c.decay))


FIGURE = PaperFigure(
    number=9, title="open-loop sinusoid near breakaway: stick intervals without and with compensation",
    run=run, result_type=Fig9Result, claims=(claim_fig9, claim_fig9_linear, claim_coast),
    assumptions=("sinusoidal torque of 1.1 x the breakaway level Fs, 0.5 Hz, 4 s",))
