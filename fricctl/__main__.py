"""``python -m fricctl`` is the ``fricctl`` command."""

import sys

from .cli import main

sys.exit(main())
