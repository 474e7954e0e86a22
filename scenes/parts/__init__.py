"""Machine parts that more than one machine is built of: the web line of the flying shear and the
rotary cutter, its line drive and measuring wheel as axes (:mod:`.web_line`) and the measuring
wheel with its errors as a device (:mod:`.measuring_wheel`).

These are not machines (none is registered; the parts of a cell, :class:`scenes.definition.Part`,
are machines): a machine package takes what it shares from here and never imports another
machine's package.
"""

from scenes.parts.measuring_wheel import MeasuringWheel, RollingCoupling
from scenes.parts.web_line import WHEEL_RADIUS, line_axis, wheel_axis

COMPILED_MODULES = ("measuring_wheel",)
"""The modules of this package that the compiled build covers (the wheel, run every physics
step)."""

__all__ = ["WHEEL_RADIUS", "MeasuringWheel", "RollingCoupling", "line_axis", "wheel_axis"]
