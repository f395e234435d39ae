"""An independent bench for the diagnosis: a second simulator, written here and shared with
nothing in the package, to see whether the decision rules generalise beyond the package's
own generator (:mod:`fricctl.bench.hidden_effects`) before an external bench does.

What differs from the package's bench, on purpose:

* integration: :func:`scipy.integrate.solve_ivp` (RK45, tight tolerances) per held-torque
  piece, the stops located by an event on the velocity and the stick decided there
  (event-located friction); a compliant joint uses a smoothed friction ``tanh(w/eps)``
  instead (LSODA);
* friction laws the diagnosis does not model exactly: a Tustin (exponential, not
  Gaussian) Stribeck dip, a ripple with two harmonics, an exponential warm-up instead
  of a linear drift, Dahl presliding instead of LuGre;
* the loop: a cascade (P position, PI velocity on a filtered difference), torque
  computed at one sample and applied over the next; a delay of any fraction of a
  sample; the encoder rounds (not floors); the recorded torque carries a current
  sensor's noise and a 12-bit quantisation;
* the excitation: multisine and pulse torques, S-curve moves, slow sweeps, holding
  position against load steps.

A dead band between motor and load (``effects=("backlash",)``: the compliant joint with the
spring acting beyond the gap and pushing only) can be hidden too; it is left out of
:data:`EFFECTS` so that the records drawn from that list stay as they were.

Magnitudes are drawn from this module's own ranges.  Seeds: ``[31, i]`` (tests);
the benchmark uses ``[32, i]``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from fricctl.datasets import Run

#: Effects this bench can hide (diagnosis names).
EFFECTS = ("stribeck", "asymmetry", "load_dependent", "position_ripple", "time_delay",
           "thermal_drift", "compliance", "presliding")


@dataclass(kw_only=True)
class Plant:
    """Axis and effect parameters of one record (SI, load side)."""

    inertia: float
    viscous: float
    coulomb: float
    res: float
    travel: float
    torque_noise: float
    effects: dict = field(default_factory=dict)


def draw_plant(rng, axis: str, effects: tuple) -> Plant:
    """An axis and the effects' magnitudes, from this bench's own ranges."""
    if axis == "rotary":
        p = Plant(inertia=rng.uniform(1e-3, 2e-2), viscous=rng.uniform(0.005, 0.05),
                  coulomb=rng.uniform(0.05, 0.4), res=2 * math.pi / rng.choice([4096, 16384, 65536]),
                  travel=1.0, torque_noise=0.0)
    else:
        p = Plant(inertia=rng.uniform(10.0, 250.0), viscous=rng.uniform(20.0, 400.0),
                  coulomb=rng.uniform(3.0, 60.0), res=rng.choice([1e-7, 5e-7, 1e-6, 5e-6]),
                  travel=0.05, torque_noise=0.0)
    p.torque_noise = rng.uniform(0.002, 0.02) * p.coulomb
    fc = p.coulomb
    for e in effects:
        if e == "stribeck":
            p.effects[e] = dict(excess=rng.uniform(0.6, 1.2) * fc, vs=rng.uniform(0.02, 0.08) * p.travel)
        elif e == "asymmetry":
            p.effects[e] = dict(ratio=rng.uniform(1.4, 1.9))
        elif e == "load_dependent":
            p.effects[e] = dict(mu=rng.uniform(0.12, 0.3))
        elif e == "position_ripple":
            p.effects[e] = dict(amp=rng.uniform(0.3, 0.6) * fc,
                                period=rng.uniform(0.05, 0.3) * p.travel, phase=rng.uniform(0, 6.3))
        elif e == "time_delay":
            p.effects[e] = dict(samples=rng.uniform(0.6, 6.0))
        elif e == "thermal_drift":
            p.effects[e] = dict(change=rng.uniform(0.3, 0.6) * rng.choice([-1.0, 1.0]))
        elif e == "compliance":
            p.effects[e] = dict(share=rng.uniform(0.4, 0.6), hz=rng.uniform(10.0, 30.0),
                                zeta=rng.uniform(0.03, 0.1))
        elif e == "presliding":
            p.effects[e] = dict(counts=rng.uniform(8.0, 25.0))
        elif e == "backlash":  # not in EFFECTS: hidden only where a test asks for it
            p.effects[e] = dict(gap=math.radians(rng.uniform(0.5, 1.5)) * p.travel,
                                share=rng.uniform(0.3, 0.6), hz=rng.uniform(200.0, 600.0),
                                zeta=rng.uniform(0.2, 0.6))
    return p


def _friction_level(p: Plant, w_sign: float, u: float, t: float, duration: float) -> float:
    """Coulomb level in the direction ``w_sign`` (before the Stribeck and viscous parts)."""
    fc = p.coulomb
    if "asymmetry" in p.effects:
        r = p.effects["asymmetry"]["ratio"]
        fc = fc * math.sqrt(r) if w_sign > 0 else fc / math.sqrt(r)
    if "load_dependent" in p.effects:
        fc += p.effects["load_dependent"]["mu"] * abs(u)
    return fc * _scale(p, t, duration)


def _scale(p: Plant, t: float, duration: float) -> float:
    if "thermal_drift" not in p.effects:
        return 1.0
    c = p.effects["thermal_drift"]["change"]
    return 1.0 + c * (1.0 - math.exp(-3.0 * t / duration)) / (1.0 - math.exp(-3.0))


def _ripple(p: Plant, q: float) -> float:
    if "position_ripple" not in p.effects:
        return 0.0
    e = p.effects["position_ripple"]
    x = 2 * math.pi * q / e["period"] + e["phase"]
    return e["amp"] * (math.sin(x) + 0.3 * math.sin(2 * x + 1.0))


def _sliding(p: Plant, w: float, s: float, u: float, t: float, duration: float) -> float:
    """Friction while sliding in direction s (velocity w) [N*m]."""
    level = _friction_level(p, s, u, t, duration)
    if "stribeck" in p.effects:
        e = p.effects["stribeck"]
        level += e["excess"] * math.exp(-abs(w) / e["vs"]) * _scale(p, t, duration)
    return s * level + p.viscous * _scale(p, t, duration) * w


def _piece_rigid(p, state, u, t0, t1, duration):
    """Integrate the rigid joint over [t0, t1] under torque u, stops located by events."""
    q, w, stuck = state
    t = t0
    while t < t1 - 1e-15:
        if stuck:
            net = u - _ripple(p, q)
            brk = _friction_level(p, np.sign(net) or 1.0, u, t, duration)
            if "stribeck" in p.effects:
                brk += p.effects["stribeck"]["excess"] * _scale(p, t, duration)
            if abs(net) <= brk:
                return (q, 0.0, True)
            s = math.copysign(1.0, net)
        else:
            s = math.copysign(1.0, w)

        def rhs(tt, x, s=s):
            return [x[1], (u - _ripple(p, x[0]) - _sliding(p, x[1], s, u, tt, duration)) / p.inertia]

        def stop(tt, x, s=s):
            return x[1] * s + (1e-12 if tt == t else 0.0)
        stop.terminal = True
        stop.direction = -1
        sol = solve_ivp(rhs, (t, t1), [q, w if not stuck else 0.0], events=stop, rtol=1e-9,
                        atol=1e-12 * max(p.travel, 1e-9), max_step=(t1 - t0))
        q, w = sol.y[0, -1], sol.y[1, -1]
        if sol.status == 1:  # stopped: stick, or turn round at once
            t = float(sol.t_events[0][0])
            q, w, stuck = float(sol.y_events[0][0][0]), 0.0, True
        else:
            return (q, w, False)
    return (q, w, stuck)


def _piece_smooth(p, state, u, t0, t1, duration):
    """Compliant joint (motor + load on a spring, encoder on the motor) or Dahl presliding,
    with a smoothed friction; LSODA."""
    eps = 1e-4 * p.travel
    comp = p.effects.get("compliance") or p.effects.get("backlash")
    gap = p.effects["backlash"]["gap"] if "backlash" in p.effects else 0.0
    dahl = p.effects.get("presliding")

    def rhs(t, x):
        qm, wm, ql, wl, z = x
        s = math.tanh(wm / eps)
        if dahl is not None:
            sig0 = p.coulomb / (dahl["counts"] * p.res)
            fr = z * _scale(p, t, duration) + p.viscous * wm
            dz = sig0 * wm * (1.0 - z / p.coulomb * np.sign(wm))
        else:
            fr = _sliding(p, wm, s, u, t, duration)
            dz = 0.0
        if comp is None:
            return [wm, (u - _ripple(p, qm) - fr) / p.inertia, wm, wm, dz]
        jl = comp["share"] * p.inertia
        jm = p.inertia - jl
        k = (2 * math.pi * comp["hz"]) ** 2 / (1 / jm + 1 / jl)
        d = 2 * comp["zeta"] * math.sqrt(k * jl)
        spring = k * (qm - ql) + d * (wm - wl)
        if gap > 0:  # a dead band: contact torque on the deflection beyond the gap, pushing only
            x, h = qm - ql, 0.5 * gap
            spring = (max(k * (x - h) + d * (wm - wl), 0.0) if x > h else
                      min(k * (x + h) + d * (wm - wl), 0.0) if x < -h else 0.0)
        return [wm, (u - _ripple(p, qm) - fr - spring) / jm, wl, spring / jl, dz]
    sol = solve_ivp(rhs, (t0, t1), state, method="LSODA", rtol=1e-8,
                    atol=1e-11 * max(p.travel, 1e-9) + 1e-12)
    return list(sol.y[:, -1])


def simulate_record(seed, *, effects: tuple = (), axis: str = "rotary",
                    sample_time: float = 0.001, duration: float = 20.0,
                    delay: float | None = None):
    """One record of this bench: ``(Run, Plant)``; ``delay`` [samples] replaces the drawn
    delay of a ``time_delay`` effect."""
    rng = np.random.default_rng(seed)
    p = draw_plant(rng, axis, effects)
    if delay is not None and "time_delay" in p.effects:
        p.effects["time_delay"]["samples"] = float(delay)
    ts = sample_time
    n = int(round(duration / ts))
    fc, inertia, trav = p.coulomb, p.inertia, p.travel
    # excitation: per segment (kind, samples), each kind once per half
    kinds = ["multisine", "pulses", "moves", "sweep", "hold"]
    order = list(rng.permutation(kinds)) + list(rng.permutation(kinds))
    lengths = np.diff(np.round(np.linspace(0, n, len(order) + 1)).astype(int))
    wv = 2 * math.pi * rng.uniform(12.0, 25.0)  # velocity loop bandwidth
    kv, ki = inertia * wv, inertia * wv ** 2 / 4
    kpos = wv / rng.uniform(5.0, 8.0)
    alpha = math.exp(-2 * math.pi * min(0.2 / ts, 200.0) * ts)
    delay = p.effects.get("time_delay", {}).get("samples", 0.0)
    smooth = bool({"compliance", "presliding", "backlash"} & set(p.effects))
    state = [0.0, 0.0, 0.0, 0.0, 0.0] if smooth else (0.0, 0.0, True)
    q_meas = np.empty(n)
    applied = np.zeros(n + 2)  # the torque acting over [t_k, t_k+1): computed at k-1
    y_prev, vhat, integ, ref, k = 0.0, 0.0, 0.0, 0.0, 0
    sensor = rng.normal(0.0, 0.01 * fc, n)
    noise = rng.normal(0.0, p.torque_noise, n)
    for kind, m in zip(order, lengths):
        t_seg = np.arange(m) * ts
        closed = kind in ("moves", "sweep", "hold")
        if kind == "multisine":
            f = rng.uniform(0.3, 2.5, 3)
            ph = rng.uniform(0, 6.3, 3)
            ff = (rng.uniform(1.5, 2.5) * fc / 1.7) * sum(np.sin(2 * np.pi * fi * t_seg + pi)
                                                        for fi, pi in zip(f, ph))
        elif kind == "pulses":
            ff = np.zeros(m)
            j = 0
            while j < m:
                on = max(int(rng.uniform(0.05, 0.4) / ts), 2)
                ff[j:j + on] = rng.choice([-1.0, 1.0]) * rng.uniform(1.5, 3.0) * fc
                j += on + int(rng.uniform(0.1, 0.5) / ts)
        else:
            ff = np.zeros(m)
        if kind == "moves":  # S-curve point-to-point moves back and forth
            target = np.zeros(m)
            j, pos = 0, ref
            while j < m:
                dur = int(rng.uniform(0.4, 1.2) / ts)
                step = rng.choice([-1.0, 1.0]) * rng.uniform(0.2, 2.0) * trav
                x = np.linspace(0, 1, max(dur, 2))
                target[j:j + dur] = (pos + step * (10 * x ** 3 - 15 * x ** 4 + 6 * x ** 5))[:m - j]
                pos += step
                j += dur + int(rng.uniform(0.1, 0.3) / ts)
                target[j - int(rng.uniform(0.1, 0.3) / ts):j] = pos
        elif kind == "sweep":  # slow constant speeds both ways (the low-speed friction)
            v = rng.uniform(0.005, 0.1) * trav * np.sign(np.sin(2 * np.pi * rng.uniform(0.2, 0.5) * t_seg))
            target = ref + np.cumsum(v) * ts
        elif kind == "hold":  # holding position against load steps
            target = np.full(m, ref)
            ff = np.zeros(m)
            j = 0
            while j < m:
                on = int(rng.uniform(0.3, 0.8) / ts)
                ff[j:j + on] = rng.choice([-1.0, 1.0]) * rng.uniform(0.5, 1.5) * fc
                j += on + int(rng.uniform(0.2, 0.5) / ts)
        else:
            target = None
        for i in range(m):
            qtrue = state[0]
            y = p.res * round(qtrue / p.res)
            q_meas[k] = y
            vhat = alpha * vhat + (1 - alpha) * (y - y_prev) / ts if k else 0.0
            y_prev = y
            if closed:
                ref = target[i]
                vref = kpos * (ref - y)
                integ += (vref - vhat) * ts
                u = kv * (vref - vhat) + ki * integ + ff[i]
            else:
                integ, ref = 0.0, y
                u = ff[i]
            u = float(np.clip(u, -10 * fc, 10 * fc))
            applied[k + 1] = u
            # the joint receives the applied torque `delay` samples late (any fraction)
            d_int, d_frac = int(math.floor(delay)), delay - math.floor(delay)
            t0 = k * ts
            old = applied[max(k - d_int - 1, 0)] if k - d_int - 1 >= 0 else 0.0
            new = applied[k - d_int] if k - d_int >= 0 else 0.0
            pieces = ([(t0, t0 + d_frac * ts, old)] if d_frac > 0 else []) + \
                [(t0 + d_frac * ts, t0 + ts, new)]
            for a, b, torque in pieces:
                torque = torque + noise[k]
                if smooth:
                    state = _piece_smooth(p, state, torque, a, b, duration)
                else:
                    state = _piece_rigid(p, state, torque, a, b, duration)
            k += 1
    levels = 2 ** 12
    tmax = 10 * fc
    recorded = np.round((applied[:n] + sensor) / (2 * tmax) * levels) * (2 * tmax) / levels
    run = Run(t=np.arange(n) * ts, torque=recorded, position=q_meas, units=axis,
              source=f"independent bench, seed {seed}")
    return run, p


# ----------------------------------------------------------------------------- tests
def test_stick_slip_and_quantisation():
    # the event-located friction holds the joint still below breakaway (no creep) and the
    # encoder rounds to whole counts (reference: the count, exact)
    run, p = simulate_record([31, 0], duration=10.0)
    counts = run.position / p.res
    np.testing.assert_allclose(counts, np.round(counts), atol=1e-9)
    steps = np.diff(run.position)
    assert 0.05 < np.mean(steps == 0) < 0.95  # both standing and sliding samples


@pytest.mark.slow
@pytest.mark.parametrize("i", range(3))
def test_none_on_the_independent_bench(i):
    from fricctl.diagnose import diagnose

    run, _ = simulate_record([31, 10 + i], axis=("rotary", "linear")[i % 2],
                             sample_time=(0.0005, 0.001, 0.005)[i], duration=20.0)
    assert diagnose(run).causes == ("none",)
