"""The operator program of one axes group: its function blocks and their sequencing, driven by a
front end (the bridge's group block, :mod:`plc.operator.group_bus`) through one vocabulary of
commands, as an axis' are (:mod:`plc.operator.axis`).

Each PLC scan the front end says in :class:`GroupOrders` what it wants: the ``enable`` level and
the Execute commands whose Execute is set (and those of them that start now, each with its
parameters). :class:`GroupOperator` passes them to the library's group blocks:

==============  ==================================================================================
enable          a level: ``MC_AddAxisToGroup`` for each member one after the other, then
                ``MC_GroupEnable``; cleared: ``MC_GroupDisable``, then ``MC_UngroupAllAxes`` (the
                members' own MC_Power powers them)
reset           ``MC_GroupReset``
move_linear     ``MC_MoveLinearAbsolute`` (Position = end_k), ``MC_MoveLinearRelative``
                (Distance = end_k) when ``relative`` is 1
move_circular   ``MC_MoveCircularAbsolute`` / ``…Relative`` (circ_mode, aux_k, end_k,
                path_choice, plane, turns)
append_line     appends a line to end_k (the motion parameters, buffer_mode, relative) to the
                group's path table, an ``MC_PATH_DATA_REF``
append_arc      appends an arc (the parameters of move_circular) to the path table
clear_path      empties the path table
move_path       ``MC_MovePath`` of the path table (its first segment in buffer_mode)
stop            ``MC_GroupStop`` (deceleration, jerk; 0: the block's defaults)
halt            ``MC_GroupHalt`` (deceleration, jerk) along the path
interrupt       ``MC_GroupInterrupt`` (deceleration, jerk): a feed hold on the path
continue        ``MC_GroupContinue``: the interrupted path resumes
set_override    ``MC_GroupSetOverride`` (vel_factor, acc_factor, jerk_factor): Enable while its
                Execute is set, with the factors sampled at its start; the group keeps them
track_belt      ``MC_TrackConveyorBelt`` (belt: the belt's axis number, frame_k and frame_rz:
                ConveyorBeltOrigin, object_k: InitialObjectPosition, latched_position, horizon,
                acceleration, jerk): the PCS moves with the part (a robot's group)
set_frame       ``MC_SetCoordinateTransform`` (frame_k, frame_rz, acceleration, jerk): a fixed
                PCS (zeros: the MCS), which ends a conveyor tracking
==============  ==================================================================================

velocity, acceleration, deceleration, jerk and buffer_mode are the parameters of every move and
segment, coord_system (an ``MC_COORD_SYSTEM``) of every move and of move_path; ``relative`` is
sampled when a move starts (it picks the absolute or the relative block). A group whose members
are a robot's joints gets its kinematics (``MC_SetKinTransform``) once it is enabled: a move in
MCS then moves the tool point, one in ACS the joints. The path-table commands are the
program's own (:class:`TableCommand`): Done in the scan they start, Error with EParam when the
table is full. A command's block is called while its Execute is set, in the scan it falls, and
while it is busy or shows an output, as an axis' is.
"""

from __future__ import annotations

__all__ = [
    "GROUP_COMMANDS",
    "MAX_SEGMENTS",
    "SCAN_ORDER",
    "GroupOperator",
    "GroupOrders",
    "OverrideCommand",
    "TableCommand",
]

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import mcl
from plc.operator.axis import Block, Parameters, showing, whole

GROUP_COMMANDS = (
    "reset",
    "move_linear",
    "move_circular",
    "append_line",
    "append_arc",
    "clear_path",
    "move_path",
    "stop",
    "halt",
    "interrupt",
    "continue",
    "set_override",
    "track_belt",
    "set_frame",
)
"""The group's Execute commands, in the order of their control bits."""

SCAN_ORDER = (*(c for c in GROUP_COMMANDS if c != "stop"), "stop")
"""The order a scan calls the commands in: a stop has the last word."""

MAX_SEGMENTS = 1000
"""The most segments the group's path table takes (another append gives EParam)."""


@dataclass(frozen=True, slots=True)
class GroupOrders:
    """What a front end tells a group in one PLC scan.

    Attributes:
        enable: the members grouped and the group enabled (a level).
        execute: the Execute commands (:data:`GROUP_COMMANDS`) whose Execute is set.
        start: of those, the ones that start now, each with its parameters.
    """

    enable: bool = False
    execute: frozenset[str] = frozenset()
    start: Mapping[str, Parameters] = field(default_factory=dict)


class TableCommand:
    """A command on the group's path table (append a segment, clear it) with a block's outputs:
    at the rising edge of Execute the action runs — Done, or Error with EParam when it refuses —
    and the outputs stay while Execute is set.

    Args:
        action: Runs the command with its parameters; whether it was taken.
    """

    def __init__(self, action: Callable[[Parameters], bool]) -> None:
        self._action = action
        self.Execute = False
        self.Done = False
        self.Busy = False
        self.Error = False
        self.ErrorID = 0

    def __call__(self, Execute: bool, params: Parameters | None = None) -> None:
        """One call: the action on the rising edge (with ``params``), else the outputs kept
        while Execute is set and cleared when it is not."""
        if Execute and not self.Execute and params is not None:
            taken = self._action(params)
            self.Done, self.Error = taken, not taken
            self.ErrorID = 0 if taken else int(mcl.ErrorID.EParam)
        elif not Execute:
            self.Done = self.Error = False
            self.ErrorID = 0
        self.Execute = Execute


class OverrideCommand:
    """MC_GroupSetOverride as an Execute command: Enable while Execute is set, with the factors
    given at its start; Done while the group follows them, Error with the block's ErrorID when
    it refuses them. The group keeps the factors when Execute falls.

    Args:
        block: The group's MC_GroupSetOverride.
    """

    def __init__(self, block: mcl.MC_GroupSetOverride) -> None:
        self.block = block
        self.Done = False
        self.Busy = False
        self.Error = False
        self.ErrorID = 0

    def __call__(self, Execute: bool, factors: Mapping[str, float] | None = None) -> None:
        """One call: the block enabled while ``Execute``, with ``factors`` (VelFactor, AccFactor,
        JerkFactor) when given."""
        block = self.block
        block(Enable=Execute, **(factors or {}))
        self.Done = Execute and bool(block.Enabled)
        self.Error = bool(block.Error)
        self.ErrorID = int(block.ErrorID)


class GroupOperator:
    """The function blocks of one axes group and their sequencing (one PLC scan per call with
    the front end's :class:`GroupOrders`).

    Args:
        name: The group's name.
        members: Its axes, in member order.
        kinematics: The group's kinematic transformation (None: the members' coordinates are
            the machine's).
        axes: The axes track_belt's ``belt`` numbers (the machine's, in its table's order).
    """

    def __init__(
        self,
        name: str,
        members: Sequence[mcl.Axis],
        kinematics: mcl.KinTransform | None = None,
        axes: Sequence[mcl.Axis] = (),
    ) -> None:
        self.members = list(members)
        self.axes = list(axes)
        self.group = group = mcl.AxesGroup(name)
        self.add = [mcl.MC_AddAxisToGroup(AxesGroup=group, Axis=axis) for axis in members]
        self.enable = mcl.MC_GroupEnable(AxesGroup=group)
        self.kinematics = (
            mcl.MC_SetKinTransform(AxesGroup=group, KinTransform=kinematics)
            if kinematics is not None
            else None
        )
        """Sets the kinematics once the group is enabled (None: the group has none)."""
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
        self.move_path = mcl.MC_MovePath(AxesGroup=group)
        self.stop = mcl.MC_GroupStop(AxesGroup=group)
        self.halt = mcl.MC_GroupHalt(AxesGroup=group)
        self.interrupt = mcl.MC_GroupInterrupt(AxesGroup=group)
        self.resume = mcl.MC_GroupContinue(AxesGroup=group)
        """The block of command ``continue``."""
        self.set_override = OverrideCommand(mcl.MC_GroupSetOverride(AxesGroup=group))
        self.track_belt = mcl.MC_TrackConveyorBelt(AxesGroup=group)
        self.set_frame = mcl.MC_SetCoordinateTransform(AxesGroup=group)
        self.status = mcl.MC_GroupReadStatus(AxesGroup=group)
        self.error = mcl.MC_GroupReadError(AxesGroup=group)
        self.path = mcl.MC_PATH_DATA_REF()
        """The path table the append commands fill and move_path runs."""
        self.append_line = TableCommand(lambda p: self._append(p, circular=False))
        self.append_arc = TableCommand(lambda p: self._append(p, circular=True))
        self.clear_path = TableCommand(self._clear)
        self.move_linear: Block = self.linear[0]
        """The linear move block the last start of move_linear chose (``relative``)."""
        self.move_circular: Block = self.circular[0]
        """The circular move block the last start of move_circular chose."""
        self._levels: frozenset[str] = frozenset()

    def block(self, command: str) -> Block:
        """The block of Execute command ``command`` (a move: the one its last start chose)."""
        return self.resume if command == "continue" else getattr(self, command)

    def __call__(self, orders: GroupOrders) -> None:
        """One PLC scan: the enable level, then the commands in :data:`GROUP_COMMANDS`' order."""
        self._grouping(orders.enable)
        levels = self._levels
        for name in SCAN_ORDER:
            execute = name in orders.execute
            params = orders.start.get(name)
            if params is not None:
                if name in levels:
                    self._call(name, False, None)  # a fresh rising edge
                self._choose(name, params)
            if execute or name in levels or showing(self.block(name)):
                self._call(name, execute, params)
        self._levels = orders.execute

    def read_status(self) -> None:
        """Read the group's status and error (MC_GroupReadStatus, MC_GroupReadError)."""
        self.status(Enable=True)
        self.error(Enable=True)

    def _grouping(self, on: bool) -> None:
        """The enable level: add the members one after the other and enable the group; when
        it falls, disable the group and take it apart."""
        add = self.add
        for k, block in enumerate(add):
            block(Execute=on and (k == 0 or add[k - 1].Done))
        self.enable(Execute=on and add[-1].Done)
        if self.kinematics is not None:
            self.kinematics(Execute=on and self.enable.Done)
        self.disable(Execute=not on and bool(self.group.axes))
        self.ungroup(Execute=not on and self.disable.Done)

    def _choose(self, name: str, params: Parameters) -> None:
        """At a move's start: the absolute or the relative block, as ``relative`` says (the
        other one, still showing an output, is released)."""
        pair = {"move_linear": self.linear, "move_circular": self.circular}.get(name)
        if pair is None:
            return
        chosen = pair[1] if whole(params("relative")) else pair[0]
        for block in pair:
            if block is not chosen and showing(block):
                block(Execute=False)
        setattr(self, name, chosen)

    def _call(self, name: str, execute: bool, params: Parameters | None) -> None:
        """Call command ``name``'s block with ``execute``; its inputs from ``params`` (at the
        start; None: the block keeps those it sampled)."""
        block = self.block(name)
        if isinstance(block, TableCommand):
            block(execute, params)
        elif isinstance(block, OverrideCommand):
            block(execute, self._inputs(name, params) if params else None)
        elif params is None:
            block(Execute=execute)
        else:
            block(Execute=execute, **self._inputs(name, params))

    def _inputs(self, name: str, p: Parameters) -> dict[str, Any]:
        """The inputs of command ``name``'s block from its parameters ``p``."""
        if name in ("reset", "continue"):
            return {}
        if name in ("stop", "halt", "interrupt"):
            return {"Deceleration": p("deceleration"), "Jerk": p("jerk")}
        if name == "set_override":
            return {
                "VelFactor": p("vel_factor"),
                "AccFactor": p("acc_factor"),
                "JerkFactor": p("jerk_factor"),
            }
        if name in ("track_belt", "set_frame"):
            return self._frame(name, p)
        coord = {"CoordSystem": whole(p("coord_system"))}
        if name == "move_path":
            return {"PathData": self.path, "BufferMode": whole(p("buffer_mode")), **coord}
        motion = {
            "Velocity": p("velocity"),
            "Acceleration": p("acceleration"),
            "Deceleration": p("deceleration"),
            "Jerk": p("jerk"),
            "BufferMode": whole(p("buffer_mode")),
        }
        if name == "move_linear":
            target = "Distance" if whole(p("relative")) else "Position"
            return {target: self._point(p, "end"), **motion, **coord}
        return {**self._arc(p), **motion, **coord}

    def _frame(self, name: str, p: Parameters) -> dict[str, Any]:
        """The inputs of MC_TrackConveyorBelt or MC_SetCoordinateTransform: the frame and the
        ramp into it; a belt number no axis has gives no belt (the block's EParam)."""
        frame = [*self._point(p, "frame"), p("frame_rz")]
        ramp = {"Acceleration": p("acceleration"), "Jerk": p("jerk")}
        if name == "set_frame":
            return {"CoordTransform": frame, **ramp}
        belt = whole(p("belt"))
        return {
            "ConveyorBelt": self.axes[belt] if 0 <= belt < len(self.axes) else None,
            "ConveyorBeltOrigin": frame,
            "InitialObjectPosition": self._point(p, "object"),
            "LatchedPosition": p("latched_position"),
            "Horizon": p("horizon"),
            **ramp,
        }

    def _point(self, p: Parameters, name: str) -> list[float]:
        """A point of the members: parameters ``<name>_1`` … ``<name>_n``."""
        return [p(f"{name}_{k + 1}") for k in range(len(self.members))]

    def _arc(self, p: Parameters) -> dict[str, Any]:
        """The inputs that make an arc (MC_MoveCircular*, a segment's)."""
        return {
            "CircMode": whole(p("circ_mode")),
            "AuxPoint": self._point(p, "aux"),
            "EndPoint": self._point(p, "end"),
            "PathChoice": whole(p("path_choice")),
            "Plane": whole(p("plane")),
            "Turns": whole(p("turns")),
        }

    def _append(self, p: Parameters, circular: bool) -> bool:
        """Append a segment from the parameters ``p``; False when the table is full."""
        segments = self.path.Segments
        if len(segments) >= MAX_SEGMENTS:
            return False
        relative = bool(whole(p("relative")))
        arc = self._arc(p) if circular else {"EndPoint": self._point(p, "end")}
        segments.append(
            mcl.MC_PATH_SEGMENT(
                Circular=circular,
                Relative=relative,
                AuxRelative=relative,
                Velocity=p("velocity"),
                Acceleration=p("acceleration"),
                Deceleration=p("deceleration"),
                Jerk=p("jerk"),
                BufferMode=whole(p("buffer_mode")),
                **arc,
            )
        )
        return True

    def _clear(self, p: Parameters) -> bool:
        """Empty the path table."""
        self.path.Segments.clear()
        return True
