import os

import matplotlib
import pytest

matplotlib.use("Agg")


def pytest_configure(config):
    # Trained networks are cached on disk (fricctl.nn.cache); the tests use a fresh cache per
    # session (shared with the chapters they run in subprocesses), never the user's.
    if "FRICCTL_CACHE" not in os.environ:
        import tempfile

        os.environ["FRICCTL_CACHE"] = tempfile.mkdtemp(prefix="fricctl-cache-")


@pytest.fixture(scope="session")
def data_dir():
    """The shared data folder (FRICCTL_DATA), or skip with the reason."""
    from pathlib import Path

    d = os.environ.get("FRICCTL_DATA")
    if not d or not (Path(d) / "emps" / "DATA_EMPS.mat").is_file():
        pytest.skip("EMPS data not found: set FRICCTL_DATA to the folder holding emps/DATA_EMPS.mat")
    return Path(d)


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    import matplotlib.pyplot as plt

    plt.close("all")


@pytest.fixture(scope="session")
def points_under_legend():
    """A function of an Axes: how many points of its lines (and of their segments, sampled)
    lie inside its legend's box in display coordinates -- 0 when the legend hides no data
    (issue 24 item 7; ``tests/test_figures_legends.py`` checks that it finds an overlap)."""
    import numpy as np

    def points_under_legend(ax) -> int:
        """How many points (and sampled points of segments) of ``ax``'s lines lie inside its
        legend's box, in display coordinates."""
        legend = ax.get_legend()
        assert legend is not None, "no legend"
        fig = ax.figure
        fig.canvas.draw()
        box = legend.get_window_extent(fig.canvas.get_renderer())
        clip = ax.get_window_extent()
        inside = 0
        for line in ax.get_lines():
            xy = np.column_stack([line.get_xdata(), line.get_ydata()]).astype(float)
            xy = xy[np.all(np.isfinite(xy), axis=1)]
            if len(xy) == 0:
                continue
            pts = line.get_transform().transform(xy)  # data, or axes (axhline) coordinates
            if len(pts) > 1:  # 8 samples on each segment
                f = np.linspace(0.0, 1.0, 9)[:-1, None, None]
                pts = (pts[:-1] + f * (pts[1:] - pts[:-1])).reshape(-1, 2)
            # only what is drawn: points inside the axes (a line clipped by the axes is not seen)
            shown = ((pts[:, 0] >= clip.x0) & (pts[:, 0] <= clip.x1)
                     & (pts[:, 1] >= clip.y0) & (pts[:, 1] <= clip.y1))
            under = ((pts[:, 0] >= box.x0) & (pts[:, 0] <= box.x1)
                     & (pts[:, 1] >= box.y0) & (pts[:, 1] <= box.y1))
            inside += int(np.sum(shown & under))
        return inside

    return points_under_legend
