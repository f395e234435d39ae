"""The paper's 2-H-1 friction network: evaluation, two trainers, accuracy, JSON, C export.

Gervini, Gomes & da Rosa (2003) estimate the joint friction torque with a
2-4-1 feed-forward network: inputs the motor torque ``Tm`` and the velocity
``omega``, four ``tanh`` hidden units, a linear output, trained by
back-propagation with momentum on the patterns ``Tat = Tm - I*alpha_hat``.  The
estimate is then added to the control torque, ``Tm(k+1) = Tc(k) + s*Tat_hat(k)``
(the compensator lives in :mod:`fricctl.compensators`, not here).

Everything is on the load side of the gear, in SI units: ``Tm`` and the friction
torque in [N*m], ``omega`` in [rad/s].  Friction has the sign of the velocity
and enters the joint as ``I*qdd = Tm - Tat``.

The network formula (the compiled closed-loop kernel reproduces it exactly)::

    xn = (x - input_offset) / input_scale        x = (Tm, omega)
    h  = tanh(w1 @ xn + b1)                      w1: (H, 2), b1: (H,)
    yn = w2 . h + b2                             w2: (H,),   b2: scalar
    y  = yn * output_scale + output_offset       [N*m]

Public API
----------
:class:`FrictionNet`
    The immutable trained network (weights, scaling, envelope, metadata).
:func:`train_backprop`
    The paper's back-propagation with momentum (numpy set-up, numba inner loop).
:func:`train_casadi`
    Levenberg-Marquardt on the least-squares objective, residuals and the exact
    Jacobian from CasADi's algorithmic differentiation.
:func:`fit_percent`, :func:`r_squared`, :func:`fit_report`
    Accuracy, with the definitions stated.
:func:`save_net`, :func:`load_net`
    JSON files with a format version; no pickle.
:func:`c_source`
    A self-contained C translation unit evaluating the network.
:func:`smooth_friction_patterns`
    Noise-free training patterns of a known smooth friction law (for tests,
    benchmarks and teaching, where the virtual bench is not needed).
"""

from __future__ import annotations

import json
import math
import time
import types
from dataclasses import dataclass, field
from pathlib import Path
from typing import NamedTuple

import numpy as np

__all__ = [
    "FORMAT_NAME",
    "FORMAT_VERSION",
    "FrictionNet",
    "TrainingHistory",
    "TrainingResult",
    "FitReport",
    "train_backprop",
    "train_casadi",
    "fit_percent",
    "r_squared",
    "fit_report",
    "save_net",
    "load_net",
    "c_source",
    "smooth_friction_patterns",
]

#: Value of the ``"format"`` key of a saved network.
FORMAT_NAME = "fricctl.FrictionNet"
#: Version of the JSON layout written by :func:`save_net`; :func:`load_net`
#: reads exactly this version.
FORMAT_VERSION = 1


# --------------------------------------------------------------------------
# The network
# --------------------------------------------------------------------------
def _frozen_array(value, name: str, shape: tuple[int, ...] | None = None) -> np.ndarray:
    try:
        arr = np.array(value, dtype=float)  # a copy: the net owns its weights
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be an array of real numbers: {exc}") from None
    if shape is not None and arr.shape != shape:
        raise ValueError(f"{name} must have shape {shape}, got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite (no NaN or inf)")
    arr.setflags(write=False)
    return arr


def _real(value, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
        raise ValueError(f"{name} must be a real number, got {value!r}")
    v = float(value)
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return v


@dataclass(frozen=True, kw_only=True, eq=False)
class FrictionNet:
    """A trained 2-H-1 friction network (load side, SI units); immutable.

    Evaluate with ``net(tm, omega)``; see the module docstring for the formula.

    Notes
    -----
    The training envelope is the axis-aligned box of the training inputs.  It
    is the minimum the compiled loop needs for clipping, and it is generous:
    the box contains corners that held no patterns (e.g. a large torque at
    zero velocity), where the net is as untested as outside the box.  Velocity
    and torque history (hysteresis, pre-sliding) are not inputs, so the net can
    only represent a static map ``(Tm, omega) -> Tat``.
    """

    w1: np.ndarray
    """Input-to-hidden weights, shape (H, 2), acting on the scaled inputs [-]."""
    b1: np.ndarray
    """Hidden biases, shape (H,) [-]."""
    w2: np.ndarray
    """Hidden-to-output weights, shape (H,) [-]."""
    b2: float
    """Output bias (scaled output) [-]."""
    input_offset: np.ndarray
    """Offsets of (Tm [N*m], omega [rad/s]) subtracted before scaling."""
    input_scale: np.ndarray
    """Scales of (Tm [N*m], omega [rad/s]) dividing the inputs; > 0."""
    output_offset: float
    """Offset added to the scaled output [N*m]."""
    output_scale: float
    """Scale multiplying the network's output [N*m]; > 0."""
    envelope_low: np.ndarray
    """Lower corner (Tm [N*m], omega [rad/s]) of the training box."""
    envelope_high: np.ndarray
    """Upper corner (Tm [N*m], omega [rad/s]) of the training box."""
    metadata: dict = field(default_factory=dict)
    """Training metadata (trainer, epochs, fit, ...); must be JSON-serialisable.
    Stored as a read-only mapping."""

    def __post_init__(self):
        w1 = _frozen_array(self.w1, "w1")
        if w1.ndim != 2 or w1.shape[1] != 2 or w1.shape[0] < 1:
            raise ValueError(f"w1 must have shape (H, 2) with H >= 1, got {w1.shape}")
        h = w1.shape[0]
        values = {
            "w1": w1,
            "b1": _frozen_array(self.b1, "b1", (h,)),
            "w2": _frozen_array(self.w2, "w2", (h,)),
            "b2": _real(self.b2, "b2"),
            "input_offset": _frozen_array(self.input_offset, "input_offset", (2,)),
            "input_scale": _frozen_array(self.input_scale, "input_scale", (2,)),
            "output_offset": _real(self.output_offset, "output_offset"),
            "output_scale": _real(self.output_scale, "output_scale"),
            "envelope_low": _frozen_array(self.envelope_low, "envelope_low", (2,)),
            "envelope_high": _frozen_array(self.envelope_high, "envelope_high", (2,)),
        }
        if not np.all(values["input_scale"] > 0):
            raise ValueError(f"input_scale must be > 0, got {values['input_scale']}")
        if not values["output_scale"] > 0:
            raise ValueError(f"output_scale must be > 0 [N*m], got {values['output_scale']}")
        if not np.all(values["envelope_low"] <= values["envelope_high"]):
            raise ValueError("envelope_low must be <= envelope_high in both Tm and omega, got "
                             f"{values['envelope_low']} and {values['envelope_high']}")
        if not isinstance(self.metadata, (dict, types.MappingProxyType)):
            raise ValueError(f"metadata must be a dict, got {type(self.metadata).__name__}")
        try:
            meta = json.loads(json.dumps(dict(self.metadata), allow_nan=False))
        except (TypeError, ValueError) as exc:
            raise ValueError(f"metadata must be JSON-serialisable: {exc}") from None
        values["metadata"] = types.MappingProxyType(meta)
        for name, v in values.items():
            object.__setattr__(self, name, v)

    # -- evaluation --------------------------------------------------------
    @property
    def hidden(self) -> int:
        """Number of hidden units H."""
        return self.w1.shape[0]

    @property
    def n_parameters(self) -> int:
        """Number of trainable weights and biases, 4*H + 1."""
        return 4 * self.hidden + 1

    def _inputs(self, tm, omega):
        tm = np.asarray(tm, dtype=float)
        omega = np.asarray(omega, dtype=float)
        try:
            tm, omega = np.broadcast_arrays(tm, omega)
        except ValueError:
            raise ValueError(f"tm and omega must have broadcastable shapes, got {tm.shape} "
                             f"and {omega.shape}") from None
        if not (np.all(np.isfinite(tm)) and np.all(np.isfinite(omega))):
            raise ValueError("tm and omega must be finite (no NaN or inf)")
        return tm, omega

    def _hidden(self, tm, omega):
        xn0 = (tm - self.input_offset[0]) / self.input_scale[0]
        xn1 = (omega - self.input_offset[1]) / self.input_scale[1]
        a = (np.multiply.outer(xn0, self.w1[:, 0]) + np.multiply.outer(xn1, self.w1[:, 1])
             + self.b1)
        return np.tanh(a)

    def __call__(self, tm, omega, *, clip: bool = False) -> np.ndarray:
        """Friction estimate ``Tat_hat(Tm, omega)`` [N*m].

        Parameters
        ----------
        tm : array_like
            Motor torque, load side [N*m].
        omega : array_like
            Velocity, load side [rad/s]; broadcast against ``tm``.
        clip : bool
            Clip the inputs to the training box first (the compiled loop does).

        Returns
        -------
        numpy.ndarray
            Friction estimate, broadcast shape of the inputs [N*m].
        """
        tm, omega = self._inputs(tm, omega)
        if clip:
            tm = np.clip(tm, self.envelope_low[0], self.envelope_high[0])
            omega = np.clip(omega, self.envelope_low[1], self.envelope_high[1])
        h = self._hidden(tm, omega)
        yn = h @ self.w2 + self.b2
        return yn * self.output_scale + self.output_offset

    def outside_envelope(self, tm, omega) -> np.ndarray:
        """True where ``(tm, omega)`` lies outside the training box (bool array)."""
        tm, omega = self._inputs(tm, omega)
        return ((tm < self.envelope_low[0]) | (tm > self.envelope_high[0])
                | (omega < self.envelope_low[1]) | (omega > self.envelope_high[1]))

    def torque_gain(self, tm, omega) -> np.ndarray:
        """Analytic derivative ``dTat_hat/dTm`` at ``(tm, omega)`` (no clipping) [-]."""
        tm, omega = self._inputs(tm, omega)
        h = self._hidden(tm, omega)
        dh = (1.0 - h * h) * self.w1[:, 0]
        return (dh @ self.w2) * self.output_scale / self.input_scale[0]

    def gain_at_rest(self) -> float:
        """The static gain ``g = dTat_hat/dTm`` at ``Tm = 0, omega = 0`` [-].

        While the joint is stuck the patterns are ``Tat = Tm``, so a net trained
        on them has ``Tat_hat ~ g*Tm`` near rest; the compensated loop
        ``Tm = Tc + s*g*Tm`` then settles at ``Tm = Tc / (1 - s*g)`` for
        ``s*g < 1`` (the dead-zone reduction factor) and winds up otherwise.
        """
        return float(self.torque_gain(0.0, 0.0))

    # -- I/O ----------------------------------------------------------------
    def to_dict(self) -> dict:
        """JSON-ready dict with the format name and version."""
        return {
            "format": FORMAT_NAME,
            "version": FORMAT_VERSION,
            "hidden": self.hidden,
            "w1": self.w1.tolist(),
            "b1": self.b1.tolist(),
            "w2": self.w2.tolist(),
            "b2": self.b2,
            "input_offset": self.input_offset.tolist(),
            "input_scale": self.input_scale.tolist(),
            "output_offset": self.output_offset,
            "output_scale": self.output_scale,
            "envelope_low": self.envelope_low.tolist(),
            "envelope_high": self.envelope_high.tolist(),
            "units": {"inputs": ["N*m", "rad/s"], "output": "N*m", "side": "load"},
            "metadata": dict(self.metadata),
        }

    @classmethod
    def from_dict(cls, data: dict) -> "FrictionNet":
        """Inverse of :meth:`to_dict`; a wrong format, version or key raises ``ValueError``."""
        if not isinstance(data, dict):
            raise ValueError(f"a saved FrictionNet is a JSON object, got {type(data).__name__}")
        if data.get("format") != FORMAT_NAME:
            raise ValueError(f"not a FrictionNet file: format is {data.get('format')!r}, "
                             f"expected {FORMAT_NAME!r}")
        if data.get("version") != FORMAT_VERSION:
            raise ValueError(f"unsupported FrictionNet format version {data.get('version')!r}; "
                             f"this fricctl reads version {FORMAT_VERSION}")
        fields_ = ("w1", "b1", "w2", "b2", "input_offset", "input_scale", "output_offset",
                   "output_scale", "envelope_low", "envelope_high", "metadata")
        expected = set(fields_) | {"format", "version", "hidden", "units"}
        missing = sorted(expected - set(data))
        unknown = sorted(set(data) - expected)
        if missing:
            raise ValueError(f"FrictionNet file is missing key(s): {', '.join(missing)}")
        if unknown:
            raise ValueError(f"FrictionNet file has unknown key(s): {', '.join(unknown)}")
        net = cls(**{k: data[k] for k in fields_})
        if data["hidden"] != net.hidden:
            raise ValueError(f"FrictionNet file says hidden={data['hidden']!r} but w1 has "
                             f"{net.hidden} rows")
        return net

    def to_json(self) -> str:
        """JSON text; floats are written with round-trip precision."""
        return json.dumps(self.to_dict(), indent=1, allow_nan=False)

    @classmethod
    def from_json(cls, text: str) -> "FrictionNet":
        """Parse :meth:`to_json` output; malformed text raises ``ValueError``."""
        try:
            data = json.loads(text)
        except json.JSONDecodeError as exc:
            raise ValueError(f"malformed FrictionNet JSON: {exc}") from None
        return cls.from_dict(data)

    def replace(self, **changes) -> "FrictionNet":
        """Copy with fields changed; unknown names raise ``ValueError``."""
        d = {k: getattr(self, k) for k in self.__dataclass_fields__}
        unknown = sorted(set(changes) - set(d))
        if unknown:
            raise ValueError(f"unknown FrictionNet field(s): {', '.join(unknown)}")
        d.update(changes)
        d["metadata"] = dict(d["metadata"])
        return FrictionNet(**d)

    def __repr__(self) -> str:
        trainer = self.metadata.get("trainer", "?") if self.metadata else "?"
        return (f"FrictionNet(hidden={self.hidden}, trainer={trainer!r}, "
                f"envelope Tm [{self.envelope_low[0]:.4g}, {self.envelope_high[0]:.4g}] N*m, "
                f"omega [{self.envelope_low[1]:.4g}, {self.envelope_high[1]:.4g}] rad/s)")


def save_net(net: FrictionNet, path) -> Path:
    """Write ``net`` as JSON to ``path`` (see :meth:`FrictionNet.to_json`); returns the path."""
    if not isinstance(net, FrictionNet):
        raise ValueError(f"save_net needs a FrictionNet, got {type(net).__name__}")
    path = Path(path)
    path.write_text(net.to_json() + "\n", encoding="utf-8")
    return path


def load_net(path) -> FrictionNet:
    """Read a network written by :func:`save_net`.

    Raises
    ------
    FileNotFoundError
        If ``path`` does not exist.
    ValueError
        If the file is not valid JSON, not a FrictionNet, of another format
        version, or has missing, unknown or malformed entries.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise ValueError(f"{path}: not a text file ({exc})") from None
    try:
        return FrictionNet.from_json(text)
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None


# --------------------------------------------------------------------------
# Accuracy
# --------------------------------------------------------------------------
def _pair(y, yhat):
    y = np.asarray(y, dtype=float).ravel()
    yhat = np.asarray(yhat, dtype=float).ravel()
    if y.shape != yhat.shape:
        raise ValueError(f"y and yhat must have the same length, got {y.size} and {yhat.size}")
    if y.size < 2:
        raise ValueError("need at least 2 samples to measure a fit")
    if not (np.all(np.isfinite(y)) and np.all(np.isfinite(yhat))):
        raise ValueError("y and yhat must be finite (no NaN or inf)")
    spread = np.linalg.norm(y - y.mean())
    if spread == 0:
        raise ValueError("y is constant: the normalised fit and R^2 are undefined")
    return y, yhat, spread


def fit_percent(y, yhat) -> float:
    """Normalised fit ``100*(1 - ||y - yhat|| / ||y - mean(y)||)`` [%].

    100 % is a perfect fit, 0 % is no better than the mean; it is negative for
    worse.  This is the "fit" of system-identification tools (MATLAB
    ``compare``).  It relates to R^2 by ``fit = 100*(1 - sqrt(1 - R^2))``, so
    R^2 = 0.98 is only a fit of 85.9 %.

    Examples
    --------
    >>> fit_percent([0.0, 1.0, 2.0, 3.0], [0.0, 1.0, 2.0, 3.0])
    100.0
    >>> round(fit_percent([0.0, 1.0, 2.0, 3.0], [1.5, 1.5, 1.5, 1.5]), 6)
    0.0
    """
    y, yhat, spread = _pair(y, yhat)
    return float(100.0 * (1.0 - np.linalg.norm(y - yhat) / spread))


def r_squared(y, yhat) -> float:
    """Coefficient of determination ``1 - ||y - yhat||^2 / ||y - mean(y)||^2`` [-].

    Examples
    --------
    >>> round(r_squared([0.0, 1.0, 2.0, 3.0], [0.0, 1.0, 2.0, 4.0]), 3)
    0.8
    """
    y, yhat, spread = _pair(y, yhat)
    return float(1.0 - np.sum((y - yhat) ** 2) / spread**2)


@dataclass(frozen=True, kw_only=True)
class FitReport:
    """Accuracy of a friction estimate on one set of patterns.

    Notes
    -----
    The paper's "98 % accuracy" has no definition; the two measures here are
    the common candidates and differ a lot (R^2 = 0.98 is a fit of 85.9 %).
    """

    fit_percent: float
    """Normalised fit, 100*(1 - ||e|| / ||y - mean(y)||) [%]."""
    r_squared: float
    """Coefficient of determination [-]."""
    rmse: float
    """Root-mean-square error [N*m]."""
    max_abs_error: float
    """Largest absolute error [N*m]."""
    n: int
    """Number of patterns."""
    outside_envelope: int = 0
    """Patterns outside the net's training box (when computed from a net)."""

    def report(self) -> str:
        """A few readable lines."""
        lines = [f"patterns      {self.n}",
                 f"fit           {self.fit_percent:.2f} %  (100*(1 - ||e||/||y - mean y||))",
                 f"R^2           {self.r_squared:.5f}",
                 f"RMSE          {self.rmse:.4g} N*m",
                 f"max |error|   {self.max_abs_error:.4g} N*m"]
        if self.outside_envelope:
            lines.append(f"outside envelope: {self.outside_envelope} patterns")
        return "\n".join(lines)

    def as_dict(self) -> dict:
        """Plain dict (JSON-ready)."""
        return {"fit_percent": self.fit_percent, "r_squared": self.r_squared,
                "rmse": self.rmse, "max_abs_error": self.max_abs_error, "n": self.n,
                "outside_envelope": self.outside_envelope}


def fit_report(y, yhat=None, *, net: FrictionNet | None = None, tm=None, omega=None) -> FitReport:
    """Accuracy of ``yhat`` against ``y``, or of ``net(tm, omega)`` against ``y``.

    Parameters
    ----------
    y : array_like
        Reference friction torque [N*m].
    yhat : array_like, optional
        Estimate [N*m]; give this or ``net``, ``tm`` and ``omega``.
    net : FrictionNet, optional
        Network evaluated (without clipping) at ``tm``, ``omega``.
    tm, omega : array_like, optional
        Inputs of the patterns [N*m], [rad/s].
    """
    outside = 0
    if net is not None:
        if yhat is not None or tm is None or omega is None:
            raise ValueError("give either yhat, or net with tm and omega")
        yhat = net(tm, omega)
        outside = int(np.count_nonzero(net.outside_envelope(tm, omega)))
    elif yhat is None:
        raise ValueError("give either yhat, or net with tm and omega")
    y, yhat, _ = _pair(y, yhat)
    e = y - yhat
    return FitReport(fit_percent=fit_percent(y, yhat), r_squared=r_squared(y, yhat),
                     rmse=float(np.sqrt(np.mean(e * e))), max_abs_error=float(np.max(np.abs(e))),
                     n=int(y.size), outside_envelope=outside)


# --------------------------------------------------------------------------
# Training data, scaling and parameter vector
# --------------------------------------------------------------------------
def _patterns(tm, omega, target):
    arrs = []
    for name, v in (("tm", tm), ("omega", omega), ("target", target)):
        a = np.asarray(v, dtype=float)
        if a.ndim != 1:
            raise ValueError(f"{name} must be a 1-D array, got shape {a.shape}")
        if not np.all(np.isfinite(a)):
            raise ValueError(f"{name} must be finite (no NaN or inf)")
        arrs.append(a)
    n = arrs[0].size
    if any(a.size != n for a in arrs):
        raise ValueError(f"tm, omega and target must have the same length, got "
                         f"{[a.size for a in arrs]}")
    if n < 2:
        raise ValueError("need at least 2 training patterns")
    for name, a in zip(("tm", "omega", "target"), arrs):
        if np.ptp(a) == 0:
            raise ValueError(f"{name} is constant over the patterns: nothing to learn from")
    return arrs


def _scaling(tm, omega, target):
    """Inputs to [-1, 1] over their range; output to zero mean, unit std."""
    lo = np.array([tm.min(), omega.min()])
    hi = np.array([tm.max(), omega.max()])
    return dict(input_offset=0.5 * (lo + hi), input_scale=0.5 * (hi - lo),
                output_offset=float(target.mean()), output_scale=float(target.std()),
                envelope_low=lo, envelope_high=hi)


def _pack(w1, b1, w2, b2) -> np.ndarray:
    """theta = [w1 row-major (2H), b1 (H), w2 (H), b2]."""
    return np.concatenate([np.ravel(w1), b1, w2, [b2]]).astype(float)


def _unpack(theta, hidden):
    h = hidden
    return (theta[:2 * h].reshape(h, 2), theta[2 * h:3 * h], theta[3 * h:4 * h],
            float(theta[4 * h]))


def _initial_theta(hidden: int, rng: np.random.Generator) -> np.ndarray:
    # Nguyen-Widrow-like: hidden units with unit-norm input weights scaled by
    # 0.7*H^(1/2) and biases spreading the tanh centres over [-1, 1] of the
    # scaled inputs; small output weights.
    w1 = rng.normal(size=(hidden, 2))
    w1 *= 0.7 * math.sqrt(hidden) / np.linalg.norm(w1, axis=1, keepdims=True)
    b1 = rng.uniform(-1.0, 1.0, size=hidden) * np.linalg.norm(w1, axis=1)
    w2 = rng.uniform(-0.5, 0.5, size=hidden)
    return _pack(w1, b1, w2, 0.0)


def _check_rng(rng):
    if not isinstance(rng, np.random.Generator):
        raise ValueError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")


def _check_hidden(hidden):
    if isinstance(hidden, bool) or not isinstance(hidden, (int, np.integer)) or hidden < 1:
        raise ValueError(f"hidden must be an integer >= 1, got {hidden!r}")
    return int(hidden)


def _make_net(theta, hidden, scaling, metadata) -> FrictionNet:
    w1, b1, w2, b2 = _unpack(theta, hidden)
    return FrictionNet(w1=w1, b1=b1, w2=w2, b2=b2, metadata=metadata, **scaling)


@dataclass(frozen=True, kw_only=True, eq=False)
class TrainingHistory:
    """Training loss over the run.

    ``loss[k]`` is the mean squared error over all training patterns in
    physical units [(N*m)^2] after step ``k`` (an epoch for back-prop, an
    accepted or rejected Levenberg-Marquardt iteration for CasADi; for several
    restarts, the best loss so far over all restarts), and ``elapsed[k]`` the
    wall time since the trainer started [s].  ``loss[0]`` is the initial loss.
    """

    trainer: str
    """'backprop' or 'casadi'."""
    step: str
    """What one entry is: 'epoch' or 'iteration'."""
    loss: np.ndarray
    """Training mean squared error [(N*m)^2]."""
    elapsed: np.ndarray
    """Wall time since the start of training [s]."""

    def time_to_reach(self, loss: float) -> float:
        """First elapsed time at which the loss is <= ``loss`` [s]; ``inf`` if never."""
        hit = np.nonzero(self.loss <= loss)[0]
        return float(self.elapsed[hit[0]]) if hit.size else math.inf


class TrainingResult(NamedTuple):
    """What both trainers return: ``net, history = train_*(...)``."""

    net: FrictionNet
    history: TrainingHistory


# --------------------------------------------------------------------------
# Back-propagation with momentum (the paper's trainer)
# --------------------------------------------------------------------------
def _numba_kernels():
    # numba is imported lazily so that `import fricctl.nn` stays light; it is a
    # declared dependency, so a missing numba is an installation error.
    from numba import njit

    @njit(cache=True)
    def accumulate(theta, x0, x1, t, h, g):
        # One pattern: loss 0.5*(yn - t)^2 on the scaled output; adds its
        # gradient to g and returns the loss.
        yn = theta[4 * h]
        hid = np.empty(h)
        for j in range(h):
            hid[j] = math.tanh(theta[2 * j] * x0 + theta[2 * j + 1] * x1 + theta[2 * h + j])
            yn += theta[3 * h + j] * hid[j]
        e = yn - t
        for j in range(h):
            d = e * theta[3 * h + j] * (1.0 - hid[j] * hid[j])
            g[2 * j] += d * x0
            g[2 * j + 1] += d * x1
            g[2 * h + j] += d
            g[3 * h + j] += e * hid[j]
        g[4 * h] += e
        return 0.5 * e * e

    @njit(cache=True)
    def batch_loss_grad(theta, xn, tn, h):
        g = np.zeros(theta.size)
        loss = 0.0
        n = tn.size
        for i in range(n):
            loss += accumulate(theta, xn[0, i], xn[1, i], tn[i], h, g)
        return loss / n, g / n

    @njit(cache=True)
    def epoch(theta, velocity, xn, tn, order, batch, lr, mom, h):
        n = order.size
        g = np.zeros(theta.size)
        for start in range(0, n, batch):
            stop = min(start + batch, n)
            g[:] = 0.0
            for k in range(start, stop):
                i = order[k]
                accumulate(theta, xn[0, i], xn[1, i], tn[i], h, g)
            m = stop - start
            for p in range(theta.size):
                velocity[p] = mom * velocity[p] - lr * g[p] / m
                theta[p] += velocity[p]
        # loss over all patterns after the epoch
        loss = 0.0
        for i in range(n):
            yn = theta[4 * h]
            for j in range(h):
                yn += theta[3 * h + j] * math.tanh(
                    theta[2 * j] * xn[0, i] + theta[2 * j + 1] * xn[1, i] + theta[2 * h + j])
            loss += 0.5 * (yn - tn[i]) ** 2
        return loss / n

    return batch_loss_grad, epoch


_KERNELS = None


def _kernels():
    global _KERNELS
    if _KERNELS is None:
        kernels = _numba_kernels()
        # compile (or load from the cache) now, so that training histories
        # time the training and not the compiler
        theta = np.zeros(5)
        xn = np.zeros((2, 2))
        tn = np.zeros(2)
        kernels[0](theta, xn, tn, 1)
        kernels[1](theta, np.zeros(5), xn, tn, np.arange(2), 1, 0.1, 0.5, 1)
        _KERNELS = kernels
    return _KERNELS


def _scaled(tm, omega, target, scaling):
    xn = np.empty((2, tm.size))
    xn[0] = (tm - scaling["input_offset"][0]) / scaling["input_scale"][0]
    xn[1] = (omega - scaling["input_offset"][1]) / scaling["input_scale"][1]
    tn = (target - scaling["output_offset"]) / scaling["output_scale"]
    return xn, tn


def train_backprop(tm, omega, target, *, hidden: int = 4, learning_rate: float = 0.05,
                   momentum: float = 0.9, epochs: int = 1000, batch_size: int = 1,
                   rng: np.random.Generator, metadata: dict | None = None) -> TrainingResult:
    """The paper's trainer: gradient descent with momentum (back-propagation).

    The update after each batch is the classical one (Rumelhart et al., 1986)::

        dtheta <- momentum*dtheta - learning_rate * mean_batch(grad 0.5*(yn - tn)^2)
        theta  <- theta + dtheta

    on scaled inputs (each to [-1, 1] over its range) and a scaled target (zero
    mean, unit standard deviation).  The pattern order is shuffled each epoch.

    Parameters
    ----------
    tm, omega, target : array_like
        1-D patterns: motor torque [N*m], velocity [rad/s], friction [N*m].
    hidden : int
        Hidden units H (4 in the paper).
    learning_rate : float
        Step size on the scaled problem, > 0 [-].
    momentum : float
        Momentum factor in [0, 1) [-].
    epochs : int
        Passes over the patterns, >= 1.
    batch_size : int
        Patterns per update: 1 is per-pattern (on-line) training as in the
        paper; ``len(tm)`` is batch gradient descent.
    rng : numpy.random.Generator
        Source of the initial weights and the pattern order.
    metadata : dict, optional
        Extra JSON-serialisable entries stored with the net (e.g. the seed).

    Returns
    -------
    TrainingResult
        ``(net, history)``; history entries are epochs.

    Notes
    -----
    No early stopping, learning-rate schedule or weight decay: the paper's
    plain method.  The inner loop is compiled with numba, so the comparison
    with :func:`train_casadi` is between algorithms, not interpreters.

    Examples
    --------
    >>> tm, om, f = smooth_friction_patterns(np.random.default_rng(0), n_sliding=200, n_stuck=0)
    >>> net, hist = train_backprop(tm, om, f, epochs=50, rng=np.random.default_rng(1))
    >>> bool(hist.loss[-1] < hist.loss[0])
    True
    """
    tm, omega, target = _patterns(tm, omega, target)
    hidden = _check_hidden(hidden)
    _check_rng(rng)
    lr = _real(learning_rate, "learning_rate")
    mom = _real(momentum, "momentum")
    if not lr > 0:
        raise ValueError(f"learning_rate must be > 0, got {learning_rate!r}")
    if not 0 <= mom < 1:
        raise ValueError(f"momentum must lie in [0, 1), got {momentum!r}")
    for name, v in (("epochs", epochs), ("batch_size", batch_size)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 1:
            raise ValueError(f"{name} must be an integer >= 1, got {v!r}")
    n = tm.size
    batch = min(int(batch_size), n)
    rng_state = rng.bit_generator.state
    scaling = _scaling(tm, omega, target)
    xn, tn = _scaled(tm, omega, target, scaling)
    batch_loss_grad, epoch = _kernels()

    t0 = time.perf_counter()
    theta = _initial_theta(hidden, rng)
    velocity = np.zeros_like(theta)
    loss = np.empty(epochs + 1)
    elapsed = np.empty(epochs + 1)
    loss[0] = batch_loss_grad(theta, xn, tn, hidden)[0]
    elapsed[0] = time.perf_counter() - t0
    for k in range(epochs):
        order = rng.permutation(n)
        loss[k + 1] = epoch(theta, velocity, xn, tn, order, batch, lr, mom, hidden)
        elapsed[k + 1] = time.perf_counter() - t0
        if not math.isfinite(loss[k + 1]):
            raise ValueError(f"back-propagation diverged at epoch {k + 1} (loss is not "
                             f"finite); lower learning_rate={lr}")
    mse = 2.0 * loss * scaling["output_scale"] ** 2  # scaled 0.5*e^2 -> physical e^2
    history = TrainingHistory(trainer="backprop", step="epoch", loss=mse, elapsed=elapsed)
    meta = {"trainer": "backprop", "hidden": hidden, "epochs": int(epochs),
            "learning_rate": lr, "momentum": mom, "batch_size": batch, "n_patterns": n,
            "rng_state": rng_state, "train_mse": float(mse[-1])}
    net = _make_net(theta, hidden, scaling, meta)
    rep = fit_report(target, net(tm, omega))
    meta.update(fit_percent=rep.fit_percent, r_squared=rep.r_squared)
    meta.update(metadata or {})
    return TrainingResult(net.replace(metadata=meta), history)


# --------------------------------------------------------------------------
# Second-order trainer: Levenberg-Marquardt with CasADi derivatives
# --------------------------------------------------------------------------
_CASADI_CACHE: dict = {}


def _casadi_functions(hidden: int, n: int):
    """CasADi Functions of (theta, xn 2xN, tn 1xN), cached per (H, N).

    Returns ``(residuals, residuals_and_jacobian)``: ``r`` (N,) and the exact
    Jacobian ``J`` (N x (4H+1)).  The network is written with MX matrix
    operations over all patterns at once (one ``tanh`` node on an H x N
    matrix), which CasADi's virtual machine evaluates as dense loops: for 1000
    patterns the Jacobian takes ~0.2 ms, against ~0.35-0.6 ms for a per-pattern
    SX function mapped over the patterns (building either takes ~10 ms).
    """
    key = (hidden, n)
    if key not in _CASADI_CACHE:
        import casadi as ca

        theta = ca.MX.sym("theta", 4 * hidden + 1)
        x = ca.MX.sym("xn", 2, n)
        t = ca.MX.sym("tn", 1, n)
        w1 = ca.reshape(theta[:2 * hidden], 2, hidden).T  # row-major (H, 2), see _pack
        b1 = theta[2 * hidden:3 * hidden]
        w2 = theta[3 * hidden:4 * hidden]
        r = (w2.T @ ca.tanh(w1 @ x + ca.repmat(b1, 1, n)) + theta[4 * hidden] - t).T
        fr = ca.Function("residuals", [theta, x, t], [r])
        frj = ca.Function("residuals_jacobian", [theta, x, t], [r, ca.jacobian(r, theta)])
        if len(_CASADI_CACHE) > 16:
            _CASADI_CACHE.clear()
        _CASADI_CACHE[key] = (fr, frj)
    return _CASADI_CACHE[key]


def train_casadi(tm, omega, target, *, hidden: int = 4, restarts: int = 3,
                 max_iterations: int = 200, tolerance: float = 1e-10,
                 rng: np.random.Generator, metadata: dict | None = None) -> TrainingResult:
    """Second-order trainer: Levenberg-Marquardt on the least-squares objective.

    Minimises ``0.5*sum_i (yn_i - tn_i)^2`` over the 4H+1 weights (same scaling
    as :func:`train_backprop`).  The residuals and their exact Jacobian are a
    CasADi expression graph (algorithmic differentiation over all patterns);
    each iteration solves ``(J'J + mu*I) d = -J'r`` and updates the damping
    ``mu`` with Nielsen's gain-ratio rule (Madsen, Nielsen & Tingleff, 2004).
    Several seeded starting points are run and the best net is kept.

    Parameters
    ----------
    tm, omega, target : array_like
        1-D patterns: motor torque [N*m], velocity [rad/s], friction [N*m].
    hidden : int
        Hidden units H.
    restarts : int
        Number of independent starting points, >= 1.
    max_iterations : int
        Iteration limit per start.
    tolerance : float
        Stop a start when the relative decrease of the loss over an accepted
        step, or the gradient's infinity norm relative to the loss, falls below
        this [-].
    rng : numpy.random.Generator
        Source of the initial weights.
    metadata : dict, optional
        Extra JSON-serialisable entries stored with the net.

    Returns
    -------
    TrainingResult
        ``(net, history)``; history entries are LM iterations (accepted or
        rejected steps), the loss being the best so far over all starts.

    Notes
    -----
    Why LM and not IPOPT: with 17 unknowns the normal equations cost nothing,
    LM needs no line search or barrier, and it is the standard trainer for small
    networks (Hagan & Menhaj, 1994).  No regularisation, so with few patterns the
    net can over-fit; check held-out patterns with :func:`fit_report`.

    Examples
    --------
    >>> tm, om, f = smooth_friction_patterns(np.random.default_rng(0), n_sliding=200, n_stuck=0)
    >>> net, hist = train_casadi(tm, om, f, restarts=1, rng=np.random.default_rng(1))
    >>> fit_percent(f, net(tm, om)) > 99
    True
    """
    tm, omega, target = _patterns(tm, omega, target)
    hidden = _check_hidden(hidden)
    _check_rng(rng)
    for name, v in (("restarts", restarts), ("max_iterations", max_iterations)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 1:
            raise ValueError(f"{name} must be an integer >= 1, got {v!r}")
    tol = _real(tolerance, "tolerance")
    if not tol > 0:
        raise ValueError(f"tolerance must be > 0, got {tolerance!r}")
    n = tm.size
    p = 4 * hidden + 1
    rng_state = rng.bit_generator.state
    scaling = _scaling(tm, omega, target)
    xn, tn = _scaled(tm, omega, target, scaling)

    t0 = time.perf_counter()
    fr, frj = _casadi_functions(hidden, n)
    # CasADi's copy-free buffer interface: the Functions read and write these
    # numpy arrays in place (CasADi is column-major: the 2xN input is the
    # row-major (N, 2) array, the N x p Jacobian the row-major (p, N) array J').
    theta_buf = np.zeros(p)
    x_buf = np.ascontiguousarray(xn.T)
    t_buf = np.ascontiguousarray(tn)
    r_buf = np.zeros(n)
    jt_buf = np.zeros((p, n))
    runs = []
    for fun, outs in ((fr, (r_buf,)), (frj, (r_buf, jt_buf))):
        buf, run = fun.buffer()
        for i, a in enumerate((theta_buf, x_buf, t_buf)):
            buf.set_arg(i, memoryview(a.reshape(-1)))
        for i, a in enumerate(outs):
            buf.set_res(i, memoryview(a.reshape(-1)))
        runs.append((buf, run))  # keep buf alive with its run
    run_r, run_rj = runs[0][1], runs[1][1]

    loss_hist = []
    elapsed = []
    best_cost, best_theta = math.inf, None
    iterations = []
    for _ in range(restarts):
        theta = _initial_theta(hidden, rng)
        theta_buf[:] = theta
        run_rj()
        r, jt = r_buf.copy(), jt_buf.copy()
        cost = 0.5 * float(r @ r)
        a = jt @ jt.T
        g = jt @ r
        mu = 1e-3 * float(np.max(np.diag(a)))
        nu = 2.0
        if cost < best_cost:
            best_cost, best_theta = cost, theta.copy()
        loss_hist.append(best_cost)
        elapsed.append(time.perf_counter() - t0)
        it = 0
        while it < max_iterations:
            if np.linalg.norm(g, np.inf) <= tol * max(cost, 1e-300):
                break
            it += 1
            try:
                d = np.linalg.solve(a + mu * np.eye(p), -g)
            except np.linalg.LinAlgError:
                d = None
            accepted = False
            if d is not None and np.all(np.isfinite(d)):
                theta_buf[:] = theta + d
                run_r()
                cost_new = 0.5 * float(r_buf @ r_buf)
                predicted = 0.5 * float(d @ (mu * d - g))  # model decrease, > 0
                rho = (cost - cost_new) / predicted if predicted > 0 else -1.0
                if rho > 0:
                    accepted = True
                    decrease = (cost - cost_new) / max(cost, 1e-300)
                    theta = theta + d
                    run_rj()  # Jacobian only at accepted points
                    r, jt = r_buf.copy(), jt_buf.copy()
                    cost = cost_new
                    a = jt @ jt.T
                    g = jt @ r
                    mu *= max(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3)
                    nu = 2.0
            if not accepted:
                mu *= nu
                nu *= 2.0
            if cost < best_cost:
                best_cost, best_theta = cost, theta.copy()
            loss_hist.append(best_cost)
            elapsed.append(time.perf_counter() - t0)
            if mu > 1e15 or (accepted and decrease < tol):
                break
        iterations.append(it)
    mse = 2.0 * np.asarray(loss_hist) / n * scaling["output_scale"] ** 2
    history = TrainingHistory(trainer="casadi", step="iteration", loss=mse,
                              elapsed=np.asarray(elapsed))
    meta = {"trainer": "casadi", "method": "levenberg-marquardt", "hidden": hidden,
            "restarts": int(restarts), "iterations": iterations, "n_patterns": n,
            "rng_state": rng_state, "train_mse": float(mse[-1])}
    net = _make_net(best_theta, hidden, scaling, meta)
    rep = fit_report(target, net(tm, omega))
    meta.update(fit_percent=rep.fit_percent, r_squared=rep.r_squared)
    meta.update(metadata or {})
    return TrainingResult(net.replace(metadata=meta), history)


# --------------------------------------------------------------------------
# Patterns of a known smooth friction law
# --------------------------------------------------------------------------
def smooth_friction_patterns(rng: np.random.Generator, *, n_sliding: int = 400,
                             n_stuck: int = 100, viscous: float = 0.0169,
                             coulomb: float = 0.144, static: float = 0.18,
                             smoothing_velocity: float = 0.05, omega_max: float = 2.0,
                             inertia: float = 2.865e-3, alpha_max: float = 50.0):
    """Noise-free patterns ``(tm, omega, friction)`` of a known smooth law.

    Sliding patterns: ``omega ~ U(-omega_max, omega_max)``, friction
    ``b*omega + Fc*tanh(omega/v)``, and the motor torque that produced the
    acceleration ``alpha ~ U(-alpha_max, alpha_max)``: ``Tm = friction + I*alpha``.
    Stuck patterns: ``omega = 0``, ``Tm ~ U(-Fs, Fs)`` and friction ``= Tm``
    (the paper's ``Tat = Tm - I*alpha`` with ``alpha = 0``).

    Parameters
    ----------
    rng : numpy.random.Generator
        Source of the samples.
    n_sliding, n_stuck : int
        Numbers of sliding and stuck patterns.
    viscous : float
        b [N*m*s/rad] (paper: 0.0169).
    coulomb : float
        Fc [N*m] (fricctl's assumed 80 % of the static level).
    static : float
        Fs, the range of the stuck torques [N*m] (paper: 0.18).
    smoothing_velocity : float
        v of the tanh smoothing of the Coulomb step [rad/s].
    omega_max : float
        Velocity range [rad/s].
    inertia : float
        I [kg*m^2] (fricctl's derived actuator inertia).
    alpha_max : float
        Acceleration range [rad/s^2].

    Returns
    -------
    tm, omega, friction : numpy.ndarray
        [N*m], [rad/s], [N*m].

    Notes
    -----
    No Stribeck dip, no noise, no estimation error in ``alpha``: this is the
    clean case where the network's only error is its approximation error.
    """
    _check_rng(rng)
    for name, v in (("n_sliding", n_sliding), ("n_stuck", n_stuck)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 0:
            raise ValueError(f"{name} must be an integer >= 0, got {v!r}")
    for name, v in (("viscous", viscous), ("coulomb", coulomb), ("static", static),
                    ("smoothing_velocity", smoothing_velocity), ("omega_max", omega_max),
                    ("inertia", inertia), ("alpha_max", alpha_max)):
        if not _real(v, name) >= 0:
            raise ValueError(f"{name} must be >= 0, got {v!r}")
    if not smoothing_velocity > 0 or not omega_max > 0:
        raise ValueError("smoothing_velocity and omega_max must be > 0 [rad/s]")
    om = rng.uniform(-omega_max, omega_max, n_sliding)
    fr = viscous * om + coulomb * np.tanh(om / smoothing_velocity)
    tm = fr + inertia * rng.uniform(-alpha_max, alpha_max, n_sliding)
    tm_stuck = rng.uniform(-static, static, n_stuck)
    return (np.concatenate([tm, tm_stuck]), np.concatenate([om, np.zeros(n_stuck)]),
            np.concatenate([fr, tm_stuck]))


# --------------------------------------------------------------------------
# C export
# --------------------------------------------------------------------------
def _c(v: float) -> str:
    return format(float(v), ".17g")


def c_source(net: FrictionNet, *, name: str = "fricctl_friction_net") -> str:
    """A self-contained C99 translation unit evaluating ``net``.

    It defines (only ``<math.h>`` needed, link with ``-lm``)::

        double NAME(double tm, double omega, int clip);
        void NAME_batch(const double *tm, const double *omega, double *out,
                        long n, int clip);
        int NAME_outside(double tm, double omega);

    with the weights printed with 17 significant digits (exact round trip of
    IEEE doubles), so the result matches :meth:`FrictionNet.__call__` to the
    rounding of ``tanh`` and of the summation order (about 1e-16 relative).

    Parameters
    ----------
    net : FrictionNet
        The network.
    name : str
        C identifier of the function.

    Examples
    --------
    >>> net = FrictionNet(w1=[[1.0, 0.0]], b1=[0.0], w2=[1.0], b2=0.0,
    ...                   input_offset=[0, 0], input_scale=[1, 1], output_offset=0.0,
    ...                   output_scale=1.0, envelope_low=[-1, -1], envelope_high=[1, 1])
    >>> "double fricctl_friction_net(double tm, double omega, int clip)" in c_source(net)
    True
    """
    if not isinstance(net, FrictionNet):
        raise ValueError(f"c_source needs a FrictionNet, got {type(net).__name__}")
    if not (isinstance(name, str) and name.isidentifier() and name.isascii()):
        raise ValueError(f"name must be a C identifier, got {name!r}")
    h = net.hidden
    arr = lambda a: "{" + ", ".join(_c(v) for v in np.ravel(a)) + "}"  # noqa: E731
    meta = json.dumps({k: net.metadata[k] for k in ("trainer", "hidden", "fit_percent")
                       if k in net.metadata})
    return f"""/* Generated by fricctl.nn.c_source: a 2-{h}-1 friction network, load side, SI.
 * inputs: tm [N*m], omega [rad/s]; output: friction torque estimate [N*m].
 * {meta.replace('*/', '* /')}
 * xn = (x - IN_OFF) / IN_SCALE; h = tanh(W1 xn + B1); y = (W2 . h + B2) * OUT_SCALE + OUT_OFF
 */
#include <math.h>

#define {name.upper()}_HIDDEN {h}

static const double {name}_w1[{h}][2] = {{{", ".join(arr(r) for r in net.w1)}}};
static const double {name}_b1[{h}] = {arr(net.b1)};
static const double {name}_w2[{h}] = {arr(net.w2)};
static const double {name}_b2 = {_c(net.b2)};
static const double {name}_in_off[2] = {arr(net.input_offset)};
static const double {name}_in_scale[2] = {arr(net.input_scale)};
static const double {name}_out_off = {_c(net.output_offset)};
static const double {name}_out_scale = {_c(net.output_scale)};
static const double {name}_env_low[2] = {arr(net.envelope_low)};
static const double {name}_env_high[2] = {arr(net.envelope_high)};

int {name}_outside(double tm, double omega)
{{
    return tm < {name}_env_low[0] || tm > {name}_env_high[0]
        || omega < {name}_env_low[1] || omega > {name}_env_high[1];
}}

double {name}(double tm, double omega, int clip)
{{
    if (clip) {{
        if (tm < {name}_env_low[0]) tm = {name}_env_low[0];
        if (tm > {name}_env_high[0]) tm = {name}_env_high[0];
        if (omega < {name}_env_low[1]) omega = {name}_env_low[1];
        if (omega > {name}_env_high[1]) omega = {name}_env_high[1];
    }}
    const double x0 = (tm - {name}_in_off[0]) / {name}_in_scale[0];
    const double x1 = (omega - {name}_in_off[1]) / {name}_in_scale[1];
    double yn = 0.0;
    for (int j = 0; j < {h}; ++j) {{
        yn += {name}_w2[j] * tanh({name}_w1[j][0] * x0 + {name}_w1[j][1] * x1 + {name}_b1[j]);
    }}
    return (yn + {name}_b2) * {name}_out_scale + {name}_out_off;
}}

void {name}_batch(const double *tm, const double *omega, double *out, long n, int clip)
{{
    for (long i = 0; i < n; ++i) out[i] = {name}(tm[i], omega[i], clip);
}}
"""
