"""The PLC-side program of the bridge: each scan it reads the command words of the signal table,
calls the library's function blocks with them and writes the status back.

Every command goes through an mcl block, with its rules and ErrorIDs (docs/reference.md):

==============  ====================================================================
enable          ``MC_Power`` Enable (a level; axes with a drive only)
reset           ``MC_Reset`` Execute
move_absolute   ``MC_MoveAbsolute`` Execute (position, velocity, acceleration, …)
move_relative   ``MC_MoveRelative`` Execute (distance, …)
move_velocity   ``MC_MoveVelocity`` Execute (velocity; its sign gives the direction)
home            the machine's homing recipe (``scenes.procedures.HomeAxis``) Execute
stop            ``MC_Stop`` Execute (deceleration; 0: the block's default)
halt            ``MC_Halt`` Execute (deceleration; 0: the block's default)
jog_pos/neg     ``GT_Jog`` JogPos / JogNeg (levels; |velocity| as JogVelo)
==============  ====================================================================

An Execute bit is passed as the block's Execute every scan: its rising edge starts the command,
the block's outputs follow the PLCopen rules. The status word shows the outputs of the current
command, the one last started.
"""

from __future__ import annotations

import logging
from typing import Any

import mcl
from scenes.bridge.table import CONTROL_BITS, STATUS_BITS, SignalTable
from scenes.procedures import HomeAxis, Recipe
from scenes.scene import Scene

log = logging.getLogger(__name__)

Command = Any
"""A command block (MC_MoveAbsolute, HomeAxis, …): Done, Busy, Error, ErrorID; maybe Active,
CommandAborted."""


class AxisBridge:
    """The blocks of one axis and the scan that drives them from its table block.

    Args:
        axis: the axis.
        recipe: its homing recipe (None: the home bit is refused and logged).
        table: the signal table.
    """

    def __init__(self, axis: mcl.Axis, recipe: Recipe | None, table: SignalTable) -> None:
        self.axis = axis
        self.table = table
        self.prefix = f"{axis.name}."
        self.power = mcl.MC_Power()
        self.reset = mcl.MC_Reset()
        self.move_absolute = mcl.MC_MoveAbsolute()
        self.move_relative = mcl.MC_MoveRelative()
        self.move_velocity = mcl.MC_MoveVelocity()
        self.home = HomeAxis(axis, recipe) if recipe is not None else None
        self.stop = mcl.MC_Stop()
        self.halt = mcl.MC_Halt()
        self.jog = mcl.GT_Jog()
        self.current: Command | None = None
        """The command last started by a rising edge (its outputs are the status)."""
        self.command = 0
        """The current command's control bit + 1 (0: none yet)."""
        self._last_word = 0

    def _param(self, name: str) -> float:
        return self.table.get(self.prefix + name)

    def __call__(self) -> None:
        """One PLC scan: control word → blocks → status."""
        word = int(self.table.get(self.prefix + "control"))
        bits = {name: bool(word >> i & 1) for i, name in enumerate(CONTROL_BITS)}
        rising = word & ~self._last_word
        self._last_word = word
        axis = self.axis
        ramp = {
            "Velocity": self._param("velocity"),
            "Acceleration": self._param("acceleration"),
            "Deceleration": self._param("deceleration"),
            "Jerk": self._param("jerk"),
        }
        if axis.has_drive:
            self.power(Axis=axis, Enable=bits["enable"])
        commands: list[tuple[str, Command]] = [("reset", self.reset)]
        self.reset(Axis=axis, Execute=bits["reset"])
        self.move_absolute(
            Axis=axis, Execute=bits["move_absolute"], Position=self._param("position"), **ramp
        )
        self.move_relative(
            Axis=axis, Execute=bits["move_relative"], Distance=self._param("distance"), **ramp
        )
        self._move_velocity(bits["move_velocity"], ramp)
        commands += [
            ("move_absolute", self.move_absolute),
            ("move_relative", self.move_relative),
            ("move_velocity", self.move_velocity),
        ]
        if self.home is not None:
            self.home(Execute=bits["home"])
            commands.append(("home", self.home))
        elif rising >> CONTROL_BITS.index("home") & 1:
            log.warning("%s: home refused: the axis has no homing recipe", axis.name)
        for name, block in (("stop", self.stop), ("halt", self.halt)):
            self._ramp_down(block, bits[name], ramp["Deceleration"], ramp["Jerk"])
            commands.append((name, block))
        self._jog(bits["jog_pos"], bits["jog_neg"], ramp["Velocity"])
        commands.append(("jog_pos", self.jog))
        commands.append(("jog_neg", self.jog))
        for name, block in commands:
            if rising >> CONTROL_BITS.index(name) & 1:
                self.current, self.command = block, CONTROL_BITS.index(name) + 1
        self._write_status()

    def _move_velocity(self, execute: bool, ramp: dict[str, float]) -> None:
        """MC_MoveVelocity: the velocity's sign is the direction."""
        velocity = ramp["Velocity"]
        direction = mcl.MC_Direction.MC_Negative if velocity < 0 else mcl.MC_Direction.MC_Positive
        self.move_velocity(
            Axis=self.axis,
            Execute=execute,
            **{**ramp, "Velocity": abs(velocity)},
            Direction=direction,
        )

    def _ramp_down(
        self, block: mcl.MC_Stop | mcl.MC_Halt, execute: bool, deceleration: float, jerk: float
    ) -> None:
        """MC_Stop or MC_Halt; a deceleration of 0 keeps the block's default."""
        ramp = {"Deceleration": deceleration} if deceleration else {}
        block(Axis=self.axis, Execute=execute, Jerk=jerk, **ramp)

    def _jog(self, jog_pos: bool, jog_neg: bool, velocity: float) -> None:
        """GT_Jog while a jog bit is set (and once more when it drops)."""
        if jog_pos or jog_neg or self.jog.Enable:
            self.jog(
                Axis=self.axis,
                Enable=jog_pos or jog_neg,
                JogPos=jog_pos,
                JogNeg=jog_neg,
                JogVelo=abs(velocity),
            )

    def _write_status(self) -> None:
        axis, current, io = self.axis, self.current, self.axis.io
        flags = {
            "done": bool(getattr(current, "Done", False)),
            "busy": bool(getattr(current, "Busy", False)),
            "active": bool(getattr(current, "Active", False)),
            "error": bool(getattr(current, "Error", False)),
            "command_aborted": bool(getattr(current, "CommandAborted", False)),
            "homed": axis.Ref,
            "lim_neg": bool(io.lim_neg),
            "ref": bool(io.ref),
            "lim_pos": bool(io.lim_pos),
            "power": bool(self.power.Status),
        }
        status = sum(1 << i for i, name in enumerate(STATUS_BITS) if flags[name])
        p = self.prefix
        self.table.update(
            [
                (p + "status", status),
                (p + "state", int(axis.state)),
                (p + "error_id", int(getattr(current, "ErrorID", 0))),
                (p + "axis_error_id", axis.AxErrorID),
                (p + "actual_position", axis.POS),
                (p + "actual_velocity", axis.VEL),
                (p + "following_error", axis.following_error),
                (p + "volts", axis.volts),
                (p + "command", self.command),
            ]
        )


class BridgeProgram:
    """The bridge's PLC program for a scene: one :class:`AxisBridge` per axis, then the
    simulation fields and the published signals. Call it once per PLC scan.

    Args:
        scene: the running scene.
        table: its signal table.
        homing: the homing recipes by axis name.
    """

    def __init__(self, scene: Scene, table: SignalTable, homing: dict[str, Recipe]) -> None:
        self.scene = scene
        self.table = table
        self.axes = [AxisBridge(scene.axes[a], homing.get(a), table) for a in table.axes]
        self.cycles = 0

    def __call__(self) -> None:
        """One PLC scan."""
        for axis in self.axes:
            axis()
        self.cycles += 1
        table, scene = self.table, self.scene
        table.set("sim.time", scene.time)
        table.set("sim.cycle", self.cycles)
        for name in table.signals:
            table.set(f"signal.{name}", scene.signal(name))
