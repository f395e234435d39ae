r"""The limit cycle of Coulomb compensation, predicted by a describing function.

The paper (Section 6) compensates Coulomb friction with ``Fcomp*sign(omega_hat)`` and reports
that at the dry friction identified experimentally the position loop oscillates, and that the
oscillation disappears at a smaller level.  A describing function tells why and predicts the
cycle: while the joint slides, the compensation and the friction it cancels add up to a relay
on the velocity,

.. math::  u = F_{comp}\,\mathrm{sign}(\hat\omega) - F_c\,\mathrm{sign}(\omega)
           \approx -(F_c - F_{comp})\,\mathrm{sign}(\hat\omega),

of height ``c = Fc - Fcomp`` in the feedback of the linear loop ``H(z)``: the sampled PD loop
of :class:`~fricctl.design.loops.LinearLoop` from a torque added to the controller's output
(held one sample later, like the compensation) to the velocity estimate ``omega_hat`` (the
backward difference the compensator reads).  A relay of height ``c`` driven by a sinusoid of
amplitude ``A`` has the describing function ``N(A) = 4c/(pi A)``; a limit cycle sits where
``H(e^{jwTs}) N(A) = -1`` (``H`` evaluated by python-control).
Over-compensation (``c < 0``) puts ``-1/N`` on the positive real axis, which the PD loop's
``H`` crosses near ``sqrt(Kp/I)``: a cycle of velocity amplitude ``A = 4|c| H/pi``, the
damping ``b + Kd`` against the relay's push.  Under-compensation (``c > 0``) leaves friction:
no cycle on this crossing.

Assumptions, stated where they matter: friction acts on the true velocity, the relay is taken
on ``omega_hat`` (half a sample later: a phase of ``w*Ts/2``, 0.02 rad at 3 Hz and 500 Hz);
the position is a sinusoid (the relay's odd harmonics filtered by the loop); the joint does
not stick at the turning points -- the compensation is 0 there (``omega_hat = 0``) and static
friction Fs holds the joint unless the loop's pull ``Kp*A_q`` exceeds it, so a cycle whose
predicted position amplitude leaves ``Kp*A_q < Fs`` dies at its first turning point
(:attr:`LimitCycle.sustained`).  Encoder quantisation is left out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import control
import numpy as np
from scipy import optimize

from .. import _validate as v
from .loops import LinearLoop

__all__ = ["Relay", "LimitCycle", "compensation_loop", "coulomb_limit_cycle"]


class Relay(control.DescribingFunctionNonlinearity):
    """``F(x) = c*sign(x)``; describing function ``4c/(pi*A)`` (c < 0: a relay that pushes)."""

    def __init__(self, height: float):
        super().__init__()
        self.height = v.real("height", height)

    def __call__(self, x):
        return self.height * np.sign(x)

    def describing_function(self, amplitude):
        if amplitude < 0:
            raise ValueError(f"amplitude must be >= 0, got {amplitude!r}")
        return 4.0 * self.height / (math.pi * amplitude) if amplitude > 0 else np.inf


@dataclass(frozen=True, kw_only=True)
class LimitCycle:
    """The describing function's prediction of a Coulomb-compensation limit cycle."""

    relay: float
    """Net relay height ``c = Fc - Fcomp`` [N*m] (negative: over-compensation)."""
    velocity_amplitude: float
    """Amplitude of ``omega_hat`` [rad/s]."""
    frequency: float
    """Frequency of the cycle [Hz]."""
    amplitude: float
    """Position amplitude ``A_q = A / w`` [rad]."""
    pull: float
    """The loop's pull at a turning point, ``Kp*A_q`` [N*m]."""
    static: float
    """The breakaway level the pull must exceed [N*m]."""

    @property
    def sustained(self) -> bool:
        """True when the joint does not stick at the turning points (``Kp*A_q > Fs``)."""
        return self.pull > self.static


def compensation_loop(loop: LinearLoop) -> control.StateSpace:
    """``H(z)``: the sampled PD loop from a torque ``u_k`` added to the controller's output at
    ``t_k`` (held over ``[t_{k+1}, t_{k+2})``, as the compensation is) to ``omega_hat_k``.

    State ``(q, omega, Tm, y_prev)`` of :meth:`LinearLoop.sampled`; reference 0.
    """
    v.instance("loop", loop, LinearLoop)
    closed = loop.sampled()
    ts = loop.sample_time
    b = np.array([[0.0], [0.0], [1.0], [0.0]])
    c = np.array([[1.0 / ts, 0.0, 0.0, -1.0 / ts]])
    return control.ss(closed.A, b, c, np.zeros((1, 1)), ts)


def coulomb_limit_cycle(loop: LinearLoop, *, compensation: float, coulomb: float,
                        static: float | None = None) -> LimitCycle | None:
    """The limit cycle a Coulomb compensation at ``compensation`` predicts on ``loop``.

    Parameters
    ----------
    loop : LinearLoop
        The PD (or P) loop on the linear viscous plant, sampled.
    compensation : float
        The compensated level Fcomp [N*m].
    coulomb : float
        The true Coulomb level Fc [N*m].
    static : float, optional
        The breakaway level Fs (default: ``coulomb``) [N*m].

    Returns
    -------
    LimitCycle or None
        None when the describing function predicts no cycle (under-compensation, or no
        crossing).

    Examples
    --------
    >>> loop = LinearLoop(kp=2.0, kd=0.05, inertia=2.865e-3, viscous=0.0169, sample_time=0.002)
    >>> cyc = coulomb_limit_cycle(loop, compensation=0.18, coulomb=0.144, static=0.18)
    >>> round(cyc.frequency, 2), cyc.sustained
    (4.17, False)
    >>> coulomb_limit_cycle(loop, compensation=0.1, coulomb=0.144) is None
    True
    """
    v.instance("loop", loop, LinearLoop)
    fcomp = v.real("compensation", compensation, nonneg=True)
    fc = v.real("coulomb", coulomb, nonneg=True)
    fs = fc if static is None else v.real("static", static, nonneg=True)
    c = fc - fcomp
    if not c < 0:
        return None
    h = compensation_loop(loop)
    ts = loop.sample_time

    def imag(w):
        return complex(control.evalfr(h, complex(np.exp(1j * w * ts)))).imag

    # -1/N(A) = pi*A/(4|c|) runs along the positive real axis: the cycle is where H crosses it
    # (Im H = 0, Re H > 0), found on a fine grid and refined (python-control's intersection
    # search also returns the curve's start at the origin, A -> 0, for this relay)
    grid = np.geomspace(1e-2 * loop.wn, 0.999 * math.pi / ts, 4000)
    resp = control.frequency_response(h, grid).complex.ravel()
    k = np.flatnonzero((np.sign(resp.imag[:-1]) != np.sign(resp.imag[1:])) & (resp.real[:-1] > 0))
    if k.size == 0:
        return None
    crossings = [optimize.brentq(imag, grid[i], grid[i + 1], xtol=1e-12) for i in k]
    w = min(crossings, key=lambda x: abs(math.log(x / loop.wn)))  # the loop's own mode
    gain = complex(control.evalfr(h, complex(np.exp(1j * w * ts)))).real
    a = 4.0 * abs(c) * gain / math.pi
    aq = a / w
    return LimitCycle(relay=c, velocity_amplitude=float(a), frequency=float(w / (2 * math.pi)),
                      amplitude=float(aq), pull=float(loop.kp * aq), static=fs)
