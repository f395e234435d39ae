r"""LuGre observer-based friction compensation (Canudas de Wit, Olsson, Åström & Lischinsky,
"A new model for control of systems with friction", IEEE TAC 40(3), 1995, Sec. V).

.. math::
    \dot{\hat z} = w - \sigma_0 \frac{|w|}{g(w)} \hat z - k\,e, \qquad
    \hat T_{at} = \sigma_0 \hat z + \sigma_1 \dot{\hat z} + \sigma_2 w,

with ``g(w) = Fc + (Fs - Fc) exp(-(|w|/ws)^delta)`` the identified static curve's level in the
direction of ``w``, ``w = omega_hat_k`` and ``e = y_k - r_k`` (the paper's ``x - x_d``; ``k`` its
observer gain, 0: the open-loop copy of the model).

Integration: over one sample ``w`` and ``e`` are held, so the observer is linear in ``z`` with
constant coefficients, ``z' = u - lam z`` (``u = w - k e``, ``lam = sigma0 |w|/g``), and is
integrated *exactly*: ``z_k = z_{k-1} exp(-lam Ts) + (u/lam)(1 - exp(-lam Ts))`` (``expm1``
for small ``lam Ts``; ``z + Ts u`` at ``lam = 0``).  The stiff term (``lam Ts`` reaches
``sigma0 |w| Ts / Fc``, thousands at speed on a stiff bristle) never makes it unstable: the
step is the ODE's own solution.  Because ``omega_hat_k`` is the mean velocity over the
previous interval, the step advances ``z`` over that interval and then outputs the estimate
at sample k (``z'`` evaluated at the new ``z``).

Provenance of the parameters: ``sigma0``, ``sigma1`` the identified LuGre law's
(``lugre_sigma0``, ``lugre_sigma1`` of the model; or given when the model has no LuGre law;
without a law and without ``sigma1``, the damping of :func:`default_sigma1`, the one rule
``fricctl simulate`` and ``fricctl compare`` share), ``sigma2`` the viscous coefficient,
``Fc``, ``Fs - Fc``, ``ws``, ``delta`` the static curve
(:func:`~fricctl.compensators.base.static_curve`), all with the friction scale applied;
``k`` is the design's (default 0).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _validate as v
from .base import (CCode, Compensator, CompiledCompensator, Entry, friction_of, joint_model,
                   static_curve)

__all__ = ["LuGreObserver", "ENTRY", "default_sigma1"]

#: Kind id in the compiled loop.
KIND = 4
(P_SIGMA0, P_SIGMA1, P_B_POS, P_B_NEG, P_FC_POS, P_FC_NEG, P_DS_POS, P_DS_NEG, P_WS,
 P_EXPONENT, P_K) = range(11)
X_Z = 0


def default_sigma1(sigma0: float, inertia: float) -> float:
    """The bristle damping assumed where a model has no LuGre law: ``sqrt(sigma0 * I)``
    [N*m*s/rad] ([N*s/m] on a linear axis).

    ASSUMPTION (not identified): the damping of Canudas de Wit et al.'s (1995) example,
    ``sigma0 = 1e5`` N/m, ``sigma1 = sqrt(1e5)`` N*s/m on a 1 kg mass, carried over as its ratio:
    the presliding mode of the inertia ``I`` on the bristle, ``I s^2 + sigma1 s + sigma0``, damped
    at ``zeta = sigma1 / (2 sqrt(sigma0 I)) = 0.5`` (critical damping would be
    ``2 sqrt(sigma0 I)``; the published ratio is kept, and with it the comparison table that
    rests on it).

    Parameters
    ----------
    sigma0 : float
        Bristle stiffness [N*m/rad] (> 0).
    inertia : float
        The joint's total inertia [kg*m^2] (> 0; mass [kg] on a linear axis).

    Examples
    --------
    >>> round(default_sigma1(1e5, 1.0), 3)   # the paper's example: sqrt(1e5) N*s/m on 1 kg
    316.228
    """
    sigma0 = v.real("sigma0", sigma0, positive=True, unit="N*m/rad")
    inertia = v.real("inertia", inertia, positive=True, unit="kg*m^2")
    return math.sqrt(sigma0 * inertia)


@dataclass(frozen=True, kw_only=True)
class LuGreObserver(Compensator):
    """LuGre observer-based compensation (Canudas de Wit et al. 1995).

    Parameters
    ----------
    sigma0 : float
        Bristle stiffness [N*m/rad] (> 0).
    sigma1 : float
        Bristle damping [N*m*s/rad].
    viscous_pos, viscous_neg : float
        sigma2 per direction [N*m*s/rad].
    coulomb_pos, coulomb_neg : float
        Fc per direction [N*m] (> 0: g never reaches 0).
    stribeck_pos, stribeck_neg : float
        Fs - Fc per direction [N*m].
    stribeck_velocity : float
        ws [rad/s].
    stribeck_exponent : float
        delta [-].
    gain : float
        Observer gain k on the position error ``y - r`` [1/s] (0: open-loop observer).
    scale : float
        Compensation scale s [-].

    Notes
    -----
    The observer uses the loop's backward-difference velocity: below one encoder count per
    sample it reads 0 and ``z`` only moves through ``-k e``; presliding motion smaller than
    a count is invisible to it.  Load-dependent, drag and position terms are left out.
    """

    sigma0: float
    """Bristle stiffness sigma0 [N*m/rad]."""
    sigma1: float = 0.0
    """Bristle damping sigma1 [N*m*s/rad]."""
    viscous_pos: float = 0.0
    """sigma2 for positive velocity [N*m*s/rad]."""
    viscous_neg: float = 0.0
    """sigma2 for negative velocity [N*m*s/rad]."""
    coulomb_pos: float
    """Fc for positive velocity [N*m]."""
    coulomb_neg: float
    """Magnitude of Fc for negative velocity [N*m]."""
    stribeck_pos: float = 0.0
    """Fs - Fc for positive velocity [N*m]."""
    stribeck_neg: float = 0.0
    """Fs - Fc for negative velocity [N*m]."""
    stribeck_velocity: float = 1.0
    """ws [rad/s]."""
    stribeck_exponent: float = 2.0
    """delta [-]."""
    gain: float = 0.0
    """Observer gain k [1/s]."""
    scale: float = 1.0
    """Compensation scale s [-]."""
    name: str = "LuGre observer"
    """Label in results and plots."""
    stateful = True  # its state: z_hat (a class attribute, not a field)

    @property
    def needs_reference(self) -> bool:
        """True when the observer gain ``k`` feeds the position error ``e = y - r`` back."""
        return self.gain != 0.0

    def __post_init__(self):
        v.real("sigma0", self.sigma0, positive=True, unit="N*m/rad")
        v.real("coulomb_pos", self.coulomb_pos, positive=True, unit="N*m")
        v.real("coulomb_neg", self.coulomb_neg, positive=True, unit="N*m")
        for name in ("sigma1", "viscous_pos", "viscous_neg", "stribeck_pos", "stribeck_neg",
                     "gain", "scale"):
            v.real(name, getattr(self, name), nonneg=True)
        v.real("stribeck_velocity", self.stribeck_velocity, positive=True, unit="rad/s")
        v.real("stribeck_exponent", self.stribeck_exponent, positive=True)
        v.text("name", self.name)

    @classmethod
    def from_model(cls, model, *, sigma0: float | None = None, sigma1: float | None = None,
                   gain: float = 0.0, scale: float = 1.0) -> "LuGreObserver":
        """The observer of an identified model; ``sigma0``/``sigma1`` default to its LuGre law's.

        A model without a LuGre law needs ``sigma0``; its ``sigma1`` defaults to
        :func:`default_sigma1` of that stiffness and the model's inertia (a friction model or law
        alone, which has no inertia, then needs ``sigma1`` too).

        Examples
        --------
        >>> from fricctl.params import paper_actuator
        >>> obs = LuGreObserver.from_model(paper_actuator(), sigma0=2000.0, sigma1=1.0)
        >>> round(obs.coulomb_pos + obs.stribeck_pos, 4)   # g(0) = Fs
        0.18
        """
        fr = friction_of(model)
        has = fr.lugre_sigma0 > 0.0
        if sigma0 is None and not has:
            raise ValueError("sigma0: the model has no LuGre law (lugre_sigma0 = 0); give the "
                             "bristle stiffness sigma0 [N*m/rad] (and sigma1)")
        s0 = fr.lugre_sigma0 if sigma0 is None else sigma0
        if sigma1 is not None:
            s1 = sigma1
        elif has:
            s1 = fr.lugre_sigma1
        else:
            from ..friction import FrictionLaw, FrictionModel

            if isinstance(model, (FrictionModel, FrictionLaw)):
                raise ValueError("sigma1: the model has no LuGre law and a friction model carries no "
                                 "inertia for the default sqrt(sigma0 * I); give sigma1 [N*m*s/rad] "
                                 "or the joint model")
            s1 = default_sigma1(s0, joint_model(model).inertia)
        fcp, dsp, bp, ws, ex = static_curve(fr, 1)
        fcn, dsn, bn, _, _ = static_curve(fr, -1)
        return cls(sigma0=s0, sigma1=s1, viscous_pos=bp, viscous_neg=bn, coulomb_pos=fcp,
                   coulomb_neg=fcn, stribeck_pos=dsp, stribeck_neg=dsn, stribeck_velocity=ws,
                   stribeck_exponent=ex, gain=gain, scale=scale)

    def compiled(self):
        p = np.array([self.sigma0, self.sigma1, self.viscous_pos, self.viscous_neg,
                      self.coulomb_pos, self.coulomb_neg, self.stribeck_pos, self.stribeck_neg,
                      self.stribeck_velocity, self.stribeck_exponent, self.gain])
        return CompiledCompensator(kind=KIND, params=p, state=np.zeros(1))


def step(p, x, wh, y, r, ts):
    """Advance z_hat exactly over the previous interval (w = omega_hat_k held), then F_hat_k."""
    w = wh
    if w >= 0.0:
        fc, ds, b = p[P_FC_POS], p[P_DS_POS], p[P_B_POS]
    else:
        fc, ds, b = p[P_FC_NEG], p[P_DS_NEG], p[P_B_NEG]
    u = abs(w) / p[P_WS]
    dip = math.exp(-u * u) if p[P_EXPONENT] == 2.0 else math.exp(-(u ** p[P_EXPONENT]))
    lam = p[P_SIGMA0] * abs(w) / (fc + ds * dip)
    drive = w - p[P_K] * (y - r)
    z = x[X_Z]
    if lam > 0.0:
        z = z * math.exp(-lam * ts) - (drive / lam) * math.expm1(-lam * ts)
    else:
        z = z + ts * drive
    x[X_Z] = z
    zd = drive - lam * z
    return p[P_SIGMA0] * z + p[P_SIGMA1] * zd + b * w


def c_code(comp: LuGreObserver) -> CCode:
    p = comp.compiled().params
    names = ("sigma0", "sigma1", "b_pos", "b_neg", "fc_pos", "fc_neg", "ds_pos", "ds_neg", "ws",
             "exponent", "k")
    docs = ("bristle stiffness sigma0 [N*m/rad]", "bristle damping sigma1 [N*m*s/rad]",
            "sigma2, w >= 0 [N*m*s/rad]", "sigma2, w < 0 [N*m*s/rad]", "Fc, w >= 0 [N*m]",
            "Fc, w < 0 [N*m]", "Fs - Fc, w >= 0 [N*m]", "Fs - Fc, w < 0 [N*m]",
            "Stribeck velocity ws [rad/s]", "Stribeck exponent [-]", "observer gain k [1/s]")
    return CCode(
        params=tuple(zip(names, p, docs)),
        state=(("z", "bristle state estimate z_hat [rad]"),),
        init="    st->z = 0.0;\n",
        step="""    double w = omega_hat, fc, ds, b, u, dip, lam, drive, z = st->z;
    (void)tm; (void)tc;
    if (w >= 0.0) { fc = P_fc_pos; ds = P_ds_pos; b = P_b_pos; }
    else { fc = P_fc_neg; ds = P_ds_neg; b = P_b_neg; }
    u = fabs(w) / P_ws;
    dip = P_exponent == 2.0 ? exp(-u * u) : exp(-pow(u, P_exponent));
    lam = P_sigma0 * fabs(w) / (fc + ds * dip);
    drive = w - P_k * (y - r);
    if (lam > 0.0) z = z * exp(-lam * st->ts) - (drive / lam) * expm1(-lam * st->ts);
    else z = z + st->ts * drive;
    st->z = z;
    return P_sigma0 * z + P_sigma1 * (drive - lam * z) + b * w;
""")


def _make(model, design, sample_time, *, sigma0: float | None = None,
          sigma1: float | None = None, gain: float = 0.0, scale: float = 1.0):
    return LuGreObserver.from_model(model, sigma0=sigma0, sigma1=sigma1, gain=gain, scale=scale)


ENTRY = Entry(name="lugre_observer", kind=KIND, cls=LuGreObserver, make=_make, step=step,
              c_code=c_code,
              description="LuGre observer z_hat' = w - sigma0 |w|/g(w) z_hat - k e, "
                          "F_hat = sigma0 z_hat + sigma1 z_hat' + sigma2 w (Canudas de Wit 1995)")
