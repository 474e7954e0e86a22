"""Benchmark: the trace's memory per simulated minute, bounded window and streaming to a file.

The gantry scene records every servo cycle of its three axes for two simulated minutes, idle
(the trace's cost does not depend on motion): with the default window, streaming every sample to
a .npy and to a .csv file, and keeping everything in memory. Prints JSON per mode (compiled and
pure Python): the memory the trace holds
after one and after two minutes and its growth per minute, the streamed file's size per minute,
and µs per servo cycle spent in the trace.

Run: ``python -m tests.benchmarks.trace``.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path
from typing import Any

from tests.benchmarks import report_in_both_modes

MINUTE = 60.0


def mode(name: str, **options: Any) -> dict[str, Any]:
    """Two simulated minutes of the gantry with trace ``options``, against the same scene
    without a trace run minute by minute alongside (the difference is the trace's cost)."""
    import scenes

    scene = scenes.load("gantry", **options)
    bare = scenes.load("gantry", trace_every=0)
    held = []
    spent = 0.0
    for _ in range(2):
        start = time.perf_counter()
        scene.run(timeout=MINUTE)
        spent += time.perf_counter() - start
        start = time.perf_counter()
        bare.run(timeout=MINUTE)
        spent -= time.perf_counter() - start
        held.append(scene.trace.nbytes)
    scene.trace.close()
    cycles = 2 * MINUTE / scene.runtime.servo_period
    report: dict[str, Any] = {
        "trace": name,
        "held_after_1_min_MB": round(held[0] / 1e6, 2),
        "held_after_2_min_MB": round(held[1] / 1e6, 2),
        "growth_MB_per_min": round((held[1] - held[0]) / 1e6, 2),
        "us_per_servo_cycle": round(spent / cycles * 1e6, 2),
    }
    stream = scene.trace.stream
    if stream is not None:
        report["file_MB_per_min"] = round(stream.stat().st_size / 2 / 1e6, 1)
    return report


def mode_report() -> dict[str, Any]:
    """Every trace mode in this process' mode."""
    import mcl

    with tempfile.TemporaryDirectory() as tmp:
        return {
            "mode": "compiled" if mcl.COMPILED else "pure Python",
            "traces": [
                mode("default window (30 s)"),
                mode("streamed to .npy", trace_file=Path(tmp) / "trace.npy"),
                mode("streamed to .csv", trace_file=Path(tmp) / "trace.csv"),
                mode("everything in memory", trace_seconds=1e9),
            ],
        }


def main() -> None:
    """Print the figures as JSON, compiled (where built) and pure Python."""
    report_in_both_modes("tests.benchmarks.trace", mode_report)


if __name__ == "__main__":
    main()
