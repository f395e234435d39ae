"""Every estimator of ``fricctl identify`` on one record, validated on another.

:func:`compare_estimators` fits a record by IDIM-LS (the EMPS recipe), IDIM-IV, DIDIM
(closed loop through the record's controller), the equation error on the record's own
signals and the default (:func:`~fricctl.identify.identify_record`), and checks each
estimate on a validation record: its torque replayed (position fit, :func:`validate`)
and its force predicted by the EMPS recipe (relative error, the benchmark's
cross-test validation, :func:`~fricctl.identify.cross_validate`).  On EMPS: identify on
``DATA_EMPS.mat``, validate on ``DATA_EMPS_PULSES.mat`` (chapter 3, the README).
"""

from __future__ import annotations

from dataclasses import dataclass

from .. import _validate as v
from ..controllers import Controller
from ..datasets import Run
from .didim import didim
from .idim import cross_validate, idim_ls
from .iv import idim_iv
from .least_squares import IdentificationResult
from .record import Validation, identify_record, validate

__all__ = ["EstimatorRow", "compare_estimators", "estimator_table"]


@dataclass(frozen=True, kw_only=True, eq=False)
class EstimatorRow:
    """One estimator's fit and its validation on the other record."""

    name: str
    """How the estimator is asked for (``fricctl identify --recipe ...``)."""
    result: IdentificationResult
    validation: Validation
    """The validation record replayed with the estimate, and its equation error."""
    cross_validation_error: float
    """Relative error of the force the EMPS recipe predicts on the validation record [%]."""


def compare_estimators(run, validation_run, *, controller: Controller | None = None,
                       model: str = "coulomb_viscous") -> tuple:
    """The estimators fitted on ``run`` and validated on ``validation_run``.

    Parameters
    ----------
    run, validation_run : fricctl.datasets.Run
        Identification and validation records of the same drive.
    controller : fricctl.controllers.Controller, optional
        The record's PD controller for IDIM-IV and DIDIM (default: fitted to the torque).
    model : {"coulomb_viscous", "asymmetric"}

    Returns
    -------
    tuple of EstimatorRow
        ``idim_ls``, ``idim_iv``, ``didim``, ``auto`` (its equation error, its DIDIM, and
        the reported estimate, which is one of the two).
    """
    v.instance("run", run, Run, "a fricctl.datasets.Run")
    v.instance("validation_run", validation_run, Run, "a fricctl.datasets.Run")
    ident = identify_record(run, model=model)
    fits = [("idim_ls", idim_ls(run, model=model)),
            ("idim_iv", idim_iv(run, model=model, controller=controller)),
            ("didim (closed loop)", didim(run, model=model, controller=controller)),
            ("auto: equation error", ident.start)]
    if ident.refined is not None:
        fits.append(("auto: DIDIM (replay)", ident.refined))
    fits.append(("auto (default): reported", ident.result))
    return tuple(EstimatorRow(name=name, result=r, validation=validate(r, validation_run),
                              cross_validation_error=cross_validate(r, validation_run)
                              .relative_error)
                 for name, r in fits)


def estimator_table(rows) -> str:
    """A Markdown table of :func:`compare_estimators` rows: each parameter ``value +- std``,
    the validation record's replayed-position fit and force relative error."""
    rows = tuple(rows)
    names = rows[0].result.names
    head = ("| estimator | " + " | ".join(names)
            + " | validation: replayed position fit [%] | validation: force rel. error [%] |")
    out = [head, "|---" * (len(names) + 3) + "|"]
    for r in rows:
        cells = [f"{x:.4g} ± {s:.2g}" for x, s in zip(r.result.estimates, r.result.std)]
        out.append(f"| `{r.name}` | " + " | ".join(cells)
                   + f" | {r.validation.simulation_fit:.2f} | {r.cross_validation_error:.3f} |")
    return "\n".join(out)
