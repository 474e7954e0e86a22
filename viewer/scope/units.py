"""The scope's units: each channel shown in an engineer's unit (following error in µm, forces in
kN, pressures in bar), and a y range per channel that never zooms onto a single DAC step."""

from __future__ import annotations

__all__ = [
    "DEFAULT_MIN_SPAN",
    "DIGITAL_RANGE",
    "FOLLOWING_ERROR_UNITS",
    "UNIT_TABLE",
    "Display",
    "auto_range",
    "display_of",
    "format_value",
    "settled_range",
]

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from viewer.sim.snapshot import Channel


@dataclass(frozen=True)
class Display:
    """How the scope shows a channel.

    Attributes:
        unit: The display unit (``"µm"``, ``"V"``, ``"0/1"`` for a digital channel).
        factor: Display value per recorded value (1000 for mm shown in µm).
        min_span: The smallest y span an auto range shrinks to [display unit].
        digital: A 0/1 channel (fixed range).
        resolution: The step a value is rounded to when shown [display unit] (0: four
            significant digits).
    """

    unit: str
    factor: float
    min_span: float
    digital: bool = False
    resolution: float = 0.0

    def text(self, value: float) -> str:
        """``value`` [display unit] as shown, with its unit (:func:`format_value`)."""
        return format_value(value, self.resolution, self.unit)

    def to_display(self, value: float) -> float:
        """A recorded value in the display unit."""
        return value * self.factor

    def to_recorded(self, value: float) -> float:
        """A value in the display unit as recorded."""
        return value / self.factor


FOLLOWING_ERROR_UNITS: dict[str, tuple[str, float]] = {
    "mm": ("µm", 1e3),
    "m": ("µm", 1e6),
    "deg": ("mdeg", 1e3),
}
"""The following error of an axis of a unit (key) in a finer unit: (unit, factor)."""

UNIT_TABLE: dict[str, tuple[str, float, float, float]] = {
    "µm": ("µm", 1.0, 10.0, 0.1),
    "mm": ("mm", 1.0, 0.05, 0.001),
    "m": ("m", 1.0, 5e-5, 1e-6),
    "deg": ("deg", 1.0, 0.1, 0.001),
    "mdeg": ("mdeg", 1.0, 10.0, 1.0),
    "mm/s": ("mm/s", 1.0, 0.1, 0.01),
    "m/s": ("m/s", 1.0, 1e-4, 1e-5),
    "deg/s": ("deg/s", 1.0, 0.1, 0.01),
    "m/min": ("m/min", 1.0, 0.01, 0.001),
    "V": ("V", 1.0, 0.1, 0.001),
    "mV": ("V", 1e-3, 0.1, 0.001),
    "bar": ("bar", 1.0, 0.05, 0.01),
    "Pa": ("bar", 1e-5, 0.05, 0.01),
    "MPa": ("bar", 10.0, 0.05, 0.01),
    "N": ("kN", 1e-3, 0.01, 0.001),
    "kN": ("kN", 1.0, 0.01, 0.001),
    "-": ("-", 1.0, 0.01, 0.0),
}
"""A recorded unit (key) as shown: (display unit, factor, smallest auto span, resolution)."""

DEFAULT_MIN_SPAN = 1e-6
"""Smallest auto span of a unit the table does not know [its unit]."""

DIGITAL_RANGE = (-0.1, 1.1)
"""The y range of a digital channel."""


def display_of(channel: Channel) -> Display:
    """How the scope shows ``channel``: following errors in µm (mm and m axes), forces in kN,
    pressures in bar, voltages in V, digital channels as 0/1."""
    if channel.digital:
        return Display("0/1", 1.0, 1.0, digital=True, resolution=1.0)
    unit, factor = channel.unit, 1.0
    if channel.name.endswith(" following error") and unit in FOLLOWING_ERROR_UNITS:
        unit, factor = FOLLOWING_ERROR_UNITS[unit]
    shown, scale, span, step = UNIT_TABLE.get(unit, (unit, 1.0, DEFAULT_MIN_SPAN, 0.0))
    return Display(shown, factor * scale, span, resolution=step)


def format_value(value: float, resolution: float, unit: str = "") -> str:
    """``value`` rounded to ``resolution`` (0: four significant digits) with ``unit``: as many
    decimals as the resolution has, a plain ``0`` for anything that rounds to zero, a minus
    sign (−) for negatives, ``—`` for no value."""
    if not math.isfinite(value):
        return "—"
    if resolution > 0.0:
        decimals = max(0, -math.floor(math.log10(resolution) + 1e-9))
        steps = round(value / resolution)
        text = "0" if steps == 0 else f"{steps * resolution:.{decimals}f}"
    else:
        text = "0" if abs(value) < 1e-12 else f"{value:.4g}"
    if text.startswith("-"):
        text = "−" + text[1:]
    return f"{text} {unit}" if unit and unit not in ("-", "0/1") else text


def auto_range(
    display: Display, values: npt.NDArray[np.float64], margin: float = 0.05
) -> tuple[float, float]:
    """A y range [display unit] holding ``values`` (display unit, NaN ignored) with a margin
    (a fraction of the span), at least ``display.min_span`` wide."""
    if display.digital:
        return DIGITAL_RANGE
    finite = values[np.isfinite(values)]
    if not finite.size:
        return (-0.5 * display.min_span, 0.5 * display.min_span)
    low, high = float(finite.min()), float(finite.max())
    span = max(high - low, display.min_span / (1.0 + 2.0 * margin))
    middle = 0.5 * (low + high)
    half = 0.5 * span * (1.0 + 2.0 * margin)
    return (_nice(middle - half, math.floor), _nice(middle + half, math.ceil))


def _nice(value: float, rounding: Callable[[float], int]) -> float:
    """``value`` rounded to 4 significant digits in the direction of ``rounding`` (floor or
    ceil), so a range does not change with every new sample."""
    if value == 0.0 or not math.isfinite(value):
        return value
    step = 10.0 ** (math.floor(math.log10(abs(value))) - 3)
    return float(rounding(value / step)) * step


def settled_range(
    previous: tuple[float, float] | None, wanted: tuple[float, float], fill: float = 0.25
) -> tuple[float, float]:
    """``previous`` while ``wanted`` fits in it and spans at least ``fill`` of it, else
    ``wanted``: an auto range that does not change (and redraw the plot) with every sample."""
    if previous is None:
        return wanted
    low, high = previous
    if low <= wanted[0] and wanted[1] <= high and wanted[1] - wanted[0] >= fill * (high - low):
        return previous
    return wanted
