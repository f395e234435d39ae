"""Benchmark: CasADi/IPOPT Stribeck fit vs scipy.optimize.least_squares (issue 4, sec. 7).

Same problem (50 000 samples of the Stribeck law, paper-like load-side values, seeded
Gaussian torque noise), same start, same bounds.  Reports wall time (median of
repeats, including CasADi's graph construction) and the final cost
0.5*sum(residual^2).  Run:  .venv/bin/python benchmarks/bench_identify.py
"""

from __future__ import annotations

import time

import numpy as np
from scipy.optimize import least_squares

from fricctl.identify import fit_friction, inverse_dynamics

N = 50_000
TRUE = dict(inertia=0.0046, viscous=0.0169, coulomb=0.144, static=0.18,
            stribeck_velocity=0.05, offset=0.003)
NAMES = tuple(TRUE)
START = dict(inertia=0.004, viscous=0.02, coulomb=0.12, static=0.2,
             stribeck_velocity=0.15, offset=0.0)
LOWER = np.array([0, 0, 0, 0, 1e-6, -np.inf])


def data(rng):
    t = np.arange(N) * 0.002
    w = 1.5 * np.sin(0.7 * t) * np.cos(0.13 * t) + 0.05 * np.sin(3 * t)
    a = 1.5 * (0.7 * np.cos(0.7 * t) * np.cos(0.13 * t) - 0.13 * np.sin(0.7 * t) * np.sin(0.13 * t)) \
        + 0.15 * np.cos(3 * t)
    y = inverse_dynamics("stribeck", TRUE, w, a) + rng.normal(0.0, 0.005, N)
    return w, a, y


def scipy_fit(w, a, y, jac):
    def res(th):
        return inverse_dynamics("stribeck", dict(zip(NAMES, th)), w, a) - y

    def jacobian(th):
        inertia, viscous, coulomb, static, vs, off = th
        s = np.sign(w)
        e = np.exp(-(w / vs) ** 2)
        return np.column_stack([a, w, s * (1 - e), s * e,
                                s * (static - coulomb) * e * 2 * w ** 2 / vs ** 3, np.ones_like(w)])

    x0 = np.array([START[n] for n in NAMES])
    out = least_squares(res, x0, jac=jacobian if jac else "2-point", bounds=(LOWER, np.inf),
                        x_scale="jac", ftol=1e-12, xtol=1e-12, gtol=1e-12, method="trf")
    return out.x, 0.5 * float(out.fun @ out.fun), out.nfev


def main(repeats: int = 3):
    rng = np.random.default_rng(0)
    w, a, y = data(rng)
    rows = []

    def timed(fn):
        times, out = [], None
        for _ in range(repeats):
            t0 = time.perf_counter()
            out = fn()
            times.append(time.perf_counter() - t0)
        return float(np.median(times)), out

    t_ca, res = timed(lambda: fit_friction(w, a, y, model="stribeck", initial=START))
    cost_ca = 0.5 * float(res.residual @ res.residual)
    rows.append(("casadi + ipopt (exact Hessian)", t_ca, cost_ca, res.estimates, res.iterations))
    for jac in (True, False):
        t_sp, (x, cost, nfev) = timed(lambda: scipy_fit(w, a, y, jac))
        rows.append((f"scipy least_squares trf ({'analytic' if jac else '2-point'} Jacobian)",
                     t_sp, cost, x, nfev))
    print(f"Stribeck fit, N = {N}, start {START}")
    print(f"{'method':<48} {'time [s]':>9} {'final cost':>14}  iters/nfev  estimates")
    for name, t, cost, x, it in rows:
        print(f"{name:<48} {t:9.3f} {cost:14.8e}  {it:>9}  " + " ".join(f"{v:.6g}" for v in x))
    print(f"time ratio scipy(analytic)/casadi = {rows[1][1] / t_ca:.2f}, "
          f"scipy(2-point)/casadi = {rows[2][1] / t_ca:.2f}")
    print(f"cost ratio casadi/scipy(analytic) - 1 = {cost_ca / rows[1][2] - 1:.3e}")


if __name__ == "__main__":
    main()
