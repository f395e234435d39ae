"""What the record supports below the naming line (issue 21, item 4).

The forward selection (:mod:`.selection`) stops when no candidate removes
:data:`~fricctl.diagnose.selection.MIN_SCORE` of what is left: a line for *naming* a cause
(an effect that matters, a 10 % drop of the held-out RMS), not for what the data show.  This
module reports the candidates of that last step that lower the held-out residual -- and,
once a supported one is taken into the model below the line, those of the next round (see
*Supported* below) -- each with:

* its held-out share, gross and net of the measuring chain's share (the chain's share
  measured on the record's effect-free twin, :mod:`.twin`, as for a named cause);
* a stated statistical test, the verdict's (:func:`~fricctl.diagnose.verdict.reduction_p`):
  the one-sided variance-ratio F test of the held-out mean squares before and after the
  term, ``1/(1 - s)`` for a share ``s``, each with the effective degrees of freedom of its
  own residual -- the model as it stands, and the model with the term fitted on all data --
  counted as the verdict counts them (samples over the integrated correlation time,
  :func:`~fricctl.diagnose.verdict.effective_dof`; taking a term out can lengthen the
  residual's correlation and so lower the count after it), at the verdict's level
  :data:`~fricctl.diagnose.verdict.SIGNIFICANCE`; first on the gross share (a term that
  fails it is not asked for the chain's share: its net share can only be smaller), then on
  the net share.  The test treats the two residuals as independent, which those of nested
  models on the same samples are not: it is conservative, chosen so that a reduction counts
  only when it stands out from the scatter of the residual's own mean square (a partial F
  test with these degrees of freedom called a 0.1 % reduction significant on a 40 s,
  1 kHz record, where the chain's share itself is measured only to that order);
* its term fitted on all data after the causes named: the physical parameters the cause's
  own extension sets (:attr:`~fricctl.diagnose.causes.Cause.changes`: a ripple's period and
  amplitude, the bristles' stiffness and damping ...) and its evidence clause;
* whether the record can tell it (the checks a named cause passes: not collinear with the
  model's columns, and the cause's own ``identifiable``: a ripple period the record
  resolves, a presliding length inside the range searched ...);
* for a term that passes the test and those checks, its held-out simulation score (the
  windowed re-simulation of each block with the model fitted without it, as a step's), which
  must not be worse (as for a named cause), and the generic alternatives a named cause must
  beat (a sensor's scale error with a nominal model, a friction-speed curve of another shape):
  where one removes more, what the term adds on top of it must pass the test.

*Supported* means: the net reduction passes the F test and the term passes every check.
Below the line the selection goes on as above it: the best supported candidate is taken
into the model and the rest are scored again on what it leaves, until none is supported, so
that candidates competing for one part of the residual are not all called supported.
Nothing is decided by a magnitude.  The test is run once per candidate and round at
p < 0.01, with no correction for the several candidates tried; below about 490 effective
degrees of freedom (before and after alike) no share under the naming line can pass it.  A period in position is also given in motor revolutions
when the travel of one revolution is known (:attr:`BelowLine.motor_revolutions`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from .causes import Term
from .crossval import full_fit
from .selection import (CHAIN_UNMEASURED, MIN_SCORE, Selection, _name, _parts, _residual, _score,
                        _Told, _why_not_told, net_of_chain, rival_on_top, sensor_scales,
                        simulation_score, speed_curve, term_trial)
from .verdict import SIGNIFICANCE, effective_dof, reduction_p

__all__ = ["BelowLine", "below_line", "TEST", "PERIOD_PARAMETERS"]

#: The test, in words (for the report).
TEST = ("verdict's one-sided variance-ratio F test of the held-out mean squares before and after "
        "the term, each with the effective degrees of freedom of its own residual (the model as "
        "it stands, and with the term fitted on all data: samples over the residual's "
        "correlation time)")

#: Fitted parameters that are a period in position: compared with one motor revolution
#: when the record's transmission is known.
PERIOD_PARAMETERS = ("ripple_period",)


@dataclass(frozen=True, kw_only=True)
class BelowLine:
    """A candidate below the naming line, with what the record says of it: one taken in a
    round below the line, or one of the last round (:func:`below_line`)."""

    cause: str
    """The candidate."""
    score: float
    """Net held-out share of the remaining torque residual (sum of squares) its term removes:
    :attr:`gross` net of :attr:`chain` (:func:`~fricctl.diagnose.selection.net_of_chain`);
    :attr:`gross` itself where the chain's share is not measured (the gross share fails the
    test already) [-]."""
    gross: float
    """The held-out share before the measuring chain's is taken off [-]."""
    chain: float
    """The measuring chain's share (the same term on the record's effect-free twin) [-]; NaN
    where not measured (the gross share fails the test already)."""
    p_value: float
    """p-value of the verdict's F test of the net reduction (of the gross one where the net
    is not measured) [-]."""
    dof: float
    """Effective degrees of freedom of the mean square before the term [-]."""
    dof_after: float
    """Effective degrees of freedom of the mean square after it (the residual with the term
    fitted on all data; :attr:`dof` where no term could be fitted or the count is not a
    positive number) [-]."""
    supported: bool
    """The net reduction passes the test at :data:`~fricctl.diagnose.verdict.SIGNIFICANCE`,
    the term can be told on this record (:attr:`plausible`), its model re-simulates the
    held-out windows no worse, and no generic rival leaves it nothing the test can tell."""
    plausible: bool | None
    """The term fitted on all data passes the checks a named cause passes before it is
    tried (:func:`~fricctl.diagnose.selection._why_not_told`; False where no variant fits),
    checked also where the test fails first (its fitted numbers are printed); None where its
    net share could not be measured."""
    reason: str = ""
    """Why it is not supported (the test, or the check it fails), or ``""``."""
    parameters: dict = field(default_factory=dict)
    """The model parameters its fitted term sets (``{name: value}``, the model's units)."""
    evidence: str = ""
    """The cause's own evidence clause for the fitted term, or ``""``."""
    simulation_score: float = math.nan
    """Held-out share of the windowed simulation error (position, sum of squares) the term
    removes [-]; NaN where not computed (the test or the checks before it fail) or where
    the windows cannot be re-simulated."""
    motor_revolutions: dict = field(default_factory=dict)
    """Per fitted period in position (:data:`PERIOD_PARAMETERS`): the period in motor
    revolutions [-]; empty where the travel of one revolution is not known."""

    def as_dict(self) -> dict:
        """The entry's JSON object."""
        return {"cause": self.cause, "score": self.score, "gross": self.gross,
                "chain": self.chain, "p_value": self.p_value, "dof": self.dof,
                "dof_after": self.dof_after,
                "supported": self.supported, "plausible": self.plausible,
                "reason": self.reason or None, "parameters": dict(self.parameters),
                "evidence": self.evidence or None, "simulation_score": self.simulation_score,
                "motor_revolutions": dict(self.motor_revolutions)}

    def sentence(self, torque_unit: str = "N*m", position_unit: str = "rad") -> str:
        """One line for the report: the shares, the test, the parameters (a period also in
        motor revolutions, the revolution read back from the two)."""
        if math.isfinite(self.chain):
            share = (f"{100 * self.score:.1f} % of what is left, net (gross "
                     f"{100 * self.gross:.1f} %, the measuring chain's {100 * self.chain:.1f} %)")
        else:
            share = (f"{100 * self.gross:.1f} % of what is left, gross (the measuring chain's "
                     f"share not measured)")
        test = (f"F test p = {self.p_value:.2g} ({self.dof:.0f} and {self.dof_after:.0f} effective "
                f"degrees of freedom, before and after)" if math.isfinite(self.p_value) else
                "no F test (no net share)")
        out = f"`{self.cause}`: removes {share}; {test}"
        if self.score >= MIN_SCORE:
            out += (" (at the naming line only once the entries taken below it are in the model, "
                    "which the selection does not do: reported, not named)")
        if self.evidence:
            out += f"; {self.evidence}"
        for name, turns in self.motor_revolutions.items():
            period = self.parameters[name]
            out += (f"; period {_length(period, position_unit)} = {turns:#.3g} motor revolutions "
                    f"(one revolution: {_length(period / turns, position_unit)})")
        if math.isfinite(self.simulation_score):
            out += (f"; held out, the re-simulation error (position, sum of squares) changes by "
                    f"{-100 * self.simulation_score:+.1f} %")
        if self.reason:
            out += f"; not supported: {self.reason}"
        return out + "."


def _length(x: float, unit: str) -> str:
    """A length in mm for a linear axis (its unit is m), else in the record's unit."""
    return f"{1e3 * x:.4g} mm" if unit == "m" else f"{x:.4g} {unit}"


def below_line(problem, sel: Selection, chain: Callable, simulate: Callable, *,
               motor_revolution: float | None = None) -> tuple:
    """The candidates below the naming line whose held-out share is positive, as
    :class:`BelowLine` entries: the supported ones in the order a forward selection below the
    line takes them, then the last round's others by net share (module notes).

    Below the line the selection goes on as above it: the best supported candidate is taken
    into the model and the others are scored again after it, until none is supported.  Each
    supported entry's shares are of what the entries before it leave; the unsupported ones
    are those of the last round (candidates that compete for one part of the residual are
    not all supported: once the best is in, the others are tested on what it leaves).

    Parameters
    ----------
    problem : Problem
        The record's normal equations.
    sel : Selection
        The forward selection (its :attr:`~Selection.final` state and
        :attr:`~Selection.last_scored`).
    chain : callable
        ``chain(floor, named, model)``, as :func:`~fricctl.diagnose.selection.forward_selection`
        takes it.
    simulate : callable
        ``simulate(fold_models)``: the held-out windowed simulation.
    motor_revolution : float, optional
        Travel of one motor revolution, in the record's position unit [rad] or [m].
    """
    state, scored = sel.final, sel.last_scored
    if state is None or not scored:
        return ()
    skip = set(sel.not_identifiable)
    taken = []
    while True:
        sse_prev = float(np.sum(state.test))
        if not sse_prev > 0:
            return tuple(taken)
        dof = effective_dof(state.base.current_residual[problem.sig.moving])
        tried = [_entry(problem, state, s, sse_prev, dof, chain, simulate, motor_revolution)
                 for name, s in scored.items() if name not in skip]
        entries = [t for t in tried if t is not None]
        best = max((t for t in entries if t.line.supported), key=lambda t: t.line.score,
                   default=None)
        if best is not None:  # a supported term has re-simulated no worse: _name takes it
            moved, _ = _name(problem, state, (_Told(cause=best.cause, fit=best.fit),), scored,
                             (), sse_prev, simulate, made={best.cause.name: best.trial})
        if best is None or len(moved.steps) == len(state.steps):
            # best share first, those with no net share (NaN: the twin ran away) last
            return tuple(taken) + tuple(sorted(
                (t.line for t in entries),
                key=lambda e: -e.score if math.isfinite(e.score) else math.inf))
        taken.append(best.line)
        state = moved
        if not state.remaining:
            return tuple(taken)
        scored = _score(problem, state, chain, float(np.sum(state.test)), None)


@dataclass(frozen=True, kw_only=True, eq=False)
class _Tried:
    """A candidate of a round below the line: its entry, its term fitted on all data (None
    where no variant fits) and its held-out trial (None where not simulated)."""

    line: BelowLine
    cause: object
    fit: object = None
    trial: object = None


def _entry(problem, state, s, sse_prev: float, dof: float, chain: Callable, simulate: Callable,
           motor_revolution: float | None):
    """:class:`_Tried` of the scored candidate ``s`` on the model as it stands, whose
    residual has ``dof`` effective degrees of freedom, or None: it does not lower the
    held-out residual (gross, or net of the measuring chain's share).  A candidate that
    reached the line in the selection's last step was set aside there (not told) and is not
    passed here; one that reaches it in a later round below the line is reported as it is."""
    name = s.cause.name
    if not s.gross > 0:
        return None
    sig = problem.sig
    fixed = tuple(x.variant for x in state.selected)
    fit = full_fit(problem, state.base.variants(s.cause, None), fixed)
    after = dof
    entry = dict(cause=name, gross=s.gross, dof=dof)
    if fit is not None:
        after = effective_dof(_residual(problem, fixed + (fit.variant,), fit.theta)[sig.moving])
        after = after if math.isfinite(after) and after > 0 else dof
        coef = fit.theta[fit.theta.size - s.cause.n_extra:]
        term = Term(h=fit.variant.h, coef=coef)
        extended = state.base.model(_parts(state.selected) + [(s.cause, fit.variant.h)], fit.theta)
        values = extended.parameters()
        entry["parameters"] = {c: float(values[c]) for c in s.cause.changes if c in values}
        entry["evidence"] = s.cause.evidence(state.base, term, extended)
        if motor_revolution is not None:
            entry["motor_revolutions"] = {c: entry["parameters"][c] / motor_revolution
                                          for c in PERIOD_PARAMETERS if c in entry["parameters"]}
    entry["dof_after"] = after
    if s.gross >= MIN_SCORE:  # the selection measured the chain's share (at the line)
        share = s.chain
    else:
        p = reduction_p(s.gross, dof, after)
        if not p < SIGNIFICANCE:  # the net share can only be smaller: the chain is not asked
            # its fitted numbers are printed: checked as a named cause's are (audit B: a hump
            # fitted on its tail, 11476 % of the Coulomb level, was printed unflagged)
            why = _why_not_told(problem, state, s.cause, fit, fixed)
            return _Tried(line=BelowLine(**entry, score=s.gross, chain=math.nan, p_value=p,
                                         supported=False, plausible=why is None,
                                         reason=_not_significant(p) + (
                                             "" if why is None else
                                             f"; and the record cannot tell it: {why}")),
                          cause=s.cause, fit=fit)
        named = tuple(x.cause for x in state.selected)
        share = chain(sse_prev * (1.0 - s.gross), named, state.model)(s.cause)
        if math.isfinite(share):
            share = max(share, 0.0)
    if not math.isfinite(share):  # the twin ran away: no net share, said so
        return _Tried(line=BelowLine(**entry, score=math.nan, chain=math.nan, p_value=math.nan,
                                     supported=False, plausible=None, reason=CHAIN_UNMEASURED),
                      cause=s.cause, fit=fit)
    net = net_of_chain(s.gross, share)
    if not net > 0:
        return None  # the measuring chain alone removes as much: nothing of the record's
    p = reduction_p(net, dof, after)
    why = _why_not_told(problem, state, s.cause, fit, fixed)
    entry.update(score=net, chain=share, p_value=p, plausible=why is None)
    reasons, tried = [], None
    if not p < SIGNIFICANCE:
        reasons.append(_not_significant(p) + " once the measuring chain's share is taken off")
    if why is not None:
        reasons.append(f"the record cannot tell it: {why}")
    if not reasons:  # the checks a named cause passes next: the re-simulation, the rivals
        tried = term_trial(problem, state, s.cause, s.cv, simulate)
        entry["simulation_score"] = sim = simulation_score(state, tried)
        if math.isfinite(sim) and sim <= 0.0:
            reasons.append(f"its extended model re-simulates the held-out windows worse "
                           f"(position error, sum of squares, {-100 * sim:+.1f} %)")
        else:
            rival = _rival(problem, state, s, sse_prev, dof, after)
            if rival is not None:
                reasons.append(rival)
    entry["supported"] = not reasons
    entry["reason"] = "; ".join(reasons)
    return _Tried(line=BelowLine(**entry), cause=s.cause, fit=fit, trial=tried)


def _rival(problem, state, s, sse_prev: float, dof: float, after: float) -> str | None:
    """Why a generic alternative a named cause must beat (a sensor's scale error with a
    nominal model; a friction-speed curve of another shape, for a cause that is not itself a
    friction curve) explains the record better and leaves the term nothing the test can
    tell on top of it, or None.  As :func:`~fricctl.diagnose.selection._scale_matches`
    (:func:`~fricctl.diagnose.selection.rival_on_top`), with the test instead of the naming
    line for what the term adds on top; the test's counts
    are those of the term's own (``dof`` before, ``after`` with the term), not re-counted on
    the rival's residuals (an approximation: the rival removes more, so its residual's count
    may differ)."""
    rivals = sensor_scales(problem, state.base, state.selected)
    if not s.cause.friction_curve:
        rivals += (speed_curve(problem, state.base, state.selected),)
    for rv in rivals:
        on_top = rival_on_top(problem, state, s, rv, sse_prev)
        if on_top is None:
            continue
        p = reduction_p(on_top, dof, after)
        if not p < SIGNIFICANCE:
            sse_rival = float(np.sum(rv.test))
            return (f"{rv.what} removes more of the held-out residual "
                    f"({100 * (1 - sse_rival / sse_prev):.0f} % against {100 * s.gross:.0f} %) "
                    f"and the term adds {100 * max(on_top, 0.0):.1f} % on top of it, which the "
                    f"test cannot tell from the scatter (p = {p:.2g})")
    return None


def _not_significant(p: float) -> str:
    return (f"the F test cannot tell the reduction from the residual's scatter (p = {p:.2g} "
            f">= {SIGNIFICANCE:g})")
