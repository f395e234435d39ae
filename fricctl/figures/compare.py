"""The compensator comparison (:mod:`fricctl.compare`): one experiment's metric over the plants."""

from __future__ import annotations

import numpy as np

from .. import _validate as v
from ._common import get_ax

__all__ = ["plot_comparison"]


def plot_comparison(result, *, experiment: str, metric: str, ax=None):
    """One metric of one experiment: every compensator (markers at the median over the seeds,
    bars from the smallest to the largest seed) on every plant of the comparison.

    Parameters
    ----------
    result : fricctl.compare.ComparisonResult
    experiment : str
        One of ``result.experiments``.
    metric : str
        One of that experiment's metrics (:data:`fricctl.compare.METRICS`).
    ax : matplotlib.axes.Axes, optional

    Returns
    -------
    matplotlib.axes.Axes
        Plants on the x axis; a run whose runaway checks failed is drawn with an open marker.
    """
    from ..compare import METRICS, ComparisonResult, experiment as _experiment

    v.instance("result", result, ComparisonResult, "a ComparisonResult (fricctl.compare.compare)")
    v.choice("experiment", experiment, result.experiments)
    v.choice("metric", metric, _experiment(experiment).metrics)
    ax = get_ax(ax)
    plants = [p["name"] for p in result.plants]
    x = np.arange(len(plants), dtype=float)
    n = len(result.compensators)
    width = 0.8 / max(n, 1)
    for i, name in enumerate(result.compensators):
        rows = [result.row(name, experiment, p) for p in plants]
        med = np.array([np.nan if r["metrics"][metric]["median"] is None else r["metrics"][metric]["median"]
                        for r in rows])
        lo = np.array([np.nan if r["metrics"][metric]["min"] is None else r["metrics"][metric]["min"]
                       for r in rows])
        hi = np.array([np.nan if r["metrics"][metric]["max"] is None else r["metrics"][metric]["max"]
                       for r in rows])
        ok = np.array([not r["runaway"]["failures"] for r in rows])  # not judged is not failed
        xi = x - 0.4 + width * (i + 0.5)
        color = f"C{i % 10}"
        ax.errorbar(xi, med, yerr=np.vstack([med - lo, hi - med]), fmt="none", capsize=2, lw=1,
                    color=color)
        ax.plot(xi[ok], med[ok], "o", color=color, label=name)
        ax.plot(xi[~ok], med[~ok], "o", mfc="none", color=color)
    unit = METRICS[metric][0]
    ax.set_xticks(x, plants, rotation=30, ha="right")
    ax.set_xlabel("plant")
    ax.set_ylabel(f"{metric} [{unit}]")
    ax.set_title(f"{experiment}: median and range over seeds (open marker: a runaway check failed)",
                 fontsize="small")
    ax.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.0, 1.0))  # never over a point
    return ax
