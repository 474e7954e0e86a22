"""A scenario run twice from scratch records the same trace, bit for bit (no wall clock, no
hidden state between runs): on the MuJoCo gantry and on the pure-Python SimMachine."""

from __future__ import annotations

from collections.abc import Callable

import mcl
from mcl import AxisState, MC_BufferMode, MC_Direction, MC_SwitchMode
from mcl.trace import Trace
from scenes.machines import gantry
from tests.helpers import configure


class Scenario:
    """Power, REF + index homing of X, then a few moves (one blended, one continuous ended by a
    halt); Y (when there is one) moves meanwhile. One PLC program, stepped by phases."""

    def __init__(self, axes: dict[str, mcl.Axis]) -> None:
        self.X = axes["X"]
        self.Y = axes.get("Y")
        self.power = mcl.MC_Power()
        self.power_y = mcl.MC_Power()
        self.approach = mcl.MC_StepAbsSwitch()
        self.pulse = mcl.MC_StepRefPulse()
        self.move_a = mcl.MC_MoveAbsolute()
        self.move_b = mcl.MC_MoveRelative()
        self.velocity = mcl.MC_MoveVelocity()
        self.halt = mcl.MC_Halt()
        self.move_y = mcl.MC_MoveRelative()
        self.phase = 0

    def program(self) -> None:
        X, p = self.X, self.phase
        self.power(Axis=X, Enable=True)
        self.approach(
            Axis=X,
            Execute=self.power.Status,
            Direction=MC_Direction.MC_SwitchNegative,
            SwitchMode=MC_SwitchMode.MC_EdgeOff,
            Velocity=50.0,
        )
        self.pulse(
            Axis=X,
            Execute=self.power.Status,
            Direction=MC_Direction.MC_Positive,
            Velocity=10.0,
            SetPosition=0.0,
            BufferMode=MC_BufferMode.Buffered,
        )
        self.move_a(Axis=X, Execute=p >= 1, Position=150.0, Velocity=300.0)
        self.move_b(
            Axis=X,
            Execute=p >= 1,
            Distance=-40.0,
            Velocity=100.0,
            BufferMode=MC_BufferMode.BlendingLow,
        )
        self.velocity(Axis=X, Execute=p >= 2, Velocity=80.0, Direction=MC_Direction.MC_Negative)
        self.halt(Axis=X, Execute=p >= 3, Deceleration=500.0)
        if self.Y is not None:
            self.power_y(Axis=self.Y, Enable=True)
            self.move_y(Axis=self.Y, Execute=p >= 1, Distance=25.0, Velocity=50.0)

    def run(self, run: Callable[..., float]) -> None:
        run(self.program, until=lambda: self.pulse.Done, timeout=30)
        self.phase = 1
        run(self.program, until=lambda: self.move_b.Done, timeout=10)
        self.phase = 2
        run(self.program, until=lambda: self.velocity.InVelocity, timeout=5)
        run(self.program, timeout=0.2)
        self.phase = 3
        run(self.program, until=lambda: self.halt.Done, timeout=5)
        run(self.program, timeout=0.2)
        assert self.X.state == AxisState.StandStill and self.X.Ref
        assert self.X.AxErrorID == 0


def assert_same_rows(a: dict[str, list[tuple[float, ...]]], b: dict[str, list[tuple[float, ...]]]):
    assert a.keys() == b.keys()
    for name in a:
        rows_a, rows_b = a[name], b[name]
        assert len(rows_a) == len(rows_b), name
        assert len(rows_a) > 1000, "the scenario ran"
        for i, (ra, rb) in enumerate(zip(rows_a, rows_b, strict=True)):
            assert ra == rb, f"axis {name}: first difference in row {i}: {ra} != {rb}"


def gantry_run() -> dict[str, list[tuple[float, ...]]]:
    scene = gantry.build(start={"X": 0.3, "Y": 0.2, "Z": -0.1}, trace_every=1)
    Scenario(scene.axes).run(scene.run)
    return scene.trace.rows


def sim_run() -> dict[str, list[tuple[float, ...]]]:
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.3)})
    configure(machine.axes["X"])
    sim = machine.sims["X"]
    trace = Trace(machine.axes, truth={"X": lambda: sim.x})
    machine.runtime.observers.append(trace)
    Scenario(machine.axes).run(machine.run)
    return trace.rows


def test_gantry_scenario_is_deterministic():
    first = gantry_run()
    second = gantry_run()
    assert_same_rows(first, second)


def test_sim_machine_scenario_is_deterministic():
    first = sim_run()
    second = sim_run()
    assert_same_rows(first, second)
