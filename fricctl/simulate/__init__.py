"""The sampled-data loop at Ts (500 Hz, zero-order hold) -> :class:`SimResult`.

Timing (the one place it is stated; the gain design's sampled-data model
follows it): at each sample instant ``t_k = k*Ts``

1. the encoder reads ``y_k = res*floor(q(t_k)/res)`` (``res`` = one count on the
   load side; ``quantize=False`` gives ``y_k = q(t_k)``);
2. the velocity estimate is the backward difference
   ``omega_hat_k = (y_k - y_{k-1})/Ts`` (``omega_hat_0 = 0``), as the paper's driver;
3. the controller gives ``Tc_k`` from ``y_k`` and ``omega_hat_k``;
4. the compensator gives ``T^at_k = T^at(Tm_k, omega_hat_k)`` (a compensator with a
   state -- observer, integral action -- from its state and ``Tm_k, omega_hat_k, y_k,
   r_k, Tc_k``, updating its state: :mod:`fricctl.compensators.base`) and the loop commands
   ``Tm_{k+1} = clip(Tc_k + s*T^at_k, -Tmax, Tmax)`` (paper Eq. 3);
5. ``Tm_{k+1}`` is held (ZOH) over ``[t_{k+1}, t_{k+2})``: one sample of
   computation delay; ``Tm_0 = 0``.

``torque_motor[k]`` is ``Tm_k``, the torque recorded as applied over
``[t_k, t_{k+1})``.  With ``delay=d`` the joint receives ``Tm_{k-d}`` instead
(a drive that acts later than the record says); ``noise_std`` adds white torque
noise to what the joint receives.  The joint itself saturates at ``+-Tmax``.

The loop (:mod:`fricctl.simulate.loop`, written once) runs compiled (numba) for the
library's controllers and every registered compensator (:mod:`fricctl.compensators`; the
runs of a batch may use different ones), including a :class:`fricctl.nn.FrictionNet`;
an arbitrary estimator callable is evaluated in Python between the same compiled
steps (same results, slower).  :func:`simulate_batch` runs N parameter variants in
one call; :func:`simulate_model` runs the loop on a :class:`~fricctl.plant.JointModel`
(your own actuator, its units, offset and delay); :func:`simulate_schedule` runs per-sample gains and references (the
hidden-effect bench); :func:`replay` drives the plant alone with a recorded torque.
"""

from __future__ import annotations

from .api import (DEFAULT_SUBSTEPS, MAX_SAMPLES, Schedule, replay, sampling_warnings, simulate,
                  simulate_batch, simulate_model, simulate_schedule)
from .results import BatchResult, ReplayResult, SimInfo, SimResult

__all__ = ["SimResult", "BatchResult", "SimInfo", "ReplayResult", "Schedule", "simulate",
           "simulate_batch", "simulate_model", "simulate_schedule", "replay", "DEFAULT_SUBSTEPS",
           "MAX_SAMPLES", "sampling_warnings"]
