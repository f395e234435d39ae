"""The held-out validation of an identification (:func:`fricctl.identify.identify_record`):
the position replayed with the other half's estimate, and the equation error's torque,
each against the record."""

from __future__ import annotations

import numpy as np

from ..units import units

__all__ = ["plot_held_out", "plot_validation"]


def plot_held_out(ident, *, fig=None):
    """The held-out validation of :func:`fricctl.identify.identify_record`
    (:func:`plot_validation` of ``ident.held_out``, titled with its estimator).

    Parameters
    ----------
    ident : fricctl.identify.RecordIdentification
        With its held-out validation (``validate=True``).
    fig : matplotlib.figure.Figure, optional
        Drawn into (two axes added); default a new figure.

    Returns
    -------
    matplotlib.figure.Figure
    """
    h = ident.held_out
    if h is None or h.failure:
        raise ValueError("ident: no held-out validation to plot ("
                         + ("validate=False" if h is None else h.failure) + ")")
    r = ident.result
    return plot_validation(h, result=r, fig=fig,
                           title=f"{r.method} ({r.model}): each block replayed with the other "
                                 f"blocks' estimate")


def plot_validation(validation, *, result, title: str = "", fig=None):
    """Two panels: measured vs replayed position, measured vs predicted (low-passed) torque.

    Parameters
    ----------
    validation : fricctl.identify.Validation
        Held-out (:func:`fricctl.identify.record.held_out_halves`) or on another record
        (:func:`fricctl.identify.validate`).
    result : fricctl.identify.IdentificationResult
        The estimate checked (its units label the axes).
    title : str
    fig : matplotlib.figure.Figure, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    h = validation
    if h.failure:
        raise ValueError(f"validation: nothing to plot ({h.failure})")
    u = units(result.units)
    fig = plt.figure(figsize=(8.0, 5.5)) if fig is None else fig
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    ax1.plot(h.t, h.measured, color="0.2", lw=1.0, label="measured")
    ax1.plot(h.t, h.simulated, color="C1", lw=1.0, ls="--",
             label=f"replayed: fit {h.simulation_fit:.1f} %")
    ax1.set_ylabel(f"position - half mean [{u.position}]")
    ax1.legend(loc="upper right", fontsize=8)
    ax2.plot(h.torque_t, h.torque_measured, color="0.2", lw=0.8, label="measured (low-passed)")
    ax2.plot(h.torque_t, h.torque_predicted, color="C0", lw=0.8, ls="--",
             label=f"equation error: fit {h.equation_fit:.1f} %")
    ax2.set_ylabel(f"torque [{u.torque}]")
    ax2.set_xlabel("time [s]")
    ax2.legend(loc="upper right", fontsize=8)
    mid = np.nanmedian(h.t)
    for ax in (ax1, ax2):
        ax.axvline(mid, color="0.6", lw=0.6)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig
