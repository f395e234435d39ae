r"""When the model is wrong: show the disagreement, name its cause, extend, measure the gain.

Given a measured record (:class:`~fricctl.datasets.Run`), :func:`diagnose` does what
an engineer does when simulation and experiment disagree:

1. **Baseline.**  Fit the rigid model ``I*q'' = Tm - b*w - Fc*sign(w)`` (stiction at
   Fc) by inverse-dynamics least squares, or take a supplied nominal
   :class:`~fricctl.plant.JointModel` as given (its JSON file format is in
   :mod:`fricctl.plant.model`).
2. **What the simulation gets wrong.**  Re-simulate the model driven by the
   measured torque over short windows (0.5 s), each started from the measured
   state, and compare position and velocity with the measurement
   (:func:`windowed_simulation`); and the equation-error (torque) residual
   ``LP(Tm) - LP(model torque)`` on the samples where the joint slides
   (:func:`torque_residual`).
3. **Name the cause.**  Every candidate of :data:`CAUSES` adds its term to the
   baseline; each is scored by *blocked cross-validation* (the record cut in
   contiguous blocks; fit on all blocks but one, predict the one left out,
   hyper-parameters such as the ripple period or the delay chosen on the
   training blocks only), as the fraction of the baseline's held-out torque
   residual it removes.  Among the candidates that remove at least
   :data:`MIN_SCORE` of it, the best whose extended model does not simulate the
   held-out windows worse than the baseline is named (if none simulates better,
   the best torque score decides: stick-slip re-simulation is chaotic); with no
   candidate above :data:`MIN_SCORE`, ``none``.
4. **Extend and measure the gain.**  Refit the model with the named term
   (CasADi, :func:`fricctl.identify.fit_least_squares`), re-simulate, and report
   the held-out RMS before and after, for the torque residual and for the
   windowed simulation error.

Modules
-------
:mod:`.signals` (velocity, acceleration, direction, rest, a model's torque along the
record), :mod:`.windows` (the windowed re-simulation), :mod:`.crossval` (variants,
blocked cross-validation, refits), :mod:`.causes` (one module per cause, and the
registry), :mod:`.report` (:class:`Diagnosis`), :mod:`.api` (the workflow).

Notes
-----
Left out: causes acting together (one is named per call; diagnose again with the
extended model as the nominal one to find a second, as chapter 08 does);
backlash; gravity and position-dependent inertia; sub-sample delays (the delay
is a whole number of samples); torque measurement noise models (least squares
assumes white residuals, so the reported standard errors are optimistic).
"""

from .api import PredictionErrors, TorqueResidual, diagnose, prediction_errors, torque_residual
from .causes import CAUSES, NOMINAL_ONLY
from .report import MIN_SCORE, Diagnosis, Gain
from .windows import SimulationRMS, WindowedSimulation, windowed_simulation

__all__ = [
    "CAUSES", "NOMINAL_ONLY", "MIN_SCORE",
    "WindowedSimulation", "Diagnosis", "diagnose", "windowed_simulation",
    "prediction_errors", "torque_residual", "Gain", "SimulationRMS", "TorqueResidual",
    "PredictionErrors",
]
