"""Breakaway excess over sliding friction, with no sliding contribution [N*m].

Its coefficients are ``static_excess_pos``/``_neg``: the *excess* ``Fs - Fc``.  ``static``
alone means the absolute breakaway level ``Fs`` everywhere in fricctl (the paper's 0.18 N*m,
:class:`~fricctl.params.ActuatorParams`, identification); model files of fricctl <= 0.1 wrote
the excess as ``static_pos``/``_neg`` and are read with those names.

The classic "static + Coulomb" model: the joint needs ``Fc + excess`` to start, and ``Fc``
once it slides (an infinitely narrow Stribeck curve).
"""

from __future__ import annotations

from ..law import DirectionalLaw, Law, direction_pair, pick

__all__ = ["Static", "LAW"]


class Static(DirectionalLaw):
    """Breakaway excess over sliding friction, with no sliding contribution [N*m].

    The classic "static + Coulomb" model: the joint needs ``Fc + excess`` to
    start, and ``Fc`` once it slides (an infinitely narrow Stribeck curve).
    """

    coefficients = ("static_excess_pos", "static_excess_neg")


def term(w, s, tm, static_excess_pos, static_excess_neg):
    return 0.0 * w


def compiled(w, s, tm, static_excess_pos, static_excess_neg):
    return 0.0


def breakaway(s, tm, static_excess_pos, static_excess_neg):
    return pick(s, static_excess_pos, static_excess_neg)


def compiled_breakaway(s, tm, static_excess_pos, static_excess_neg):
    return static_excess_pos if s > 0 else static_excess_neg


LAW = Law(
    name="static", order=30, role="level", constructor=Static,
    description="stiction: a breakaway torque above the sliding level, gone once moving",
    coefficients=direction_pair("static_excess", "N*m", "breakaway excess over sliding friction"),
    term=term, compiled=compiled, breakaway=breakaway, compiled_breakaway=compiled_breakaway,
)
