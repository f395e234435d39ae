"""Compiled (numba) evaluation of a friction parameter vector, generated from the registered laws.

These are the primitives the plant kernels integrate; they compute what
:meth:`fricctl.friction.FrictionModel.torque` and ``breakaway`` compute in numpy, one sample
at a time (``tests/test_friction.py`` pins the two together for every law).  ``fp`` is the
vector of :mod:`.layout`, ``s`` the direction of motion (+1 or -1), ``tm`` the transmitted
torque, ``t`` the time, ``z`` a presliding state and ``g`` the level it slides at.

Each function below is generated from the laws of one role (:mod:`fricctl.friction.law`):
the source is assembled here, each law's compiled term called with its coefficients read
from ``fp`` at their layout positions, and compiled with :func:`fricctl._jit.jit`, whose cache
is keyed by the digest of every law module (so an edited law is never served stale).
:data:`SOURCE` holds the generated text.

=============  ==========================================================================
function       generated from
=============  ==========================================================================
``scale_at``   the scale law: ``scale*(1 + drift*t)``
``ripple``     the position laws (not scaled)
``rate``       the rate laws (viscous, drag), scaled
``level``      the level laws (Coulomb, static, Stribeck, load), scaled; a magnitude
``sliding``    ``rate + s*level``: the friction while sliding, no ripple
``breakaway``  the level laws' breakaway contributions, scaled: a magnitude
``state``      the state laws: ``(z', friction)`` of the active one, ``(0, 0)`` if none
=============  ==========================================================================
"""

from __future__ import annotations

import inspect

from .._jit import jit
from .law import SIGNALS
from .laws import LAWS, laws_with_role
from .layout import IDX

__all__ = ["scale_at", "ripple", "rate", "level", "sliding", "breakaway", "state", "SOURCE"]


def _call(prefix: str, law, func, signals: dict, scale: str | None = None) -> str:
    """``prefix_law(arg, ...)``: signals by their local names, coefficients as ``fp[i]``; with
    ``scale``, the law's magnitudes (coefficients that add) multiplied by it first."""
    magnitudes = {c.name for c in law.coefficients if c.combine == "add"}
    args = []
    for name in inspect.signature(func).parameters:
        if name in SIGNALS:
            args.append(signals[name])
        elif name in law.field_names:
            args.append(f"{scale} * fp[{IDX[name]}]" if scale and name in magnitudes
                        else f"fp[{IDX[name]}]")
        else:
            raise ValueError(f"law {law.name}: compiled term argument {name!r} is neither a signal "
                             f"{SIGNALS} nor one of its coefficients {law.field_names}")
    return f"_{prefix}_{law.name}({', '.join(args)})"


def _sum(terms: list[str]) -> str:
    return " + ".join(terms) if terms else "0.0"


def _generate() -> tuple[str, dict]:
    names: dict = {}
    for law in LAWS.values():
        if law.compiled is not None:
            names[f"_t_{law.name}"] = jit(law.compiled)
        if law.compiled_breakaway is not None:
            names[f"_b_{law.name}"] = jit(law.compiled_breakaway)
        if law.state is not None:
            names[f"_s_{law.name}"] = jit(law.state.compiled)
    sig = {"w": "w", "s": "s", "tm": "tm", "q": "q", "t": "t", "z": "z", "zd": "zd", "g": "g"}
    (scale,) = laws_with_role("scale")
    rest = dict(sig, w="0.0")
    breaks = [_call("b", law, law.compiled_breakaway, sig) if law.compiled_breakaway is not None
              else _call("t", law, law.compiled, rest) for law in laws_with_role("level")]
    state_lines = []
    for law in laws_with_role("state"):
        state_lines += [f"    if fp[{IDX[law.state.switch]}] > 0.0:",
                        f"        return {_call('s', law, law.state.compiled, sig)}"]
    src = "\n".join([
        "def scale_at(fp, t):",
        '    """Friction scale at time t [-]."""',
        f"    return {_call('t', scale, scale.compiled, sig)}",
        "",
        "def ripple(fp, q):",
        '    """Position-periodic torque at q [N*m] (not scaled: it is not friction)."""',
        f"    return {_sum([_call('t', law, law.compiled, sig) for law in laws_with_role('position')])}",
        "",
        "def rate(fp, w, s, t):",
        '    """The rate terms (viscous, drag), scaled, in direction s [N*m]."""',
        # the scale multiplies each rate law's magnitudes, (k*b)*w: the arithmetic of the
        # hand-written kernels before the laws were plug-ins, kept to the last bit
        "    k = scale_at(fp, t)",
        f"    return {_sum([_call('t', law, law.compiled, sig, 'k') for law in laws_with_role('rate')])}",
        "",
        "def level(fp, w, s, tm, t):",
        '    """The level (Coulomb, Stribeck, load), scaled, in direction s at speed |w| [N*m]."""',
        f"    return scale_at(fp, t) * ({_sum([_call('t', law, law.compiled, sig) for law in laws_with_role('level')])})",
        "",
        "def sliding(fp, w, s, tm, t):",
        '    """Friction torque (no ripple) while sliding in direction s; smooth in w [N*m]."""',
        "    return rate(fp, w, s, t) + s * level(fp, w, s, tm, t)",
        "",
        "def breakaway(fp, s, tm, t):",
        '    """Torque the drive must exceed to start moving in direction s, a magnitude [N*m]."""',
        f"    return scale_at(fp, t) * ({_sum(breaks)})",
        "",
        "def state(fp, w, z, g):",
        '    """(z\', friction) of the active presliding law at level g; (0, 0) without one."""',
        *state_lines,
        "    return 0.0, 0.0",
        "",
    ])
    return src, names


#: The generated source of this module's functions.
SOURCE, _NAMES = _generate()
_namespace = dict(_NAMES, __name__=__name__)
exec(compile(SOURCE, "<generated-friction-kernels>", "exec"), _namespace)  # noqa: S102 - our own text
for _name in ("scale_at", "ripple", "rate", "level", "sliding", "breakaway", "state"):
    # callees first: a generated function calls the compiled ones above it by name
    _namespace[_name] = jit(_namespace[_name])
scale_at, ripple, rate, level = (_namespace[n] for n in ("scale_at", "ripple", "rate", "level"))
sliding, breakaway, state = (_namespace[n] for n in ("sliding", "breakaway", "state"))
