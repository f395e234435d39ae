"""Shared plotting helpers (axes creation, a legend that leaves the data visible)."""

from __future__ import annotations


def get_ax(ax=None):
    """Return ``ax`` or a new Axes on a new figure (pyplot is imported only then: a caller
    that draws on its own axes, such as ``fricctl diagnose --report``, never loads it)."""
    if ax is None:
        import matplotlib

        matplotlib.use(matplotlib.get_backend())  # never force a GUI backend
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=(6.4, 3.6), layout="constrained")
    return ax


def legend_beside(ax, **kwargs):
    """The legend of ``ax`` to the right of the axes, outside the data: it can never hide a
    plotted point, wherever the lines go (a root locus, an oscillation that fills the plot;
    ``loc="best"`` still covers data when no empty corner is large enough).  In a figure with
    ``layout="constrained"`` (what :func:`get_ax` makes) the axes shrink to make room."""
    kwargs.setdefault("fontsize", "small")
    return ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0, **kwargs)
