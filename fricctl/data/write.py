"""``python -m fricctl.data.write``: regenerate ``paper_actuator.json`` from :mod:`fricctl.params`."""

from . import write_paper_actuator

if __name__ == "__main__":  # pragma: no cover
    print(write_paper_actuator())
