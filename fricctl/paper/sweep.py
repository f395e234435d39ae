"""Where NN compensation keeps the PD steady-state error below 0.3 deg: friction scale x link inertia."""

from __future__ import annotations

from concurrent.futures import Executor
from dataclasses import dataclass

import numpy as np

from .. import _validate as v
from .. import controllers as ctl
from ..compensators import NoCompensation
from ..compensators.nn_confirmed import VELOCITIES, network_compensator
from ..design import Design
from ..nn import FrictionNet
from ..params import ActuatorParams, paper_actuator
from ..simulate import simulate_batch
from .common import ACCURACY_DEG, SS_WINDOW, designs

__all__ = ["SweepResult", "robustness_sweep"]


@dataclass(frozen=True, eq=False, kw_only=True)
class SweepResult:
    """Steady-state error of the PD step over friction scale x link inertia.

    Attributes
    ----------
    friction_scales : true friction / nominal [-], shape (S,)
    link_inertias : [kg*m^2], shape (L,)
    error_nn : ``|steady-state error|`` with NN compensation [rad], shape (L, S)
    error_none : without compensation [rad], shape (L, S)
    settled_nn : the compensated joint at rest over the whole steady-state window (the last
        0.5 s) [bool], shape (L, S); where it is not, it still hunts and ``error_nn`` is the mean
        of a moving error, not a steady state
    tolerance : the accuracy asked for [rad]
    step : reference step [rad]
    kp, kd : the gains used (fixed: the controller is not redesigned) [N*m/rad], [N*m*s/rad]
    compensation_scale : s [-]
    """

    friction_scales: np.ndarray
    link_inertias: np.ndarray
    error_nn: np.ndarray
    error_none: np.ndarray
    settled_nn: np.ndarray
    tolerance: float
    step: float
    kp: float
    kd: float
    compensation_scale: float

    @property
    def within(self) -> np.ndarray:
        """Where NN compensation meets the tolerance, shape (L, S) [bool]."""
        return self.error_nn < self.tolerance

    def report(self) -> str:
        """A table of ``|e_ss|`` [deg] with NN compensation (* marks >= tolerance, ~ a joint
        still moving in the last 0.5 s)."""
        head = "J_link [kg*m^2] | " + " | ".join(f"x{s:.2f}" for s in self.friction_scales)
        rows = [f"|e_ss| [deg] with NN compensation, step {np.rad2deg(self.step):.1f} deg, "
                f"tolerance {np.rad2deg(self.tolerance):.2f} deg (* = not met, ~ = still moving in the "
                "last 0.5 s: the mean of a hunting error)", head]
        for i, j in enumerate(self.link_inertias):
            cells = [f"{np.rad2deg(e):.3f}{'*' if not ok else ''}{'' if still else '~'}"
                     for e, ok, still in zip(self.error_nn[i], self.within[i], self.settled_nn[i])]
            rows.append(f"{j:.4f} | " + " | ".join(cells))
        hunting = int(np.count_nonzero(self.within & ~self.settled_nn))
        rows.append(f"met in {int(self.within.sum())} of {self.within.size} cases"
                    + (f" ({hunting} of them still moving)" if hunting else ""))
        return "\n".join(rows)


@dataclass(frozen=True, eq=False, kw_only=True)
class _Row:
    """One link inertia of the sweep: ``|e_ss|`` over the friction scales [rad]."""

    error_nn: np.ndarray
    error_none: np.ndarray
    settled_nn: np.ndarray


def _sweep_row(params: ActuatorParams, net_json: str, scales: tuple, kp: float, kd: float,
               step: float, duration: float, comp_scale: float, simulator,
               velocity: str = "backward-difference") -> _Row:
    # Module-level and fed plain data (the net as JSON) so that any Executor,
    # including a process pool or a dask client, can run it.
    net = FrictionNet.from_json(net_json)
    base = params.friction_model()
    frs = [base.scaled(float(s)) for s in scales]
    c = ctl.pd_control(kp, kd, ctl.step(step))
    nn = simulator(params, c, network_compensator(net, velocity, scale=comp_scale), duration=duration,
                   friction=frs)
    none = simulator(params, c, NoCompensation(), duration=duration, friction=frs)
    last = nn.t >= nn.t[-1] - SS_WINDOW + 1e-12   # the window steady_state_error averages over
    return _Row(error_nn=np.abs(nn.steady_state_error(SS_WINDOW)),
                error_none=np.abs(none.steady_state_error(SS_WINDOW)),
                settled_nn=np.all(nn.stuck[..., last], axis=-1))


def robustness_sweep(net: FrictionNet, params: ActuatorParams | None = None, *,
                     friction_scales=(0.8, 0.9, 1.0, 1.1, 1.2),
                     link_inertias=(0.0, 0.0023, 0.0046, 0.0069, 0.0092),
                     step: float = float(np.deg2rad(30.0)), duration: float = 3.0,
                     design: Design | None = None, compensation_scale: float = 1.0,
                     tolerance: float = float(np.deg2rad(ACCURACY_DEG)),
                     executor: Executor | None = None, simulator=simulate_batch,
                     velocity: str = "backward-difference") -> SweepResult:
    """Where NN compensation keeps the PD steady-state error below ``tolerance``.

    For every link inertia (one job: a batch over the friction scales) the PD
    step is simulated with the net trained on the nominal actuator (not
    retrained) and without compensation.

    Parameters
    ----------
    net : FrictionNet
        Trained on the nominal actuator.
    params : ActuatorParams, optional
        The nominal actuator (its ``link_inertia`` is replaced by each sweep value).
    friction_scales : sequence of float
        True friction / nominal friction [-], > 0.
    link_inertias : sequence of float
        Link inertias [kg*m^2], >= 0.
    step : float
        Reference step [rad].
    duration : float
        Run length [s]; steady state is the mean over its last 0.5 s.
    design : Design, optional
        Fixed gains; default the paper's Fig. 16-17 PD (0.4 s, 0.85, with the
        0.0046 kg*m^2 link): a different load is *not* redesigned for.
    compensation_scale : float
        s of the compensator [-].
    tolerance : float
        Accuracy asked for [rad] (default the paper's 0.3 deg).
    executor : concurrent.futures.Executor, optional
        Runs the rows (``executor.submit``); e.g. a ``ProcessPoolExecutor`` or a
        ``dask.distributed.Client``'s executor.  Default: in this process.  A
        process pool must use the ``"spawn"`` start method
        (``mp_context=multiprocessing.get_context("spawn")``): forking a process
        whose numba/OpenMP threads have started aborts the workers.
    simulator : callable
        Batch simulator with :func:`fricctl.simulate.simulate_batch`'s signature.
    velocity : {"backward-difference", "confirmed"}
        The velocity the network is fed: the paper's backward difference, or the fricctl
        pipeline's direction-confirmed velocity (:mod:`fricctl.compensators.nn_confirmed`;
        :attr:`fricctl.paper.PaperNetwork.velocity` names a pipeline's).

    Returns
    -------
    SweepResult

    Notes
    -----
    Rigid joint only (the link is added to the inertia); the link's elasticity,
    gravity and a load-dependent friction are left out.
    """
    v.instance("net", net, FrictionNet)
    p = paper_actuator() if params is None else v.instance("params", params, ActuatorParams,
                                                            "an ActuatorParams")
    scales = v.array("friction_scales", friction_scales, min_size=1)
    links = v.array("link_inertias", link_inertias, min_size=1)
    if np.any(scales <= 0):
        raise ValueError(f"friction_scales must all be > 0, got {scales.tolist()}")
    if np.any(links < 0):
        raise ValueError(f"link_inertias must all be >= 0 [kg*m^2], got {links.tolist()}")
    step = v.real("step", step, positive=True, unit="rad")
    duration = v.real("duration", duration, positive=True, unit="s")
    tolerance = v.real("tolerance", tolerance, positive=True, unit="rad")
    compensation_scale = v.real("compensation_scale", compensation_scale)
    velocity = v.choice("velocity", velocity, VELOCITIES)
    if executor is not None and not hasattr(executor, "submit"):
        raise ValueError(f"executor must be a concurrent.futures.Executor, got {type(executor).__name__}")
    d = designs(p)["fig16-17"] if design is None else v.instance("design", design, Design)
    args = [(p.replace(link_inertia=float(j)), net.to_json(), tuple(scales.tolist()), d.kp, d.kd,
             step, duration, compensation_scale, simulator, velocity) for j in links]
    if executor is None:
        rows = [_sweep_row(*a) for a in args]
    else:
        futures = [executor.submit(_sweep_row, *a) for a in args]
        rows = [f.result() for f in futures]
    return SweepResult(friction_scales=scales, link_inertias=links,
                       error_nn=np.array([r.error_nn for r in rows]),
                       error_none=np.array([r.error_none for r in rows]),
                       settled_nn=np.array([r.settled_nn for r in rows]), tolerance=tolerance, step=step,
                       kp=d.kp, kd=d.kd, compensation_scale=compensation_scale)
