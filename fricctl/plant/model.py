"""The model of one actuator that every command reads: :class:`JointModel` and its file.

Model file format (JSON, version 2)
-----------------------------------
::

    {"format": "fricctl.joint_model", "version": 2,
     "units": "linear",                       # or "rotary" (N*m, rad, kg*m^2)
     "inertia": 95.1089,                      # total inertia I [kg*m^2] or mass [kg]
     "friction": {"viscous_pos": 203.5, "viscous_neg": 203.5,
                  "coulomb_pos": 20.39, "coulomb_neg": 20.39},    # FrictionModel fields
     "offset": -3.1648,                       # constant resistive torque [N*m] or force [N]
     "delay": 0.0,                            # torque acts this much later [s]
     "load_inertia": 0.0, "stiffness": 0.0, "damping": 0.0,     # elastic joint (Eq. 1)
     "backlash": 0.0,                         # dead band motor-load, total width [rad] or [m]
                                              # (needs the elastic joint; written when > 0)
     "sample_time": 0.001,                    # Ts of the controller [s], or null
     "encoder_resolution": 5e-08,             # one count [rad] or [m], or null
     "max_torque": null,                      # saturation +-Tmax [N*m] or [N], null = unknown
     "source": "free text",
     "provenance": {"inertia": {"source": "identified", "std": 0.1085, "note": "IDIM-LS"},
                    "friction.coulomb_pos": {"source": "identified", "std": 0.1012,
                                             "note": "coulomb (one level, both directions)"}}}

Required: ``format``, ``version``, ``units``, ``inertia``, ``friction``; the other
keys may be left out (offset, delay and the elastic joint then are 0, sample time,
encoder resolution and torque limit unknown, no provenance).  ``friction`` holds
any fields of :class:`fricctl.friction.FrictionModel` (missing ones take its
defaults).  ``load_inertia > 0`` makes the joint elastic: the part
``load_inertia`` of ``inertia`` sits behind a spring ``stiffness`` with damping
``damping``; the encoder and the friction are on the motor side.  ``backlash > 0``
(version 2 only; needs the elastic joint) opens a dead band of that total width between
motor and load: the spring (then the stiffness of the contact) acts on the dead-zoned
deflection and the damping only in contact.

``provenance`` says, per value, where it comes from: its keys are the names above
(``"inertia"``, ``"max_torque"``, ...) and ``"friction.<field>"``; each entry has a
``source`` (one of :data:`PROVENANCE_SOURCES`), an optional standard deviation
``std`` (same unit as the value, or null) and an optional ``note``.

Version 1 files (no sample time, encoder, torque limit or provenance; ``units``
optional, default rotary) are read too; :meth:`JointModel.save` writes version 2.

Reading is strict: an unknown or missing key, another format or version, a
duplicate key, NaN or Infinity, a boolean or a string where a number is expected,
a number beyond double precision, a non-physical value (negative inertia, ...) or
JSON nested deeper than a model file ever is raise :class:`ValueError` naming
the key.  No pickle: a file is data, never code.
"""

from __future__ import annotations

import math
import json
import types
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Mapping

from .. import _validate as v
from .._atomic import write_text
from ..friction import FIELDS as FRICTION_FIELDS
from ..friction import FrictionModel
from ..units import KINDS
from ..units import units as units_of
from .joints import FlexibleJoint, RigidJoint

__all__ = ["JointModel", "Provenance", "ESTIMATE_FIELDS", "MODEL_FORMAT", "MODEL_VERSION",
           "READ_VERSIONS", "PROVENANCE_SOURCES", "provenance_keys"]

MODEL_FORMAT = "fricctl.joint_model"
#: The version :meth:`JointModel.save` writes.
MODEL_VERSION = 2
#: The versions :meth:`JointModel.load` reads.
READ_VERSIONS = (1, 2)
#: Where a value may come from (the ``source`` of a :class:`Provenance`).
PROVENANCE_SOURCES = ("paper", "datasheet", "identified", "measured", "derived", "assumption",
                      "diagnosed")

#: Numeric top-level keys: (name, check, quantity of fricctl.units.Units or "s").
_NUMBERS = (("inertia", "positive", "inertia"), ("offset", "real", "torque"),
            ("delay", "nonneg", "s"), ("load_inertia", "nonneg", "inertia"),
            ("stiffness", "nonneg", "stiffness"), ("damping", "nonneg", "viscous"),
            ("backlash", "nonneg", "position"))
#: Optional numeric keys (None = unknown).
_OPTIONAL = (("sample_time", "s"), ("encoder_resolution", "position"), ("max_torque", "torque"))
_REQUIRED = ("format", "version", "units", "inertia", "friction")
_KEYS_V1 = ("format", "version", "units", "inertia", "friction", "offset", "delay",
            "load_inertia", "stiffness", "damping", "source")
_KEYS_V2 = _KEYS_V1 + ("backlash",) + tuple(n for n, _ in _OPTIONAL) + ("provenance",)
#: Identified parameter names (fricctl.identify.MODELS) -> the model values they set.
ESTIMATE_FIELDS = {
    "inertia": ("inertia",), "offset": ("offset",),
    "viscous": ("friction.viscous_pos", "friction.viscous_neg"),
    "coulomb": ("friction.coulomb_pos", "friction.coulomb_neg"),
    "viscous_pos": ("friction.viscous_pos",), "viscous_neg": ("friction.viscous_neg",),
    "coulomb_pos": ("friction.coulomb_pos",), "coulomb_neg": ("friction.coulomb_neg",),
    "static": ("friction.stribeck_pos", "friction.stribeck_neg"),
    "stribeck_velocity": ("friction.stribeck_velocity",),
}
#: Deepest nesting a model file has (object > provenance > entry); deeper is refused.
_MAX_DEPTH = 4
#: Longest text a model file holds (a note, a source) [characters].
_MAX_TEXT = 10_000


def provenance_keys() -> tuple[str, ...]:
    """The names a ``provenance`` entry may have: the numeric keys and ``friction.<field>``."""
    return (tuple(n for n, _, _ in _NUMBERS) + tuple(n for n, _ in _OPTIONAL)
            + tuple(f"friction.{f}" for f in FRICTION_FIELDS))


@dataclass(frozen=True, kw_only=True)
class Provenance:
    """Where one value of a model comes from.

    Examples
    --------
    >>> Provenance(source="identified", std=0.1085, note="IDIM-LS")
    Provenance(source='identified', std=0.1085, note='IDIM-LS')
    """

    source: str
    """One of :data:`PROVENANCE_SOURCES`."""
    std: float | None = None
    """Standard deviation of the value, same unit (None: not known)."""
    note: str = ""
    """How the value was obtained (free text)."""

    def __post_init__(self):
        v.choice("source", self.source, PROVENANCE_SOURCES)
        if self.std is not None:
            object.__setattr__(self, "std", v.real("std", self.std, nonneg=True))
        v.text("note", self.note)

    def as_dict(self) -> dict:
        """The file's entry ``{"source", "std", "note"}``."""
        return {"source": self.source, "std": self.std, "note": self.note}


@dataclass(frozen=True, kw_only=True)
class JointModel:
    """One actuator: inertia, friction, offset, delay, elasticity, sampling, encoder, limit.

    Parameters
    ----------
    inertia : float
        Total inertia I (motor side + load) [kg*m^2] ([kg] for a linear axis).
    friction : FrictionModel
        Resistive torque law (motor side).
    offset : float
        Constant resistive torque [N*m]: the joint receives ``Tm - offset``.
    delay : float
        The joint receives the commanded torque this much later [s]; applied as
        the nearest whole number of samples.
    load_inertia : float
        0 for a rigid joint; else the part of ``inertia`` behind the spring [kg*m^2].
    stiffness : float
        Joint stiffness K of the elastic joint [N*m/rad] (> 0 when load_inertia > 0, 0
        when it is 0: a rigid joint has no spring).
    damping : float
        Structural damping across the spring [N*m*s/rad] (0 on a rigid joint).
    backlash : float
        Total width of the dead band between motor and load, load side [rad] ([m] on a
        linear axis); 0 for none.  Needs the elastic joint (``load_inertia > 0``): the
        spring is then the contact's stiffness, acting on the dead-zoned deflection, the
        damping acts only in contact; a rigid joint with backlash is an elastic joint with a
        stiff contact.
    units : {"rotary", "linear"}
        Rotary joint (N*m, rad) or linear axis (N, m, kg).
    source : str
        Where the model comes from.
    sample_time : float or None
        Sample time Ts of the controller, within
        :data:`fricctl._validate.SAMPLE_TIME_RANGE` (1 ns to an hour) [s]; None when not known.
    encoder_resolution : float or None
        One encoder count, load side, at most one revolution (2*pi rad) on a rotary joint
        [rad] or [m]; None when not known.
    max_torque : float or None
        Torque (force) saturation +-Tmax [N*m] or [N]; None when not known.
    provenance : mapping of str to Provenance
        Where each value comes from (keys: :func:`provenance_keys`).

    Notes
    -----
    A model has no controller and no compensator: those are the design's and the
    simulation's.  Temperature and motor electrical dynamics are left out.

    Examples
    --------
    >>> from fricctl.friction import Viscous, Coulomb
    >>> m = JointModel(inertia=0.00745, friction=(Viscous(0.0169) + Coulomb(0.144)).model(),
    ...                sample_time=0.002, provenance={"inertia": Provenance(source="derived")})
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
    backlash: float = 0.0
    units: str = "rotary"
    source: str = ""
    sample_time: float | None = None
    encoder_resolution: float | None = None
    max_torque: float | None = None
    provenance: Mapping[str, Provenance] = field(default_factory=dict, hash=False)

    def __post_init__(self):
        v.choice("units", self.units, KINDS)
        labels = units_of(self.units)
        for name, check, quantity in _NUMBERS:
            unit = "s" if quantity == "s" else getattr(labels, quantity)
            kw = {"positive": check == "positive", "nonneg": check == "nonneg"}
            object.__setattr__(self, name, v.real(name, getattr(self, name), unit=unit, **kw))
        for name, quantity in _OPTIONAL:
            x = getattr(self, name)
            if x is not None:
                unit = "s" if quantity == "s" else getattr(labels, quantity)
                object.__setattr__(self, name, v.real(name, x, positive=True, unit=unit))
        if self.sample_time is not None:
            object.__setattr__(self, "sample_time", v.sample_time("sample_time", self.sample_time))
        if (self.units == "rotary" and self.encoder_resolution is not None
                and self.encoder_resolution > 2 * math.pi):
            raise ValueError(f"encoder_resolution must be at most one revolution (2*pi rad) on a "
                             f"rotary joint, got {self.encoder_resolution!r} rad")
        v.instance("friction", self.friction, FrictionModel, "a fricctl.friction.FrictionModel")
        if self.load_inertia == 0:  # rigid: a spring or its damping would be silently ignored
            for name in ("stiffness", "damping"):
                if getattr(self, name) > 0:
                    raise ValueError(f"{name}: a spring needs a load behind it (load_inertia > "
                                     f"0, the part of the inertia beyond the spring); a rigid "
                                     f"joint has {name} 0")
        if self.load_inertia > 0:
            if not self.load_inertia < self.inertia:
                raise ValueError("load_inertia must be < inertia (the motor side needs inertia too)")
            if not self.stiffness > 0:
                raise ValueError("stiffness: an elastic joint (load_inertia > 0) needs stiffness > 0")
            if self.friction.has_state:
                raise ValueError(f"friction: {self.friction.state_law.constructor.__name__} friction "
                                 "is supported on the rigid joint only")
        elif self.backlash > 0:
            raise ValueError("backlash: a dead band needs a load behind it (load_inertia > 0, "
                             "stiffness > 0: the contact's stiffness)")
        v.text("source", self.source)
        v.instance("provenance", self.provenance, (dict, types.MappingProxyType), "a mapping")
        allowed = provenance_keys()
        for key, entry in self.provenance.items():
            v.choice("provenance key", key, allowed)
            v.instance(f"provenance[{key!r}]", entry, Provenance, "a Provenance")
        ordered = {k: self.provenance[k] for k in allowed if k in self.provenance}
        object.__setattr__(self, "provenance", types.MappingProxyType(ordered))

    # ------------------------------------------------------------------ physics
    @property
    def elastic(self) -> bool:
        """True for the elastic joint of paper Eq. 1."""
        return self.load_inertia > 0

    @property
    def viscous(self) -> float:
        """The one viscous coefficient of a linear design model: the mean of both directions,
        times the friction scale [N*m*s/rad] or [N*s/m]."""
        return self.friction.scale * 0.5 * (self.friction.viscous_pos + self.friction.viscous_neg)

    @property
    def velocity_quantum(self) -> float | None:
        """One encoder count per sample, ``encoder_resolution / sample_time`` [rad/s] or [m/s];
        None when either is unknown."""
        if self.encoder_resolution is None or self.sample_time is None:
            return None
        return self.encoder_resolution / self.sample_time

    def delay_samples(self, sample_time: float) -> int:
        """The delay as a whole number of samples of ``sample_time`` [s]."""
        ts = v.real("sample_time", sample_time, positive=True)
        n = self.delay / ts
        if n > 1e6:
            raise ValueError(f"delay: {self.delay:g} s is {n:.3g} samples of {ts:g} s "
                             f"(more than 1e6): not a drive delay")
        return int(round(n))

    def joint(self):
        """The :class:`~fricctl.plant.RigidJoint` or :class:`~fricctl.plant.FlexibleJoint`."""
        if self.elastic:
            return FlexibleJoint(motor_inertia=self.inertia - self.load_inertia,
                                 load_inertia=self.load_inertia, stiffness=self.stiffness,
                                 damping=self.damping, friction=self.friction,
                                 backlash=self.backlash)
        return RigidJoint(inertia=self.inertia, friction=self.friction)

    def parameters(self) -> dict:
        """Flat parameter dict (JSON-ready): the non-default physical values only."""
        out = {"inertia": self.inertia}
        out.update(self.friction.changed())
        for name in ("offset", "delay", "load_inertia", "stiffness", "damping", "backlash"):
            if getattr(self, name) != 0.0:
                out[name] = getattr(self, name)
        return {k: float(x) for k, x in out.items()}

    # ------------------------------------------------------------------ building
    @classmethod
    def from_params(cls, params, *, source: str, plant: str = "rigid") -> "JointModel":
        """The model of an :class:`~fricctl.params.ActuatorParams`, with its provenance.

        Parameters
        ----------
        params : fricctl.params.ActuatorParams
            Actuator (load side).
        source : str
            The model's ``source`` text.
        plant : {"rigid", "flexible"}
            Rigid joint of inertia ``total_inertia``, or the elastic joint of Eq. 1
            (needs ``link_inertia > 0``: the link sits behind the spring).

        Notes
        -----
        Each provenance entry names the field of ``ActuatorParams`` it comes from and
        takes that field's source tag; a value computed from two fields is ``derived``.

        Examples
        --------
        >>> from fricctl.params import paper_actuator
        >>> m = JointModel.from_params(paper_actuator(), source="paper")
        >>> round(m.friction.breakaway(+1), 3), m.provenance["friction.viscous_pos"].source
        (0.18, 'paper')
        """
        from ..params import ActuatorParams

        v.instance("params", params, ActuatorParams, "an ActuatorParams")
        v.choice("plant", plant, ("rigid", "flexible"))
        if plant == "flexible" and not params.link_inertia > 0:
            raise ValueError("plant='flexible' needs link_inertia > 0 (the load behind the spring)")

        def of(name, note=""):
            return Provenance(source=params.source(name), note=f"ActuatorParams.{name}" + note)

        derived = Provenance(source="derived", note="ActuatorParams.static - .coulomb "
                             "(the breakaway excess over the Coulomb level)")
        prov = {"inertia": of("inertia", " + .link_inertia" if params.link_inertia else ""),
                "sample_time": of("sample_time"), "max_torque": of("max_torque"),
                "encoder_resolution": Provenance(
                    source="derived", note="2*pi / (ActuatorParams.encoder_counts * .gear_ratio)")}
        for d in ("pos", "neg"):
            prov[f"friction.viscous_{d}"] = of("viscous")
            prov[f"friction.coulomb_{d}"] = of("coulomb")
            prov[f"friction.stribeck_{d}"] = derived
        prov["friction.stribeck_velocity"] = of("stribeck_velocity")
        elastic = {}
        if plant == "flexible":
            elastic = dict(load_inertia=params.link_inertia, stiffness=params.stiffness,
                           damping=params.joint_damping)
            prov.update(load_inertia=of("link_inertia"), stiffness=of("stiffness"),
                        damping=of("joint_damping"))
        return cls(inertia=params.total_inertia, friction=params.friction_model(),
                   units="rotary", source=source, sample_time=params.sample_time,
                   encoder_resolution=params.encoder_resolution, max_torque=params.max_torque,
                   provenance=prov, **elastic)

    @classmethod
    def from_estimates(cls, estimates: Mapping[str, float], *, units: str, source: str,
                       std: Mapping[str, float] | None = None, note: str = "",
                       sample_time: float | None = None, encoder_resolution: float | None = None,
                       max_torque: float | None = None,
                       provenance: Mapping[str, Provenance] | None = None) -> "JointModel":
        """The rigid-joint model of identified parameters, each with its standard deviation.

        Parameters
        ----------
        estimates : mapping
            Parameter name -> value, with the names of :data:`fricctl.identify.MODELS`:
            ``inertia`` (required), ``offset``, ``viscous`` and ``coulomb`` (both
            directions), ``viscous_pos``/``_neg``, ``coulomb_pos``/``_neg``, ``static``
            and ``stribeck_velocity`` (a Gaussian Stribeck excess ``static - coulomb``).
        units : {"rotary", "linear"}
        source : str
            The model's ``source`` text.
        std : mapping, optional
            Name -> standard deviation (same names).
        note : str
            Provenance note of every identified value (how it was identified).
        sample_time, encoder_resolution, max_torque : float, optional
            [s], [rad] or [m], [N*m] or [N]; None = unknown.
        provenance : mapping, optional
            Provenance of ``sample_time``, ``encoder_resolution``, ``max_torque``.

        Examples
        --------
        >>> m = JointModel.from_estimates({"inertia": 95.1, "viscous": 203.5, "coulomb": 20.4,
        ...                                "offset": -3.2}, std={"coulomb": 0.1}, units="linear",
        ...                                source="EMPS")
        >>> m.friction.coulomb_neg, m.provenance["friction.coulomb_neg"].std
        (20.4, 0.1)
        """
        v.instance("estimates", estimates, Mapping, "a mapping of parameter names to values")
        std = {} if std is None else dict(v.instance("std", std, Mapping, "a mapping"))
        unknown = sorted(set(estimates) - set(ESTIMATE_FIELDS))
        if unknown or "inertia" not in estimates:
            raise ValueError(f"estimates: need 'inertia', may have {', '.join(ESTIMATE_FIELDS)}; "
                             f"unknown {unknown}")
        x = {k: v.real(f"estimates[{k!r}]", val) for k, val in estimates.items()}
        if "static" in x:
            fc = x.get("coulomb", 0.0)
            if x["static"] < fc:
                raise ValueError(f"static: the identified breakaway level {x['static']:.4g} lies "
                                 f"below the Coulomb level {fc:.4g}")
            x["static"] -= fc  # the Stribeck excess over the Coulomb level
        fr, prov = {}, dict(provenance or {})
        for name, value in x.items():
            for key in ESTIMATE_FIELDS[name]:
                s = std.get(name) if name != "static" else None
                n = note + (" (static - coulomb; the std of static is "
                            f"{std['static']:.4g})" if name == "static" and "static" in std else "")
                prov[key] = Provenance(source="identified", std=s, note=n)
                if key.startswith("friction."):
                    fr[key[len("friction."):]] = value
        return cls(inertia=x["inertia"], offset=x.get("offset", 0.0), friction=FrictionModel(**fr),
                   units=units, source=source, sample_time=sample_time,
                   encoder_resolution=encoder_resolution, max_torque=max_torque, provenance=prov)

    # ------------------------------------------------------------------ file
    def as_dict(self) -> dict:
        """The JSON file content (format ``fricctl.joint_model``, version 2)."""
        # backlash is written only when there is one: files of joints without keep the
        # content they had before the key existed (and stay readable by older versions)
        gap = {"backlash": self.backlash} if self.backlash > 0 else {}
        return {"format": MODEL_FORMAT, "version": MODEL_VERSION, "units": self.units,
                "inertia": self.inertia, "friction": self.friction.changed(),
                "offset": self.offset, "delay": self.delay, "load_inertia": self.load_inertia,
                "stiffness": self.stiffness, "damping": self.damping, **gap,
                "sample_time": self.sample_time, "encoder_resolution": self.encoder_resolution,
                "max_torque": self.max_torque, "source": self.source,
                "provenance": {k: p.as_dict() for k, p in self.provenance.items()}}

    def to_json(self) -> str:
        """:meth:`as_dict` as indented JSON (never NaN or Infinity)."""
        return json.dumps(self.as_dict(), indent=2, allow_nan=False)

    def save(self, path, *, overwrite: bool = True) -> Path:
        """Write the JSON file; returns the path.

        Parameters
        ----------
        path : str or os.PathLike
            Destination.
        overwrite : bool
            False: refuse (:class:`FileExistsError`) when ``path`` exists, also when another
            process creates it while this one writes (the file is written atomically:
            :mod:`fricctl._atomic`).
        """
        path = Path(path)
        if not v.flag("overwrite", overwrite) and path.exists():
            raise FileExistsError(17, "already exists (not overwritten)", str(path))
        return write_text(path, self.to_json() + "\n", overwrite=overwrite)

    @classmethod
    def from_dict(cls, d: dict) -> "JointModel":
        """The model of a parsed file (version 1 or 2); every problem is a ValueError naming the key."""
        if not isinstance(d, dict):
            raise ValueError("model file: expected a JSON object")
        if d.get("format") != MODEL_FORMAT:
            start = (f"missing key 'format'" if "format" not in d
                     else f"format: must be {MODEL_FORMAT!r}, got {d['format']!r}")
            raise ValueError(f"{start}: a model file starts {{\"format\": \"{MODEL_FORMAT}\", "
                             f"\"version\": {MODEL_VERSION}, \"units\": ...}} ({_WHERE})")
        version = d.get("version")
        if "version" not in d:
            raise ValueError(f"missing key 'version' ({MODEL_VERSION} for the format this "
                             f"fricctl writes; {_WHERE})")
        if type(version) is not int or version not in READ_VERSIONS:
            raise ValueError(f"version: unsupported {version!r} (this fricctl reads versions "
                             f"{', '.join(map(str, READ_VERSIONS))})")
        allowed = _KEYS_V1 if version == 1 else _KEYS_V2
        unknown = sorted(set(d) - set(allowed))
        if unknown:
            raise ValueError(f"unknown key(s) {_with_hints(unknown, allowed, top=True)} in a "
                             f"version {version} model file ({_WHERE})")
        required = ("format", "version", "inertia", "friction") if version == 1 else _REQUIRED
        for req in required:
            if req not in d:
                raise ValueError(f"missing key {req!r}")
        kw = {"units": d.get("units", "rotary")}
        if not isinstance(kw["units"], str) or kw["units"] not in KINDS:
            raise ValueError(f"units: must be one of {', '.join(map(repr, KINDS))}, "
                             f"got {kw['units']!r}")
        for name, _, _ in _NUMBERS:
            if name in d:
                kw[name] = v.real(name, d[name])
        for name, _ in _OPTIONAL:
            if d.get(name) is not None:
                try:
                    kw[name] = v.real(name, d[name])
                except ValueError as exc:
                    raise ValueError(f"{exc} (or null when unknown)") from None
        if "source" in d:
            kw["source"] = _text("source", d["source"])
        kw["friction"] = _friction(d["friction"])
        if "provenance" in d:
            kw["provenance"] = _provenance(d["provenance"])
        return cls(**kw)

    @classmethod
    def from_json(cls, text: str) -> "JointModel":
        """Parse a model file's text strictly (duplicate keys, NaN, deep nesting are errors)."""
        v.text("text", text)
        return cls.from_dict(v.strict_json(text, max_depth=_MAX_DEPTH))

    @classmethod
    def load(cls, path) -> "JointModel":
        """Read a model file (raises FileNotFoundError / ValueError naming the file and key)."""
        return v.json_file(path, "model file", cls.from_json)


# ---------------------------------------------------------------------- reading helpers
def _text(name, x) -> str:
    v.text(name, x)
    if len(x) > _MAX_TEXT:
        raise ValueError(f"{name}: longer than {_MAX_TEXT} characters")
    return x


#: Where a reader of an error finds every key of the file.
_WHERE = "every key: docs/model_file.md; `fricctl model new` writes a file from numbers"


def _with_hints(keys, known, *, top: bool) -> str:
    """``'viscous' (...), 'sampletime' (did you mean 'sample_time'?)``: each unknown key with
    where it belongs, or the known key it is close to.  A friction coefficient given at the top
    level belongs under ``friction``; a direction-dependent one is two magnitudes
    (``viscous_pos``, ``viscous_neg``); ``static``, the breakaway level, is stored as the excess
    over the Coulomb level."""
    from difflib import get_close_matches

    where = "friction." if top else ""
    out = []
    for key in keys:
        if key in ("static", "breakaway", "static_pos", "static_neg"):
            hint = (f"the breakaway level Fs is stored as its excess over the Coulomb level: "
                    f"{where}stribeck_pos and stribeck_neg = Fs - Fc, with stribeck_velocity")
        elif f"{key}_pos" in FRICTION_FIELDS and f"{key}_neg" in FRICTION_FIELDS:
            hint = (f"per direction, two positive magnitudes: {where}{key}_pos and "
                    f"{where}{key}_neg")
        elif top and key in FRICTION_FIELDS:
            hint = f"a friction coefficient: it belongs under 'friction'"
        else:
            near = get_close_matches(key, known, n=1)
            hint = f"did you mean {near[0]!r}?" if near else ""
        out.append(f"{key!r}" + (f" ({hint})" if hint else ""))
    return ", ".join(out)


#: Friction fields renamed since the first model files (old name -> name now).
_RENAMED = {"static_pos": "static_excess_pos", "static_neg": "static_excess_neg"}


def _friction(fr) -> FrictionModel:
    if not isinstance(fr, dict):
        raise ValueError("friction: must be an object of FrictionModel fields")
    both = [old for old, new in _RENAMED.items() if old in fr and new in fr]
    if both:
        raise ValueError(f"friction: {both[0]!r} and {_RENAMED[both[0]]!r} are the same field "
                         "(its old and new name); give one")
    fr = {_RENAMED.get(k, k): x for k, x in fr.items()}
    unknown = sorted(set(fr) - set(FRICTION_FIELDS))
    if unknown:
        raise ValueError(f"friction: unknown field(s) "
                         f"{_with_hints(unknown, FRICTION_FIELDS, top=False)}")
    values = {k: v.real(f"friction.{k}", x) for k, x in fr.items()}
    try:
        return FrictionModel(**values)
    except ValueError as exc:
        field_first = str(exc).split(" ", 1)[0] in FRICTION_FIELDS
        raise ValueError(f"friction.{exc}" if field_first else f"friction: {exc}") from None


def _provenance(prov) -> dict:
    if not isinstance(prov, dict):
        raise ValueError("provenance: must be an object {name: {source, std, note}}")
    allowed = provenance_keys()
    out = {}
    for key, entry in prov.items():
        if key not in allowed:
            raise ValueError(f"provenance: unknown value name {key!r} (one of inertia, offset, "
                             f"..., friction.<field>)")
        if not isinstance(entry, dict):
            raise ValueError(f"provenance.{key}: must be an object {{source, std, note}}")
        extra = sorted(set(entry) - {"source", "std", "note"})
        if extra:
            raise ValueError(f"provenance.{key}: unknown key(s) {', '.join(map(repr, extra))}")
        if "source" not in entry:
            raise ValueError(f"provenance.{key}: missing key 'source'")
        try:
            std = entry.get("std")
            out[key] = Provenance(source=entry["source"],
                                  std=None if std is None else v.real("std", std),
                                  note=_text("note", entry.get("note", "")))
        except ValueError as exc:
            raise ValueError(f"provenance.{key}.{exc}") from None
    return out
