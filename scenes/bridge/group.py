"""The bridge's group block: the axes a machine names as its group (``MachineDef.group``: the
gantry's X, Y, Z) moved together on lines, arcs and paths through the library's group blocks
(docs/bridge.md, The group block).

==============  =====================================================================
enable          a level: MC_AddAxisToGroup for each member, then MC_GroupEnable; cleared:
                MC_GroupDisable, then MC_UngroupAllAxes (the members' own enable bits power
                them)
reset           ``MC_GroupReset``
move_linear     ``MC_MoveLinearAbsolute`` (Position = end_k), ``…Relative`` (Distance) when
                ``relative`` is 1
move_circular   ``MC_MoveCircularAbsolute`` / ``…Relative`` (circ_mode, aux_k, end_k,
                path_choice, plane, turns)
append_line     appends a line to end_k to the group's path table (as a segment of
                MC_PATH_DATA_REF: the motion fields, buffer_mode, relative)
append_arc      appends an arc (the fields of move_circular) to the path table
clear_path      empties the path table
move_path       ``MC_MovePath`` of the path table (its first segment in buffer_mode)
stop            ``MC_GroupStop`` (deceleration, jerk; 0: the defaults)
==============  =====================================================================

The velocity, acceleration, deceleration, jerk and buffer_mode fields are those of every move.
The status, the handshake and ``command_count`` work as for an axis (:mod:`scenes.bridge.program`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, ClassVar

import mcl
from mcl.command import Status
from mcl.fb import ExecuteFB
from scenes.bridge.handshake import Command, CommandWord, _int, _showing
from scenes.bridge.table import GROUP_CONTROL_BITS, GROUP_STATUS_BITS, SignalTable

MAX_SEGMENTS = 1000
"""The most segments the group's path table takes (another append gives EParam)."""


class _TableCommand(ExecuteFB):
    """A command on the group's path table (append a segment, clear it): Done in the scan of
    its Execute edge, EParam when the table is full."""

    REFS: ClassVar[tuple[str, ...]] = ()

    def __init__(self, action: Callable[[], bool]) -> None:
        super().__init__()
        self._action = action

    def _begin(self) -> int:
        return 0 if self._action() else int(mcl.ErrorID.EParam)

    def _poll(self) -> Status | None:
        return Status.Done


class GroupBridge(CommandWord):
    """The group of a table (its ``members``) and the scan that drives it from the group block.

    Args:
        members: the group's axes, in member order.
        table: the signal table.
    """

    BITS = GROUP_CONTROL_BITS

    def __init__(self, members: list[mcl.Axis], table: SignalTable) -> None:
        super().__init__(table.group, table)
        self.members = members
        self.prefix = f"{table.group}."
        self.group = mcl.AxesGroup(table.group)
        group = self.group
        self.add = [mcl.MC_AddAxisToGroup(AxesGroup=group, Axis=axis) for axis in members]
        self.enable = mcl.MC_GroupEnable(AxesGroup=group)
        self.disable = mcl.MC_GroupDisable(AxesGroup=group)
        self.ungroup = mcl.MC_UngroupAllAxes(AxesGroup=group)
        self.reset = mcl.MC_GroupReset(AxesGroup=group)
        self.linear = (
            mcl.MC_MoveLinearAbsolute(AxesGroup=group),
            mcl.MC_MoveLinearRelative(AxesGroup=group),
        )
        self.circular = (
            mcl.MC_MoveCircularAbsolute(AxesGroup=group),
            mcl.MC_MoveCircularRelative(AxesGroup=group),
        )
        self.path = mcl.MC_MovePath(AxesGroup=group)
        self.stop = mcl.MC_GroupStop(AxesGroup=group)
        self.status = mcl.MC_GroupReadStatus(AxesGroup=group)
        self.error = mcl.MC_GroupReadError(AxesGroup=group)
        self.table_data = mcl.MC_PATH_DATA_REF()
        """The path table the append commands fill and move_path runs."""
        self.append_line = _TableCommand(lambda: self._append(False))
        self.append_arc = _TableCommand(lambda: self._append(True))
        self.clear = _TableCommand(self._clear)
        self._calls: dict[str, Callable[[bool], None]] = {
            "reset": lambda x: self.reset(Execute=x),
            "move_linear": lambda x: self._pair(self.linear, x, self._linear_inputs),
            "move_circular": lambda x: self._pair(self.circular, x, self._circular_inputs),
            "append_line": lambda x: self.append_line(Execute=x),
            "append_arc": lambda x: self.append_arc(Execute=x),
            "clear_path": lambda x: self.clear(Execute=x),
            "move_path": lambda x: self.path(Execute=x, PathData=self.table_data, **self._buffer()),
            "stop": lambda x: self.stop(
                Execute=x, Deceleration=self._param("deceleration"), Jerk=self._param("jerk")
            ),
        }

    def _param(self, name: str) -> float:
        return self.table.get(self.prefix + name)

    def _relative(self) -> int:
        return 1 if self._param("relative") else 0

    def _block_for(self, name: str) -> Command | None:
        blocks: dict[str, Command] = {
            "reset": self.reset,
            "move_linear": self.linear[self._relative()],
            "move_circular": self.circular[self._relative()],
            "append_line": self.append_line,
            "append_arc": self.append_arc,
            "clear_path": self.clear,
            "move_path": self.path,
            "stop": self.stop,
        }
        return blocks.get(name)

    def __call__(self) -> None:
        """One PLC scan: the group's control word → its blocks (as an axis' scan)."""
        client, word = self._words()
        last, self._last_word = self._last_word, word
        self._grouping(bool(word & 1))
        for i, name in enumerate(self.BITS):
            call = self._calls.get(name)
            mask = 1 << i
            if call is not None and (word & mask or last & mask or self._busy(name)):
                call(bool(word & mask))
        rising = word & ~last
        if rising & ~1:
            self._started(rising)
        self._hold(client)

    def _busy(self, name: str) -> bool:
        if name == "move_linear":
            return any(_showing(b) for b in self.linear)
        if name == "move_circular":
            return any(_showing(b) for b in self.circular)
        block = self._block_for(name)
        return block is not None and _showing(block)

    def _grouping(self, on: bool) -> None:
        """The enable level: add the members one after the other and enable the group; when
        it falls, disable the group and take it apart."""
        for k, add in enumerate(self.add):
            add(Execute=on and (k == 0 or self.add[k - 1].Done))
        self.enable(Execute=on and self.add[-1].Done)
        self.disable(Execute=not on and bool(self.group.axes))
        self.ungroup(Execute=not on and self.disable.Done)

    def _pair(
        self, pair: tuple[Any, Any], execute: bool, inputs: Callable[[int], dict[str, Any]]
    ) -> None:
        """The absolute and the relative block of a move: the one ``relative`` selects gets
        ``execute``, the other FALSE while it still shows an output."""
        chosen = self._relative()
        for k, block in enumerate(pair):
            if k == chosen:
                block(Execute=execute, **inputs(k))
            elif _showing(block):
                block(Execute=False)

    def _points(self, name: str) -> list[float]:
        return [self._param(f"{name}_{k + 1}") for k in range(len(self.members))]

    def _dynamics(self) -> dict[str, float]:
        return {
            "Velocity": self._param("velocity"),
            "Acceleration": self._param("acceleration"),
            "Deceleration": self._param("deceleration"),
            "Jerk": self._param("jerk"),
        }

    def _buffer(self) -> dict[str, int]:
        return {"BufferMode": _int(self._param("buffer_mode"))}

    def _linear_inputs(self, relative: int) -> dict[str, Any]:
        target = "Distance" if relative else "Position"
        return {target: self._points("end"), **self._dynamics(), **self._buffer()}

    def _arc_fields(self) -> dict[str, Any]:
        return {
            "CircMode": _int(self._param("circ_mode")),
            "AuxPoint": self._points("aux"),
            "EndPoint": self._points("end"),
            "PathChoice": _int(self._param("path_choice")),
            "Plane": _int(self._param("plane")),
            "Turns": _int(self._param("turns")),
        }

    def _circular_inputs(self, relative: int) -> dict[str, Any]:
        return {**self._arc_fields(), **self._dynamics(), **self._buffer()}

    def _append(self, circular: bool) -> bool:
        """Append a segment from the fields; False when the table is full."""
        segments = self.table_data.Segments
        if len(segments) >= MAX_SEGMENTS:
            return False
        relative = bool(self._relative())
        segment = mcl.MC_PATH_SEGMENT(
            Circular=circular,
            EndPoint=self._points("end"),
            Relative=relative,
            AuxRelative=relative,
            Velocity=self._param("velocity"),
            Acceleration=self._param("acceleration"),
            Deceleration=self._param("deceleration"),
            Jerk=self._param("jerk"),
            BufferMode=_int(self._param("buffer_mode")),
        )
        if circular:
            segment.AuxPoint = self._points("aux")
            segment.CircMode = _int(self._param("circ_mode"))
            segment.PathChoice = _int(self._param("path_choice"))
            segment.Plane = _int(self._param("plane"))
            segment.Turns = _int(self._param("turns"))
        segments.append(segment)
        return True

    def _clear(self) -> bool:
        self.table_data.Segments.clear()
        return True

    def publish(self) -> None:
        """Write the group's status and actual positions into the table."""
        current, held = self.current, self._held
        self._arm()
        self.status(Enable=True)
        self.error(Enable=True)
        state = self.group.state
        flags = {
            "done": held["done"],
            "busy": bool(getattr(current, "Busy", False)),
            "active": bool(getattr(current, "Active", False)),
            "error": held["error"],
            "command_aborted": held["command_aborted"],
            "enabled": state != mcl.GroupState.GroupDisabled,
            "in_position": bool(self.status.InPosition),
        }
        p = self.prefix
        values: list[tuple[str, float]] = [
            (p + "status", sum(1 << i for i, n in enumerate(GROUP_STATUS_BITS) if flags[n])),
            (p + "state", int(state)),
            (p + "error_id", self._held_error if held["error"] else 0),
            (p + "group_error_id", self.error.GroupErrorID),
            (p + "command", self.command),
            (p + "command_count", self.count),
            (p + "segments", len(self.table_data.Segments)),
        ]
        values += [
            (f"{p}actual_{k + 1}", axis.POS if math.isfinite(axis.POS) else 0.0)
            for k, axis in enumerate(self.members)
        ]
        self.table.update(values)
