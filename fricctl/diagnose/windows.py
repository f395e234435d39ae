"""What the simulation gets wrong: the model re-simulated over short windows of a record.

Each window starts from the measured state (filtered position, estimated
velocity, or rest where the encoder stands still) and runs open loop on the
recorded torque (delayed and offset as the model says), with
:func:`fricctl.simulate.replay`; the error against the encoder is the
"simulation error" a diagnosis reports.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _validate as v
from ..datasets import Run
from ..plant import JointModel
from ..simulate import replay
from .signals import Signals, delay_in_samples, delayed, estimate_signals
from .stops import EndStops, end_stops

__all__ = ["SimulationRMS", "WindowedSimulation", "WindowGrid", "window_grid", "simulate_windows",
           "windowed_simulation", "clear_of_stops", "signals_clear_of_stops"]


@dataclass(frozen=True, kw_only=True)
class SimulationRMS:
    """RMS error of a windowed re-simulation (:meth:`WindowedSimulation.rms`)."""

    position: float
    """Position error [rad] ([m] on a linear axis)."""
    velocity: float
    """Velocity error [rad/s] ([m/s])."""


@dataclass(frozen=True, kw_only=True, eq=False)
class WindowedSimulation:
    """The model re-simulated over windows, each from the measured state.

    Attributes
    ----------
    starts : ndarray of int
        First sample of each window.
    length : int
        Samples per window.
    q : ndarray, shape (N,)
        Simulated position, NaN outside windows [rad].
    omega : ndarray, shape (N,)
        Simulated velocity, NaN outside windows [rad/s].
    position_error, velocity_error : ndarray, shape (n_windows,)
        RMS over each window of ``q_sim - q_meas`` [rad] and ``w_sim - w_est`` [rad/s].
    failure : str
        Why the model could not be re-simulated (the errors are then NaN), or ``""``.
    """

    starts: np.ndarray
    length: int
    q: np.ndarray
    omega: np.ndarray
    position_error: np.ndarray
    velocity_error: np.ndarray
    failure: str = ""

    def rms(self, select=None) -> SimulationRMS:
        """Position [rad] and velocity [rad/s] RMS error over the selected windows (all by default)."""
        sel = np.ones(self.starts.size, bool) if select is None else np.asarray(select, bool)
        if not sel.any():
            return SimulationRMS(position=float("nan"), velocity=float("nan"))
        return SimulationRMS(position=float(np.sqrt(np.mean(self.position_error[sel] ** 2))),
                             velocity=float(np.sqrt(np.mean(self.velocity_error[sel] ** 2))))

    @classmethod
    def merge(cls, parts, *, n: int, length: int) -> "WindowedSimulation":
        """One simulation from disjoint sets of windows over the same ``n`` samples (in order)."""
        qs = np.full(n, np.nan)
        ws = np.full(n, np.nan)
        failure = next((s.failure for s in parts if s.failure), "")
        for s in parts:
            ok = ~np.isnan(s.q)
            qs[ok] = s.q[ok]
            ws[ok] = s.omega[ok]
        return cls(starts=np.concatenate([s.starts for s in parts]), length=length, q=qs, omega=ws,
                   position_error=np.concatenate([s.position_error for s in parts]),
                   velocity_error=np.concatenate([s.velocity_error for s in parts]),
                   failure=failure)

    @classmethod
    def failed(cls, starts, *, n: int, length: int, reason: str) -> "WindowedSimulation":
        """The simulation of a model that cannot be re-simulated on the record: NaN errors
        (undefined, never infinite) and the reason."""
        starts = np.asarray(starts, dtype=int)
        nan = np.full(starts.size, np.nan)
        return cls(starts=starts, length=length, q=np.full(n, np.nan), omega=np.full(n, np.nan),
                   position_error=nan, velocity_error=nan.copy(), failure=reason)


@dataclass(frozen=True, kw_only=True, eq=False)
class WindowGrid:
    """Where the windows of a record start, and their length."""

    starts: np.ndarray
    """First sample of each window."""
    length: int
    """Samples per window."""


#: Fewest samples in a re-simulation window [-].
MIN_WINDOW_SAMPLES = 10


def window_grid(sig: Signals, window: float) -> WindowGrid:
    """Back-to-back windows of ``window`` seconds, clear of the filter's edge effects.

    A window shorter than :data:`MIN_WINDOW_SAMPLES` samples of the record is refused
    (a ValueError with the shortest window in seconds)."""
    n = sig.t.size
    window = v.real("window", window, positive=True, unit="s")
    if window / sig.ts < MIN_WINDOW_SAMPLES - 0.5:
        raise ValueError(f"window: {window:g} s is {window / sig.ts:.3g} samples of this record "
                         f"(Ts = {sig.ts:g} s); a re-simulation window needs at least "
                         f"{MIN_WINDOW_SAMPLES} samples ({MIN_WINDOW_SAMPLES * sig.ts:g} s)")
    length = int(round(window / sig.ts))
    border = max(int(math.ceil(2.0 / (sig.cutoff * sig.ts))), 10)
    starts = np.arange(border, n - length - border, length)
    if starts.size == 0:
        raise ValueError(f"record too short for {window} s windows")
    return WindowGrid(starts=starts, length=length)


def simulate_windows(model: JointModel, sig: Signals, starts, length: int) -> WindowedSimulation:
    """Re-simulate ``model`` over the windows starting at ``starts`` (``length`` samples each)."""
    joint = model.joint()
    torque_all = delayed(sig.tm, delay_in_samples(model, sig.ts)) - model.offset
    n = sig.t.size
    qs = np.full(n, np.nan)
    ws = np.full(n, np.nan)
    pe = np.empty(starts.size)
    ve = np.empty(starts.size)
    fr = model.friction
    nsub = None
    zlug = None
    law = fr.state_law
    if law is not None:  # presliding: sub-steps for the bristle's rate at the record's speeds
        vmax = float(np.percentile(np.abs(sig.w), 99.5)) + 1e-9
        nsub = int(min(max(40, math.ceil(sig.ts * law.state.speed_rate(fr, vmax) / 1.5)), 4000))
        zlug = law.state.initial(fr, sig.qf)
    for i, k0 in enumerate(starts):
        idx = np.arange(k0, k0 + length)
        torque = torque_all[idx]
        w0 = 0.0 if sig.rest[k0] else float(sig.w[k0])
        state = None
        if zlug is not None:  # bristle deflection from the Dahl state along the measured motion
            state = [sig.qf[k0], w0, sig.qf[k0], w0, zlug[k0]]
        rep = replay(joint, torque, sig.ts, q0=float(sig.qf[k0]), omega0=w0, t0=float(sig.t[k0]),
                     substeps=nsub, state=state)
        q, w = rep.q, rep.omega
        qs[idx] = q
        ws[idx] = w
        pe[i] = np.sqrt(np.mean((q - sig.q[idx]) ** 2))
        ve[i] = np.sqrt(np.mean((w - sig.w[idx]) ** 2))
    return WindowedSimulation(starts=starts, length=length, q=qs, omega=ws, position_error=pe,
                              velocity_error=ve)


def windowed_simulation(model: JointModel, run: Run, *, window: float = 0.5) -> WindowedSimulation:
    """Re-simulate ``model`` driven by the measured torque over windows of ``window`` seconds.

    Each window starts from the measured state (filtered position, estimated
    velocity, or rest where the encoder stands still) and runs open loop on the
    recorded torque (delayed and offset as the model says).  Windows holding a contact
    with an end stop are left out, as :func:`~fricctl.diagnose.diagnose` leaves them out.

    Parameters
    ----------
    model : JointModel
    run : Run
    window : float
        Window length [s].

    Returns
    -------
    WindowedSimulation
    """
    v.instance("model", model, JointModel)
    v.instance("run", run, Run, "a fricctl.datasets.Run")
    window = v.real("window", window, positive=True, unit="s")
    sig, stops = signals_clear_of_stops(run)
    grid = clear_of_stops(window_grid(sig, window), stops, sig)
    return simulate_windows(model, sig, grid.starts, grid.length)


def clear_of_stops(grid: WindowGrid, stops: EndStops, sig: Signals) -> WindowGrid:
    """The windows that hold no contact with an end stop (a rigid model re-simulated through
    a stop runs past it: such a window measures the stop, not the model), nor start within
    the filter's reach after one (the window's first velocity is a filtered estimate: the
    border :func:`window_grid` keeps from the record's ends)."""
    if not stops.found:
        return grid
    border = max(int(math.ceil(2.0 / (sig.cutoff * sig.ts))), 10)
    hit = np.concatenate([[0], np.cumsum(stops.mask)])
    keep = hit[grid.starts + grid.length] - hit[np.maximum(grid.starts - border, 0)] == 0
    if not keep.any():
        raise ValueError(f"every {grid.length}-sample re-simulation window of the record holds a "
                         f"contact with an end stop ({stops.description}): shorten the window (--window), or "
                         f"record more motion clear of the stops")
    return WindowGrid(starts=grid.starts[keep], length=grid.length)


def signals_clear_of_stops(run: Run) -> tuple:
    """``(signals, stops)``: the record's signals in one block for one model's check, and its
    end stops, whose contacts (found as :func:`~fricctl.diagnose.diagnose` finds them) are left
    out of the sliding mask with the filter's reach -- a rigid model's equation error at an
    impact measures the stop, not the model."""
    stops = end_stops(run)
    return estimate_signals(run, 1, exclude=stops.mask if stops.found else None), stops
