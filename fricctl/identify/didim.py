r"""DIDIM: the parameters that make the simulated record match the measured one.

Gautier, Janot & Vandanjon, "A new closed-loop output error method for parameter
identification of robot dynamics", IEEE Trans. Control Syst. Technol. 21(2), 2013.

The direct-and-inverse dynamic identification model simulates the record with the
parameters (:mod:`~fricctl.identify.simulation`: closed loop through the record's
controller, or the recorded torque replayed) and minimises the output error

.. math::

    \min_\theta \; \| y - \hat y(\theta) \|^2

over the dynamic parameters, where ``y`` is what the record measures without
differentiation: the drive torque of a closed-loop record (the paper's choice: under a
stiff loop the simulated position barely depends on the parameters, the torque that
holds it on the reference does), the encoder position of an open-loop one (no derivative
of a quantised signal enters, which is the point).  No regressor is built from the
measured motion, so the errors-in-variables bias of IDIM-LS cannot arise.

Solver: Levenberg-Marquardt on a forward-difference Jacobian of the simulation (each
column one more simulation), each step the bounded linear least squares of the
linearised error posed in CasADi (:func:`~fricctl.identify.fit_least_squares`, inertia
and friction magnitudes kept non-negative).  Standard errors from the Jacobian at the
optimum: ``sigma * sqrt(diag((J^T J)^-1))``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _validate as v
from ..controllers import Controller
from ..datasets import Run
from ..estimation import decimate
from .idim import IdimRecipe, idim_ls
from .least_squares import IdentificationResult, fit_least_squares, linear_prediction
from .models import LINEAR_MODELS, MODELS, lower_bounds, model_names
from .simulation import RecordLoop, initial_velocity, record_loop, simulate_record

__all__ = ["didim", "OUTPUTS"]

#: The simulated outputs DIDIM can match: ``"torque"`` (closed loop only) and ``"position"``.
OUTPUTS = ("torque", "position")


@dataclass(frozen=True, kw_only=True)
class _Problem:
    run: Run
    loop: RecordLoop
    names: tuple
    output: str
    initial_velocity: float
    recipe: IdimRecipe

    def measured(self) -> np.ndarray:
        return self.observed(self.run.torque if self.output == "torque" else self.run.position)

    def observed(self, x) -> np.ndarray:
        """The output as compared: a torque decimated by the recipe (the parallel filtering
        of IDIM-LS: the drive's high-frequency torque, a loop's answer to what no rigid model
        holds, is left out -- on EMPS it is 94 % of the raw torque error), a position as is."""
        if self.output == "position":
            return np.asarray(x, dtype=float)
        return decimate(np.asarray(x, dtype=float)[self.recipe.border:], self.recipe.decimation)

    def residual(self, theta) -> np.ndarray:
        sim = simulate_record(self.run, dict(zip(self.names, theta)), self.loop,
                              initial_velocity=self.initial_velocity)
        if self.output == "torque":
            return self.measured() - self.observed(sim.torque)
        r = self.run.position - sim.position
        # the encoder's first reading (the replay's start) is off by up to a count: a
        # constant the parameters cannot explain, profiled out (the start fitted by LS)
        return r - r.mean()

    def jacobian(self, theta, r0, step) -> np.ndarray:
        """d(simulated output)/d(theta) by forward differences (``-d r/d theta``)."""
        J = np.empty((r0.size, theta.size))
        for j in range(theta.size):
            th = theta.copy()
            th[j] += step[j]
            J[:, j] = (r0 - self.residual(th)) / step[j]
        return J


def didim(run, *, model: str = "coulomb_viscous", offset: bool | None = None,
          output: str | None = None, controller: Controller | None = None,
          recipe: IdimRecipe | None = None, max_iterations: int = 30,
          tolerance: float = 1e-6) -> IdentificationResult:
    """DIDIM of a record: the simulation (output) error minimised over the parameters.

    Parameters
    ----------
    run : fricctl.datasets.Run
        Measured record.
    model : {"coulomb_viscous", "asymmetric"}
        Linear friction model (the start is its IDIM-LS fit).
    offset : bool, optional
        Include the constant offset (default: as in :data:`~fricctl.identify.MODELS`).
    output : {"torque", "position"}, optional
        The output matched; default ``"torque"`` in closed loop, ``"position"`` in open
        loop (a replay's torque is the record's: ``"torque"`` needs a closed loop).
    controller : fricctl.controllers.Controller, optional
        The record's controller; default inferred
        (:func:`~fricctl.identify.simulation.record_loop`).
    recipe : IdimRecipe, optional
        Signal processing of the IDIM-LS start; its border and decimation also apply
        to a torque output (measured and simulated alike).
    max_iterations : int
        Most Levenberg-Marquardt iterations (Jacobians) [-].
    tolerance : float
        Stop when a step changes the parameters, each in units of its magnitude, by
        less than ``tolerance`` relative to their norm [-].

    Returns
    -------
    IdentificationResult
        ``method="DIDIM"``, ``measured``/``predicted`` the recorded and the simulated
        output (so ``fit_percent`` is the simulation fit), ``condition_number`` that of
        the Jacobian.

    Notes
    -----
    The simulated joint is rigid, without encoder quantisation or noise; a closed loop
    runs the package's sampled loop (:mod:`fricctl.simulate`).  The output error of a
    simulation is coloured (a position integrates every torque error), so the standard
    errors, which assume white errors, are optimistic.  Stick-slip makes the simulated
    output a non-smooth function of the parameters; the forward differences step by
    1e-4 of each magnitude, above that roughness on the records tested.
    """
    v.instance("run", run, Run, "a fricctl.datasets.Run")
    if v.choice("model", model, MODELS) not in LINEAR_MODELS:
        raise ValueError(f"model: DIDIM starts from IDIM-LS, which needs a linear model "
                         f"({', '.join(LINEAR_MODELS)}), not {model!r}")
    max_iterations = v.integer("max_iterations", max_iterations, low=1)
    tolerance = v.real("tolerance", tolerance, positive=True)
    loop = record_loop(run, controller)
    if output is None:
        output = "torque" if loop.closed else "position"
    v.choice("output", output, OUTPUTS)
    if output == "torque" and not loop.closed:
        raise ValueError("output: 'torque' needs a closed-loop simulation (an open-loop replay "
                         "applies the recorded torque); give the controller or use 'position'")
    recipe = IdimRecipe() if recipe is None else v.instance("recipe", recipe, IdimRecipe)
    start = idim_ls(run, model=model, offset=offset, recipe=recipe)
    names = model_names(model, offset)
    prob = _Problem(run=run, loop=loop, names=names, output=output, recipe=recipe,
                    initial_velocity=initial_velocity(run, recipe.cutoff,
                                                     recipe.filter_order))
    theta = start.estimates.copy()
    # magnitude of each parameter: its start, or (offset near 0) a thousandth of the largest
    # torque it could explain alone
    mag = np.maximum(np.abs(theta), 1e-3 * np.abs(start.measured).max())
    lower = lower_bounds(names)
    lower[names.index("inertia")] = 1e-3 * theta[names.index("inertia")]  # simulable
    r = prob.residual(theta)
    cost = float(r @ r)
    lam, converged, warnings = 1e-3, False, list(loop.warnings)
    for iteration in range(1, max_iterations + 1):
        J = prob.jacobian(theta, r, 1e-4 * mag)
        D = np.sqrt(np.sum(J * J, axis=0))
        while True:
            step = _lm_step(J, r, D, lam, names, lower - theta, mag)
            trial = theta + step
            rt = prob.residual(trial)
            ct = float(rt @ rt)
            if ct <= cost:
                break
            lam *= 4.0
            if lam > 1e8:
                step = np.zeros_like(theta)
                break
        change = float(np.linalg.norm(step / mag) / np.linalg.norm(theta / mag))
        if ct <= cost:
            theta, r, cost, lam = trial, rt, ct, max(lam / 3.0, 1e-9)
        if change < tolerance:
            converged = True
            break
    if not converged:
        warnings.append(f"DIDIM did not converge in {max_iterations} iterations (last relative "
                        f"step {change:.2g}): the estimate is the last iterate")
    if output == "position":
        warnings.append("standard errors assume a white output error; a replayed position "
                        "integrates every torque error (coloured), so they are optimistic "
                        "(36x on a seeded 1 kHz test record)")
    J = prob.jacobian(theta, r, 1e-4 * mag)
    measured = prob.measured()
    measured = measured - measured.mean() if output == "position" else measured
    predicted = measured - r
    sigma = float(np.std(r, ddof=1))
    cov = np.linalg.inv(J.T @ J)
    at_bound = np.isfinite(lower) & (theta <= lower + 1e-9 * mag)
    return IdentificationResult(
        names=names, estimates=theta, std=sigma * np.sqrt(np.diag(cov)),
        condition_number=float(np.linalg.cond(J)),
        abs_diag_r=np.abs(np.diag(np.linalg.qr(J, mode="r"))), measured=measured,
        predicted=predicted, model=model, units=run.units, recipe=recipe,
        solver_status=f"{'converged' if converged else 'not converged'}: {output} error, "
                      f"{loop.describe()}",
        iterations=iteration, at_bound=at_bound, method="DIDIM", warnings=tuple(warnings))


def _lm_step(J, r, D, lam, names, lower, mag) -> np.ndarray:
    """``argmin ||r - J d||^2 + lam ||D d||^2`` subject to ``d >= lower``, in CasADi/IPOPT."""
    A = np.vstack([J, np.sqrt(lam) * np.diag(D)])
    b = np.concatenate([r, np.zeros(len(names))])
    res = fit_least_squares(linear_prediction, A, b, names=names, initial=np.zeros(len(names)),
                            lower=np.minimum(lower, 0.0), scale=1e-2 * mag)
    return res.estimates
