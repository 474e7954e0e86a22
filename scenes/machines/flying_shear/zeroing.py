"""How well MC_GearInPos' Zeroing 2 zeroes the master at the print marks, measured from the
physics (a runtime observer of a flying-shear scene)."""

from __future__ import annotations

__all__ = ["ZeroingRecorder"]

from typing import Any

import mcl
from scenes.machines.flying_shear.devices import MARKS, mark_at
from scenes.scene import Scene


class ZeroingRecorder:
    """How well MC_GearInPos' Zeroing 2 zeroed the master at each print mark, from the physics;
    a runtime observer (called every servo cycle).

    When the master coordinate falls back by more than half a print pitch within a servo cycle,
    it has just been set to 0 at a mark; the recorder then compares it with the true strip
    travel since that mark passed the sensor.

    Args:
        scene: the flying-shear scene.
        marks: the print marks (on the strip coordinate M).
    """

    def __init__(self, scene: Scene, marks: mcl.Marks = MARKS) -> None:
        self.master = scene.axes["W"]
        self.marks = marks
        self._strip: Any = memoryview(scene.data.qpos)
        self._m = scene.joint("M").qpos_adr
        self._last = self.master.POS
        self.errors: list[float] = []
        """Per zeroing: master coordinate minus the true travel since the mark [mm]."""

    def __call__(self, t: float) -> None:
        """Observe one servo instant."""
        position, marks = self.master.POS, self.marks
        if position < self._last - 500.0 * marks.pitch:
            m = float(self._strip[self._m])
            travel = m - mark_at(marks, round((m - marks.first) / marks.pitch))
            self.errors.append(position - 1000.0 * travel)
        self._last = position
