"""Benchmark: the hydraulic press cycle against its bare physics, and the hydraulic model's cost.

The press demo (homing to block, approach, pressing, hold, decompression, return) runs from its
demo start in chunks of 0.1 s of simulated time; after each chunk the same number of ``mj_step``
calls runs alone on a second MjData of the same model (the bare physics, no device), so both see
the same machine at the same moment. Then the hydraulic model alone: the device's hook (valve,
chambers, force and friction written) and :meth:`ValveCylinder.step` (the math only), timed per
physics step while the valve moves the ram and while it presses solid. Prints JSON per mode
(compiled, where built, and pure Python, each in a fresh process).

Run: ``python -m tests.benchmarks.press``.
"""

from __future__ import annotations

import time
from typing import Any

from tests.benchmarks import report_in_both_modes

CHUNK = 0.1
"""Simulated seconds per measured chunk [s]."""


def cycle() -> dict[str, Any]:
    """The press demo against bare mj_step of the same model."""
    import mujoco

    import scenes

    definition = scenes.definition("press")
    scene = scenes.load("press", start=definition.demo_start, trace_every=0)
    program = scenes.demo(scene)
    model = scene.model
    bare = mujoco.MjData(model)
    bare.qpos[:] = scene.data.qpos
    mujoco.mj_forward(model, bare)
    steps = round(CHUNK / scene.plant.timestep)
    stack = physics = simulated = 0.0
    while not (program.done or program.error) and simulated < 60.0:
        start = time.perf_counter()
        scene.run(program, timeout=CHUNK)
        stack += time.perf_counter() - start
        start = time.perf_counter()
        mujoco.mj_step(model, bare, steps)
        physics += time.perf_counter() - start
        simulated += CHUNK
    return {
        "simulated_s": round(simulated, 1),
        "demo_error": program.error,
        "demo_real_time_factor": round(simulated / stack, 1),
        "bare_physics_real_time_factor": round(simulated / physics, 1),
        "ratio": round(physics / stack, 3),
        "us_per_physics_step_demo": round(stack / (simulated / scene.plant.timestep) * 1e6, 2),
        "us_per_physics_step_bare": round(physics / (simulated / scene.plant.timestep) * 1e6, 2),
    }


def hydraulics(steps: int = 20000) -> dict[str, Any]:
    """Cost of the hydraulic model per physics step [µs]: the device hook and the math alone."""
    import mujoco

    import scenes
    from scenes.machines.press.devices import CylinderDevice

    scene = scenes.load("press", trace_every=0)
    device = scene.devices["cylinder"]
    assert isinstance(device, CylinderDevice)
    model, data = scene.model, scene.data
    result: dict[str, Any] = {}
    for case, volts, q in (("moving", 3.0, 0.05), ("pressing solid", 10.0, 0.2499)):
        data.qpos[0], data.qvel[0] = q, 0.0
        mujoco.mj_forward(model, data)
        device.apply(volts, True, False)
        hook = device.before_step
        start = time.perf_counter()
        for _ in range(steps):
            hook(model, data)
        hooked = time.perf_counter() - start
        h = device.hydraulics
        iterations = 0
        start = time.perf_counter()
        for _ in range(steps):
            h.step(q, 0.01)
            iterations += h.iterations
        math_only = time.perf_counter() - start
        start = time.perf_counter()
        mujoco.mj_step(model, data, steps)
        bare = time.perf_counter() - start
        result[case] = {
            "us_device_hook": round(hooked / steps * 1e6, 2),
            "us_valve_cylinder_step": round(math_only / steps * 1e6, 2),
            "newton_iterations_per_step": round(iterations / steps, 2),
            "us_mj_step": round(bare / steps * 1e6, 2),
        }
    return result


def mode_report() -> dict[str, Any]:
    """The press in this process' mode."""
    import mcl
    import scenes

    return {
        "mode": "compiled" if mcl.COMPILED and scenes.COMPILED else "pure Python",
        "cycle": cycle(),
        "hydraulics_per_physics_step": hydraulics(),
    }


def main() -> None:
    """Print the benchmark as JSON, compiled (where built) and pure Python."""
    report_in_both_modes("tests.benchmarks.press", mode_report)


if __name__ == "__main__":
    main()
