"""The block diagram of the compensated loop (paper Eq. 3): drawn, labelled, refused on bad input."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402

from fricctl import figures  # noqa: E402
from fricctl.figures import plot_compensation_loop  # noqa: E402


def _texts(ax):
    return [t.get_text() for t in ax.texts]


@pytest.mark.parametrize("closed", [False, True])
def test_draws_the_labelled_blocks(closed):
    fig, ax = plt.subplots()
    out = plot_compensation_loop(ax, closed=closed)
    assert out is ax
    text = "\n".join(_texts(ax))
    for label in ("ZOH", "joint", "encoder", "velocity estimate", "net", "$z^{-1}$", "$\\times s$",
                  "$T_m(k)$", "$T_c(k)$"):
        assert label in text, label
    assert ("P / PD" in text) is closed          # the controller only in the closed loop
    assert ("$r$" in _texts(ax)) is closed
    assert len(ax.patches) == (10 if closed else 8)  # 7 blocks + 1 sum; closed: +1 block, +1 sum
    fig.canvas.draw()                            # renders (mathtext parses) without error
    plt.close(fig)


def test_new_axes_and_export():
    ax = figures.plot_compensation_loop()
    assert ax.figure is not None and not ax.axison
    plt.close(ax.figure)


def test_bad_closed_refused():
    with pytest.raises(ValueError, match="closed"):
        plot_compensation_loop(closed="yes")
