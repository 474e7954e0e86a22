"""``python -m scenes``: the command line (:mod:`scenes.tools.cli`)."""

__all__: list[str] = []

import sys

from scenes.tools.cli import main

sys.exit(main())
