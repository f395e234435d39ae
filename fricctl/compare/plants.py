"""The plants of the comparison: the bench's true plant and its perturbations, each a plain object.

A plant is a JSON-able dict: its ``name`` and the fields it changes (any field left out keeps
its nominal value).  The compensators are built once from the design model and the nominal
design and are *not* redesigned or retrained for a perturbed plant: a perturbation is what the
deployed compensator meets, not what it was made for.

====================  =====  ============================================================
field                 unit   meaning (nominal)
====================  =====  ============================================================
friction_scale        -      the true friction x this (1)
stribeck_velocity     -      the Stribeck velocity x this (1)
  _scale
link_inertia          kg m2  the link's inertia, replacing the experiment's own (None: the
                             experiment's: none, or the paper's link where it has one)
encoder_counts        1/rev  encoder counts per revolution (None: the bench's)
delay                 -      extra samples before the joint receives the torque (0)
compensation_scale    -      s of Tm(k+1) = Tc(k) + s*T^at(k) (1); the paper's answer to wear
torque_noise          N m    standard deviation of white torque noise at the joint (0); a
                             plant with noise runs every contender over the seeds
====================  =====  ============================================================
"""

from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType
from typing import Mapping

from .. import _validate as v
from ..params import PAPER_LINK_INERTIA, ActuatorParams
from ..paper.common import AGED_SCALE

__all__ = ["PLANTS", "FIELDS", "check_plant", "Realised", "realise", "noisy"]

#: Plant field -> (unit, nominal value).
FIELDS = MappingProxyType({
    "friction_scale": ("-", 1.0),
    "stribeck_velocity_scale": ("-", 1.0),
    "link_inertia": ("kg*m^2", None),
    "encoder_counts": ("counts/rev", None),
    "delay": ("samples", 0),
    "compensation_scale": ("-", 1.0),
    "torque_noise": ("N*m", 0.0),
})

#: The plants of the comparison, by name.  Wear is the paper's Fig. 16: friction x 0.95 after
#: 30 h, the compensation lowered to s = 0.95 without retraining (fricctl.paper.common.AGED_SCALE);
#: the link is the SCARA link of Figs. 16-18; the coarse encoder has a quarter of the bench's
#: 2000 counts/rev (an assumption: a cheaper encoder); the delay is one more sample (a slower
#: drive or bus); the noise is white torque noise of 0.002 N*m, about 1 % of the breakaway level
#: (an assumption: a current loop's noise, which the paper does not give).
PLANTS: Mapping[str, Mapping] = MappingProxyType({p["name"]: MappingProxyType(p) for p in (
    {"name": "nominal"},
    {"name": "friction_0.8", "friction_scale": 0.8},
    {"name": "friction_1.2", "friction_scale": 1.2},
    {"name": "wear", "friction_scale": AGED_SCALE, "compensation_scale": AGED_SCALE},
    {"name": "link", "link_inertia": PAPER_LINK_INERTIA},
    {"name": "stribeck_0.5", "stribeck_velocity_scale": 0.5},
    {"name": "stribeck_2", "stribeck_velocity_scale": 2.0},
    {"name": "encoder_500", "encoder_counts": 500},
    {"name": "delay_1", "delay": 1},
    {"name": "noise", "torque_noise": 0.002},
)})


def check_plant(plant) -> dict:
    """``plant`` (a name of :data:`PLANTS` or a dict) as a plain, checked dict.

    Raises
    ------
    ValueError
        An unknown name, a dict without ``name``, an unknown field or a non-physical value.
    """
    if isinstance(plant, str):
        if plant not in PLANTS:
            raise ValueError(f"unknown plant {plant!r}; choose from {', '.join(PLANTS)}")
        plant = PLANTS[plant]
    if not isinstance(plant, Mapping):
        raise ValueError(f"plant must be a name or a mapping, got {type(plant).__name__}")
    if "name" not in plant:
        raise ValueError("plant: a plant needs a 'name'")
    unknown = sorted(set(plant) - set(FIELDS) - {"name"})
    if unknown:
        raise ValueError(f"plant {plant['name']!r}: unknown field {unknown[0]!r}; fields: {', '.join(FIELDS)}")
    out = {"name": v.text("plant name", plant["name"], empty=False)}
    for key, val in plant.items():
        if key == "name":
            continue
        if key in ("friction_scale", "stribeck_velocity_scale", "compensation_scale"):
            out[key] = v.real(key, val, positive=key != "compensation_scale", nonneg=True)
        elif key == "torque_noise":
            out[key] = v.real(key, val, nonneg=True, unit="N*m")
        elif key == "link_inertia":
            out[key] = None if val is None else v.real(key, val, nonneg=True, unit="kg*m^2")
        elif key == "encoder_counts":
            out[key] = None if val is None else v.integer(key, val, low=1)
        else:  # delay
            out[key] = v.integer(key, val, low=0)
    return out


@dataclass(frozen=True, kw_only=True, eq=False)
class Realised:
    """A plant made concrete for one experiment.

    Attributes
    ----------
    params : the actuator the experiment runs (link and encoder applied)
    friction : its true friction model (scale and Stribeck velocity applied)
    delay : extra samples of delay [-]
    compensation_scale : s [-]
    noise_std : white torque noise at the joint [N*m]
    """

    params: ActuatorParams
    friction: object
    delay: int
    compensation_scale: float
    noise_std: float


def realise(plant, params: ActuatorParams) -> Realised:
    """The perturbed actuator, friction and loop of ``plant`` around the experiment's ``params``."""
    p = {**{k: nominal for k, (_, nominal) in FIELDS.items()}, **check_plant(plant)}
    params = v.instance("params", params, ActuatorParams, "an ActuatorParams")
    changes = {"stribeck_velocity": params.stribeck_velocity * p["stribeck_velocity_scale"]}
    if p["link_inertia"] is not None:
        changes["link_inertia"] = p["link_inertia"]
    if p["encoder_counts"] is not None:
        changes["encoder_counts"] = p["encoder_counts"]
    q = params.replace(**changes)
    fr = q.friction_model()
    if p["friction_scale"] != 1.0:
        fr = fr.scaled(p["friction_scale"])
    return Realised(params=q, friction=fr, delay=p["delay"], compensation_scale=p["compensation_scale"],
                    noise_std=p["torque_noise"])


def noisy(plant) -> bool:
    """Whether ``plant`` draws random numbers (torque noise): its runs then differ by seed."""
    p = check_plant(plant)
    return "torque_noise" in p and p["torque_noise"] > 0
