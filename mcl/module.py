"""A GT-x75x servo module: the axes that share one GT_EStop (MotionControlLib §3.14)."""

from __future__ import annotations

__all__ = ["Module"]

from collections.abc import Iterable
from typing import ClassVar

from mcl.axis import Axis


class Module:
    """Up to six axes of one servo module.

    Args:
        axes: the module's axes; each gets ``axis.module`` set to this module.
    """

    MAX_AXES: ClassVar[int] = 6

    def __init__(self, axes: Iterable[Axis]) -> None:
        self.axes = list(axes)
        if not 1 <= len(self.axes) <= self.MAX_AXES:
            raise ValueError(f"a module has 1 to {self.MAX_AXES} axes, got {len(self.axes)}")
        for axis in self.axes:
            if axis.module is not None and axis.module is not self:
                raise ValueError(f"axis {axis.name!r} already belongs to another module")
            axis.module = self
