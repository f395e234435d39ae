"""fricctl: neural-network friction compensation of a geared robot drive joint.

A textbook companion to Gervini, Gomes & da Rosa, "A new robotic drive joint
friction compensation mechanism using neural networks", J. Braz. Soc. Mech. Sci.
& Eng. 25(2), 2003.

Layers (dependencies flow one way; ``docs/architecture.md``)::

    _validate, units, params -> friction -> plant -> simulate, compensators, controllers
      -> estimation, datasets -> identify, design, nn -> bench, diagnose, paper
      -> figures, cli

``import fricctl`` does not import matplotlib; only :mod:`fricctl.figures` and
the command line do.
"""

__version__ = "0.1.0"

from .params import ActuatorParams, paper_actuator  # noqa: E402,F401

__all__ = ["ActuatorParams", "paper_actuator", "__version__"]
