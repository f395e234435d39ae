"""Noise-free training patterns of a known smooth friction law (tests, benchmarks, teaching).

Where the virtual bench (:mod:`fricctl.bench.experiments`) is not needed, these
patterns give the network a target it can represent, so that its only error is
its approximation error.
"""

from __future__ import annotations

import numpy as np

from .. import _validate as v
from ..datasets import FrictionPatterns

__all__ = ["smooth_friction_patterns"]


def smooth_friction_patterns(rng: np.random.Generator, *, n_sliding: int = 400,
                             n_stuck: int = 100, viscous: float = 0.0169,
                             coulomb: float = 0.144, static: float = 0.18,
                             smoothing_velocity: float = 0.05, omega_max: float = 2.0,
                             inertia: float = 2.865e-3,
                             alpha_max: float = 50.0) -> FrictionPatterns:
    """Noise-free patterns ``(tm, omega, friction)`` of a known smooth law.

    Sliding patterns: ``omega ~ U(-omega_max, omega_max)``, friction
    ``b*omega + Fc*tanh(omega/v)``, and the motor torque that produced the
    acceleration ``alpha ~ U(-alpha_max, alpha_max)``: ``Tm = friction + I*alpha``.
    Stuck patterns: ``omega = 0``, ``Tm ~ U(-Fs, Fs)`` and friction ``= Tm``
    (the paper's ``Tat = Tm - I*alpha`` with ``alpha = 0``).

    Parameters
    ----------
    rng : numpy.random.Generator
        Source of the samples.
    n_sliding, n_stuck : int
        Numbers of sliding and stuck patterns.
    viscous : float
        b [N*m*s/rad] (paper: 0.0169).
    coulomb : float
        Fc [N*m] (fricctl's assumed 80 % of the static level).
    static : float
        Fs, the range of the stuck torques, >= ``coulomb`` [N*m] (paper: 0.18).
    smoothing_velocity : float
        v of the tanh smoothing of the Coulomb step, > 0 [rad/s].
    omega_max : float
        Velocity range, > 0 [rad/s].
    inertia : float
        I [kg*m^2] (fricctl's derived actuator inertia).
    alpha_max : float
        Acceleration range [rad/s^2].

    Returns
    -------
    FrictionPatterns
        ``tm`` [N*m], ``omega`` [rad/s], ``friction`` [N*m]; the sliding patterns first,
        then the stuck ones (``at_rest``).

    Notes
    -----
    No Stribeck dip, no noise, no estimation error in ``alpha``: this is the
    clean case where the network's only error is its approximation error.

    Examples
    --------
    >>> p = smooth_friction_patterns(np.random.default_rng(0), n_sliding=3, n_stuck=2)
    >>> bool(np.all(p.friction[3:] == p.tm[3:])), p.omega[3:].tolist()
    (True, [0.0, 0.0])
    """
    v.rng("rng", rng)
    n_sliding = v.integer("n_sliding", n_sliding, low=0)
    n_stuck = v.integer("n_stuck", n_stuck, low=0)
    for name, value, unit in (("viscous", viscous, "N*m*s/rad"), ("coulomb", coulomb, "N*m"),
                              ("static", static, "N*m"), ("inertia", inertia, "kg*m^2"),
                              ("alpha_max", alpha_max, "rad/s^2")):
        v.real(name, value, nonneg=True, unit=unit)
    if static < coulomb:
        raise ValueError(f"static must be >= coulomb (the breakaway level is not below the "
                         f"sliding level), got static={static!r} N*m and coulomb={coulomb!r} N*m")
    if n_sliding + n_stuck < 1:
        raise ValueError("n_sliding + n_stuck must be at least 1 (no patterns asked for)")
    v.real("smoothing_velocity", smoothing_velocity, positive=True, unit="rad/s")
    v.real("omega_max", omega_max, positive=True, unit="rad/s")
    om = rng.uniform(-omega_max, omega_max, n_sliding)
    fr = viscous * om + coulomb * np.tanh(om / smoothing_velocity)
    tm = fr + inertia * rng.uniform(-alpha_max, alpha_max, n_sliding)
    tm_stuck = rng.uniform(-static, static, n_stuck)
    return FrictionPatterns(tm=np.concatenate([tm, tm_stuck]),
                            omega=np.concatenate([om, np.zeros(n_stuck)]),
                            friction=np.concatenate([fr, tm_stuck]),
                            at_rest=np.arange(n_sliding + n_stuck) >= n_sliding)
