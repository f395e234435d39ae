"""Actuator parameters: frozen dataclasses, SI units, load side of the gear.

Every field carries its unit in ``metadata["unit"]`` and a provenance tag in
``metadata["source"]``: ``"paper"`` (Gervini, Gomes & da Rosa 2003), ``"derived"``
(computed from paper values, derivation in the docstring) or ``"assumption"``
(not given by the paper; a plausible value for a small harmonic drive).

The paper's facts used here (load side):

* static friction 0.18 N*m, which is 12.7 % of the maximum torque, so the
  maximum torque is 0.18 / 0.127 = 1.417 N*m;
* viscous friction 0.0169 N*m*s/rad;
* sample time 0.002 s (500 Hz, zero-order hold);
* SCARA link inertia 0.0046 kg*m^2 (the "actuator + link" designs of Figs. 16-18).

Rotor-side quantities are converted with :func:`fricctl.units.to_load_side` /
:func:`fricctl.units.to_rotor_side` (inertia and viscous scale with n^2, torques with n).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace

from . import _validate as v

__all__ = [
    "ActuatorParams",
    "PAPER_STATIC_FRICTION",
    "PAPER_STATIC_FRACTION",
    "PAPER_VISCOUS",
    "PAPER_LINK_INERTIA",
    "PAPER_SAMPLE_TIME",
    "paper_actuator",
    "derive_inertia_from_p_design",
]

#: Static (breakaway) friction, load side [N*m]; paper, Sec. 4.
PAPER_STATIC_FRICTION = 0.18
#: Static friction as a fraction of the maximum torque [-]; paper ("12.7 %").
PAPER_STATIC_FRACTION = 0.127
#: Viscous friction coefficient, load side [N*m*s/rad]; paper.
PAPER_VISCOUS = 0.0169
#: Inertia of the SCARA link added in Figs. 16-18 [kg*m^2]; paper.
PAPER_LINK_INERTIA = 0.0046
#: Sample time of the 500 Hz zero-order-hold loop [s]; paper.
PAPER_SAMPLE_TIME = 0.002


def _unit(unit: str, source: str):
    return field(metadata={"unit": unit, "source": source})


def derive_inertia_from_p_design(
    viscous: float = PAPER_VISCOUS, rise_time: float = 0.2, damping: float = 0.3
) -> float:
    r"""Inertia that makes the paper's P design self-consistent.

    The paper designs its P controller (Figs. 11-12) for a rise time of 0.2 s and a
    damping ratio of 0.3 on the linear viscous model ``I*s^2 + b*s + Kp``.  With a
    single gain, both specifications can only hold for one inertia:

    .. math::

        \omega_n = \frac{\pi - \arccos\zeta}{t_r\sqrt{1-\zeta^2}}
        \quad\text{(0-100 % rise time)},\qquad
        2\zeta\omega_n = b / I \;\Rightarrow\; I = \frac{b}{2\zeta\omega_n}.

    With b = 0.0169 N*m*s/rad this gives omega_n = 9.830 rad/s and
    I = 2.865e-3 kg*m^2.

    Parameters
    ----------
    viscous : float
        Viscous coefficient b [N*m*s/rad].
    rise_time : float
        0-100 % rise time of the P design [s].
    damping : float
        Damping ratio of the P design, 0 < zeta < 1 [-].

    Returns
    -------
    float
        Inertia [kg*m^2].

    Examples
    --------
    >>> round(derive_inertia_from_p_design(), 7)
    0.0028653
    """
    if not 0.0 < damping < 1.0:
        raise ValueError(f"damping must lie in (0, 1) for a 0-100 % rise time, got {damping!r}")
    if not rise_time > 0.0:
        raise ValueError(f"rise_time must be > 0 s, got {rise_time!r}")
    wd_tr = math.pi - math.acos(damping)
    wn = wd_tr / (rise_time * math.sqrt(1.0 - damping**2))
    return viscous / (2.0 * damping * wn)


@dataclass(frozen=True, kw_only=True)
class ActuatorParams:
    """Harmonic-drive actuator, rigid or flexible, load side, SI units.

    The defaults are the paper's actuator (see :func:`paper_actuator`).  Friction
    levels here are the nominal friction law of the actuator; the simulator builds
    its :class:`fricctl.friction.FrictionModel` from them
    (:meth:`friction_model`), and any other model can be passed instead.

    Notes
    -----
    Not modelled: motor electrical dynamics (the current loop is taken as ideal, so
    the commanded torque is the motor torque), temperature (except through an
    explicit drift term of the friction model), backlash (a harmonic drive has
    none to speak of).
    """

    inertia: float = _unit("kg*m^2", "derived")
    """Actuator inertia (rotor reflected through n^2, plus flange), load side.
    Derived so that the paper's P design (0.2 s, zeta 0.3) is self-consistent;
    see :func:`derive_inertia_from_p_design`."""

    link_inertia: float = _unit("kg*m^2", "paper")
    """Inertia of the attached link; 0 (no link) by default, 0.0046 for the SCARA link."""

    viscous: float = _unit("N*m*s/rad", "paper")
    """Viscous friction coefficient b."""

    coulomb: float = _unit("N*m", "assumption")
    """Coulomb (sliding) friction level Fc; assumed 80 % of the static level."""

    static: float = _unit("N*m", "paper")
    """Static (breakaway) friction level Fs >= Fc."""

    stribeck_velocity: float = _unit("rad/s", "assumption")
    """Stribeck velocity vs of the exponential decay from Fs to Fc."""

    max_torque: float = _unit("N*m", "derived")
    """Torque saturation +-Tmax = Fs / 0.127."""

    sample_time: float = _unit("s", "paper")
    """Sample time Ts of the zero-order-hold loop (500 Hz)."""

    gear_ratio: float = _unit("-", "assumption")
    """Gear ratio n of the harmonic drive (rotor speed / load speed)."""

    encoder_counts: int = _unit("counts/rev", "assumption")
    """Encoder counts per rotor revolution (500 lines, x4 quadrature)."""

    stiffness: float = _unit("N*m/rad", "assumption")
    """Joint stiffness K of the flexspline (paper Eq. 1), load side."""

    joint_damping: float = _unit("N*m*s/rad", "assumption")
    """Structural damping across the elastic joint (Eq. 1), load side."""

    def __post_init__(self):
        positive = ("inertia", "max_torque", "sample_time", "gear_ratio", "stiffness",
                    "stribeck_velocity")
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "encoder_counts":
                checked = v.integer(f.name, value, low=1)
            elif f.name == "sample_time":
                checked = v.sample_time(f.name, value)
            else:
                checked = v.real(f.name, value, positive=f.name in positive, nonneg=True,
                                 unit=f.metadata["unit"])
            object.__setattr__(self, f.name, checked)
        if self.static < self.coulomb:
            raise ValueError(
                f"static ({self.static} N*m) must be >= coulomb ({self.coulomb} N*m): "
                "breakaway friction cannot be below sliding friction")
        if self.static >= self.max_torque:
            raise ValueError(
                f"static ({self.static} N*m) must be < max_torque ({self.max_torque} N*m), "
                "or the joint can never break loose")

    # -- derived quantities ------------------------------------------------
    @property
    def total_inertia(self) -> float:
        """Inertia seen by the rigid joint, actuator + link [kg*m^2]."""
        return self.inertia + self.link_inertia

    @property
    def encoder_resolution(self) -> float:
        """One encoder count on the load side [rad]: 2*pi / (counts * n)."""
        return 2.0 * math.pi / (self.encoder_counts * self.gear_ratio)

    @classmethod
    def _metadata(cls, name: str) -> dict:
        for f in fields(cls):
            if f.name == name:
                return f.metadata
        raise ValueError(f"unknown ActuatorParams field {name!r}")

    @classmethod
    def unit(cls, name: str) -> str:
        """Unit of field ``name`` (raises ``ValueError`` for an unknown field)."""
        return cls._metadata(name)["unit"]

    @classmethod
    def source(cls, name: str) -> str:
        """Provenance of field ``name``: 'paper', 'derived' or 'assumption'."""
        return cls._metadata(name)["source"]

    def with_link(self, link_inertia: float = PAPER_LINK_INERTIA) -> "ActuatorParams":
        """Copy with the SCARA link attached (0.0046 kg*m^2 by default)."""
        return replace(self, link_inertia=link_inertia)

    def replace(self, **changes) -> "ActuatorParams":
        """Copy with fields changed; unknown names raise ``ValueError``."""
        names = {f.name for f in fields(self)}
        unknown = sorted(set(changes) - names)
        if unknown:
            raise ValueError(f"unknown ActuatorParams field(s): {', '.join(unknown)}")
        return replace(self, **changes)

    def friction_model(self):
        """The nominal friction law: viscous + Coulomb + exponential Stribeck.

        Returns
        -------
        fricctl.friction.FrictionModel
        """
        from .friction import Coulomb, Stribeck, Viscous

        return (Viscous(self.viscous) + Coulomb(self.coulomb)
                + Stribeck(self.static - self.coulomb, self.stribeck_velocity))

    def as_dict(self) -> dict:
        """Field values as a plain dict (JSON-ready)."""
        return {f.name: getattr(self, f.name) for f in fields(self)}


def paper_actuator(**changes) -> ActuatorParams:
    """The paper's harmonic-drive actuator (load side).

    Paper values: viscous 0.0169 N*m*s/rad, static 0.18 N*m (12.7 % of Tmax,
    so Tmax = 1.417 N*m), Ts = 0.002 s.  Derived: inertia 2.865e-3 kg*m^2
    (:func:`derive_inertia_from_p_design`).  Assumptions (labelled): Coulomb
    0.144 N*m (80 % of static), Stribeck velocity 0.02 rad/s, gear ratio 100,
    2000 counts per rotor revolution (3.14e-5 rad per count on the load),
    stiffness K = 2000 N*m/rad (a small cup-type harmonic drive), joint damping
    0.05 N*m*s/rad.

    Parameters
    ----------
    **changes
        Fields to override, e.g. ``link_inertia=PAPER_LINK_INERTIA``.

    Examples
    --------
    >>> p = paper_actuator()
    >>> round(p.max_torque, 3), round(p.static / p.max_torque, 3)
    (1.417, 0.127)
    """
    base = ActuatorParams(
        inertia=derive_inertia_from_p_design(PAPER_VISCOUS, 0.2, 0.3),
        link_inertia=0.0,
        viscous=PAPER_VISCOUS,
        coulomb=0.8 * PAPER_STATIC_FRICTION,
        static=PAPER_STATIC_FRICTION,
        stribeck_velocity=0.02,
        max_torque=PAPER_STATIC_FRICTION / PAPER_STATIC_FRACTION,
        sample_time=PAPER_SAMPLE_TIME,
        gear_ratio=100.0,
        encoder_counts=2000,
        stiffness=2000.0,
        joint_damping=0.05,
    )
    return base.replace(**changes) if changes else base
