"""Benchmark: what a cam table costs per servo cycle and when it is selected.

Prints JSON: per interpolation, a table of 10 000 points (9 999 segments), the time to check and
build it (MC_CamTableSelect's work) [ms], and one evaluation of position, slope and curvature
[µs], along the table (the master advancing as in a servo cycle: the segment is found from the
previous one) and at random master positions (a binary search each time).
Run: ``python -m tests.benchmarks.cam_table`` (in the mode mcl runs in: compiled after ``make
setup``, ``MCL_PURE_PYTHON=1`` for the interpreter).
"""

from __future__ import annotations

import json
import math
import random
import time

import mcl
from mcl.cam_table import CamLaw, MC_CamPoint, compile_cam

POINTS = 10000


def table(law: CamLaw) -> mcl.MC_CAM_REF:
    """A table of ``POINTS`` points over 1000 master units, all segments of ``law``: through a
    sine (Linear, CubicSpline), rest to rest between 0 and 10 (the motion laws)."""
    points = []
    rest = law not in (CamLaw.Linear, CamLaw.CubicSpline)
    for i in range(POINTS):
        x = i / (POINTS - 1)
        y = 10.0 * (i % 2) if rest else 10.0 * math.sin(2.0 * math.pi * x)
        points.append(MC_CamPoint(1000.0 * x, y, math.nan, math.nan, law))
    return mcl.MC_CAM_REF(Points=points)


def figures(law: CamLaw) -> dict[str, float]:
    source = table(law)
    start = time.perf_counter()
    cam = compile_cam(source, False)
    built = time.perf_counter() - start
    assert not isinstance(cam, str), cam
    n = 200000
    start = time.perf_counter()
    for i in range(n):
        cam.at(i * 0.005)
    along = time.perf_counter() - start
    masters = [random.uniform(0.0, 1000.0) for _ in range(n)]
    start = time.perf_counter()
    for m in masters:
        cam.at(m)
    scattered = time.perf_counter() - start
    return {
        "build_ms": round(built * 1e3, 1),
        "along_us": round(along / n * 1e6, 3),
        "random_us": round(scattered / n * 1e6, 3),
    }


def main() -> None:
    random.seed(1)
    laws = tuple(CamLaw)
    result: dict[str, object] = {"compiled": mcl.COMPILED, "points": POINTS}
    result.update({law.name: figures(law) for law in laws})
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
