"""Speed and accuracy of the stick-slip simulator against what a user would otherwise write.

The same closed loop -- PD step of 30 deg (tr 0.3 s, zeta 0.9), 10 s, the paper actuator's
viscous + Coulomb + Stribeck (static) friction, 500 Hz -- simulated by

* fricctl's compiled, event-located sampled loop (``fricctl.simulate.simulate``);
* a python-control ``nlsys`` with tanh-smoothed friction and a continuous PD, run by
  ``control.input_output_response`` with its default solver (RK45) and with LSODA;

each compared with an *independent* fine event-located reference of its own loop, written here
with ``scipy.integrate.solve_ivp`` (DOP853, rtol 1e-11) and terminal events at omega = 0:
the sampled loop for fricctl, the continuous loop for python-control.

Batch: ``simulate_batch`` with N = 1000 variants (viscous 0.8-1.2x), per-trajectory cost
against one ``simulate`` call and against the Python-callback loop (a compensator that is a
plain Python callable, the path any custom estimator takes).

Run: ``.venv/bin/python benchmarks/bench_simulate.py`` (about a minute).
"""

from __future__ import annotations

import math
import time

import control as ct
import numpy as np
from scipy.integrate import solve_ivp

from fricctl.compensators import NNCompensator
from fricctl.controllers import pd_control, step
from fricctl.params import paper_actuator
from fricctl.simulate import simulate, simulate_batch

P = paper_actuator()
I, B = P.inertia, P.viscous
FC, FS, VS = P.coulomb, P.static, P.stribeck_velocity
R = math.radians(30.0)
ZETA, TR = 0.9, 0.3
WN = (math.pi - math.acos(ZETA)) / (TR * math.sqrt(1 - ZETA**2))
KP, KD = I * WN**2, 2 * ZETA * WN * I - B
TS, T_END = P.sample_time, 10.0
TMAX = P.max_torque


def level(w):
    return FC + (FS - FC) * math.exp(-(w / VS) ** 2)


def _slide_rhs(s, torque_fn):
    def f(t, x):
        return [x[1], (torque_fn(t, x) - B * x[1] - s * level(x[1])) / I]
    return f


def _stop_event(s):
    """Terminal event: the velocity of direction s crosses zero (never fires at a start from rest)."""
    def ev(t, x):
        return x[1]
    ev.terminal = True
    ev.direction = -s
    return ev


def reference_sampled(rtol=1e-11):
    """Independent event-located reference of fricctl's sampled loop (no quantisation)."""
    n = int(round(T_END / TS))
    q = np.zeros(n)
    x = np.array([0.0, 0.0])
    y_prev = 0.0
    tm_next = 0.0
    for k in range(n):
        q[k] = x[0]
        y = x[0]
        wh = (y - y_prev) / TS if k else 0.0
        tm = tm_next
        tm_next = min(max(KP * (R - y) - KD * wh, -TMAX), TMAX)
        t0, t1 = k * TS, (k + 1) * TS
        while t0 < t1 - 1e-15:
            if x[1] == 0.0:
                if abs(tm) <= FS:
                    break
                s = math.copysign(1.0, tm)
            else:
                s = math.copysign(1.0, x[1])
            sol = solve_ivp(_slide_rhs(s, lambda t, xx: tm), (t0, t1), x, method="DOP853", rtol=rtol,
                            atol=1e-14, events=_stop_event(s))
            x = sol.y[:, -1].copy()
            if sol.status == 1:
                x[1] = 0.0
                t0 = sol.t_events[0][0]
            else:
                t0 = t1
        y_prev = y
    return q


def reference_continuous(t_eval, rtol=1e-11):
    """Event-located reference of the continuous PD loop with exact stick-slip."""
    def torque(t, x):
        return min(max(KP * (R - x[0]) - KD * x[1], -TMAX), TMAX)

    x = np.array([0.0, 0.0])
    t0 = 0.0
    ts, qs = [0.0], [0.0]
    while t0 < T_END:
        if x[1] == 0.0:
            u = torque(t0, x)
            if abs(u) <= FS:
                break  # stuck for good: the reference is constant after the step
            s = math.copysign(1.0, u)
        else:
            s = math.copysign(1.0, x[1])
        sol = solve_ivp(_slide_rhs(s, torque), (t0, T_END), x, method="DOP853", rtol=rtol, atol=1e-14,
                        events=_stop_event(s), dense_output=True)
        tt = t_eval[(t_eval > t0) & (t_eval <= sol.t[-1])]
        ts.extend(tt)
        qs.extend(sol.sol(tt)[0])
        x = sol.y[:, -1].copy()
        t0 = sol.t[-1]
        if sol.status == 1:
            x[1] = 0.0
    ts.append(T_END + 1)
    qs.append(x[0])
    return np.interp(t_eval, ts, qs)


def python_control_run(method, eps):
    def upd(t, x, u, params):
        w = x[1]
        torque = min(max(KP * (R - x[0]) - KD * w, -TMAX), TMAX)
        f = B * w + (FC + (FS - FC) * math.exp(-(w / VS) ** 2)) * math.tanh(w / eps)
        return [w, (torque - f) / I]

    sys = ct.nlsys(upd, None, states=2, inputs=0, outputs=2, name="tanh_joint")
    t = np.arange(int(round(T_END / TS))) * TS
    kw = {} if method is None else {"solve_ivp_method": method}
    t0 = time.perf_counter()
    res = ct.input_output_response(sys, t, 0, [0.0, 0.0], **kw)
    return time.perf_counter() - t0, t, res.states[0]


def best_of(fn, repeat):
    best = float("inf")
    out = None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def main():
    ctrl = pd_control(KP, KD, step(R))
    simulate(P, ctrl, duration=T_END)  # compile (cached on disk after the first run)
    t_fr, res = best_of(lambda: simulate(P, ctrl, duration=T_END, quantize=False), 20)
    ref_s = reference_sampled()
    err_fr = np.abs(res.q - ref_s)

    rows = []
    ref_c = None
    for eps in (1e-2, 1e-3):
        for method in (None, "LSODA"):
            dt, t, q = python_control_run(method, eps)
            if ref_c is None:
                ref_c = reference_continuous(t)
            e = np.abs(q - ref_c)
            rows.append((f"python-control {'RK45 (default)' if method is None else method}, tanh eps={eps:g} rad/s",
                         dt, e.max(), abs(q[-1] - ref_c[-1])))

    print(f"closed loop: PD 30 deg, Kp={KP:.4f} N*m/rad, Kd={KD:.4f} N*m*s/rad, 10 s at 500 Hz\n")
    print(f"{'simulator':58s} {'time [s]':>10s} {'max |q-ref| [rad]':>18s} {'final err [rad]':>16s}")
    print(f"{'fricctl simulate (compiled, event-located, 4 substeps)':58s} {t_fr:10.5f} {err_fr.max():18.2e}"
          f" {abs(res.q[-1] - ref_s[-1]):16.2e}")
    for name, dt, emax, efin in rows:
        print(f"{name:58s} {dt:10.4f} {emax:18.2e} {efin:16.2e}")
    print("\nspeed-up of fricctl:")
    for name, dt, _, _ in rows:
        print(f"  vs {name}: {dt / t_fr:8.0f}x")
    print(f"final positions: fricctl {res.q[-1]:.6f}, sampled reference {ref_s[-1]:.6f}, "
          f"continuous reference {ref_c[-1]:.6f} rad")

    # batch
    n = 1000
    variants = [P.replace(viscous=P.viscous * s) for s in np.linspace(0.8, 1.2, n)]
    simulate_batch(variants[:2], ctrl, duration=T_END)  # compile the parallel loop
    t_batch, _ = best_of(lambda: simulate_batch(variants, ctrl, duration=T_END), 2)
    t_single, _ = best_of(lambda: simulate(P, ctrl, duration=T_END), 20)
    py_comp = NNCompensator(lambda tm, w: 0.0 * tm, name="python callable")
    t_py, _ = best_of(lambda: simulate(P, ctrl, py_comp, duration=T_END), 2)
    per = t_batch / n
    print(f"\nbatch N={n}: {t_batch:.3f} s, {per * 1e3:.3f} ms per trajectory")
    print(f"  single compiled run: {t_single * 1e3:.3f} ms -> ratio {t_single / per:.1f}x")
    print(f"  single run through the Python-callback loop: {t_py * 1e3:.1f} ms -> ratio {t_py / per:.0f}x")


if __name__ == "__main__":
    main()
