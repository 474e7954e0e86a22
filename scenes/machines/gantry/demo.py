"""The gantry demo: a pick-and-place cycle along blended straight lines."""

from __future__ import annotations

__all__ = ["DWELL", "PATH", "PATH_VELOCITY", "PICK", "PLACE", "SAFE_Z", "B", "Demo"]

from typing import Any, ClassVar

import mcl
from plc.procedures import HomeAxis
from plc.sequence import REST, Step, StepSequence, at_rest
from scenes.machines.gantry.axes import HOMING
from scenes.scene import Scene

B = mcl.MC_BufferMode
SAFE_Z = -40.0
"""Travel height of the tool [mm] (Z coordinate; 0 = top)."""
PICK = (250.0, 150.0, -220.0)
PLACE = (750.0, 450.0, -220.0)
PATH: tuple[tuple[tuple[tuple[float, float, float], mcl.MC_BufferMode], ...], ...] = (
    # batch 1: over the part and down to it; the corner in the air is blended
    (((PICK[0], PICK[1], SAFE_Z), B.Aborting), (PICK, B.BlendingLow)),
    # batch 2 (after gripping): up, across, down to the place position, corners blended
    (
        ((PICK[0], PICK[1], SAFE_Z), B.Buffered),
        ((PLACE[0], PLACE[1], SAFE_Z), B.BlendingLow),
        (PLACE, B.BlendingLow),
    ),
    # batch 3 (after releasing): up and back to the parking position
    (((PLACE[0], PLACE[1], SAFE_Z), B.Buffered), ((500.0, 300.0, SAFE_Z), B.BlendingLow)),
)
"""The pick-and-place path: batches of straight segments (end point [mm], BufferMode)."""
PATH_VELOCITY = 200.0
"""Path velocity [mm/s]."""
DWELL = 0.3
"""Gripper time at pick and place [s]."""


class Demo(StepSequence):
    """The gantry demo: power, home Z then X and Y (REF + index), group the axes, then a
    pick-and-place cycle along straight lines (MC_MoveLinearAbsolute) with blended corners;
    finally the group is disabled and taken apart (every axis at rest, single again).

    Call once per PLC cycle; ``step`` says what it is doing, ``done`` when finished.
    """

    STEPS = (
        "power on",
        "home Z",
        "home X and Y",
        "group X, Y, Z",
        "move over the part",
        "grip",
        "carry to the place position",
        "release",
        "return to park",
        REST,
        "done",
    )
    BATCH_OF: ClassVar[dict[str, int]] = {
        "move over the part": 0,
        "carry to the place position": 1,
        "return to park": 2,
    }
    """The step that runs each batch of PATH."""

    def __init__(self, scene: Scene) -> None:
        self.scene = scene
        self.axes = [scene.axes[n] for n in ("X", "Y", "Z")]
        group = self.group = mcl.AxesGroup("gantry", corner_tolerance=0.02)
        # constant inputs are bound once; a scan sets only what changes (Execute)
        self.power = [mcl.MC_Power(Axis=axis, Enable=True) for axis in self.axes]
        self.home = {n: HomeAxis(scene.axes[n], HOMING[n]) for n in ("X", "Y", "Z")}
        self.add = [mcl.MC_AddAxisToGroup(AxesGroup=group, Axis=axis) for axis in self.axes]
        self.enable = mcl.MC_GroupEnable(AxesGroup=group)
        self.disable = mcl.MC_GroupDisable(AxesGroup=group)
        self.ungroup = mcl.MC_UngroupAllAxes(AxesGroup=group)
        self.moves = [
            [
                mcl.MC_MoveLinearAbsolute(
                    AxesGroup=group,
                    Position=position,
                    Velocity=PATH_VELOCITY,
                    Acceleration=2000.0,
                    Deceleration=2000.0,
                    Jerk=20000.0,
                    BufferMode=mode,
                )
                for position, mode in batch
            ]
            for batch in PATH
        ]
        self.index = 0
        self.error = ""
        homing = {f"home{n}": h for n, h in self.home.items()}
        self.blocks: dict[str, Any] = {
            **homing,
            **{f"move{b}.{i}": m for b, ms in enumerate(self.moves) for i, m in enumerate(ms)},
        }
        """The blocks a report watches, by name."""
        grouping = {
            **{f"add{n}": add for n, add in zip(("X", "Y", "Z"), self.add, strict=True)},
            "enable": self.enable,
        }
        self.declare(
            Step("power on", lambda: all(p.Status for p in self.power)),
            Step("home Z", lambda: self.home["Z"].Done, homing),
            Step("home X and Y", lambda: self.home["X"].Done and self.home["Y"].Done, homing),
            Step("group X, Y, Z", lambda: self.enable.Done, grouping),
            self._batch("move over the part"),
            Step("grip", self._dwelt),
            self._batch("carry to the place position"),
            Step("release", self._dwelt),
            self._batch("return to park"),
            Step(
                REST,
                lambda: self.ungroup.Done and at_rest(self.axes),
                {"disable": self.disable, "ungroup": self.ungroup},
            ),
            Step("done"),
        )

    def _batch(self, step: str) -> Step:
        """The step that runs a batch of PATH: complete when its last move is Done."""
        moves = self.moves[self.BATCH_OF[step]]
        return Step(step, lambda: moves[-1].Done, {f"move{i}": m for i, m in enumerate(moves)})

    def _dwelt(self) -> bool:
        """The gripper's time is over."""
        return self.scene.time - self.entered >= DWELL

    def failure(self, step: str, block: str, error_id: int) -> str:
        """The ``error`` text: the step and the ErrorID."""
        return f"{step}: error {error_id}"

    def __call__(self) -> None:
        """One PLC scan."""
        step = self.STEPS[self.index]
        for power in self.power:
            power()
        home = self.home
        home["Z"](Execute=step == "home Z")
        homing = step == "home X and Y"
        home["X"](Execute=homing)
        home["Y"](Execute=homing)
        grouping = step == "group X, Y, Z"
        for add in self.add:
            add.Execute = grouping
            add()
        enable, disable, ungroup = self.enable, self.disable, self.ungroup
        enable.Execute = grouping and self.add[-1].Done
        enable()
        disable.Execute = step == REST
        disable()
        ungroup.Execute = disable.Done
        ungroup()
        batch = self.BATCH_OF.get(step)
        for b, moves in enumerate(self.moves):
            start = b == batch
            for move in moves:
                move.Execute = start
                move()
        self.advance(self.scene.time)
