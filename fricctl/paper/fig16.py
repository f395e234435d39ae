"""Fig. 16: the aged actuator with the link: NN x 0.95 (not retrained), Coulomb, none.

The paper's Coulomb compensation is run at two levels, both identified on the bench's records
(:class:`~fricctl.paper.common.CoulombLevels`) and scaled by s like the network: at the dry
friction identified experimentally (the breakaway level of the dead-zone experiment), where the
paper saw the joint oscillate, and at a smaller level (the Coulomb level of a least-squares fit
on the sliding patterns), where the oscillation disappeared.  Each is a claim, with the limit
cycle measured over the run's last second against a describing function's prediction
(:func:`fricctl.design.coulomb_limit_cycle`).

A limit cycle is not a runaway: the runaway checks (:mod:`fricctl.paper.runaway`) ask whether the
compensated joint follows its control torque (``|Tm| <= |Tc| + Fs + b|omega|``); a Coulomb
compensation no larger than the breakaway level meets that bound whether or not the joint
oscillates, and the Coulomb claims require it (:func:`~fricctl.paper.runaway.wind_up` of their
run) so that neither can pass by a runaway.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import controllers as ctl
from . import coast as coast_test
from .claims import Claim, gate
from .common import (ACCURACY_DEG, AGED_SCALE, COULOMB_AT_FC, COULOMB_AT_FS, SS_WINDOW, LinkFigure,
                     deg, last_window, link_runs, oscillation, sign_changes)
from .network import PaperNetwork, check_network
from .registry import PaperFigure
from .runaway import MOTION_COUNTS, wind_up

__all__ = ["Fig16Result", "run", "claim_fig16_nn", "claim_fig16_coulomb_fs", "claim_fig16_coulomb_fc",
           "claim_fig16_none", "FIGURE"]

#: The two Coulomb runs, in claim order.
COULOMB_RUNS = (COULOMB_AT_FS, COULOMB_AT_FC)


@dataclass(frozen=True, eq=False, kw_only=True)
class Fig16Result(LinkFigure):
    """Fig. 16: aged actuator with link, PD (0.4 s, 0.85): NN x 0.95, Coulomb at two levels, none.

    Attributes
    ----------
    runs : ``{"none", "NN x 0.95", "Coulomb at Fs", "Coulomb at Fc"}`` -> run
    design : the PD design with the link
    coulomb_levels : the identified levels of the Coulomb runs (before the scale s)
    step : reference step [rad]
    friction_scale : true friction of the aged actuator / nominal [-] (assumption)
    scale : compensation scale s of the NN and Coulomb runs [-]
    steady_state_error : per run, mean r - q over the last 0.5 s [rad]
    reference_crossings : per run, sign changes of r - q after the step [-]
    torque_sign_changes : per run, sign changes of Tm over the last 0.5 s [-]
    cycles : per Coulomb run, its oscillation over the last second (:class:`~fricctl.paper.common.Oscillation`)
    predicted : per Coulomb run, the describing function's limit cycle on the sampled PD loop
        against the aged bench's true friction (``None``: none predicted)
    coulomb_wind_up : per Coulomb run, its runaway check (a limit cycle passes it)
    wind_up : runaway check of the NN run
    coast : the network's coast test
    """

    step: float
    friction_scale: float
    steady_state_error: dict
    reference_crossings: dict
    torque_sign_changes: dict
    cycles: dict
    predicted: dict
    coulomb_wind_up: dict
    scale: float = AGED_SCALE
    """Compensation scale s of the NN and Coulomb runs [-]."""

    def coulomb_level(self, key: str) -> float:
        """The compensated level of Coulomb run ``key``: s times its identified level [N*m]."""
        return self.scale * self.coulomb_levels.level(key)


def _predict(design, params, level: float, friction_scale: float):
    from ..design import LinearLoop, coulomb_limit_cycle

    return coulomb_limit_cycle(LinearLoop.of(design), compensation=level,
                               coulomb=friction_scale * params.coulomb, static=friction_scale * params.static)


def run(network: PaperNetwork, *, step_deg: float = 30.0, duration: float = 3.0,
        friction_scale: float = AGED_SCALE, scale: float = AGED_SCALE) -> Fig16Result:
    """Aged actuator with link: NN x 0.95 (no retraining) vs Coulomb at two levels vs none (Fig. 16)."""
    net = check_network(network)
    step_rad = float(np.deg2rad(step_deg))
    lr = link_runs(net, "fig16-17", ctl.step(step_rad), duration, friction_scale, scale)
    runs = lr.runs
    tol = net.params.encoder_resolution
    levels = lr.coulomb_levels
    return Fig16Result(
        runs=runs, design=lr.design, coulomb_levels=levels, step=step_rad, friction_scale=friction_scale,
        steady_state_error={k: r.steady_state_error(SS_WINDOW) for k, r in runs.items()},
        reference_crossings={k: sign_changes(r.error[r.t > 0], tol=tol) for k, r in runs.items()},
        torque_sign_changes={k: sign_changes(r.torque_motor[last_window(r)]) for k, r in runs.items()},
        cycles={k: oscillation(runs[k]) for k in COULOMB_RUNS},
        predicted={k: _predict(lr.design, net.params, scale * levels.level(k), friction_scale)
                   for k in COULOMB_RUNS},
        coulomb_wind_up={k: wind_up(runs[k]) for k in COULOMB_RUNS},
        wind_up=wind_up(runs[f"NN x {scale:g}"]), coast=coast_test.run(net), scale=scale)


def _oscillates(r: Fig16Result, key: str) -> bool:
    """The joint oscillates (a Coulomb run): it crosses the reference twice after the step, or its
    encoder still moves more than :data:`~fricctl.paper.runaway.MOTION_COUNTS` counts over the last
    second.  Judged on the position, not on the torque: with a velocity estimate that flickers at
    rest, ``Fc*sign(omega_hat)`` makes Tm change sign at any level while the joint stays within the
    flicker's count or two -- the paper's oscillation that disappears is the joint's."""
    return r.reference_crossings[key] >= 2 or r.cycles[key].counts > MOTION_COUNTS


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


def _prediction_text(r: Fig16Result, key: str) -> str:
    """The describing function's prediction for Coulomb run ``key``, one clause."""
    cyc = r.predicted[key]
    level = r.coulomb_level(key)
    if cyc is None:
        return (f"the describing function predicts no cycle ({level:.4f} N*m does not exceed the aged "
                "Coulomb friction: no pushing relay is left)")
    return (f"the describing function predicts {deg(cyc.amplitude):.3f} deg at {cyc.frequency:.2f} Hz "
            f"(relay {cyc.relay:+.4f} N*m), whose pull Kp*A = {cyc.pull:.4f} N*m "
            + ("exceeds" if cyc.sustained else "stays below") + f" the aged breakaway level "
            f"{cyc.static:.3f} N*m" + ("" if cyc.sustained else ": the joint sticks at its first turning point"))


def _measured(r: Fig16Result, key: str) -> str:
    cyc = r.cycles[key]
    return (f"{r.reference_crossings[key]} reference crossings, e_ss {deg(r.steady_state_error[key]):.3f} deg; "
            f"last {cyc.window:g} s: "
            + (f"cycle of {deg(cyc.amplitude):.3f} deg at {cyc.frequency:.2f} Hz" if cyc.sustained else
               f"no cycle ({cyc.counts} counts peak to peak)")
            + f", {r.torque_sign_changes[key]} Tm sign changes in the last 0.5 s (reported, not judged)"
            + "; " + _prediction_text(r, key))


def _flicker(r: Fig16Result, key: str, bench) -> str:
    """Whether one flicker of ``omega_hat`` at rest, toward the reference, would break the stuck joint
    of Coulomb run ``key`` loose: the compensation plus the loop's pull ``Kp*|e_ss|`` against the
    aged breakaway torque."""
    from .benches import as_bench

    aged_fs = r.friction_scale * as_bench(bench).actuator.static
    push = r.coulomb_level(key) + r.design.kp * abs(r.steady_state_error[key])
    return (f"a flicker toward the reference where it stopped would add the compensation to the loop's "
            f"pull, {r.coulomb_level(key):.4f} + Kp*|e_ss| = {push:.4f} N*m, "
            + ("above" if push > aged_fs else "below") + f" the aged breakaway torque {aged_fs:.4f} N*m"
            + (": the joint would break loose again" if push > aged_fs else ": it would stay stuck"))


#: What no seed changes on a noise-free bench (the note of both Coulomb claims).
_SAME_EVERY_SEED = (" The same in every seed: both levels come from the bench's noise-free records (the "
                    "dead-zone experiment; the pipeline's patterns, fitted whole) and the runs do not "
                    "involve the network, so the seed changes nothing here.")


def _seeds_note(bench) -> str:
    """What the seed changes in a Coulomb claim: nothing on a noise-free bench; the sensing noise of
    its runs otherwise (the levels stay those of the clean records)."""
    from .benches import RANDOM_PHASE, as_bench

    s = as_bench(bench).sensing
    random = s.torque_ripple > 0.0 and s.torque_ripple_phase == RANDOM_PHASE
    ripple = ("" if s.torque_ripple == 0.0 else
              f" Every run's plant receives the bench's torque ripple ({s.torque_ripple:.3g} N*m, period "
              f"{s.torque_ripple_period:.4g} rad), " + ("its phase drawn for each run from the seed." if random
                                                       else "the same in every seed."))
    if s.noise_free and not random:
        return _SAME_EVERY_SEED + ripple
    drawn = ("the ripple's phase" if s.noise_free else
             f"the bench's sensing noise (encoder edge jitter {s.encoder_jitter:g} counts, torque noise "
             f"{s.torque_noise:.3g} N*m)")
    return (f" The levels are the same in every seed (identified on the bench's noise-free records); the "
            f"runs are not: each seed draws {drawn}.{ripple}")


def _jitter_clause(bench) -> str:
    from .benches import as_bench

    s = as_bench(bench).sensing
    return ("encoder edge jitter, which this bench leaves out" if s.encoder_jitter == 0.0 else
            f"this bench's edge jitter of {s.encoder_jitter:g} counts did not make it flicker enough here")


def claim_fig16_coulomb_fs(r: Fig16Result, bench=None) -> Claim:
    k = COULOMB_AT_FS
    lv = r.coulomb_levels
    ok = _oscillates(r, k)
    ec, en = abs(r.steady_state_error[k]), abs(r.steady_state_error[r.nn_key])
    closer = (f" Against the paper, this Coulomb compensation also ends closer to the reference "
              f"({deg(ec):.3f} deg) than {r.nn_key} ({deg(en):.3f} deg)." if ec < en else "")
    why = ("" if ok else "Fc*sign(omega_hat) is zero while the encoder reads no motion, so once the joint "
           "sticks the compensation vanishes and nothing drives a limit cycle: the joint overshoots (the "
           "compensation pushes along the motion while it slides) and stays stuck at its first turning "
           "point. A cycle needs a velocity estimate that flickers at rest (" + _jitter_clause(bench)
           + "): " + _flicker(r, k, bench) + ".")
    return gate(Claim(
        id="fig16-coulomb-fs", claim="Coulomb compensation at the dry friction identified experimentally "
        "(the breakaway level of the dead-zone experiment, x s = 0.95) makes the joint oscillate (here: the "
        f"error changes sign >= 2 times after the step, or the encoder moves > {MOTION_COUNTS} counts peak to "
        "peak over the last 1 s; judged on the position, not on Tm's sign changes, which a velocity estimate "
        "flickering at rest makes at any level)", paper="oscillates",
        measured=f"level {r.coulomb_level(k):.4f} N*m (s x {lv.breakaway:.4f}, the breakaway read off the "
        f"dead-zone experiment to +-{lv.breakaway_step:.4f} N*m); " + _measured(r, k), passed=ok,
        figure="Fig. 16", value=r.reference_crossings[k], unit="reference crossings",
        note=why + closer + _seeds_note(bench)), (r.coulomb_wind_up[k],))


def claim_fig16_coulomb_fc(r: Fig16Result, bench=None) -> Claim:
    k = COULOMB_AT_FC
    lv = r.coulomb_levels
    # "disappears": the breakaway level must oscillate and this one not; a joint still at both
    # levels reproduces nothing (a claim that cannot fail is not a reproduction)
    at_fs = _oscillates(r, COULOMB_AT_FS)
    ok = at_fs and not _oscillates(r, k)
    trivial = ("Not reproduced: nothing to disappear on this bench -- the breakaway level does not "
               "oscillate (fig16-coulomb-fs) and neither does this one. With a velocity estimate that "
               "flickers at rest, " + _flicker(r, k, bench) + "." if not at_fs else "")
    return gate(Claim(
        id="fig16-coulomb-fc", claim="At a smaller Coulomb level the oscillation disappears (here: the level "
        "a least-squares fit of Fc*sign(omega) + b*omega gives on the pipeline's sliding friction patterns, "
        "x s = 0.95; no oscillation by the criterion of fig16-coulomb-fs, where the breakaway level oscillates)", paper="no oscillation",
        measured=f"level {r.coulomb_level(k):.4f} N*m (s x {lv.coulomb:.4f}, fitted on {lv.patterns} sliding "
        f"patterns, b {lv.viscous:.4f} N*m*s/rad); " + _measured(r, k), passed=ok, figure="Fig. 16",
        value=r.reference_crossings[k], unit="reference crossings",
        note=(trivial or ("" if ok else "the joint oscillates at the smaller level too.")) + _seeds_note(bench)),
        (r.coulomb_wind_up[k],))


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
    result_type=Fig16Result,
    claims=(claim_fig16_nn, claim_fig16_coulomb_fs, claim_fig16_coulomb_fc, claim_fig16_none),
    assumptions=("step of 30 deg",
                 "the aged actuator is the bench's true friction x 0.95 (the paper lowers the "
                 "compensation scale to s = 0.95 after 30 h of wear without retraining)",
                 "the Coulomb compensator at the breakaway level the dead-zone experiment reads and at "
                 "the Coulomb level a least-squares fit on the sliding patterns gives, both with the "
                 "same s = 0.95"))
