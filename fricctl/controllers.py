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

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

__all__ = [
    "Controller", "open_loop", "p_control", "pd_control",
    "Signal", "constant", "step", "sawtooth", "sinusoid", "ramp_sinusoid", "sequence", "from_array",
]


def _finite(name, v):
    if isinstance(v, bool) or not isinstance(v, (int, float, np.floating, np.integer)) or not math.isfinite(v):
        raise ValueError(f"{name} must be a finite number, got {v!r}")
    return float(v)


@dataclass(frozen=True)
class Signal:
    """A time signal: ``signal(t)`` evaluates it on an array of times [s].

    ``description`` says what it is, for reports and figure titles.
    """

    func: Callable[[np.ndarray], np.ndarray]
    description: str

    def __call__(self, t):
        t = np.asarray(t, dtype=float)
        out = np.broadcast_to(np.asarray(self.func(t), dtype=float), t.shape).copy()
        if not np.all(np.isfinite(out)):
            raise ValueError(f"signal {self.description!r} produced NaN or inf")
        return out

    def __add__(self, other: "Signal") -> "Signal":
        if not isinstance(other, Signal):
            return NotImplemented
        return Signal(lambda t: self.func(t) + other.func(t), f"{self.description} + {other.description}")

    def __repr__(self):
        return f"Signal({self.description})"


def constant(value: float) -> Signal:
    """Constant signal."""
    v = _finite("value", value)
    return Signal(lambda t: np.full_like(t, v), f"constant {v:g}")


def step(amplitude: float, t0: float = 0.0) -> Signal:
    """Step of ``amplitude`` at ``t0`` [s] (value ``amplitude`` for t >= t0)."""
    a = _finite("amplitude", amplitude)
    t0 = _finite("t0", t0)
    return Signal(lambda t: np.where(t >= t0, a, 0.0), f"step {a:g} at {t0:g} s")


def sawtooth(amplitude: float, period: float) -> Signal:
    """Rising ramp from 0 to ``amplitude`` over each ``period`` [s], then reset."""
    a = _finite("amplitude", amplitude)
    p = _finite("period", period)
    if p <= 0:
        raise ValueError(f"period must be > 0 s, got {period!r}")
    return Signal(lambda t: a * np.mod(t, p) / p, f"sawtooth {a:g}, period {p:g} s")


def sinusoid(amplitude: float, frequency: float, phase: float = 0.0, offset: float = 0.0) -> Signal:
    """``offset + amplitude*sin(2*pi*frequency*t + phase)``; frequency [Hz]."""
    a = _finite("amplitude", amplitude)
    f = _finite("frequency", frequency)
    ph = _finite("phase", phase)
    off = _finite("offset", offset)
    if f <= 0:
        raise ValueError(f"frequency must be > 0 Hz, got {frequency!r}")
    return Signal(lambda t: off + a * np.sin(2 * np.pi * f * t + ph), f"sinusoid {a:g} at {f:g} Hz")


def ramp_sinusoid(amplitude_start: float, amplitude_end: float, frequency: float,
                  duration: float) -> Signal:
    """Sinusoid whose amplitude grows linearly from start to end over ``duration`` [s]."""
    a0 = _finite("amplitude_start", amplitude_start)
    a1 = _finite("amplitude_end", amplitude_end)
    f = _finite("frequency", frequency)
    d = _finite("duration", duration)
    if f <= 0 or d <= 0:
        raise ValueError("frequency and duration must be > 0")
    return Signal(lambda t: (a0 + (a1 - a0) * np.clip(t / d, 0, 1)) * np.sin(2 * np.pi * f * t),
                  f"sinusoid {a0:g}->{a1:g} at {f:g} Hz")


def sequence(levels, durations) -> Signal:
    """Piecewise-constant sequence: ``levels[i]`` for ``durations[i]`` seconds each.

    After the last interval the signal holds the last level.
    """
    lv = np.asarray(levels, dtype=float)
    du = np.asarray(durations, dtype=float)
    if lv.ndim != 1 or du.shape != lv.shape or lv.size == 0:
        raise ValueError("levels and durations must be 1-D arrays of equal, non-zero length")
    if not (np.all(np.isfinite(lv)) and np.all(np.isfinite(du))):
        raise ValueError("levels and durations must be finite")
    if np.any(du <= 0):
        raise ValueError("durations must be > 0 s")
    edges = np.concatenate([[0.0], np.cumsum(du)])

    def f(t):
        i = np.clip(np.searchsorted(edges, t, side="right") - 1, 0, lv.size - 1)
        return lv[i]

    return Signal(f, f"sequence of {lv.size} levels")


def from_array(t_samples, values) -> Signal:
    """Zero-order hold of ``values`` given at increasing times ``t_samples`` [s]."""
    ts = np.asarray(t_samples, dtype=float)
    v = np.asarray(values, dtype=float)
    if ts.ndim != 1 or v.shape != ts.shape or ts.size == 0:
        raise ValueError("t_samples and values must be 1-D arrays of equal, non-zero length")
    if not (np.all(np.isfinite(ts)) and np.all(np.isfinite(v))):
        raise ValueError("t_samples and values must be finite")
    if np.any(np.diff(ts) <= 0):
        raise ValueError("t_samples must be strictly increasing")

    def f(t):
        i = np.clip(np.searchsorted(ts, t + 1e-12 * max(1.0, abs(ts[-1])), side="right") - 1, 0, ts.size - 1)
        return v[i]

    return Signal(f, f"array of {v.size} samples")


@dataclass(frozen=True)
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
        _finite("kp", self.kp)
        _finite("kd", self.kd)
        if self.kp < 0 or self.kd < 0:
            raise ValueError(f"gains must be >= 0, got kp={self.kp!r}, kd={self.kd!r}")
        if not isinstance(self.reference, Signal) or not isinstance(self.feedforward, Signal):
            raise ValueError("reference and feedforward must be fricctl.controllers.Signal objects")

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
