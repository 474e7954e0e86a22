"""Benchmarks: they print figures (JSON), they assert nothing."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from collections.abc import Callable
from typing import Any


def report_in_both_modes(module: str, report: Callable[[], dict[str, Any]]) -> None:
    """Print ``report()`` as JSON, measured in fresh processes: compiled (where built), then
    pure Python. Inside such a process (``--this-mode``) print just that mode's report."""
    if "--this-mode" in sys.argv:
        print(json.dumps(report()))
        return
    import mcl

    reports = []
    for pure in ([False] if mcl.COMPILED else []) + [True]:
        out = subprocess.run(
            [sys.executable, "-m", module, "--this-mode"],
            env={**os.environ, "MCL_PURE_PYTHON": "1" if pure else ""},
            check=True,
            capture_output=True,
            text=True,
        ).stdout
        reports.append(json.loads(out))
    print(json.dumps(reports, indent=2))
