"""The paper's 2-H-1 friction network as an immutable object: :class:`FrictionNet`.

Gervini, Gomes & da Rosa (2003) estimate the joint friction torque with a
2-4-1 feed-forward network: inputs the motor torque ``Tm`` and the velocity
``omega``, four ``tanh`` hidden units, a linear output.  Everything is on the
load side of the gear, in SI units: ``Tm`` and the friction torque in [N*m],
``omega`` in [rad/s].  Friction has the sign of the velocity and enters the
joint as ``I*qdd = Tm - Tat``.

The network formula (:mod:`fricctl.nn.layout` holds the compiled-loop and
training versions of the same formula; one test pins all of them together)::

    xn = (x - input_offset) / input_scale        x = (Tm, omega)
    h  = tanh(w1 @ xn + b1)                      w1: (H, 2), b1: (H,)
    yn = w2 . h + b2                             w2: (H,),   b2: scalar
    y  = yn * output_scale + output_offset       [N*m]
"""

from __future__ import annotations

import json
import types
from dataclasses import dataclass, field

import numpy as np

from .. import _validate as v
from ..units import KINDS

__all__ = ["FrictionNet", "ARRAY_FIELDS"]

#: The array fields of a :class:`FrictionNet` with their required shapes
#: (``"H"`` is the number of hidden units, fixed by ``w1``).
ARRAY_FIELDS = (("w1", ("H", 2)), ("b1", ("H",)), ("w2", ("H",)), ("input_offset", (2,)),
                ("input_scale", (2,)), ("envelope_low", (2,)), ("envelope_high", (2,)))


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

    Examples
    --------
    >>> net = FrictionNet(w1=[[1.0, 0.0]], b1=[0.0], w2=[1.0], b2=0.0,
    ...                   input_offset=[0, 0], input_scale=[1, 1], output_offset=0.0,
    ...                   output_scale=2.0, envelope_low=[-1, -1], envelope_high=[1, 1])
    >>> float(net(0.5, 0.0)) == 2.0 * float(np.tanh(0.5))
    True
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
        w1 = v.array("w1", self.w1, ndim=2)
        if w1.shape[1] != 2 or w1.shape[0] < 1:
            raise ValueError(f"w1 must have shape (H, 2) with H >= 1, got {w1.shape}")
        h = w1.shape[0]
        values = {}
        for name, shape in ARRAY_FIELDS:
            a = v.array(name, getattr(self, name), ndim=None,
                        shape=tuple(h if s == "H" else s for s in shape))
            a = np.array(a)  # a copy: the net owns its weights
            a.setflags(write=False)
            values[name] = a
        values["b2"] = v.real("b2", self.b2)
        values["output_offset"] = v.real("output_offset", self.output_offset, unit="N*m")
        values["output_scale"] = v.real("output_scale", self.output_scale, positive=True,
                                        unit="N*m")
        if not np.all(values["input_scale"] > 0):
            raise ValueError(f"input_scale must be > 0, got {values['input_scale']}")
        if not np.all(values["envelope_low"] <= values["envelope_high"]):
            raise ValueError("envelope_low must be <= envelope_high in both Tm and omega, got "
                             f"{values['envelope_low']} and {values['envelope_high']}")
        v.instance("metadata", self.metadata, (dict, types.MappingProxyType), "a dict")
        try:
            meta = json.loads(json.dumps(dict(self.metadata), allow_nan=False))
        except (TypeError, ValueError) as exc:
            raise ValueError(f"metadata must be JSON-serialisable: {exc}") from None
        if "units" in meta:  # the axis it was trained on (fricctl train writes it)
            v.choice("metadata['units']", meta["units"], KINDS)
        values["metadata"] = types.MappingProxyType(meta)
        for name, value in values.items():
            object.__setattr__(self, name, value)

    # -- evaluation --------------------------------------------------------
    @property
    def units(self) -> str:
        """Kind of axis the net was trained on: ``"rotary"`` (Tm [N*m], omega [rad/s]) or
        ``"linear"`` (force [N], velocity [m/s]); ``metadata["units"]``, rotary if absent."""
        return self.metadata["units"] if "units" in self.metadata else "rotary"

    @property
    def hidden(self) -> int:
        """Number of hidden units H."""
        return self.w1.shape[0]

    @property
    def n_parameters(self) -> int:
        """Number of trainable weights and biases, 4*H + 1."""
        return 4 * self.hidden + 1

    def _inputs(self, tm, omega):
        tm = v.array("tm", tm, ndim=None)
        omega = v.array("omega", omega, ndim=None)
        try:
            return np.broadcast_arrays(tm, omega)
        except ValueError:
            raise ValueError(f"tm and omega must have broadcastable shapes, got {tm.shape} "
                             f"and {omega.shape}") from None

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

    # -- JSON (the format itself lives in fricctl.nn.io) ---------------------
    # io builds FrictionNet objects, so it imports this module; these thin
    # methods import io when called, which keeps the import graph one-way.
    def to_dict(self) -> dict:
        """JSON-ready dict with the format name and version (:func:`fricctl.nn.io.net_to_dict`)."""
        from .io import net_to_dict

        return net_to_dict(self)

    @classmethod
    def from_dict(cls, data: dict) -> "FrictionNet":
        """Inverse of :meth:`to_dict`; a wrong format, version or key raises ``ValueError``."""
        from .io import net_from_dict

        return net_from_dict(data)

    def to_json(self) -> str:
        """JSON text; floats are written with round-trip precision."""
        from .io import net_to_json

        return net_to_json(self)

    @classmethod
    def from_json(cls, text: str) -> "FrictionNet":
        """Parse :meth:`to_json` output; malformed text raises ``ValueError``."""
        from .io import net_from_json

        return net_from_json(text)

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
