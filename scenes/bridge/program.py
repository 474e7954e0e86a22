"""The PLC-side program of the bridge: each scan it reads the command words of the signal table,
calls the library's function blocks with them and writes the status back.

Every command goes through an mcl block, with its rules and ErrorIDs (docs/reference.md):

==============  ====================================================================
enable          ``MC_Power`` Enable (a level; axes with a drive only)
reset           ``MC_Reset`` Execute
move_absolute   ``MC_MoveAbsolute`` Execute (position, velocity, acceleration, …, buffer_mode)
move_relative   ``MC_MoveRelative`` Execute (distance, …)
move_additive   ``MC_MoveAdditive`` Execute (distance, …)
move_velocity   ``MC_MoveVelocity`` Execute (velocity; its sign gives the direction)
home            the machine's homing recipe (``plc.procedures.HomeAxis``) Execute
stop            ``MC_Stop`` Execute (deceleration; 0: the block's default)
halt            ``MC_Halt`` Execute (deceleration; 0: the block's default)
jog_pos/neg     ``GT_Jog`` JogPos / JogNeg (levels; |velocity| as JogVelo)
gear_in         ``MC_GearIn`` Execute (master, ratio_numerator, ratio_denominator, ramps)
gear_in_pos     ``MC_GearInPos`` Execute (… master/slave_sync_position, master_start_distance,
                velocity, zeroing)
gear_out        ``MC_GearOut`` Execute
force_control   ``MC_ForceControl`` Execute (force, force_ramp, gain, …, velocity, acceleration)
outputs         ``MC_WriteDigitalOutput`` for each output bit that differs from the output
==============  ====================================================================

A command the axis cannot take (home without a recipe, gearing on an axis without gearing
fields) is refused: the status shows Error with ErrorID EParam (5).

An Execute bit is passed as the block's Execute every scan: its rising edge starts the command,
the block's outputs follow the PLCopen rules. A method call (:meth:`SignalTable.request`) sets
its command's Execute at the next scan and holds it until the axis' next command. The status
word shows the outputs of the current command, the one last started, and ``command_count``
counts the commands started. A result of the current command (Done, Error with its ErrorID,
CommandAborted) is held in the status until the master acknowledges it — it clears the
command's bit after the result was published while the bit was set — or starts another
command: a master that polls slowly, or clears the bit early, still sees it.
"""

from __future__ import annotations

__all__ = ["RESULTS", "AxisBridge", "BridgeProgram", "Command"]

import logging
import math
from collections.abc import Callable, Sequence
from typing import Any

import mcl
from mcl.errors import ErrorID
from plc.procedures import HomeAxis, Recipe
from scenes.bridge.table import CONTROL_BITS, STATUS_BITS, SignalTable
from scenes.scene import Scene

log = logging.getLogger(__name__)

Command = Any
"""A command block (MC_MoveAbsolute, HomeAxis, …): Done, Busy, Error, ErrorID; maybe Active,
CommandAborted."""


RESULTS = ("done", "error", "command_aborted")
"""The status bits of a command's result, held until the master acknowledges it."""


def _int(value: float) -> int:
    """An INT input from a register value (0 for a value that is not finite)."""
    return round(value) if math.isfinite(value) and abs(value) < 2**31 else 0


class AxisBridge:
    """The blocks of one axis and the scan that drives them from its table block.

    Args:
        axis: the axis.
        recipe: its homing recipe (None: the home bit is refused with EParam).
        table: the signal table.
        axes: every axis of the table, in its order (the masters of gearing).
    """

    def __init__(
        self, axis: mcl.Axis, recipe: Recipe | None, table: SignalTable, axes: list[mcl.Axis]
    ) -> None:
        self.axis = axis
        self.name = axis.name
        self.table = table
        self.axes = axes
        self.prefix = f"{axis.name}."
        self.fields = {
            f.name[len(self.prefix) :] for f in table.fields if f.name.startswith(self.prefix)
        }
        self.power = mcl.MC_Power()
        self.reset = mcl.MC_Reset()
        self.move_absolute = mcl.MC_MoveAbsolute()
        self.move_relative = mcl.MC_MoveRelative()
        self.move_additive = mcl.MC_MoveAdditive()
        self.move_velocity = mcl.MC_MoveVelocity()
        self.home = HomeAxis(axis, recipe) if recipe is not None else None
        self.stop = mcl.MC_Stop()
        self.halt = mcl.MC_Halt()
        self.jog = mcl.GT_Jog()
        self.gear_in = mcl.MC_GearIn()
        self.gear_in_pos = mcl.MC_GearInPos()
        self.gear_out = mcl.MC_GearOut()
        self.outputs = [mcl.MC_WriteDigitalOutput() for _ in axis.io.outputs]
        self.force_control = mcl.MC_ForceControl()
        self.current: Command | None = None
        """The command last started by a rising edge (its outputs are the status)."""
        self.command = 0
        """The current command's control bit + 1 (0: none yet)."""
        self.count = 0
        """Commands started (``command_count``, modulo 65536)."""
        self._last_word = 0
        self._last_client = 0
        self._serial = -1
        self._requested = -1
        self._deferred = -1
        self._pending = 0
        self._held: dict[str, bool] = dict.fromkeys(RESULTS, False)
        """The current command's result bits held until acknowledged."""
        self._held_error = 0
        """The ErrorID held with the error bit."""
        self._armed = False
        """The held result was published while the master's command bit was set: the bit's
        fall acknowledges it."""
        self._calls = self._commands()

    @property
    def commands(self) -> tuple[str, ...]:
        """The Execute commands (control bits) the axis takes; the others are refused with
        EParam."""
        return tuple(self._calls)

    def _param(self, name: str) -> float:
        return self.table.get(self.prefix + name) if name in self.fields else 0.0

    def _words(self) -> tuple[int, int]:
        """This scan's control word of the client and the whole control word: the client's
        with the Execute of the command last requested (a method call), held until the axis'
        next command. A request whose bit was high in the last scan, or a client's command
        on the bit a request holds, first gets one scan low (a fresh rising edge)."""
        client = self.table.take_control(self.name) | self._pending
        self._pending = 0
        bit, serial = self.table.requested(self.name)
        if serial != self._serial:
            self._serial = serial
            self._requested = -1
            if self._last_word >> bit & 1:
                self._deferred = bit
            else:
                self._requested, self._deferred = bit, -1
        elif self._deferred >= 0:
            self._requested, self._deferred = self._deferred, -1
        elif self._requested >= 0 and client & ~self._last_client & ~1:
            held = 1 << self._requested  # the control word starts a command: the call's ends
            if client & ~self._last_client & held:
                client &= ~held
                self._pending = held
            self._requested = -1
        requested = 1 << self._requested if self._requested >= 0 else 0
        return client, client | requested

    def _commands(self) -> dict[str, tuple[Command, Callable[[bool], None]]]:
        """The Execute commands the axis can take, by control bit: the block (its outputs are
        the status) and the call that passes it this scan's Execute."""
        commands: dict[str, tuple[Command, Callable[[bool], None]]] = {
            "reset": (self.reset, lambda x: self.reset(Axis=self.axis, Execute=x)),
            "move_absolute": (self.move_absolute, self._move_absolute),
            "move_relative": (self.move_relative, self._move_relative),
            "move_additive": (self.move_additive, self._move_additive),
            "move_velocity": (self.move_velocity, self._move_velocity),
            "stop": (self.stop, lambda x: self._ramp_down(self.stop, x)),
            "halt": (self.halt, lambda x: self._ramp_down(self.halt, x)),
        }
        home = self.home
        if home is not None:
            commands["home"] = (home, lambda x: home(Execute=x))
        if "master" in self.fields:
            commands["gear_in"] = (self.gear_in, self._gear_in)
            commands["gear_in_pos"] = (self.gear_in_pos, self._gear_in_pos)
            commands["gear_out"] = (
                self.gear_out,
                lambda x: self.gear_out(Slave=self.axis, Execute=x),
            )
        if "force" in self.fields:
            commands["force_control"] = (self.force_control, self._force_control)
        return commands

    def __call__(self) -> None:
        """One PLC scan: control word → blocks. A block is called while its Execute is set,
        in the scan it falls, and while it is busy or shows an output; an idle one is not."""
        client, word = self._words()
        last, self._last_word = self._last_word, word
        rising = word & ~last
        axis = self.axis
        if axis.has_drive:
            self.power(Axis=axis, Enable=bool(word & 1))
        for name, (block, call) in self._calls.items():
            mask = _MASK[name]
            if word & mask or last & mask or _showing(block):
                call(bool(word & mask))
        self._jog(bool(word & _MASK["jog_pos"]), bool(word & _MASK["jog_neg"]))
        self._write_outputs()
        if rising & ~1:
            self._started(rising)
        self._hold(client)

    def _started(self, rising: int) -> None:
        """The commands whose bits rose: the last is the current one (each counts); a bit the
        axis has no command for is refused with EParam."""
        for i, name in enumerate(CONTROL_BITS):
            if rising >> i & 1 and name != "enable":
                self.command = i + 1
                self.count = (self.count + 1) & 0xFFFF
                self._release()
                if name in ("jog_pos", "jog_neg"):
                    self.current = self.jog
                elif name in self._calls:
                    self.current = self._calls[name][0]
                else:
                    self.current = None
                    self._held["error"], self._held_error = True, ErrorID.EParam
                    log.warning(
                        "%s: %s refused: the axis has no %s", self.name, name, _MISSING[name]
                    )

    def _hold(self, client: int) -> None:
        """Hold the current command's result; release it when the master's bit falls after
        the result was published while the bit was set (the acknowledgement)."""
        bit = 1 << (self.command - 1) if self.command else 0
        if self._armed and self._last_client & bit and not client & bit:
            self._release()
        self._last_client = client
        current = self.current
        for name, output in zip(RESULTS, ("Done", "Error", "CommandAborted"), strict=True):
            if getattr(current, output, False):
                self._held[name] = True
        if getattr(current, "Error", False):
            self._held_error = int(getattr(current, "ErrorID", 0))

    def _release(self) -> None:
        """Forget the held result (acknowledged, or another command started)."""
        self._held = dict.fromkeys(RESULTS, False)
        self._held_error = 0
        self._armed = False

    def observe(self) -> None:
        """A scan while the PLC is not in control: the blocks are not called; the control
        word's edges and requests are taken so that none fires later."""
        client, self._last_word = self._words()
        self._last_client = client

    def _ramp(self) -> dict[str, float]:
        return {
            "Velocity": self._param("velocity"),
            "Acceleration": self._param("acceleration"),
            "Deceleration": self._param("deceleration"),
            "Jerk": self._param("jerk"),
            "BufferMode": _int(self._param("buffer_mode")),
        }

    def _move_absolute(self, execute: bool) -> None:
        position = self._param("position")
        self.move_absolute(Axis=self.axis, Execute=execute, Position=position, **self._ramp())

    def _move_relative(self, execute: bool) -> None:
        distance = self._param("distance")
        self.move_relative(Axis=self.axis, Execute=execute, Distance=distance, **self._ramp())

    def _move_additive(self, execute: bool) -> None:
        distance = self._param("distance")
        self.move_additive(Axis=self.axis, Execute=execute, Distance=distance, **self._ramp())

    def _move_velocity(self, execute: bool) -> None:
        """MC_MoveVelocity: the velocity's sign is the direction."""
        ramp = self._ramp()
        velocity = ramp["Velocity"]
        direction = mcl.MC_Direction.MC_Negative if velocity < 0 else mcl.MC_Direction.MC_Positive
        ramp["Velocity"] = abs(velocity)
        self.move_velocity(Axis=self.axis, Execute=execute, Direction=direction, **ramp)

    def _gear(self) -> dict[str, Any]:
        """The in-outs and inputs MC_GearIn and MC_GearInPos share; a master number outside
        the table gives the blocks the slave itself as master (EParam)."""
        number = _int(self._param("master"))
        master = self.axes[number] if 0 <= number < len(self.axes) else self.axis
        return {
            "Master": master,
            "Slave": self.axis,
            "RatioNumerator": _int(self._param("ratio_numerator")),
            "RatioDenominator": _int(self._param("ratio_denominator")),
            "Acceleration": self._param("acceleration"),
            "Deceleration": self._param("deceleration"),
            "Jerk": self._param("jerk"),
        }

    def _gear_in(self, execute: bool) -> None:
        self.gear_in(Execute=execute, **self._gear())

    def _gear_in_pos(self, execute: bool) -> None:
        self.gear_in_pos(
            Execute=execute,
            MasterSyncPosition=self._param("master_sync_position"),
            SlaveSyncPosition=self._param("slave_sync_position"),
            MasterStartDistance=self._param("master_start_distance"),
            Velocity=self._param("velocity"),
            Zeroing=_int(self._param("zeroing")),
            **self._gear(),
        )

    def _force_control(self, execute: bool) -> None:
        """MC_ForceControl (velocity, acceleration and buffer mode of the move fields)."""
        self.force_control(
            Axis=self.axis,
            Execute=execute,
            Force=self._param("force"),
            ForceRamp=self._param("force_ramp"),
            Velocity=self._param("velocity"),
            Acceleration=self._param("acceleration"),
            Gain=self._param("gain"),
            InputNumber=_int(self._param("input_number")),
            Scale=self._param("scale"),
            InputNumber2=_int(self._param("input_number2")),
            Scale2=self._param("scale2"),
            Offset=self._param("offset"),
            Tolerance=self._param("tolerance"),
            BufferMode=_int(self._param("buffer_mode")),
        )

    def _ramp_down(self, block: mcl.MC_Stop | mcl.MC_Halt, execute: bool) -> None:
        """MC_Stop or MC_Halt (a deceleration or jerk of 0: the axis' default ramp)."""
        deceleration, jerk = self._param("deceleration"), self._param("jerk")
        block(Axis=self.axis, Execute=execute, Deceleration=deceleration, Jerk=jerk)

    def _jog(self, jog_pos: bool, jog_neg: bool) -> None:
        """GT_Jog while a jog bit is set (and once more when it drops); |velocity| as JogVelo."""
        if jog_pos or jog_neg or self.jog.Enable:
            self.jog(
                Axis=self.axis,
                Enable=jog_pos or jog_neg,
                JogPos=jog_pos,
                JogNeg=jog_neg,
                JogVelo=abs(self._param("velocity")),
            )

    def _write_outputs(self) -> None:
        """MC_WriteDigitalOutput for every output whose bit differs from the output."""
        if not self.outputs:
            return
        wanted = _int(self._param("outputs"))
        for k, block in enumerate(self.outputs):
            value = bool(wanted >> k & 1)
            block(
                Axis=self.axis,
                Execute=value != self.axis.io.outputs[k],
                OutputNumber=k,
                Value=value,
            )

    def publish(self) -> None:
        """Write the axis' status and actual values into the table."""
        axis, current, io, held = self.axis, self.current, self.axis.io, self._held
        if any(held.values()) and self.command:  # seen while the bit is set: its fall acks
            self._armed |= bool(self._last_client >> (self.command - 1) & 1)
        flags = {
            "done": held["done"],
            "busy": bool(getattr(current, "Busy", False)),
            "active": bool(getattr(current, "Active", False)),
            "error": held["error"],
            "command_aborted": held["command_aborted"],
            "homed": axis.Ref,
            "lim_neg": bool(io.lim_neg),
            "ref": bool(io.ref),
            "lim_pos": bool(io.lim_pos),
            "power": bool(self.power.Status),
            "index": bool(io.index),
            "in_velocity": bool(getattr(current, "InVelocity", False)),
            "in_gear": bool(getattr(current, "InGear", False)),
            "in_sync": bool(getattr(current, "InSync", False)),
            "start_sync": bool(getattr(current, "StartSync", False)),
            "in_force": bool(getattr(current, "InForce", False)),
        }
        status = sum(1 << i for i, name in enumerate(STATUS_BITS) if flags[name])
        inputs = sum(1 << i for i, on in enumerate(axis.DI) if on)
        p = self.prefix
        values = [
            (p + "status", status),
            (p + "state", int(axis.state)),
            (p + "error_id", self._held_error if held["error"] else 0),
            (p + "axis_error_id", axis.AxErrorID),
            (p + "actual_position", axis.POS),
            (p + "actual_velocity", axis.VEL),
            (p + "following_error", axis.following_error),
            (p + "volts", axis.volts),
            (p + "command", self.command),
            (p + "command_count", self.count),
            (p + "inputs", inputs),
        ]
        if "force" in self.fields:
            values.append((p + "actual_force", self.force_control.ActualForce))
        analog = axis.AI
        values += [
            (f"{p}analog_{k}", analog[k])
            for k in range(len(analog))
            if f"analog_{k}" in self.fields
        ]
        self.table.update(values)


_MASK = {name: 1 << i for i, name in enumerate(CONTROL_BITS)}
"""Each control bit's mask."""


def _showing(block: Command) -> bool:
    """Whether a block is busy or shows an output (so it must see the next scan)."""
    return bool(block.Busy or block.Done or block.Error or getattr(block, "CommandAborted", False))


_MISSING = {
    "home": "homing recipe",
    "gear_in": "gearing",
    "gear_in_pos": "gearing",
    "gear_out": "gearing",
    "force_control": "analog inputs",
}
"""What an axis lacks when it refuses a command bit."""


class BridgeProgram:
    """The bridge's PLC program for a scene: one :class:`AxisBridge` per axis of each table.
    Call it once per PLC scan; :meth:`publish` writes the status, the simulation fields and
    the published signals into the tables — every scan, or (``publish_every_scan`` False) when
    the runner calls it, at the end of each run of scans.

    Args:
        scene: the running scene.
        tables: its signal tables (a cell: one per part).
        homing: the homing recipes by axis name.
        publish_every_scan: publish after each scan.
    """

    def __init__(
        self,
        scene: Scene,
        tables: Sequence[SignalTable],
        homing: dict[str, Recipe],
        publish_every_scan: bool = True,
    ) -> None:
        self.scene = scene
        self.tables = list(tables)
        self.axes = []
        for table in self.tables:
            axes = [scene.axes[a] for a in table.axes]
            self.axes += [AxisBridge(axis, homing.get(axis.name), table, axes) for axis in axes]
        self.cycles = 0
        self.publish_every_scan = publish_every_scan
        self.publish()

    @property
    def target(self) -> int:
        """The lockstep target cycle: the largest any table was given."""
        return max(int(table.get("sim.target")) for table in self.tables)

    def __call__(self) -> None:
        """One PLC scan (the axes of a table whose PLC is not in control are left alone)."""
        for axis in self.axes:
            if axis.table.in_control:
                axis()
            else:
                axis.observe()
        self.cycles += 1
        if self.publish_every_scan:
            self.publish()

    def publish(self) -> None:
        """Write every axis' status, the simulation fields and the signals into the tables."""
        for axis in self.axes:
            axis.publish()
        scene = self.scene
        for table in self.tables:
            table.update(
                [
                    ("sim.time", scene.time),
                    ("sim.cycle", self.cycles),
                    *((f"signal.{name}", scene.signal(name)) for name in table.signals),
                ]
            )
