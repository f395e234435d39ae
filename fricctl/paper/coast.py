"""The coast test: a torque pulse, then ``Tc = 0``, with the pipeline's compensation.

Not a figure of the paper: a check of ours that every claim with compensation
requires (:mod:`fricctl.paper.runaway`).  The compensation is meant to turn the
actuator into a linear viscous one, ``I*dw/dt = Tc - b*w``; after the pulse that
actuator coasts down as ``exp(-(b/I)*t)``.  A compensation that over-estimates
friction (a gain at rest above one, or the viscous term cancelled) keeps the joint
going or speeds it up by itself.

Why a module of its own and not a ``figNN`` entry of the figure registry: the
registry is the paper's figures (numbered, each with its plot and its claims); the
coast test is one experiment per *network* that several figures' claims need.  Each
compensated figure's ``run`` stores ``coast.run(network)`` in its result, so a
result alone says whether its claims pass; :func:`run` is memoised per network object
(a weak reference: the cache never keeps a network alive), so the experiment runs
once per network however many figures ask.  Its own claim, ``coast-decay``, lives
with Fig. 9 (both are open-loop torque experiments).
"""

from __future__ import annotations

import threading
import weakref
from dataclasses import dataclass

import numpy as np

from .. import _validate as v
from .. import controllers as ctl
from ..compensators import NoCompensation
from ..friction import Viscous
from ..simulate import SimResult, simulate
from .network import PaperNetwork, check_network
from .runaway import RunawayCheck, coast_decay, wind_up

__all__ = ["CoastResult", "run", "PULSE_FACTOR", "PULSE_DURATION", "COAST_DURATION"]

#: Pulse torque as a multiple of the breakaway level Fs [-].
PULSE_FACTOR = 2.0
#: Pulse length [s] (about two time constants I/b of the actuator, 0.17 s).
PULSE_DURATION = 0.3
#: Time with ``Tc = 0`` after the pulse [s] (about 12 time constants).
COAST_DURATION = 2.0


@dataclass(frozen=True, eq=False, kw_only=True)
class CoastResult:
    """A torque pulse then ``Tc = 0``, with the pipeline's compensation.

    Attributes
    ----------
    run : the compensated run
    linear : the linear viscous actuator (the bench with viscous friction only, no
        compensation) under the same control torque
    pulse_torque : [N*m]
    pulse_duration : [s]
    t_end : first instant without pulse torque at the joint (the pulse's last command
        acts one sample late) [s]
    omega_end : velocity at ``t_end`` [rad/s]
    decay : the coast check (:func:`fricctl.paper.runaway.coast_decay`)
    wind_up : the wind-up check of the same run
    """

    run: SimResult
    linear: SimResult
    pulse_torque: float
    pulse_duration: float
    t_end: float
    omega_end: float
    decay: RunawayCheck
    wind_up: RunawayCheck

    @property
    def passed(self) -> bool:
        """The coast check passes."""
        return self.decay.passed


_CACHE: "weakref.WeakKeyDictionary[PaperNetwork, CoastResult]" = weakref.WeakKeyDictionary()
_LOCK = threading.Lock()


def run(network: PaperNetwork, *, pulse_factor: float = PULSE_FACTOR,
        pulse_duration: float = PULSE_DURATION, coast_duration: float = COAST_DURATION) -> CoastResult:
    """Open-loop pulse of ``pulse_factor*Fs`` for ``pulse_duration``, then ``Tc = 0``.

    With the default arguments the result is memoised per network object.

    Parameters
    ----------
    network : PaperNetwork
    pulse_factor : float
        Pulse torque over the breakaway level Fs [-].
    pulse_duration, coast_duration : float
        [s].

    Returns
    -------
    CoastResult

    Notes
    -----
    Rigid joint without the link, nominal friction; the pulse starts from rest.
    """
    net = check_network(network)
    pulse_factor = v.real("pulse_factor", pulse_factor, positive=True)
    pulse_duration = v.real("pulse_duration", pulse_duration, positive=True, unit="s")
    coast_duration = v.real("coast_duration", coast_duration, positive=True, unit="s")
    default = (pulse_factor, pulse_duration, coast_duration) == (PULSE_FACTOR, PULSE_DURATION,
                                                                 COAST_DURATION)
    if default:
        with _LOCK:
            hit = _CACHE.get(net)
        if hit is not None:
            return hit
    res = _experiment(net, pulse_factor, pulse_duration, coast_duration)
    if default:
        with _LOCK:
            _CACHE[net] = res
    return res


def _experiment(net: PaperNetwork, pulse_factor, pulse_duration, coast_duration) -> CoastResult:
    p = net.params
    amp = pulse_factor * p.static
    c = ctl.open_loop(ctl.sequence([amp, 0.0], [pulse_duration, coast_duration]))
    duration = pulse_duration + coast_duration
    from .common import sensed  # common imports this module

    r = simulate(p, c, net.compensator(), duration=duration, **sensed(net, "coast NN", p))
    lin = simulate(p, c, NoCompensation(), duration=duration, friction=Viscous(p.viscous))
    # Tc(k) reaches the joint as Tm(k+1): the pulse acts until one sample after its last command
    off = np.flatnonzero((r.t > 0) & (r.torque_cmd == 0.0))
    if off.size == 0 or off[0] + 1 >= r.t.size:
        raise ValueError("the run ends before the pulse does")
    k_end = int(off[0]) + 1
    t_end = float(r.t[k_end])
    return CoastResult(run=r, linear=lin, pulse_torque=float(amp), pulse_duration=float(pulse_duration),
                       t_end=t_end, omega_end=float(r.omega[k_end]), decay=coast_decay(r, t_end),
                       wind_up=wind_up(r))
