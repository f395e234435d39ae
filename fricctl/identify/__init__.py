r"""Friction identification by inverse-dynamics least squares, posed in CasADi.

The inverse dynamic identification model (IDIM) of one axis, rotary convention
(for a linear axis read force [N], mass [kg], [m], [m/s]):

.. math::

    \tau = I\,\ddot q + F_f(\dot q) + \text{offset},

with the friction laws of :mod:`~fricctl.identify.models` (``w`` = velocity,
friction has the sign of ``w``): ``"coulomb_viscous"``, ``"asymmetric"`` (EMPS
eq. 12, two positive magnitudes per direction) and ``"stribeck"``.

Every fit is a CasADi NLP solved by IPOPT over *scaled* variables
``theta = scale * z`` with bounds (inertia, viscous, Coulomb and static levels
non-negative, Stribeck velocity positive).  :func:`fit_least_squares` is the
generic entry point: any per-sample prediction written in CasADi symbols.
Statistics follow the IDIM-LS report of the EMPS benchmark (Janot, Gautier &
Brunot 2019): ``std_j = sigma * sqrt(((J^T J)^-1)_jj)`` with ``sigma`` the sample
standard deviation of the residual, relative std in %, condition number of the
observation (Jacobian) matrix, relative error ``100*||y - yhat|| / ||y||``.

Modules
-------
* :mod:`~fricctl.identify.models` -- :data:`MODELS`, :func:`model_names`,
  :func:`regressor`, :func:`inverse_dynamics` (numpy, the laws stated once);
* :mod:`~fricctl.identify.least_squares` -- :func:`fit_least_squares` and
  :class:`IdentificationResult` (CasADi + IPOPT, IDIM-LS statistics, ``report()``);
* :mod:`~fricctl.identify.fit` -- :func:`fit_friction` (a law from samples);
* :mod:`~fricctl.identify.idim` -- from a record: :func:`identify_run`, the EMPS
  recipe :class:`IdimRecipe` / :func:`idim_ls`, :class:`CrossValidation` /
  :func:`cross_validate`;
* :mod:`~fricctl.identify.simulation` -- the record simulated with identified
  parameters (closed loop through its controller, or its torque replayed);
* :mod:`~fricctl.identify.iv` -- :func:`idim_iv`, IDIM-LS refined with instruments
  simulated by the model (Janot, Vandanjon & Gautier 2014);
* :mod:`~fricctl.identify.didim` -- :func:`didim`, the simulation (output) error
  minimised over the parameters (Gautier, Janot & Vandanjon 2013);
* :mod:`~fricctl.identify.signals` -- the record's signals, filtered in its own motion band
  (also every diagnosis's);
* :mod:`~fricctl.identify.record` -- :func:`identify_record`, the default of ``fricctl
  identify`` and the baseline of every diagnosis: equation error on the record's signals,
  DIDIM, the choice between them by a Hausman test, validation on held-out halves;
* :mod:`~fricctl.identify.uncertainty` -- standard errors for coloured residuals (the
  score summed over blocks).

Notes
-----
Left out: weighted least squares, nonlinear laws in IDIM-IV and DIDIM, LuGre (its internal
state makes it an output-error problem), and any static (breakaway) information
-- samples at rest carry none in an inverse model and are dropped by
:func:`identify_run`.
"""

from __future__ import annotations

from .fit import fit_friction
from .didim import didim
from .idim import (CrossValidation, IdimObservations, IdimRecipe, cross_validate, identify_run,
                   idim_ls, idim_observations)
from .iv import idim_iv
from .record import RecordIdentification, Validation, equation_error, identify_record, validate
from .least_squares import IdentificationResult, fit_least_squares, linear_prediction
from .models import (
    LINEAR_MODELS,
    MODELS,
    inverse_dynamics,
    lower_bounds,
    model_names,
    parameter_unit,
    regressor,
)

__all__ = [
    "MODELS",
    "LINEAR_MODELS",
    "model_names",
    "parameter_unit",
    "lower_bounds",
    "regressor",
    "inverse_dynamics",
    "IdentificationResult",
    "fit_least_squares",
    "linear_prediction",
    "fit_friction",
    "identify_run",
    "IdimRecipe",
    "idim_ls",
    "CrossValidation",
    "cross_validate",
    "IdimObservations",
    "idim_observations",
    "idim_iv",
    "didim",
    "identify_record",
    "RecordIdentification",
    "equation_error",
    "validate",
    "Validation",
]
