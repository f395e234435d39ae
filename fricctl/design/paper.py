"""The paper's four designs (Figs. 11-12, 13-14, 16-17, 18) and the design table."""

from __future__ import annotations

import math
from collections.abc import Mapping

from .. import _validate as v
from ..params import PAPER_LINK_INERTIA, ActuatorParams, paper_actuator
from .gains import design_p, design_pd
from .result import Design

__all__ = ["PAPER_DESIGN_SPECS", "paper_designs", "design_table"]

#: The paper's four designs: key -> (law, rise time [s], damping [-], with link).
PAPER_DESIGN_SPECS = {
    "fig11-12": ("p", 0.2, 0.3, False),
    "fig13-14": ("pd", 0.3, 0.9, False),
    "fig16-17": ("pd", 0.4, 0.85, True),
    "fig18": ("pd", 0.22, 0.5, True),
}


def paper_designs(params: ActuatorParams | None = None, *, rise_time_definition: str | None = None,
                  link_inertia: float = PAPER_LINK_INERTIA) -> dict[str, Design]:
    """The paper's four controllers (Figs. 11-12, 13-14, 16-17, 18).

    ========  ====  =========  =======  =========================
    key       law   rise time  damping  plant
    ========  ====  =========  =======  =========================
    fig11-12  P     0.2 s      0.3      actuator
    fig13-14  PD    0.3 s      0.9      actuator
    fig16-17  PD    0.4 s      0.85     actuator + link 0.0046
    fig18     PD    0.22 s     0.5      actuator + link 0.0046
    ========  ====  =========  =======  =========================

    The P design uses ``priority="rise_time"``; with the paper actuator the
    damping is met too, since the inertia was derived from this design.
    Rise times are 0-100 % (all dampings < 1) unless ``rise_time_definition`` says
    otherwise (a bench's reading of the paper's "rise time",
    :mod:`fricctl.paper.benches`).

    Parameters
    ----------
    params : ActuatorParams, optional
        The design model of the actuator without link (default
        :func:`fricctl.params.paper_actuator`); its ``viscous`` is the b the designs
        count on, which a bench may keep apart from its true b.
    rise_time_definition : {"0-100", "10-90", "peak"}, optional
        How every design reads its rise time (default: 0-100 %).
    link_inertia : float
        Inertia of the link of the "with link" designs [kg*m^2] (the paper's 0.0046).

    Returns
    -------
    dict of str to Design
    """
    if params is None:
        params = paper_actuator()
    v.instance("params", params, ActuatorParams, "an ActuatorParams")
    link_inertia = v.real("link_inertia", link_inertia, nonneg=True, unit="kg*m^2")
    out = {}
    for key, (law, tr, zeta, link) in PAPER_DESIGN_SPECS.items():
        p = params.with_link(link_inertia) if link else params
        if law == "p":
            out[key] = design_p(p, rise_time=tr, damping=zeta, priority="rise_time",
                                rise_time_definition=rise_time_definition)
        else:
            out[key] = design_pd(p, rise_time=tr, damping=zeta,
                                 rise_time_definition=rise_time_definition)
    return out


def design_table(designs: Mapping[str, Design]) -> str:
    """Markdown table of designs: specs, gains, continuous and sampled metrics.

    Parameters
    ----------
    designs : mapping of str to Design
        E.g. :func:`paper_designs`.

    Returns
    -------
    str
        One row per design; times in s, overshoot in %.
    """
    def f(x, fmt):
        return "-" if x is None or not math.isfinite(x) else format(x, fmt)

    head = ("| design | law | I [`kg*m^2`] | tr req [s] | zeta req | Kp [`N*m/rad`] | "
            "Kd [`N*m*s/rad`] | tr [s] | zeta | OS [%] | ts [s] | tr Ts [s] | zeta Ts | "
            "OS Ts [%] | ts Ts [s] |")
    rows = [head, "|" + "|".join(["---"] * (head.count("|") - 1)) + "|"]
    for key, d in designs.items():
        v.instance(f"designs[{key!r}]", d, Design)
        a, s = d.achieved, d.sampled
        rows.append("| " + " | ".join([
            str(key), d.law.upper(), f(d.inertia, ".4g"), f(d.requested_rise_time, ".3g"),
            f(d.requested_damping, ".3g"), f(d.kp, ".4g"), f(d.kd, ".4g"),
            f(a.rise_time, ".4f"), f(a.damping, ".3f"), f(a.overshoot_percent, ".2f"),
            f(a.settling_time, ".3f"), f(s.rise_time, ".4f"), f(s.damping, ".3f"),
            f(s.overshoot_percent, ".2f"), f(s.settling_time, ".3f")]) + " |")
    return "\n".join(rows)
