"""Benchmark: the gantry as a machine, every figure measured on the MuJoCo physics.

Prints JSON:

- ``demo``: the demo's real-time factor (whole stack: PLC program, mcl, plant I/O, MuJoCo), the
  bare-physics real-time factor (mj_step alone on the same model and timestep), their ratio, the
  peak following error per axis, and the contour error of the pick-and-place path (largest
  distance of the `tool` site from the ideal straight segments, over the whole path and away from
  the blended corners); with and without the per-cycle trace;
- ``moves_400_mm_s``: per axis and direction, a jerk-limited 200 mm move at 400 mm/s (the axis'
  default ramps): peak following error and overshoot at the stop [µm] (set point against the
  joint coordinate), settling time into ±5 µm [ms];
- ``contour``: the 3-D zigzag of ``scenes.machines.gantry.ZIGZAG`` at 200 and 300 mm/s,
  Buffered (largest error, right after the corners included) and BlendingLow with a 50 µm
  corner tolerance (largest error at the corners and on the straight parts) [µm];
- ``lim_stop_at_vmax``: MC_MoveVelocity at Vmax onto each limit switch: speed at the trip, stopping
  distance from the trip, room left to the hard stop [mm] and the hard stop's force [N];
- ``force_on_stop_after_block_homing``: MC_StepBlock + MC_StepDirect and GT_MoveAbsBlock's
  TorqueLimit stop: the force on the block over 20 s of holding (``tests.benchmarks.block_homing``);
- ``ref_index_homing_repeatability``: REF + index homing of X from 10 starts with the real
  sensors: where the origin lands against the index [µm].

Run: ``python -m tests.benchmarks.gantry``.
"""

from __future__ import annotations

import json
import time
from typing import Any

import mujoco
import numpy as np

import mcl
from scenes.machines import gantry
from scenes.tools import commissioning
from scenes.tools.contour import distance_to_polyline, run_path
from tests.benchmarks.block_homing import block_forces

MOVES = {  # axis: (start for the positive move, start for the negative move) [m]
    "X": (0.30, 0.55),
    "Y": (0.20, 0.45),
    "Z": (-0.22, -0.02),
}
LIMITS = {  # axis: (start towards LIM+, start towards LIM−) [m], room to reach Vmax
    "X": (0.75, 0.25),
    "Y": (0.35, 0.25),
    "Z": (-0.15, -0.10),
}
CORNER_TOLERANCE = 0.05
"""Corner tolerance of the blended zigzag [mm]."""


def demo(trace_every: int) -> dict[str, object]:
    """One demo run; timing figures and accuracy from the physics."""
    scene = gantry.build(start=dict(gantry.MACHINE.demo_start), trace_every=trace_every)
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
    return {
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
        "corner_tolerance_um": round(program.group.corner_tolerance * 1e3, 1),
        "contour_error_um_max": round(float(errors.max()), 1),
        "contour_error_um_straight_parts": round(float(errors[far].max()), 1),
        "demo_error": program.error,
    }


def moves() -> dict[str, dict[str, float]]:
    """Point-to-point moves at 400 mm/s, each way on each axis (goals: ≤ 30 µm, ≤ 5 µm, ≤ 50 ms)."""
    out: dict[str, dict[str, float]] = {}
    for axis, starts in MOVES.items():
        for sign, start in zip((1.0, -1.0), starts, strict=True):
            scene = gantry.build(start={**gantry.MACHINE.demo_start, axis: start}, trace_every=0)
            fig = commissioning.measure_move(scene, axis, sign * 200.0, 400.0, settle=0.3)
            out[f"{axis}{'+' if sign > 0 else '-'}"] = {
                "peak_following_error_um": round(fig.peak_error * 1e3, 1),
                "overshoot_um": round(fig.overshoot * 1e3, 1),
                "settling_ms": round(fig.settling * 1e3, 1),
            }
    return out


def contour() -> dict[str, dict[str, float]]:
    """The zigzag, Buffered and blended (goals: ≤ 20 µm; corners within the tolerance)."""
    out: dict[str, dict[str, float]] = {}
    for mode in (mcl.MC_BufferMode.Buffered, mcl.MC_BufferMode.BlendingLow):
        for velocity in (200.0, 300.0):
            scene = gantry.build(start=gantry.ZIGZAG_START, trace_every=0)
            modes = [mode] * len(gantry.ZIGZAG)
            c = run_path(
                scene, "XYZ", "gantry/tool", gantry.ZIGZAG, modes, velocity, CORNER_TOLERANCE
            )
            key = f"{mode.name}_{velocity:g}_mm_s"
            if mode == mcl.MC_BufferMode.Buffered:
                out[key] = {"max_um": round(float(c.errors.max()) * 1e6, 1)}
            else:
                out[key] = {
                    "corner_tolerance_um": CORNER_TOLERANCE * 1e3,
                    "corners_max_um": round(c.corner_error(0.005) * 1e6, 1),
                    "straight_parts_max_um": round(c.straight_error(0.005) * 1e6, 1),
                }
    return out


def limits() -> dict[str, dict[str, float]]:
    """From Vmax onto each limit switch (goal: stopped before the hard stop, no force on it)."""
    out: dict[str, dict[str, float]] = {}
    for axis, starts in LIMITS.items():
        for direction, start in zip((1, -1), starts, strict=True):
            scene = gantry.build(start={**gantry.MACHINE.demo_start, axis: start}, trace_every=0)
            stop = commissioning.run_into_limit(scene, axis, direction, acceleration=10000.0)
            out[f"{axis}_lim_{'pos' if direction > 0 else 'neg'}"] = {
                "speed_at_trip_mm_s": round(stop.speed * 1e3, 1),
                "stopping_distance_mm": round(stop.distance * 1e3, 2),
                "room_to_hard_stop_mm": round(stop.margin * 1e3, 2),
                "hard_stop_force_n": round(stop.stop_force, 1),
            }
    return out


def homing_repeatability() -> dict[str, Any]:
    """REF + index homing of X from 10 starts with the real sensors (hysteresis, repeatability,
    noise, index jitter): where the origin lands against the index position [µm]."""
    import random

    from scenes.machines.gantry.scenarios import homing_repeatability as home

    draw = random.Random(5)
    errors = [home(seed, 10.0, draw.uniform(30.0, 400.0))["origin_error_um"] for seed in range(10)]
    return {
        "origin_error_um": [round(e, 2) for e in errors],
        "spread_um": round(max(errors) - min(errors), 2),
        "count_um": 1.0,
    }


def main() -> None:
    """Print the benchmark as JSON."""
    report = {
        "demo": [demo(trace_every=1), demo(trace_every=0)],
        "moves_400_mm_s": moves(),
        "contour": contour(),
        "lim_stop_at_vmax": limits(),
        "force_on_stop_after_block_homing": block_forces(),
        "ref_index_homing_repeatability": homing_repeatability(),
    }
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
