"""Everything at once, over seeds and pipelines: train, run every figure, check and aggregate the claims.

A claim about a trained network is a claim about training seeds: for each pipeline
(:data:`fricctl.nn.pipelines.PIPELINES`) :func:`reproduce_paper` trains one network
per seed, runs every registered figure on it and checks its claims
(:func:`seed_run`, one job per network, through any ``concurrent.futures.Executor``),
then aggregates the verdicts per claim and pipeline (:mod:`fricctl.paper.table`).
The figures shown come from one *representative* seed per pipeline
(:func:`~fricctl.paper.table.representative_seed`), re-run in the calling process:
training is deterministic, so the network is the one the job judged (checked).
Everything runs on one bench (:mod:`fricctl.paper.benches`), named in the results.
"""

from __future__ import annotations

import time
from concurrent.futures import Executor, as_completed
from dataclasses import dataclass
from types import MappingProxyType
from typing import Callable, Mapping

import numpy as np

from .. import _validate as v
from ..nn import FrictionNet
from ..nn.pipelines import PIPELINES
from ..params import ActuatorParams
from .benches import Bench, as_bench
from .claims import paper_claims
from .common import AGED_SCALE, designs, gain_for_band, stuck_band
from .network import PaperNetwork, pipeline_velocity, train_paper_network
from .registry import paper_figures
from .sweep import SweepResult, robustness_sweep
from .table import aggregate_claims, claims_json, claims_markdown, holds_summary, representative_seed

__all__ = ["SeedRun", "PaperResults", "seed_run", "representative_figures", "reproduce_paper", "MAX_SEEDS"]

#: Most seeds one call accepts (a bound on the work: ~10 s of CPU per network) [-].
MAX_SEEDS = 1000


@dataclass(frozen=True, kw_only=True)
class SeedRun:
    """One network of one pipeline and its claims: what a job returns (plain, picklable data).

    Attributes
    ----------
    pipeline : ``"paper"`` or ``"fricctl"``
    seed : training seed [-]
    claims : the claims of every figure, in figure order
    net_json : the trained network (:meth:`fricctl.nn.FrictionNet.to_json`)
    gain_at_rest : ``g = dT^at/dTm`` at rest [-]
    certificate : the slope certificate (fricctl pipeline) as a dict, or None
    viscous_removed : ``b_hat`` left out of the net's target [N*m*s/rad]
    fit_percent : held-out normalised fit of the full friction estimate [%] (the reading
        of the paper's "98 %" that claim nn-fit judges)
    r_squared : held-out R^2 (variance accounted for) of the same estimate [-]
    seconds : wall time of the job [s]
    """

    pipeline: str
    seed: int
    claims: tuple
    net_json: str
    gain_at_rest: float
    certificate: dict | None
    viscous_removed: float
    fit_percent: float
    r_squared: float
    seconds: float

    @property
    def net(self) -> FrictionNet:
        """The trained network."""
        return FrictionNet.from_json(self.net_json)

    @property
    def velocity(self) -> str:
        """The velocity the pipeline's compensator feeds the network
        (:attr:`fricctl.paper.PaperNetwork.velocity`)."""
        return pipeline_velocity(self.pipeline)

    @property
    def n_passed(self) -> int:
        """Claims passed (the paper's and the extras) [-]."""
        return sum(c.passed for c in self.claims)


def _figures(network: PaperNetwork) -> dict:
    return {num: fig.run(network) for num, fig in paper_figures().items()}


def representative_figures(bench: Bench, fast: bool, pipeline: str, seed: int,
                           net_json: str | None = None):
    """Train (or read from the cache) one network again on ``bench`` and run every figure on it.

    Returns ``(network, figures)``.  With ``net_json`` (the network its job judged) the
    network trained here must be that one (training is deterministic).

    Raises
    ------
    RuntimeError
        The network differs from ``net_json``.
    """
    net = train_paper_network(bench=bench, fast=fast, seed=seed, pipeline=pipeline)
    if net_json is not None and net.net.to_json() != net_json:
        raise RuntimeError(f"{pipeline} seed {seed}: the network trained again differs from the one "
                           "its job judged (training is not deterministic)")
    return net, MappingProxyType(_figures(net))


def seed_run(bench: Bench, fast: bool, pipeline: str, seed: int) -> SeedRun:
    """Train one network on ``bench`` and check every claim on it (one job of :func:`reproduce_paper`).

    Module-level and fed plain data (a bench pickles as its file's content), so that a
    process pool can run it.
    """
    t0 = time.perf_counter()
    network = train_paper_network(bench=bench, fast=fast, seed=seed, pipeline=pipeline)
    claims = tuple(paper_claims(_figures(network), network.bench))
    cert = network.trained.certificate
    return SeedRun(pipeline=pipeline, seed=seed, claims=claims, net_json=network.net.to_json(),
                   gain_at_rest=network.net.gain_at_rest(),
                   certificate=None if cert is None else cert.as_dict(),
                   viscous_removed=float(network.trained.viscous_removed),
                   fit_percent=float(network.fit_held_out.fit_percent),
                   r_squared=float(network.fit_held_out.r_squared),
                   seconds=time.perf_counter() - t0)


@dataclass(frozen=True, eq=False, kw_only=True)
class PaperResults:
    """Every network's claims, and the figures of one representative seed per pipeline.

    Attributes
    ----------
    params : the actuator (the bench's true plant)
    bench : the bench everything ran on
    fast : whether the short experiments were used
    seeds : the training seeds, 0 .. N-1 [-]
    pipelines : the pipelines, in table order
    runs : ``(pipeline, seed)`` -> :class:`SeedRun`
    representative : pipeline -> the seed whose figures are shown
    networks : pipeline -> the representative :class:`PaperNetwork` (empty when
        ``reproduce_paper(figures=False)``)
    figures : pipeline -> (figure number -> result) of the representative network (idem)
    sweeps : pipeline -> robustness sweep of the representative network
    stats : per claim and pipeline over the seeds (:class:`~fricctl.paper.table.ClaimStats`)
    """

    params: ActuatorParams
    bench: Bench
    fast: bool
    seeds: tuple
    pipelines: tuple
    runs: Mapping
    representative: Mapping
    networks: Mapping
    figures: Mapping
    sweeps: Mapping
    stats: tuple

    def claims(self, pipeline: str, seed: int | None = None) -> tuple:
        """The claims of one network (default: the pipeline's representative seed)."""
        seed = self.representative[pipeline] if seed is None else seed
        return self.runs[(pipeline, seed)].claims

    def summary(self) -> str:
        """One line per pipeline: ``"<pipeline>: N of M claims of the paper hold in >= 90 % of K seeds"``."""
        return "\n".join(f"{p}: {holds_summary(self.stats, p)}" for p in self.pipelines)

    def why(self) -> list[str]:
        """Why some claims cannot hold on this bench, with the numbers of this run."""
        p = self.params
        fs = p.static
        kp14 = designs(self.bench)["fig13-14"].kp
        kp16 = designs(self.bench)["fig16-17"].kp
        g_needed = gain_for_band(np.deg2rad(0.3), fs, kp14)
        out = []
        for name in self.pipelines:
            g = np.array([self.runs[(name, s)].gain_at_rest for s in self.seeds])
            gm = float(np.median(g))
            text = (f"**{name} pipeline, dead zone against accuracy:** gain at rest g = {gm:.3f} (median; "
                    f"{g.min():.3f}-{g.max():.3f} over {g.size} seeds). While stuck the compensated loop "
                    "settles at Tm = Tc/(1 - g), so the joint breaks away once |Tc| > Fs*(1 - g), and a "
                    "stuck PD loop stops anywhere within +-Fs*(1 - g)/Kp of the reference: with "
                    f"Fs = {fs:.3f} N*m and Fig. 14's Kp = {kp14:.3f} N*m/rad ")
            if gm < 1:
                text += (f"that is +-{np.rad2deg(stuck_band(fs, gm, kp14)):.2f} deg. A dead-zone reduction of x "
                         f"is a gain g = 1 - 1/x: the paper's ~6x (g = 0.83) leaves +-"
                         f"{np.rad2deg(fs / 6 / kp14):.2f} deg, and < 0.3 deg from every approach needs "
                         f"g >= {g_needed:.3f} (a reduction >= {1 / (1 - g_needed):.0f}x).")
            else:
                text += ("there is no such band: with g >= 1 the stuck loop has no fixed point below "
                         "breakaway, the motor torque winds up until the joint breaks loose, and the "
                         "compensated joint runs away (the runaway checks).")
            out.append(text)
            if gm < 1:
                sg = AGED_SCALE * gm
                band = stuck_band(AGED_SCALE * fs, gm, kp16, AGED_SCALE)
                # the g whose band AGED_SCALE*Fs*(1 - s*g)/Kp is the paper's 0.3 deg
                g_aged = gain_for_band(np.deg2rad(0.3), AGED_SCALE * fs, kp16, AGED_SCALE)
                out.append(
                    f"**{name} pipeline, Figs. 16-17 (s = {AGED_SCALE:g}, friction x {AGED_SCALE:g}):** "
                    f"the stuck loop's gain is s*g = {sg:.3f}, which leaves "
                    f"+-{AGED_SCALE:g}*Fs*(1 - s*g)/Kp = +-{np.rad2deg(band):.2f} deg with the link "
                    f"design's Kp = {kp16:.3f} N*m/rad in the worst case: the 0.3 deg of fig16-nn and "
                    "fig17-nn is not guaranteed for every approach; it holds where the joint happens to "
                    "stop closer to the reference. A band under 0.3 deg at this s would need "
                    f"g >= {g_aged:.3f}" + (", above 1, where the same network at s = 1 winds the torque "
                    "up: no certificate of g can give these two claims, only where the joint's approach "
                    "ends." if g_aged >= 1 else "."))
        out.append(self._statements())
        return out

    def _statements(self) -> str:
        """What the bench's own uncompensated torques allow, with its numbers: whether Figs. 11,
        17 and 18 can move at all (``Kp*r`` against the breakaway level)."""
        g, fs = designs(self.bench), self.params.static
        b = self.bench
        rows = ((f"Fig. 11 (Kp*25 deg, {b.rise_time_reading} rise time)", g["fig11-12"].kp * np.deg2rad(25.0)),
                ("Fig. 17 (Kp*0.08 rad)", g["fig16-17"].kp * 0.08),
                (f"Fig. 18 (Kp*{b.fig18_amplitude:g} rad)", g["fig18"].kp * b.fig18_amplitude))
        cells = "; ".join(f"{what} = {x:.3f} N*m {'>' if x > fs else '<='} Fs" for what, x in rows)
        return (f"**The paper's own statements on the {b.name} bench**: without compensation the "
                f"commanded torques are {cells} = {fs:.3f} N*m (a joint whose torque stays below Fs "
                "never moves). Which readings of the paper let all its statements hold is tabulated, "
                "with the unknowns searched, in [docs/paper_consistency.md](docs/paper_consistency.md).")

    def markdown(self) -> str:
        """``claims.md``."""
        n = len(self.seeds)
        pre = (f"Bench **{self.bench.name}** (`fricctl reproduce --bench {self.bench.name}`): "
               f"{self.bench.description}\n\n"
               f"Virtual bench, {'fast' if self.fast else 'full'} run: {n} training "
               f"seed{'s' if n != 1 else ''} (0-{n - 1}) per pipeline. Assumptions of the experiments "
               "are listed in `fricctl.paper`'s module docstring. Every network is in "
               "`nets/<pipeline>-seed<K>.json` (re-run one with "
               "`fricctl simulate --compensation nn_confirmed --net nets/fricctl-seed<K>.json`, the "
               "fricctl pipeline's direction-confirmed velocity; `--compensation nn --net "
               "nets/paper-seed<K>.json`, the paper's backward difference).\n\n"
               "| pipeline | seed | gain at rest g | held-out fit [%] | held-out R^2 | claims passed | "
               "certified |\n"
               "|---|---|---|---|---|---|---|\n")
        rows = []
        for p in self.pipelines:
            for s in self.seeds:
                r = self.runs[(p, s)]
                cert = "--" if r.certificate is None else ("yes" if r.certificate["passed"] else "**no**")
                mark = " (figures)" if s == self.representative[p] else ""
                rows.append(f"| {p} | {s}{mark} | {r.gain_at_rest:.3f} | {r.fit_percent:.1f} | "
                            f"{r.r_squared:.3f} | {r.n_passed} of {len(r.claims)} | {cert} |")
        pre += "\n".join(rows)
        sweeps = "## Robustness sweeps (not claims of the paper)"
        for p in self.pipelines:
            sweeps += (f"\n\n{p} pipeline, seed {self.representative[p]}:\n\n```text\n{self.sweeps[p].report()}"
                       "\n```")
        return claims_markdown(self.stats, preamble=pre, why=self.why(), appendix=sweeps,
                               title="Claims of Gervini, Gomes & da Rosa (2003) on the virtual bench "
                               f"({self.bench.name})")

    def json(self) -> str:
        """``claims.json`` (strict JSON, one object per claim and pipeline, each naming the bench)."""
        return claims_json(self.stats, bench=self.bench.name)


def _check_pipelines(pipelines) -> tuple:
    if isinstance(pipelines, str):
        pipelines = (pipelines,)
    try:
        names = tuple(pipelines)
    except TypeError:
        raise ValueError(f"pipelines must be a sequence of names, got {type(pipelines).__name__}") from None
    if not names:
        raise ValueError("pipelines must name at least one pipeline")
    for n in names:
        v.choice("pipelines", n, tuple(PIPELINES))
    if len(set(names)) != len(names):
        raise ValueError(f"pipelines must not repeat a name, got {list(names)}")
    return names


def reproduce_paper(params: ActuatorParams | None = None, *, bench=None, fast: bool = False,
                    seeds: int = 10, pipelines=("paper", "fricctl"), executor: Executor | None = None,
                    progress: Callable[[int, int, str], None] | None = None,
                    figures: bool = True) -> PaperResults:
    """Train ``seeds`` networks per pipeline, run every figure on each, aggregate the claims.

    Parameters
    ----------
    params : ActuatorParams, optional
        Replaces the bench's plant, designed on as it is (its own b).
    bench : str or Bench, optional
        The bench (:data:`fricctl.paper.benches.BENCHES`; default
        :data:`~fricctl.paper.benches.DEFAULT_BENCH`, or with ``params`` alone
        :data:`~fricctl.paper.benches.PARAMS_BENCH`: :func:`~fricctl.paper.benches.as_bench`).
    fast : bool
        Short training experiments and a small sweep grid.
    seeds : int
        Networks per pipeline, trained with seeds 0 .. seeds-1 [-] (1 .. :data:`MAX_SEEDS`).
    pipelines : sequence of str
        Names in :data:`fricctl.nn.pipelines.PIPELINES`, in table order.
    executor : concurrent.futures.Executor, optional
        Runs the jobs (:func:`seed_run`, one per network).  Default: in this process.  A
        process pool must use the ``"spawn"`` start method
        (``mp_context=multiprocessing.get_context("spawn")``): forking a process whose
        numba/OpenMP threads have started aborts the workers.
    progress : callable, optional
        ``progress(done, total, name)`` as jobs finish.
    figures : bool
        Re-run the representative seed of each pipeline here and keep its network and
        figure results (:func:`representative_figures`); False leaves that to the caller
        (``fricctl reproduce`` draws them in its worker processes).

    Returns
    -------
    PaperResults

    Raises
    ------
    RuntimeError
        The representative network re-trained here differs from the one its job judged
        (training would not be deterministic).
    """
    b = as_bench(bench, params)
    p = b.actuator
    fast = v.flag("fast", fast)
    n = v.integer("seeds", seeds, low=1, high=MAX_SEEDS)
    names = _check_pipelines(pipelines)
    if executor is not None and not hasattr(executor, "submit"):
        raise ValueError(f"executor must be a concurrent.futures.Executor, got {type(executor).__name__}")
    # pipeline by pipeline: the jobs of one seed never run at once, so the second reads what the
    # first left in the disk cache of trained nets (Fig. 8's exact-pattern net is the same)
    jobs = [(name, s) for name in names for s in range(n)]
    keep_figures = v.flag("figures", figures)
    total = len(jobs) + (len(names) if keep_figures else 0) + 1

    def tick(i, what):
        if progress is not None:
            progress(i, total, what)

    tick(0, "training")
    runs = {}
    if executor is None:
        for i, (name, s) in enumerate(jobs, start=1):
            runs[(name, s)] = seed_run(b, fast, name, s)
            tick(i, f"{name} seed {s}")
    else:
        futures = {executor.submit(seed_run, b, fast, name, s): (name, s) for name, s in jobs}
        for i, f in enumerate(as_completed(futures), start=1):
            runs[futures[f]] = f.result()
            tick(i, "{} seed {}".format(*futures[f]))
    runs = {k: runs[k] for k in sorted(runs, key=lambda k: (names.index(k[0]), k[1]))}
    rep = {name: representative_seed({s: runs[(name, s)].n_passed for s in range(n)}) for name in names}
    networks, figs, sweeps = {}, {}, {}
    grid = dict(friction_scales=(0.8, 1.0, 1.2), link_inertias=(0.0, 0.0046)) if fast else {}
    for i, name in enumerate(names, start=len(jobs) + 1):
        run = runs[(name, rep[name])]
        # its rows (one per link inertia) through the same executor: deterministic, so the same numbers
        sweeps[name] = robustness_sweep(run.net, p, design=designs(b)["fig16-17"], executor=executor,
                                        velocity=run.velocity, **grid)
        if keep_figures:
            networks[name], figs[name] = representative_figures(b, fast, name, rep[name], run.net_json)
            tick(i, f"{name} seed {rep[name]} figures")
    tick(total, "done")
    return PaperResults(
        params=p, bench=b, fast=fast, seeds=tuple(range(n)), pipelines=names, runs=MappingProxyType(runs),
        representative=MappingProxyType(rep), networks=MappingProxyType(networks),
        figures=MappingProxyType(figs), sweeps=MappingProxyType(sweeps),
        stats=aggregate_claims({k: r.claims for k, r in runs.items()}, rep))

