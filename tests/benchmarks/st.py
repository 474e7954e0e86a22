"""Benchmark: the cost of one PLC scan of each machine's demo in Structured Text
(examples/st/<machine>_demo.st, translated by mcl.st) against its Python version.

Each demo runs from its demo start to its end; only the program's calls are timed (not the
servo cycles or the physics between them), so the figure is what the program itself costs per
scan: µs per scan of the ST demo and of the Python demo, and their ratio (target ≤ 1.2). Each
runs :data:`REPEATS` times, the fastest counting (a burst of another process on a shared
machine does not count). Printed as JSON per mode (compiled where built, then pure Python, each
in a fresh process).

Run: ``python -m tests.benchmarks.st``.
"""

from __future__ import annotations

import time
from typing import Any

from tests.benchmarks import report_in_both_modes

MACHINES = ("gantry", "flying_shear", "press")
"""The machines whose demos exist in ST."""
REPEATS = 3
"""Runs of each demo; the fastest counts."""


def per_scan(machine: str, st: bool) -> float:
    """µs per PLC scan of the machine's demo (ST or Python), over a whole run to its end."""
    import scenes
    from tests.test_st_demos import st_demo

    scene = scenes.load(machine, start=scenes.definition(machine).demo_start, trace_every=0)
    program: Any = st_demo(scene) if st else scenes.demo(scene)
    spent = [0.0, 0]
    clock = time.perf_counter

    def scan() -> None:
        start = clock()
        program()
        spent[0] += clock() - start
        spent[1] += 1

    scene.run(scan, until=lambda: program.done or program.error, timeout=120.0)
    return spent[0] / spent[1] * 1e6


def report() -> dict[str, Any]:
    """Per machine: µs per scan of the ST and the Python demo, and their ratio."""
    import mcl

    figures: dict[str, Any] = {"mode": "compiled" if mcl.COMPILED else "pure Python"}
    for machine in MACHINES:
        st = min(per_scan(machine, True) for _ in range(REPEATS))
        python = min(per_scan(machine, False) for _ in range(REPEATS))
        figures[machine] = {
            "st_us_per_scan": round(st, 2),
            "python_us_per_scan": round(python, 2),
            "ratio": round(st / python, 3),
        }
    return figures


if __name__ == "__main__":
    report_in_both_modes("tests.benchmarks.st", report)
