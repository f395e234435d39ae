r"""P and PD gains from rise time and damping, on the linear viscous model.

The paper designs every controller "as if the system was linear (only viscous
friction)".  The plant is the rigid joint with viscous friction only, load side:

.. math::

    G(s) = \frac{q(s)}{T_m(s)} = \frac{1}{s\,(I s + b)},

with ``I = params.total_inertia`` (actuator + link) and ``b = params.viscous``.

Control laws
------------
* P: ``Tc = Kp*(r - q)``.  Closed loop ``Kp / (I s^2 + b s + Kp)``.  One gain, so
  only one of the two specifications can be imposed (``priority``).
* PD: ``Tc = Kp*(r - q) - Kd*omega_hat``, the derivative acts on the *measured
  velocity* (rate feedback), not on the error.  The closed loop
  ``Kp / (I s^2 + (b + Kd) s + Kp)`` is the standard second-order system with
  no zero, so the closed-form relations hold exactly:
  ``Kp = I*wn^2`` and ``Kd = 2*zeta*wn*I - b``.
* For teaching, :meth:`Design.error_pd_closed_loop` gives the loop of a PD
  acting on the error, ``(Kp + Kd s)(r - q)``: the same poles, plus a zero at
  ``-Kp/Kd`` that adds overshoot.

Rise time
---------
The rise-time definition is always explicit: ``"0-100"`` (Ogata's definition
for underdamped systems, first time the step reaches its final value; the
default when zeta < 1) or ``"10-90"`` (required when zeta >= 1, where the step
never reaches its final value).  For 0-100 the closed form is
``wn = (pi - acos(zeta)) / (tr*sqrt(1 - zeta^2))``; for 10-90 the normalised
rise time ``wn*tr`` is found with :func:`scipy.optimize.brentq` on the
closed-form step response.

Verification
------------
Every :class:`Design` carries the *achieved* step metrics, measured with
:func:`control.step_info` (with ``RiseTimeLimits`` set from the definition) on a
time grid of at least 2000 points per rise time, because ``step_info`` does not
interpolate between samples; and the same metrics of the *sampled-data loop*
of the core simulator (zero-order hold at ``Ts``, backward-difference velocity,
one sample of computation delay; see :func:`sampled_loop`).  A
:class:`DesignWarning` is issued when the sampled loop's rise time or damping
differs from the continuous design by more than 10 %, or when a P design misses
its non-priority specification by more than 10 %.

Modules
-------
* :mod:`~fricctl.design.second_order` -- rise-time definitions, the normalised
  rise time, dominant damping, :class:`StepMetrics` and :func:`step_metrics`;
* :mod:`~fricctl.design.result` -- :class:`Design` and :class:`DesignWarning`;
* :mod:`~fricctl.design.loops` -- the design plant (:func:`plant_tf`), the
  continuous and sampled-data loops (:class:`LinearLoop`, :func:`sampled_loop`)
  and their responses (:class:`SampledResponse`, :func:`linear_response`);
* :mod:`~fricctl.design.gains` -- :func:`design_p` and :func:`design_pd`;
* :mod:`~fricctl.design.paper` -- the paper's designs and :func:`design_table`;
* :mod:`~fricctl.design.describing` -- the limit cycle of an over-compensating Coulomb
  compensation on the sampled loop, by a describing function (:func:`coulomb_limit_cycle`).

Dependencies: :mod:`fricctl.params`, numpy, scipy, python-control (which imports
matplotlib on import: this package is the one non-plotting part that loads it).
"""

from __future__ import annotations

from .describing import LimitCycle, coulomb_limit_cycle
from .gains import WARN_TOLERANCE, design_p, design_pd
from .loops import LinearLoop, SampledResponse, linear_response, plant_tf, sampled_loop
from .paper import PAPER_DESIGN_SPECS, design_table, paper_designs
from .result import Design, DesignWarning
from .second_order import (
    RISE_TIME_DEFINITIONS,
    SETTLING_THRESHOLD,
    StepMetrics,
    normalized_rise_time,
    step_metrics,
)

__all__ = [
    "DesignWarning",
    "StepMetrics",
    "Design",
    "RISE_TIME_DEFINITIONS",
    "SETTLING_THRESHOLD",
    "WARN_TOLERANCE",
    "PAPER_DESIGN_SPECS",
    "design_p",
    "design_pd",
    "normalized_rise_time",
    "plant_tf",
    "LinearLoop",
    "SampledResponse",
    "sampled_loop",
    "step_metrics",
    "linear_response",
    "paper_designs",
    "design_table",
    "LimitCycle",
    "coulomb_limit_cycle",
]
