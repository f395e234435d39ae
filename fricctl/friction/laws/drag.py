"""Drag friction growing with the square of the speed, ``c*w*|w|`` [N*m*s^2/rad^2].

Churning of the lubricant in a gearbox, air or oil drag on a fast link: friction that grows
faster than linearly with speed, where a viscous term would have to be inflated to match it
at high speed and then over-predict at low speed.
"""

from __future__ import annotations

import numpy as np

from ..law import DirectionalLaw, Law, direction_pair, pick

__all__ = ["Drag", "LAW"]


class Drag(DirectionalLaw):
    """Quadratic drag ``c*omega*|omega|`` (or ``pos``/``neg`` per direction) [N*m*s^2/rad^2]."""

    coefficients = ("drag_pos", "drag_neg")


def term(w, s, drag_pos, drag_neg):
    return pick(s, drag_pos, drag_neg) * w * np.abs(w)


def compiled(w, s, drag_pos, drag_neg):
    return (drag_pos if s > 0 else drag_neg) * w * abs(w)


def regressors(w, symmetric):
    col = w * np.abs(w)
    if symmetric:
        return {"drag": col}
    return {"drag_pos": col * (w > 0), "drag_neg": col * (w < 0)}


def damping(c, speed):
    """``dT/dw = 2*c*|w|``: it grows with speed, so it needs the largest speed of the run."""
    if speed is None:
        return 0.0
    return 2.0 * max(c["drag_pos"], c["drag_neg"]) * speed


LAW = Law(
    name="drag", order=100, role="rate", constructor=Drag,
    description="drag: friction growing with the square of the speed (churning, windage)",
    coefficients=direction_pair("drag", "N*m*s^2/rad^2", "quadratic drag coefficient"),
    term=term, compiled=compiled, regressors=regressors, damping=damping,
)
