"""The paper's experiments on the virtual bench, and its claims checked by numbers.

Gervini, Gomes & da Rosa (2003) show their results in Figs. 4-18.  Each
``figN(network)`` below re-runs the experiment of figure N on the virtual bench
(deterministic: every random draw comes from ``network.seed``) and returns a
frozen result; :mod:`fricctl.figures.paper` draws it.  All figures share one
trained network, :func:`train_paper_network` (a training pipeline run once:
Table-2-style experiments -> friction patterns with the polynomial velocity
estimator -> 2-4-1 network), of either pipeline: ``"paper"`` (the literal recipe)
or ``"fricctl"`` (the fix, :mod:`fricctl.nn.pipelines`).  Compensated runs use
``network.compensator(s)``; whatever needs the full friction estimate uses
``network.estimate(Tm, omega)``.

:func:`paper_claims` turns the results into :class:`Claim` rows: the paper's
words, the paper's value, the value measured here (a sentence and the number the
criterion thresholds) and pass/fail, each with an explicit tolerance in its text.
A claim that the bench does not reproduce is reported as failing, with the
physical reason in ``note``; nothing is tuned to make a claim pass.  A claim whose
measurement involves compensation also requires the runaway checks of
:mod:`~fricctl.paper.runaway` (no wind-up, reversal under a sinusoidal torque,
the network's coast test, :mod:`~fricctl.paper.coast`): no claim passes by a
joint that runs away.  :func:`robustness_sweep` maps where NN compensation keeps
the PD steady-state error below 0.3 deg over friction scale and link inertia.
:func:`reproduce_paper` runs everything over training seeds and pipelines, and
aggregates the claims (:mod:`~fricctl.paper.table`; ``fricctl reproduce``).

Everything runs on a *bench* (:mod:`~fricctl.paper.benches`: a model file of the plant plus
the experiments' settings, each value with its provenance): ``consistent`` (the default: the
readings under which every statement of the paper can hold, ``docs/paper_consistency.md``, with
the sensing a real bench has) or ``literal`` (the paper's numbers with fricctl's first readings,
noise-free; what an ActuatorParams given alone is judged with); the network carries it (``network.bench``) and the figures
read their designs, Fig. 18's sawtooth and Fig. 11's reading from it.

Assumptions (the paper does not give these; labelled as such in the results):

* Fig. 9: sinusoidal torque of 1.1 x the breakaway level Fs, 0.5 Hz, 4 s;
* Fig. 16: step of 30 deg; the aged actuator is the bench's true friction x 0.95
  (the paper lowers the compensation scale to s = 0.95 after 30 h of wear
  without retraining); the Coulomb compensator at the breakaway level the
  dead-zone experiment reads and at the Coulomb level a least-squares fit on the
  sliding patterns gives, both with the same s = 0.95;
* Fig. 17 runs on the same aged actuator and compensation as Fig. 16;
* Fig. 18: the sawtooth's span and period are the bench's (fig18_amplitude, fig18_period;
  literal: 0 to 0.1 rad over 1 s), three periods (the figure's two and one more).

Each figure's registry entry carries the same list (``PaperFigure.assumptions``).

Modules
-------
* :mod:`~fricctl.paper.benches` -- :class:`~fricctl.paper.benches.Bench`, ``bench(name)``,
  ``BENCHES`` (the shipped JSON files);
* :mod:`~fricctl.paper.network` -- :class:`PaperNetwork`, :func:`train_paper_network`;
* :mod:`~fricctl.paper.common` -- the constants, the cached designs, the step and
  link runs and the measurements several figures share;
* ``figNN`` -- one module per figure: its frozen result, ``run(network, ...)``, its
  claim makers and its registry entry ``FIGURE = PaperFigure(...)``;
* :mod:`~fricctl.paper.registry` -- :class:`PaperFigure`, :func:`paper_figures`
  (the entries of every ``figNN`` module, found by name);
* :mod:`~fricctl.paper.claims` -- :class:`Claim`, :func:`gate`, :func:`paper_claims`;
* :mod:`~fricctl.paper.runaway` -- :class:`RunawayCheck`, :func:`wind_up`,
  :func:`divergence`, :func:`reversal`, :func:`coast_decay`;
* :mod:`~fricctl.paper.coast` -- the coast test, one per network (not a paper figure);
* :mod:`~fricctl.paper.table` -- :class:`ClaimStats` over seeds, ``claims.md``/``claims.json``;
* :mod:`~fricctl.paper.sweep` -- :func:`robustness_sweep`;
* :mod:`~fricctl.paper.reproduce` -- :func:`reproduce_paper` (seeds x pipelines).

Adding a figure: write ``fricctl/paper/figNN.py`` (result, ``run``, claim makers,
``FIGURE``) and its plot (``@paper_plot(NN)`` in :mod:`fricctl.figures.paper`);
nothing else changes.  Run a figure with ``paper.fig09.run(network)`` (the modules
are imported when the package is) or ``paper.FIGURES[9](network)``.

Notes
-----
The bench is the simulator of :mod:`fricctl.simulate` with the plant of a bench (the literal
one is the paper actuator of :mod:`fricctl.params`); it has no measurement noise, no torque ripple and no
thermal drift unless asked for (the consistent bench asks for the first two in its ``sensing``:
:mod:`fricctl.paper.benches`).  Claims about the real hardware (e.g. "after
30 h of operation") are modelled, not measured.
"""

from __future__ import annotations

from types import MappingProxyType

from . import benches, coast
from .claims import EXTRA, Claim, claims_summary, gate, is_extra, paper_claims
from .common import (ACCURACY_DEG, AGED_SCALE, STICK_MIN_DURATION, restarts, sign_changes,
                     stick_intervals_after_motion)
from .network import PaperNetwork, train_paper_network
from .registry import PaperFigure, paper_figures
from .reproduce import PaperResults, SeedRun, reproduce_paper, seed_run
from .runaway import RunawayCheck, coast_decay, divergence, reversal, wind_up
from .sweep import SweepResult, robustness_sweep
from .table import (HOLD_RATE, ClaimStats, aggregate_claims, benches_glance, claims_json, claims_markdown,
                    representative_seed)

__all__ = [
    "PaperNetwork", "train_paper_network",
    "FIGURES", "PaperFigure", "paper_figures", "SweepResult", "robustness_sweep",
    "Claim", "gate", "paper_claims", "claims_summary", "is_extra", "EXTRA",
    "RunawayCheck", "wind_up", "divergence", "reversal", "coast_decay", "coast", "benches",
    "ClaimStats", "aggregate_claims", "representative_seed", "claims_markdown", "claims_json", "HOLD_RATE",
    "benches_glance",
    "PaperResults", "SeedRun", "seed_run", "reproduce_paper",
    "stick_intervals_after_motion", "restarts", "sign_changes",
    "ACCURACY_DEG", "STICK_MIN_DURATION", "AGED_SCALE",
]

#: Figure number -> experiment function (read-only; built from the registry).
FIGURES = MappingProxyType({n: fig.run for n, fig in paper_figures().items()})
