"""The network every figure shares: a training pipeline run once on the virtual bench.

:func:`train_paper_network` runs Table-2-style experiments on the virtual bench,
measures friction patterns with the pipeline's velocity estimator, splits them
(seeded) and trains the 2-4-1 network with one of the pipelines of
:mod:`fricctl.nn.pipelines` (``"paper"``: the literal recipe; ``"fricctl"``: the fix);
:class:`PaperNetwork` keeps all of it, with the fit of the full friction estimate on
the held-out, training and true-friction patterns.
"""

from __future__ import annotations

import dataclasses
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _validate as v
from ..bench.experiments import BenchPatterns, Experiment, friction_patterns, training_experiments
from ..compensators import ConfirmedNNCompensator, NNCompensator
from ..compensators.nn_confirmed import network_compensator
from ..design import DesignWarning
from ..nn import FitReport, FrictionNet, fit_report
from ..nn.cache import cached_pipeline_net
from ..nn.pipelines import PipelineNet
from ..nn.pipelines import pipeline as _pipeline
from ..params import ActuatorParams

__all__ = ["PaperNetwork", "train_paper_network", "check_network", "pipeline_velocity"]


@dataclass(frozen=True, eq=False, kw_only=True)
class PaperNetwork:
    """The paper's pipeline run once: experiments, patterns, trained network, fit.

    Attributes
    ----------
    params : the actuator (no link): the bench's true plant, ``bench.actuator``
    bench : the bench (:class:`fricctl.paper.benches.Bench`) the figures run on: its designs,
        its readings, its experiments' settings
    experiments : the training experiments (records and truth)
    patterns : all friction patterns ``Tat = Tm - I*alpha_hat``
    train, held_out : random split of the patterns (``train_fraction`` / rest)
    trained : the pipeline's result (``.net``, ``.viscous_removed``, ``.certificate``)
    fit_held_out : fit of the full friction estimate on the held-out measured patterns
    fit_train : fit on the training patterns
    fit_true : fit on the held-out patterns against the simulator's *true* friction
    seed : seed of the split and of the trainer
    fast : whether the short experiments were used
    pipeline : ``"paper"`` or ``"fricctl"``
    sensing_seed : seed of the noise of the figures' runs (:func:`fricctl.paper.common.sensed`);
        None: ``seed`` (:meth:`sensed_on` sets another)
    """

    params: ActuatorParams
    bench: Any
    experiments: tuple
    patterns: BenchPatterns
    train: BenchPatterns
    held_out: BenchPatterns
    trained: PipelineNet
    fit_held_out: FitReport
    fit_train: FitReport
    fit_true: FitReport
    seed: int
    fast: bool
    pipeline: str
    sensing_seed: int | None = None

    def sensed_on(self, bench, sensing_seed: int | None = None) -> "PaperNetwork":
        """The same trained network judged on ``bench`` -- this network's bench with other
        sensing (:meth:`fricctl.paper.benches.Bench.with_sensing`) -- its figures' noise drawn
        from ``sensing_seed`` (None: this network's).

        The network, its patterns and its Coulomb levels are those of the clean training
        records, whatever the sensing: only the figures' runs change.

        Raises
        ------
        ValueError
            ``bench`` differs from this network's bench in more than its sensing.
        """
        from .benches import Bench

        b = v.instance("bench", bench, Bench, "a Bench (Bench.with_sensing)")
        mine = self.bench
        if (b.model, dict(b.settings)) != (mine.model, dict(mine.settings)):
            raise ValueError(f"bench: {b.name!r} differs from the network's bench {mine.name!r} in "
                             "more than its sensing (its plant or settings): train a network on it")
        seed = None if sensing_seed is None else v.integer("sensing_seed", sensing_seed, low=0)
        return dataclasses.replace(self, bench=b, sensing_seed=seed)

    @property
    def noise_seed(self) -> int:
        """The seed the figures' runs draw their sensing noise from [-]."""
        return self.seed if self.sensing_seed is None else self.sensing_seed

    @property
    def net(self) -> FrictionNet:
        """The trained 2-4-1 network (what the compensator evaluates)."""
        return self.trained.net

    def estimate(self, tm, omega):
        """The full friction estimate [N*m] (the net plus the viscous term it leaves out)."""
        return self.trained.estimate(tm, omega)

    @property
    def velocity(self) -> str:
        """The velocity the pipeline's compensator feeds its network
        (:data:`fricctl.compensators.nn_confirmed.VELOCITIES`): ``"confirmed"`` for the fricctl
        pipeline, ``"backward-difference"`` (the paper's) for the paper's."""
        return pipeline_velocity(self.pipeline)

    def compensator(self, scale: float = 1.0) -> NNCompensator | ConfirmedNNCompensator:
        """The pipeline's compensation ``s*net(Tm, omega)``.

        The paper's pipeline feeds the network the backward-difference velocity, as the paper's
        controller computes it. The fricctl pipeline compensates the nonlinear part and feeds
        the direction-confirmed velocity of :mod:`fricctl.compensators.nn_confirmed`: a
        difference against the last nonzero difference's direction is read as rest, so encoder
        jitter at rest does not switch the estimate between its rest and its sliding branch.
        """
        return network_compensator(self.net, self.velocity, scale=scale)

    def experiment(self, name: str) -> Experiment:
        """The training experiment called ``name`` (e.g. ``"open-loop steps"``)."""
        for ex in self.experiments:
            if ex.name == name:
                return ex
        raise ValueError(f"no experiment named {name!r}; have {[e.name for e in self.experiments]}")


def pipeline_velocity(pipeline: str) -> str:
    """The velocity a pipeline's compensator feeds its network: ``"confirmed"`` (the fricctl
    pipeline, :mod:`fricctl.compensators.nn_confirmed`) or ``"backward-difference"`` (the paper's)."""
    return "confirmed" if v.choice("pipeline", pipeline, ("paper", "fricctl")) == "fricctl" else \
        "backward-difference"


def check_network(network) -> PaperNetwork:
    """``network`` itself if it is a :class:`PaperNetwork`; ``ValueError`` otherwise."""
    return v.instance("network", network, PaperNetwork, "a PaperNetwork (train_paper_network)")


def train_paper_network(params: ActuatorParams | None = None, *, bench=None, fast: bool = False,
                        seed: int = 0, pipeline: str = "paper", train_fraction: float = 0.8,
                        estimator: str | None = None, **estimator_options) -> PaperNetwork:
    """Run a training pipeline once on the virtual bench (shared by every figure).

    Parameters
    ----------
    params : ActuatorParams, optional
        The actuator without link, designed on as it is (its own b); default the bench's plant.
    bench : str or Bench, optional
        The bench (:mod:`fricctl.paper.benches`): its plant, unless ``params`` replaces it, and
        the settings of its experiments (the training loops' gains are its designs').  Default
        :data:`~fricctl.paper.benches.DEFAULT_BENCH`, or with ``params`` alone
        :data:`~fricctl.paper.benches.PARAMS_BENCH` (:func:`~fricctl.paper.benches.as_bench`).
    fast : bool
        Short experiments (8 torque levels, 6 closed-loop steps) for tests.
    seed : int
        Seed of the train/held-out split and of the trainer [-].
    pipeline : {"paper", "fricctl"}
        :data:`fricctl.nn.pipelines.PIPELINES`: the paper's literal recipe, or fricctl's.
    train_fraction : float
        Fraction of the patterns used for training; the rest measure the fit [-].
    estimator : str, optional
        Velocity/acceleration estimator of the patterns; default the pipeline's (with its
        options, unless ``estimator_options`` are given).
    **estimator_options
        Passed to the estimator (e.g. ``window=100``).

    Returns
    -------
    PaperNetwork

    Notes
    -----
    Trained networks are cached on disk by configuration (:mod:`fricctl.nn.cache`;
    ``FRICCTL_CACHE=off`` retrains every time).  The paper pipeline trains with the CasADi Levenberg-Marquardt trainer (3 seeded
    restarts, at most 4000 patterns); the paper's back-propagation reaches a similar loss
    far more slowly (Chapter 4 compares them).  The fricctl pipeline trains with the
    certified trainer (at most 2000 patterns).
    """
    from .benches import as_bench

    b = as_bench(bench, params)
    p = b.actuator
    seed = v.integer("seed", seed, low=0)
    recipe = _pipeline(pipeline)
    if estimator is None:
        estimator = recipe.estimator
        estimator_options = estimator_options or dict(recipe.estimator_options)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DesignWarning)
        exps = training_experiments(p, fast=fast, gains=b.training_gains())
    pats = friction_patterns(exps, p, method=estimator, **estimator_options)
    split = pats.split(train_fraction, np.random.default_rng(seed))
    train, held = split.train, split.held_out
    meta = {"seed": seed, "fast": bool(fast), "estimator": estimator, "patterns": len(train)}
    key = {"what": "paper network", "pipeline": pipeline, "params": p.as_dict(), "design": b.design_key(),
           "estimator": estimator, "estimator_options": estimator_options,
           "train_fraction": float(train_fraction), **meta}
    trained = cached_pipeline_net(key, lambda: recipe.train(
        train, rng=np.random.default_rng(seed), metadata=meta), patterns=train)

    def fit(target, pats_):
        return fit_report(target, trained.estimate(pats_.tm, pats_.omega))

    return PaperNetwork(
        params=p, bench=b, experiments=tuple(exps), patterns=pats, train=train, held_out=held,
        trained=trained, fit_held_out=fit(held.friction, held), fit_train=fit(train.friction, train),
        fit_true=fit(held.friction_true, held), seed=seed, fast=bool(fast), pipeline=pipeline)
