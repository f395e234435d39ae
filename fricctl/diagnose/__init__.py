r"""When the model is wrong: show the disagreement, name its cause, extend, measure the gain.

Given a measured record (:class:`~fricctl.datasets.Run`), :func:`diagnose` does what
an engineer does when simulation and experiment disagree:

0. **End stops.**  Impacts against a hard limit the record hits again and again (or once
   far harder than torque and friction can brake) are found (:mod:`.stops`); their contacts
   are left out of the equation error (with the filter's reach), of the re-simulation
   windows, of the twin and of the verdict, and the report says so.  The stop is not
   modelled.
1. **Baseline.**  Fit the rigid model ``I*q'' = Tm - b*w - Fc*sign(w)`` (stiction at
   Fc) by inverse-dynamics least squares, or take a supplied nominal
   :class:`~fricctl.plant.JointModel` (its JSON file format is in
   :mod:`fricctl.plant.model`) without the effects a cause can judge: its offset,
   asymmetric levels, Stribeck excess are removed (:func:`judged_by_removal`) and
   named again only if the record supports them (marked "held by the supplied
   model"), so that the causes do not depend on what the model happened to hold.
2. **What the simulation gets wrong.**  Re-simulate the model driven by the
   measured torque over short windows (0.5 s), each started from the measured
   state, and compare position and velocity with the measurement
   (:func:`windowed_simulation`); and the equation-error (torque) residual
   ``LP(Tm) - LP(model torque)`` on the samples where the joint slides
   (:func:`torque_residual`).
3. **Name every cause, one step at a time.**  Every candidate of :data:`CAUSES`
   adds its term to the model; each is scored by *blocked cross-validation* (the
   record cut in contiguous blocks; fit on all blocks but one, predict the one
   left out, hyper-parameters such as the ripple period or the delay chosen on
   the training blocks only), as the fraction of the remaining held-out torque
   residual it removes, net of what the same term removes on the record's
   effect-free twin (:mod:`.twin`: the measuring chain's share, taken of the record's
   chain residual: :func:`~.selection.net_of_chain`).  Among the
   candidates whose net score reaches :data:`MIN_SCORE` and that can be told on
   this record (not collinear with the model's columns, no coefficient at a
   bound, no resonance above the excitation's band: else "cannot be told on this
   record, because ..."), the best whose extended model does not simulate the
   held-out windows worse is named (if none simulates better, the best torque
   score decides: stick-slip re-simulation is chaotic); then the search repeats
   with that term in the model (:mod:`.selection`), until no candidate reaches
   :data:`MIN_SCORE` (nothing named: ``none``).
4. **Extend and measure the gain.**  Refit the model with every named term
   (CasADi, :func:`fricctl.identify.fit_least_squares`), re-simulate, and report
   the held-out RMS before and after each step and overall, for the torque
   residual and for the windowed simulation error.
5. **What the data support below the line.**  The candidates of the step that named
   nothing that lower the held-out residual are reported with their net share, the
   verdict's F test of the reduction, their fitted physical parameters and the checks a
   named cause passes (:mod:`.below`): "supported" by the test and the checks, never by a
   magnitude; not named.

Every threshold is read off the record: the low-pass cut-off is the band the
excitation reaches above the encoder's quantisation noise (at most half the
Nyquist frequency), the chain's share comes from the record's own twin, the
resolvable presliding lengths and delays from its encoder and sample time.

Modules
-------
:mod:`.signals` (velocity, acceleration, direction, rest, the excitation's band, a
model's torque along the record), :mod:`.windows` (the windowed re-simulation),
:mod:`.crossval` (variants, their composition, blocked cross-validation, refits),
:mod:`.causes` (one module per cause, and the registry), :mod:`.twin` (the
effect-free twin), :mod:`.selection` (the forward selection), :mod:`.below` (what the
record supports below the naming line), :mod:`.report`
(:class:`Diagnosis`), :mod:`.api` (the workflow).

Notes
-----
Limits: a record of at most :data:`MAX_SAMPLES` samples (the diagnosis holds about
:data:`BYTES_PER_SAMPLE` bytes per sample: 7.0 kB, a 4 GB budget; a longer record is
refused with the number), sampled every 1 us to 10 s, with re-simulation windows of at
least 10 samples; a nominal model must be one the record's sample time can re-simulate
(:mod:`fricctl.simulate` refuses a plant needing more than 100 000 RK4 sub-steps per sample)
and agree with the record's sample time and encoder count when it states them.

Left out: position-dependent inertia (gravity and other loads of position are
the ``position_load`` cause); two effects acting on
the same model parameters (friction scale and drift); torque measurement noise
models (least squares assumes white residuals, so the reported standard errors are
optimistic).
"""

from .api import (BYTES_PER_SAMPLE, MAX_SAMPLES, PredictionErrors, TorqueResidual,
                  check_model_agrees, diagnose, judged_by_removal, prediction_errors,
                  torque_residual)
from .below import BelowLine
from .causes import CAUSES, NOMINAL_ONLY
from .report import Diagnosis, Gain
from .selection import MIN_SCORE, Step
from .windows import SimulationRMS, WindowedSimulation, windowed_simulation

__all__ = [
    "CAUSES", "NOMINAL_ONLY", "MIN_SCORE",
    "WindowedSimulation", "Diagnosis", "diagnose", "windowed_simulation",
    "prediction_errors", "torque_residual", "Gain", "SimulationRMS", "TorqueResidual",
    "PredictionErrors", "Step", "MAX_SAMPLES", "BYTES_PER_SAMPLE", "check_model_agrees",
    "judged_by_removal", "BelowLine",
]
