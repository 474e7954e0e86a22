"""Single simulated axis: power, a jerk-limited move, a blended chain, velocity, stop.

Runs on the pure-Python simulated axis (no physics engine) and prints what a commissioning
engineer watches: positions, states and the output edges of every function block. The program
is written the way a PLC programmer writes it: one scan function that sets the blocks' inputs by
the step, the steps declared as a table (each step's end), the blocks' constant inputs bound
once.
"""

from __future__ import annotations

__all__ = ["CONSTANTS", "MACHINE", "STEPS", "Demo"]

from typing import Any

import mcl
from plc.sequence import Step, StepSequence, never
from scenes.definition import AxisDef, MachineDef
from scenes.scene import Scene

CONSTANTS = dict(Kp=3.0, Ki=150.0, Ff=1.0, Kc=50.0, Vmax=500.0, Filter=2.0, Ka=0.0065)
"""Servo constants for the default simulated axis (Vmax 500 mm/s at 10 V)."""

STEPS = (
    "MC_Power",
    "MC_MoveRelative 300 mm at 400 mm/s, jerk-limited",
    "three moves blended (BlendingNext): no stop between them",
    "MC_MoveVelocity 100 mm/s",
    "MC_Stop: Stopping while Execute is TRUE",
    "MC_Stop released: StandStill",
    "done",
)


class Demo(StepSequence):
    """The demo's PLC program; call it once per PLC cycle. ``step`` says what it does."""

    STEPS = STEPS

    def __init__(self, scene: Scene) -> None:
        X = self.X = scene.axes["X"]
        self.index = 0
        self.error = ""
        blend = mcl.MC_BufferMode.BlendingNext
        # constant inputs are bound once; a scan sets only Enable and Execute
        self.power = mcl.MC_Power(Axis=X)
        self.move = mcl.MC_MoveRelative(
            Axis=X,
            Distance=300.0,
            Velocity=400.0,
            Acceleration=4000.0,
            Deceleration=4000.0,
            Jerk=100000.0,
        )
        self.first = mcl.MC_MoveRelative(
            Axis=X, Distance=-100.0, Velocity=300.0, Acceleration=3000.0
        )
        self.second = mcl.MC_MoveRelative(
            Axis=X, Distance=-100.0, Velocity=150.0, Acceleration=3000.0, BufferMode=blend
        )
        self.third = mcl.MC_MoveRelative(
            Axis=X, Distance=-50.0, Velocity=300.0, Acceleration=3000.0, BufferMode=blend
        )
        self.velocity = mcl.MC_MoveVelocity(Axis=X, Velocity=100.0, Acceleration=1000.0)
        self.stop = mcl.MC_Stop(Axis=X, Deceleration=2000.0)
        self.blocks: dict[str, Any] = {
            name: getattr(self, name)
            for name in ("power", "move", "first", "second", "third", "velocity", "stop")
        }
        """The blocks a report watches, by name."""
        done = (
            lambda: self.power.Status,
            lambda: self.move.Done,
            lambda: self.third.Done,
            lambda: self.velocity.InVelocity,
            lambda: self.stop.Done,
            lambda: X.state == mcl.AxisState.StandStill,
            never,
        )
        self.declare(*(Step(s, d, self.blocks) for s, d in zip(STEPS, done, strict=True)))

    def __call__(self) -> None:
        """One PLC scan."""
        step = self.index
        self.power.Enable = True
        self.power()
        self.move.Execute = step == 1
        self.move()
        for fb in (self.first, self.second, self.third):
            fb.Execute = step == 2
            fb()
        self.velocity.Execute = step == 3
        self.velocity()
        self.stop.Execute = step == 4
        self.stop()
        self.advance()


MACHINE = MachineDef(
    name="single_axis",
    description="one simulated axis in pure Python (no physics engine): moves, blends, stop",
    axes={
        "X": AxisDef(
            config=mcl.AxisConfig(),
            constants=mcl.ServoConstants(**CONSTANTS),
            sim=mcl.SimAxisParams(start=0.2),
        )
    },
    demo=Demo,
)
"""The simulated single axis in the registry."""
