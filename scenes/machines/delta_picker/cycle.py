"""The standard pick cycle of the delta picker, the rate the industry quotes for its delta
robots: up 25 mm, across 305 mm, down 25 mm and back, the corners blended, with a 0.1 kg part.

:func:`prepare` homes and groups the arms (the demo's first steps; the belt stands) and lays
part 0 at the first of :data:`PLACES`, on the belt; the tray's place 305 mm across is the
second. :class:`StandardCycle` then carries the part there and back, ``cycles`` times: at each
place the vacuum comes on (:data:`VACUUM_ON`), one leg carries the part up, across and down
(three MC_MoveLinearAbsolute in the MCS, the second and third BlendingLow within
:data:`CORNER`), the vacuum goes off (:data:`VACUUM_OFF`) and the part stays there for the next
leg. A cycle is two legs (there and back), each a pick and a place.
"""

from __future__ import annotations

__all__ = ["CORNER", "CYCLE_MOVE", "PLACES", "StandardCycle", "prepare"]

from typing import Any

import mcl
from scenes.machines.delta_picker.axes import BELT_Y
from scenes.machines.delta_picker.demo import CLEAR, GRIP_Z, PRESS, VACUUM_OFF, VACUUM_ON, Demo
from scenes.scene import Scene

B = mcl.MC_BufferMode
PLACES = ((0.0, BELT_Y), (0.0, BELT_Y + 305.0))
"""The two places [mm, MCS x, y]: on the standing belt's centre line and in the tray, 305 mm
across."""
Z = GRIP_Z - PRESS
"""The effector's centre when the cup, pressed, sits on the part [mm]."""
CYCLE_MOVE = {
    "Velocity": 4000.0,
    "Acceleration": 100000.0,
    "Deceleration": 100000.0,
    "Jerk": 6.0e6,
}
"""Path velocity [mm/s], acceleration [mm/s²] and jerk [mm/s³] of the cycle's moves: the
robot's TCP limits (``DELTA.tcp``); the jerk leaves the TCP's largest jerk the room the corners'
turns take."""
CORNER = 10.0
"""How far a blended corner may leave the commanded path [mm]."""


def prepare(scene: Scene) -> mcl.AxesGroup:
    """Home and group the arms with the demo (the belt stands) and lay part 0 at the first
    place; the group, in GroupStandby."""
    demo = Demo(scene)
    scene.run(demo, until=lambda: demo.step == "over the belt" or bool(demo.error), timeout=10.0)
    if demo.error:
        raise RuntimeError(demo.error)
    model, data = scene.model, scene.data
    joint = model.joint(scene.model_name("part0_x"))
    slide, dof = int(joint.qposadr[0]), int(joint.dofadr[0])
    centre = data.xpos[model.body(scene.model_name("part0")).id] - data.qpos[slide : slide + 3]
    x, y = PLACES[0]
    data.qpos[slide] = x / 1000.0 - centre[0]
    data.qpos[slide + 1] = y / 1000.0 - centre[1]
    data.qvel[dof : dof + 6] = 0.0
    return demo.group


class StandardCycle:
    """The standard cycle, ``cycles`` times (module docstring); one call is one PLC scan.

    Attributes:
        legs: each leg's start and end [s] (vacuum on at the pick until vacuum off at the
            place).
        error: why it stopped ("" while it runs or when done).
    """

    def __init__(self, scene: Scene, group: mcl.AxesGroup, cycles: int) -> None:
        self.scene = scene
        self.cycles = cycles
        arm = scene.axes["A1"]
        self.on = mcl.MC_WriteDigitalOutput(Axis=arm, OutputNumber=0, Value=True)
        self.off = mcl.MC_WriteDigitalOutput(Axis=arm, OutputNumber=0, Value=False)
        self.down = mcl.MC_MoveLinearAbsolute(
            AxesGroup=group, Position=[*PLACES[0], Z], **CYCLE_MOVE
        )
        corner: dict[str, Any] = {
            "TransitionMode": mcl.MC_TRANSITION_MODE.TMMaxCornerDeviation,
            "TransitionParameter": [CORNER],
        }
        self.moves = []
        for start, end in (PLACES, PLACES[::-1]):
            path = ((*start, Z + CLEAR), (*end, Z + CLEAR), (*end, Z))
            modes = (B.Aborting, B.BlendingLow, B.BlendingLow)
            self.moves.append(
                [
                    mcl.MC_MoveLinearAbsolute(
                        AxesGroup=group, Position=list(p), BufferMode=m, **CYCLE_MOVE, **corner
                    )
                    for p, m in zip(path, modes, strict=True)
                ]
            )
        self.phase = "down"
        self.leg = 0
        self.since = scene.time
        self.legs: list[tuple[float, float]] = []
        self.error = ""

    @property
    def done(self) -> bool:
        """Every cycle ran."""
        return len(self.legs) >= 2 * self.cycles

    def __call__(self) -> None:
        """One PLC scan: run the phase's blocks, then go on when it is complete."""
        phase, now = self.phase, self.scene.time
        self.down(Execute=phase == "down")
        self.on(Execute=phase == "grip")
        self.off(Execute=phase == "release")
        for k, moves in enumerate(self.moves):
            for move in moves:
                move(Execute=phase == "carry" and k == self.leg % 2)
        blocks = [self.down, self.on, self.off, *self.moves[0], *self.moves[1]]
        failed = next((b for b in blocks if b.Error), None)
        if failed is not None:
            self.error = f"{type(failed).__name__} ErrorID {failed.ErrorID}"
            return
        if phase == "down" and self.down.Done:
            self._enter("grip", now)
        elif phase == "grip" and now - self.since >= VACUUM_ON - 1e-9:
            self.start = self.since
            self._enter("carry", now)
        elif phase == "carry" and self.moves[self.leg % 2][-1].Done:
            self._enter("release", now)
        elif phase == "release" and now - self.since >= VACUUM_OFF - 1e-9:
            self.legs.append((self.start, now))
            self.leg += 1
            self._enter("done" if self.done else "grip", now)

    def _enter(self, phase: str, now: float) -> None:
        self.phase, self.since = phase, now
