"""The delta picker's demo choosing where a part goes, without running the physics: the free
tray place nearest to where the part was picked (a place is free again 1.5 s after a part was
put there; the one filled longest ago when none is), the carry entering it straight from in
front, and the robot heading from the tray to where the next latched part will be."""

from __future__ import annotations

import pytest

import mcl
import scenes
from scenes.machines.delta_picker import SLOTS
from scenes.machines.delta_picker.axes import EYE_X
from scenes.machines.delta_picker.demo import CLEAR, CLEARED, GRIP_Z, OFF_BELT, WAIT, Demo
from scenes.machines.delta_picker.devices import PART_LENGTH

B = mcl.MC_BufferMode
Z = GRIP_Z + CLEAR
"""The carry's height [mm]."""


@pytest.fixture
def demo() -> Demo:
    """The demo on a freshly loaded picker (the belt stands; the time is 0)."""
    return Demo(scenes.load("delta_picker", trace_every=0))


@pytest.mark.parametrize(
    ("x", "place"),
    [(-500.0, 0), (-300.0, 0), (-200.0, 1), (-40.0, 3), (40.0, 4), (100.0, 5), (400.0, 7)],
)
def test_an_empty_tray_takes_a_part_at_the_place_nearest_to_where_it_was_picked(
    demo: Demo, x: float, place: int
) -> None:
    assert demo._free_slot(x) == place


def test_a_place_is_free_again_once_a_part_was_put_there_1_5_s_ago(demo: Demo) -> None:
    now = demo.scene.time
    demo.placed_at[0] = now - 0.2
    demo.placed_at[1] = now - CLEARED + 0.01
    assert demo._free_slot(-315.0) == 2  # the nearest places are still taken: the next one
    demo.placed_at[1] = now - CLEARED
    assert demo._free_slot(-315.0) == 1
    demo.placed_at[0] = now - 5.0
    assert demo._free_slot(-315.0) == 0


def test_with_every_place_taken_the_part_goes_to_the_one_filled_longest_ago(demo: Demo) -> None:
    now = demo.scene.time
    demo.placed_at[:] = [now - 0.1 * (1 + (k + 3) % len(SLOTS)) for k in range(len(SLOTS))]
    assert max(now - t for t in demo.placed_at) < CLEARED
    for x in (-315.0, 0.0, 315.0):
        assert demo._free_slot(x) == 4


def carry(demo: Demo) -> list[tuple[list[float], object]]:
    """The carry's moves: target [mm, MCS] and buffer mode."""
    return [(list(m.Position), m.BufferMode) for m in demo.moves["carry to the tray"]]


def test_a_carried_part_clears_the_belt_and_enters_its_place_straight_from_in_front(
    demo: Demo,
) -> None:
    """Lifted at x = -200 mm over the belt, the part goes to place 1 (x -225 mm, y 155 mm):
    across off the belt's parts, to 80 mm in front of the place, straight in (along y, x the
    place's), down onto it (each blended into the one before); then straight up."""
    demo.carry_from([-200.0, -150.0, Z - 2.0])
    assert demo.slot == 1
    assert carry(demo) == [
        ([-200.0, OFF_BELT, Z], B.Aborting),
        ([-225.0, 75.0, Z], B.BlendingLow),
        ([-225.0, 155.0, Z], B.BlendingLow),
        ([-225.0, 155.0, GRIP_Z], B.BlendingLow),
    ]
    up = demo.moves["up from the tray"][0]
    assert (list(up.Position), up.BufferMode) == ([-225.0, 155.0, Z], B.Aborting)


def test_a_part_lifted_beyond_the_belt_is_not_carried_back_over_it(demo: Demo) -> None:
    """Lifted 20 mm beyond :data:`OFF_BELT` (x 60 mm), with place 4 taken: the first leg
    keeps its y; the part goes to place 5, the nearest free."""
    demo.placed_at[4] = demo.scene.time
    demo.carry_from([60.0, OFF_BELT + 20.0, Z])
    assert demo.slot == 5
    assert carry(demo)[0][0] == [60.0, OFF_BELT + 20.0, Z]
    assert carry(demo)[1][0] == [135.0, 75.0, Z]


def test_a_part_latched_at_the_eye_has_its_centre_half_a_part_before_it(demo: Demo) -> None:
    """The latch is the belt's position when the part's leading edge cut the beam; the belt
    runs at :data:`BELT_SPEED` (the run's velocity)."""
    now = demo.belt.sp_pos
    half = 500.0 * PART_LENGTH
    assert demo._part_x(now) == pytest.approx(EYE_X - half)
    assert demo._part_x(now - 100.0) == pytest.approx(EYE_X - half + 100.0)
    assert demo._part_x(now - 100.0, 0.2) == pytest.approx(EYE_X - half + 150.0)


@pytest.mark.parametrize(("travel", "x"), [(200.0, -180.0), (0.0, -250.0), (800.0, 250.0)], ids=str)
def test_from_the_tray_the_robot_heads_for_where_the_next_part_will_be(
    demo: Demo, travel: float, x: float
) -> None:
    """The next latched part has travelled ``travel`` [mm] since its latch: its centre will
    be at EYE_X - 30 + travel + 50 mm (0.2 s at 250 mm/s) as the robot gets there, ``x``
    within the tracking range ±250 mm; the robot comes 25 mm above it at its lateral position.
    The place just filled is taken for 1.5 s."""
    demo.slot = 2
    demo.queue[:] = [(demo.belt.sp_pos - travel, -140.0), (demo.belt.sp_pos, -160.0)]
    assert demo._released() == "up from the tray"
    over = demo.moves["up from the tray"][1]
    assert list(over.Position) == pytest.approx([x, -140.0, Z])
    assert len(demo.queue) == 2
    assert demo.placed_at[2] == demo.scene.time
    assert demo._free_slot(SLOTS[2][0]) == 1


def test_from_the_tray_with_no_part_latched_the_robot_waits_past_the_eye(demo: Demo) -> None:
    demo.queue.clear()
    assert demo._released() == "up from the tray"
    assert list(demo.moves["up from the tray"][1].Position) == list(WAIT)
