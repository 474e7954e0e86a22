"""Benchmark: every machine of the registry running its demo, against its bare physics.

For each machine the demo (PLC program included) runs from its demo start in chunks of 0.1 s of
simulated time; after each chunk the same number of physics steps runs alone on a copy of the
model (MuJoCo's ``mj_step`` and the machine's devices — hydraulics, a roll's ripple, a knife
valve: the physics MuJoCo does not model; simulated axes: their plant), so both see the same
machine load at the same moment. Prints JSON per mode (compiled and pure Python, each in a fresh
process): the demo's real-time factor, the bare physics' real-time factor and their ratio (1.0 =
the stack costs nothing beyond the physics), µs per servo cycle; for a machine with devices also
the ratio to MuJoCo alone and the devices' cost per physics step. A machine of simulated axes has
no physics engine to compare against (its "physics" is a few arithmetic operations per axis), so
its ratio is left out and its real-time factor and µs per cycle stand alone.

Run: ``python -m tests.benchmarks.machines``.
"""

from __future__ import annotations

import time
from typing import Any

from tests.benchmarks import report_in_both_modes

CHUNK = 0.1
"""Simulated seconds per measured chunk [s]."""


def bare_stepper(scene: Any, with_devices: bool) -> Any:
    """Steps the same physics alone: a copy of the model with its own MjData (and, with
    ``with_devices``, fresh instances of the machine's devices: hydraulics, roll ripple, a knife
    valve — the physics MuJoCo does not model), or fresh simulated axes."""
    import copy

    import mujoco

    import mcl
    import scenes
    from scenes.plant import MujocoPlant

    if scene.has_model:
        model = copy.deepcopy(scene.model)  # devices may write model fields (equality data)
        data = mujoco.MjData(model)
        data.qpos[:] = scene.data.qpos
        mujoco.mj_forward(model, data)
        definition = scenes.definition(scene.name)
        devices = (
            {d: f(model, data, f"{scene.name}/") for d, f in definition.devices.items()}
            if with_devices
            else {}
        )
        return MujocoPlant(model, data, [], devices).step
    plant = scene.plant
    assert isinstance(plant, mcl.SimPlant)
    bare = mcl.SimPlant([mcl.SimAxis(axis.params) for axis in plant.axes], plant.timestep)
    for axis in bare.axes:
        axis.write(1.0, True)  # moving, as the demo's axes are
    return bare.step


def machine(name: str) -> dict[str, Any]:
    """The demo of machine ``name`` against its bare physics."""
    import scenes

    definition = scenes.definition(name)
    scene = scenes.load(name, start=definition.demo_start, trace_every=0)
    program = scenes.demo(scene)
    physics = bare_stepper(scene, with_devices=True)
    mujoco_alone = bare_stepper(scene, with_devices=False)
    steps = round(CHUNK / scene.plant.timestep)
    stack = bare = alone = simulated = 0.0
    while not (program.done or program.error) and simulated < 300.0:
        start = time.perf_counter()
        scene.run(program, timeout=CHUNK)
        stack += time.perf_counter() - start
        start = time.perf_counter()
        physics(steps)
        bare += time.perf_counter() - start
        start = time.perf_counter()
        mujoco_alone(steps)
        alone += time.perf_counter() - start
        simulated += CHUNK
    cycles = simulated / scene.runtime.servo_period
    physics_steps = simulated / scene.plant.timestep
    devices = scenes.definition(name).devices
    return {
        "machine": name,
        "physics": ("MuJoCo" + (f" + devices {sorted(devices)}" if devices else ""))
        if scene.has_model
        else "simulated axes (a few lines of Euler, no engine)",
        "simulated_s": round(simulated, 1),
        "demo_real_time_factor": round(simulated / stack, 1),
        "bare_physics_real_time_factor": round(simulated / bare, 1),
        "ratio": round(bare / stack, 2) if scene.has_model else None,
        "ratio_to_mujoco_alone": round(alone / stack, 2) if devices else None,
        "us_per_servo_cycle": round(stack / cycles * 1e6, 1),
        "us_per_physics_step_in_devices": round((bare - alone) / physics_steps * 1e6, 2)
        if devices
        else None,
        "demo_error": program.error,
    }


def mode_report() -> dict[str, Any]:
    """Every machine in this process' mode."""
    import mcl
    import scenes

    return {
        "mode": "compiled" if mcl.COMPILED else "pure Python",
        "machines": [machine(name) for name in sorted(scenes.MACHINES)],
    }


def main() -> None:
    """Print the benchmark as JSON, compiled (where built) and pure Python."""
    report_in_both_modes("tests.benchmarks.machines", mode_report)


if __name__ == "__main__":
    main()
