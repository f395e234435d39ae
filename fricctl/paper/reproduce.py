"""Everything at once: train the network, run every registered figure and the sweep, check the claims."""

from __future__ import annotations

from concurrent.futures import Executor
from dataclasses import dataclass
from typing import Callable

from .. import _validate as v
from ..params import ActuatorParams, paper_actuator
from .claims import claims_summary, paper_claims
from .network import PaperNetwork, train_paper_network
from .registry import paper_figures
from .sweep import SweepResult, robustness_sweep

__all__ = ["PaperResults", "reproduce_paper"]


@dataclass(frozen=True, eq=False, kw_only=True)
class PaperResults:
    """All figures, the sweep and the claims of one :func:`reproduce_paper` run.

    Attributes
    ----------
    network : the shared network
    figures : figure number -> result, in figure order
    sweep : the robustness sweep
    claims : the claims of every figure, in figure order
    """

    network: PaperNetwork
    figures: dict
    sweep: SweepResult
    claims: tuple

    @property
    def n_passed(self) -> int:
        return sum(c.passed for c in self.claims)

    def summary(self) -> str:
        """``"N of M claims of the paper reproduced (extras: n of m)"``."""
        return claims_summary(self.claims)


def reproduce_paper(params: ActuatorParams | None = None, *, fast: bool = False, seed: int = 0,
                    executor: Executor | None = None,
                    progress: Callable[[int, int, str], None] | None = None) -> PaperResults:
    """Train once, run every figure and the robustness sweep, check the claims.

    Parameters
    ----------
    params : ActuatorParams, optional
    fast : bool
        Short training experiments and a small sweep grid.
    seed : int
        Seed of the network's split and training [-].
    executor : concurrent.futures.Executor, optional
        Passed to :func:`robustness_sweep`.
    progress : callable, optional
        ``progress(done, total, name)`` before each step.

    Returns
    -------
    PaperResults
    """
    p = paper_actuator() if params is None else params
    seed = v.integer("seed", seed, low=0)
    registry = paper_figures()
    steps = ["network"] + [f"fig{n}" for n in registry] + ["sweep"]
    total = len(steps)

    def tick(i, name):
        if progress is not None:
            progress(i, total, name)

    tick(0, "network")
    network = train_paper_network(p, fast=fast, seed=seed)
    figs = {}
    for i, (num, fig) in enumerate(registry.items(), start=1):
        tick(i, f"fig{num}")
        figs[num] = fig.run(network)
    tick(total - 1, "sweep")
    grid = dict(friction_scales=(0.8, 1.0, 1.2), link_inertias=(0.0, 0.0046)) if fast else {}
    sweep = robustness_sweep(network.net, p, executor=executor, **grid)
    tick(total, "done")
    return PaperResults(network=network, figures=figs, sweep=sweep, claims=tuple(paper_claims(figs, p)))
