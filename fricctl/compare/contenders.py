"""The contenders of the comparison, built by name: one table, one factory signature.

Every contender is made by ``factory(model, design, sample_time, seed, options) ->
Compensator`` from what a user of a real drive has:

model : :class:`fricctl.plant.JointModel`
    The identified (design) model of the joint: the Coulomb levels read their levels from
    it, never from the bench's true plant.
design : :class:`fricctl.design.Design`
    The experiment's controller (a compensator that needs the loop's gains reads them here).
sample_time : float
    The controller's sample time Ts [s].
seed : int
    The training seed (contenders whose result does not depend on it ignore it).
options : mapping
    The contender's own options; an option it does not know is refused.

A contender whose making is expensive per seed (a trained network) declares a ``prepare(seed,
options) -> options`` step: the protocol runs it once per seed (as a job of its executor) and
passes what it returns to the factory; the factory alone, without it, does the same work itself.

Adding a contender is one entry in :data:`CONTENDERS`; the compensators of
:mod:`fricctl.compensators` that its ``make(name, model, design, sample_time, **options)``
builds are one name each in :data:`REGISTERED` (present only when ``fricctl.compensators``
lists them in its ``available()``).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from types import MappingProxyType
from typing import Callable, Mapping

from .. import _validate as v
from ..compensators import Compensator, CoulombCompensator, NoCompensation
from ..compensators.nn_confirmed import network_compensator

__all__ = ["Contender", "CONTENDERS", "REGISTERED", "contender", "contender_names", "make_contender"]


@dataclass(frozen=True, kw_only=True)
class Contender:
    """One compensator of the comparison: its name, what it is, how it is made.

    Attributes
    ----------
    name : the name the table, the rows and ``fricctl compare --compensators`` use
    description : one line: what it compensates with and where its parameters come from
    factory : ``(model, design, sample_time, seed, options) -> Compensator``
    seeded : whether the compensator depends on the seed (a trained network): the protocol
        then runs it once per seed, a contender that does not once
    prepare : optional ``(seed, options) -> options``: the expensive per-seed step (training),
        whose result (JSON-able) the factory accepts as options
    options : the option names the factory accepts; None: any, passed on to a maker that checks
        them itself (:func:`fricctl.compensators.make`)
    """

    name: str
    description: str
    factory: Callable
    seeded: bool = False
    prepare: Callable | None = None
    options: tuple | None = ()

    def __post_init__(self):
        v.text("name", self.name, empty=False)
        v.text("description", self.description, empty=False)
        if not callable(self.factory):
            raise ValueError(f"contender {self.name!r}: factory must be callable")
        if self.prepare is not None and not callable(self.prepare):
            raise ValueError(f"contender {self.name!r}: prepare must be callable or None")

    def check_options(self, options: Mapping) -> dict:
        """``options`` as a dict, or ``ValueError`` naming an option this contender does not take."""
        if not isinstance(options, Mapping):
            raise ValueError(f"options of {self.name!r} must be a mapping, got {type(options).__name__}")
        if self.options is None:
            return dict(options)
        unknown = sorted(set(options) - set(self.options))
        if unknown:
            have = ", ".join(self.options) if self.options else "none"
            raise ValueError(f"contender {self.name!r} takes no option {unknown[0]!r} (its options: {have})")
        return dict(options)


def _levels(model) -> tuple:
    """The model's Coulomb (sliding) and breakaway levels, both directions [N*m]."""
    from ..plant import JointModel

    m = v.instance("model", model, JointModel, "a JointModel (the identified design model)")
    if m.units != "rotary":
        raise ValueError(f"model: the comparison runs on a rotary joint, got a {m.units} axis")
    fr = m.friction
    return ((fr.sliding_level(+1), fr.sliding_level(-1)), (fr.breakaway(+1), fr.breakaway(-1)))


def _none(model, design, sample_time, seed, options):
    return NoCompensation(name="none")


def _coulomb(model, design, sample_time, seed, options):
    (pos, neg), _ = _levels(model)
    return CoulombCompensator(coulomb_pos=pos, coulomb_neg=neg, name="coulomb")


def _coulomb_breakaway(model, design, sample_time, seed, options):
    _, (pos, neg) = _levels(model)
    return CoulombCompensator(coulomb_pos=pos, coulomb_neg=neg, name="coulomb_breakaway")


@functools.lru_cache(maxsize=64)
def _trained(pipeline: str, bench: str, seed: int, fast: bool) -> str:
    """The pipeline's network for ``seed`` on ``bench``, as JSON (trained once per process;
    :func:`fricctl.paper.train_paper_network` keeps it in the disk cache of trained nets)."""
    from ..paper.network import train_paper_network

    return train_paper_network(bench=bench, seed=seed, pipeline=pipeline, fast=fast).net.to_json()


def _net_options(options: Mapping) -> tuple:
    from ..paper.benches import BENCHES, DEFAULT_BENCH

    bench = options["bench"] if "bench" in options else DEFAULT_BENCH
    v.choice("bench", bench, tuple(BENCHES))
    fast = v.flag("fast", options["fast"]) if "fast" in options else False
    return bench, fast


def _given(options: Mapping, seed: int) -> str | None:
    """Seed ``seed``'s network from the option ``networks`` (one JSON text per seed, seed k at
    index k: networks trained elsewhere, e.g. the ones ``fricctl reproduce`` wrote), or None."""
    if "networks" not in options:
        return None
    nets = options["networks"]
    if isinstance(nets, (str, bytes)) or not isinstance(nets, (list, tuple)):
        raise ValueError(f"option networks must be a list of JSON texts (one per seed), got "
                         f"{type(nets).__name__}")
    if seed >= len(nets):
        raise ValueError(f"option networks holds {len(nets)} network(s) (seeds 0 .. {len(nets) - 1}): "
                         f"none for seed {seed}")
    return v.text(f"networks[{seed}]", nets[seed], empty=False)


def _network(pipeline: str, name: str):
    """Factory and prepare step of the network of ``pipeline``, trained per seed on the bench
    (:func:`fricctl.paper.train_paper_network`: the bench's training experiments, the seeded
    split and trainer; not retrained for a perturbed plant, as a deployed net is not).

    Options: ``bench``, ``fast`` (the training's), ``network`` (one JSON text: this network for
    every seed) or ``networks`` (a list of JSON texts, seed k's at index k: no training).
    """

    def prepare(seed, options):
        bench, fast = _net_options(options)
        seed = v.integer("seed", seed, low=0)
        # a network given (one for every seed, or seed k's) is the one run: nothing is trained
        given = options["network"] if "network" in options else _given(options, seed)
        rest = {k: x for k, x in options.items() if k != "networks"}
        return {**rest, "network": given if given is not None else _trained(pipeline, bench, seed, fast)}

    def factory(model, design, sample_time, seed, options):
        from ..nn import FrictionNet
        from ..paper.benches import bench as load_bench

        bench, fast = _net_options(options)
        ts = load_bench(bench).actuator.sample_time
        if abs(v.real("sample_time", sample_time, positive=True, unit="s") - ts) > 1e-12 * ts:
            raise ValueError(f"contender {name!r}: the network is trained at the bench's Ts = {ts:g} s, "
                             f"not at sample_time = {sample_time:g} s")
        seed = v.integer("seed", seed, low=0)
        text = options["network"] if "network" in options else _given(options, seed)
        if text is None:
            text = _trained(pipeline, bench, seed, fast)
        from ..paper.network import pipeline_velocity

        # the pipeline's velocity, as its figures run it (fricctl.paper.PaperNetwork.compensator)
        return network_compensator(FrictionNet.from_json(text), pipeline_velocity(pipeline), name=name)

    return factory, prepare


#: ASSUMPTION (not in the paper, whose bench has no presliding model): where the model has no
#: LuGre law, the LuGre observer's bristle deflects ``BRISTLE_COUNTS`` encoder counts at the
#: breakaway level (``sigma0 = Fs / (BRISTLE_COUNTS * count)``; the diagnosis's presliding scan
#: starts at a few counts, below which the encoder cannot see a bristle), and its damping is
#: the observer's own default, :func:`fricctl.compensators.lugre_observer.default_sigma1`
#: (``sqrt(sigma0 * I)``, Canudas de Wit et al.'s example: damping ratio 0.5 on the joint's
#: inertia; ``fricctl simulate`` builds the same).  The option ``sigma0`` [N*m/rad] replaces the
#: assumed stiffness (the damping rule then applies to it), ``sigma1`` [N*m*s/rad] the damping;
#: on a model with a LuGre law either replaces the law's (``fricctl compare --sigma0 / --sigma1``).
BRISTLE_COUNTS = 10.0


def _lugre_defaults(model, options: dict) -> dict:
    """``options`` with the bristle of a model without a LuGre law: ``sigma0`` given (checked:
    a finite stiffness > 0) or assumed (:data:`BRISTLE_COUNTS`); ``sigma1`` given (checked), else
    the observer's default (:meth:`~fricctl.compensators.LuGreObserver.from_model`)."""
    out = dict(options)
    if "sigma0" in out:
        out["sigma0"] = v.real("sigma0", out["sigma0"], positive=True, unit="N*m/rad")
    if "sigma1" in out:
        out["sigma1"] = v.real("sigma1", out["sigma1"], nonneg=True, unit="N*m*s/rad")
    fr = model.friction
    if fr.lugre_sigma0 > 0.0:
        return out
    if "sigma0" not in out:
        count = model.encoder_resolution
        if not count > 0.0:
            raise ValueError("lugre_observer: the model has neither a LuGre law nor an encoder count "
                             "to size an assumed bristle from; give the option sigma0 [N*m/rad] "
                             "(fricctl compare --sigma0)")
        out["sigma0"] = max(fr.breakaway(1), fr.breakaway(-1)) / (BRISTLE_COUNTS * count)
    return out


def _registered(name: str, description: str) -> Contender:
    """A contender that :func:`fricctl.compensators.make` builds (the stateful compensators)."""

    def factory(model, design, sample_time, seed, options):
        from .. import compensators

        if name == "lugre_observer":
            options = _lugre_defaults(model, dict(options))
        return compensators.make(name, model, design, sample_time, **options)

    return Contender(name=name, description=description, factory=factory, options=None)


_nn, _nn_prepare = _network("fricctl", "nn")
_nn_paper, _nn_paper_prepare = _network("paper", "nn_paper")

_TABLE = (
    Contender(name="none", description="no compensation: Tm(k+1) = Tc(k)", factory=_none),
    Contender(name="coulomb", description="Fc*sign(omega_hat), Fc the model's sliding (Coulomb) level",
              factory=_coulomb),
    Contender(name="coulomb_breakaway", description="Fs*sign(omega_hat), Fs the model's breakaway "
              "level (the paper's 'dry friction identified experimentally')", factory=_coulomb_breakaway),
    Contender(name="nn", description="2-4-1 network, fricctl pipeline (nonlinear part, certified gain "
              "at rest, direction-confirmed velocity), trained per seed on the bench", factory=_nn, seeded=True, prepare=_nn_prepare,
              options=("bench", "fast", "network", "networks")),
    Contender(name="nn_paper", description="2-4-1 network, the paper's literal recipe (full friction, "
              "least squares), trained per seed on the bench", factory=_nn_paper, seeded=True,
              prepare=_nn_paper_prepare, options=("bench", "fast", "network", "networks")),
)

#: The stateful compensators of :mod:`fricctl.compensators` (issue 23 item 1), one line each:
#: a name here joins :data:`CONTENDERS` when ``fricctl.compensators.available()`` lists it.
REGISTERED = {
    "feedforward": "model-based feedforward: the identified static (Stribeck) law at omega_hat",
    "lugre_observer": "LuGre observer-based compensation (Canudas de Wit et al. 1995); the model's "
                      "LuGre law, or an assumed bristle of BRISTLE_COUNTS encoder counts at Fs",
    "dob": "disturbance observer (Ohnishi), nominal inertia, Q-filter bandwidth",
    "integral": "integral action: the PD becomes a PID with anti-windup",
}


def _table() -> dict:
    from .. import compensators

    table = {c.name: c for c in _TABLE}
    have = set(compensators.available())
    table.update({n: _registered(n, d) for n, d in REGISTERED.items() if n in have})
    return table


#: Contender name -> :class:`Contender` (read-only), in table order.
CONTENDERS: Mapping[str, Contender] = MappingProxyType(_table())


def contender_names() -> tuple:
    """The contenders' names, in table order."""
    return tuple(CONTENDERS)


def contender(name: str) -> Contender:
    """The contender called ``name``; ``ValueError`` listing the names otherwise."""
    if not isinstance(name, str) or name not in CONTENDERS:
        raise ValueError(f"unknown compensator {name!r}; choose from {', '.join(CONTENDERS)}")
    return CONTENDERS[name]


def make_contender(name: str, model, design, sample_time: float, seed: int = 0,
                   options: Mapping | None = None) -> Compensator:
    """Build the contender ``name`` (see the module's docstring for the arguments).

    Examples
    --------
    >>> from fricctl.paper.benches import bench
    >>> from fricctl.paper.common import designs
    >>> b = bench("literal")
    >>> c = make_contender("coulomb_breakaway", b.model, designs(b)["fig13-14"], 0.002)
    >>> round(c.coulomb_pos, 3), c.name
    (0.18, 'coulomb_breakaway')
    """
    c = contender(name)
    opts = c.check_options({} if options is None else options)
    seed = v.integer("seed", seed, low=0)
    comp = c.factory(model, design, sample_time, seed, opts)
    if not isinstance(comp, Compensator):
        raise TypeError(f"contender {name!r} made a {type(comp).__name__}, not a Compensator")
    return comp
