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
linearised error a bounded quadratic posed once in CasADi (IPOPT; inertia
and friction magnitudes kept non-negative).  Standard errors from the Jacobian at the
optimum, the residual summed over blocks longer than its correlation
(:mod:`~fricctl.identify.uncertainty`; the white-noise formula is optimistic for an
output error, 36 times on a seeded 1 kHz open-loop record).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .. import _validate as v
from ..controllers import Controller
from ..datasets import Run
from ..estimation import decimate
from .idim import IdimRecipe, idim_ls
from .least_squares import IdentificationResult
from .models import LINEAR_MODELS, MODELS, lower_bounds, model_names
from .simulation import (RecordLoop, initial_velocity, record_loop, record_substeps,
                         simulate_record)
from .uncertainty import block_covariance

__all__ = ["didim", "OUTPUTS", "MIN_INERTIA_SHARE", "MAX_REPLAY_COST"]

#: The simulated outputs DIDIM can match: ``"torque"`` (closed loop only) and ``"position"``.
OUTPUTS = ("torque", "position")
#: Least inertia DIDIM's iterates may take, as a share of its start's (the equation error's):
#: a refinement stays within a decade below it, and the replay's RK4 sub-steps grow as 1/I [-].
MIN_INERTIA_SHARE = 0.1
#: Most RK4 sub-steps per sample a trial's simulation may run, as a multiple of its start's [-]
#: (the cost of a replay, per sample of the record): a trial beyond is refused as a step that
#: raises the cost.  The inertia's floor alone allows ten times the start's rate; an iterate
#: far stiffer than that (viscous/inertia thousands of times the start's) is no refinement,
#: and each of its replays costs hundreds of the start's (228 s of one diagnosis of a 60 s,
#: 2 kHz closed-loop record drifting in its replay, benchmarks/README.md).
MAX_REPLAY_COST = 10


@dataclass(frozen=True, kw_only=True)
class _Problem:
    runs: tuple
    """The record's segments (one, or the pieces of a record with gaps: position output)."""
    loop: RecordLoop
    names: tuple
    output: str
    initial_velocities: tuple
    recipe: IdimRecipe

    @cached_property
    def _measured(self) -> np.ndarray:
        if self.output == "torque":
            return self.observed(self.runs[0].torque)
        return np.concatenate([r.position - r.position.mean() for r in self.runs])

    def measured(self) -> np.ndarray:
        return self._measured

    def observed(self, x) -> np.ndarray:
        """The output as compared: a torque decimated by the recipe (the parallel filtering
        of IDIM-LS: the drive's high-frequency torque, a loop's answer to what no rigid model
        holds, is left out -- on EMPS it is 94 % of the raw torque error), a position as is."""
        if self.output == "position":
            return np.asarray(x, dtype=float)
        return decimate(np.asarray(x, dtype=float)[self.recipe.border:], self.recipe.decimation)

    def residual(self, theta) -> np.ndarray:
        params = dict(zip(self.names, theta))
        if self.output == "torque":
            sim = simulate_record(self.runs[0], params, self.loop,
                                  initial_velocity=self.initial_velocities[0])
            return self._measured - self.observed(sim.torque)
        out = []
        for run, w0 in zip(self.runs, self.initial_velocities):
            r = run.position - simulate_record(run, params, self.loop, initial_velocity=w0).position
            # the encoder's first reading (the replay's start) is off by up to a count: a
            # constant the parameters cannot explain, profiled out (the start fitted by LS)
            out.append(r - r.mean())
        return np.concatenate(out)

    def substeps(self, theta) -> int:
        """RK4 sub-steps per sample the simulation at ``theta`` runs (its cost per sample)."""
        return max(record_substeps(run, dict(zip(self.names, theta))) for run in self.runs)

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
          tolerance: float = 1e-6, start: IdentificationResult | None = None,
          loop: RecordLoop | None = None, also: tuple = ()) -> IdentificationResult:
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
    start : IdentificationResult, optional
        The estimate to start from, over the same parameter names (default: the record's
        IDIM-LS by ``recipe``); :func:`~fricctl.identify.identify_record` starts from its
        equation error on the record's own signals.
    loop : RecordLoop, optional
        How the record is simulated, when already decided (:func:`record_loop`);
        exclusive with ``controller``.
    also : tuple of fricctl.datasets.Run
        More segments of the same drive (a record with gaps: the blocks left in by a
        delete-a-block jackknife), each replayed from its own start; the output errors of
        all segments are minimised together.  Open loop (replay) and position output only;
        ``start`` is then required.

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
    errors come from the residual summed over blocks longer than its correlation
    (:func:`~fricctl.identify.uncertainty.block_covariance`).  Stick-slip makes the simulated
    output a non-smooth function of the parameters; the forward differences step by
    1e-4 of each magnitude, above that roughness on the records tested.

    The iterates stay near their start: the inertia above :data:`MIN_INERTIA_SHARE` of it,
    and a trial step whose simulation would run more than :data:`MAX_REPLAY_COST` times the
    start's RK4 sub-steps per sample (:func:`~fricctl.identify.simulation.record_substeps`)
    is refused as one that raises the cost, the count said in the warnings.
    """
    v.instance("run", run, Run, "a fricctl.datasets.Run")
    if v.choice("model", model, MODELS) not in LINEAR_MODELS:
        raise ValueError(f"model: DIDIM starts from IDIM-LS, which needs a linear model "
                         f"({', '.join(LINEAR_MODELS)}), not {model!r}")
    max_iterations = v.integer("max_iterations", max_iterations, low=1)
    tolerance = v.real("tolerance", tolerance, positive=True)
    if loop is None:
        loop = record_loop(run, controller)
    elif controller is not None:
        raise ValueError("controller: give the controller or the loop, not both")
    else:
        v.instance("loop", loop, RecordLoop)
    if output is None:
        output = "torque" if loop.closed else "position"
    v.choice("output", output, OUTPUTS)
    if output == "torque" and not loop.closed:
        raise ValueError("output: 'torque' needs a closed-loop simulation (an open-loop replay "
                         "applies the recorded torque); give the controller or use 'position'")
    recipe = IdimRecipe() if recipe is None else v.instance("recipe", recipe, IdimRecipe)
    names = model_names(model, offset)
    own_start = start is None
    if own_start:
        start = idim_ls(run, model=model, offset=offset, recipe=recipe)
    else:
        v.instance("start", start, IdentificationResult)
        if tuple(start.names) != names:
            raise ValueError(f"start: its parameters {start.names} are not the model's {names}")
    also = tuple(v.instance(f"also[{i}]", r, Run, "a fricctl.datasets.Run")
                 for i, r in enumerate(also))
    if also and (loop.closed or output != "position" or start is None):
        raise ValueError("also: more segments are replayed (open loop, position output) from a "
                         "given start")
    runs = (run,) + also
    prob = _Problem(runs=runs, loop=loop, names=names, output=output, recipe=recipe,
                    initial_velocities=tuple(initial_velocity(r, recipe.cutoff,
                                                              recipe.filter_order) for r in runs))
    theta = start.estimates.copy()
    # magnitude of each parameter: its start, or (offset near 0) a thousandth of the largest
    # torque it could explain alone
    mag = np.maximum(np.abs(theta), 1e-3 * np.abs(start.measured).max())
    lower = lower_bounds(names)
    # DIDIM refines its start: an inertia below a tenth of the start's is no refinement, and
    # its replay needs ten times the RK4 sub-steps and more (the stiffness b/I; a record the
    # rigid model cannot hold -- an unmodelled stop or offset -- drove iterates to the old bound
    # of a thousandth, and one diagnosis to 23 min of replays).  At this bound the estimate is
    # flagged (at_bound).
    lower[names.index("inertia")] = MIN_INERTIA_SHARE * theta[names.index("inertia")]
    r = prob.residual(theta)
    cost = float(r @ r)
    lam, converged, warnings = 1e-3, False, list(loop.warnings)
    # a trial whose simulation would run more than MAX_REPLAY_COST times the start's RK4
    # sub-steps is refused before it runs (its replay and its Jacobian's would cost that many
    # times the start's): the stiffest it asked for is reported
    substeps0 = prob.substeps(theta)
    max_substeps, refused = MAX_REPLAY_COST * substeps0, []
    step_solver = _StepSolver(len(names))
    for iteration in range(1, max_iterations + 1):
        J, J_at = prob.jacobian(theta, r, 1e-4 * mag), theta
        D = np.sqrt(np.sum(J * J, axis=0))
        while True:
            step = step_solver(J, r, D, lam, lower - theta, mag)
            trial = np.maximum(theta + step, lower)  # IPOPT honours bounds to its tolerance
            n_sub = prob.substeps(trial)
            if n_sub > max_substeps:  # too costly: a rejected step, as one that raises the cost
                refused.append(n_sub)
                rt, ct = r, math.inf
            else:
                try:
                    rt = prob.residual(trial)
                    ct = float(rt @ rt)
                except ValueError:  # a trial the replay cannot simulate (diverges, too stiff):
                    rt, ct = r, math.inf  # a rejected step, as one that raises the cost
            if not math.isfinite(ct):
                ct = math.inf
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
    if refused:
        warnings.append(f"DIDIM refused {len(refused)} trial step(s) whose simulation would run "
                        f"up to {max(refused)} RK4 sub-steps per sample, more than "
                        f"{MAX_REPLAY_COST} times the start's {substeps0}: a joint that much "
                        f"stiffer (viscous/inertia) is no refinement of the start, and each "
                        f"of its replays would cost as many times the start's")
    if not converged:
        warnings.append(f"DIDIM did not converge in {max_iterations} iterations (last relative "
                        f"step {change:.2g}): the estimate is the last iterate")
    if own_start and not start.fit_percent >= 0.0:
        # a start worse than the torque's mean (review R12: a constant torque driving the joint
        # one way; DIDIM then gave inertia 7.5e-7 +- 1e-8 for 2.9e-3 at a position fit of
        # 99.9995 %): the replay follows the record with parameters the record does not excite
        warnings.append(
            f"its IDIM-LS start fits {start.fit_percent:.3g} % of the torque, less than its mean "
            f"does: DIDIM refines an estimate the equation error does not support, and a "
            f"replay can follow a record that barely excites a parameter (a joint at one speed: "
            f"the inertia) with any value of it -- its fit and standard errors do not vouch for "
            f"the estimate")
    if theta is not J_at:  # else the last iteration took no step: its Jacobian is this one
        J = prob.jacobian(theta, r, 1e-4 * mag)  # (r is theta's; three replays saved)
    measured = prob.measured()
    predicted = measured - r
    bc = block_covariance(J, r)
    if bc.capped:
        warnings.append(f"the {output} error is correlated over {bc.correlation:.3g} samples, "
                        f"more than a twentieth of the record: the standard errors are lower "
                        f"bounds")
    at_bound = np.isfinite(lower) & (theta <= lower + 1e-9 * mag)
    return IdentificationResult(
        names=names, estimates=theta, std=bc.std,
        condition_number=float(np.linalg.cond(J)),
        abs_diag_r=np.abs(np.diag(np.linalg.qr(J, mode="r"))), measured=measured,
        predicted=predicted, model=model, units=run.units, recipe=recipe,
        solver_status=f"{'converged' if converged else 'not converged'}: {output} error, "
                      f"{loop.describe()}",
        iterations=iteration, at_bound=at_bound, method="DIDIM", warnings=tuple(warnings))


class _StepSolver:
    """The Levenberg-Marquardt step ``argmin ||r - J d||^2 + lam ||D d||^2`` subject to
    ``d >= lower``: a p-variable bounded quadratic posed once in CasADi (IPOPT), its
    matrices NLP parameters, so each step costs a solve and not a graph over the record's
    samples (which took four fifths of a DIDIM's time)."""

    def __init__(self, p: int):
        import casadi as ca

        z = ca.MX.sym("z", p)
        H = ca.MX.sym("H", p, p)
        c = ca.MX.sym("c", p)
        f = 0.5 * ca.dot(z, ca.mtimes(H, z)) - ca.dot(c, z)
        self.p = p
        self.solver = ca.nlpsol("lm_step", "ipopt",
                                {"x": z, "p": ca.vertcat(ca.vec(H), c), "f": f},
                                {"ipopt.print_level": 0, "print_time": False,
                                 "ipopt.sb": "yes", "ipopt.tol": 1e-12})

    def __call__(self, J, r, D, lam, lower, mag) -> np.ndarray:
        S = 1e-2 * mag  # the step in units of a hundredth of each parameter's magnitude
        Js = J * S
        H = Js.T @ Js + lam * np.diag((D * S) ** 2)
        c = Js.T @ r
        nrm = float(np.max(np.abs(np.diag(H)))) or 1.0
        sol = self.solver(x0=np.zeros(self.p), p=np.concatenate([(H / nrm).ravel(order="F"),
                                                                  c / nrm]),
                          lbx=np.minimum(lower, 0.0) / S, ubx=np.inf)
        if not self.solver.stats()["success"]:
            raise ValueError(f"the Levenberg-Marquardt step failed "
                             f"({self.solver.stats()['return_status']})")
        return np.asarray(sol["x"]).ravel() * S
