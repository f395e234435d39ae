"""The result of a diagnosis: :class:`Diagnosis` (named causes step by step, evidence, models,
held-out gain), its JSON object (:meth:`Diagnosis.as_dict`, finite numbers only: NaN and
infinities become null) and its Markdown report (:meth:`Diagnosis.report`)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .._json import json_safe
from ..plant import JointModel
from ..units import units as unit_labels
from . import causes
from .selection import CHAIN_UNMEASURED, MIN_SCORE, Step
from .verdict import Verdict, _capital
from .windows import WindowedSimulation

if TYPE_CHECKING:
    from ..identify import IdentificationResult
    from .stops import EndStops

__all__ = ["MIN_SCORE", "Gain", "Diagnosis", "evidence_text"]


def _num(x, fmt: str = ".4g", scale: float = 1.0, unit: str = "") -> str:
    """``x`` formatted for a report table, ``n/a`` when it is not a finite number."""
    if x is None or not np.isfinite(x):
        return "n/a"
    return f"{scale * x:{fmt}}" + (f" {unit}" if unit else "")


@dataclass(frozen=True, kw_only=True)
class Gain:
    """Held-out RMS errors before (baseline) and after (extended model)."""

    torque_rms_before: float
    """Equation-error (torque) residual of the baseline [N*m]."""
    torque_rms_after: float
    """Equation-error (torque) residual of the extended model [N*m]."""
    simulation_rms_before: float
    """Windowed re-simulation, position error of the baseline [rad]."""
    simulation_rms_after: float
    """Windowed re-simulation, position error of the extended model [rad]."""
    velocity_rms_before: float
    """Windowed re-simulation, velocity error of the baseline [rad/s]."""
    velocity_rms_after: float
    """Windowed re-simulation, velocity error of the extended model [rad/s]."""

    def as_dict(self) -> dict:
        """The ``gain`` object of ``fricctl diagnose --json`` (key order as it has always been)."""
        return {k: float(getattr(self, k)) for k in (
            "torque_rms_before", "torque_rms_after", "simulation_rms_before",
            "velocity_rms_before", "simulation_rms_after", "velocity_rms_after")}


@dataclass(frozen=True, kw_only=True, eq=False)
class Diagnosis:
    """What :func:`~fricctl.diagnose.diagnose` found.

    Attributes
    ----------
    cause : str
        The first cause named (one of :data:`~fricctl.diagnose.CAUSES`; ``none`` when
        nothing is).
    causes : tuple of str
        Every cause named, in the order the forward selection added them (``("none",)``).
    steps : tuple of Step
        One :class:`~fricctl.diagnose.selection.Step` per named cause: its net score and
        the held-out torque and simulation RMS before and after it.
    ranking : tuple of (str, float)
        The first step's candidates with their net scores, best first: the held-out
        fraction of the baseline's torque residual (sum of squares) each removes, net of
        the measuring chain's share (:func:`~fricctl.diagnose.selection.net_of_chain`) [-];
        NaN for a candidate with no net share (its chain share could not be measured: the
        twin ran away), in the place a net 0 takes.
    evidence : str
        The evidence for the named causes, in words and numbers.
    baseline, extended : JointModel
        The baseline (fitted or nominal) and the model extended with every named term
        (the baseline itself when the cause is ``none``).
    gain : Gain
        Held-out RMS errors before (baseline) and after (all named terms).
    simulation_scores : dict
        First step: per supported candidate, the held-out fraction of the windowed
        simulation error (position, sum of squares) it removes [-].
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
    not_identifiable : dict
        Candidates that reached :data:`MIN_SCORE` but cannot be told apart on this
        record, with the reason ("cannot be told on this record, because ...").
    last_ranking : tuple of (str, float)
        The candidates of the step that named nothing, with their net scores: why the
        selection stopped (none reached :data:`MIN_SCORE`); NaN: no net share, as in
        :attr:`ranking` (the reason in :attr:`not_identifiable`).
    chain_rms : float
        Held-out torque residual RMS the measuring chain alone leaves on the record's
        effect-free twin [N*m].
    cutoff : float
        Low-pass cut-off of the diagnosis: the band the excitation reaches, at most
        half the Nyquist frequency [Hz].
    notes : dict
        Why a number is undefined (NaN), by its path in :meth:`as_dict` or its top-level
        key (e.g. ``"gain"``: a model that cannot be re-simulated on the record).
    verdict : Verdict
        Whether the final model explains the record (its held-out residual against the
        measuring chain's floor) and where the rest lives (:mod:`.verdict`).
    end_stops : EndStops
        The record's end stops (:func:`~fricctl.diagnose.stops.end_stops`): their contacts
        are left out of the equation error, the re-simulation windows, the twin and the
        verdict, and its description says so (None: not looked for).
    held : tuple of str
        The causes whose effect the supplied model held (its offset, asymmetric levels,
        Stribeck excess ...): removed to be judged, ``baseline`` is the supplied model
        without them, and each is in :attr:`causes` only if the record supports it
        (:func:`~fricctl.diagnose.api.judged_by_removal`); empty in fit mode.
    supplied : JointModel or None
        The model as supplied (None in fit mode).
    below_line : tuple of BelowLine
        The candidates below the naming line that lower the held-out residual
        (:func:`~fricctl.diagnose.below.below_line`): the supported ones in the order a
        selection below the line takes them, then the last round's others by net share; each
        with its net share, the F test of the reduction (each mean square with its own
        effective degrees of freedom), its fitted physical parameters, whether the record can
        tell it, and its held-out simulation score where the checks before it pass.
    motor_revolution : float or None
        Travel of one motor revolution [rad] or [m] the periods are compared with (None:
        unknown).
    """

    cause: str
    causes: tuple
    steps: tuple
    ranking: tuple
    evidence: str
    baseline: JointModel
    extended: JointModel
    gain: Gain
    simulation_scores: dict
    fit: "IdentificationResult | None"
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
    not_identifiable: dict
    last_ranking: tuple = ()
    chain_rms: float = float("nan")
    cutoff: float = float("nan")
    notes: dict = None
    verdict: Verdict = None
    end_stops: "EndStops | None" = None
    held: tuple = ()
    supplied: JointModel | None = None
    below_line: tuple = ()
    motor_revolution: float | None = None

    @property
    def origin(self) -> dict:
        """Per named cause: ``"held by the supplied model"`` or ``"found"``."""
        return {c: "held by the supplied model" if c in self.held else "found"
                for c in self.causes if c != causes.NONE}

    @property
    def explained(self) -> bool:
        """The final model explains the record within the measuring chain's floor."""
        return bool(self.verdict is not None and self.verdict.explained)

    @property
    def score(self) -> float:
        """Net score of the first named cause (0 for ``none``) [-]."""
        return self.steps[0].score if self.steps else 0.0

    def as_dict(self) -> dict:
        """The ``fricctl diagnose --json`` object (finite numbers or null; ``undefined``
        gives the reason for every null number, by its path)."""
        out = {
            "explained": self.explained,
            "residual_over_floor": (float("nan") if self.verdict is None
                                    else self.verdict.residual_over_floor),
            "verdict": None if self.verdict is None else self.verdict.as_dict(),
            "cause": self.cause,
            "causes": list(self.causes),
            "steps": [s.as_dict() for s in self.steps],
            "ranking": [{"cause": c, "score": float(s)} for c, s in self.ranking],
            "not_identifiable": dict(self.not_identifiable),
            "last_ranking": [{"cause": c, "score": float(s)} for c, s in self.last_ranking],
            "evidence": self.evidence,
            "baseline": self.baseline.parameters(),
            "extended": self.extended.parameters(),
            "gain": self.gain.as_dict(),
            "chain_rms": float(self.chain_rms),
            "cutoff": float(self.cutoff),
            "nominal_model": self.nominal,
            "units": self.units,
            "end_stops": None if self.end_stops is None else self.end_stops.as_dict(),
            "origin": self.origin,
            "held_by_model": list(self.held),
            "supplied": None if self.supplied is None else self.supplied.parameters(),
            "below_line": [e.as_dict() for e in self.below_line],
            "motor_revolution": self.motor_revolution}
        notes = dict(self.notes or {})
        undefined: dict = {}

        def note(path: str, x: float | None) -> None:
            """Why the number at ``path`` is null: ``notes``' entry for the path or for its
            top-level key, else a generic reason (None values of the object are not numbers)."""
            if x is not None:
                head = path.split(".")[0].split("[")[0]
                undefined[path] = notes.get(path) or notes.get(head) or (
                    "not a finite number on this record (an overflow or 0/0 of the computation)")

        safe = json_safe(out, note)
        safe["undefined"] = undefined
        return safe

    def report(self) -> str:
        """Markdown report: causes step by step, evidence, ranking, models, gain."""
        u = unit_labels(self.units)
        g = self.gain
        title = " + ".join(f"`{c}`" for c in self.causes)
        lines = [f"# Diagnosis: {title}", ""]
        if self.verdict is not None:
            lines += [f"**{self.verdict.sentence()}**", ""]
        if self.end_stops is not None and self.end_stops.found:
            lines += [f"**{_capital(self.end_stops.description)}.**", ""]
        lines += [f"*{c}: {causes.physical(c)}*" + (" (held by the supplied model)"
                                                   if c in self.held else "")
                  for c in self.causes]
        if self.held:
            lines += ["", f"The supplied model holds {', '.join(self.held)}: removed to be "
                          f"judged by the same held-out tests (the baseline below is the "
                          f"supplied model without them)."]
        lines += ["", "## Evidence", "", self.evidence, "",
                  "## Steps (held-out, blocked cross-validation)", ""]
        if self.steps:
            lines += ["| step | cause | net score | gross | chain's share | torque RMS before -> after "
                      f"[{u.torque}] | simulation RMS before -> after [{u.position}] |",
                      "|---|---|---|---|---|---|---|"]
            for i, st in enumerate(self.steps, 1):
                lines.append(f"| {i} | {st.cause} | {_num(st.score, '.1f', 100, '%')} | "
                             f"{_num(st.gross, '.1f', 100, '%')} | {_num(st.chain, '.1f', 100, '%')} | "
                             f"{_num(st.torque_rms_before)} -> {_num(st.torque_rms_after)} | "
                             f"{_num(st.simulation_rms_before)} -> "
                             f"{_num(st.simulation_rms_after)} |")
            lines += [f"\nStep {i}: {st.cause} is named in place of a larger gross share: "
                      + ", ".join(f"{c} removes {100 * g:.1f} %" for c, g in st.passed_over)
                      + f" against {100 * st.gross:.1f} %, with no net share (the measuring "
                        f"chain's share cannot be measured); {st.cause} may stand in for "
                        + ("it." if len(st.passed_over) == 1 else "one of them.")
                      for i, st in enumerate(self.steps, 1) if st.passed_over]
        else:
            lines.append("No candidate reaches the score: nothing named.")
        if self.last_ranking:
            best = self.last_ranking[0]
            # a best candidate at or above the line stopped the selection for another reason
            # than its score (issue 21's pair [12102, 43, 1]: 57.5 % said alone read as if
            # the line had stopped it, where its fitted gap could not be told)
            reason = self.not_identifiable.get(best[0])
            if best[1] < MIN_SCORE and reason != CHAIN_UNMEASURED:  # the line stopped it
                reason = None
            why = "" if reason is None else f"; not named: {_why(reason)}"
            said = (f"has no net share: {CHAIN_UNMEASURED}" if reason == CHAIN_UNMEASURED else
                    f"removes {100 * best[1]:.1f} % of what is left (net of the measuring "
                    f"chain's share, which is measured only where the gross share reaches the "
                    f"line){why}")
            lines += ["", f"Stopped: the best remaining candidate, {best[0]}, {said}."]
        lines += self._below_lines(u)
        chain_said = (f"the measuring chain alone leaves {self.chain_rms:.3g} {u.torque} RMS"
                      if math.isfinite(self.chain_rms) else
                      "no floor: the twin of the baseline ran away")
        lines += ["", f"A step names the candidate that removes the most of the remaining held-out "
                      f"torque residual (sum of squares), net of what the same term removes on the "
                      f"record's effect-free twin ({chain_said}): net = (gross - chain) / (1 - "
                      f"chain) where gross > chain (else gross - chain), the chain's share being "
                      f"a fraction of the twin's residual, which is what the record keeps with "
                      f"the term in; named when the net share is "
                      f">= {100 * MIN_SCORE:.0f} % (a 10 % drop of the RMS).  Low-pass cut-off "
                      f"{self.cutoff:.4g} Hz.", ""]
        if self.not_identifiable:
            lines += ["## Not named: cannot be told on this record, or tried and rejected", ""]
            lines += [f"- `{c}`: {_why(r)}." for c, r in self.not_identifiable.items()]
            lines.append("")
        lines += ["## Candidates of the first step", "",
                  "| cause | net score | simulation score |", "|---|---|---|"]
        for c, sc in self.ranking:
            ss = self.simulation_scores.get(c)
            sim = "-" if ss is None else _num(ss, ".1f", 100, "%")  # the supported only
            net = _num(sc, ".1f", 100, "%") if math.isfinite(sc) else "no net share"
            lines.append(f"| {c} | {net} | {sim} |")
        first = self.steps[0] if self.steps else None
        listed = dict(self.ranking).get(first.cause) if first is not None else None
        if listed is not None and math.isfinite(listed) and abs(first.score - listed) > 5e-4:
            lines += ["", f"`{first.cause}` scores {100 * first.score:.1f} % in its step, not the "
                          f"table's {100 * listed:.1f} %: its step scores the model it named, with "
                          f"a column read from the model's torque settled on that model's whole "
                          f"torque; the table scores every candidate beside the columns as they "
                          f"stood."]
        lines += ["", "## Held-out gain", "", "| quantity | before | after | change |",
                  "|---|---|---|---|"]
        for name, b, a, unit in (
                ("torque residual RMS", g.torque_rms_before, g.torque_rms_after, u.torque),
                ("windowed simulation RMS, position", g.simulation_rms_before,
                 g.simulation_rms_after, u.position),
                ("windowed simulation RMS, velocity", g.velocity_rms_before, g.velocity_rms_after,
                 u.velocity)):
            change = (a / b - 1) if np.isfinite(a) and np.isfinite(b) and b > 0 else float("nan")
            lines.append(f"| {name} | {_num(b, unit=unit)} | {_num(a, unit=unit)} | "
                         f"{_num(change, '+.1f', 100, '%')} |")
        failure = self.sim_after.failure or self.sim_before.failure
        if failure:
            lines += ["", f"n/a: {failure}."]
        lines += ["", "## Models", "", "| parameter | baseline | extended |", "|---|---|---|"]
        pb, pe = self.baseline.parameters(), self.extended.parameters()
        for k in list(pb) + [k for k in pe if k not in pb]:
            lines.append(f"| {k} | {_num(pb[k], '.6g') if k in pb else '-'} | "
                         f"{_num(pe[k], '.6g') if k in pe else '-'} |")
        if any(k not in pb for k in pe) or any(k not in pe for k in pb):
            lines += ["", "'-': the model has no such term (the value is 0 or the law's default)."]
        if self.fit is not None:
            lines += ["", "## Refit (CasADi least squares)", "", "```", self.fit.report(), "```"]
        return "\n".join(lines) + "\n"


    def _below_lines(self, u) -> list:
        """The report's sections on the last step's candidates below the naming line."""
        if not self.below_line:
            return []
        from .below import TEST
        from .verdict import SIGNIFICANCE

        out = []
        for title, group in (("Supported by the data but below the naming line",
                              [e for e in self.below_line if e.supported]),
                             ("Below the naming line, not supported",
                              [e for e in self.below_line if not e.supported])):
            if group:
                out += ["", f"## {title}", ""]
                out += [f"- {e.sentence(u.torque, u.position)}"
                        for e in group]
        out += ["", f"Supported: the net reduction passes the {TEST}, at p < {SIGNIFICANCE:g}, "
                    f"and the fitted term passes the checks a named cause passes (told on this "
                    f"record, a held-out re-simulation no worse, no generic alternative that "
                    f"leaves it nothing the test can tell); the supported ones are taken in "
                    f"turn, each tested on what those above it leave.  Below the naming line "
                    f"({100 * MIN_SCORE:.0f} %) a cause is reported, not named."]
        return out


def _passed_over(st) -> str:
    """The sentence that flags a step's cause named while a candidate with no net share
    removed more of the residual gross (:attr:`~.selection.Step.passed_over`), or ``""``."""
    if not st.passed_over:
        return ""
    which = ", ".join(f"{c} ({100 * g:.0f} %)" for c, g in st.passed_over)
    one = len(st.passed_over) == 1
    return (f" Named in place of a larger share: {which} removed more of the same residual "
            f"gross (against {100 * st.gross:.0f} %) but {'has' if one else 'have'} no net "
            f"share (the measuring chain's share could not be measured at this step), so "
            f"{st.cause} may stand in for {'it' if one else 'one of them'}.")


def _why(reason: str) -> str:
    """A dropped candidate's reason as a clause: tried and rejected, or not told."""
    return reason if reason.startswith("tried, rejected") else \
        f"cannot be told on this record, because {reason}"


def evidence_text(steps: tuple, bodies: tuple, ranking: tuple, gain: Gain,
                  not_identifiable: dict, units: str, verdict: Verdict | None = None,
                  stops: str = "") -> str:
    """The evidence paragraph: each step's net score and its cause's own clause, the gain,
    the verdict (explained within noise only when it is), the end stops left out (``stops``,
    a sentence, or ``""``)."""
    u = unit_labels(units)
    cannot = "".join(f" {c}: {_why(r)}." for c, r in not_identifiable.items())
    said = "" if verdict is None else " " + verdict.sentence()
    if stops:
        said += " " + _capital(stops) + "."
    if not steps:
        best = ranking[0] if ranking else ("-", 0.0)
        supported = sum(score >= MIN_SCORE for _, score in ranking)
        unmeasured = [c for c, r in not_identifiable.items() if r == CHAIN_UNMEASURED]
        if unmeasured:  # no net share to compare with the line: no "best"
            head = (f"none: the share of {', '.join(unmeasured)} net of the measuring chain's "
                    f"cannot be measured on this record (its effect-free twin ran away), so "
                    f"{'it is' if len(unmeasured) == 1 else 'they are'} not named")
        elif supported:  # they reached the score and were dropped: the reasons follow
            head = (f"none: {supported} candidate{'s' if supported > 1 else ''} remove "
                    f"{100 * MIN_SCORE:.0f} % of the held-out torque residual net of the "
                    f"measuring chain's share (best: {best[0]} with {100 * best[1]:.1f} %), but "
                    f"none can be named on this record (each one's reason follows)")
        else:
            head = (f"none: no candidate removes {100 * MIN_SCORE:.0f} % of the held-out torque "
                    f"residual net of the measuring chain's share (best: {best[0]} with "
                    f"{100 * best[1]:.1f} %)")
        return (f"{head}; held-out torque RMS {_num(gain.torque_rms_before, '.3g')} {u.torque}."
                + said + cannot)
    parts = []
    for i, (st, body) in enumerate(zip(steps, bodies)):
        lead = "" if i == 0 else "Then "
        whose = "the baseline's" if i == 0 else "the remaining"
        parts.append(f"{lead}{st.cause}: {causes.physical(st.cause)}. Adding the term removes "
                     f"{100 * st.score:.0f} % of {whose} held-out torque residual (sum of squares, "
                     f"blocked cross-validation, net of the measuring chain's share: the term "
                     f"removes {100 * st.chain:.0f} % of the record's effect-free twin's "
                     f"residual); {body}." + _passed_over(st))
    tail = (f" Held-out torque RMS {_num(gain.torque_rms_before, '.3g')} -> "
            f"{_num(gain.torque_rms_after, '.3g')} {u.torque}, windowed simulation RMS "
            f"{_num(gain.simulation_rms_before, '.3g')} -> {_num(gain.simulation_rms_after, '.3g')} "
            f"{u.position}.")
    return " ".join(parts) + tail + said + cannot
