"""The registry of the paper's figures, built from the ``figNN`` modules of this package.

Each module ``fricctl/paper/figNN.py`` holds one figure: its frozen result, its
``run(network, ...)`` experiment, its claim makers and one registry entry,
``FIGURE = PaperFigure(...)``.  :func:`paper_figures` finds those modules (any
module of the package named ``fig`` + two digits), imports them and returns their
entries by figure number, so that adding a figure is one new module (plus its plot,
registered in :mod:`fricctl.figures.paper` with ``@paper_plot(N)``) and no other
edit.

A claim maker is ``make(result, bench) -> Claim``: the figure's result and the bench the
claims are judged on (:class:`fricctl.paper.benches.Bench`: its nominal actuator, its
readings; most makers need only the result).
"""

from __future__ import annotations

import functools
import importlib
import pkgutil
import re
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any, Callable, Mapping

from .. import _validate as v

__all__ = ["PaperFigure", "paper_figures"]

_MODULE_NAME = re.compile(r"fig(\d\d)")


@dataclass(frozen=True, kw_only=True)
class PaperFigure:
    """One figure of the paper on the virtual bench: what runs it and what it claims.

    Attributes
    ----------
    number : the paper's figure number [-]
    title : one line: what the figure shows
    run : ``run(network, **options) -> result``: the experiment
    result_type : the class of ``run``'s result (the plot registry checks against it)
    claims : claim makers ``make(result, bench) -> Claim``, in table order
    assumptions : what the experiment assumes that the paper does not say
    """

    number: int
    title: str
    run: Callable[..., Any]
    result_type: type
    claims: tuple = ()
    assumptions: tuple = field(default=())

    def __post_init__(self):
        v.integer("number", self.number, low=1)
        v.text("title", self.title, empty=False)
        if not callable(self.run):
            raise ValueError(f"run of Fig. {self.number} must be callable, got {type(self.run).__name__}")
        v.instance("result_type", self.result_type, type, "a class")
        for name in ("claims", "assumptions"):
            v.instance(name, getattr(self, name), tuple, "a tuple")
        for make in self.claims:
            if not callable(make):
                raise ValueError(f"claims of Fig. {self.number} must be callables, got {type(make).__name__}")
        for a in self.assumptions:
            v.text("assumptions", a, empty=False)

    def make_claims(self, result, bench=None) -> list:
        """The claims of this figure checked on ``result`` (a list of :class:`~fricctl.paper.Claim`).

        ``bench``: the bench the result was run on, as :func:`fricctl.paper.benches.as_bench`
        takes it (a name, a Bench, an ActuatorParams, or None for the default bench).
        """
        from .benches import as_bench

        v.instance("result", result, self.result_type)
        b = as_bench(bench)
        return [make(result, b) for make in self.claims]


@functools.cache
def paper_figures() -> Mapping[int, PaperFigure]:
    """Figure number -> :class:`PaperFigure`, from every ``figNN`` module of :mod:`fricctl.paper`.

    Read-only and in figure order.  Discovered once (the modules are imported on
    the first call; the result is immutable, so a second discovery from another
    thread would only find the same entries).

    Raises
    ------
    TypeError
        A ``figNN`` module has no ``FIGURE`` entry of type :class:`PaperFigure`.
    ValueError
        An entry's number differs from its module's name.
    """
    package = importlib.import_module(__package__)
    found = {}
    for info in pkgutil.iter_modules(package.__path__):
        m = _MODULE_NAME.fullmatch(info.name)
        if m is None:
            continue
        module = importlib.import_module(f"{__package__}.{info.name}")
        fig = getattr(module, "FIGURE", None)
        if not isinstance(fig, PaperFigure):
            raise TypeError(f"{module.__name__} must define FIGURE = PaperFigure(...), "
                            f"got {type(fig).__name__}")
        if fig.number != int(m.group(1)):
            raise ValueError(f"{module.__name__} registers Fig. {fig.number}: its number must match "
                             "the module's name")
        found[fig.number] = fig
    return MappingProxyType(dict(sorted(found.items())))
