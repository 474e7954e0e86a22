"""Benchmark: every machine of the registry running its demo, against its bare physics.

For each machine the demo (PLC program included) runs from its demo start in chunks of 0.1 s of
simulated time. After each chunk the same physics runs alone for the same time, one servo period
per call (as any controller of it must step it), on a copy of the model: MuJoCo's ``mj_step`` and
the machine's devices (hydraulics, a roll's ripple, a knife valve: the physics MuJoCo does not
model); simulated axes: their plant. It starts from the state the scene had at the chunk's start
(positions, velocities, controls, drive enables, device states), so both integrate the same
machine in the same situation and see the same machine load at the same moment. Prints JSON per
mode (compiled and pure Python, each in a fresh process): the demo's real-time factor, the bare
physics' real-time factor and their ratio (1.0 = the stack costs nothing beyond the physics), µs
per servo cycle; for a machine with devices also the ratio to MuJoCo alone and the devices' cost
per physics step. A machine of simulated axes has no physics engine to compare against (its
"physics" is a few arithmetic operations per axis), so its ratio is left out and its real-time
factor and µs per cycle stand alone. Each demo runs :data:`REPEATS` times and each chunk counts
with its fastest run, so a burst of another process on a shared machine does not count.

Every chunk is timed on two clocks: this thread's CPU time, which the figures are computed from
(the time the process spent computing; another process running on the same cores does not count
in it), and the wall clock, whose ratio is ``ratio_wall`` (on an idle machine the same; on a
shared one lower, since a chunk the scheduler interrupts counts the other process' time too).

Run: ``python -m tests.benchmarks.machines``.
"""

from __future__ import annotations

import time
from typing import Any

from tests.benchmarks import report_in_both_modes

CHUNK = 0.1
"""Simulated seconds per measured chunk [s]."""


class BarePhysics:
    """The same physics alone: a copy of the model with its own MjData (with ``devices``, fresh
    instances of the machine's devices: hydraulics, roll ripple, a knife valve — the physics
    MuJoCo does not model), or fresh simulated axes.

    :meth:`sync` (untimed) copies the scene's present — positions, velocities, controls, drive
    enables and brakes, the devices' states — so that :meth:`step` integrates the same machine
    in the same situation (contacts, pressures) as the scene's next chunk.
    """

    def __init__(self, scene: Any, devices: bool) -> None:
        import copy

        import mujoco

        import mcl
        from scenes.plant.mujoco import MujocoPlant

        self.scene = scene
        if not scene.has_model:
            plant = scene.plant
            assert isinstance(plant, mcl.SimPlant)
            bare = mcl.SimPlant([mcl.SimAxis(axis.params) for axis in plant.axes], plant.timestep)
            for axis in bare.axes:
                axis.write(1.0, True)  # moving, as the demo's axes are
            self.step = bare.step
            return
        self.model = copy.deepcopy(scene.model)  # devices may write model fields (equality data)
        self.data = mujoco.MjData(self.model)
        alone = len(scene.machines) == 1
        self.devices = (
            {
                d if alone else f"{m.name}/{d}": f(self.model, self.data, f"{m.name}/")
                for m in scene.machines
                for d, f in m.devices.items()
            }
            if devices
            else {}
        )
        self.spec = mujoco.mjtState.mjSTATE_INTEGRATION
        self.step = MujocoPlant(self.model, self.data, [], self.devices).step

    def sync(self) -> None:
        """Take over the scene's present state (not timed)."""
        if not self.scene.has_model:
            return
        import mujoco
        import numpy as np

        scene, model, data = self.scene, self.model, self.data
        size = mujoco.mj_stateSize(scene.model, self.spec)
        state = np.empty(size)
        mujoco.mj_getState(scene.model, scene.data, state, self.spec)
        mujoco.mj_setState(model, data, state, self.spec)
        model.opt.disableactuator = scene.model.opt.disableactuator
        model.dof_frictionloss[:] = scene.model.dof_frictionloss
        model.eq_data[:] = scene.model.eq_data
        for name, device in self.devices.items():
            device.set_state(scene.devices[name].get_state())
        mujoco.mj_forward(model, data)


REPEATS = 3
"""Runs of each demo; each chunk's time is the fastest of its runs (the figures of a shared
machine: another process' burst slows a chunk of one run, not the same chunk of every run)."""


def machine(name: str) -> dict[str, Any]:
    """The demo of machine ``name`` against its bare physics."""
    import scenes

    definition = scenes.definition(name)
    parts = [p.machine for p in definition.parts] or [definition]
    devices = [f"{m.name}/{d}" if definition.parts else d for m in parts for d in m.devices]
    runs = []
    for _ in range(REPEATS):
        scene = scenes.load(name, start=definition.demo_start, trace_every=0)
        program = scenes.demo(scene)
        runs.append(chunk_times(scene, program, lambda p=program: p.done or bool(p.error)))
    return {
        "machine": name,
        "physics": ("MuJoCo" + (f" + devices {sorted(devices)}" if devices else ""))
        if scene.has_model
        else "simulated axes (a few lines of Euler, no engine)",
        **figures(scene, runs),
        "demo_error": program.error,
    }


def against_bare_physics(
    scene: Any, program: Any, finished: Any, longest: float = 300.0
) -> dict[str, Any]:
    """Run ``program`` on ``scene`` in chunks of :data:`CHUNK` until ``finished()``, each chunk
    followed by the same physics alone (:class:`BarePhysics`, with and without the devices);
    returns the real-time factors, their ratios and µs per servo cycle."""
    return figures(scene, [chunk_times(scene, program, finished, longest)])


Chunk = tuple[float, float, float, float, float, float]
"""The times of one chunk [s]: the stack, the bare physics with the machine's devices and MuJoCo
alone, in this thread's CPU time, then the same three on the wall clock."""


def _clocks() -> tuple[float, float]:
    """This thread's CPU time and the wall clock now [s]."""
    return time.thread_time(), time.perf_counter()


def chunk_times(scene: Any, program: Any, finished: Any, longest: float = 300.0) -> list[Chunk]:
    """The times of each chunk of :data:`CHUNK` (:data:`Chunk`): the stack (``program`` on
    ``scene``), the bare physics with the machine's devices, MuJoCo alone; until
    ``finished()``."""
    physics = BarePhysics(scene, devices=True)
    mujoco_alone = BarePhysics(scene, devices=False)
    ticks = round(scene.runtime.servo_period / scene.plant.timestep)
    periods = range(round(CHUNK / scene.runtime.servo_period))
    chunks: list[Chunk] = []
    simulated = 0.0
    while not finished() and simulated < longest:
        physics.sync()
        mujoco_alone.sync()
        cpu0, wall0 = _clocks()
        scene.run(program, timeout=CHUNK)
        cpu1, wall1 = _clocks()
        for _ in periods:  # a servo period per call, as any controller of it steps it
            physics.step(ticks)
        cpu2, wall2 = _clocks()
        for _ in periods:
            mujoco_alone.step(ticks)
        cpu3, wall3 = _clocks()
        chunks.append(
            (cpu1 - cpu0, cpu2 - cpu1, cpu3 - cpu2, wall1 - wall0, wall2 - wall1, wall3 - wall2)
        )
        simulated += CHUNK
    return chunks


def figures(scene: Any, runs: list[list[Chunk]]) -> dict[str, Any]:
    """Real-time factors, ratios and µs per servo cycle of runs of the same chunks (each
    chunk's fastest run counts), in CPU time; the ratio on the wall clock besides."""
    n = min(len(run) for run in runs)
    stack, bare, alone, stack_wall, bare_wall, _ = (
        sum(min(run[k][i] for run in runs) for k in range(n)) for i in range(6)
    )
    simulated = n * CHUNK
    with_devices = scene.has_model and bool(scene.devices)
    return {
        "simulated_s": round(simulated, 1),
        "runs": len(runs),
        "demo_real_time_factor": round(simulated / stack, 1),
        "bare_physics_real_time_factor": round(simulated / bare, 1),
        "ratio": round(bare / stack, 2) if scene.has_model else None,
        "ratio_wall": round(bare_wall / stack_wall, 2) if scene.has_model else None,
        "ratio_to_mujoco_alone": round(alone / stack, 2) if with_devices else None,
        "us_per_servo_cycle": round(stack / (simulated / scene.runtime.servo_period) * 1e6, 1),
        "us_per_physics_step_in_devices": round(
            (bare - alone) / (simulated / scene.plant.timestep) * 1e6, 2
        )
        if with_devices
        else None,
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
