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
