"""Single simulated axis: power, a jerk-limited move, a blended chain, velocity, stop.

Runs on the pure-Python simulated axis (no physics engine) and prints what a commissioning
engineer watches: positions, states and the output edges of every function block. The program
is written the way a PLC programmer writes it: one scan function with a step counter.
"""

from __future__ import annotations

import mcl
from scenes.report import EdgeLog

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


class Program:
    """The demo's PLC program; call it once per PLC cycle."""

    def __init__(self, axis: mcl.Axis, log: EdgeLog) -> None:
        self.X = axis
        self.log = log
        self.step = 0
        self.power, self.move = mcl.MC_Power(), mcl.MC_MoveRelative()
        self.first, self.second, self.third = (mcl.MC_MoveRelative() for _ in range(3))
        self.velocity, self.stop = mcl.MC_MoveVelocity(), mcl.MC_Stop()
        log.watch(
            **{
                name: getattr(self, name)
                for name in ("power", "move", "first", "second", "third", "velocity", "stop")
            }
        )
        log.title(STEPS[0])

    def next(self) -> None:
        """Go to the next step."""
        self.step += 1
        self.log.title(STEPS[self.step])

    def __call__(self) -> None:
        X, step = self.X, self.step
        blend = mcl.MC_BufferMode.BlendingNext
        self.power(Axis=X, Enable=True)
        self.move(
            Axis=X,
            Execute=step == 1,
            Distance=300.0,
            Velocity=400.0,
            Acceleration=4000.0,
            Deceleration=4000.0,
            Jerk=100000.0,
        )
        self.first(Axis=X, Execute=step == 2, Distance=-100.0, Velocity=300.0, Acceleration=3000.0)
        self.second(
            Axis=X,
            Execute=step == 2,
            Distance=-100.0,
            Velocity=150.0,
            Acceleration=3000.0,
            BufferMode=blend,
        )
        self.third(
            Axis=X,
            Execute=step == 2,
            Distance=-50.0,
            Velocity=300.0,
            Acceleration=3000.0,
            BufferMode=blend,
        )
        self.velocity(Axis=X, Execute=step == 3, Velocity=100.0, Acceleration=1000.0)
        self.stop(Axis=X, Execute=step == 4, Deceleration=2000.0)
        if (
            (step == 0 and self.power.Status)
            or (step == 1 and self.move.Done)
            or (step == 2 and self.third.Done)
            or (step == 3 and self.velocity.InVelocity)
            or (step == 4 and self.stop.Done)
            or (step == 5 and X.state == mcl.AxisState.StandStill)
        ):
            self.next()


def main() -> None:
    """Run the demo headless and print the report."""
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2)})
    X = machine.axes["X"]
    mcl.GT_SetConstant()(Axis=X, Execute=True, **CONSTANTS)
    log = EdgeLog(machine)
    program = Program(X, log)
    machine.run(program, until=lambda: program.step == len(STEPS) - 1, timeout=10.0)
    log.summary()


if __name__ == "__main__":
    main()
