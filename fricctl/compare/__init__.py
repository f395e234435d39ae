"""One protocol, many plants: every friction compensator on the paper's experiments.

The paper ends: "NN comparisons with other friction models will be performed as a
continuation of the present work."  This package is that comparison's protocol (issue 23):

* :mod:`~fricctl.compare.contenders` -- the compensators, built by name through one factory
  signature ``(model, design, sample_time, seed, options)`` (:data:`CONTENDERS`,
  :func:`make_contender`);
* :mod:`~fricctl.compare.experiments` -- the paper's experiments with any compensator and plant,
  and the metrics with their units (:data:`EXPERIMENTS`, :data:`METRICS`; :func:`oscillation`
  judges a run's limit cycle);
* :mod:`~fricctl.compare.plants` -- the nominal plant and its perturbations, plain dicts
  (:data:`PLANTS`);
* :mod:`~fricctl.compare.protocol` -- :func:`compare` (any ``concurrent.futures`` executor, Dask's
  included) and its :class:`ComparisonResult` (``.rows``, ``.table()``, ``.to_json()``).

``fricctl compare`` runs it from the command line; :func:`fricctl.figures.plot_comparison` draws
one experiment's metric over the plants.
"""

from __future__ import annotations

from .contenders import CONTENDERS, REGISTERED, Contender, contender, contender_names, make_contender
from .experiments import (EXPERIMENTS, HF_CUTOFF, METRICS, Experiment, Oscillation, Outcome, experiment,
                          oscillation)
from .plants import FIELDS, PLANTS, check_plant, realise
from .protocol import MAX_SEEDS, ComparisonResult, compare

__all__ = ["CONTENDERS", "REGISTERED", "Contender", "contender", "contender_names", "make_contender",
           "EXPERIMENTS", "METRICS", "HF_CUTOFF", "Experiment", "Outcome", "experiment",
           "Oscillation", "oscillation",
           "PLANTS", "FIELDS", "check_plant", "realise", "ComparisonResult", "compare", "MAX_SEEDS"]
