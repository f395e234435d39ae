"""Shared plotting helpers (axes creation)."""

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
