"""The measuring wheel's velocity as the viewer shows it (a drive's display: the position
difference over a window, then a first-order filter): on the scope a line at 0 while the wheel
stands still, not a block of ±25 mm/s; the raw one-cycle velocity stays a channel; the shown
velocity follows a moving wheel."""

from __future__ import annotations

from typing import cast

import numpy as np
import pytest

import mcl
from viewer.scope.units import auto_range, display_of
from viewer.sim import velocity
from viewer.sim.session import Session


def test_the_cutter_wheel_standing_still_is_a_line_at_zero_on_the_scope() -> None:
    session = Session("rotary_cutter")
    session.advance(7000)  # 14 s of PLC scans, the line at rest
    channels = session.recorder.channels
    names = [c.name for c in channels]
    _, values = session.recorder.series()
    session.close()
    shown = names.index("W velocity")  # one of the cutter's scope defaults
    trace = values[shown, -5000:]  # the last 10 s, every 2 ms
    low, high = auto_range(display_of(channels[shown]), trace)
    # a trace that jumps across its plotted range from sample to sample paints a block
    assert np.max(np.abs(np.diff(trace))) <= 0.05 * (high - low)
    assert np.max(np.abs(trace)) <= display_of(channels[shown]).min_span  # 0.1 mm/s
    raw = names.index("W raw velocity")
    assert channels[raw].unit == "mm/s"
    assert np.ptp(values[raw, -5000:]) >= 25.0  # the encoder's count per 1 ms cycle, kept


class Wheel:
    """An encoder-only axis moving at a constant velocity [mm/s] with a 0.025 mm count."""

    has_drive = False

    def __init__(self, speed: float) -> None:
        self.speed, self.actual, self.VEL = speed, 0.0, 0.0

    def at(self, time: float) -> None:
        self.actual = np.floor(self.speed * time / 0.025) * 0.025


@pytest.mark.parametrize("speed", [0.0, 12.5, -500.0])
def test_the_shown_velocity_of_a_moving_wheel_is_its_speed(speed: float) -> None:
    wheel = Wheel(speed)
    axis = cast(mcl.Axis, wheel)
    shown = velocity.ShownVelocity({"W": axis}, 0.002)
    assert shown.velocity("W", axis) == 0.0  # nothing sampled: its VEL
    settle = velocity.WINDOW + 8 * velocity.TIME_CONSTANT
    for k in range(round(settle / 0.002) + 1):
        wheel.at(k * 0.002)
        shown.sample(k * 0.002)
    # within a count per window of the speed
    assert shown.velocity("W", axis) == pytest.approx(speed, abs=0.025 / velocity.WINDOW)


def test_the_shown_velocity_follows_a_start_of_the_line_with_its_time_constant() -> None:
    wheel = Wheel(0.0)
    axis = cast(mcl.Axis, wheel)
    shown = velocity.ShownVelocity({"W": axis}, 0.002)
    start, speed = 0.5, 400.0  # the line starts at 0.5 s

    def run(until: float, at: float) -> float:
        for k in range(round(at / 0.002), round(until / 0.002) + 1):
            t = k * 0.002
            wheel.actual = np.floor(max(t - start, 0.0) * speed / 0.025) * 0.025
            shown.sample(t)
        return shown.velocity("W", axis)

    assert run(start, 0.0) == 0.0
    lagging = run(start + velocity.WINDOW + velocity.TIME_CONSTANT, start + 0.002)
    assert 0.4 * speed < lagging < 0.9 * speed  # first order: about 1 − 1/e behind the window
    settled = run(start + velocity.WINDOW + 8 * velocity.TIME_CONSTANT, start + 0.302)
    assert settled == pytest.approx(speed, abs=0.025 / velocity.WINDOW)
