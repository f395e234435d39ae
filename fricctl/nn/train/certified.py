"""Constrained least squares: a net whose gain at rest is certified inside a band (CasADi).

Why.  While the joint is stuck the patterns are ``Tat = Tm``; the compensated loop
``Tm(k+1) = Tc + s*T^at(Tm(k), 0)`` then has the loop gain ``s*g`` with
``g = dT^at/dTm`` at rest.  ``g >= 1`` winds the torque up like an integrator (the
joint runs away); ``g < 1`` leaves a dead zone ``Fs*(1 - s*g)`` and a stuck
position loop stops anywhere within ``+-Fs*(1 - s*g)/Kp`` of its reference.  A net
trained by plain least squares lands wherever the data push it (1.2-1.5 on the
paper's bench).  This trainer makes ``g`` a *specification*:

* ``gain_band[0] <= dT^at/dTm <= gain_band[1]`` at ``omega = 0`` for ``|Tm| <= rest_torque``
  (the largest torque the joint was seen to hold);
* ``|dT^at/dTm| <= gain_band[1]`` everywhere between rest and ``sliding_velocity``
  (one encoder count per sample: below it the joint is not known to move), so the
  stuck loop cannot wind up in the blend either;
* ``|dT^at/dTm| <= sliding_slope`` once the joint slides (``|omega| >= sliding_velocity``):
  sliding friction depends on the velocity, and on the transmitted torque at most as
  much as a harmonic drive's mesh friction does (10-30 %); a larger slope is the
  acceleration estimate's error (``Tm - I*alpha_hat`` correlates with ``Tm`` at torque
  steps), and it would feed the motor torque back through the estimate;
* ``|T^at(0, omega)| <= sliding_limit * rest_torque`` while sliding (no friction larger
  than 1.5x the largest holding torque seen: Stribeck peaks stay below it);
* ``T^at(0, 0) = 0`` (no torque at rest without a load: the stuck pattern at Tm = 0).

The constraints are imposed on grids, as penalties of growing weight in a
Levenberg-Marquardt least-squares problem (residuals and exact Jacobian from CasADi),
and the result is then *certified* on a dense grid (:func:`certify`); an attempt whose
certificate fails is retried from a perturbed start.  The net is returned with its
:class:`Certificate` in the metadata.

The inner loop starts from a *structured* net (a pair of units forming the at-rest
ramp that fades as the joint slides, a unit for the Coulomb step, the rest small and
random) that satisfies the constraints, rather than from random weights.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from ... import _validate as v
from ..layout import pack, unpack
from ..net import FrictionNet
from .core import LoopResult, TrainingProblem, Trainer

__all__ = ["Certificate", "certify", "loop", "TRAINER"]

#: Samples of the dense certification grid at rest.
CERTIFY_POINTS = 2001
#: Tolerance of the certificate on the slopes [-] (IPOPT's constraint tolerance is 1e-8).
SLOPE_TOLERANCE = 1e-6


@dataclass(frozen=True, kw_only=True)
class Certificate:
    """What a dense grid says about a net's slope ``dT^at/dTm``."""

    gain_min: float
    """Smallest ``dT^at/dTm`` at rest over ``|Tm| <= rest_torque`` [-]."""
    gain_max: float
    """Largest one [-]."""
    blend_slope_max: float
    """Largest ``|dT^at/dTm|`` at rest over the whole torque range [-]."""
    sliding_slope_max: float
    """Largest ``|dT^at/dTm|`` at ``omega = k*sliding_velocity``, k = +-1, +-2, ... [-]."""
    offset: float
    """``T^at(0, 0)`` [N*m]."""
    gain_band: tuple
    """The band asked for (lo, hi) [-]."""
    sliding_slope: float
    """The bound asked for while sliding [-]."""
    rest_torque: float
    """Torque range certified at rest [N*m]."""
    sliding_velocity: float
    """Where sliding begins [rad/s]."""
    passed: bool
    """Every slope inside its bound (to 1e-6)."""

    def as_dict(self) -> dict:
        """JSON-ready (stored in the net's metadata)."""
        d = asdict(self)
        d["gain_band"] = list(self.gain_band)
        return d


def _band(gain_band) -> tuple:
    if not isinstance(gain_band, (tuple, list)) or len(gain_band) != 2:
        raise ValueError(f"gain_band must be a pair (lo, hi), got {gain_band!r}")
    lo = v.real("gain_band lo", gain_band[0], positive=True)
    hi = v.real("gain_band hi", gain_band[1], positive=True)
    if not lo <= hi < 1.0:
        raise ValueError(f"gain_band must satisfy 0 < lo <= hi < 1 (g >= 1 winds the stuck loop up), "
                         f"got ({lo}, {hi})")
    return lo, hi


def certify(net: FrictionNet, *, gain_band, sliding_slope: float, rest_torque: float,
            sliding_velocity: float, torque_range: float | None = None,
            velocity_range: float | None = None) -> Certificate:
    """Check a net's slopes on a dense grid (the certificate stored with a trained net).

    Parameters
    ----------
    net : FrictionNet
    gain_band : (float, float)
        Allowed ``dT^at/dTm`` at rest [-].
    sliding_slope : float
        Allowed ``|dT^at/dTm|`` while sliding [-].
    rest_torque : float
        ``|Tm|`` range checked at rest [N*m].
    sliding_velocity : float
        One encoder count per sample [rad/s]: the backward-difference velocity the loop feeds
        the compensator is 0 or a multiple of it, and that lattice is what is certified.
    torque_range, velocity_range : float, optional
        ``|Tm|`` and ``|omega|`` ranges checked away from rest; default the net's envelope.

    Notes
    -----
    Velocities between 0 and one count per sample are never seen by the compensator of a
    quantised loop and are not certified; a compensator fed a continuous velocity estimate
    must check them itself.
    """
    v.instance("net", net, FrictionNet)
    lo, hi = _band(gain_band)
    sb = v.real("sliding_slope", sliding_slope, nonneg=True)
    fs = v.real("rest_torque", rest_torque, positive=True, unit="N*m")
    ws = v.real("sliding_velocity", sliding_velocity, positive=True, unit="rad/s")
    tr = (float(np.max(np.abs([net.envelope_low[0], net.envelope_high[0]])))
          if torque_range is None else v.real("torque_range", torque_range, positive=True))
    wr = (float(np.max(np.abs([net.envelope_low[1], net.envelope_high[1]])))
          if velocity_range is None else v.real("velocity_range", velocity_range, positive=True))
    tm = np.linspace(-fs, fs, CERTIFY_POINTS)
    g = net.torque_gain(tm, np.zeros_like(tm))
    tgrid = np.linspace(-tr, tr, 201)
    blend = np.abs(net.torque_gain(tgrid, np.zeros_like(tgrid)))
    k = np.arange(1, int(math.ceil(max(wr, ws) / ws)) + 1)
    wsl = np.concatenate([-k[::-1], k]) * ws
    slide = np.abs(net.torque_gain(*np.meshgrid(tgrid, wsl)))
    offset = float(net(0.0, 0.0))
    cert = dict(gain_min=float(g.min()), gain_max=float(g.max()),
                blend_slope_max=float(blend.max()), sliding_slope_max=float(slide.max()),
                offset=offset)
    passed = (cert["gain_min"] >= lo - SLOPE_TOLERANCE and cert["gain_max"] <= hi + SLOPE_TOLERANCE
              and cert["blend_slope_max"] <= hi + SLOPE_TOLERANCE
              and cert["sliding_slope_max"] <= sb + SLOPE_TOLERANCE
              and abs(offset) <= 1e-6 * net.output_scale)
    return Certificate(**cert, gain_band=(lo, hi), sliding_slope=sb, rest_torque=fs,
                       sliding_velocity=ws, passed=bool(passed))


def _structured_start(problem: TrainingProblem, band, rest_x: float, torque_x: float,
                      slide_x: float, coulomb: float, rng, perturb: float) -> np.ndarray:
    """A start that satisfies the constraints: the at-rest ramp as a pair of units that
    cancel once the joint slides, a unit for the Coulomb step, the others small.

    ``rest_x``, ``torque_x``, ``slide_x``: the rest torque, the largest torque and the
    sliding velocity in scaled units.  The pair ``tanh(a*x0 + c*x1) + tanh(a*x0 - c*x1)`` is
    linear to within 2 % over the rest range at ``x1 = 0`` and has a negligible slope in
    ``x0`` once ``c*x1 > a*x0 + 2.5`` for every torque: ``c = (a*torque_x + 2.5)/slide_x``."""
    h = problem.hidden
    if h < 3:
        raise ValueError("the certified trainer needs hidden >= 3 (ramp pair + Coulomb unit)")
    sc = problem.scaling
    g = 0.5 * (band[0] + band[1])
    # the pair 2*w2*tanh(a*x0)*... is linear to within 2 % up to the rest torque
    a = 0.1 / max(rest_x, 1e-9)
    c = (a * torque_x + 2.5) / slide_x
    w1 = np.zeros((h, 2))
    b1 = np.zeros(h)
    w2 = np.zeros(h)
    w1[0], w1[1] = (a, c), (a, -c)
    w2[0] = w2[1] = g * sc.input_scale[0] / (2 * a * sc.output_scale)
    w1[2] = (0.0, 3.0)
    w2[2] = coulomb
    w1[3:] = rng.normal(scale=0.5, size=(h - 3, 2))
    b1[3:] = rng.normal(scale=0.5, size=h - 3)
    w2[3:] = rng.normal(scale=0.01, size=h - 3)
    theta = pack(w1, b1, w2, 0.0)
    if perturb > 0:
        theta = theta * (1 + perturb * rng.normal(size=theta.size))
    return theta


def loop(problem: TrainingProblem, *, gain_band=(0.98, 0.99), sliding_slope: float = 0.3,
         sliding_limit: float = 1.5, rest_torque: float | None = None,
         sliding_velocity: float | None = None, attempts: int = 4,
         max_iterations: int = 300) -> LoopResult:
    """The scaled least-squares problem with the slope constraints as penalties; retried until certified.

    Parameters
    ----------
    gain_band : (float, float)
        ``dT^at/dTm`` at rest, ``0 < lo <= hi < 1`` [-].
    sliding_slope : float
        ``|dT^at/dTm|`` bound while sliding [-].
    sliding_limit : float
        ``|T^at|`` bound while sliding, in units of ``rest_torque`` [-].
    rest_torque : float, optional
        ``|Tm|`` range of the band [N*m]; default the largest ``|Tm|`` of the patterns at
        rest (``omega == 0``).
    sliding_velocity : float
        Velocity from which the joint slides [rad/s]: one encoder count per sample.
        Required.
    attempts : int
        Starts tried until one is solved and certified (1 .. 50).
    max_iterations : int
        Levenberg-Marquardt iterations per penalty stage.
    """
    import casadi as ca

    lo, hi = _band(gain_band)
    sb = v.real("sliding_slope", sliding_slope, nonneg=True)
    vlim = v.real("sliding_limit", sliding_limit, positive=True)
    attempts = v.integer("attempts", attempts, low=1, high=50)
    max_iterations = v.integer("max_iterations", max_iterations, low=1, high=100_000)
    if sliding_velocity is None:
        raise ValueError("the certified trainer needs sliding_velocity [rad/s]: the velocity of "
                         "one encoder count per sample (resolution / Ts)")
    sc = problem.scaling
    if np.any(sc.input_offset != 0):
        raise ValueError("the certified trainer needs centred scaling (Scaling.centred)")
    ws = v.real("sliding_velocity", sliding_velocity, positive=True, unit="rad/s")
    xn, tn, h = problem.xn, problem.tn, problem.hidden
    tm = xn[0] * sc.input_scale[0]
    om = xn[1] * sc.input_scale[1]
    at_rest = om == 0.0
    if rest_torque is None:
        if not at_rest.any():
            raise ValueError("no pattern at rest (omega == 0): give rest_torque")
        rest_torque = float(np.max(np.abs(tm[at_rest])))
    fs = v.real("rest_torque", rest_torque, positive=True, unit="N*m")
    tmax = float(np.max(np.abs(tm)))
    wmax = max(float(np.max(np.abs(om))), 2 * ws)
    ts_, wsc, ys = sc.input_scale[0], sc.input_scale[1], sc.output_scale

    theta = ca.MX.sym("theta", 4 * h + 1)
    w1 = ca.reshape(theta[:2 * h], 2, h).T
    b1, w2, b2 = theta[2 * h:3 * h], theta[3 * h:4 * h], theta[4 * h]

    def hidden(x0, x1):
        x = ca.DM(np.vstack([x0, x1]))
        return ca.tanh(w1 @ x + ca.repmat(b1, 1, x.shape[1]))

    def value(x0, x1):       # physical [N*m]
        return ((w2.T @ hidden(x0, x1)).T + b2) * ys + sc.output_offset

    def slope(x0, x1):       # dT/dTm [-]
        return ((w2 * w1[:, 0]).T @ (1 - hidden(x0, x1) ** 2)).T * ys / ts_

    n = problem.n
    objective = 0.5 * ca.sumsqr((w2.T @ hidden(xn[0], xn[1])).T + b2 - ca.DM(tn)) / n
    t_rest = np.linspace(-fs, fs, 41) / ts_
    w_blend = np.zeros(1)          # at rest, over the whole torque range
    # the loop's velocity is 0 or k counts per sample: constrain k = 1, 2, 3, 4, 6, ... (denser
    # where friction changes fast, at low speed); the certificate checks every k
    kmax = wmax / ws
    w_slide = ws * np.unique(np.round(np.concatenate([np.arange(1, 5),
                                                      np.geomspace(5, max(kmax, 6), 6)])))
    t_grid = np.linspace(-tmax, tmax, 21) / ts_
    # the grids hold the constraints at their points; between them a slope can pass its bound by
    # a little, so the grid bounds keep a margin (10 % of the band, 5 % of the slope bounds) and
    # the dense certificate checks the bounds themselves
    m = 0.1 * (hi - lo)
    lo_g, hi_g, sb_g = lo + m, hi - m, 0.95 * sb

    def grid(ws_):
        tt, ww = np.meshgrid(t_grid, np.unique(np.concatenate([-ws_, ws_])) / wsc)
        return tt.ravel(), ww.ravel()

    tb, wb = grid(w_blend)
    tsl, wsl = grid(w_slide)
    groups = [(slope(t_rest, 0 * t_rest), lo_g, hi_g), (slope(tb, wb), -hi_g, hi_g),
              (slope(tsl, wsl), -sb_g, sb_g),
              (value(0 * w_slide, w_slide / wsc), -vlim * fs, vlim * fs),
              (value(0 * w_slide, -w_slide / wsc), -vlim * fs, vlim * fs),
              (value(np.zeros(1), np.zeros(1)), 0.0, 0.0)]
    g = ca.vertcat(*[e for e, _, _ in groups])
    lbg = np.concatenate([np.full(e.shape[0], a) for e, a, _ in groups])
    ubg = np.concatenate([np.full(e.shape[0], b) for e, _, b in groups])
    # Penalty Levenberg-Marquardt: residuals [data / sqrt(N); sqrt(weight)*violation], the
    # weight raised by 100x per stage until the violations vanish (a stage ends at LM's
    # convergence).  With 4H + 1 unknowns each step is a 17x17 solve, so a run takes a few
    # hundred milliseconds; IPOPT on the same problem needed 5-40 s (MUMPS on the KKT system of
    # ~1300 constraints at every one of several hundred iterations).
    weight = ca.MX.sym("weight")
    viol = ca.fmax(g - ca.DM(ubg), 0) + ca.fmax(ca.DM(lbg) - g, 0)
    data = ((w2.T @ hidden(xn[0], xn[1])).T + b2 - ca.DM(tn)) / math.sqrt(n)
    r = ca.vertcat(data, ca.sqrt(weight) * viol)
    fun = ca.Function("residuals", [theta, weight], [r, ca.jacobian(r, theta), viol])
    sliding = ~at_rest
    coulomb = float(np.mean(np.abs(tn[sliding]))) if sliding.any() else 0.5
    losses, elapsed, outcomes = [], [], []
    best = None
    for k in range(attempts):
        th = _structured_start(problem, (lo, hi), fs / ts_, tmax / ts_, ws / wsc, coulomb,
                               problem.rng, perturb=0.0 if k == 0 else 0.05 * k)
        if k == 0:
            losses.append(0.5 * float(np.sum(fun(th, 0.0)[0].full().ravel() ** 2)))
            elapsed.append(problem.elapsed())
        for stage_weight in PENALTY_WEIGHTS:
            th = _levenberg_marquardt(fun, th, stage_weight, max_iterations)
        r0, _, vv = (x.full() for x in fun(th, 0.0))
        f = 0.5 * float(np.sum(r0.ravel() ** 2))
        net = _net(th, h, sc)
        cert = certify(net, gain_band=(lo, hi), sliding_slope=sb, rest_torque=fs,
                       sliding_velocity=ws, torque_range=tmax, velocity_range=wmax)
        outcomes.append("certified" if cert.passed else
                        f"not certified (largest grid violation {float(np.max(vv)):.2g})")
        if cert.passed and math.isfinite(f) and (best is None or f < best[0]):
            best = (f, th, cert, k)
        losses.append(best[0] if best is not None else f)
        elapsed.append(problem.elapsed())
        if best is not None:
            problem.report(attempts, attempts)  # certified: the attempts left are not needed
            break
        problem.report(k + 1, attempts)
    if best is None:
        raise ValueError(f"certified training failed: no start out of {attempts} gave a net whose "
                         f"slopes meet the band {lo}..{hi} ({'; '.join(outcomes)}); "
                         "try more attempts or a wider band")
    f, th, cert, k = best
    return LoopResult(theta=th, loss=np.asarray(losses), elapsed=np.asarray(elapsed),
                      metadata={"method": "penalty Levenberg-Marquardt, slope-constrained "
                                          "least squares", "attempts": k + 1, "outcomes": outcomes,
                                "certificate": cert.as_dict()})


#: Penalty weights of the successive stages (the constraints are O(1) slopes and torques
#: in N*m; the data term is a mean of squared scaled residuals, O(0.1)).
PENALTY_WEIGHTS = (1e2, 1e4, 1e6, 1e8)


def _levenberg_marquardt(fun, theta, weight, max_iterations):
    """Minimise 0.5*|r(theta)|^2 from ``theta`` (Nielsen's damping update)."""
    r, jac, _ = (x.full() for x in fun(theta, weight))
    r = r.ravel()
    cost = 0.5 * float(r @ r)
    a, grad = jac.T @ jac, jac.T @ r
    mu, nu = 1e-3 * float(np.max(np.diag(a))), 2.0
    p = theta.size
    for _ in range(max_iterations):
        if np.linalg.norm(grad, np.inf) <= 1e-12 * max(cost, 1e-300):
            break
        try:
            d = np.linalg.solve(a + mu * np.eye(p), -grad)
        except np.linalg.LinAlgError:
            d = None
        if d is not None and np.all(np.isfinite(d)):
            r_new, jac_new, _ = (x.full() for x in fun(theta + d, weight))
            r_new = r_new.ravel()
            cost_new = 0.5 * float(r_new @ r_new)
            predicted = 0.5 * float(d @ (mu * d - grad))
            rho = (cost - cost_new) / predicted if predicted > 0 else -1.0
            if rho > 0:
                decrease = (cost - cost_new) / max(cost, 1e-300)
                theta, r, jac, cost = theta + d, r_new, jac_new, cost_new
                a, grad = jac.T @ jac, jac.T @ r
                mu *= max(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3)
                nu = 2.0
                if decrease < 1e-10:
                    break
                continue
        mu *= nu
        nu *= 2.0
        if mu > 1e20:
            break
    return theta


def _net(theta, hidden, scaling) -> FrictionNet:
    w = unpack(theta, hidden)
    return FrictionNet(w1=w.w1, b1=w.b1, w2=w.w2, b2=w.b2, **scaling.net_fields())


TRAINER = Trainer(name="certified", step="attempt", loop=loop,
                  description="least squares under slope constraints (penalty Levenberg-Marquardt): "
                              "the gain at rest "
                              "certified inside a band, bounded feedback of Tm while sliding",
                  # the loop refuses the seam's default range scaling and has no default for
                  # sliding_velocity: bare patterns cannot feed it
                  requires="a centred scaling (Scaling.centred) and sliding_velocity, one encoder "
                           "count per sample: the fricctl pipeline prepares both")
