"""``python -m scenes``: the command line (:mod:`scenes.tools.cli`)."""

import sys

from scenes.tools.cli import main

sys.exit(main())
