"""The network's parameter vectors: :mod:`fricctl.netlayout`, under the network package's name.

The layout lives below the sampled loop (the compiled compensator reads it), so that
``import fricctl.simulate`` does not load the network package and its trainers.
"""

from ..netlayout import *  # noqa: F401,F403 - the same names
from ..netlayout import __all__  # noqa: F401
