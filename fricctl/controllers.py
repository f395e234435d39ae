"""Controllers and references of the sampled loop.

Every controller is ``Tc(k) = feedforward(t_k) + Kp*(r(t_k) - y_k) - Kd*omega_hat_k``:

* :func:`open_loop` -- a torque profile alone (Kp = Kd = 0), the paper's
  open-loop experiments (Figs. 5, 9, 10);
* :func:`p_control` -- ``Kp*(r - y)`` (Figs. 11-12);
* :func:`pd_control` -- ``Kp*(r - y) - Kd*omega_hat``: the derivative acts on the
  measured velocity (rate feedback), so the designed closed loop has no zero.

``y_k`` is the encoder reading and ``omega_hat_k`` its backward difference
(see :mod:`fricctl.simulate` for the timing).  References and torque profiles are
callables of time (vectorised), built with :func:`step`, :func:`sawtooth`,
:func:`sinusoid`, :func:`ramp_sinusoid`, :func:`sequence` or :func:`from_array`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from . import _validate as v

__all__ = [
    "Controller", "open_loop", "p_control", "pd_control",
    "Signal", "constant", "step", "sawtooth", "sinusoid", "ramp_sinusoid", "sequence", "from_array",
]


@dataclass(frozen=True, kw_only=True)
class Signal:
    """A time signal: ``signal(t)`` evaluates it on an array of times [s].

    ``description`` says what it is, for reports and figure titles.
    """

    func: Callable[[np.ndarray], np.ndarray]
    description: str
    frequency: float | None = None
    """Highest frequency of a periodic signal [Hz] (a sawtooth's: its fundamental); None for
    one that is not periodic.  The simulation warns when it is at or above the Nyquist
    frequency of the sample time (:func:`fricctl.simulate.sampling_warnings`)."""

    def __post_init__(self):
        if self.frequency is not None:
            object.__setattr__(self, "frequency",
                               v.real("frequency", self.frequency, positive=True, unit="Hz"))

    def __call__(self, t):
        t = v.array("t", t, ndim=None)
        out = np.broadcast_to(np.asarray(self.func(t), dtype=float), t.shape).copy()
        if not np.all(np.isfinite(out)):
            raise ValueError(f"signal {self.description!r} produced NaN or inf")
        return out

    def __add__(self, other: "Signal") -> "Signal":
        if not isinstance(other, Signal):
            return NotImplemented
        freqs = [f for f in (self.frequency, other.frequency) if f is not None]
        return Signal(func=lambda t: self.func(t) + other.func(t),
                      description=f"{self.description} + {other.description}",
                      frequency=max(freqs) if freqs else None)

    def __repr__(self):
        return f"Signal({self.description})"


def constant(value: float) -> Signal:
    """Constant signal."""
    c = v.real("value", value)
    return Signal(func=lambda t: np.full_like(t, c), description=f"constant {c:g}")


def step(amplitude: float, t0: float = 0.0) -> Signal:
    """Step of ``amplitude`` at ``t0`` [s] (value ``amplitude`` for t >= t0)."""
    a = v.real("amplitude", amplitude)
    t0 = v.real("t0", t0)
    return Signal(func=lambda t: np.where(t >= t0, a, 0.0), description=f"step {a:g} at {t0:g} s")


def sawtooth(amplitude: float, period: float) -> Signal:
    """Rising ramp from 0 to ``amplitude`` over each ``period`` [s], then reset."""
    a = v.real("amplitude", amplitude)
    p = v.real("period", period, positive=True, unit="s")
    return Signal(func=lambda t: a * np.mod(t, p) / p, description=f"sawtooth {a:g}, period {p:g} s",
                  frequency=1.0 / p)


def sinusoid(amplitude: float, frequency: float, phase: float = 0.0, offset: float = 0.0) -> Signal:
    """``offset + amplitude*sin(2*pi*frequency*t + phase)``; frequency [Hz]."""
    a = v.real("amplitude", amplitude)
    f = v.real("frequency", frequency, positive=True, unit="Hz")
    ph = v.real("phase", phase)
    off = v.real("offset", offset)
    return Signal(func=lambda t: off + a * np.sin(2 * np.pi * f * t + ph),
                  description=f"sinusoid {a:g} at {f:g} Hz", frequency=f)


def ramp_sinusoid(amplitude_start: float, amplitude_end: float, frequency: float,
                  duration: float) -> Signal:
    """Sinusoid whose amplitude grows linearly from start to end over ``duration`` [s]."""
    a0 = v.real("amplitude_start", amplitude_start)
    a1 = v.real("amplitude_end", amplitude_end)
    f = v.real("frequency", frequency, positive=True, unit="Hz")
    d = v.real("duration", duration, positive=True, unit="s")
    return Signal(func=lambda t: (a0 + (a1 - a0) * np.clip(t / d, 0, 1)) * np.sin(2 * np.pi * f * t),
                  description=f"sinusoid {a0:g}->{a1:g} at {f:g} Hz", frequency=f)


def sequence(levels, durations) -> Signal:
    """Piecewise-constant sequence: ``levels[i]`` for ``durations[i]`` seconds each.

    After the last interval the signal holds the last level.
    """
    lv = v.array("levels", levels, min_size=1)
    du = v.array("durations", durations, size=lv.size)
    if np.any(du <= 0):
        raise ValueError("durations must be > 0 s")
    edges = np.concatenate([[0.0], np.cumsum(du)])

    def f(t):
        i = np.clip(np.searchsorted(edges, t, side="right") - 1, 0, lv.size - 1)
        return lv[i]

    return Signal(func=f, description=f"sequence of {lv.size} levels")


def from_array(t_samples, values) -> Signal:
    """Zero-order hold of ``values`` given at increasing times ``t_samples`` [s]."""
    ts = v.array("t_samples", t_samples, min_size=1)
    vals = v.array("values", values, size=ts.size)
    if np.any(np.diff(ts) <= 0):
        raise ValueError("t_samples must be strictly increasing")

    def f(t):
        i = np.clip(np.searchsorted(ts, t + 1e-12 * max(1.0, abs(ts[-1])), side="right") - 1, 0, ts.size - 1)
        return vals[i]

    return Signal(func=f, description=f"array of {vals.size} samples")


@dataclass(frozen=True, kw_only=True)
class Controller:
    """``Tc = feedforward(t) + kp*(reference(t) - y) - kd*omega_hat``.

    Attributes
    ----------
    kp : float
        Proportional gain [N*m/rad].
    kd : float
        Rate-feedback gain on the measured velocity [N*m*s/rad].
    reference : Signal
        Position reference r(t) [rad].
    feedforward : Signal
        Open-loop torque added to the feedback [N*m].
    name : str
        "open loop", "P" or "PD".
    """

    kp: float = 0.0
    kd: float = 0.0
    reference: Signal = field(default_factory=lambda: constant(0.0))
    feedforward: Signal = field(default_factory=lambda: constant(0.0))
    name: str = "open loop"

    def __post_init__(self):
        object.__setattr__(self, "kp", v.real("kp", self.kp, nonneg=True, unit="N*m/rad"))
        object.__setattr__(self, "kd", v.real("kd", self.kd, nonneg=True, unit="N*m*s/rad"))
        v.instance("reference", self.reference, Signal, "a fricctl.controllers.Signal")
        v.instance("feedforward", self.feedforward, Signal, "a fricctl.controllers.Signal")
        v.text("name", self.name)

    def __call__(self, t, y, omega_hat):
        """Control torque Tc at times ``t`` for readings ``y`` and ``omega_hat``."""
        return self.feedforward(t) + self.kp * (self.reference(t) - y) - self.kd * omega_hat


def open_loop(torque: Signal) -> Controller:
    """Open-loop torque profile ``Tc = torque(t)`` [N*m]."""
    return Controller(feedforward=torque, name="open loop")


def p_control(kp: float, reference: Signal) -> Controller:
    """P position control ``Tc = kp*(r - y)``."""
    return Controller(kp=kp, reference=reference, name="P")


def pd_control(kp: float, kd: float, reference: Signal) -> Controller:
    """PD position control with rate feedback ``Tc = kp*(r - y) - kd*omega_hat``."""
    return Controller(kp=kp, kd=kd, reference=reference, name="PD")
