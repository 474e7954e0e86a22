"""An axis channel (mcl.channel.AxisChannel) refuses settings it cannot sample with: a message
that names the axis, what is wrong and what would be right."""

from __future__ import annotations

import math
from typing import Any

import pytest

import mcl

NONE = (math.inf, -math.inf)
"""The window of a switch the axis does not have."""


def channel(**settings: Any) -> mcl.AxisChannel:
    return mcl.AxisChannel("X", 1e-6, 4000, **settings)


def test_switch_windows_are_three_intervals_or_missing() -> None:
    assert channel(windows=((0.5, math.inf), (-math.inf, -0.5), NONE)).probe_delay == 0.0
    assert channel(windows=((0.5, 0.5), NONE, NONE)).counts == 0  # one point is an interval
    for windows in (((0.5, math.inf), NONE), ((0.5, 0.4), NONE, NONE), (NONE,) * 4):
        with pytest.raises(ValueError, match=r"axis X: windows must be three \(lo, hi\)") as bad:
            channel(windows=windows)
        assert repr(windows) in str(bad.value)


def test_the_probe_delay_is_a_finite_time_not_below_zero() -> None:
    assert channel(probe_delay=0.0).probe_delay == 0.0
    assert channel(probe_delay=0.002).probe_delay == 0.002
    for delay in (-0.001, math.nan, math.inf):
        with pytest.raises(ValueError, match=f"axis X: probe_delay must be >= 0 s, got {delay}"):
            channel(probe_delay=delay)
