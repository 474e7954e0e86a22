"""A machine made ready for an external PLC (:class:`Bridge`): its scene, one signal table per
machine (a cell: one per part), the bridge program and the thread that runs the simulation,
free at a speed or in lockstep with the client. The servers (:mod:`scenes.bridge.modbus`,
:mod:`scenes.bridge.opcua`) serve its tables."""

from __future__ import annotations

__all__ = ["Bridge", "check_speed"]

import math

import scenes
from scenes.bridge.program import BridgeProgram
from scenes.bridge.runs import LockstepRun, PacedRun
from scenes.bridge.table import SignalTable, tables_of


def check_speed(speed: float | None) -> None:
    """Refuse a speed that is not a finite number > 0 (None: lockstep).

    Raises:
        ValueError: says what is wrong.
    """
    if speed is not None and not (math.isfinite(speed) and speed > 0.0):
        raise ValueError(f"speed must be a finite number > 0, got {speed}")


class Bridge:
    """The scene of registry machine ``machine`` with its tables, program and run.

    Args:
        machine: registry name (``gantry``, ``cell``, …).
        speed: simulated seconds per wall second of a free run; None: lockstep.
    """

    def __init__(self, machine: str, speed: float | None = 1.0) -> None:
        check_speed(speed)
        self.definition = scenes.definition(machine)
        self.scene = scenes.load(machine, trace_every=0)
        self.tables: list[SignalTable] = tables_of(self.definition)
        self.program = BridgeProgram(self.scene, self.tables, scenes.homing(self.scene))
        self.lockstep = speed is None
        self.run: LockstepRun | PacedRun = (
            LockstepRun(self.program) if speed is None else PacedRun(self.program, speed)
        )
        self.mode = "lockstep" if speed is None else f"free-running at {speed:g}x"

    def start(self) -> None:
        """Start the simulation thread."""
        self.run.start()

    def stop(self) -> None:
        """Stop the simulation thread."""
        self.run.stop()
