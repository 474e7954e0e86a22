"""Benchmark: the gantry demo on MuJoCo, against the bare physics of the same model.

Prints JSON: the demo's real-time factor (whole stack: PLC program, mcl, plant I/O, MuJoCo),
the bare-physics real-time factor (mj_step alone on the same model and timestep), their ratio,
the peak following error per axis, and the contour error of the pick-and-place path: the largest
distance of the MuJoCo `tool` site from the ideal straight segments, over the whole path and on
the straight parts away from the blended corners.
Run: ``python -m tests.benchmarks.gantry``.
"""

from __future__ import annotations

import json
import time

import mujoco
import numpy as np

from scenes import gantry
from scenes.contour import distance_to_polyline


def run(trace_every: int) -> dict[str, object]:
    """One demo run; timing figures and accuracy from the physics."""
    scene = gantry.build(start={"X": 0.43, "Y": 0.27, "Z": -0.12}, trace_every=trace_every)
    program = gantry.Demo(scene)
    model, data = scene.model, scene.data
    tool = model.site("gantry/tool").id
    samples: list[np.ndarray] = []

    def sample(t: float) -> None:
        if program.step in ("move over the part", "carry to the place position", "return to park"):
            samples.append(data.site_xpos[tool].copy())

    scene.runtime.observers.append(sample)
    start = time.perf_counter()
    scene.run(program, until=lambda: program.done or bool(program.error), timeout=120.0)
    wall = time.perf_counter() - start
    simulated = scene.time

    steps = round(simulated / model.opt.timestep)
    bare_data = mujoco.MjData(model)
    start = time.perf_counter()
    for _ in range(steps):
        mujoco.mj_step(model, bare_data)
    bare = time.perf_counter() - start

    # ideal path in world coordinates [m]: tool = offset + joint coordinates, and the homed
    # coordinates [mm] equal the joint coordinates; it starts where the first move started
    offset = data.site_xpos[tool] - np.array([scene.joint_position(a) for a in "XYZ"])
    corners = [offset + np.array(p) / 1000.0 for batch in gantry.PATH for p, _ in batch]
    vertices = [samples[0], *corners]
    points = np.array(samples[1:])
    errors = distance_to_polyline(points, vertices) * 1e6
    corner_zone = 0.005  # m: 5 mm around each corner holds the blends
    far = np.min([np.linalg.norm(points - c, axis=1) for c in vertices], axis=0) > corner_zone
    result: dict[str, object] = {
        "trace_every": trace_every,
        "simulated_s": round(simulated, 3),
        "demo_real_time_factor": round(simulated / wall, 1),
        "bare_physics_real_time_factor": round(simulated / bare, 1),
        "ratio": round(bare / wall, 2),
        "us_per_servo_cycle": round(wall / simulated * 1e3, 2),
        "peak_following_error_um": {
            a: round(max(abs(e) for e in scene.trace.column(a, "following_error")) * 1e3, 1)
            for a in "XYZ"
        }
        if trace_every
        else "trace off",
        "contour_error_um_max": round(float(errors.max()), 1),
        "contour_error_um_straight_parts": round(float(errors[far].max()), 1),
        "demo_error": program.error,
    }
    return result


def main() -> None:
    """Print the benchmark as JSON (with and without the per-cycle trace)."""
    print(json.dumps([run(trace_every=1), run(trace_every=0)], indent=2))


if __name__ == "__main__":
    main()
