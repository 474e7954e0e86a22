"""How the scope lays its channels out on the plot's y direction: on shared axes (one y axis
per display unit, the channels of a unit drawn over each other on it; a track per unit when
the axes do not fit in the chart's width) or in stacked tracks
(each channel in its own band of the plot's height, all on one time axis, one y axis that
labels each band's range in the channel's unit)."""

from __future__ import annotations

__all__ = [
    "ASPECT",
    "AXIS_FONT",
    "CHART_FRAME",
    "CHAR_WIDTH",
    "DIGITAL_BAND",
    "LABEL_SIZE",
    "LAYOUTS",
    "MIN_TRACK",
    "NEUTRAL",
    "SHARED",
    "STACKED",
    "TICKS",
    "TRACK_GAP",
    "Layout",
    "aspect_of",
    "band_range",
    "layout_of",
    "nice_ticks",
    "shared_layout",
    "stacked_layout",
    "unit_groups",
    "unit_tracks",
]

import math
from collections.abc import Sequence
from dataclasses import dataclass

import viser.uplot

from viewer.scope.units import Display, format_value

SHARED = "shared axes"
"""Layout: one y axis per unit, the channels of a unit over each other."""

STACKED = "stacked tracks"
"""Layout: a band of the plot's height per channel, one time axis."""

LAYOUTS = (SHARED, STACKED)
"""The layouts the scope offers."""

DIGITAL_BAND = 0.12
"""Height of the band the digital channels share at the bottom of the shared layout, a
fraction of the plot's height (their 0/1 levels need no axis)."""

TICKS = 5
"""Ticks a shared y axis aims at."""

AXIS_FONT = "11px system-ui, sans-serif"
"""Font of the y axes' values and labels."""

CHAR_WIDTH = 7.0
"""Width of a character of :data:`AXIS_FONT` [CSS px], to size an axis to its values."""

LABEL_SIZE = 14.0
"""Room for an axis' label (its unit) [CSS px]."""

TRACK_GAP = 0.1
"""Space between stacked tracks, a fraction of a track's band."""

AXES_SHARE = 0.4
"""At most this fraction of the chart's width goes to the shared layout's y axes: when they
need more, each unit gets a track of the plot's height instead (:func:`unit_tracks`)."""

ASPECT = 1.9
"""Width / height of the chart while its tracks are high enough."""

MIN_TRACK = 48.0
"""Least height of a track of the plot [CSS px]: a trace in it reads like one on its own."""

CHART_FRAME = 80.0
"""Height of the chart beyond its plotting area [CSS px]: the time axis with its values and
label, and the padding."""

NEUTRAL = "#444444"
"""Colour of an axis several channels share."""


@dataclass(frozen=True)
class Layout:
    """Where each channel is drawn.

    Attributes:
        scales: The scale key of each channel (its series and its overlay use it).
        ranges: The range of each scale [display unit of its channels].
        axes: The y axes.
        tracks: Bands the plot's height is shared out in (1: every channel over all of it).
    """

    scales: tuple[str, ...]
    ranges: dict[str, tuple[float, float]]
    axes: tuple[viser.uplot.Axis, ...]
    tracks: int = 1


def unit_groups(displays: Sequence[Display]) -> list[list[int]]:
    """The channels (indices) of each display unit, units in the order they first appear."""
    groups: dict[str, list[int]] = {}
    for k, display in enumerate(displays):
        groups.setdefault(display.unit, []).append(k)
    return list(groups.values())


def nice_ticks(low: float, high: float, count: int = TICKS) -> tuple[float, ...]:
    """About ``count`` ticks in [low, high] on a step of 1, 2 or 5 times a power of ten."""
    if not (math.isfinite(low) and math.isfinite(high)) or high <= low:
        return ()
    rough = (high - low) / max(count, 1)
    power = 10.0 ** math.floor(math.log10(rough))
    step = next(m * power for m in (1.0, 2.0, 5.0, 10.0) if m * power >= rough)
    first = math.ceil(low / step - 1e-9)
    ticks = []
    k = first
    while k * step <= high + 1e-9 * step:
        ticks.append(k * step)
        k += 1
    return tuple(ticks)


def band_range(low: float, high: float, bottom: float, top: float) -> tuple[float, float]:
    """The scale range that draws [low, high] between heights ``bottom`` and ``top``
    (fractions of the plot's height, from below)."""
    total = (high - low) / (top - bottom)
    start = low - bottom * total
    return (start, start + total)


def _axis(
    scale: str, label: str, color: str, side: int, ticks: Sequence[float], texts: Sequence[str]
) -> viser.uplot.Axis:
    """A y axis with its ticks and their texts given, as wide as its longest text."""
    widest = max((len(t) for t in texts), default=3)
    return viser.uplot.Axis(
        scale=scale,
        label=label,
        stroke=color,
        side=3 if side == 3 else 1,
        font=AXIS_FONT,
        labelFont=AXIS_FONT,
        labelSize=LABEL_SIZE if label else 0.0,
        labelGap=0.0,
        gap=3.0,
        ticks={"size": 4.0},
        size=8.0 + CHAR_WIDTH * widest,
        splits=tuple(ticks),
        values=tuple(texts),
        grid={"show": False},
    )


def shared_layout(
    displays: Sequence[Display],
    ranges: Sequence[tuple[float, float]],
    colors: Sequence[str],
    width: float = math.inf,
) -> Layout:
    """One scale and one y axis per unit (alternately left and right, in the channel's colour
    when it is alone on it; the range holds every channel of the unit); the digital channels
    in a band at the bottom, without an axis. In a chart ``width`` [CSS px] too narrow for
    the axes in :data:`AXES_SHARE` of it, a track per unit instead (:func:`unit_tracks`)."""
    scales = [""] * len(displays)
    scale_ranges: dict[str, tuple[float, float]] = {}
    axes = []
    analog = [g for g in unit_groups(displays) if not displays[g[0]].digital]
    digital = [k for k, d in enumerate(displays) if d.digital]
    bottom = DIGITAL_BAND if digital else 0.0
    for g, members in enumerate(analog):
        key = f"u{g}"
        for k in members:
            scales[k] = key
        low = min(ranges[k][0] for k in members)
        high = max(ranges[k][1] for k in members)
        scale_ranges[key] = band_range(low, high, bottom, 1.0)
        ticks = nice_ticks(low, high)
        step = ticks[1] - ticks[0] if len(ticks) > 1 else 0.0
        texts = [format_value(t, _resolution(step)) for t in ticks]
        color = colors[members[0]] if len(members) == 1 else NEUTRAL
        side = 3 if g % 2 == 0 else 1
        axes.append(_axis(key, f"[{displays[members[0]].unit}]", color, side, ticks, texts))
    if digital:
        for k in digital:
            scales[k] = "d"
        low, high = ranges[digital[0]]
        scale_ranges["d"] = band_range(low, high, 0.0, DIGITAL_BAND - 0.02)
    if sum(float(a.get("size", 0.0)) + float(a.get("labelSize", 0.0)) for a in axes) > (
        AXES_SHARE * width
    ):
        return unit_tracks(displays, ranges, colors)
    if axes:
        axes[0]["grid"] = {"show": True}
    return Layout(tuple(scales), scale_ranges, tuple(axes))


def unit_tracks(
    displays: Sequence[Display], ranges: Sequence[tuple[float, float]], colors: Sequence[str]
) -> Layout:
    """A track of the plot's height per unit (the first unit's on top), the channels of a
    unit drawn over each other in it on the unit's range, one y axis labelling each track's
    range in its unit (:func:`stacked_layout` of the units)."""
    groups = unit_groups(displays)
    placed = stacked_layout(
        [displays[g[0]] for g in groups],
        [(min(ranges[k][0] for k in g), max(ranges[k][1] for k in g)) for g in groups],
        [colors[g[0]] if len(g) == 1 else NEUTRAL for g in groups],
    )
    scales = [""] * len(displays)
    for g, members in enumerate(groups):
        for k in members:
            scales[k] = placed.scales[g]
    return Layout(tuple(scales), placed.ranges, placed.axes, len(groups))


def _resolution(step: float) -> float:
    """The resolution that shows every tick of ``step`` exactly (1, 2, 5 times 10^n)."""
    return 10.0 ** math.floor(math.log10(step) + 1e-9) if step > 0.0 else 0.0


def stacked_layout(
    displays: Sequence[Display], ranges: Sequence[tuple[float, float]], colors: Sequence[str]
) -> Layout:
    """A scale per channel whose range puts the channel's own range in its band (the first
    channel on top), and one y axis (on the first channel's scale) with a tick at each band's
    ends, the top one labelled with the channel's value there, in its unit."""
    n = len(displays)
    scales = tuple(f"s{k}" for k in range(n))
    scale_ranges: dict[str, tuple[float, float]] = {}
    band = 1.0 / max(n, 1)
    for k, (low, high) in enumerate(ranges):
        bottom = (n - 1 - k) * band + 0.5 * TRACK_GAP * band
        scale_ranges[scales[k]] = band_range(low, high, bottom, bottom + (1 - TRACK_GAP) * band)
    ticks: list[float] = []
    texts: list[str] = []
    if n:
        first_low, first_high = scale_ranges[scales[0]]
        for k, (low, high) in enumerate(ranges):
            start, end = scale_ranges[scales[k]]
            for value, shown in ((low, ""), (high, displays[k].text(high))):
                fraction = (value - start) / (end - start)
                ticks.append(first_low + fraction * (first_high - first_low))
                texts.append(shown)
    axis = _axis(scales[0] if n else "y", "", NEUTRAL, 3, ticks, texts)
    axis["grid"] = {"show": True}
    return Layout(scales, scale_ranges, (axis,), n)


def aspect_of(tracks: int, width: float) -> float:
    """Width / height of a chart ``width`` [CSS px] wide: :data:`ASPECT`, or taller, so that
    each of its ``tracks`` is at least :data:`MIN_TRACK` high (the panel then scrolls)."""
    return min(ASPECT, width / (CHART_FRAME + max(tracks, 1) * MIN_TRACK))


def layout_of(
    kind: str,
    displays: Sequence[Display],
    ranges: Sequence[tuple[float, float]],
    colors: Sequence[str],
    width: float = math.inf,
) -> Layout:
    """The layout ``kind`` (:data:`SHARED` or :data:`STACKED`) of the channels in a chart
    ``width`` [CSS px] wide."""
    if kind == STACKED:
        return stacked_layout(displays, ranges, colors)
    return shared_layout(displays, ranges, colors, width)
