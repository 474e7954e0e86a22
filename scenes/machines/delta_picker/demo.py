"""The delta picker's demo: home the arms, group them with the delta kinematics, then pick every
part the infeed conveyor brings and place it in the tray.

The conveyor indexes: it runs until the photo eye (the touch probe of ``C``) latches a part's
leading edge, then stops the part's centre under the pick point (MC_MoveAbsolute to the latched
position plus the eye-to-pick distance). The robot picks it with the standard cycle, blended:
down 25 mm onto it, vacuum on, up 25 mm, across to its place in the tray (305 mm for the first
slot), down 25 mm, vacuum off, up and back over the belt. Every move is a Cartesian move of the
group (MC_MoveLinearAbsolute in MCS through the delta's inverse kinematics).
"""

from __future__ import annotations

__all__ = ["CLEAR", "PICK", "SLOTS", "Demo"]

from typing import Any

import mcl
from plc.procedures import HomeAxis
from plc.sequence import REST, Step, StepSequence, at_rest
from scenes.machines.delta_picker.axes import (
    ARMS,
    BELT_TOP,
    BELT_Y,
    DELTA,
    EYE_X,
    HOMING,
    PART_HEIGHT,
    PART_X,
    TOOL,
)
from scenes.machines.delta_picker.devices import VacuumGripper
from scenes.scene import Scene

B = mcl.MC_BufferMode
GRIP_Z = BELT_TOP + PART_HEIGHT + TOOL
"""The effector's centre when the cup touches a part's top [mm] (the tray's top is as high)."""
CLEAR = 25.0
"""The standard cycle's lift [mm]."""
PICK = (0.0, BELT_Y, GRIP_Z)
"""Where a part is picked [mm, MCS]."""
SLOTS = tuple((x, 155.0) for x in (315.0, -315.0, 225.0, -225.0, 135.0, -135.0, 45.0, -45.0))
"""The tray's places (x, y) [mm], 305 mm across the belt from the pick point, filled from the
outside in (a part carried 25 mm high never passes over one placed)."""
BELT_SPEED = 200.0
"""Conveyor speed while it brings a part [mm/s]."""
MOVE = {"Velocity": 2000.0, "Acceleration": 20000.0, "Deceleration": 20000.0, "Jerk": 1.0e6}
"""Path velocity [mm/s], acceleration [mm/s²], jerk [mm/s³] of the robot's moves."""
DWELL = 0.05
"""Vacuum build-up and release time [s]."""


class Demo(StepSequence):
    """Power, home the three arms (REF + motor index), group them and set the kinematics, then
    pick and place every part; finally ungroup. ``results``: one row per part."""

    STEPS = (
        "power on",
        "home the arms",
        "group the arms",
        "over the belt",
        "wait for a part",
        "bring it under the robot",
        "down to the part",
        "grip",
        "carry to the tray",
        "release",
        "back over the belt",
        REST,
        "done",
    )

    def __init__(self, scene: Scene) -> None:
        self.scene = scene
        self.arms = [scene.axes[a] for a in ARMS]
        self.belt = scene.axes["C"]
        self.gripper = scene.device("vacuum", VacuumGripper)
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
        self.feed = mcl.MC_MoveAbsolute(Axis=self.belt, Velocity=BELT_SPEED, Acceleration=2000.0)
        self.part = 0
        self.moves: dict[str, list[mcl.MC_MoveLinearAbsolute]] = {}
        for step, count in (
            ("over the belt", 1),
            ("down to the part", 1),
            ("carry to the tray", 3),
            ("back over the belt", 2),
        ):
            self.moves[step] = [
                mcl.MC_MoveLinearAbsolute(AxesGroup=group, **MOVE) for _ in range(count)
            ]
        self._aim(0)
        self.rows: list[dict[str, Any]] = []
        self.started = 0.0
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
            Step(
                "wait for a part", lambda: self.probe.Done, {"probe": self.probe, "run": self.run}
            ),
            Step("bring it under the robot", lambda: self.feed.Done, {"feed": self.feed}),
            self._path("down to the part"),
            Step("grip", self._dwelt, {"vacuum": self.vacuum}),
            self._path("carry to the tray"),
            Step("release", self._dwelt, {"vacuum": self.vacuum}),
            Step(
                "back over the belt",
                lambda: self.moves["back over the belt"][-1].Done,
                self._watch("back over the belt"),
                then=self._next_part,
            ),
            Step(
                REST,
                lambda: self.ungroup.Done and at_rest([*self.arms, self.belt]),
                {"disable": self.disable, "ungroup": self.ungroup},
            ),
            Step("done"),
        )

    @property
    def results(self) -> list[dict[str, Any]]:
        """One row per part placed."""
        return self.rows

    def _watch(self, step: str) -> dict[str, Any]:
        return {f"move{i}": m for i, m in enumerate(self.moves[step])}

    def _path(self, step: str) -> Step:
        moves = self.moves[step]
        return Step(step, lambda: moves[-1].Done, self._watch(step))

    def _aim(self, k: int) -> None:
        """Set the moves' positions for part ``k`` (its place in the tray)."""
        x, y = SLOTS[k % len(SLOTS)]
        px, py, pz = PICK
        up, place_up, place = (px, py, pz + CLEAR), (x, y, pz + CLEAR), (x, y, pz)
        self.moves["over the belt"][0].Position = list(up)
        self.moves["down to the part"][0].Position = list(PICK)
        carry = self.moves["carry to the tray"]
        for move, target, mode in zip(
            carry, (up, place_up, place), (B.Aborting, B.BlendingLow, B.BlendingLow), strict=True
        ):
            move.Position, move.BufferMode = list(target), mode
        back = self.moves["back over the belt"]
        back[0].Position, back[0].BufferMode = list(place_up), B.Aborting
        back[1].Position, back[1].BufferMode = list(up), B.BlendingLow

    def _dwelt(self) -> bool:
        return self.scene.time - self.entered >= DWELL

    def _next_part(self) -> str:
        """A part is placed: record it; the next part, or the end."""
        grips = self.gripper.grips
        grip = grips[-1] if grips else None
        self.rows.append(
            {
                "part": self.part,
                "pick error [mm]": grip.error if grip is not None else None,
                "cycle [s]": self.scene.time - self.started,
            }
        )
        self.started = self.scene.time
        self.part += 1
        if self.part >= len(PART_X):
            return REST
        self._aim(self.part)
        return "wait for a part"

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
        self.probe(Execute=step == "wait for a part")
        self.run(Execute=step == "wait for a part")
        if step == "bring it under the robot" and not self.feed.Busy and not self.feed.Done:
            self.feed.Position = self.probe.RecordedPosition + (PICK[0] - (EYE_X - 30.0))
        self.feed(Execute=step == "bring it under the robot")
        self.vacuum(Execute=step in ("grip", "release"), Value=step == "grip")
        for name, moves in self.moves.items():
            for move in moves:
                move(Execute=step == name)
        self.disable(Execute=step == REST)
        self.ungroup(Execute=self.disable.Done)
        if step == "wait for a part" and not self.started:
            self.started = self.scene.time
        self.advance(self.scene.time)
