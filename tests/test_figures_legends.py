"""No legend hides data (issue 24 item 7): the root locus here, the paper's Fig. 12 in
``tests/test_paper.py``, both with the ``points_under_legend`` fixture of ``conftest.py``
(a legend's box, in display coordinates after drawing, holds no point of a plotted line nor
of the segments between them; Agg, artists and coordinates, not pixels).
"""

from __future__ import annotations

import warnings

import matplotlib.pyplot as plt
import numpy as np
import pytest

from fricctl.design import design_p, design_pd
from fricctl.params import paper_actuator


def test_the_check_sees_a_legend_on_data(points_under_legend):
    """The measure itself finds a legend placed on the lines (else the tests prove nothing)."""
    fig, ax = plt.subplots(figsize=(6.4, 3.6), layout="constrained")
    x = np.linspace(0.0, 1.0, 200)
    ax.plot(x, np.full_like(x, 0.5), label="flat line")
    ax.plot(x, x, label="diagonal")
    ax.set_ylim(0.0, 1.0)
    ax.legend(loc="center")
    assert points_under_legend(ax) > 0


@pytest.mark.parametrize("law", ["p", "pd"])
def test_root_locus_legend_covers_no_data(law, points_under_legend):
    from fricctl.figures import plot_root_locus

    p = paper_actuator()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the design's own warnings are not the point here
        d = (design_p(p, rise_time=0.2, damping=0.3) if law == "p"
             else design_pd(p, rise_time=0.25, damping=0.9))
    ax = plot_root_locus(d)
    assert len(ax.get_legend().get_texts()) >= 3
    assert points_under_legend(ax) == 0
