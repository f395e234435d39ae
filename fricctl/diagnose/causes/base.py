"""What a cause module provides and what it is handed: :class:`Cause`, :class:`Term`,
:class:`Baseline` (the record as every candidate sees it), and the bench's side,
:class:`BenchActuator` and :class:`Injection`.

Kept apart from :mod:`fricctl.diagnose.causes` (the registry) so that a cause module
imports its interface without importing the registry that imports it.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Callable, Iterable, Mapping, Sequence

import numpy as np

from ... import _validate as v
from ...friction import Coulomb, FrictionModel, Viscous
from ...plant import FlexibleJoint, JointModel, RigidJoint
from ...units import Units, units
from ..crossval import Variant
from ..signals import Signals, delay_in_samples, friction_columns, predict

__all__ = ["Cause", "Term", "Baseline", "BenchActuator", "Injection", "identifiable_always",
           "coulomb_level", "coulomb_share"]


@dataclass(frozen=True, kw_only=True, eq=False)
class Term:
    """A cause's term as fitted on a record: its hyper-parameter and its coefficients."""

    h: object = None
    """Hyper-parameter chosen on the training data (Stribeck velocity, period, delay in
    samples, ``(wl, zeta)`` of the resonance, presliding length ...), or None."""
    coef: np.ndarray = field(default_factory=lambda: np.zeros(0))
    """Coefficients of the cause's extra columns, in the order of :attr:`Cause.params`."""
    extended: JointModel | None = None
    """The model with this term, fitted with it on all data (what :attr:`Cause.identifiable`
    compares the term with: a refitted baseline's inertia is the joint fit's), or None."""


def identifiable_always(base: "Baseline", term: Term) -> str | None:
    """The default identifiability check: every fitted term counts as evidence (None)."""
    return None


@dataclass(frozen=True, kw_only=True, eq=False)
class Cause:
    """One candidate cause of a disagreement between a model and a record.

    A cause module defines one ``CAUSE = Cause(...)``; the registry
    (:mod:`fricctl.diagnose.causes`) finds it.  The diagnosis calls, in this order:
    :attr:`variants` (per training set when :attr:`per_fold`) in the blocked
    cross-validation, and :attr:`extend` for every fitted model; then, for the
    supported candidates best first, :attr:`refine` and :attr:`identifiable` on all
    data until one can be told on the record (it is named); :attr:`evidence` for the
    report.  The bench calls :attr:`inject`.
    """

    name: str
    """Identifier (also the module name), e.g. ``"stribeck"``."""
    physical: str
    """The physical effect in one line, for reports."""
    order: int
    """Place in the candidate list (ascending): a tie in score goes to the lower number."""
    params: tuple
    """Names of the coefficients of the extra columns (``()`` for a pure shift such as a delay)."""
    changes: tuple
    """The model parameters the effect acts on (keys of :meth:`JointModel.parameters`): its
    extension sets only these, and the bench's injection changes only these."""
    variants: Callable[["Baseline", int | None], Iterable[Variant]]
    """``variants(base, fold)``: one :class:`~fricctl.diagnose.crossval.Variant` per value of the
    hyper-parameter (extra columns, target, sign and upper bounds of the coefficients)."""
    extend: Callable[[JointModel, Term, "Baseline"], JointModel]
    """``extend(model, term, base)``: ``model`` with the fitted term added.  A function of a model,
    so that several causes' terms apply one after the other."""
    evidence: Callable[["Baseline", Term, JointModel], str]
    """``evidence(base, term, extended)``: what in the data shows the cause and the fitted values,
    as one clause (the diagnosis adds the score before it and the held-out gain after it)."""
    inject: Callable[[np.random.Generator, "BenchActuator"], "Injection"]
    """``inject(rng, actuator)``: the bench hides the effect in a drawn actuator (magnitudes drawn
    from ``rng`` in a fixed sequence, so that a seed gives the same record)."""
    nominal_only: bool = False
    """True when the cause only exists against a supplied nominal model (inertia, friction level)."""
    friction_curve: bool = False
    """True when the term is itself a shape of the friction-speed curve, an odd function of
    the velocity (a Stribeck excess, a drag, a friction level's scale): the selection's
    generic curve (:func:`fricctl.diagnose.selection.speed_curve`) spans it, so the candidate
    is not compared with that curve; every other candidate must beat it."""
    per_fold: bool = False
    """True when :attr:`variants` depends on the training blocks (``fold`` is the block left out,
    None for all data); else it is called once with ``fold=None``."""
    per_step: bool = False
    """True when :attr:`variants` reads :attr:`Baseline.current_residual` (the residual of the
    model as it stands): they are made again after each cause the selection names
    (:meth:`Baseline.advanced`)."""
    reads_model_torque: bool = False
    """True when the term's column is made from the torque of the model as it stands
    (:attr:`Baseline.current_torque`; e.g. a friction growing with the transmitted torque),
    a torque that the term itself and every cause named after it change: the selection
    remakes the column after each step, its own included, until it settles
    (:func:`fricctl.diagnose.crossval.settle`).  Such a cause is :attr:`per_step` and not
    :attr:`per_fold`."""
    refine: Callable[["Baseline", list], list] | None = None
    """``refine(base, variants)``: a finer grid around the variants, or None; applied to every
    set of variants (:meth:`Baseline.variants`), so that a named cause's term is as good on
    each fold's training blocks as on all data."""
    identifiable: Callable[["Baseline", Term], str | None] = identifiable_always
    """``identifiable(base, term)``: None when the term fitted on all data can be told apart on
    this record, else the reason why not, a clause completing "cannot be told on this record,
    because ..." (a cause that cannot be told is never named): a coefficient at its bound, a
    hyper-parameter at the end of what the record resolves, a resonance above the band the
    excitation reaches.  Collinearity of the term's columns with the model's is checked for
    every cause by the selection itself."""
    remove: Callable[[JointModel], JointModel] | None = None
    """``remove(model)``: ``model`` without this effect (the parameters it acts on at their
    neutral values: no offset, equal levels both ways, no Stribeck excess ...), or None when
    the effect has no neutral value (a nominal model's inertia or friction level).  A
    supplied model's terms are judged by removal: the diagnosis removes every term a cause
    can remove, and the selection names again what the record supports from there
    (:func:`~fricctl.diagnose.diagnose`), each marked as held by the supplied model."""

    def __post_init__(self):
        if not (isinstance(self.name, str) and self.name.isidentifier()):
            raise ValueError(f"Cause.name must be an identifier (the module name), got {self.name!r}")
        v.text("Cause.physical", self.physical, empty=False)
        v.integer("Cause.order", self.order)
        if self.reads_model_torque and (self.per_fold or not self.per_step):
            raise ValueError(f"Cause {self.name}: a term read from the model's torque is made "
                             f"again per step (per_step=True) on all data (per_fold=False)")
        for name in ("variants", "extend", "evidence", "inject", "identifiable"):
            if not callable(getattr(self, name)):
                raise ValueError(f"Cause {self.name}: {name} must be a function")

    def held_by(self, model: JointModel) -> bool:
        """True when ``model`` holds this effect (:attr:`remove` changes it)."""
        return self.remove is not None and self.remove(model).parameters() != model.parameters()

    @property
    def n_extra(self) -> int:
        """Number of extra regressor columns (= coefficients)."""
        return len(self.params)


def coulomb_level(model: JointModel) -> float:
    """Mean Coulomb level of ``model``, times its friction scale [N*m]."""
    fr = model.friction
    return 0.5 * (fr.coulomb_pos + fr.coulomb_neg) * fr.scale


def coulomb_share(value: float, level: float, torque: str) -> str:
    """``value`` [N*m] as a share of the Coulomb level ``level`` [N*m], a clause for an
    evidence sentence ("12 % of the Coulomb level 0.3 N*m"; ``torque``: the unit label).

    A model fitted with no Coulomb friction (a level of 0: the fit's bound; issue 21's pair
    [12102, 43, 1], the baseline fitted on a delayed record) has no share to give: said so,
    not a percentage of a floor (it read "14003820618838 % of the Coulomb level 0 N*m").
    """
    if not level > 0:
        return f"the Coulomb level is {level:.3g} {torque}: no share of it"
    return f"{100 * value / level:.0f} % of the Coulomb level {level:.3g} {torque}"


class Baseline:
    """The record as every candidate sees it: the baseline's columns or prediction, the target.

    In *fit mode* (no nominal model) the baseline ``I*q'' + b*w + Fc*sign(w)`` is refitted with
    each candidate: its three columns come first in every design, and ``theta`` holds the fit
    on all data.  With a *nominal* model the target is the nominal model's residual and each
    candidate fits only its own term.

    Parameters
    ----------
    sig : Signals
    nominal : JointModel or None
    theta : ndarray or None
        Fit mode: the baseline (I, b, Fc) fitted on all sliding samples.
    """

    def __init__(self, sig: Signals, nominal: JointModel | None, theta: np.ndarray | None):
        self.sig = sig
        self.nominal = nominal
        n = sig.t.size
        #: effective sign of the motion (fractional at reversals)
        self.sign = sig.seff
        self.fit_mode = nominal is None
        if self.fit_mode:
            #: (N, 3) columns of the baseline (fit mode), or None
            self.columns = np.column_stack([sig.a, sig.filt(sig.w), sig.filt(self.sign)])
            #: delay of the baseline [samples] (a fraction kept)
            self.delay = 0.0
            #: the target every candidate fits (LP torque, or the nominal residual)
            self.target = sig.torque_target(0)
            #: what the target is measured from (the nominal prediction, or zeros)
            self.reference = np.zeros(n)
            self.theta = theta
        else:
            self.columns = None
            self.delay = delay_in_samples(nominal, sig.ts)
            tp = predict(nominal, sig)
            self.target = tp.target - tp.prediction
            self.reference = tp.prediction
            self.theta = None
            u = sig.centred(self.delay)
            #: nominal friction along the measured motion, raw and low-passed [N*m]
            self.nominal_friction_raw = friction_columns(sig, nominal.friction, u)
            self.nominal_friction = sig.filt(self.nominal_friction_raw)
        #: the sample-centred torque the joint receives under the baseline's delay [N*m]
        self.torque = sig.centred(self.delay)
        self._variants: dict = {}
        self._step = 0
        self._current: np.ndarray | None = None
        self._prediction: np.ndarray | None = None

    @property
    def labels(self) -> Units:
        """Unit labels of the record."""
        return units(self.sig.units)

    @cached_property
    def fitted(self) -> JointModel:
        """The baseline model fitted on all data (fit mode), or the nominal model."""
        return self.model((), self.theta if self.fit_mode else np.zeros(0))

    @cached_property
    def residual(self) -> np.ndarray:
        """The baseline's residual on all samples (fit on all data) [N*m]."""
        if self.fit_mode:
            return self.target - self.columns @ self.theta
        return self.target.copy()

    @property
    def current_residual(self) -> np.ndarray:
        """The residual on all samples of the model as it stands (the baseline until a cause
        is named; :meth:`advanced`) [N*m]."""
        return self.residual if self._current is None else self._current

    def advanced(self, residual: np.ndarray, prediction: np.ndarray) -> "Baseline":
        """The baseline once a cause is named: ``residual`` is the new model's residual on all
        samples, ``prediction`` what its columns predict there (``residual`` is the composed
        target minus ``prediction``; the composed target is the delayed one once a delay is
        named, so the prediction is kept, not recovered from :attr:`target`).

        A new object; this one is left as it was, so that whoever holds it (the diagnosis,
        an earlier step) still sees the model it was given.  The values computed once per
        record (columns, target, the fitted baseline) and the variants made so far are
        shared; a per-step cause's variants are made again from the new residual (they are
        keyed by the step).
        """
        new = copy.copy(self)
        new._current = np.asarray(residual, dtype=float)
        new._prediction = np.asarray(prediction, dtype=float)
        new._step = self._step + 1
        new._variants = dict(self._variants)
        return new

    @cached_property
    def model_torque(self) -> np.ndarray:
        """The torque the baseline model needs along the measured motion, low-passed like
        the target (``I*a + b*w + Fc*sign(w)`` fitted on all data, or the nominal model's
        prediction): the recorded torque without its noise [N*m]."""
        if self.fit_mode:
            return self.columns @ self.theta
        return self.reference.copy()

    @property
    def current_torque(self) -> np.ndarray:
        """The low-passed torque the model *as it stands* needs along the measured motion
        (:attr:`model_torque` until a cause is named; then the baseline with the named
        causes' terms, refitted with them: :meth:`advanced`) [N*m]."""
        if self._current is None:
            return self.model_torque
        return self.reference + self._prediction

    @cached_property
    def model_torque_raw(self) -> np.ndarray:
        """:attr:`model_torque` before the low-pass, sample by sample [N*m]."""
        sig = self.sig
        if self.fit_mode:
            inertia, b, fc = self.theta[:3]
            return inertia * sig.a + b * sig.w + fc * self.sign
        return (self.nominal.inertia * sig.a + self.nominal_friction_raw
                + self.nominal.offset)

    @property
    def inertia(self) -> float:
        """The baseline's inertia (fitted on all data, or the nominal one) [kg*m^2]."""
        return float(self.theta[0]) if self.fit_mode else self.nominal.inertia

    def variant(self, h, cols, signs, y=None, upper=()) -> Variant:
        """A :class:`Variant` with extra columns ``cols`` against the baseline's target, or
        against ``y`` (a shifted target: the variant then sets the target of a composition)."""
        cols = np.asarray(cols, dtype=float)
        if cols.ndim == 1:
            cols = cols[:, None]
        return Variant(h=h, extra=cols, y=self.target if y is None else y, signs=tuple(signs),
                       upper=tuple(upper), shifts_target=y is not None)

    def variants(self, cause: Cause, fold: int | None = None) -> list:
        """The cause's variants, refined when it has :attr:`Cause.refine` (computed once per
        cause, or once per fold or per step when it says so)."""
        key = (cause.name, fold if cause.per_fold else None,
               self._step if cause.per_step else None)
        if key not in self._variants:
            variants = list(cause.variants(self, key[1]))
            if cause.refine is not None:
                variants = cause.refine(self, variants)
            self._variants[key] = variants
        return self._variants[key]

    def model(self, parts: Sequence, theta: np.ndarray) -> JointModel:
        """The model of a fit: the baseline (from ``theta`` in fit mode) extended by each
        ``(cause, h)`` of ``parts`` in turn, their coefficients following in ``theta``."""
        units_ = self.sig.units
        theta = np.asarray(theta, dtype=float)
        if self.fit_mode:
            inertia, b, fc = theta[:3]
            k = 3
            model = JointModel(inertia=max(inertia, 1e-12),
                               friction=Viscous(max(float(b), 0.0)) + Coulomb(max(float(fc), 0.0)),
                               units=units_)
        else:
            model = replace(self.nominal, units=units_)
            k = 0
        for cause, h in parts:
            model = cause.extend(model, Term(h=h, coef=theta[k:k + cause.n_extra]), self)
            k += cause.n_extra
        return model


# ============================================================================ bench
@dataclass(frozen=True, kw_only=True)
class BenchActuator:
    """The baseline actuator the bench drew for one record (load side), before any effect."""

    motor_inertia: float
    """Actuator (motor side) inertia Jm [kg*m^2]."""
    link_inertia: float
    """Link inertia Jl, rigidly attached unless a cause makes it elastic [kg*m^2]."""
    viscous: float
    """Viscous coefficient b [N*m*s/rad]."""
    coulomb: float
    """Coulomb level Fc (stiction at the same level) [N*m]."""
    sample_time: float
    """Ts of the record [s]."""
    duration: float
    """Length of the record [s]."""
    encoder_resolution: float
    """One encoder count [rad]."""
    travel: float = 1.0
    """Position unit of the bench's motion [rad] ([m] on a linear axis): speeds, ripple periods
    and Stribeck velocities are drawn as multiples of it (1 rad on a rotary joint; a linear
    axis moves some centimetres where a joint turns a radian)."""
    strength: float = 1.0
    """Factor on the size of the hidden effect (1: as drawn; 0.3: about a third of its torque),
    for records near the 10 % line [-]."""
    top_speed: float | None = None
    """The speed the bench's fastest excitation reaches with this actuator, at which an effect
    growing with speed (drag) is sized [rad/s] ([m/s] on a linear axis); None: 6 x
    :attr:`travel` per second."""
    units: str = "rotary"
    """``"rotary"`` or ``"linear"`` (labels of the models the bench returns)."""

    def __post_init__(self):
        for name in ("motor_inertia", "viscous", "coulomb", "sample_time", "duration",
                     "encoder_resolution", "travel", "strength"):
            object.__setattr__(self, name, v.real(name, getattr(self, name), positive=True))
        object.__setattr__(self, "link_inertia", v.real("link_inertia", self.link_inertia,
                                                          nonneg=True))
        top = 6.0 * self.travel if self.top_speed is None else self.top_speed
        object.__setattr__(self, "top_speed", v.real("top_speed", top, positive=True))
        v.choice("units", self.units, ("rotary", "linear"))

    @property
    def inertia(self) -> float:
        """Total inertia Jm + Jl [kg*m^2]."""
        return self.motor_inertia + self.link_inertia

    def friction(self) -> FrictionModel:
        """The baseline friction ``Viscous(b) + Coulomb(Fc)``."""
        return Viscous(self.viscous) + Coulomb(self.coulomb)

    def nominal(self) -> JointModel:
        """The model an engineer would hold: the true baseline actuator."""
        return JointModel(inertia=self.inertia, friction=self.friction(), units=self.units)

    def weaker(self, ratio: float) -> float:
        """A ratio of the effect (1.3 = 30 % more) at :attr:`strength` (``ratio**strength``)."""
        return float(ratio) ** self.strength

    def rigid(self, *, magnitude: Mapping, friction=None, breakaway: float | None = None,
              delay: int = 0, inertia: float | None = None, offset: float = 0.0,
              substeps: int = 4) -> "Injection":
        """The injection of an effect that keeps the joint rigid.

        Parameters
        ----------
        magnitude : mapping
            Parameters of the effect (SI), for the record's metadata.
        friction : FrictionLaw or FrictionModel, optional
            The true friction (default: the baseline's).
        breakaway : float, optional
            The torque the drive must exceed to start moving, for sizing the excitation
            (default: the Coulomb level) [N*m].
        delay : int
            The joint receives the torque this many samples late.
        inertia : float, optional
            The true inertia (default: the baseline's) [kg*m^2].
        offset : float
            A constant torque at the joint (it receives ``Tm - offset``; the bench
            simulates the truth's offset) [N*m].
        substeps : int
            RK4 sub-intervals per sample of the bench simulation.
        """
        fr = (self.friction() if friction is None else friction).model()
        true_inertia = self.inertia if inertia is None else inertia
        return Injection(joint=RigidJoint(inertia=true_inertia, friction=fr),
                         truth=JointModel(inertia=true_inertia, friction=fr,
                                          offset=v.real("offset", offset),
                                          delay=delay * self.sample_time, units=self.units),
                         nominal=self.nominal(), magnitude=dict(magnitude),
                         breakaway=self.coulomb if breakaway is None else breakaway,
                         delay=delay, substeps=substeps)


@dataclass(frozen=True, kw_only=True, eq=False)
class Injection:
    """An effect hidden in a bench actuator: what the bench simulates and what is true."""

    joint: RigidJoint | FlexibleJoint
    """The joint the bench simulates (a constant torque, :attr:`truth`'s ``offset``, is
    applied to it by the bench)."""
    truth: JointModel
    """The complete true model (baseline + effect)."""
    nominal: JointModel
    """The model an engineer would hold (the true baseline actuator, without the effect)."""
    magnitude: dict
    """Parameters of the effect (SI units)."""
    breakaway: float
    """Torque needed to start moving, for sizing the excitation [N*m]."""
    delay: int = 0
    """Samples between the recorded torque and the torque the joint receives."""
    substeps: int = 4
    """RK4 sub-intervals per sample of the bench simulation."""

