"""Fig. 8: the trained network against the measured friction patterns it did not see."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..bench.experiments import BenchPatterns, true_patterns
from ..nn import FitReport, FrictionNet, fit_report
from ..nn.cache import cached_pipeline_net
from ..nn.pipelines import PIPELINES
from .claims import EXTRA, Claim
from .network import PaperNetwork, check_network
from .registry import PaperFigure

__all__ = ["Fig8Result", "run", "claim_fit", "claim_fit_exact", "FIGURE", "ACCURACY_READING"]

#: The paper's accuracy of the trained network (Section 4: "98 %") [%].
PAPER_FIT_PERCENT = 98.0

#: Which reading of the paper's undefined "98 % accuracy" the claim judges, and why (issue
#: 22 item 4).  Two readings are common: the normalised fit 100*(1 - ||e||/||y - mean y||)
#: and R^2 = 1 - ||e||^2/||y - mean y||^2 (variance accounted for), tied by
#: fit = 100*(1 - sqrt(1 - R^2)).  The claim reads the fit, on every seed: an "accuracy" in
#: percent is a size of the error relative to the signal's, as the fit is (R^2 is a share of
#: variance, the square of that size); it is the "fit %" the identification tools of the
#: paper's time (MATLAB's System Identification Toolbox, `compare`) print for a model
#: against data; and it is the stricter reading, so a network that holds it holds R^2 >= 0.98
#: too, never the converse.  R^2 is reported beside it for every seed (claims.md's table).
ACCURACY_READING = ("normalised fit 100*(1 - ||e||/||y - mean y||) on held-out patterns: a "
                    "percent accuracy is a relative size of the error, as the fit is (R^2 is "
                    "its square's complement), it is the fit % the identification tools of "
                    "2003 print, and the stricter reading (it implies R^2 >= 0.98)")


@dataclass(frozen=True, eq=False, kw_only=True)
class Fig8Result:
    """Fig. 8: measured ("experimental") against network friction, held-out patterns.

    Attributes
    ----------
    target : held-out friction patterns [N*m]
    predicted : network estimate on them [N*m]
    fit_held_out, fit_train, fit_true : see :class:`~fricctl.paper.PaperNetwork`
    gain_at_rest : ``dTat_hat/dTm`` at rest [-]
    fit_exact : held-out fit of a 2-4-1 network trained by least squares, with the same
        split and seed, on exact patterns (the simulator's true velocity and friction): what
        a perfect measuring chain would allow the architecture (the same for every pipeline:
        a statement about the network and the data, not about a pipeline's constraints)
    """

    target: np.ndarray
    predicted: np.ndarray
    fit_held_out: FitReport
    fit_train: FitReport
    fit_true: FitReport
    gain_at_rest: float
    fit_exact: FitReport


def _exact_net(net: PaperNetwork, train: BenchPatterns, *, split_fraction: float) -> FrictionNet:
    """The paper recipe's least squares (:data:`fricctl.nn.pipelines.PIPELINES` ``"paper"``) on
    exact patterns, through the disk cache of trained nets: it depends on the experiments, the
    split and the seed, not on the pipeline judged, so both pipelines of a seed share it."""
    p = net.params
    key = {"what": "Fig. 8 exact-pattern network", "params": p.as_dict(), "design": net.bench.design_key(),
           "fast": net.fast,
           "seed": net.seed, "split_fraction": float(split_fraction), "patterns": len(train)}
    return cached_pipeline_net(key, lambda: PIPELINES["paper"].train(
        train, rng=np.random.default_rng(net.seed)), patterns=train).net


def run(network: PaperNetwork) -> Fig8Result:
    """The pipeline's full friction estimate on the held-out patterns (Fig. 8).

    ``predicted`` is :meth:`PaperNetwork.estimate` (for the fricctl pipeline the net plus
    the viscous term it leaves out), so both pipelines are judged on the same target.
    """
    net = check_network(network)
    ho = net.held_out
    exact = true_patterns(net.experiments)
    # same permutation as the measured patterns' split (same length, same seed)
    split = exact.split(len(net.train) / len(net.patterns), np.random.default_rng(net.seed))
    train_e, held_e = split.train, split.held_out
    net_e = _exact_net(net, train_e, split_fraction=len(net.train) / len(net.patterns))
    fit_exact = fit_report(held_e.friction, net_e(held_e.tm, held_e.omega))
    return Fig8Result(target=ho.friction, predicted=np.asarray(net.estimate(ho.tm, ho.omega)),
                      fit_held_out=net.fit_held_out, fit_train=net.fit_train, fit_true=net.fit_true,
                      gain_at_rest=net.net.gain_at_rest(), fit_exact=fit_exact)


def claim_fit(r: Fig8Result, params=None) -> Claim:
    f = r.fit_held_out
    ok = f.fit_percent >= PAPER_FIT_PERCENT
    return Claim(
        id="nn-fit", claim="The 2-4-1 network learns the friction patterns with 98 % accuracy "
        f"(read as the {ACCURACY_READING}; >= 98 % on every seed judged)",
        paper="98 %", measured=f"fit {f.fit_percent:.1f} %, R^2 {f.r_squared:.3f} (train fit "
        f"{r.fit_train.fit_percent:.1f} %; vs true friction {r.fit_true.fit_percent:.1f} %)", passed=ok,
        figure="Fig. 8", value=f.fit_percent, unit="%",
        note="" if ok else "The paper does not define its accuracy. The patterns Tm - I*alpha_hat carry "
        "the estimator's error where the acceleration jumps (torque steps, stick/slip transitions): "
        f"trained on exact patterns the same network reaches a fit of {r.fit_exact.fit_percent:.1f} % "
        "(claim nn-fit-exact): most of the gap to 98 % is the measuring chain, not the 2-4-1 network. "
        f"R^2 is the kinder measure (R^2 = 0.98 is a fit of {100 * (1 - math.sqrt(1 - 0.98)):.1f} %).")


def claim_fit_exact(r: Fig8Result, params=None) -> Claim:
    f = r.fit_exact
    ok = f.fit_percent >= PAPER_FIT_PERCENT
    return Claim(
        id="nn-fit-exact", claim="(Extra, not in the paper.) Trained on exact patterns -- the simulator's "
        "true velocity and friction at the same samples, same split and seed -- the same 2-4-1 network "
        "reaches 98 % (normalised fit on held-out patterns)", paper=EXTRA,
        measured=f"fit {f.fit_percent:.1f} %, R^2 {f.r_squared:.4f}", passed=ok, figure="Fig. 8",
        value=f.fit_percent, unit="%",
        note="" if ok else "close to 98 % but below it in this run: the exact-pattern fit varies between "
        "runs (the fast run's shorter experiments reach 98.4 % with the same architecture, split rule and "
        "seed), so this is the training data and the optimiser's local minimum, not a limit of the "
        "2-4-1 map; either way the measured-pattern fit (claim nn-fit) is far below it.")


FIGURE = PaperFigure(number=8, title="the network against held-out friction patterns", run=run,
                     result_type=Fig8Result, claims=(claim_fit, claim_fit_exact))
