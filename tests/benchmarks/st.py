"""Benchmark: the cost of one PLC scan of each machine's demo in Structured Text
(examples/st/<machine>_demo.st, translated by plc.st) against its Python version.

Each demo runs from its demo start to its end; only the program's calls are timed (not the
servo cycles or the physics between them), so the figure is what the program itself costs per
scan. The ST and the Python demo run side by side, a PLC cycle of one then a PLC cycle of the
other, so that a burst of another process on a shared machine falls on both alike. Each pair
runs :data:`REPEATS` times; printed per machine: the median over the runs of µs per scan of the
ST demo, of the Python demo and of their ratio (target ≤ 1.2), every run's ratio, and the
ratio of the least cost of each scan over the runs (the demos are deterministic: scan n does
the same work in every run, so its least time is its cost without interruptions). As JSON per
mode (compiled where built, then pure Python, each in a fresh process).

Run: ``python -m tests.benchmarks.st``.
"""

from __future__ import annotations

import statistics
import time
from typing import Any

from tests.benchmarks import report_in_both_modes

MACHINES = ("gantry", "flying_shear", "press")
"""The machines whose demos exist in ST."""
REPEATS = 5
"""Runs of each pair of demos."""


def side_by_side(machine: str) -> tuple[list[float], list[float]]:
    """Seconds of each PLC scan of the machine's ST demo and of its Python demo, run
    alternately one PLC cycle each, each to its end."""
    import scenes
    from tests.plc.st.test_demos import st_demo

    clock = time.perf_counter
    runs = []
    for st in (True, False):
        scene = scenes.load(machine, start=scenes.definition(machine).demo_start, trace_every=0)
        program: Any = st_demo(scene) if st else scenes.demo(scene)
        spent: list[float] = []

        def scan(program: Any = program, spent: list[float] = spent) -> None:
            start = clock()
            program()
            spent.append(clock() - start)

        runs.append((scene, program, scan, spent))
    period = runs[0][0].runtime.plc_period
    while not all(program.done or program.error for _, program, _, _ in runs):
        for scene, program, scan, _ in runs:
            if not (program.done or program.error):
                scene.run(scan, timeout=period)
    return runs[0][3], runs[1][3]


def report() -> dict[str, Any]:
    """Per machine: µs per scan of the ST and the Python demo (medians over the runs), their
    ratio, every run's ratio, and the ratio of the scans' least costs."""
    import mcl

    figures: dict[str, Any] = {"mode": "compiled" if mcl.COMPILED else "pure Python"}
    for machine in MACHINES:
        pairs = [side_by_side(machine) for _ in range(REPEATS)]
        st = [sum(s) / len(s) * 1e6 for s, _ in pairs]
        python = [sum(p) / len(p) * 1e6 for _, p in pairs]
        ratios = [s / p for s, p in zip(st, python, strict=True)]
        least_st = sum(min(scan) for scan in zip(*(s for s, _ in pairs), strict=True))
        least_python = sum(min(scan) for scan in zip(*(p for _, p in pairs), strict=True))
        figures[machine] = {
            "st_us_per_scan": round(statistics.median(st), 2),
            "python_us_per_scan": round(statistics.median(python), 2),
            "ratio": round(statistics.median(ratios), 3),
            "ratios": [round(r, 3) for r in ratios],
            "least_cost_ratio": round(least_st / least_python, 3),
        }
    return figures


if __name__ == "__main__":
    report_in_both_modes("tests.benchmarks.st", report)
