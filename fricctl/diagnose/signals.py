"""A model's torque along the signals of a record (:mod:`fricctl.identify.signals`).

:func:`predict` gives, for a :class:`~fricctl.plant.JointModel`, the low-passed
torque the joint receives and the model's low-passed torque along the measured
motion: their difference is the equation-error (torque) residual.  The record's
signals themselves (:class:`Signals`, :func:`estimate_signals`) are identification's,
re-exported here: a diagnosis reads a record exactly as ``fricctl identify`` does.
"""

from __future__ import annotations

import math
import weakref
from dataclasses import dataclass

import numpy as np
from scipy import signal

from .._jit import jit
from ..friction import FrictionModel
from ..identify.signals import (BAND_MARGIN, MAX_CUTOFF, SAMPLE_TIME_RANGE, Signals, centred,
                                delay_in_samples, delayed, estimate_signals, motion_band)
from ..plant import JointModel

__all__ = ["Signals", "TorquePrediction", "estimate_signals", "centred", "delayed",
           "delay_in_samples", "motion_band", "load_acceleration", "backlash_load",
           "BacklashLoad", "restitution", "contact_damping_ratio", "friction_columns", "predict",
           "BAND_MARGIN", "MAX_CUTOFF", "SAMPLE_TIME_RANGE"]


def load_acceleration(sig: Signals, wl: float, zeta: float) -> np.ndarray:
    """Acceleration of a load on a spring (natural frequency wl [rad/s], damping zeta) driven by qf."""
    # the bilinear (Tustin) transform of (2*zeta*wl*s + wl^2)/(s^2 + 2*zeta*wl*s + wl^2),
    # written out (scipy.signal.bilinear gives the same, ten times slower)
    k = 2.0 / sig.ts
    b1, b0, a1, a0 = 2 * zeta * wl, wl * wl, 2 * zeta * wl, wl * wl
    az = np.array([k * k + a1 * k + a0, 2 * (a0 - k * k), k * k - a1 * k + a0])
    bz = np.array([b1 * k + b0, 2 * b0, b0 - b1 * k]) / az[0]
    az = az / az[0]
    # start at equilibrium with the first position: filter the deviation
    ql = signal.lfilter(bz, az, sig.qf - sig.qf[0]) + sig.qf[0]
    vl = np.gradient(ql, sig.ts)
    return np.gradient(vl, sig.ts)


@jit
def _backlash_load(qm, wm, am, ts, half, e, vmin):
    """The load behind a dead band of half-width ``half`` driven by the motor motion
    (qm, wm, am): rigid contact with restitution ``e`` (a bounce slower than ``vmin`` is
    plastic), no force on the load but the contact's."""
    n = qm.size
    ql = np.empty(n)
    wl = np.empty(n)
    side = np.zeros(n)
    q, w, c = qm[0], wm[0], 0.0
    for k in range(n):
        if k > 0:
            if c != 0.0 and c * am[k] < 0.0:
                c = 0.0  # the contact would have to pull: the load leaves the face
            if c == 0.0:
                q = q + w * ts  # the load coasts across the gap
                d = qm[k] - q
                face = 1.0 if d >= half else (-1.0 if d <= -half else 0.0)
                if face != 0.0:  # the motor's face meets the load: an impact
                    q = qm[k] - face * half
                    u = w - wm[k]  # the load's speed relative to the motor before it
                    if e * abs(u) > vmin:
                        w = wm[k] - e * u  # it bounces off the face, back into the gap
                        side[k] = face
                    else:
                        c = face  # plastic: picked up
            if c != 0.0:  # in contact: the load follows the motor
                q = qm[k] - c * half
                w = wm[k]
        ql[k] = q
        wl[k] = w
        if c != 0.0:
            side[k] = c
    return ql, wl, side


@dataclass(frozen=True, kw_only=True, eq=False)
class BacklashLoad:
    """A load behind a dead band, driven by the measured motion (:func:`backlash_load`)."""

    acceleration: np.ndarray
    """Load acceleration along the record (impacts as one-sample velocity steps) [rad/s^2]."""
    side: np.ndarray
    """+1 / -1: in contact on (or bouncing off) the forward / backward face; 0: crossing the
    gap [-]."""

    @property
    def crossings(self) -> int:
        """How many times the load left one face and met the other."""
        faces = self.side[self.side != 0]
        return int(np.count_nonzero(np.diff(faces) != 0)) if faces.size > 1 else 0


def restitution(zeta: float) -> float:
    """Coefficient of restitution of a linear spring-damper contact of damping ratio
    ``zeta`` (the relative speed after an impact over the one before; 0 from critical
    damping on) [-]."""
    if zeta >= 1.0:
        return 0.0
    return math.exp(-math.pi * zeta / math.sqrt(1.0 - zeta * zeta))


def contact_damping_ratio(e: float) -> float:
    """The damping ratio of a linear spring-damper contact of restitution ``e`` (1 for
    ``e == 0``: the critically damped, plastic contact) [-]."""
    if e <= 0.0:
        return 1.0
    le = math.log(e)
    return -le / math.sqrt(math.pi ** 2 + le * le)


#: The motor's speed and acceleration along a record (:func:`_motor_motion`), by its signals
#: (weakly: gone with the record).
_MOTOR = weakref.WeakKeyDictionary()


def _motor_motion(sig: Signals) -> tuple:
    """Speed and acceleration of the motor side, the gradients of the filtered position
    ([rad/s], [rad/s^2]): the same for every gap, computed once per record (the backlash
    scan asks for some 200 gaps)."""
    hit = _MOTOR.get(sig)
    if hit is None:
        wm = np.gradient(sig.qf, sig.ts)
        hit = _MOTOR[sig] = (wm, np.gradient(wm, sig.ts))
    return hit


def backlash_load(sig: Signals, gap: float, restitution: float = 0.0) -> BacklashLoad:
    """The load behind a dead band of total width ``gap`` [rad] driven by the record's motion.

    The contact is rigid (a contact resonance above the band the record resolves): in
    contact the load follows the motor; the contact holds while the motor's acceleration
    points the way the face pushes (the load has no force of its own: friction is on the
    motor side), else the load leaves the face and coasts at its speed until a face of the
    motor (either one) meets it again.  There it bounces back with ``restitution`` times the
    relative speed [-] (0: plastic, it takes the motor's speed), until the bounce is slower
    than one encoder count per sample.  The record starts with the load in the middle of
    the gap.
    """
    wm, am = _motor_motion(sig)
    vmin = (sig.resolution if sig.resolution > 0 else 1e-9 * float(np.ptp(sig.qf))) / sig.ts
    ql, wl, side = _backlash_load(np.ascontiguousarray(sig.qf, dtype=float), wm, am,
                                  float(sig.ts), 0.5 * float(gap), float(restitution), vmin)
    return BacklashLoad(acceleration=np.gradient(wl, sig.ts), side=side)


def friction_columns(sig: Signals, fr: FrictionModel, tm_joint) -> np.ndarray:
    """Friction torque of ``fr`` along the measured motion (before low-pass) [N*m].

    At the two samples of a reversal the torques for both directions are blended
    with the effective sign ``sig.seff``.
    """
    f = _friction_raw(sig, fr, tm_joint, sig.w)
    rho = sig.seff * np.sign(sig.w)
    mix = rho < 1.0
    if np.any(mix):
        f_alt = _friction_raw(sig, fr, tm_joint, -sig.w)
        f = np.where(mix, 0.5 * (1 + rho) * f + 0.5 * (1 - rho) * f_alt, f)
    return f


def _friction_raw(sig: Signals, fr: FrictionModel, tm_joint, w) -> np.ndarray:
    # the model's own evaluation along the measured motion (a presliding law integrates its
    # state along the position record: its law's along_motion)
    return fr.along_motion(sig.qf, w, tm_joint, sig.t)


@dataclass(frozen=True, kw_only=True, eq=False)
class TorquePrediction:
    """The low-passed torque the joint receives and a model's low-passed torque [N*m]."""

    target: np.ndarray
    """LP of the (delayed) sample-centred recorded torque."""
    prediction: np.ndarray
    """LP of the model's torque along the measured motion."""

    @property
    def residual(self) -> np.ndarray:
        """``target - prediction`` [N*m]."""
        return self.target - self.prediction


def predict(model: JointModel, sig: Signals) -> TorquePrediction:
    """LP of the torque the joint receives and the model's LP torque along the measured motion."""
    u = sig.centred(delay_in_samples(model, sig.ts))
    target = sig.filt(u)
    pred = (model.inertia * sig.a + sig.filt(friction_columns(sig, model.friction, u))
            + model.offset * sig.filt(np.ones(u.size)))
    if model.backlash > 0:  # the contact taken as rigid (above the band): backlash_load
        jl = model.load_inertia
        mu = jl * (model.inertia - jl) / model.inertia
        e = restitution(model.damping / (2 * math.sqrt(model.stiffness * mu)))
        pred = pred + jl * (sig.filt(backlash_load(sig, model.backlash, e).acceleration) - sig.a)
    elif model.elastic:
        jl = model.load_inertia
        wl = math.sqrt(model.stiffness / jl)
        zeta = model.damping / (2 * math.sqrt(model.stiffness * jl))
        pred = pred + jl * (sig.filt(load_acceleration(sig, wl, zeta)) - sig.a)
    return TorquePrediction(target=target, prediction=pred)
