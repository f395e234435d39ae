"""Fig. 16: the aged actuator with the link: NN x 0.95 (not retrained), Coulomb, none."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import controllers as ctl
from . import coast as coast_test
from .claims import Claim, gate
from .common import (ACCURACY_DEG, AGED_SCALE, SS_WINDOW, LinkFigure, deg, last_window, link_runs,
                     sign_changes)
from .network import PaperNetwork, check_network
from .registry import PaperFigure
from .runaway import wind_up

__all__ = ["Fig16Result", "run", "claim_fig16_nn", "claim_fig16_coulomb", "claim_fig16_none",
           "FIGURE"]


@dataclass(frozen=True, eq=False, kw_only=True)
class Fig16Result(LinkFigure):
    """Fig. 16: aged actuator with link, PD (0.4 s, 0.85): NN x 0.95, Coulomb, none.

    Attributes
    ----------
    runs : ``{"none", "NN x 0.95", "Coulomb"}`` -> run
    design : the PD design with the link
    step : reference step [rad]
    friction_scale : true friction of the aged actuator / nominal [-] (assumption)
    scale : compensation scale s of the NN and Coulomb runs [-]
    steady_state_error : per run, mean r - q over the last 0.5 s [rad]
    reference_crossings : per run, sign changes of r - q after the step [-]
    torque_sign_changes : per run, sign changes of Tm over the last 0.5 s [-]
    wind_up : runaway check of the NN run
    coast : the network's coast test
    """

    step: float
    friction_scale: float
    steady_state_error: dict
    reference_crossings: dict
    torque_sign_changes: dict
    scale: float = AGED_SCALE
    """Compensation scale s of the NN and Coulomb runs [-]."""


def run(network: PaperNetwork, *, step_deg: float = 30.0, duration: float = 3.0,
        friction_scale: float = AGED_SCALE, scale: float = AGED_SCALE) -> Fig16Result:
    """Aged actuator with link: NN x 0.95 (no retraining) vs Coulomb vs none (Fig. 16)."""
    net = check_network(network)
    step_rad = float(np.deg2rad(step_deg))
    lr = link_runs(net, "fig16-17", ctl.step(step_rad), duration, friction_scale, scale)
    runs = lr.runs
    tol = net.params.encoder_resolution
    return Fig16Result(
        runs=runs, design=lr.design, step=step_rad, friction_scale=friction_scale,
        steady_state_error={k: r.steady_state_error(SS_WINDOW) for k, r in runs.items()},
        reference_crossings={k: sign_changes(r.error[r.t > 0], tol=tol) for k, r in runs.items()},
        torque_sign_changes={k: sign_changes(r.torque_motor[last_window(r)]) for k, r in runs.items()},
        wind_up=wind_up(runs[f"NN x {scale:g}"]), coast=coast_test.run(net), scale=scale)


def _oscillates(r: Fig16Result, key: str) -> bool:
    return r.reference_crossings[key] >= 2 or r.torque_sign_changes[key] >= 10


def claim_fig16_nn(r: Fig16Result, params=None) -> Claim:
    k = r.nn_key
    e, e0 = abs(r.steady_state_error[k]), abs(r.steady_state_error["none"])
    ok = deg(e) < ACCURACY_DEG and r.torque_sign_changes[k] < 10
    return gate(Claim(
        id="fig16-nn", claim="Aged actuator (friction x 0.95, assumed) with link: NN compensation scaled to "
        "0.95 works without retraining (here: |e_ss| < 0.3 deg and no chatter: < 10 sign changes of Tm "
        "in the last 0.5 s)", paper="works",
        measured=f"|e_ss| {deg(e):.3f} deg ({e0 / e if e > 0 else math.inf:.0f}x smaller than without), "
        f"{r.torque_sign_changes[k]} Tm sign changes", passed=ok, figure="Fig. 16", value=deg(e), unit="deg",
        note="" if ok else "The loop is stable and the error much smaller than without, but it stops in the "
        "residual dead band +-DZ/Kp, as in Fig. 14; with s = 0.95 the stuck loop's gain is s*g instead of g "
        "(see 'why' below)."), (r.wind_up, r.coast.decay))


def describing_function_note(r: Fig16Result, bench=None) -> str:
    """What a describing function (:func:`fricctl.design.coulomb_limit_cycle`) predicts on the
    figure's sampled PD loop: at the run's Coulomb level, and at the breakaway level the paper
    compensated with (both times s), against the aged bench's friction."""
    from ..design import LinearLoop, coulomb_limit_cycle
    from .benches import as_bench

    p = as_bench(bench).actuator
    s = r.scale
    loop = LinearLoop.of(r.design)
    fc, fs = r.friction_scale * p.coulomb, r.friction_scale * p.static
    parts = []
    for what, level in (("at this run's level", s * p.coulomb), ("at the breakaway level the paper "
                                                                  "compensated with", s * p.static)):
        cyc = coulomb_limit_cycle(loop, compensation=level, coulomb=fc, static=fs)
        if cyc is None:
            against = ("exactly the Coulomb friction it cancels: no relay is left"
                       if math.isclose(level, fc, rel_tol=1e-9) else
                       f"below the Coulomb friction {fc:.3f} N*m: friction is left")
            parts.append(f"{what} ({level:.3f} N*m, {against}) it predicts no cycle")
        else:
            parts.append(f"{what} ({level:.3f} N*m) a cycle of {deg(cyc.amplitude):.2f} deg at "
                         f"{cyc.frequency:.2f} Hz, whose pull Kp*A = {cyc.pull:.3f} N*m "
                         + ("exceeds" if cyc.sustained else "stays below")
                         + f" the breakaway level {fs:.3f} N*m"
                         + ("" if cyc.sustained else ": the joint sticks at its first turning point"))
    return " A describing function on this loop (fricctl.design.coulomb_limit_cycle): " + "; ".join(parts) + "."


def claim_fig16_coulomb(r: Fig16Result, bench=None) -> Claim:
    k = "Coulomb"
    ok = _oscillates(r, k)
    ec, en = abs(r.steady_state_error[k]), abs(r.steady_state_error[r.nn_key])
    closer = (f" Against the paper, Coulomb compensation here also ends closer to the reference "
              f"({deg(ec):.3f} deg) than {r.nn_key} ({deg(en):.3f} deg)." if ec < en else "")
    return Claim(
        id="fig16-coulomb", claim="Coulomb compensation oscillates around the reference or chatters (here: "
        "the error changes sign >= 2 times, or Tm changes sign >= 10 times in the last 0.5 s)",
        paper="oscillates / chatters",
        measured=f"{r.reference_crossings[k]} reference crossings, {r.torque_sign_changes[k]} Tm sign "
        f"changes; e_ss {deg(r.steady_state_error[k]):.3f} deg", passed=ok, figure="Fig. 16",
        value=r.reference_crossings[k], unit="reference crossings",
        note="" if ok else "Fc*sign(omega_hat) is zero while the encoder reads no motion, so once the joint "
        "sticks the compensation vanishes and nothing drives a limit cycle: the joint overshoots (the "
        "braking Coulomb term is cancelled while moving) and stays stuck. Chatter needs a velocity "
        "estimate that is noisy at rest (noise, a finer encoder, a different estimator)."
        + describing_function_note(r, bench) + closer)


def claim_fig16_none(r: Fig16Result, params=None) -> Claim:
    e = abs(r.steady_state_error["none"])
    ok = deg(e) >= ACCURACY_DEG
    return Claim(
        id="fig16-none", claim="Without compensation a steady-state error remains (here: |e_ss| >= 0.3 deg)",
        paper="error remains", measured=f"|e_ss| {deg(e):.2f} deg", passed=ok, figure="Fig. 16",
        value=deg(e), unit="deg",
        note="The joint sticks inside the dead band +-Fs/Kp." if ok else "the joint reached the reference")


FIGURE = PaperFigure(
    number=16, title="aged actuator with link: NN x 0.95, Coulomb and no compensation", run=run,
    result_type=Fig16Result, claims=(claim_fig16_nn, claim_fig16_coulomb, claim_fig16_none),
    assumptions=("step of 30 deg",
                 "the aged actuator is the bench's true friction x 0.95 (the paper lowers the "
                 "compensation scale to s = 0.95 after 30 h of wear without retraining)",
                 "the Coulomb compensator is the nominal Coulomb level with the same s = 0.95"))
