"""Axes powered, added to a group and the group enabled, for the tools and tests that move a
group (the circle test, the contour error)."""

from __future__ import annotations

__all__ = ["PoweredGroup"]

from collections.abc import Sequence

import mcl


class PoweredGroup:
    """``axes`` powered and grouped in a new group ``name``, which is enabled once every axis is
    powered and added; call it once per PLC scan, before the group's moves.

    Args:
        axes: the members, in member order.
        name: the group's name.
        corner_tolerance: the group's corner tolerance [mm].
    """

    def __init__(self, axes: Sequence[mcl.Axis], name: str, corner_tolerance: float) -> None:
        self.group = mcl.AxesGroup(name, corner_tolerance=corner_tolerance)
        self.power = [mcl.MC_Power(Axis=a) for a in axes]
        self.add = [mcl.MC_AddAxisToGroup(AxesGroup=self.group, Axis=a) for a in axes]
        self.enable = mcl.MC_GroupEnable(AxesGroup=self.group)

    @property
    def blocks(self) -> tuple[mcl.MC_AddAxisToGroup | mcl.MC_GroupEnable, ...]:
        """The group's blocks that may report an error."""
        return (*self.add, self.enable)

    def __call__(self) -> None:
        """One PLC scan: power, add, enable."""
        for p in self.power:
            p(Enable=True)
        ready = all(p.Status for p in self.power)
        for a in self.add:
            a(Execute=ready)
        self.enable(Execute=ready and self.add[-1].Done)
