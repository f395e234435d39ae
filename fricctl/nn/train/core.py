"""The common seam every trainer of the friction network goes through.

A trainer is an *inner loop*: a function ``loop(problem, **options) -> LoopResult``
that improves the parameter vector ``theta`` (layout in :mod:`fricctl.nn.layout`)
on a :class:`TrainingProblem`.  Everything else is done here, once, for all of
them (:meth:`Trainer.train`):

1. check the patterns, ``hidden`` and ``rng``;
2. scale the patterns (:class:`Scaling`: inputs to [-1, 1] over their range,
   target to zero mean and unit standard deviation); the inner loop sees only
   the scaled problem;
3. initial weights (:func:`initial_theta`, drawn from ``rng`` whenever the loop
   asks: :meth:`TrainingProblem.initial_theta`);
4. start the clock (after the trainer's ``prepare``, e.g. compiling kernels) and run
   the loop with one BLAS thread (:func:`fricctl._threads.one_blas_thread`, restored
   after it);
5. after the loop: the history in physical units (:class:`TrainingHistory`),
   the net with its scaling and metadata, the fit on the training patterns,
   and the :class:`TrainingResult`.

A new trainer is one module in this package defining its loop and a
module-level ``TRAINER = Trainer(...)``; :mod:`fricctl.nn.train` finds it.  The entry
also declares what a command line shows of it (``fricctl train``): the loop options it
may set (:class:`TrainerOption`: type, help, largest value), named option sets
(:class:`Recipe`), the work the loop refuses, and what it needs that bare patterns do
not give (``requires``); the command reads them, it does not restate them.
"""

from __future__ import annotations

import inspect
import math
import time
import types
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ... import _validate as v
from ..._threads import one_blas_thread
from ..layout import pack, unpack
from ..metrics import fit_report
from ..net import FrictionNet

__all__ = ["Scaling", "initial_theta", "TrainingProblem", "LoopResult", "TrainingHistory",
           "TrainingResult", "Trainer", "TrainerOption", "Recipe", "MAX_HIDDEN", "MAX_RESTARTS", "PATTERN_MAX",
           "PATTERN_MIN_SPAN", "check_work"]

#: Most hidden units a trainer accepts (the paper's net has 4).  Levenberg-Marquardt's
#: step solves a (4H+1)-square system per iteration over an N x (4H+1) Jacobian: at
#: H = 32 and 4000 patterns an iteration takes ~0.15 s, at H = 64 ~0.6 s.
MAX_HIDDEN = 32
#: Most starting points a trainer runs (each a full training).
MAX_RESTARTS = 100
#: Largest pattern magnitude a trainer accepts: squares and sums of squares of the
#: values stay finite in double precision.
PATTERN_MAX = 1e150
#: Smallest range of each pattern column: the scaling divides by it (1e-300 made NaN).
PATTERN_MIN_SPAN = 1e-150


def check_work(what: str, work: float, limit: float, advice: str) -> None:
    """Refuse a training whose work estimate ``work`` exceeds ``limit`` (same unit).

    ``advice`` says which setting would finish (e.g. "at most 2000 epochs").
    """
    if work > limit:
        raise ValueError(f"{what} is {work:.3g}, more than the {limit:.3g} a training may take: "
                         f"{advice}")


# -- scaling ---------------------------------------------------------------------------
@dataclass(frozen=True, kw_only=True, eq=False)
class Scaling:
    """How the patterns are scaled for training (stored in the net, undone on evaluation)."""

    input_offset: np.ndarray
    """Centre of the (Tm [N*m], omega [rad/s]) range."""
    input_scale: np.ndarray
    """Half-width of the (Tm [N*m], omega [rad/s]) range."""
    output_offset: float
    """Mean of the target [N*m]."""
    output_scale: float
    """Standard deviation of the target [N*m]."""
    envelope_low: np.ndarray
    """Smallest (Tm [N*m], omega [rad/s]) of the patterns."""
    envelope_high: np.ndarray
    """Largest (Tm [N*m], omega [rad/s]) of the patterns."""

    @classmethod
    def of(cls, tm: np.ndarray, omega: np.ndarray, target: np.ndarray) -> "Scaling":
        """Inputs to [-1, 1] over their range; output to zero mean, unit std."""
        lo = np.array([tm.min(), omega.min()])
        hi = np.array([tm.max(), omega.max()])
        return cls(input_offset=0.5 * (lo + hi), input_scale=0.5 * (hi - lo),
                   output_offset=float(target.mean()), output_scale=float(target.std()),
                   envelope_low=lo, envelope_high=hi)

    @classmethod
    def centred(cls, tm: np.ndarray, omega: np.ndarray, target: np.ndarray, *,
                torque_scale: float, velocity_scale: float) -> "Scaling":
        """Inputs and output about zero, inputs divided by the given scales.

        Friction is odd in (Tm, omega) about rest, so no offsets; ``velocity_scale``
        sets where the net's tanh units resolve the velocity (a low speed puts the
        resolution where friction is nonlinear, instead of over the whole range).
        """
        ts = v.real("torque_scale", torque_scale, positive=True, unit="N*m")
        ws = v.real("velocity_scale", velocity_scale, positive=True, unit="rad/s")
        return cls(input_offset=np.zeros(2), input_scale=np.array([ts, ws]), output_offset=0.0,
                   output_scale=float(np.sqrt(np.mean(target ** 2))) or 1.0,
                   envelope_low=np.array([tm.min(), omega.min()]),
                   envelope_high=np.array([tm.max(), omega.max()]))

    def inputs(self, tm: np.ndarray, omega: np.ndarray) -> np.ndarray:
        """Scaled inputs ``xn``, shape (2, N) [-]."""
        xn = np.empty((2, tm.size))
        xn[0] = (tm - self.input_offset[0]) / self.input_scale[0]
        xn[1] = (omega - self.input_offset[1]) / self.input_scale[1]
        return xn

    def target(self, target: np.ndarray) -> np.ndarray:
        """Scaled target ``tn`` [-]."""
        return (target - self.output_offset) / self.output_scale

    def net_fields(self) -> dict:
        """The scaling fields of a :class:`~fricctl.nn.net.FrictionNet`."""
        return dict(input_offset=self.input_offset, input_scale=self.input_scale,
                    output_offset=self.output_offset, output_scale=self.output_scale,
                    envelope_low=self.envelope_low, envelope_high=self.envelope_high)


def initial_theta(hidden: int, rng: np.random.Generator) -> np.ndarray:
    """Initial weights of a 2-H-1 net on scaled inputs (``theta`` layout of :mod:`fricctl.nn.layout`).

    Nguyen-Widrow-like: hidden units with unit-norm input weights scaled by
    ``0.7*sqrt(H)`` and biases spreading the tanh centres over [-1, 1] of the
    scaled inputs; small output weights, zero output bias.
    """
    hidden = v.integer("hidden", hidden, low=1)
    v.rng("rng", rng)
    w1 = rng.normal(size=(hidden, 2))
    w1 *= 0.7 * math.sqrt(hidden) / np.linalg.norm(w1, axis=1, keepdims=True)
    b1 = rng.uniform(-1.0, 1.0, size=hidden) * np.linalg.norm(w1, axis=1)
    w2 = rng.uniform(-0.5, 0.5, size=hidden)
    return pack(w1, b1, w2, 0.0)


# -- what an inner loop gets and gives ---------------------------------------------------
@dataclass(frozen=True, kw_only=True, eq=False)
class TrainingProblem:
    """The scaled least-squares problem an inner loop works on."""

    hidden: int
    """Hidden units H; ``theta`` has ``4*H + 1`` entries."""
    xn: np.ndarray
    """Scaled inputs, shape (2, N), C-contiguous [-]."""
    tn: np.ndarray
    """Scaled targets, shape (N,) [-]."""
    rng: np.random.Generator
    """The caller's generator: initial weights, pattern order, ..."""
    start: float
    """``time.perf_counter()`` when training started [s]."""
    scaling: Scaling
    """How :attr:`xn` and :attr:`tn` were scaled (a loop that constrains the net in
    physical units converts its grids with it)."""
    progress: Callable[[int, int], None] | None = None
    """``progress(done, total)`` after each step (:meth:`report`), or None."""

    def report(self, done: int, total: int) -> None:
        """Tell :attr:`progress` (if any) that ``done`` of ``total`` steps are done."""
        if self.progress is not None:
            self.progress(int(done), int(total))

    @property
    def n(self) -> int:
        """Number of patterns N."""
        return int(self.tn.size)

    def initial_theta(self) -> np.ndarray:
        """A fresh starting point drawn from :attr:`rng` (:func:`initial_theta`)."""
        return initial_theta(self.hidden, self.rng)

    def elapsed(self) -> float:
        """Wall time since :attr:`start` [s]."""
        return time.perf_counter() - self.start


@dataclass(frozen=True, kw_only=True, eq=False)
class LoopResult:
    """What an inner loop returns."""

    theta: np.ndarray
    """The trained parameters (layout of :mod:`fricctl.nn.layout`)."""
    loss: np.ndarray
    """Scaled loss ``0.5*mean((yn - tn)^2)`` after each step; ``loss[0]`` is the initial one [-]."""
    elapsed: np.ndarray
    """Wall time of each entry of :attr:`loss` since the start [s]."""
    metadata: dict = field(default_factory=dict)
    """The loop's settings and outcome, JSON-serialisable (stored with the net)."""


@dataclass(frozen=True, kw_only=True, eq=False)
class TrainingHistory:
    """Training loss over the run.

    ``loss[k]`` is the mean squared error over all training patterns in
    physical units [(N*m)^2] after step ``k`` (an epoch for back-prop, an
    accepted or rejected Levenberg-Marquardt iteration for CasADi; for several
    restarts, the best loss so far over all restarts), and ``elapsed[k]`` the
    wall time since the trainer started [s].  ``loss[0]`` is the initial loss.
    """

    trainer: str
    """Name of the trainer (a key of :data:`fricctl.nn.train.TRAINERS`)."""
    step: str
    """What one entry is: 'epoch' or 'iteration'."""
    loss: np.ndarray
    """Training mean squared error [(N*m)^2]."""
    elapsed: np.ndarray
    """Wall time since the start of training [s]."""

    def time_to_reach(self, loss: float) -> float:
        """First elapsed time at which the loss is <= ``loss`` [s]; ``inf`` if never."""
        hit = np.nonzero(self.loss <= loss)[0]
        return float(self.elapsed[hit[0]]) if hit.size else math.inf


@dataclass(frozen=True, kw_only=True, eq=False)
class TrainingResult:
    """What every trainer returns: the trained net and its loss history."""

    net: FrictionNet
    """The trained network (its metadata say how it was trained and its fit)."""
    history: TrainingHistory
    """Loss and wall time per step."""


# -- the seam ------------------------------------------------------------------------------
def _patterns(tm, omega, target):
    arrs = [v.array(name, a, ndim=1) for name, a in (("tm", tm), ("omega", omega),
                                                     ("target", target))]
    if any(a.size != arrs[0].size for a in arrs):
        raise ValueError(f"tm, omega and target must have the same length, got "
                         f"{[a.size for a in arrs]}")
    if arrs[0].size < 2:
        raise ValueError("need at least 2 training patterns")
    for name, a in zip(("tm", "omega", "target"), arrs):
        span, big = float(np.ptp(a)), float(np.max(np.abs(a)))
        if span == 0:
            raise ValueError(f"{name} is constant over the patterns: nothing to learn from")
        # the scaling divides by the span and squares the values: both must stay normal doubles
        if big > PATTERN_MAX:
            raise ValueError(f"{name} reaches {big:.3g}: too large to train on (its square "
                             f"overflows double precision, at most {PATTERN_MAX:g}); check its units")
        if span < PATTERN_MIN_SPAN:
            raise ValueError(f"{name} varies by only {span:.3g} over the patterns: too little to "
                             f"scale (at least {PATTERN_MIN_SPAN:g}); check its units")
    return arrs


@dataclass(frozen=True, kw_only=True)
class TrainerOption:
    """An option of a trainer's loop that a command line sets (``fricctl train --NAME``).

    Its default is the loop's keyword default, or the value of the trainer's
    :class:`Recipe` in use; the loop checks the value (the command line only reads it).
    """

    name: str
    """The loop's keyword; the flag is ``--`` and the name with ``-`` for ``_``."""
    type: type
    """``int``, ``float`` or ``str``: what the flag's text is read as."""
    help: str
    """One line for ``--help``: what it sets, its unit in brackets, its domain."""
    high: float | None = None
    """The largest value the loop accepts (it refuses more with a ``ValueError`` naming
    the option), stated in ``--help``; None: no fixed limit."""
    metavar: str | None = None
    """How ``--help`` shows the value (None: the name in capitals)."""

    def __post_init__(self):
        if not (isinstance(self.name, str) and self.name.isidentifier()):
            raise ValueError(f"TrainerOption.name must be an identifier (the loop's keyword), "
                             f"got {self.name!r}")
        if self.type not in (int, float, str):
            raise ValueError(f"TrainerOption {self.name}: type must be int, float or str, "
                             f"got {self.type!r}")
        v.text(f"TrainerOption {self.name}: help", self.help, empty=False)
        if self.high is not None:
            v.real(f"TrainerOption {self.name}: high", self.high)
        if self.metavar is not None:
            v.text(f"TrainerOption {self.name}: metavar", self.metavar, empty=False)

    @property
    def flag(self) -> str:
        """The command line's flag, e.g. ``--learning-rate``."""
        return "--" + self.name.replace("_", "-")


@dataclass(frozen=True, kw_only=True)
class Recipe:
    """A named set of a trainer's options (``fricctl train --recipe NAME``)."""

    name: str
    """What ``--recipe`` takes."""
    description: str
    """One line: what the set is and where its values come from."""
    options: Mapping[str, object]
    """Loop option -> value (read-only); the loop's defaults stand for the others."""

    def __post_init__(self):
        if not (isinstance(self.name, str) and self.name.isidentifier()):
            raise ValueError(f"Recipe.name must be an identifier, got {self.name!r}")
        v.text(f"Recipe {self.name}: description", self.description, empty=False)
        v.instance(f"Recipe {self.name}: options", self.options, Mapping, "a mapping")
        object.__setattr__(self, "options", types.MappingProxyType(dict(self.options)))


@dataclass(frozen=True, kw_only=True)
class Trainer:
    """A registered trainer: its name, what it does, its inner loop, and what a command
    line shows of it (``fricctl train``)."""

    name: str
    """Registry key, also the ``"trainer"`` entry of the net's metadata."""
    description: str
    """One line: the method."""
    step: str
    """What one history entry is (``"epoch"``, ``"iteration"``)."""
    loop: Callable[..., LoopResult]
    """``loop(problem, **options) -> LoopResult``; its keyword defaults are the options'."""
    prepare: Callable[[], None] | None = None
    """Run before the clock starts (e.g. compile kernels), or None."""
    flags: tuple = ()
    """The loop options a command line may set (:class:`TrainerOption`), in ``--help``
    order; the others keep their defaults there."""
    recipes: tuple = ()
    """Named option sets (:class:`Recipe`) a command line chooses with ``--recipe``; the
    first is its default (none: the loop's own defaults)."""
    limits: str = ""
    """The work the loop refuses, one clause for ``fricctl train --help`` (docs/limits.md)."""
    requires: str | None = None
    """What the loop needs that bare patterns with the seam's default scaling do not give
    (a scaling or an option only a pipeline prepares), or None.  A trainer that requires
    something is reached through a pipeline, not through ``fricctl train --trainer``."""

    def __post_init__(self):
        v.text("name", self.name, empty=False)
        v.text("description", self.description, empty=False)
        v.text("step", self.step, empty=False)
        if not callable(self.loop) or not (self.prepare is None or callable(self.prepare)):
            raise ValueError("loop (and prepare, if given) must be callable")
        v.text("limits", self.limits)
        if self.requires is not None:
            v.text("requires", self.requires, empty=False)
        known = self.options()
        for what, entries, cls in (("flags", self.flags, TrainerOption),
                                   ("recipes", self.recipes, Recipe)):
            v.instance(f"{self.name}: {what}", entries, tuple, "a tuple")
            names = [v.instance(f"{self.name}: {what}", e, cls).name for e in entries]
            if len(set(names)) != len(names):
                raise ValueError(f"trainer {self.name!r}: {what} name one entry twice: {names}")
        for name in [f.name for f in self.flags] + [k for r in self.recipes for k in r.options]:
            if name not in known:
                raise ValueError(f"trainer {self.name!r}: {name!r} is not an option of its loop "
                                 f"({', '.join(known) or 'none'})")

    def options(self) -> dict:
        """The loop's options with their defaults."""
        params = list(inspect.signature(self.loop).parameters.values())[1:]
        return {p.name: p.default for p in params}

    def defaults(self, recipe: str | None = None) -> dict:
        """The loop's options as a command line starts from them.

        The loop's defaults, updated by the :class:`Recipe` called ``recipe`` (None: the
        first of :attr:`recipes`, if any); an unknown name raises ``ValueError``.
        """
        if recipe is None and not self.recipes:
            return self.options()
        if recipe is None:
            chosen = self.recipes[0]
        else:
            names = [r.name for r in self.recipes]
            chosen = self.recipes[names.index(v.choice(f"recipe of trainer {self.name!r}",
                                                        recipe, names))]
        return {**self.options(), **chosen.options}

    def train(self, tm, omega, target, *, hidden: int = 4, rng: np.random.Generator,
              metadata: dict | None = None, scaling: Scaling | None = None,
              progress: Callable[[int, int], None] | None = None,
              **options) -> TrainingResult:
        """Train a 2-``hidden``-1 net on the patterns with this trainer.

        Parameters
        ----------
        tm, omega, target : array_like
            1-D patterns: motor torque [N*m], velocity [rad/s], friction [N*m].
        hidden : int
            Hidden units H (4 in the paper).
        rng : numpy.random.Generator
            Source of the initial weights (and whatever else the loop draws).
        metadata : dict, optional
            Extra JSON-serialisable entries stored with the net (e.g. the seed).
        scaling : Scaling, optional
            Input and output scaling; default :meth:`Scaling.of` the patterns (inputs to
            [-1, 1] over their range).  A pipeline that wants the net's resolution where
            friction is nonlinear (low speeds) passes its own.
        progress : callable, optional
            ``progress(done, total)`` after each step of the loop (epoch, iteration); a
            command line shows a bar with it.  Not stored with the net.
        **options
            The loop's options (:meth:`options`); unknown names raise ``ValueError``.
        """
        unknown = sorted(set(options) - set(self.options()))
        if unknown:
            raise ValueError(f"unknown option(s) {', '.join(unknown)} for trainer {self.name!r}; "
                             f"it takes {', '.join(self.options()) or 'none'}")
        tm, omega, target = _patterns(tm, omega, target)
        hidden = v.integer("hidden", hidden, low=1)
        if hidden > MAX_HIDDEN:
            raise ValueError(f"hidden={hidden} is more than the {MAX_HIDDEN} hidden units a "
                             f"trainer accepts (the paper's net has 4)")
        v.rng("rng", rng)
        if progress is not None and not callable(progress):
            raise ValueError(f"progress must be a callable progress(done, total), got "
                             f"{type(progress).__name__}")
        if metadata is not None:
            v.instance("metadata", metadata, dict)
        rng_state = rng.bit_generator.state
        scaling = (Scaling.of(tm, omega, target) if scaling is None
                   else v.instance("scaling", scaling, Scaling))
        xn, tn = scaling.inputs(tm, omega), scaling.target(target)
        if self.prepare is not None:
            self.prepare()
        problem = TrainingProblem(hidden=hidden, xn=xn, tn=tn, rng=rng,
                                  start=time.perf_counter(), scaling=scaling, progress=progress)
        # one BLAS thread for the loop's small products (17 x N normal matrices): a
        # second OpenBLAS thread doubled their CPU, or spun at load (fricctl/_threads.py)
        with one_blas_thread():
            out = self.loop(problem, **options)
        mse = 2.0 * out.loss * scaling.output_scale ** 2  # scaled 0.5*e^2 -> physical e^2
        history = TrainingHistory(trainer=self.name, step=self.step, loss=mse,
                                  elapsed=np.asarray(out.elapsed))
        meta = {"trainer": self.name, "hidden": hidden, **out.metadata,
                "n_patterns": int(tm.size), "rng_state": rng_state, "train_mse": float(mse[-1])}
        w = unpack(out.theta, hidden)
        net = FrictionNet(w1=w.w1, b1=w.b1, w2=w.w2, b2=w.b2, metadata=meta,
                          **scaling.net_fields())
        rep = fit_report(target, net(tm, omega))
        meta.update(fit_percent=rep.fit_percent, r_squared=rep.r_squared)
        meta.update(metadata or {})
        return TrainingResult(net=net.replace(metadata=meta), history=history)
