"""The compiled step of every registered compensator, dispatched on its kind: :func:`step`.

Generated from the registry as :mod:`fricctl.friction.compiled` generates the friction
kernels from the laws: one ``if kind == K`` per registered kind with a step, calling that
module's step with the arguments it names (``p``, ``x`` and the signals of
:data:`fricctl.compensators.base.SIGNALS`); a kind without a step (none) gives 0.  The cache
of the compiled code is keyed by the digest of every compensator module
(:func:`fricctl._jit.compiled_sources`).  :data:`SOURCE` holds the generated text.
"""

from __future__ import annotations

import inspect

from .._jit import jit
from . import REGISTRY

__all__ = ["step", "SOURCE"]


def _generate() -> tuple[str, dict]:
    names, lines = {}, []
    for entry in REGISTRY.values():
        if entry.step is None:
            continue
        names[f"_step_{entry.name}"] = jit(entry.step)
        args = ", ".join(inspect.signature(entry.step).parameters)
        lines += [f"    if kind == {entry.kind}:", f"        return _step_{entry.name}({args})"]
    src = "\n".join([
        "def step(kind, p, x, tm, wh, y, r, tc, ts):",
        '    """T^at of the compensator of kind ``kind`` (parameters p, state x changed in place)."""',
        *lines,
        "    return 0.0",
        "",
    ])
    return src, names


#: The generated source of :func:`step`.
SOURCE, _NAMES = _generate()
_namespace = dict(_NAMES, __name__=__name__)
exec(compile(SOURCE, "<generated-compensator-step>", "exec"), _namespace)  # noqa: S102 - our own text
step = jit(_namespace["step"])
