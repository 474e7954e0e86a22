"""Benchmark: cost of a servo cycle on simulated axes, and the following error of a long move.

Prints JSON per mode (compiled where built, and pure Python, each in a fresh process).
``us_per_servo_cycle`` is the wall time of one servo period of the whole stack (PLC program with
FB calls every 2 ms in the bind-once style, trajectory, regulator, supervision, simulated plant
with two 0.5 ms substeps) divided by the number of servo cycles; ``library_us`` subtracts the
plant alone; ``per_axis_us`` is the slope of ``library_us`` from 1 to 100 axes.
Run: ``python -m tests.benchmarks.servo_cycle``.
"""

from __future__ import annotations

import time

import mcl
from tests.benchmarks import report_in_both_modes
from tests.helpers import CONSTANTS

AXES = (1, 3, 10, 30, 100)


def _machine(n: int) -> mcl.SimMachine:
    names = [f"A{i}" for i in range(n)]
    machine = mcl.SimMachine({name: mcl.SimAxisParams(start=0.2) for name in names})
    for axis in machine.axes.values():
        mcl.GT_SetConstant(Axis=axis, **CONSTANTS)(Execute=True)
    return machine


def servo_cycle_cost(n: int, seconds: float = 2.0) -> dict[str, float]:
    """Wall time per servo cycle with ``n`` axes moving back and forth [µs]."""
    machine = _machine(n)
    axes = list(machine.axes.values())
    powers = [mcl.MC_Power(Axis=axis, Enable=True) for axis in axes]
    limits = dict(Velocity=400.0, Acceleration=4000.0, Deceleration=4000.0, Jerk=100000.0)
    moves = [mcl.MC_MoveRelative(Axis=axis, **limits) for axis in axes]
    toggle = [False]
    distance = [200.0]

    def program() -> None:
        for power in powers:
            power()
        for move in moves:
            move.Execute = toggle[0]
            move()
        if all(m.Done for m in moves) or not toggle[0]:
            toggle[0] = not toggle[0]
            if toggle[0]:
                distance[0] = -distance[0]
                for move in moves:
                    move.Distance = distance[0]

    machine.run(program, timeout=0.1)
    cycles = round(seconds / machine.runtime.servo_period)
    start = time.perf_counter()
    machine.run(program, timeout=seconds)
    stack = (time.perf_counter() - start) / cycles * 1e6
    plant = machine.plant
    start = time.perf_counter()
    for _ in range(cycles):  # one servo period: sample the inputs, two physics steps
        plant.sense()
        plant.step(2)
    plant_only = (time.perf_counter() - start) / cycles * 1e6
    return {
        "axes": n,
        "us_per_servo_cycle": round(stack, 2),
        "plant_us": round(plant_only, 2),
        "library_us": round(stack - plant_only, 2),
        "real_time_factor": round(machine.runtime.servo_period * 1e6 / stack, 1),
    }


def following_error() -> dict[str, float]:
    """Peak and settled following error of a 300 mm, 400 mm/s jerk-limited MoveAbsolute [µm]."""
    machine = _machine(1)
    axis = machine.axes["A0"]
    power, move = mcl.MC_Power(), mcl.MC_MoveAbsolute()
    machine.run(lambda: power(Axis=axis, Enable=True), until=lambda: power.Status, timeout=0.1)
    axis.Ref = True  # the coordinate counts from power-up; no homing needed on the simulated axis
    peak = [0.0]

    def observe(t: float) -> None:
        peak[0] = max(peak[0], abs(axis.following_error))

    machine.runtime.observers.append(observe)

    def program() -> None:
        power(Axis=axis, Enable=True)
        move(
            Axis=axis,
            Execute=True,
            Position=300.0,
            Velocity=400.0,
            Acceleration=4000.0,
            Deceleration=4000.0,
            Jerk=100000.0,
        )

    machine.run(program, until=lambda: move.Done, timeout=5.0)
    at_done = abs(300.0 - axis.POS)
    machine.run(program, timeout=0.5)
    return {
        "peak_following_error_um": round(peak[0] * 1000, 2),
        "error_at_done_um": round(at_done * 1000, 2),
        "settled_error_um_after_0.5s": round(abs(300.0 - axis.POS) * 1000, 2),
    }


def mode_report() -> dict[str, object]:
    """The figures in this process' mode."""
    cycles = [servo_cycle_cost(n) for n in AXES]
    slope = (cycles[-1]["library_us"] - cycles[0]["library_us"]) / (AXES[-1] - AXES[0])
    return {
        "mode": "compiled" if mcl.COMPILED else "pure Python",
        "servo_cycle": cycles,
        "per_axis_us": round(slope, 2),
        "move_300mm_400mm_s": following_error(),
    }


def main() -> None:
    """Print the benchmark as JSON, compiled (where built) and pure Python."""
    report_in_both_modes("tests.benchmarks.servo_cycle", mode_report)


if __name__ == "__main__":
    main()
