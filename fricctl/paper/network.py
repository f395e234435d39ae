"""The network every figure shares: the paper's training pipeline run once.

:func:`train_paper_network` runs Table-2-style experiments on the virtual bench,
measures friction patterns with the paper's polynomial velocity estimator, splits
them (seeded) and trains the 2-4-1 network; :class:`PaperNetwork` keeps all of it,
with the fit on the held-out, training and true-friction patterns.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from .. import _validate as v
from ..bench.experiments import Experiment, Patterns, friction_patterns, train_network, training_experiments
from ..design import DesignWarning
from ..nn import FitReport, FrictionNet, TrainingResult, fit_report
from ..params import ActuatorParams, paper_actuator

__all__ = ["PaperNetwork", "train_paper_network", "check_network"]


@dataclass(frozen=True, eq=False, kw_only=True)
class PaperNetwork:
    """The paper's pipeline run once: experiments, patterns, trained network, fit.

    Attributes
    ----------
    params : the actuator (no link) [-]
    experiments : the training experiments (records and truth)
    patterns : all friction patterns ``Tat = Tm - I*alpha_hat``
    train, held_out : random split of the patterns (``train_fraction`` / rest)
    training : the trainer's result (``.net``, ``.history``)
    fit_held_out : fit of the net on the held-out measured patterns
    fit_train : fit on the training patterns
    fit_true : fit on the held-out patterns against the simulator's *true* friction
    seed : seed of the split and of the trainer
    fast : whether the short experiments were used
    """

    params: ActuatorParams
    experiments: tuple
    patterns: Patterns
    train: Patterns
    held_out: Patterns
    training: TrainingResult
    fit_held_out: FitReport
    fit_train: FitReport
    fit_true: FitReport
    seed: int
    fast: bool

    @property
    def net(self) -> FrictionNet:
        """The trained 2-4-1 network."""
        return self.training.net

    def experiment(self, name: str) -> Experiment:
        """The training experiment called ``name`` (e.g. ``"open-loop steps"``)."""
        for ex in self.experiments:
            if ex.name == name:
                return ex
        raise ValueError(f"no experiment named {name!r}; have {[e.name for e in self.experiments]}")


def check_network(network) -> PaperNetwork:
    """``network`` itself if it is a :class:`PaperNetwork`; ``ValueError`` otherwise."""
    return v.instance("network", network, PaperNetwork, "a PaperNetwork (train_paper_network)")


def train_paper_network(params: ActuatorParams | None = None, *, fast: bool = False, seed: int = 0,
                        train_fraction: float = 0.8, estimator: str = "polynomial_segments",
                        **estimator_options) -> PaperNetwork:
    """Run the paper's training pipeline once (shared by every figure).

    Parameters
    ----------
    params : ActuatorParams, optional
        The actuator without link; default :func:`~fricctl.params.paper_actuator`.
    fast : bool
        Short experiments (8 torque levels, 6 closed-loop steps) for tests.
    seed : int
        Seed of the train/held-out split and of the trainer [-].
    train_fraction : float
        Fraction of the patterns used for training; the rest measure the fit [-].
    estimator : str
        Velocity/acceleration estimator of the patterns (the paper's by default).
    **estimator_options
        Passed to the estimator (e.g. ``window=100``).

    Returns
    -------
    PaperNetwork

    Notes
    -----
    Training uses the CasADi Levenberg-Marquardt trainer (3 seeded restarts, at
    most 4000 patterns); the paper's back-propagation reaches a similar loss far
    more slowly (Chapter 4 compares them).
    """
    p = paper_actuator() if params is None else v.instance("params", params, ActuatorParams,
                                                            "an ActuatorParams")
    seed = v.integer("seed", seed, low=0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DesignWarning)
        exps = training_experiments(p, fast=fast)
    pats = friction_patterns(exps, p, method=estimator, **estimator_options)
    split = pats.split(train_fraction, np.random.default_rng(seed))
    train, held = split.train, split.held_out
    res = train_network(train, rng=np.random.default_rng(seed))
    net = res.net
    return PaperNetwork(
        params=p, experiments=tuple(exps), patterns=pats, train=train, held_out=held, training=res,
        fit_held_out=fit_report(held.friction, net=net, tm=held.tm, omega=held.omega),
        fit_train=fit_report(train.friction, net=net, tm=train.tm, omega=train.omega),
        fit_true=fit_report(held.friction_true, net=net, tm=held.tm, omega=held.omega),
        seed=seed, fast=bool(fast))
