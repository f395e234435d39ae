"""Load-dependent friction: friction grows with the transmitted torque |Tm| (mesh friction).

Regressor: ``LP(|T| * sign(w))`` with ``T`` the torque the model *as it stands* needs along
the measured motion (:attr:`~fricctl.diagnose.causes.base.Baseline.current_torque`: the
baseline, with the terms of the causes already named), not the recorded one, and the braking
phases (torque against the motion) read from the recorded torque:
``LP(T) - 2*LP(T*[Tm*sign(w) < 0])``; coefficient ``mu`` in [0, :data:`MAX_LOAD_COEFFICIENT`].
Bench: mu = 0.08 .. 0.20 (friction + mu*|Tm|; harmonic drives lose 10-30 %).

Notes
-----
Why the model's torque: ``|Tm|*sign(w)`` equals ``Tm`` itself whenever the drive pushes the
way it moves, so a column built on the recorded torque "explains" the target -- its noise
included (a closed loop feeds encoder noise into ``Tm``) -- and the fit slides to the bound
with I, b, Fc shrunk.  Built on the model's low-passed torque, the column holds neither
the recorded noise nor the rectified noise of the acceleration estimate, and without
braking phases it is the baseline's own prediction: collinear with the baseline's
columns, which the selection reports as "cannot be told"; with a nominal model it is the
nominal torque, which a scale error of the recorded torque fits as well: the cause's own
identifiability test reports it (:data:`SCALE_SHARE`).

Why the model *as it stands*, made again after each named cause: the simulation applies
``mu*|Tm|`` to the whole recorded torque, the part a named drag, ripple or Stribeck excess
drives included.  A column built on the baseline alone leaves that part out, and the named
term, refitted with the column, takes up ``mu`` times itself (a drag ``c*w*|w|`` comes back as
about ``(1 + mu)*c``): the fit then counts the load on that part twice when it is simulated,
and the extended model re-simulated worse than without the term although the true one
re-simulates far better (issue 21's pairs: load with drag, ripple, thermal drift, compliance,
Stribeck, backlash).

The other order, and the term's own torque: once this cause is named, a drag or ripple named
*after* it changes the torque of the model as it stands, and so does its own term, which the
simulation applies to the whole torque too.  The cause is
:attr:`~fricctl.diagnose.causes.base.Cause.reads_model_torque`: the selection remakes its
column on the model after each step, its own term included, and
refits every coefficient until the column settles (:func:`fricctl.diagnose.crossval.settle`),
and keeps the settled model only where it is no worse held out and re-simulated (a fixed point
is not a least-squares minimum: :func:`fricctl.diagnose.selection.term_trial`).
With the column left as it was named, a drag named after it came back 1.25 times itself on the
test record of ``tests/test_diagnose_load_dependent.py`` (within 0.3 % once settled), and the
coefficient 0.176 where 0.198 settled (0.2 simulated; the drag named first).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ...friction import LoadDependent
from .base import Cause

#: Largest load-dependence mu (friction + mu*|Tm|) a diagnosis will fit [-]: a drive whose
#: mesh friction grows by more than half the torque it transmits would hardly move a load.
MAX_LOAD_COEFFICIENT = 0.5


#: Share of the column's energy (sliding samples) outside the nominal model's own torque below
#: which, with a nominal model, the term cannot be told from a scale of that torque [-] (the
#: selection's collinearity share).
SCALE_SHARE = 1e-3


def _column(base):
    # |T|*sign(w) = T - 2*T*[T*sign(w) < 0]: the (low-passed) prediction of the model as it
    # stands, less twice the model's torque where the recorded torque brakes (opposes the
    # motion) -- so without braking the column is that prediction exactly, and neither the
    # recorded noise nor the model's low-pass ringing at starts and stops enters it.  The
    # baseline's torque is taken sample by sample (its raw columns); what the named causes
    # add to it is known low-passed only, and is smooth (a drag, a ripple, a drift)
    braking = (base.torque * base.sign < 0).astype(float)
    now = base.current_torque
    raw = base.model_torque_raw + (now - base.model_torque)
    return now - 2.0 * base.sig.filt(raw * braking)


def _variants(base, fold):
    yield base.variant(None, _column(base), (1,), upper=(MAX_LOAD_COEFFICIENT,))


def _extend(model, term, base):
    return replace(model, friction=model.friction + LoadDependent(max(term.coef[0], 0.0)))


def _braking(base) -> float:
    """Share of the sliding samples where the recorded torque opposes the motion [-]."""
    m = base.sig.moving
    return float(np.mean(base.torque[m] * base.sign[m] < 0))


def _evidence(base, term, extended):
    m = base.sig.moving
    u = np.abs(base.model_torque[m])
    rr = (base.residual * np.sign(base.sig.w))[m]
    c = float(np.corrcoef(u, rr)[0, 1]) if u.std() > 0 else float("nan")
    return (f"the baseline residual in the direction of motion grows with |Tm| "
            f"(correlation {c:.2f}; the drive brakes on {100 * _braking(base):.0f} % of the "
            f"sliding samples); fitted friction + {extended.friction.load_coefficient:.3g} x |Tm|"
            + (f" (at the coefficient's bound, {MAX_LOAD_COEFFICIENT}: not determined by the "
               f"record)" if term.coef[0] >= 0.999 * MAX_LOAD_COEFFICIENT else ""))


def _outside_model_torque(base) -> float:
    """Share of the column's energy (sliding samples) outside the torque of the model as it
    stands [-]."""
    m = base.sig.moving
    c, t = _column(base)[m], base.current_torque[m]
    cc, tt = float(c @ c), float(t @ t)
    if cc == 0.0 or tt == 0.0:
        return 1.0
    return max(1.0 - float(c @ t) ** 2 / (cc * tt), 0.0)


def _identifiable(base, term):
    if term.coef[0] >= 0.999 * MAX_LOAD_COEFFICIENT:
        return (f"the load coefficient sits at its bound ({MAX_LOAD_COEFFICIENT}): the record does "
                f"not determine it (the drive brakes on {100 * _braking(base):.1f} % of the "
                f"sliding samples)")
    # with a nominal model there are no baseline columns for the selection's collinearity test
    # to see it: without braking the column is the nominal torque itself (with the terms named
    # before it: the torque of the model as it stands), which a scale error of the recorded
    # torque (a sensor gain, a torque constant) fits exactly as well
    if not base.fit_mode and _outside_model_torque(base) < SCALE_SHARE:
        return (f"the drive brakes on {100 * _braking(base):.1f} % of the sliding samples: its "
                f"column is the model's own torque (the nominal one with any term named before "
                f"it; only {100 * _outside_model_torque(base):.2g} % of it lies outside), which a "
                f"scale error of the recorded torque (a sensor gain, a torque constant) fits as "
                f"well")
    return None


def _inject(rng, act):
    mag = dict(coefficient=rng.uniform(0.08, 0.20) * act.strength)
    return act.rigid(magnitude=mag, friction=act.friction() + LoadDependent(mag["coefficient"]))


CAUSE = Cause(
    name="load_dependent", order=30,
    physical="friction grows with the transmitted torque |Tm|",
    changes=("load_coefficient",),
    params=("load_coefficient",), variants=_variants, per_step=True, reads_model_torque=True,
    extend=_extend,
    evidence=_evidence,
    identifiable=_identifiable, inject=_inject)
