"""The result of a diagnosis: :class:`Diagnosis` (named cause, evidence, models, held-out gain),
its JSON object (:meth:`Diagnosis.as_dict`) and its Markdown report (:meth:`Diagnosis.report`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..plant import JointModel
from ..units import units as unit_labels
from . import causes
from .windows import WindowedSimulation

if TYPE_CHECKING:
    from ..identify import IdentificationResult

__all__ = ["MIN_SCORE", "Gain", "Diagnosis", "evidence_text"]

#: Smallest held-out fraction of the baseline torque residual (sum of squares) a
#: candidate must remove to be named: 1 - 0.9**2, i.e. the held-out torque RMS must
#: drop by 10 %, the issue's definition of an effect that matters.  Terms that fit
#: only noise remove nothing held out; terms built on the measured acceleration
#: (compliance) can remove a few % of pure process noise, which this margin covers.
MIN_SCORE = 1.0 - 0.9 ** 2


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
        The named cause (one of :data:`~fricctl.diagnose.CAUSES`).
    ranking : tuple of (str, float)
        Every applicable candidate with its score, best first: the held-out
        fraction of the baseline's torque residual (sum of squares) it removes [-].
    evidence : str
        The evidence for the named cause, in words and numbers.
    baseline, extended : JointModel
        The baseline (fitted or nominal) and the model extended with the named
        term (the baseline itself when the cause is ``none``).
    gain : Gain
        Held-out RMS errors before and after.
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
    not_identifiable : dict
        Candidates above :data:`MIN_SCORE` passed over because their term cannot be
        told apart on this record, with the reason (``Cause.identifiable``; empty today).
    """

    cause: str
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
                "gain": self.gain.as_dict(),
                "nominal_model": self.nominal,
                "units": self.units}

    def report(self) -> str:
        """Markdown report: cause, evidence, ranking, models, gain."""
        u = unit_labels(self.units)
        g = self.gain
        lines = [f"# Diagnosis: `{self.cause}`", "",
                 f"*{causes.physical(self.cause)}*", "", "## Evidence", "", self.evidence, "",
                 "## Candidates (held-out, blocked cross-validation)", "",
                 "| cause | torque score | simulation score |", "|---|---|---|"]
        for c, s in self.ranking:
            ss = self.simulation_scores.get(c, float("nan"))
            lines.append(f"| {c} | {100 * s:.1f} % | {100 * ss:.1f} % |")
        lines += ["", f"Score: fraction of the baseline's held-out torque residual (sum of squares) "
                      f"the candidate removes; named when >= {100 * MIN_SCORE:.0f} %.", "",
                  "## Held-out gain", "", "| quantity | before | after | change |", "|---|---|---|---|"]
        for name, b, a, unit in (
                ("torque residual RMS", g.torque_rms_before, g.torque_rms_after, u.torque),
                ("windowed simulation RMS, position", g.simulation_rms_before,
                 g.simulation_rms_after, u.position),
                ("windowed simulation RMS, velocity", g.velocity_rms_before, g.velocity_rms_after,
                 u.velocity)):
            lines.append(f"| {name} | {b:.4g} {unit} | {a:.4g} {unit} | {100 * (a / b - 1):+.1f} % |")
        lines += ["", "## Models", "", "| parameter | baseline | extended |", "|---|---|---|"]
        pb, pe = self.baseline.parameters(), self.extended.parameters()
        for k in list(pb) + [k for k in pe if k not in pb]:
            lines.append(f"| {k} | {pb.get(k, float('nan')):.6g} | {pe.get(k, float('nan')):.6g} |")
        if self.fit is not None:
            lines += ["", "## Refit (CasADi least squares)", "", "```", self.fit.report(), "```"]
        return "\n".join(lines) + "\n"


def evidence_text(cause: str, body: str, ranking: tuple, gain: Gain, units: str) -> str:
    """The evidence paragraph: the score of ``cause``, the cause's own ``body``, the gain."""
    u = unit_labels(units)
    if cause == causes.NONE:
        best = ranking[0] if ranking else ("-", 0.0)
        return (f"none: no candidate removes {100 * MIN_SCORE:.0f} % of the held-out torque residual "
                f"(best: {best[0]} with {100 * best[1]:.1f} %); the baseline explains the data within "
                f"noise (held-out torque RMS {gain.torque_rms_before:.3g} {u.torque}).")
    score = dict(ranking).get(cause, 0.0)
    head = (f"{cause}: {causes.physical(cause)}. Adding the term removes {100 * score:.0f} % of the "
            f"baseline's held-out torque residual (sum of squares, blocked cross-validation); ")
    tail = (f". Held-out torque RMS {gain.torque_rms_before:.3g} -> {gain.torque_rms_after:.3g} "
            f"{u.torque}, windowed simulation RMS {gain.simulation_rms_before:.3g} -> "
            f"{gain.simulation_rms_after:.3g} {u.position}.")
    return head + body + tail
