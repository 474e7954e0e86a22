"""The delta picker's demo: home the arms, group them with the delta kinematics, then pick parts
on the fly from the running infeed conveyor and place them in the tray.

The belt runs on at :data:`BELT_SPEED`. The photo eye (the touch probe of ``C``, re-armed after
every latch) latches the belt's position as each part's leading edge cuts its beam; the light
curtain beside it gives the part's lateral position. For each latched part, in turn:
MC_TrackConveyorBelt makes the product coordinate system (PCS) move with the part (origin: the
effector's centre when the cup touches the part's centre); a part that will have left the
robot's reach within :data:`HORIZON`, or comes too fast, is refused with its ErrorID and the
next one is taken. Tracking, the robot goes across to 25 mm above the part and down to just
above it (blended, in PCS), waits until the tool point follows the part (its following error
settled), touches it, grips and lifts it 25 mm (still in PCS); then MC_SetCoordinateTransform
ends the tracking (the robot slows down to a standstill holding the part in the air) and the
standard cycle carries it into the tray in the MCS: across (off the belt's parts first), down
25 mm, blended; vacuum off, up 25 mm and on, blended, over the belt to where the next latched
part will be :data:`AHEAD` later, where the robot waits to track it. Every move runs at the
robot's TCP limits.
"""

from __future__ import annotations

__all__ = [
    "BELT_SPEED",
    "CLEAR",
    "HORIZON",
    "HOVER",
    "MOVE",
    "PICK",
    "SLOTS",
    "VACUUM_OFF",
    "VACUUM_ON",
    "Demo",
]

import math
from typing import Any

import mcl
from mcl.enums import MC_COORD_SYSTEM
from plc.procedures import HomeAxis
from plc.sequence import REST, Step, StepSequence, at_rest
from scenes.machines.delta_picker.axes import (
    ARMS,
    BELT_TOP,
    BELT_Y,
    DELTA,
    EYE_DELAY,
    EYE_X,
    HOMING,
    PART_HEIGHT,
    PART_X,
    TOOL,
)
from scenes.machines.delta_picker.devices import PART_LENGTH, PhotoEye, VacuumGripper
from scenes.scene import Scene

B = mcl.MC_BufferMode
GRIP_Z = BELT_TOP + PART_HEIGHT + TOOL
"""The effector's centre when the cup touches a part's top [mm] (the tray's top is as high)."""
CLEAR = 25.0
"""The standard cycle's lift [mm]."""
PICK = (0.0, BELT_Y, GRIP_Z)
"""The middle of the robot's reach over the belt [mm, MCS]."""
WAIT = (EYE_X + 100.0, BELT_Y, GRIP_Z + CLEAR)
"""Where the robot waits for the first part [mm, MCS]."""
PRESS = 1.0
"""How far below a part's nominal top the cup is set down onto it [mm]: the cup's bellows (the
3 mm within which its face pushes, models/README.md) take it up, and the lip seals; a part on
the belt sits 0.1–0.2 mm deep in the belt's soft contact (measured on the physics)."""
BELT_ORIGIN = [EYE_X, BELT_Y, GRIP_Z - PRESS]
"""The belt frame in the MCS (MC_TrackConveyorBelt's ConveyorBeltOrigin): at the photo eye on
the belt's centre line, at the grip height; x along the belt [mm]."""
SLOTS = tuple((x, 155.0) for x in (-315.0, -225.0, -135.0, -45.0, 45.0, 135.0, 225.0, 315.0))
"""The tray's places (x, y) [mm], 305 mm across the belt's centre line; a part goes to the free
one nearest to where it was picked."""
FRONT = 80.0
"""A carried part comes straight across into its place from this far in front of it [mm of
MCS y]: its far edge (30 mm from the cup's centre, a blended corner within 2 mm) stays 10 mm
short of the parts placed beside it, which it would hit, lifted only :data:`CLEAR`."""
CLEARED = 1.5
"""A place is free again this long after a part was placed there [s]: the outfeed takes a part
away once it has rested in the tray for 1 s."""
BELT_SPEED = 250.0
"""Conveyor speed [mm/s]."""
TRACK_FROM = -250.0
"""A part is tracked once its centre has come this far [mm of MCS x] (the arms' reach is
better away from its edge)."""
HORIZON = 0.4
"""A part is tracked only if it stays within reach this long [s]: reach it, settle, grip, lift
and stop take at most 0.33 s."""
MOVE = {"Velocity": 4000.0, "Acceleration": 100000.0, "Deceleration": 100000.0, "Jerk": 6.0e6}
"""Path velocity [mm/s], acceleration [mm/s²], jerk [mm/s³] of the robot's moves: those of the
standard cycle, the robot's TCP limits (``DELTA.tcp``)."""
AHEAD = 0.2
"""Going back to the belt, the robot heads for where the next part will be this much later [s]
(about as long as it takes to get there)."""
RAMP = 60000.0
"""The tool point's acceleration as it speeds up with the belt and slows down from it [mm/s²]."""
CORNER = 10.0
"""How far a blended corner of the cycle may leave the commanded path [mm]."""
SETTLED = 0.1
"""The tool point's following error across and along the belt at which the cup goes down onto
the part [mm]."""
HOVER = 4.0
"""The cup settles this far above the part's top before it touches it [mm], clear of the 3 mm
over which its bellows push: a cup that comes down still catching up with the part drags it
along (0.3 mm at 0.5 m/s, measured on the physics)."""
PLACED = 0.3
"""The tool point's following error at which the vacuum goes off over the tray [mm] (a part is
placed within a millimetre; stopping from the carry, the tool point lags up to 1 mm)."""
CONTACT = 0.08
"""The vacuum comes on this long after the cup began to come down onto a part [s] (the move
takes ~25 ms, then the bellows settle): pressed on the part, the cup rides with it while the
arms' following error stays a few tenths of a millimetre, so no following error tells when it
has settled. Measured on the physics over 40 parts at 0.5 and 1.0 m/s: pick errors within
0.22 mm for waits of 40–100 ms, 0.3 mm when the vacuum comes on at once; by 80 ms the cup's
face has come within 1 mm of the part's top."""
SETTLE_TIMEOUT = 0.1
"""The cup goes down onto the part (the vacuum on over the tray) at the latest this long after
it arrived [s]."""
OFF_BELT = BELT_Y + 100.0
"""A part carried this far across [mm, MCS y] clears the parts on the belt (their far edge
lies within 55 mm of its centre line, a carried part's 30 mm from the cup's centre, a blended
corner within :data:`CORNER`); lifted only :data:`CLEAR`, its 30 mm body would hit them."""
VACUUM_ON = 0.025
"""From the valve's opening until the cup holds the part [s]: a compact ejector at the cup (its
valve switching in 5–10 ms) evacuates a Ø40 mm bellows cup in 10–20 ms (models/README.md)."""
VACUUM_OFF = 0.015
"""From the valve's closing until the part is free [s] (a blow-off pulse vents the cup)."""


def _moves(group: mcl.AxesGroup) -> dict[str, list[mcl.MC_MoveLinearAbsolute]]:
    """The robot's moves, by the step that runs them."""
    counts = {
        "over the belt": 1,
        "down onto it": 2,
        "touch it": 1,
        "lift it": 1,
        "carry to the tray": 4,
        "up from the tray": 2,
    }
    return {
        step: [mcl.MC_MoveLinearAbsolute(AxesGroup=group, **MOVE) for _ in range(count)]
        for step, count in counts.items()
    }


CORNERING = (mcl.MC_TRANSITION_MODE.TMMaxCornerDeviation, [CORNER])


class Demo(StepSequence):
    """Power, home the three arms (REF + motor index), group them and set the kinematics, run
    the belt, then track, pick and place :attr:`parts` latched parts; finally stop the belt and
    ungroup. ``results``: one row per latched part (picked, or refused with its ErrorID)."""

    STEPS = (
        "power on",
        "home the arms",
        "group the arms",
        "over the belt",
        "wait for a part",
        "track it",
        "down onto it",
        "settle",
        "touch it",
        "grip",
        "lift it",
        "stop tracking",
        "carry to the tray",
        "settle over the tray",
        "release",
        "up from the tray",
        REST,
        "done",
    )

    def __init__(self, scene: Scene) -> None:
        self.scene = scene
        self.arms = [scene.axes[a] for a in ARMS]
        self.belt = scene.axes["C"]
        self.gripper = scene.device("vacuum", VacuumGripper)
        self.eye = scene.device("eye", PhotoEye)
        self.parts = len(PART_X)
        """How many latched parts the demo handles before it ends."""
        group = self.group = mcl.AxesGroup("delta", corner_tolerance=2.0)
        self.power = [mcl.MC_Power(Axis=axis) for axis in (*self.arms, self.belt)]
        self.home = [HomeAxis(scene.axes[a], HOMING[a]) for a in ARMS]
        self.add = [mcl.MC_AddAxisToGroup(AxesGroup=group, Axis=axis) for axis in self.arms]
        self.enable = mcl.MC_GroupEnable(AxesGroup=group)
        self.kinematics = mcl.MC_SetKinTransform(AxesGroup=group, KinTransform=DELTA)
        self.disable = mcl.MC_GroupDisable(AxesGroup=group)
        self.ungroup = mcl.MC_UngroupAllAxes(AxesGroup=group)
        self.vacuum = mcl.MC_WriteDigitalOutput(Axis=self.arms[0], OutputNumber=0)
        self.belt_ref = mcl.MC_FinishHoming(Axis=self.belt)
        """The belt's coordinate needs no reference: its power-up count is confirmed."""
        self.probe = mcl.MC_TouchProbe(Axis=self.belt)
        self.run = mcl.MC_MoveVelocity(Axis=self.belt, Velocity=BELT_SPEED, Acceleration=2000.0)
        self.halt = mcl.MC_Halt(Axis=self.belt, Deceleration=2000.0)
        self.track = mcl.MC_TrackConveyorBelt(
            AxesGroup=group,
            ConveyorBelt=self.belt,
            ConveyorBeltOrigin=BELT_ORIGIN,
            Horizon=HORIZON,
            Acceleration=RAMP,
        )
        self.untrack = mcl.MC_SetCoordinateTransform(AxesGroup=group, Acceleration=RAMP)
        self.queue: list[tuple[float, float]] = []
        """Latched parts not yet handled: belt position [mm] and lateral position [mm, MCS y]."""
        self.latched = 0
        self.picked = 0
        self.slot = 0
        """The tray's place the part held goes to (index in :data:`SLOTS`)."""
        self.placed_at = [-math.inf] * len(SLOTS)
        """When a part was placed in each of the tray's places last [s]."""
        self.moves = _moves(group)
        self._aim()
        self.rows: list[dict[str, Any]] = []
        self._gripped = 0
        """Grips the rows account for."""
        self.started = 0.0
        self._declare_steps()

    def _declare_steps(self) -> None:
        """The pick cycle's steps, each with the blocks it runs and watches."""
        grouping: dict[str, Any] = {f"add{i}": add for i, add in enumerate(self.add)}
        grouping |= {"enable": self.enable, "kinematics": self.kinematics}
        self.declare(
            Step(
                "power on",
                lambda: all(p.Status for p in self.power) and self.belt.Ref,
                {"belt reference": self.belt_ref},
            ),
            Step(
                "home the arms",
                lambda: all(h.Done for h in self.home),
                {f"home{i}": h for i, h in enumerate(self.home)},
            ),
            Step("group the arms", lambda: self.kinematics.Done, grouping),
            self._path("over the belt"),
            Step("wait for a part", self._waited, {"run": self.run}, then=self._next_part),
            Step("track it", lambda: self.track.Done or self.track.Error, then=self._tracked),
            self._path("down onto it"),
            Step("settle", self._settled),
            Step("touch it", self._touched, self._watch("touch it")),
            Step("grip", self._dwelt, {"vacuum": self.vacuum}),
            self._path("lift it"),
            Step(
                "stop tracking",
                lambda: self.untrack.Done,
                {"untrack": self.untrack},
                then=self._stopped,
            ),
            self._path("carry to the tray"),
            Step("settle over the tray", lambda: self._settled(PLACED)),
            Step("release", self._dwelt, {"vacuum": self.vacuum}, then=self._released),
            Step(
                "up from the tray",
                lambda: self.moves["up from the tray"][-1].Done,
                self._watch("up from the tray"),
                then=self._placed,
            ),
            Step(
                REST,
                lambda: self.ungroup.Done and at_rest([*self.arms, self.belt]),
                {"disable": self.disable, "ungroup": self.ungroup, "halt": self.halt},
            ),
            Step("done"),
        )

    @property
    def results(self) -> list[dict[str, Any]]:
        """One row per latched part handled."""
        return self.rows

    def _watch(self, step: str) -> dict[str, Any]:
        return {f"move{i}": m for i, m in enumerate(self.moves[step])}

    def _path(self, step: str) -> Step:
        moves = self.moves[step]
        return Step(step, lambda: moves[-1].Done, self._watch(step))

    def _aim(self) -> None:
        """Set the moves' positions of the pick cycle."""
        self.moves["over the belt"][0].Position = list(WAIT)
        down = self.moves["down onto it"]
        for move, target, mode in zip(
            down, ((0.0, 0.0, CLEAR), (0.0, 0.0, HOVER)), (B.Aborting, B.BlendingLow), strict=True
        ):
            move.Position, move.BufferMode = list(target), mode
            move.CoordSystem = MC_COORD_SYSTEM.PCS
            move.TransitionMode, move.TransitionParameter = CORNERING
        for step, z in (("touch it", 0.0), ("lift it", CLEAR)):
            move = self.moves[step][0]
            move.Position, move.BufferMode = [0.0, 0.0, z], B.Aborting
            move.CoordSystem = MC_COORD_SYSTEM.PCS
        self.carry_from(list(PICK))
        over = self.moves["up from the tray"][1]
        over.Position, over.BufferMode = list(WAIT), B.BlendingLow
        over.TransitionMode, over.TransitionParameter = CORNERING

    def _free_slot(self, x: float) -> int:
        """The free place in the tray nearest to ``x`` [mm, MCS]; the one filled longest ago if
        none is free."""
        now = self.scene.time
        free = [k for k, t in enumerate(self.placed_at) if now - t >= CLEARED]
        if not free:
            return min(range(len(SLOTS)), key=lambda k: self.placed_at[k])
        return min(free, key=lambda k: abs(SLOTS[k][0] - x))

    def carry_from(self, lifted: list[float]) -> None:
        """The rest of the standard cycle from where the lifted part came to a standstill [mm,
        MCS]: across the belt (the part off the belt's parts first), in front of the nearest
        free place, straight into it, down; then up from it."""
        self.slot = self._free_slot(lifted[0])
        x, y = SLOTS[self.slot]
        z = GRIP_Z + CLEAR
        off = max(lifted[1], OFF_BELT)
        targets = ((lifted[0], off, z), (x, y - FRONT, z), (x, y, z), (x, y, GRIP_Z))
        modes = (B.Aborting, B.BlendingLow, B.BlendingLow, B.BlendingLow)
        for move, target, mode in zip(self.moves["carry to the tray"], targets, modes, strict=True):
            move.Position, move.BufferMode = list(target), mode
        up = self.moves["up from the tray"][0]
        up.Position, up.BufferMode = [x, y, z], B.Aborting

    def _settled(self, within: float = SETTLED) -> bool:
        """The cup follows the part (or stands over its place): the tool point's following
        error (set point against actual, in the MCS) is ``within`` [mm] across and along the
        belt (the cup's bellows takes up a few tenths of a millimetre in height)."""
        if self.scene.time - self.entered >= SETTLE_TIMEOUT:
            return True
        actual = DELTA.forward([arm.actual for arm in self.arms])
        target = DELTA.forward([arm.sp_pos for arm in self.arms])
        return math.hypot(actual[0] - target[0], actual[1] - target[1]) <= within

    def _touched(self) -> bool:
        """The cup is down on the part and its bellows have settled: the touch is done and
        :data:`CONTACT` has passed since it began."""
        done = self.moves["touch it"][0].Done
        return done and self.scene.time - self.entered >= CONTACT - 1e-9

    def _dwelt(self) -> bool:
        """The vacuum has built up (grip) or vented (release)."""
        dwell = VACUUM_ON if self.STEPS[self.index] == "grip" else VACUUM_OFF
        return self.scene.time - self.entered >= dwell - 1e-9

    def _part_x(self, latch: float, later: float = 0.0) -> float:
        """The centre of the part latched at belt position ``latch`` [mm, MCS x], ``later`` [s]
        from now."""
        travel = self.belt.sp_pos - latch + self.run.Velocity * later
        return EYE_X - 500.0 * PART_LENGTH + travel

    def _released(self) -> str:
        """Up from the tray and over the belt, where the next part will be (or the first
        part's waiting place)."""
        self.placed_at[self.slot] = self.scene.time
        over = self.moves["up from the tray"][1]
        if self.queue:
            latch, lateral = self.queue[0]
            x = min(max(TRACK_FROM, self._part_x(latch, AHEAD)), -TRACK_FROM)
            over.Position = [x, lateral, GRIP_Z + CLEAR]
        else:
            over.Position = list(WAIT)
        return "up from the tray"

    def _waited(self) -> bool:
        """A latched part has come to :data:`TRACK_FROM`, or every part was latched."""
        if not self.queue:
            return self.latched >= self.parts
        return self._part_x(self.queue[0][0]) >= TRACK_FROM

    def _next_part(self) -> str:
        """Track the next latched part, or end once every part was handled."""
        if not self.queue:
            return REST
        latch, lateral = self.queue.pop(0)
        self.track.LatchedPosition = latch
        self.track.InitialObjectPosition = [-500.0 * PART_LENGTH, lateral - BELT_Y, 0.0]
        return "track it"

    def _tracked(self) -> str:
        """The part is tracked, or refused: record it and take the next one."""
        if self.track.Done:
            return "down onto it"
        self._record(error_id=self.track.ErrorID)
        return "wait for a part"

    def _stopped(self) -> str:
        """The robot stands holding the part: carry it from there."""
        self.carry_from(DELTA.forward([arm.sp_pos for arm in self.arms]))
        return "carry to the tray"

    def _placed(self) -> str:
        self._record()
        self.picked += 1
        return "wait for a part"

    def _record(self, error_id: int = 0) -> None:
        """One row: the part refused with ``error_id``, or picked (the cup gripped it)."""
        grips = self.gripper.grips
        grip = grips[-1] if len(grips) > self._gripped and not error_id else None
        self._gripped = len(grips)
        self.rows.append(
            {
                "part": len(self.rows),
                "picked": grip is not None,
                "error id": error_id,
                "pick error [mm]": grip.error if grip is not None else None,
                "place": self.slot if grip is not None else None,
                "cycle [s]": self.scene.time - self.started,
            }
        )
        self.started = self.scene.time

    def _latch(self, running: bool) -> None:
        """Keep the photo eye armed while the belt runs; queue every part it latches."""
        probe = self.probe
        if probe.Done and self.latched < self.parts:
            lateral = self.eye.lateral[-1] if self.eye.lateral else BELT_Y
            # the belt ran on for the eye's response time before the latch
            edge = probe.RecordedPosition - self.run.Velocity * EYE_DELAY
            self.queue.append((edge, lateral))
            self.latched += 1
        probe(Execute=running and not probe.Done and self.latched < self.parts)

    def __call__(self) -> None:
        """One PLC scan."""
        step = self.STEPS[self.index]
        for power in self.power:
            power(Enable=True)
        self.belt_ref(Execute=step == "power on" and self.power[-1].Status)
        for home in self.home:
            home(Execute=step == "home the arms")
        grouping = step == "group the arms"
        for add in self.add:
            add(Execute=grouping)
        self.enable(Execute=grouping and self.add[-1].Done)
        self.kinematics(Execute=grouping and self.enable.Done)
        running = self.index >= self.STEPS.index("over the belt") and step not in (REST, "done")
        self.run(Execute=running)
        self.halt(Execute=step == REST)
        self._latch(running and self.run.InVelocity)
        self.track(Execute=step == "track it")
        self.untrack(Execute=step == "stop tracking")
        self.vacuum(Execute=step in ("grip", "release"), Value=step == "grip")
        for name, moves in self.moves.items():
            for move in moves:
                move(Execute=step == name)
        self.disable(Execute=step == REST and self.halt.Done)
        self.ungroup(Execute=self.disable.Done)
        if step == "wait for a part" and not self.started:
            self.started = self.scene.time
        self.advance(self.scene.time)
