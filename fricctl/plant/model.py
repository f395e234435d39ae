"""The joint model a diagnosis, a design or a simulation reads: :class:`JointModel` and its file.

Model file format (JSON, version 1)
-----------------------------------
::

    {"format": "fricctl.joint_model", "version": 1,
     "units": "rotary",                       # or "linear" (kg, N*s/m, N, m)
     "inertia": 0.00745,                      # total inertia I [kg*m^2]
     "friction": {"viscous_pos": 0.0169, "viscous_neg": 0.0169,
                  "coulomb_pos": 0.144, "coulomb_neg": 0.144},   # FrictionModel fields
     "offset": 0.0,                           # constant resistive torque [N*m]
     "delay": 0.0,                            # torque acts this much later [s]
     "load_inertia": 0.0, "stiffness": 0.0, "damping": 0.0,     # elastic joint (Eq. 1)
     "source": "free text"}

``friction`` holds any fields of :class:`fricctl.friction.FrictionModel`
(missing ones take its defaults; unknown ones are an error).  ``load_inertia > 0``
makes the joint elastic: the part ``load_inertia`` of ``inertia`` sits behind a
spring ``stiffness`` [N*m/rad] with damping ``damping`` [N*m*s/rad]; the encoder
and the friction are on the motor side.  Unknown keys, a missing key, another
format or version are errors.  No pickle.

"""

from __future__ import annotations

import json
from dataclasses import dataclass, fields
from pathlib import Path

from .. import _validate as v
from ..friction import DEFAULTS as FRICTION_DEFAULTS
from ..friction import FrictionModel
from ..units import KINDS
from .joints import FlexibleJoint, RigidJoint

__all__ = ["JointModel", "MODEL_FORMAT", "MODEL_VERSION"]

MODEL_FORMAT = "fricctl.joint_model"
MODEL_VERSION = 1


@dataclass(frozen=True, kw_only=True)
class JointModel:
    """A joint model the diagnosis simulates: inertia, friction, offset, delay, elasticity.

    Parameters
    ----------
    inertia : float
        Total inertia I (motor side + load) [kg*m^2] ([kg] for a linear axis).
    friction : FrictionModel
        Resistive torque law (motor side).
    offset : float
        Constant resistive torque [N*m]: the joint receives ``Tm - offset``.
    delay : float
        The joint receives the recorded torque this much later [s]; applied as
        the nearest whole number of samples.
    load_inertia : float
        0 for a rigid joint; else the part of ``inertia`` behind the spring [kg*m^2].
    stiffness : float
        Joint stiffness K of the elastic joint [N*m/rad] (> 0 when load_inertia > 0).
    damping : float
        Structural damping across the spring [N*m*s/rad].
    units : {"rotary", "linear"}
        Labels only.
    source : str
        Where the model comes from.

    Examples
    --------
    >>> from fricctl.friction import Viscous, Coulomb
    >>> m = JointModel(inertia=0.00745, friction=(Viscous(0.0169) + Coulomb(0.144)).model())
    >>> JointModel.from_json(m.to_json()) == m
    True
    """

    inertia: float
    friction: FrictionModel
    offset: float = 0.0
    delay: float = 0.0
    load_inertia: float = 0.0
    stiffness: float = 0.0
    damping: float = 0.0
    units: str = "rotary"
    source: str = ""

    def __post_init__(self):
        for name, kw in (("inertia", dict(positive=True)), ("offset", {}),
                         ("delay", dict(nonneg=True)), ("load_inertia", dict(nonneg=True)),
                         ("stiffness", dict(nonneg=True)), ("damping", dict(nonneg=True))):
            object.__setattr__(self, name, v.real(name, getattr(self, name), **kw))
        v.instance("friction", self.friction, FrictionModel, "a fricctl.friction.FrictionModel")
        if self.load_inertia > 0:
            if not self.load_inertia < self.inertia:
                raise ValueError("load_inertia must be < inertia (the motor side needs inertia too)")
            if not self.stiffness > 0:
                raise ValueError("an elastic joint (load_inertia > 0) needs stiffness > 0")
            if self.friction.is_lugre:
                raise ValueError("LuGre friction is supported on the rigid joint only")
        v.choice("units", self.units, KINDS)
        v.text("source", self.source)

    @property
    def elastic(self) -> bool:
        """True for the elastic joint of paper Eq. 1."""
        return self.load_inertia > 0

    def delay_samples(self, sample_time: float) -> int:
        """The delay as a whole number of samples of ``sample_time`` [s]."""
        return int(round(self.delay / v.real("sample_time", sample_time, positive=True)))

    def joint(self):
        """The :class:`~fricctl.plant.RigidJoint` or :class:`~fricctl.plant.FlexibleJoint`."""
        if self.elastic:
            return FlexibleJoint(motor_inertia=self.inertia - self.load_inertia,
                                 load_inertia=self.load_inertia, stiffness=self.stiffness,
                                 damping=self.damping, friction=self.friction)
        return RigidJoint(inertia=self.inertia, friction=self.friction)

    def parameters(self) -> dict:
        """Flat parameter dict (JSON-ready): the non-default values only."""
        out = {"inertia": self.inertia}
        out.update(self.friction.changed())
        for name in ("offset", "delay", "load_inertia", "stiffness", "damping"):
            if getattr(self, name) != 0.0:
                out[name] = getattr(self, name)
        return {k: float(x) for k, x in out.items()}

    def as_dict(self) -> dict:
        """The JSON file content (format ``fricctl.joint_model``, version 1)."""
        return {"format": MODEL_FORMAT, "version": MODEL_VERSION, "units": self.units,
                "inertia": self.inertia, "friction": self.friction.as_dict(),
                "offset": self.offset, "delay": self.delay, "load_inertia": self.load_inertia,
                "stiffness": self.stiffness, "damping": self.damping, "source": self.source}

    def to_json(self) -> str:
        return json.dumps(self.as_dict(), indent=2)

    def save(self, path) -> Path:
        """Write the JSON file; returns the path."""
        path = Path(path)
        path.write_text(self.to_json() + "\n")
        return path

    @classmethod
    def from_dict(cls, d: dict) -> "JointModel":
        if not isinstance(d, dict):
            raise ValueError("model file: expected a JSON object")
        if d.get("format") != MODEL_FORMAT:
            raise ValueError(f"model file: 'format' must be {MODEL_FORMAT!r}, got {d.get('format')!r}")
        if d.get("version") != MODEL_VERSION:
            raise ValueError(f"model file: unsupported version {d.get('version')!r} "
                             f"(this fricctl reads version {MODEL_VERSION})")
        keys = {f.name for f in fields(cls)} | {"format", "version"}
        unknown = sorted(set(d) - keys)
        if unknown:
            raise ValueError(f"model file: unknown key(s) {', '.join(unknown)}")
        for req in ("inertia", "friction"):
            if req not in d:
                raise ValueError(f"model file: missing key {req!r}")
        fr = d["friction"]
        if not isinstance(fr, dict):
            raise ValueError("model file: 'friction' must be an object of FrictionModel fields")
        for k, x in fr.items():
            if k in FRICTION_DEFAULTS:
                v.real(f"friction.{k}", x)
        kw = {k: v for k, v in d.items() if k not in ("format", "version")}
        kw["friction"] = FrictionModel.from_dict(fr)
        return cls(**kw)

    @classmethod
    def from_json(cls, text: str) -> "JointModel":
        try:
            d = json.loads(text)
        except json.JSONDecodeError as exc:
            raise ValueError(f"model file: not valid JSON ({exc.msg} at line {exc.lineno})") from None
        return cls.from_dict(d)

    @classmethod
    def load(cls, path) -> "JointModel":
        """Read a model file (raises FileNotFoundError / ValueError naming the problem)."""
        path = Path(path)
        if not path.is_file():
            raise FileNotFoundError(f"{path}: no such model file")
        try:
            return cls.from_json(path.read_text())
        except ValueError as exc:
            raise ValueError(f"{path.name}: {exc}") from None


