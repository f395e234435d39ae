r"""When the model is wrong: show the disagreement, name its cause, extend, measure the gain.

Given a measured record (:class:`~fricctl.datasets.Run`), :func:`diagnose` does what
an engineer does when simulation and experiment disagree:

1. **Baseline.**  Fit the rigid model ``I*q'' = Tm - b*w - Fc*sign(w)`` (stiction at
   Fc) by inverse-dynamics least squares, or take a supplied nominal
   :class:`JointModel` as given (JSON file format below).
2. **What the simulation gets wrong.**  Re-simulate the model driven by the
   measured torque over short windows (0.5 s), each started from the measured
   state, and compare position and velocity with the measurement
   (:func:`windowed_simulation`); and the equation-error (torque) residual
   ``LP(Tm) - LP(model torque)`` on the samples where the joint slides.
3. **Name the cause.**  Every candidate of :data:`CAUSES` adds its term to the
   baseline; each is scored by *blocked cross-validation* (the record cut in
   contiguous blocks; fit on all blocks but one, predict the one left out,
   hyper-parameters such as the ripple period or the delay chosen on the
   training blocks only), as the fraction of the baseline's held-out torque
   residual it removes.  Among the candidates that remove at least
   :data:`MIN_SCORE` of it, the best whose extended model does not simulate the
   held-out windows worse than the baseline is named (if none simulates better,
   the best torque score decides: stick-slip re-simulation is chaotic); with no
   candidate above :data:`MIN_SCORE`, ``none``.
4. **Extend and measure the gain.**  Refit the model with the named term
   (CasADi, :func:`fricctl.identify.fit_least_squares`), re-simulate, and report
   the held-out RMS before and after, for the torque residual and for the
   windowed simulation error.

Signals
-------
Velocity and acceleration come from the zero-phase Butterworth + central
difference estimator (:func:`fricctl.estimation.butterworth_central`, cut-off
``fc`` = a fifth of the Nyquist frequency).  The torque is first centred on the
sample grid (``(Tm[k-1] + Tm[k])/2``: a held torque acts half a sample before the
central-difference acceleration it causes) and low-passed with the same filter;
every nonlinear regressor column is low-passed too ("parallel filtering"), so
``LP(Tm) = I*LP(q'') + LP(F)`` holds sample by sample.  Samples at rest (encoder
constant) and a guard of ``1/fc`` around them carry no sliding-friction
information and are left out of the equation error.

Model file format (JSON, version 1)
-----------------------------------
::

    {"format": "fricctl.joint_model", "version": 1,
     "units": "rotary",                       # or "linear" (kg, N*s/m, N, m)
     "inertia": 0.00745,                      # total inertia I [kg*m^2]
     "friction": {"viscous_pos": 0.0169, "viscous_neg": 0.0169,
                  "coulomb_pos": 0.144, "coulomb_neg": 0.144},   # FrictionModel fields
     "offset": 0.0,                           # constant resistive torque [N*m]
     "delay": 0.0,                            # torque acts this much later [s]
     "load_inertia": 0.0, "stiffness": 0.0, "damping": 0.0,     # elastic joint (Eq. 1)
     "source": "free text"}

``friction`` holds any fields of :class:`fricctl.friction.FrictionModel`
(missing ones take its defaults; unknown ones are an error).  ``load_inertia > 0``
makes the joint elastic: the part ``load_inertia`` of ``inertia`` sits behind a
spring ``stiffness`` [N*m/rad] with damping ``damping`` [N*m*s/rad]; the encoder
and the friction are on the motor side.  Unknown keys, a missing key, another
format or version are errors.  No pickle.

Notes
-----
Left out: causes acting together (one is named per call; diagnose again with the
extended model as the nominal one to find a second, as chapter 08 does);
backlash; gravity and position-dependent inertia; sub-sample delays (the delay
is a whole number of samples); torque measurement noise models (least squares
assumes white residuals, so the reported standard errors are optimistic).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field, fields, replace
from pathlib import Path

import numpy as np
from numba import njit
from scipy import signal

from .datasets import Run
from .estimation import butterworth_central, zero_phase_filter
from .friction import FrictionModel
from .plant import JointModel
from .simulate import replay

__all__ = [
    "CAUSES", "NOMINAL_ONLY", "MIN_SCORE",
    "JointModel", "WindowedSimulation", "Diagnosis", "diagnose", "windowed_simulation",
    "prediction_errors", "torque_residual",
]

#: Candidate causes, in the order the issue lists them.
#: Largest load-dependence mu (friction + mu*|Tm|) a diagnosis will fit [-].
MAX_LOAD_COEFFICIENT = 0.5

CAUSES = ("none", "stribeck", "asymmetry", "load_dependent", "position_ripple", "time_delay",
          "thermal_drift", "compliance", "presliding", "inertia", "friction_scale")
#: Causes that only exist against a supplied nominal model.
NOMINAL_ONLY = ("inertia", "friction_scale")
#: Smallest held-out fraction of the baseline torque residual (sum of squares) a
#: candidate must remove to be named: 1 - 0.9**2, i.e. the held-out torque RMS must
#: drop by 10 %, the issue's definition of an effect that matters.  Terms that fit
#: only noise remove nothing held out; terms built on the measured acceleration
#: (compliance) can remove a few % of pure process noise, which this margin covers.
MIN_SCORE = 1.0 - 0.9 ** 2

_PHYSICAL = {  # a short description per cause, for reports
    "none": "the baseline explains the data within noise",
    "stribeck": "friction at low speed exceeds the Coulomb level and decays toward it with speed",
    "asymmetry": "friction differs between the two directions (or a constant torque offset)",
    "load_dependent": "friction grows with the transmitted torque |Tm|",
    "position_ripple": "a torque disturbance periodic in position",
    "time_delay": "the torque acts some samples later than recorded",
    "thermal_drift": "the friction level changes steadily over the record",
    "compliance": "the joint is elastic: a resonance the rigid model lacks",
    "presliding": "friction depends on motion history near reversals and stops",
    "inertia": "the inertia differs from the nominal model",
    "friction_scale": "the overall friction level differs from the nominal model",
}


# ============================================================================ model
def _finite(name, v, *, positive=False, nonneg=False):
    if isinstance(v, bool) or not isinstance(v, (int, float, np.floating, np.integer)) \
            or not math.isfinite(float(v)):
        raise ValueError(f"{name} must be a finite number, got {v!r}")
    v = float(v)
    if positive and not v > 0:
        raise ValueError(f"{name} must be > 0, got {v!r}")
    if nonneg and v < 0:
        raise ValueError(f"{name} must be >= 0, got {v!r}")
    return v




# ============================================================================ signals
@njit(cache=True)
def _dahl_state(q, xc, z0):
    """Normalised Dahl/LuGre bristle state along a position record (exact per step).

    ``dz/dx = (1 - sign(dx)*z)/xc``, so over a step dx:
    ``z <- s + (z - s)*exp(-|dx|/xc)`` with ``s = sign(dx)``.
    """
    z = np.empty(q.size)
    zz = z0
    z[0] = zz
    for k in range(1, q.size):
        dx = q[k] - q[k - 1]
        if dx != 0.0:
            s = 1.0 if dx > 0 else -1.0
            zz = s + (zz - s) * math.exp(-abs(dx) / xc)
        z[k] = zz
    return z


@dataclass(frozen=True, eq=False)
class _Signals:
    """Everything the equation error and the windows need, computed once."""

    t: np.ndarray
    ts: float
    tm: np.ndarray          # recorded torque
    q: np.ndarray           # encoder position
    qf: np.ndarray          # filtered position
    w: np.ndarray           # velocity estimate, its sign taken from the encoder (see _signals)
    seff: np.ndarray        # effective sign of the motion per sample (fractional at reversals)
    a: np.ndarray           # acceleration estimate
    lp: tuple               # (b, a) of the low-pass
    slide: np.ndarray       # 1.0 where the joint slides, 0.0 at rest (encoder constant)
    moving: np.ndarray      # samples used by the equation error
    rest: np.ndarray        # samples at rest (encoder constant around them)
    folds: np.ndarray       # fold index per sample
    n_folds: int
    resolution: float       # smallest position step seen [rad]
    cutoff: float           # [Hz]
    units: str

    def filt(self, x):
        """Low-pass of ``x`` with the samples at rest zeroed.

        At rest the friction is the reaction that holds the joint, equal to the torque
        it receives (q'' = 0): so the torque and every friction column are zeroed there
        before filtering, and ``LP(Tm*S) = I*LP(q'') + sum_j theta_j*LP(f_j*S)`` holds at
        every sample (S = 1 while sliding), with no filter smear across stops.
        """
        return zero_phase_filter(self.lp[0], self.lp[1], np.asarray(x, dtype=float) * self.slide)

    def torque_target(self, delay: int = 0, offset: float = 0.0) -> np.ndarray:
        """LP of the sample-centred torque the joint receives, delayed by ``delay`` samples."""
        u = _centred(self.tm, delay)
        return self.filt(u) - offset

    def centred(self, delay: int = 0) -> np.ndarray:
        return _centred(self.tm, delay)


def _centred(tm, delay):
    u = np.empty_like(tm)
    u[1:] = 0.5 * (tm[1:] + tm[:-1])
    u[0] = tm[0]
    if delay > 0:
        u = np.concatenate([np.full(delay, u[0]), u[:-delay]])
    return u


def _signals(run: Run, n_folds: int) -> _Signals:
    ts = run.sample_time
    cutoff = 0.1 / ts  # a fifth of the Nyquist frequency (100 Hz at 1 kHz, the EMPS choice)
    est = butterworth_central(run.t, run.position, cutoff=cutoff)
    b, a = signal.butter(4, cutoff * 2 * ts)
    q = np.asarray(run.position, dtype=float)
    steps = np.abs(np.diff(q))
    nz = steps[steps > 0]
    res = float(np.min(nz)) if nz.size else 0.0
    n = q.size
    # at rest: no encoder change across a sample on either side
    still = np.zeros(n, dtype=bool)
    same = steps == 0.0
    still[1:-1] = same[:-1] & same[1:]
    guard = max(int(math.ceil(1.0 / (cutoff * ts))), 1)
    edge = np.zeros(n, dtype=bool)
    border = max(5 * guard, 20)
    edge[:border] = edge[-border:] = True
    moving = (~still) & (~edge)
    if moving.sum() < 50 * n_folds:
        raise ValueError(f"too little motion: {int(moving.sum())} sliding samples for {n_folds} "
                         f"blocks (need at least {50 * n_folds}); record longer or move more")
    folds = np.minimum((np.arange(n) * n_folds) // n, n_folds - 1)
    active = sum(int(moving[folds == f].sum() >= 20) for f in range(n_folds))
    if active < min(3, n_folds):
        raise ValueError(f"the joint slides in only {active} of {n_folds} blocks of the record; "
                         f"cross-validation needs motion in at least 3")
    # Direction of motion from the encoder, not from the filtered velocity: at a
    # reversal the velocity is kinked (friction flips), and the zero-phase filter
    # moves its zero crossing by a sample or more -- a 2*Fc error there.
    w = np.asarray(est.velocity, dtype=float)
    dq = np.zeros(n)
    dq[1:-1] = q[2:] - q[:-2]
    direction = np.where(dq != 0, np.sign(dq), np.sign(w))
    w = direction * np.abs(w)
    # At a reversal between samples k-1 and k the friction flips inside a sample.
    # The reversal instant t* is where the decelerating motion before it stops: the
    # vertex of a parabola through the encoder readings k-9 .. k-1 (the motion after
    # the reversal is often much slower, and filters or short fits straddling the
    # kink place t* late).  Each sample near t* gets the triangle-weighted mean of
    # the sign over +-Ts, the weighting of the second difference used below.
    seff = direction.copy()
    flips = np.flatnonzero((direction[1:] != direction[:-1]) & (direction[1:] != 0)
                           & (direction[:-1] != 0)) + 1
    flips = flips[(flips >= 10) & (flips <= n - 3)]
    if flips.size:
        loc = np.arange(-9.0, 0.0)          # samples k-9 .. k-1, relative to k
        V = np.column_stack([loc ** 2, loc, np.ones(loc.size)])
        coef = np.linalg.lstsq(V, np.stack([q[k - 9:k] for k in flips]).T, rcond=None)[0]
        with np.errstate(divide="ignore", invalid="ignore"):
            tv = -coef[1] / (2 * coef[0])
        tstar = np.clip(np.nan_to_num(tv, nan=-0.5), -2.0, 1.0)   # relative to k
        for k, ts_ in zip(flips, tstar):
            sb = direction[k - 1]
            for j in range(k - 2, k + 2):
                x = ts_ - (j - k)           # t* relative to sample j
                if x <= -1:
                    wb = 0.0
                elif x <= 0:
                    wb = (x + 1) ** 2 / 2
                elif x < 1:
                    wb = 1 - (1 - x) ** 2 / 2
                else:
                    wb = 1.0
                if direction[j] != 0:
                    seff[j] = sb * (2 * wb - 1)
    # Acceleration by the narrow second difference of the filtered position: under a
    # held torque it equals the mean of the two torques around the sample exactly
    # ((Tm[k-1] + Tm[k])/2, the centred torque), where central differences applied
    # twice would spread it over four samples with weights 1,3,3,1 and leave a
    # mismatch at every torque or friction jump.
    qf = np.asarray(est.position, dtype=float)
    acc = np.empty(n)
    acc[1:-1] = (qf[2:] - 2 * qf[1:-1] + qf[:-2]) / ts ** 2
    acc[0], acc[-1] = acc[1], acc[-2]
    return _Signals(t=np.asarray(run.t, float), ts=ts, tm=np.asarray(run.torque, float), q=q,
                    qf=qf, w=w, seff=seff,
                    a=acc, lp=(b, a), slide=(~still).astype(float),
                    moving=moving, rest=still,
                    folds=folds, n_folds=n_folds, resolution=res, cutoff=cutoff, units=run.units)


# ============================================================================ torque prediction
def _load_accel(sig: _Signals, wl: float, zeta: float) -> np.ndarray:
    """Acceleration of a load on a spring (natural frequency wl, damping zeta) driven by qf."""
    num = [2 * zeta * wl, wl * wl]
    den = [1.0, 2 * zeta * wl, wl * wl]
    bz, az = signal.bilinear(num, den, fs=1.0 / sig.ts)
    # start at equilibrium with the first position: filter the deviation
    ql = signal.lfilter(bz, az, sig.qf - sig.qf[0]) + sig.qf[0]
    vl = np.gradient(ql, sig.ts)
    return np.gradient(vl, sig.ts)


def _friction_columns(sig: _Signals, fr: FrictionModel, tm_joint) -> np.ndarray:
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


def _friction_raw(sig: _Signals, fr: FrictionModel, tm_joint, w) -> np.ndarray:
    if fr.is_lugre:
        xc = min(fr.coulomb_pos, fr.coulomb_neg) / fr.lugre_sigma0
        z = _dahl_state(sig.qf, xc, 0.0)
        s = np.sign(w)
        level = np.where(z >= 0, fr.coulomb_pos, fr.coulomb_neg) + fr.load_coefficient * np.abs(tm_joint)
        visc = np.where(w > 0, fr.viscous_pos, fr.viscous_neg) * w
        damp = fr.lugre_sigma1 * w * (1 - s * z)
        return fr.scale_at(sig.t) * (level * z + visc) + fr.ripple(sig.qf) + damp
    return fr.torque(w, sig.qf, tm_joint, sig.t)


def _predict(model: JointModel, sig: _Signals) -> tuple[np.ndarray, np.ndarray]:
    """(target, prediction): LP of the torque the joint receives and the model's LP torque."""
    d = model.delay_samples(sig.ts)
    u = sig.centred(d)
    target = sig.filt(u)
    pred = (model.inertia * sig.a + sig.filt(_friction_columns(sig, model.friction, u))
            + model.offset * sig.filt(np.ones(u.size)))
    if model.elastic:
        jl = model.load_inertia
        wl = math.sqrt(model.stiffness / jl)
        zeta = model.damping / (2 * math.sqrt(model.stiffness * jl))
        pred = pred + jl * (sig.filt(_load_accel(sig, wl, zeta)) - sig.a)
    return target, pred


def torque_residual(model: JointModel, run: Run) -> tuple[np.ndarray, np.ndarray]:
    """Equation-error residual of ``model`` on ``run``: (residual, mask of sliding samples).

    ``residual = LP(Tm received) - LP(model torque along the measured motion)`` [N*m];
    meaningful where ``mask`` is true (the joint slides).
    """
    sig = _signals(run, 1)
    target, pred = _predict(model, sig)
    return target - pred, sig.moving


# ============================================================================ windowed simulation
@dataclass(frozen=True, eq=False)
class WindowedSimulation:
    """The model re-simulated over windows, each from the measured state.

    Attributes
    ----------
    starts : ndarray of int
        First sample of each window.
    length : int
        Samples per window.
    q : ndarray, shape (N,)
        Simulated position, NaN outside windows [rad].
    omega : ndarray, shape (N,)
        Simulated velocity, NaN outside windows [rad/s].
    position_error, velocity_error : ndarray, shape (n_windows,)
        RMS over each window of ``q_sim - q_meas`` [rad] and ``w_sim - w_est`` [rad/s].
    """

    starts: np.ndarray
    length: int
    q: np.ndarray
    omega: np.ndarray
    position_error: np.ndarray
    velocity_error: np.ndarray

    def rms(self, select=None) -> tuple[float, float]:
        """(position RMS [rad], velocity RMS [rad/s]) over the selected windows."""
        sel = np.ones(self.starts.size, bool) if select is None else np.asarray(select, bool)
        if not sel.any():
            return float("nan"), float("nan")
        return (float(np.sqrt(np.mean(self.position_error[sel] ** 2))),
                float(np.sqrt(np.mean(self.velocity_error[sel] ** 2))))


def _windows(sig: _Signals, window: float):
    n = sig.t.size
    length = max(int(round(window / sig.ts)), 10)
    border = max(int(math.ceil(2.0 / (sig.cutoff * sig.ts))), 10)
    starts = np.arange(border, n - length - border, length)
    if starts.size == 0:
        raise ValueError(f"record too short for {window} s windows")
    return starts, length


def _simulate_windows(model: JointModel, sig: _Signals, starts, length) -> WindowedSimulation:
    joint = model.joint()
    d = model.delay_samples(sig.ts)
    n = sig.t.size
    qs = np.full(n, np.nan)
    ws = np.full(n, np.nan)
    pe = np.empty(starts.size)
    ve = np.empty(starts.size)
    fr = model.friction
    nsub = None
    zlug = None
    if fr.is_lugre:
        xc = min(fr.coulomb_pos, fr.coulomb_neg) / fr.lugre_sigma0
        vmax = float(np.percentile(np.abs(sig.w), 99.5)) + 1e-9
        nsub = int(min(max(40, math.ceil(sig.ts * vmax / xc / 1.5)), 4000))
        zlug = _dahl_state(sig.qf, xc, 0.0) * xc
    for i, k0 in enumerate(starts):
        idx = np.arange(k0, k0 + length)
        src = np.clip(idx - d, 0, n - 1)
        torque = sig.tm[src] - model.offset
        w0 = 0.0 if sig.rest[k0] else float(sig.w[k0])
        state = None
        if zlug is not None:  # bristle deflection from the Dahl state along the measured motion
            state = [sig.qf[k0], w0, sig.qf[k0], w0, zlug[k0]]
        rep = replay(joint, torque, sig.ts, q0=float(sig.qf[k0]), omega0=w0, t0=float(sig.t[k0]),
                     substeps=nsub, state=state)
        q, w = rep.q, rep.omega
        qs[idx] = q
        ws[idx] = w
        pe[i] = np.sqrt(np.mean((q - sig.q[idx]) ** 2))
        ve[i] = np.sqrt(np.mean((w - sig.w[idx]) ** 2))
    return WindowedSimulation(starts=starts, length=length, q=qs, omega=ws, position_error=pe,
                              velocity_error=ve)


def windowed_simulation(model: JointModel, run: Run, *, window: float = 0.5) -> WindowedSimulation:
    """Re-simulate ``model`` driven by the measured torque over windows of ``window`` seconds.

    Each window starts from the measured state (filtered position, estimated
    velocity, or rest where the encoder stands still) and runs open loop on the
    recorded torque (delayed and offset as the model says).

    Parameters
    ----------
    model : JointModel
    run : Run
    window : float
        Window length [s].

    Returns
    -------
    WindowedSimulation
    """
    if not isinstance(model, JointModel):
        raise ValueError("model must be a JointModel")
    sig = _signals(run, 1)
    starts, length = _windows(sig, window)
    return _simulate_windows(model, sig, starts, length)


# ============================================================================ candidates
def _solve(G, g):
    """Normal equations of a (scaled) linear least-squares problem, solved by CasADi."""
    import casadi as ca

    p = G.shape[0]
    if p == 0:
        return np.zeros(0)
    ridge = 1e-12 * max(float(np.trace(G)) / max(p, 1), 1e-300)
    return np.asarray(ca.solve(ca.DM(G + ridge * np.eye(p)), ca.DM(g))).ravel()


@dataclass(frozen=True, eq=False)
class _Variant:
    """One setting of a candidate's hyper-parameter: extra columns and target."""

    h: object                 # hyper-parameter (period, delay, (wl, zeta), ...), or None
    extra: np.ndarray         # (N, k) extra regressor columns
    y: np.ndarray             # (N,) target (torque, or torque minus nominal prediction)
    signs: tuple              # per extra column: +1 (coefficient >= 0) or 0 (free)
    upper: tuple = ()         # per extra column: upper bound of the (unscaled) coefficient, or ()


class _Problem:
    """Block (fold) sums of the normal equations, shared by every candidate."""

    def __init__(self, sig: _Signals, base_cols: np.ndarray | None):
        self.sig = sig
        m = sig.moving
        self.rows = [np.flatnonzero(m & (sig.folds == f)) for f in range(sig.n_folds)]
        self.all_rows = np.flatnonzero(m)
        self.base = base_cols  # (N, 3) or None (nominal model)

    def design(self, v: _Variant):
        X = v.extra if self.base is None else np.column_stack([self.base, v.extra])
        return X

    def stats(self, X, y):
        rows = self.all_rows
        scale = np.sqrt(np.mean(X[rows] ** 2, axis=0))
        scale[scale == 0] = 1.0
        Xs = X / scale
        F = self.sig.n_folds
        p = X.shape[1]
        G = np.empty((F, p, p))
        g = np.empty((F, p))
        s = np.empty(F)
        for f, r in enumerate(self.rows):
            Xf = Xs[r]
            yf = y[r]
            G[f] = Xf.T @ Xf
            g[f] = Xf.T @ yf
            s[f] = yf @ yf
        return G, g, s, scale

    @staticmethod
    def sse(theta, G, g, s):
        return float(s - 2 * theta @ g + theta @ G @ theta)


def _solve_bounded(G, g, scale, upper, n_extra):
    """:func:`_solve`, then any extra coefficient above its upper bound is held at the bound
    and the others refitted (the bounded least-squares solution when one bound is active)."""
    th = _solve(G, g)
    if not upper:
        return th
    p = th.size
    fixed = {}
    for j, ub in enumerate(upper):
        i = p - n_extra + j
        if math.isfinite(ub) and th[i] / scale[i] > ub:
            fixed[i] = ub * scale[i]
    if not fixed:
        return th
    fi = np.array(sorted(fixed))
    fv = np.array([fixed[i] for i in fi])
    free = np.array([i for i in range(p) if i not in fixed], dtype=int)
    out = np.empty(p)
    out[fi] = fv
    out[free] = _solve(G[np.ix_(free, free)], g[free] - G[np.ix_(free, fi)] @ fv)
    return out


def _valid(theta, scale, signs, n_extra):
    if n_extra == 0:
        return True
    ex = theta[-n_extra:]
    return all(sg == 0 or c >= 0 for c, sg in zip(ex, signs))


def _cv(problem: _Problem, variants_for_fold, n_extra: int):
    """Blocked CV: per fold the variant with the least training SSE, its held-out SSE.

    Returns (test SSE per fold, (h, theta_unscaled) per fold or None).
    """
    F = problem.sig.n_folds
    cache = {}
    test = np.empty(F)
    fits = []
    for f in range(F):
        best = None
        for v in variants_for_fold(f):
            key = id(v)
            if key not in cache:
                cache[key] = problem.stats(problem.design(v), v.y)
            G, g, s, scale = cache[key]
            Gt, gt, st = G.sum(0) - G[f], g.sum(0) - g[f], s.sum() - s[f]
            th = _solve_bounded(Gt, gt, scale, v.upper, n_extra)
            if not _valid(th, scale, v.signs, n_extra):
                continue
            tr = _Problem.sse(th, Gt, gt, st)
            if best is None or tr < best[0]:
                best = (tr, _Problem.sse(th, G[f], g[f], s[f]), v.h, th / scale)
        if best is None:
            test[f] = np.nan
            fits.append(None)
        else:
            test[f] = best[1]
            fits.append((best[2], best[3]))
    return test, fits


def _full_fit(problem: _Problem, variants, n_extra: int):
    """All sliding samples: the variant with the least SSE and its scaled design."""
    best = None
    for v in variants:
        X = problem.design(v)
        G, g, s, scale = problem.stats(X, v.y)
        th = _solve_bounded(G.sum(0), g.sum(0), scale, v.upper, n_extra)
        if not _valid(th, scale, v.signs, n_extra):
            continue
        sse = _Problem.sse(th, G.sum(0), g.sum(0), s.sum())
        if best is None or sse < best[0]:
            best = (sse, v, th / scale)
    return best


class _Candidates:
    """Columns of every candidate, for fit mode (base refit) or a fixed nominal model."""

    def __init__(self, sig: _Signals, nominal: JointModel | None, base_full: np.ndarray | None):
        self.sig = sig
        self.nominal = nominal
        n = sig.t.size
        s = sig.seff
        self.s = s
        self.lp_w = sig.filt(sig.w)
        self.lp_s = sig.filt(s)
        self.fit_mode = nominal is None
        if self.fit_mode:
            self.base_cols = np.column_stack([sig.a, self.lp_w, self.lp_s])
            self.d0 = 0
            self.y0 = sig.torque_target(0)
            self.ref = np.zeros(n)
            self.base_theta = base_full  # (I, b, Fc) fitted on all data
        else:
            self.base_cols = None
            self.d0 = nominal.delay_samples(sig.ts)
            target, pred = _predict(nominal, sig)
            self.y0 = target - pred
            self.ref = pred
            u = sig.centred(self.d0)
            self.nom_friction_raw = _friction_columns(sig, nominal.friction, u)
            self.nom_friction = sig.filt(self.nom_friction_raw)
        self.u0 = sig.centred(self.d0)
        self._cache = {}

    def applicable(self):
        out = [c for c in CAUSES if c != "none"]
        if self.fit_mode:
            out = [c for c in out if c not in NOMINAL_ONLY]
        return out

    # ---- variants per cause ------------------------------------------------
    def variants(self, cause, fold=None):
        if cause == "position_ripple":
            return self._ripple_variants(fold)
        if cause not in self._cache:
            self._cache[cause] = list(getattr(self, "_v_" + cause)())
        return self._cache[cause]

    def _v(self, h, cols, signs, y=None, upper=()):
        cols = np.asarray(cols, dtype=float)
        if cols.ndim == 1:
            cols = cols[:, None]
        return _Variant(h=h, extra=cols, y=self.y0 if y is None else y, signs=tuple(signs),
                        upper=tuple(upper))

    def _v_stribeck(self):
        sig = self.sig
        v95 = float(np.percentile(np.abs(sig.w[sig.moving]), 95))
        for vs in v95 * np.logspace(-3, -0.7, 14):
            yield self._v(float(vs), sig.filt(self.s * np.exp(-(sig.w / vs) ** 2)), (1,))

    def _v_asymmetry(self):
        sig = self.sig
        yield self._v(None, np.column_stack([sig.filt(sig.w * (sig.w > 0)), sig.filt(np.ones(sig.t.size))]),
                      (0, 0))

    def _v_load_dependent(self):
        # |Tm|*sign(w) equals Tm itself whenever the drive pushes the way it moves, so without
        # braking phases in the training blocks the fit can slide to mu ~ 1 with I, b, Fc ~ 0
        # (the column "explains" the target). A drive whose mesh friction grows by more than
        # half the torque it transmits would hardly move a load; the bound excludes that.
        yield self._v(None, self.sig.filt(np.abs(self.u0) * self.s), (1,), upper=(MAX_LOAD_COEFFICIENT,))

    def _v_time_delay(self):
        sig = self.sig
        dmax = max(int(round(0.02 / sig.ts)), 6)
        for d in range(1, dmax + 1):
            y = sig.torque_target(self.d0 + d) - self.ref
            # the extra column is empty: the delay only moves the target
            yield _Variant(h=self.d0 + d, extra=np.zeros((sig.t.size, 0)), y=y, signs=())

    def _drift_ref(self):
        sig = self.sig
        if self.fit_mode:
            _, b, fc = self.base_theta
            tc = sig.t - 0.5 * (sig.t[0] + sig.t[-1])
            return sig.filt(tc * (b * sig.w + fc * self.s))
        return sig.filt((sig.t - sig.t[0]) * self.nom_friction_raw)

    def _v_thermal_drift(self):
        yield self._v(None, self._drift_ref(), (0,))

    def _v_compliance(self):
        sig = self.sig
        fmax = 0.45 / sig.ts
        for wl in 2 * np.pi * np.logspace(np.log10(3.0), np.log10(fmax), 22):
            for zeta in (0.02, 0.05, 0.12):
                col = sig.filt(_load_accel(sig, wl, zeta)) - sig.a
                yield self._v((float(wl), zeta), col, (1,))

    def _v_presliding(self):
        sig = self.sig
        res = sig.resolution if sig.resolution > 0 else 1e-6 * np.ptp(sig.q)
        # presliding shorter than 3 encoder counts is below what the encoder resolves
        for nc in np.logspace(np.log10(3.0), np.log10(150.0), 14):
            xc = nc * res
            z = _dahl_state(sig.qf, xc, 0.0)
            yield self._v(float(xc), sig.filt(z - self.s), (1,))

    def _v_inertia(self):
        yield self._v(None, self.sig.a, (0,))

    def _v_friction_scale(self):
        yield self._v(None, self.nom_friction, (0,))

    def _ripple_variants(self, fold):
        """Periods at the top peaks of the residual's periodogram in position (training data)."""
        key = ("ripple", fold)
        if key in self._cache:
            return self._cache[key]
        sig = self.sig
        rows = sig.moving & (sig.folds != fold) if fold is not None else sig.moving.copy()
        r = self._base_residual()[rows]
        q = sig.qf[rows]
        span = float(np.ptp(q))
        res = sig.resolution if sig.resolution > 0 else 1e-6 * span
        pmin = max(30 * res, 2e-5 * span)
        pmax = span / 4
        out = []
        if pmax > 2 * pmin:
            # Schuster periodogram of the residual as a function of position: residual
            # summed into bins of pmin/8, FFT (zero-padded x2 for a finer grid).
            nb = int(min(2 ** 21, 2 ** math.ceil(math.log2(span / (pmin / 8) + 1))))
            width = span / (nb - 1) if nb > 1 else span
            idx = np.minimum(((q - q.min()) / width).astype(np.int64), nb - 1)
            binned = np.bincount(idx, weights=r - r.mean(), minlength=nb)
            spec = np.abs(np.fft.rfft(binned, n=2 * nb)) ** 2
            nu = np.fft.rfftfreq(2 * nb, d=width)
            ok = (nu >= 1 / pmax) & (nu <= 1 / pmin)
            power = np.where(ok, spec, 0.0)
            peaks, _ = signal.find_peaks(power)
            top = peaks[np.argsort(power[peaks])[::-1][:3]] if peaks.size else []
            for i in top:
                per = 1.0 / nu[i]
                ang = 2 * np.pi * sig.qf / per
                out.append(self._v(float(per), np.column_stack([sig.filt(np.sin(ang)),
                                                                sig.filt(np.cos(ang))]), (0, 0)))
        self._cache[key] = out
        return out

    def _base_residual(self):
        if "base_res" not in self._cache:
            if self.fit_mode:
                self._cache["base_res"] = self.y0 - self.base_cols @ self.base_theta
            else:
                self._cache["base_res"] = self.y0.copy()
        return self._cache["base_res"]

    # ---- a model from a fit ---------------------------------------------------
    def model(self, cause, h, theta, units) -> JointModel:
        from .friction import Coulomb, LoadDependent, LuGre, PositionRipple, Stribeck, Viscous

        if self.fit_mode:
            inertia, b, fc = theta[:3]
            ex = theta[3:]
            base = JointModel(inertia=max(inertia, 1e-12), friction=Viscous(max(float(b), 0.0)) + Coulomb(max(float(fc), 0.0)),
                              units=units)
        else:
            base = replace(self.nominal, units=units)
            ex = theta
            fc = 0.5 * (base.friction.coulomb_pos + base.friction.coulomb_neg)
        fr = base.friction
        if cause in (None, "none"):
            return base
        if cause == "stribeck":
            fr = fr + Stribeck(max(ex[0], 0.0), h)
        elif cause == "asymmetry":
            db, c = ex
            d = fr.as_dict()
            d["viscous_pos"] = max(d["viscous_pos"] + db, 0.0)
            d["coulomb_pos"] = max(d["coulomb_pos"] + c, 0.0)
            d["coulomb_neg"] = max(d["coulomb_neg"] - c, 0.0)
            fr = FrictionModel.from_dict(d)
        elif cause == "load_dependent":
            fr = fr + LoadDependent(max(ex[0], 0.0))
        elif cause == "position_ripple":
            al, be = ex
            fr = fr + PositionRipple(float(math.hypot(al, be)), h, float(math.atan2(be, al)))
        elif cause == "time_delay":
            return replace(base, delay=h * self.sig.ts)
        elif cause == "thermal_drift":
            delta = float(ex[0])
            if self.fit_mode:
                tmid = 0.5 * (self.sig.t[0] + self.sig.t[-1])
                s0 = max(1.0 - delta * tmid, 1e-3)
                fr = replace(fr.scaled(s0), drift=delta / s0)
            else:
                fr = replace(fr, drift=fr.drift + delta)
        elif cause == "compliance":
            wl, zeta = h
            jl = min(max(ex[0], 1e-12), 0.95 * base.inertia)
            k = jl * wl * wl
            return replace(base, load_inertia=jl, stiffness=k, damping=2 * zeta * wl * jl)
        elif cause == "presliding":
            level = max(fc, 1e-12)
            sigma0 = level / h
            # bristle damping is not identified (one column, see Notes); a damping ratio
            # of 0.5 of the bristle mode keeps the re-simulation from ringing
            s1 = math.sqrt(sigma0 * base.inertia)
            d = fr.as_dict()
            if min(d["coulomb_pos"], d["coulomb_neg"]) <= 0:
                return base
            d["static_pos"] = d["static_neg"] = 0.0
            fr = FrictionModel.from_dict(d) + LuGre(sigma0, s1)
        elif cause == "inertia":
            return replace(base, inertia=max(base.inertia + ex[0], 1e-3 * base.inertia))
        elif cause == "friction_scale":
            fr = fr.scaled(max(1.0 + ex[0], 1e-3))
        return replace(base, friction=fr)


# ============================================================================ result
@dataclass(frozen=True, eq=False)
class Diagnosis:
    """What :func:`diagnose` found.

    Attributes
    ----------
    cause : str
        The named cause (one of :data:`CAUSES`).
    ranking : tuple of (str, float)
        Every applicable candidate with its score, best first: the held-out
        fraction of the baseline's torque residual (sum of squares) it removes [-].
    evidence : str
        The evidence for the named cause, in words and numbers.
    baseline, extended : JointModel
        The baseline (fitted or nominal) and the model extended with the named
        term (the baseline itself when the cause is ``none``).
    gain : dict
        Held-out RMS before/after: ``torque_rms_before``, ``torque_rms_after``
        [N*m], ``simulation_rms_before``, ``simulation_rms_after`` (position over
        the windows) [rad], ``velocity_rms_before``, ``velocity_rms_after`` [rad/s].
    simulation_scores : dict
        Per candidate, the held-out fraction of the windowed simulation error
        (position, sum of squares) it removes [-] (information, not the decision).
    fit : IdentificationResult or None
        The CasADi refit of the extended model (estimates with standard errors).
    t, torque, position, velocity : ndarray
        The record and the estimated velocity (for the figures).
    residual_before, residual_after : ndarray
        Torque residual of baseline and extended model, NaN where not sliding [N*m].
    sim_before, sim_after : WindowedSimulation
        Windowed re-simulation of both models (each window with the model fitted
        without that window's block).
    nominal : bool
        True when the baseline was a supplied nominal model.
    units : str
    """

    cause: str
    ranking: tuple
    evidence: str
    baseline: JointModel
    extended: JointModel
    gain: dict
    simulation_scores: dict
    fit: object
    t: np.ndarray
    torque: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    residual_before: np.ndarray
    residual_after: np.ndarray
    sim_before: WindowedSimulation
    sim_after: WindowedSimulation
    nominal: bool
    units: str = "rotary"

    @property
    def score(self) -> float:
        """Score of the named cause (0 for ``none``) [-]."""
        return dict(self.ranking).get(self.cause, 0.0)

    def as_dict(self) -> dict:
        """The ``fricctl diagnose --json`` object."""
        return {"cause": self.cause,
                "ranking": [{"cause": c, "score": float(s)} for c, s in self.ranking],
                "evidence": self.evidence,
                "baseline": self.baseline.parameters(),
                "extended": self.extended.parameters(),
                "gain": {k: float(v) for k, v in self.gain.items()},
                "nominal_model": self.nominal,
                "units": self.units}

    def report(self) -> str:
        """Markdown report: cause, evidence, ranking, models, gain."""
        tu, qu = ("N*m", "rad") if self.units == "rotary" else ("N", "m")
        g = self.gain
        lines = [f"# Diagnosis: `{self.cause}`", "",
                 f"*{_PHYSICAL[self.cause]}*", "", "## Evidence", "", self.evidence, "",
                 "## Candidates (held-out, blocked cross-validation)", "",
                 "| cause | torque score | simulation score |", "|---|---|---|"]
        for c, s in self.ranking:
            ss = self.simulation_scores.get(c, float("nan"))
            lines.append(f"| {c} | {100 * s:.1f} % | {100 * ss:.1f} % |")
        lines += ["", f"Score: fraction of the baseline's held-out torque residual (sum of squares) "
                      f"the candidate removes; named when >= {100 * MIN_SCORE:.0f} %.", "",
                  "## Held-out gain", "", "| quantity | before | after | change |", "|---|---|---|---|"]
        for name, key, unit in (("torque residual RMS", "torque", tu),
                                ("windowed simulation RMS, position", "simulation", qu),
                                ("windowed simulation RMS, velocity", "velocity", qu + "/s")):
            b, a = g[f"{key}_rms_before"], g[f"{key}_rms_after"]
            lines.append(f"| {name} | {b:.4g} {unit} | {a:.4g} {unit} | {100 * (a / b - 1):+.1f} % |")
        lines += ["", "## Models", "", "| parameter | baseline | extended |", "|---|---|---|"]
        pb, pe = self.baseline.parameters(), self.extended.parameters()
        for k in list(pb) + [k for k in pe if k not in pb]:
            lines.append(f"| {k} | {pb.get(k, float('nan')):.6g} | {pe.get(k, float('nan')):.6g} |")
        if self.fit is not None:
            lines += ["", "## Refit (CasADi least squares)", "", "```", self.fit.report(), "```"]
        return "\n".join(lines) + "\n"


# ============================================================================ evidence
def _evidence(cause, cands: _Candidates, h, theta, model: JointModel, base: JointModel, ranking,
              gain, sig: _Signals) -> str:
    tu, qu = ("N*m", "rad") if sig.units == "rotary" else ("N", "m")
    m = sig.moving
    r = cands._base_residual()
    fc = 0.5 * (base.friction.coulomb_pos + base.friction.coulomb_neg) * base.friction.scale
    score = dict(ranking).get(cause, 0.0)
    head = (f"{cause}: {_PHYSICAL[cause]}. Adding the term removes {100 * score:.0f} % of the "
            f"baseline's held-out torque residual (sum of squares, blocked cross-validation); ")
    ex = theta[3:] if cands.fit_mode else theta
    fr = model.friction
    if cause == "none":
        best = ranking[0] if ranking else ("-", 0.0)
        return (f"none: no candidate removes {100 * MIN_SCORE:.0f} % of the held-out torque residual "
                f"(best: {best[0]} with {100 * best[1]:.1f} %); the baseline explains the data within "
                f"noise (held-out torque RMS {gain['torque_rms_before']:.3g} {tu}).")
    if cause == "stribeck":
        vs = h
        w = np.abs(sig.w[m])
        rr = (r * np.sign(sig.w))[m]
        lo = rr[w < vs].mean() if np.any(w < vs) else float("nan")
        hi = rr[w > 10 * vs].mean() if np.any(w > 10 * vs) else float("nan")
        body = (f"below |w| = {vs:.3g} {qu}/s the baseline residual averages {lo:+.3g} {tu} in the "
                f"direction of motion, above {10 * vs:.3g} {qu}/s {hi:+.3g} {tu}; fitted Stribeck "
                f"excess {fr.stribeck_pos:.3g} {tu} ({100 * fr.stribeck_pos / max(fc, 1e-12):.0f} % of "
                f"the Coulomb level {fc:.3g} {tu}), Stribeck velocity {vs:.3g} {qu}/s")
    elif cause == "asymmetry":
        pos = r[m & (sig.w > 0)].mean()
        neg = r[m & (sig.w < 0)].mean()
        body = (f"the baseline residual averages {pos:+.3g} {tu} moving forward and {neg:+.3g} {tu} "
                f"moving backward; fitted Coulomb +{fr.coulomb_pos:.3g} / -{fr.coulomb_neg:.3g} {tu}, "
                f"viscous +{fr.viscous_pos:.3g} / -{fr.viscous_neg:.3g} {tu}*s/{qu} (a constant offset "
                f"of {0.5 * (fr.coulomb_pos - fr.coulomb_neg):+.3g} {tu} slides the same way)")
    elif cause == "load_dependent":
        u = np.abs(cands.u0[m])
        rr = (r * np.sign(sig.w))[m]
        c = float(np.corrcoef(u, rr)[0, 1]) if u.std() > 0 else float("nan")
        body = (f"the baseline residual in the direction of motion grows with |Tm| "
                f"(correlation {c:.2f}); fitted friction + {fr.load_coefficient:.3g} x |Tm|")
    elif cause == "position_ripple":
        body = (f"residual periodic in position, period {fr.ripple_period:.4g} {qu}, amplitude "
                f"{fr.ripple_amplitude:.3g} {tu} ({100 * fr.ripple_amplitude / max(fc, 1e-12):.0f} % of "
                f"the Coulomb level)")
    elif cause == "time_delay":
        d = model.delay_samples(sig.ts)
        body = (f"the torque acts {d} samples ({1e3 * d * sig.ts:.3g} ms) later than recorded "
                f"(the held-out residual is least at that shift among 1 .. "
                f"{max(int(round(0.02 / sig.ts)), 6)} samples)")
    elif cause == "thermal_drift":
        t0, t1 = sig.t[0], sig.t[-1]
        s0 = fr.scale * (1 + fr.drift * t0)
        s1 = fr.scale * (1 + fr.drift * t1)
        body = (f"the friction level changes by {100 * (s1 / s0 - 1):+.0f} % over the record "
                f"({t1 - t0:.3g} s, {100 * fr.drift / max(s0, 1e-12) * fr.scale:+.3g} % per s)")
    elif cause == "compliance":
        jm = model.inertia - model.load_inertia
        fr_hz = math.sqrt(model.stiffness * (1 / jm + 1 / model.load_inertia)) / (2 * math.pi)
        f, pxx = signal.welch(np.where(m, r, 0.0), fs=1 / sig.ts, nperseg=min(1024, r.size))
        sel = f > 2.0
        fpk = float(f[sel][np.argmax(pxx[sel])]) if sel.any() else float("nan")
        body = (f"residual spectrum peaks at {fpk:.3g} Hz; fitted elastic joint: stiffness K = "
                f"{model.stiffness:.4g} {tu}/{qu}, load inertia {model.load_inertia:.3g}, motor-side "
                f"inertia {jm:.3g}, resonance {fr_hz:.3g} Hz")
    elif cause == "presliding":
        xc = h
        counts = xc / sig.resolution if sig.resolution > 0 else float("nan")
        body = (f"the friction builds up over a presliding displacement of {xc:.3g} {qu} "
                f"({counts:.0f} encoder counts) after each reversal instead of switching with the "
                f"sign of the velocity; LuGre bristle stiffness sigma0 = {fr.lugre_sigma0:.4g} {tu}/{qu}")
    elif cause == "inertia":
        body = (f"inertia {model.inertia:.4g} against the nominal {base.inertia:.4g} "
                f"({100 * (model.inertia / base.inertia - 1):+.0f} %)")
    elif cause == "friction_scale":
        body = f"friction level x {fr.scale / base.friction.scale:.3f} of the nominal model"
    else:  # pragma: no cover
        body = ""
    tail = (f". Held-out torque RMS {gain['torque_rms_before']:.3g} -> {gain['torque_rms_after']:.3g} {tu}, "
            f"windowed simulation RMS {gain['simulation_rms_before']:.3g} -> "
            f"{gain['simulation_rms_after']:.3g} {qu}.")
    return head + body + tail


# ============================================================================ workflow
def _check_run(run):
    if not isinstance(run, Run):
        raise ValueError(f"run must be a fricctl.datasets.Run, got {type(run).__name__}")


def _baseline_fit(sig: _Signals, units: str):
    """The rigid baseline I, b, Fc by CasADi least squares on the sliding samples."""
    from .identify import fit_least_squares

    m = sig.moving
    X = np.column_stack([sig.a, sig.filt(sig.w), sig.filt(sig.seff)])[m]
    y = sig.torque_target(0)[m]
    scale = (np.linalg.norm(y) or 1.0) / np.maximum(np.linalg.norm(X, axis=0), 1e-300)
    return fit_least_squares(_dot, X, y, names=("inertia", "viscous", "coulomb"),
                             initial=np.zeros(3), lower=[0.0, 0.0, 0.0], scale=scale, units=units)


def _dot(theta, rows):
    """Linear prediction ``sum_j theta_j * x_j`` over the data rows (CasADi symbols)."""
    out = theta[0] * rows[0]
    for j in range(1, len(rows)):
        out = out + theta[j] * rows[j]
    return out


def diagnose(run: Run, model: JointModel | None = None, *, window: float = 0.5,
             folds: int = 8) -> Diagnosis:
    """Show what the model gets wrong on ``run``, name the cause, extend it, measure the gain.

    Parameters
    ----------
    run : Run
        The measured record (uniform sampling, any rate; moving in most blocks).
    model : JointModel, optional
        A nominal model to diagnose as given; default: fit the rigid baseline
        ``I*q'' = Tm - b*w - Fc*sign(w)``.
    window : float
        Window of the re-simulation [s].
    folds : int
        Blocks of the blocked cross-validation (3 .. 20).

    Returns
    -------
    Diagnosis

    Notes
    -----
    With a nominal model every candidate fits only its own term on top of it (the
    nominal is trusted otherwise); without, the baseline's I, b and Fc are refitted
    with each candidate.  ``inertia`` and ``friction_scale`` only apply to a
    nominal model.

    Examples
    --------
    >>> import numpy as np
    >>> from fricctl.bench.hidden_effects import hidden_effect_record
    >>> rec = hidden_effect_record(np.random.default_rng(3), cause="time_delay", duration=20.0)
    >>> diagnose(rec.run).cause
    'time_delay'
    """
    _check_run(run)
    if model is not None and not isinstance(model, JointModel):
        raise ValueError(f"model must be a JointModel (or None), got {type(model).__name__}")
    if isinstance(folds, bool) or not isinstance(folds, (int, np.integer)) or not 3 <= folds <= 20:
        raise ValueError(f"folds must be an integer in 3 .. 20, got {folds!r}")
    window = _finite("window", window, positive=True)
    sig = _signals(run, int(folds))
    units = run.units
    fit0 = None
    if model is None:
        fit0 = _baseline_fit(sig, units)
        base_theta = fit0.estimates.copy()
    else:
        base_theta = None
    cands = _Candidates(sig, model, base_theta)
    problem = _Problem(sig, cands.base_cols)
    base_var = _Variant(h=None, extra=np.zeros((sig.t.size, 0)), y=cands.y0, signs=())
    base_test, base_fits = _cv(problem, lambda f: [base_var], 0)
    base_sse = float(np.sum(base_test))

    scores = {}
    fold_fits = {}
    for cause in cands.applicable():
        nx = 0 if cause == "time_delay" else None
        vs_all = cands.variants(cause, None)
        if cause != "position_ripple" and not vs_all:
            continue
        if nx is None:
            probe = vs_all[0] if vs_all else None
            nx = probe.extra.shape[1] if probe is not None else 2
        test, fits = _cv(problem, lambda f, c=cause: cands.variants(c, f), nx)
        test = np.where(np.isnan(test), base_test, test)
        fits = [("__base__", bf[1]) if fc is None else fc for fc, bf in zip(fits, base_fits)]
        scores[cause] = 1.0 - float(np.sum(test)) / base_sse if base_sse > 0 else 0.0
        fold_fits[cause] = fits
    ranking = tuple(sorted(scores.items(), key=lambda kv: -kv[1]))

    # ---- models per fold -> held-out windowed simulation ------------------------
    starts, length = _windows(sig, window)
    wfold = sig.folds[starts]
    inside = sig.folds[np.minimum(starts + length - 1, sig.t.size - 1)] == wfold
    baseline_model = (cands.model(None, None, base_theta, units) if model is None
                      else replace(model, units=units))

    def fold_model(c, f):
        if c == "none":
            th = base_fits[f][1] if model is None else np.zeros(0)
            return cands.model(None, None, th, units)
        h, th = fold_fits[c][f]
        if isinstance(h, str) and h == "__base__":
            return cands.model(None, None, th, units)
        return cands.model(c, h, th, units)

    def heldout_sim(c):
        sims = [_simulate_windows(fold_model(c, f), sig, starts[(wfold == f) & inside], length)
                for f in range(sig.n_folds)]
        pe = np.concatenate([s.position_error for s in sims])
        ve = np.concatenate([s.velocity_error for s in sims])
        qs = np.full(sig.t.size, np.nan)
        ws = np.full(sig.t.size, np.nan)
        for s in sims:
            ok = ~np.isnan(s.q)
            qs[ok] = s.q[ok]
            ws[ok] = s.omega[ok]
        allst = np.concatenate([s.starts for s in sims])
        return WindowedSimulation(starts=allst, length=length, q=qs, omega=ws, position_error=pe,
                                  velocity_error=ve)

    sim_base = heldout_sim("none")
    pb = float(np.sum(sim_base.position_error ** 2))
    sim_scores = {}
    sims = {}
    for c, _ in ranking:
        sims[c] = heldout_sim(c)
        sim_scores[c] = 1.0 - float(np.sum(sims[c].position_error ** 2)) / pb if pb > 0 else 0.0
    # The named cause: the best torque score of at least MIN_SCORE among the candidates
    # whose extended model does not simulate the held-out windows worse than the
    # baseline (a term that explains the torque but breaks the simulation is not the
    # physical cause: e.g. a load term absorbing a resonance).
    # When no supported candidate simulates better (stick-slip re-simulation with a Stribeck
    # dip is chaotic: a slightly wrong breakaway makes a window stick or slip at another
    # instant), the torque evidence alone decides.
    supported = [c for c, sc in ranking if sc >= MIN_SCORE]
    credible = [c for c in supported if sim_scores.get(c, 0.0) > 0.0] or supported
    cause = credible[0] if credible else "none"
    sim_after = sims.get(cause, sim_base)

    # ---- extension: refit on all data with CasADi ---------------------------------
    refit = None
    if cause == "none":
        extended = baseline_model
        after_test = base_test
        h_full = None
        theta_full = base_theta if model is None else np.zeros(0)
    else:
        variants = cands.variants(cause, None)
        if cause == "position_ripple":
            variants = _refine_ripple(cands, variants)
        nx = variants[0].extra.shape[1]
        _, v_best, th0 = _full_fit(problem, variants, nx)
        h_full = v_best.h
        refit, theta_full = _casadi_refit(problem, v_best, nx, cause, units)
        extended = cands.model(cause, h_full, theta_full, units)
        after_test, _ = _cv(problem, lambda f, c=cause: cands.variants(c, f), nx)
        after_test = np.where(np.isnan(after_test), base_test, after_test)
    nmov = int(sig.moving.sum())
    gain = {"torque_rms_before": math.sqrt(base_sse / nmov),
            "torque_rms_after": math.sqrt(float(np.sum(after_test)) / nmov)}
    (gain["simulation_rms_before"], gain["velocity_rms_before"]) = sim_base.rms()
    (gain["simulation_rms_after"], gain["velocity_rms_after"]) = sim_after.rms()

    tb, pbm = _predict(baseline_model, sig)
    ta, pa = _predict(extended, sig)
    res_b = np.where(sig.moving, tb - pbm, np.nan)
    res_a = np.where(sig.moving, ta - pa, np.nan)
    evidence = _evidence(cause, cands, h_full, theta_full, extended, baseline_model, ranking, gain, sig)
    return Diagnosis(cause=cause, ranking=ranking, evidence=evidence, baseline=baseline_model,
                     extended=extended, gain=gain, simulation_scores=sim_scores, fit=refit or fit0,
                     t=sig.t, torque=sig.tm, position=sig.q, velocity=sig.w,
                     residual_before=res_b, residual_after=res_a, sim_before=sim_base,
                     sim_after=sim_after, nominal=model is not None, units=units)


def _refine_ripple(cands: _Candidates, variants):
    """A finer period grid around each periodogram peak (full data)."""
    out = list(variants)
    sig = cands.sig
    span = float(np.ptp(sig.qf[sig.moving]))
    for v in variants:
        per = v.h
        dnu = 1.0 / (6 * span)
        for k in np.linspace(-1.0, 1.0, 9):
            nu = 1.0 / per + k * dnu
            if nu <= 0:
                continue
            ang = 2 * np.pi * sig.qf * nu
            out.append(cands._v(float(1.0 / nu), np.column_stack([sig.filt(np.sin(ang)),
                                                                   sig.filt(np.cos(ang))]), (0, 0)))
    return out


def _casadi_refit(problem: _Problem, v: _Variant, nx: int, cause: str, units: str):
    """Refit the linear coefficients of the extended model by CasADi/IPOPT least squares."""
    from .identify import fit_least_squares

    X = problem.design(v)[problem.all_rows]
    y = v.y[problem.all_rows]
    p = X.shape[1]
    if p == 0:
        return None, np.zeros(0)
    base_names = ("inertia", "viscous", "coulomb") if problem.base is not None else ()
    extra_names = {"stribeck": ("stribeck_excess",), "asymmetry": ("delta_viscous_pos", "offset"),
                   "load_dependent": ("load_coefficient",), "position_ripple": ("ripple_sin", "ripple_cos"),
                   "time_delay": (), "thermal_drift": ("drift",), "compliance": ("load_inertia",),
                   "presliding": ("presliding_level",), "inertia": ("delta_inertia",),
                   "friction_scale": ("delta_scale",)}[cause]
    names = base_names + extra_names
    lower = [0.0] * len(base_names) + [0.0 if s > 0 else -np.inf for s in v.signs]
    upper = [np.inf] * len(base_names) + (list(v.upper) if v.upper else [np.inf] * nx)
    scale = (np.linalg.norm(y) or 1.0) / np.maximum(np.linalg.norm(X, axis=0), 1e-300)
    res = fit_least_squares(_dot, X, y, names=names, initial=np.zeros(p), lower=lower, upper=upper,
                            scale=scale, units=units)
    return res, res.estimates.copy()


# ============================================================================ transfer
def prediction_errors(model: JointModel, run: Run, *, window: float = 0.5) -> dict:
    """How well ``model`` predicts another record (no refit): RMS errors.

    Returns
    -------
    dict
        ``torque_rms`` (equation error on the sliding samples) [N*m],
        ``simulation_rms`` (windowed position error) [rad], ``velocity_rms`` [rad/s].
    """
    _check_run(run)
    if not isinstance(model, JointModel):
        raise ValueError("model must be a JointModel")
    sig = _signals(run, 1)
    target, pred = _predict(model, sig)
    r = (target - pred)[sig.moving]
    starts, length = _windows(sig, window)
    sim = _simulate_windows(model, sig, starts, length)
    p, v = sim.rms()
    return {"torque_rms": float(np.sqrt(np.mean(r ** 2))), "simulation_rms": p, "velocity_rms": v}
