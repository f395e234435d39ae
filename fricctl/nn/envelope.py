"""Where a trained network knows the friction, and where it extrapolates.

A :class:`~fricctl.nn.FrictionNet` stores its *training envelope*: the box of the training
inputs ``(Tm, omega)`` (``envelope_low``, ``envelope_high``, in every saved network file).  Outside
it the net's output is whatever its ``tanh`` units extrapolate to: a net trained on a record that
barely moves has never seen sliding friction, and a fit of 97 % on its own patterns says nothing
about it.  Two checks say so:

* :func:`narrow_speed_warnings` (``fricctl train``): the envelope's speeds span only a few encoder
  counts per sample (:data:`NARROW_SPEED_COUNTS`), the velocity unit of the loop's backward
  difference;
* :func:`excursion` / :func:`excursion_warnings` (``fricctl simulate``): how far (the largest
  ``|omega|`` and ``|Tm|`` against the envelope's) and how long (seconds, share of the samples) a
  run drove the net outside its envelope.

Notes
-----
The envelope is a box: a point inside it may still lie far from every training pattern (e.g.
high torque at high speed when the patterns held high torque only at rest).  These checks see only
the box.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _validate as v
from ..units import units as units_of
from .net import FrictionNet

__all__ = ["NARROW_SPEED_COUNTS", "narrow_speed_warnings", "Excursion", "excursion",
           "excursion_warnings"]

#: Speeds of the training patterns, in encoder counts per sample, at or below which ``fricctl
#: train`` warns [-].  The loop's backward difference reads velocity in whole counts per sample,
#: so patterns within +-3 counts per sample hold at most seven of its readings: the slow end of
#: the friction curve (breakaway, Stribeck), not the sliding friction a tracking loop meets.
NARROW_SPEED_COUNTS = 3.0


def _edge(low: float, high: float) -> float:
    """The envelope's largest magnitude along one input."""
    return max(abs(float(low)), abs(float(high)))


def narrow_speed_warnings(net: FrictionNet, velocity_quantum: float | None) -> list[str]:
    """A warning when the net's training speeds span at most :data:`NARROW_SPEED_COUNTS` encoder
    counts per sample (none when they span more, or the quantum is unknown).

    Parameters
    ----------
    net : FrictionNet
        The trained net (its ``envelope_low``, ``envelope_high``).
    velocity_quantum : float or None
        One encoder count per sample, the patterns' ``velocity_quantum`` [rad/s]; None: unknown.

    Returns
    -------
    list of str

    Examples
    --------
    >>> net = FrictionNet(w1=[[0.0, 1.0]], b1=[0.0], w2=[1.0], b2=0.0, input_offset=[0, 0],
    ...                   input_scale=[1, 1], output_offset=0.0, output_scale=0.1,
    ...                   envelope_low=[-0.2, -0.05], envelope_high=[0.2, 0.05])
    >>> len(narrow_speed_warnings(net, 0.05)), len(narrow_speed_warnings(net, 0.01))
    (1, 0)
    """
    v.instance("net", net, FrictionNet)
    if velocity_quantum is None:
        return []
    quantum = v.real("velocity_quantum", velocity_quantum, positive=True)
    u = units_of(net.units)
    top = _edge(net.envelope_low[1], net.envelope_high[1])
    counts = top / quantum
    if counts > NARROW_SPEED_COUNTS:
        return []
    return [f"the patterns cover only a narrow band of speeds: |omega| <= {top:.4g} {u.velocity}, "
            f"{counts:.3g} encoder count(s) per sample (one count per sample = {quantum:.4g} "
            f"{u.velocity}; warned at <= {NARROW_SPEED_COUNTS:g}); the net has not seen the "
            f"friction at higher speeds and extrapolates there, whatever its fit on these "
            f"patterns (fricctl simulate warns where a run leaves the envelope)"]


@dataclass(frozen=True, kw_only=True)
class Excursion:
    """How far and how long a sequence of net inputs left the net's training envelope."""

    samples: int
    """Inputs outside the envelope [-]."""
    total: int
    """Inputs checked [-]."""
    duration: float
    """Time outside: ``samples * sample_time`` [s]."""
    tm_max: float
    """Largest ``|Tm|`` of the inputs [N*m]."""
    tm_edge: float
    """The envelope's largest ``|Tm|`` [N*m]."""
    omega_max: float
    """Largest ``|omega|`` of the inputs [rad/s]."""
    omega_edge: float
    """The envelope's largest ``|omega|`` [rad/s]."""

    @property
    def fraction(self) -> float:
        """Share of the inputs outside the envelope [-]."""
        return self.samples / self.total if self.total else 0.0


def excursion(net: FrictionNet, tm, omega, sample_time: float) -> Excursion:
    """The inputs ``(tm, omega)`` a run fed the net, against its training envelope.

    Parameters
    ----------
    net : FrictionNet
    tm, omega : array_like, shape (n,)
        The net's inputs per sample [N*m], [rad/s].
    sample_time : float
        Time per input [s].

    Returns
    -------
    Excursion

    Examples
    --------
    >>> net = FrictionNet(w1=[[0.0, 1.0]], b1=[0.0], w2=[1.0], b2=0.0, input_offset=[0, 0],
    ...                   input_scale=[1, 1], output_offset=0.0, output_scale=0.1,
    ...                   envelope_low=[-1, -0.5], envelope_high=[1, 0.5])
    >>> e = excursion(net, [0.0, 0.5, 0.2, 0.0], [0.0, 4.0, 0.4, -1.0], 0.002)
    >>> e.samples, round(e.duration, 6), e.omega_max / e.omega_edge
    (2, 0.004, 8.0)
    """
    v.instance("net", net, FrictionNet)
    tm = v.array("tm", tm, min_size=1)
    omega = v.array("omega", omega, shape=tm.shape)
    ts = v.real("sample_time", sample_time, positive=True, unit="s")
    n = int(np.count_nonzero(net.outside_envelope(tm, omega)))
    return Excursion(samples=n, total=int(tm.size), duration=n * ts,
                     tm_max=float(np.max(np.abs(tm))),
                     tm_edge=_edge(net.envelope_low[0], net.envelope_high[0]),
                     omega_max=float(np.max(np.abs(omega))),
                     omega_edge=_edge(net.envelope_low[1], net.envelope_high[1]))


def excursion_warnings(exc: Excursion, kind: str = "rotary", *, clipped: bool = False) -> list[str]:
    """One warning when :func:`excursion` found inputs outside the envelope (else none).

    ``kind`` names the units (:mod:`fricctl.units`); ``clipped``: the net's inputs were held to
    the envelope (``--clip``), so it did not extrapolate but held its edge values.
    """
    v.instance("exc", exc, Excursion)
    if exc.samples == 0:
        return []
    u = units_of(kind)

    def far(name, top, edge, unit):
        if top <= edge:
            return None
        times = f"{top / edge:.3g}x" if edge > 0 else "beyond"
        return f"|{name}| up to {top:.4g} {unit}, {times} the envelope's {edge:.4g} {unit}"

    torque = "Tm" if kind == "rotary" else "Fm"
    where = [w for w in (far("omega", exc.omega_max, exc.omega_edge, u.velocity),
                         far(torque, exc.tm_max, exc.tm_edge, u.torque)) if w]
    if not where:  # an asymmetric box: left on its narrower side, within its largest magnitudes
        where = [f"beyond the narrower side of the box (largest |omega| {exc.omega_max:.4g} "
                 f"{u.velocity}, |{torque}| {exc.tm_max:.4g} {u.torque})"]
    there = ("its inputs were clipped to the envelope (--clip), so it held its edge values there"
             if clipped else "there it extrapolates (--clip holds its inputs to the envelope)")
    return [f"the network ran outside its training envelope for {exc.duration:.3g} s "
            f"({100 * exc.fraction:.3g} % of the samples): {'; '.join(where)}; {there}"]
