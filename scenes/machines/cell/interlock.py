"""The cell's zone interlock: the gantry's place position lies in a zone it shares with the
press's table, so the gantry may enter it only while the press's ram is up, and the press may
stroke only while the gantry is out of it.

Each machine's demo runs unchanged; the interlock holds a demo at the step that would enter the
zone (it is not scanned while it waits, so the step's blocks are not started: the machine stands
where the previous step left it) until the zone is free, and then grants it the zone until it has
left it again. Whether the zone is free is read from the physics through the cell's published
signals ``gantry_in_zone`` and ``ram_up``.
"""

from __future__ import annotations

__all__ = ["ZoneInterlock", "ZoneUser"]

from collections.abc import Callable

from plc.sequence import DemoProgram


class ZoneUser:
    """A demo that uses the shared zone from step ``enter`` until ``left()`` is true again after
    step ``leave`` began.

    Args:
        demo: the machine's demo program.
        enter: the step that goes into the zone (held until the zone is granted).
        leave: the step from which on the machine leaves the zone.
        left: reads whether the machine is out of the zone (from the physics).
    """

    def __init__(self, demo: DemoProgram, enter: str, leave: str, left: Callable[[], bool]) -> None:
        self.demo, self.enter, self.leave, self.left = demo, enter, leave, left
        self.holding = False
        """The zone is granted to this demo."""
        self.waited = 0.0
        """How long it has waited for the zone so far [s]."""

    def release_if_done(self) -> None:
        """Give the zone back once the demo is past ``leave`` and out of the zone."""
        if self.holding and (self.demo.done or self.demo.step == self.leave) and self.left():
            self.holding = False


class ZoneInterlock:
    """Scans the demos of the machines that share a zone, one of them in the zone at a time.

    Args:
        users: the demos and the steps of theirs that use the zone.
        plc_period: the PLC cycle [s] (for the waiting times).
    """

    def __init__(self, users: list[ZoneUser], plc_period: float) -> None:
        self.users = users
        self.plc_period = plc_period
        self.enabled = True
        """False: every demo is scanned as if alone (to show what the interlock prevents)."""

    def __call__(self) -> None:
        """One PLC scan of every demo the interlock lets run."""
        for user in self.users:
            if user.holding:
                user.release_if_done()
        for user in self.users:
            if self.enabled and not user.holding and user.demo.step == user.enter:
                if any(o.holding or not o.left() for o in self.users if o is not user):
                    user.waited += self.plc_period
                    continue  # held before the step that enters the zone
                user.holding = True
            user.demo()
