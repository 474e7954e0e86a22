"""The three-axis gantry (models/gantry.xml) wired to three mcl axes X, Y, Z.

Commissioning data: encoder 1 µm per count, Vmax = the axis velocity at 10 V (3000 rpm of each
motor), servo constants found by ``python -m scenes.tools.commissioning gantry X`` (Y, Z): velocity
steps on each amplifier give its gain, lag and friction; Ff corrects the gain, Ka = the lag plus
the module's delays, Kv = 1/(2·lag) ≈ 195 1/s, Kf the friction's voltage, Ki a corner at Kv/8
(what is left, and the weight on Z).
Software limits 2 mm outside the working travel, inside the LIM switches (5 mm outside it); from
Vmax the error-stop ramp (max_deceleration) ends before the hard stops.
"""

from __future__ import annotations

from typing import Any, ClassVar

import mcl
from scenes.definition import AxisDef, MachineDef
from scenes.procedures import HomeAxis, HomingRecipe
from scenes.program import StepSequence
from scenes.scene import Scene


def _spec(
    vmax: float,
    gains: tuple[float, float, float, float, float],
    travel: tuple[float, float],
    homing: HomingRecipe,
) -> AxisDef:
    """One gantry axis: ``gains`` = (Kp, Ki, Ff, Ka, Kf) from the commissioning procedure,
    ``travel`` = working travel [mm] (the software limits lie SW_MARGIN outside it)."""
    kp, ki, ff, ka, kf = gains
    return AxisDef(
        config=mcl.AxisConfig(
            resolution=0.001,
            dev_max=2.0,
            in_position=0.005,
            acceleration=2000.0,
            deceleration=2000.0,
            jerk=50000.0,
            max_acceleration=20000.0,
            max_deceleration=20000.0,
        ),
        constants=mcl.ServoConstants(
            Kp=kp,
            Ki=ki,
            Ff=ff,
            Kc=50.0,
            Vmax=vmax,
            LimPos=travel[1] + SW_MARGIN,
            LimNeg=travel[0] - SW_MARGIN,
            Filter=2.0,
            Ka=ka,
            Kf=kf,
            Ki1=0.0,
        ),
        homing=homing,
    )


SW_MARGIN = 2.0
"""Software limits outside the working travel [mm]; the LIM switches trip 5 mm outside it."""

HOMING = {
    # REF is on below its edge: search away from it (SwitchNegative), stop where it goes off,
    # then the next index pulse in the positive direction is the origin. SetPosition makes the
    # coordinate equal the joint coordinate in mm (index pulses at 120, 100 and -20 mm).
    "X": HomingRecipe(set_position=120.0),
    "Y": HomingRecipe(set_position=100.0),
    "Z": HomingRecipe(set_position=-20.0, search_velocity=25.0),
}
"""REF switch + index homing of each axis."""

AXES = {
    "X": _spec(1000.0, (1.9565, 47.78, 1.0015, 0.00256, 0.006), (0.0, 1000.0), HOMING["X"]),
    "Y": _spec(1000.0, (1.9638, 48.05, 1.0033, 0.00256, 0.0133), (0.0, 600.0), HOMING["Y"]),
    "Z": _spec(500.0, (3.9466, 97.17, 1.0018, 0.00254, 0.0143), (-250.0, 0.0), HOMING["Z"]),
}
"""Commissioning data of the gantry axes (user units mm)."""


def build(start: dict[str, float] | None = None, **scene_options: Any) -> Scene:
    """The gantry scene.

    Args:
        start: joint coordinates at power-up [m] per axis, e.g. ``{"X": 0.3}``.
        **scene_options: ``servo_period``, ``plc_period``, ``trace_every`` (see :class:`Scene`).
    """
    return Scene([MACHINE], start=start, **scene_options)


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
ZIGZAG_START = {"X": 0.3, "Y": 0.1, "Z": -0.1}
"""Joint coordinates [m] where the contour test path (:data:`ZIGZAG`) starts."""
ZIGZAG = (
    (150.0, 60.0, -40.0),
    (-150.0, 60.0, -40.0),
    (150.0, 60.0, 40.0),
    (-150.0, 60.0, 40.0),
    (150.0, 60.0, 0.0),
)
"""A zigzag in space: five straight segments [mm] (X, Y, Z distances), turning by 129–138° at
each corner; the contour measurement of the gantry (tests and benchmark) runs it."""


class Demo(StepSequence):
    """The gantry demo: power, home Z then X and Y (REF + index), group the axes, then a
    pick-and-place cycle along straight lines (MC_MoveLinearAbsolute) with blended corners.

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
        # constant inputs are bound once; a scan passes only what changes (Enable, Execute)
        self.power = [mcl.MC_Power(Axis=axis) for axis in self.axes]
        self.home = {n: HomeAxis(scene.axes[n], HOMING[n]) for n in ("X", "Y", "Z")}
        self.add = [mcl.MC_AddAxisToGroup(AxesGroup=group, Axis=axis) for axis in self.axes]
        self.enable = mcl.MC_GroupEnable(AxesGroup=group)
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
        self._timer = 0.0
        self.error = ""
        self._watched = [self._blocks_of(step) for step in self.STEPS]
        """Per step, the blocks whose error stops the demo."""
        self.blocks: dict[str, Any] = {
            **{f"home{n}": h for n, h in self.home.items()},
            **{f"move{b}.{i}": m for b, ms in enumerate(self.moves) for i, m in enumerate(ms)},
        }
        """The blocks a report watches, by name."""

    def _blocks_of(self, step: str) -> tuple[Any, ...]:
        """The blocks that act in ``step``."""
        if step.startswith("home"):
            return tuple(self.home.values())
        if step.startswith("group"):
            return (*self.add, self.enable)
        if step in self.BATCH_OF:
            return tuple(self.moves[self.BATCH_OF[step]])
        return ()

    def _next(self) -> None:
        self.index += 1
        self._timer = self.scene.time

    def __call__(self) -> None:
        """One PLC scan."""
        step = self.STEPS[self.index]
        for power in self.power:
            power.Enable = True
            power()
        self.home["Z"](Execute=step == "home Z")
        for name in ("X", "Y"):
            self.home[name](Execute=step == "home X and Y")
        grouping = step == "group X, Y, Z"
        for add in self.add:
            add.Execute = grouping
            add()
        self.enable.Execute = grouping and self.add[-1].Done
        self.enable()
        batch_of = self.BATCH_OF
        for b, moves in enumerate(self.moves):
            start = batch_of.get(step) == b
            for move in moves:
                move.Execute = start
                move()
        for fb in self._watched[self.index]:
            if fb.Error:
                self.error = f"{step}: error {fb.ErrorID}"
                return
        dwell = self.scene.time - self._timer >= DWELL
        if (
            (step == "power on" and all(p.Status for p in self.power))
            or (step == "home Z" and self.home["Z"].Done)
            or (step == "home X and Y" and self.home["X"].Done and self.home["Y"].Done)
            or (step == "group X, Y, Z" and self.enable.Done)
            or (step in batch_of and self.moves[batch_of[step]][-1].Done)
            or (step in ("grip", "release") and dwell)
        ):
            self._next()


MACHINE = MachineDef(
    name="gantry",
    description="three-axis Cartesian gantry: ball screws, servo amplifiers, Z brake",
    model="gantry.xml",
    axes=AXES,
    demo=Demo,
    demo_start={"X": 0.43, "Y": 0.27, "Z": -0.12},
)
"""The gantry in the registry."""
