"""Shared plotting helpers (axes creation)."""

from __future__ import annotations

import matplotlib

matplotlib.use(matplotlib.get_backend())  # never force a GUI backend
import matplotlib.pyplot as plt  # noqa: E402


def get_ax(ax=None):
    """Return ``ax`` or a new Axes on a new figure."""
    if ax is None:
        _, ax = plt.subplots(figsize=(6.4, 3.6), layout="constrained")
    return ax
