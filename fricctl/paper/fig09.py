"""Fig. 9: open-loop sinusoidal torque near breakaway, without and with NN compensation."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import controllers as ctl
from ..compensators import NNCompensator, NoCompensation
from ..simulate import SimResult, simulate
from .claims import Claim
from .common import STICK_MIN_DURATION, stick_intervals_after_motion
from .network import PaperNetwork, check_network
from .registry import PaperFigure

__all__ = ["Fig9Result", "run", "claim_fig9", "FIGURE"]


@dataclass(frozen=True, eq=False, kw_only=True)
class Fig9Result:
    """Fig. 9: open-loop sinusoidal torque near breakaway, without and with NN compensation.

    Attributes
    ----------
    without, with_nn : the two runs
    amplitude : control torque amplitude [N*m]
    frequency : [Hz]
    sticks_without, sticks_with : rests >= STICK_MIN_DURATION after first motion, (start, end) [s]
    peak_speed_without, peak_speed_with : max |omega| [rad/s]
    """

    without: SimResult
    with_nn: SimResult
    amplitude: float
    frequency: float
    sticks_without: list
    sticks_with: list
    peak_speed_without: float
    peak_speed_with: float


def run(network: PaperNetwork, *, amplitude_factor: float = 1.1, frequency: float = 0.5,
        duration: float = 4.0) -> Fig9Result:
    """Open-loop sinusoid of ``amplitude_factor * Fs`` without and with compensation (Fig. 9)."""
    net = check_network(network)
    p = net.params
    amp = amplitude_factor * p.static
    c = ctl.open_loop(ctl.sinusoid(amp, frequency))
    r0 = simulate(p, c, NoCompensation(), duration=duration)
    r1 = simulate(p, c, NNCompensator(net.net), duration=duration)
    return Fig9Result(without=r0, with_nn=r1, amplitude=amp, frequency=frequency,
                      sticks_without=stick_intervals_after_motion(r0),
                      sticks_with=stick_intervals_after_motion(r1),
                      peak_speed_without=float(np.abs(r0.omega).max()),
                      peak_speed_with=float(np.abs(r1.omega).max()))


def claim_fig9(r: Fig9Result, params=None) -> Claim:
    n0, n1 = len(r.sticks_without), len(r.sticks_with)
    ok = n0 >= 1 and n1 == 0
    return Claim(
        id="fig9-stick", claim=f"Open-loop sinusoidal torque near the static friction: stick intervals "
        f"without compensation, none with (here: rests >= {1e3 * STICK_MIN_DURATION:.0f} ms after the "
        f"first motion, amplitude {r.amplitude:.3f} N*m = 1.1*Fs, {r.frequency:g} Hz)",
        paper="sticks without, none with",
        measured=f"{n0} stick intervals without, {n1} with; peak speed {r.peak_speed_without:.2f} rad/s "
        f"without, {r.peak_speed_with:.1f} rad/s with", passed=ok, figure="Fig. 9",
        note=("with compensation the net's gain at rest g > 1 makes the open loop wind the torque up: the "
              "joint no longer sticks but runs far faster than without (see peak speeds)"
              if ok and r.peak_speed_with > 5 * r.peak_speed_without else
              "" if ok else "the compensated joint still stops at some velocity reversals for longer than "
              f"{1e3 * STICK_MIN_DURATION:.0f} ms"))


FIGURE = PaperFigure(
    number=9, title="open-loop sinusoid near breakaway: stick intervals without and with compensation",
    run=run, result_type=Fig9Result, claims=(claim_fig9,),
    assumptions=("sinusoidal torque of 1.1 x the breakaway level Fs, 0.5 Hz, 4 s",))
