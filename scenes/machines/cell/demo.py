"""The cell's demo: the gantry's pick-and-place and the press's cycle, over and over until the
gantry is done, at once, each machine's own demo unchanged, under the zone interlock."""

from __future__ import annotations

__all__ = ["RAM_UP", "ZONE_X", "Demo", "gantry_in_zone", "own_demo", "ram_up"]

from plc.sequence import DemoProgram
from scenes.machines.cell.interlock import ZoneInterlock, ZoneUser
from scenes.scene import Scene

ZONE_X = 0.60
"""The shared zone begins where the gantry's X joint passes 0.60 m (its place position is at
0.75 m, beside the press) [m]."""
RAM_UP = 0.020
"""The press's ram counts as up above 20 mm of stroke (it returns to 10 mm) [m]."""


def own_demo(scene: Scene, machine: str) -> DemoProgram:
    """A new run of machine ``machine``'s own demo, in its own view of the cell's scene."""
    view = scene.machine(machine)
    (definition,) = view.machines
    if definition.demo is None:
        raise LookupError(f"machine {machine!r} of the cell has no demo")
    return definition.demo(view)


def gantry_in_zone(scene: Scene) -> bool:
    """The gantry's X joint is in the shared zone (from the physics)."""
    return scene.machine("gantry").joint("X").position > ZONE_X


def ram_up(scene: Scene) -> bool:
    """The press's ram is up, out of the shared zone (from the physics)."""
    return scene.machine("press").joint("R").position < RAM_UP


class Demo:
    """Both machines' demos, the press's over and over until the gantry's is done, one of them
    in the shared zone at a time.

    Args:
        scene: the cell's scene.
        interlock: False runs the demos without the interlock (what it prevents).
    """

    def __init__(self, scene: Scene, interlock: bool = True) -> None:
        self.scene = scene
        self.gantry = ZoneUser(
            own_demo(scene, "gantry"),
            enter="carry to the place position",
            leave="return to park",
            left=lambda: not gantry_in_zone(scene),
        )
        self.press = ZoneUser(
            own_demo(scene, "press"),
            enter="rapid approach",
            leave="return",
            left=lambda: ram_up(scene),
        )
        self.cycles = 1
        """Press cycles begun so far."""
        self.interlock = ZoneInterlock([self.gantry, self.press], scene.runtime.plc_period)
        self.interlock.enabled = interlock

    @property
    def done(self) -> bool:
        """The gantry's demo and the press's last cycle have finished."""
        return self.gantry.demo.done and self.press.demo.done

    @property
    def error(self) -> str:
        """The first machine's error (empty: none)."""
        gantry, press = self.gantry.demo.error, self.press.demo.error
        if gantry:
            return f"gantry: {gantry}"
        return f"press: {press}" if press else ""

    @property
    def step(self) -> str:
        """What each machine does."""
        return self.error or f"gantry: {self.gantry.demo.step}; press: {self.press.demo.step}"

    def __call__(self) -> None:
        """One PLC scan of the cell."""
        gantry, press = self.gantry, self.press
        if gantry.demo.error or press.demo.error:
            return
        if press.demo.done and not gantry.demo.done and not press.holding:
            self.press.demo = own_demo(self.scene, "press")
            self.cycles += 1
        self.interlock()
