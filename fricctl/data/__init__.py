"""Data shipped with fricctl: the paper's actuator as a model file.

``paper_actuator.json`` is :func:`paper_actuator_model` written by
:meth:`fricctl.plant.JointModel.save`; it is generated, never edited by hand.
Regenerate it after a change of :mod:`fricctl.params` with ``python -m fricctl.data.write``
(``tests/test_model_file.py`` regenerates it and compares).

Examples
--------
>>> from fricctl.plant import JointModel
>>> JointModel.load(paper_actuator_file()) == paper_actuator_model()
True
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

__all__ = ["PAPER_ACTUATOR_SOURCE", "paper_actuator_file", "paper_actuator_model",
           "write_paper_actuator"]

#: The ``source`` text of the shipped model of the paper's actuator.
PAPER_ACTUATOR_SOURCE = ("Gervini, Gomes & da Rosa (2003): the paper's harmonic-drive actuator, "
                         "load side, no link (fricctl.params.paper_actuator)")


def paper_actuator_file() -> Path:
    """Path of the shipped ``paper_actuator.json`` (installed with the package)."""
    return Path(str(resources.files(__name__).joinpath("paper_actuator.json")))


def paper_actuator_model():
    """The paper's actuator (:func:`fricctl.params.paper_actuator`) as a rigid-joint model.

    Returns
    -------
    fricctl.plant.JointModel
        With sample time, encoder resolution, torque limit and each value's provenance.
    """
    from ..params import paper_actuator
    from ..plant import JointModel

    return JointModel.from_params(paper_actuator(), source=PAPER_ACTUATOR_SOURCE)


def write_paper_actuator(path=None) -> Path:
    """Write :func:`paper_actuator_model` to ``path`` (default: the shipped file)."""
    return paper_actuator_model().save(paper_actuator_file() if path is None else path)
