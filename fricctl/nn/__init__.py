"""The paper's 2-H-1 friction network: evaluation, trainers, accuracy, JSON, C export.

Gervini, Gomes & da Rosa (2003) estimate the joint friction torque with a
2-4-1 feed-forward network: inputs the motor torque ``Tm`` and the velocity
``omega``, four ``tanh`` hidden units, a linear output, trained by
back-propagation with momentum on the patterns ``Tat = Tm - I*alpha_hat``.  The
estimate is then added to the control torque, ``Tm(k+1) = Tc(k) + s*Tat_hat(k)``
(the compensator lives in :mod:`fricctl.compensators`, not here).

Everything is on the load side of the gear, in SI units: ``Tm`` and the friction
torque in [N*m], ``omega`` in [rad/s].  Friction has the sign of the velocity
and enters the joint as ``I*qdd = Tm - Tat``.

Modules
-------
:mod:`~fricctl.nn.net`
    :class:`FrictionNet`, the immutable trained network (formula in its docstring).
:mod:`~fricctl.nn.layout`
    The parameter vectors (``theta`` for training, the compiled-loop vector) and
    the numba forward passes that read them (numpy and numba only).
:mod:`~fricctl.nn.train`
    The trainers behind one seam, registered by name: :func:`train_backprop`
    (the paper's) and :func:`train_casadi` (Levenberg-Marquardt, CasADi Jacobian).
:mod:`~fricctl.nn.metrics`
    :func:`fit_percent`, :func:`r_squared`, :func:`fit_report`, with the definitions.
:mod:`~fricctl.nn.io`
    :func:`save_net`, :func:`load_net`: JSON with a format version; no pickle.
:mod:`~fricctl.nn.c_export`
    :func:`c_source`, a self-contained C translation unit evaluating the network.
:mod:`~fricctl.nn.patterns`
    :func:`smooth_friction_patterns`, noise-free patterns of a known smooth law.
"""

from __future__ import annotations

from .c_export import c_source
from .io import FORMAT_NAME, FORMAT_VERSION, load_net, save_net
from .metrics import FitReport, fit_percent, fit_report, r_squared
from .net import FrictionNet
from .patterns import smooth_friction_patterns
from .train import (TRAINERS, Trainer, TrainingHistory, TrainingResult, train_backprop,
                    train_casadi)

__all__ = [
    "FORMAT_NAME",
    "FORMAT_VERSION",
    "FrictionNet",
    "TrainingHistory",
    "TrainingResult",
    "FitReport",
    "Trainer",
    "TRAINERS",
    "train_backprop",
    "train_casadi",
    "fit_percent",
    "r_squared",
    "fit_report",
    "save_net",
    "load_net",
    "c_source",
    "smooth_friction_patterns",
]
