r"""Disturbance observer (Ohnishi; the DOB of motion-control practice):
``d_hat = Q(s) [Tm - J_n s omega]``, ``T^at = d_hat``.

Everything that is not the nominal inertia's reaction -- friction, a load torque, an inertia
error -- is estimated and fed back, so the PD sees the nominal plant ``1/(J_n s^2)``.
``Q(s) = g/(s + g)``, first order; its bandwidth ``g`` [rad/s] is the one design knob.

Discretisation at the sample time Ts (stated, since the loop's signals are sampled):

* the acceleration ``s*omega`` is the difference of two backward-difference velocities,
  ``(omega_hat_k - omega_hat_{k-1})/Ts``; for a torque held per sample this difference is
  driven by the mean of the last two held torques, so the raw disturbance is
  ``d_k = (Tm_{k-1} + Tm_{k-2})/2 - J_n (omega_hat_k - omega_hat_{k-1})/Ts``
  (exact for a rigid joint under a constant disturbance, between encoder counts);
* ``Q`` is discretised by its pole (matched pole-zero, unit DC gain, the input at sample k
  -- not the zero-order-hold equivalent, which would use ``d_{k-1}``):
  ``d_hat_k = a d_hat_{k-1} + (1 - a) d_k``, ``a = exp(-g Ts)``.

State: ``(d_hat, omega_hat_{k-1}, Tm_{k-1}, Tm_{k-2})``.

Provenance: ``J_n`` is the identified model's total inertia (:attr:`JointModel.inertia`,
:attr:`ActuatorParams.total_inertia`); ``g`` the user's; :func:`make` defaults it to
``1/(10 Ts)`` [rad/s]: the Q loop carries about two samples of delay (the held torque, the
backward difference and the loop's one-sample command), which cost ``g * 2 Ts = 0.2 rad``
(11 deg) of phase at its crossover there.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _validate as v
from .base import CCode, Compensator, CompiledCompensator, Entry, joint_model

__all__ = ["DisturbanceObserver", "ENTRY", "default_bandwidth"]

#: Kind id in the compiled loop.
KIND = 5
P_INERTIA, P_BANDWIDTH = range(2)
X_D, X_W_PREV, X_TM1, X_TM2 = range(4)


def default_bandwidth(sample_time: float) -> float:
    """``1/(10 Ts)`` [rad/s]: see the module docstring."""
    return 1.0 / (10.0 * v.real("sample_time", sample_time, positive=True, unit="s"))


@dataclass(frozen=True, kw_only=True)
class DisturbanceObserver(Compensator):
    """First-order disturbance observer, ``T^at = d_hat``.

    Parameters
    ----------
    inertia : float
        Nominal inertia J_n [kg*m^2] (> 0).
    bandwidth : float
        Q-filter bandwidth g [rad/s] (> 0).
    scale : float
        Compensation scale s [-].

    Notes
    -----
    A joint at rest below one encoder count per sample reads zero velocity: the observer
    then sees the whole held torque as disturbance (stiction holds it), which is what makes
    a DOB hunt on a joint with static friction above its Coulomb level.  The plant's delay,
    if any, is not modelled (a delayed plant looks like an inertia error).
    """

    inertia: float
    """Nominal inertia J_n [kg*m^2]."""
    bandwidth: float
    """Q-filter bandwidth g [rad/s]."""
    scale: float = 1.0
    """Compensation scale s [-]."""
    name: str = "DOB"
    """Label in results and plots."""
    stateful = True  # its state: d_hat and the last velocity and torques

    @property
    def estimates_friction(self) -> bool:
        """False: ``d_hat`` is the whole disturbance (friction, inertia error, load)."""
        return False

    def __post_init__(self):
        v.real("inertia", self.inertia, positive=True, unit="kg*m^2")
        v.real("bandwidth", self.bandwidth, positive=True, unit="rad/s")
        v.real("scale", self.scale, nonneg=True)
        v.text("name", self.name)

    @classmethod
    def from_model(cls, model, *, bandwidth: float, scale: float = 1.0) -> "DisturbanceObserver":
        """The observer with the model's total inertia as J_n.

        Examples
        --------
        >>> from fricctl.params import paper_actuator
        >>> dob = DisturbanceObserver.from_model(paper_actuator(), bandwidth=50.0)
        >>> round(dob.inertia, 8)
        0.00286531
        """
        return cls(inertia=joint_model(model).inertia, bandwidth=bandwidth, scale=scale)

    def compiled(self):
        return CompiledCompensator(kind=KIND, params=np.array([self.inertia, self.bandwidth]),
                                   state=np.zeros(4))


def step(p, x, tm, wh, ts):
    """``d_hat_k = a d_hat_{k-1} + (1-a) [(Tm_{k-1} + Tm_{k-2})/2 - J_n (w_k - w_{k-1})/Ts]``."""
    a = math.exp(-p[P_BANDWIDTH] * ts)
    raw = 0.5 * (x[X_TM1] + x[X_TM2]) - p[P_INERTIA] * (wh - x[X_W_PREV]) / ts
    d = a * x[X_D] + (1.0 - a) * raw
    x[X_D] = d
    x[X_W_PREV] = wh
    x[X_TM2] = x[X_TM1]
    x[X_TM1] = tm
    return d


def c_code(comp: DisturbanceObserver) -> CCode:
    return CCode(
        params=(("inertia", comp.inertia, "nominal inertia J_n [kg*m^2]"),
                ("bandwidth", comp.bandwidth, "Q-filter bandwidth g [rad/s]")),
        state=(("a", "exp(-g Ts) [-]"), ("d", "disturbance estimate d_hat [N*m]"),
               ("w_prev", "previous omega_hat [rad/s]"), ("tm1", "Tm_{k-1} [N*m]"),
               ("tm2", "Tm_{k-2} [N*m]")),
        init="    st->a = exp(-P_bandwidth * st->ts);\n"
             "    st->d = 0.0;\n    st->w_prev = 0.0;\n    st->tm1 = 0.0;\n    st->tm2 = 0.0;\n",
        step="""    double raw;
    (void)y; (void)r; (void)tc;
    raw = 0.5 * (st->tm1 + st->tm2) - P_inertia * (omega_hat - st->w_prev) / st->ts;
    st->d = st->a * st->d + (1.0 - st->a) * raw;
    st->w_prev = omega_hat;
    st->tm2 = st->tm1;
    st->tm1 = tm;
    return st->d;
""")


def _make(model, design, sample_time, *, bandwidth: float | None = None, scale: float = 1.0):
    g = default_bandwidth(sample_time) if bandwidth is None else bandwidth
    return DisturbanceObserver.from_model(model, bandwidth=g, scale=scale)


ENTRY = Entry(name="dob", kind=KIND, cls=DisturbanceObserver, make=_make, step=step,
              c_code=c_code,
              description="disturbance observer d_hat = Q(s)[Tm - J_n s omega], first-order Q")
