"""MC_GroupSetOverride's AccFactor and JerkFactor on simulated axes, scan by scan: the path's
acceleration stays within AccFactor and its jerk within JerkFactor times the planned ones (the
path clock runs at min(VelFactor, √AccFactor, ∛JerkFactor)), a change is ramped, a move still
ends at its end point, and factors out of range are refused with the group's factors kept."""

from __future__ import annotations

import itertools
import math
from dataclasses import replace

import pytest

import mcl
from mcl import ErrorID
from tests.helpers import make_machine
from tests.mcl.test_group import Recorder, build_group, record
from tests.mcl.test_group_control import DT, JERK, scans

V, ACC = 100.0, 2000.0
LINE = dict(Position=[30.0, 40.0], Velocity=V, Acceleration=ACC, Deceleration=ACC, Jerk=JERK)
"""A line of 50 mm from (0, 0)."""


@pytest.fixture
def xy() -> tuple[mcl.SimMachine, mcl.AxesGroup]:
    """Two powered, referenced axes X, Y at 0 mm in an enabled group."""
    machine = make_machine("XY")
    return machine, build_group(machine, "XY")


def path_figures(rec: Recorder, start: int = 0) -> tuple[float, float, float]:
    """The model's largest path speed [mm/s], |acceleration| [mm/s²] and |jerk| [mm/s³] from
    one servo cycle to the next, from sample ``start`` on (a line: the speed's derivatives)."""
    speeds = rec.speeds()[start:]
    acc = [(b - a) / DT for a, b in itertools.pairwise(speeds)]
    jerk = [(b - a) / DT for a, b in itertools.pairwise(acc)]
    return max(speeds), max(map(abs, acc)), max(map(abs, jerk))


def run_line(machine: mcl.SimMachine, group: mcl.AxesGroup, **factors: float) -> Recorder:
    """The line from rest with the override's ``factors`` set before it, to its Done."""
    override = mcl.MC_GroupSetOverride(AxesGroup=group, Enable=True, **factors)
    override()
    assert override.Enabled and not override.Error
    line = mcl.MC_MoveLinearAbsolute(AxesGroup=group, **LINE)
    rec = record(machine, "XY")

    def program() -> None:
        line(Execute=True)
        override()

    machine.run(program, until=lambda: line.Done, timeout=5.0)
    assert [a.sp_pos for a in group.axes] == pytest.approx([30.0, 40.0], abs=1e-9)
    return rec


def test_acc_factor_limits_the_path_acceleration(xy: tuple[mcl.SimMachine, mcl.AxesGroup]) -> None:
    """AccFactor 0.25: the path accelerates at a quarter of the line's Acceleration (and, with
    time scaling, runs at √0.25 = half its Velocity); it ends at its end point."""
    speed, acc, jerk = path_figures(run_line(*xy, AccFactor=0.25))
    assert speed == pytest.approx(0.5 * V)
    assert 0.9 * 0.25 * ACC < acc <= 0.25 * ACC * 1.0001
    assert jerk <= 0.125 * JERK * 1.0001


def test_jerk_factor_limits_the_path_jerk(xy: tuple[mcl.SimMachine, mcl.AxesGroup]) -> None:
    """JerkFactor 0.125: the path's jerk stays within an eighth of the line's Jerk (the path
    runs at ∛0.125 = half its Velocity, its acceleration within a quarter)."""
    speed, acc, jerk = path_figures(run_line(*xy, JerkFactor=0.125))
    assert speed == pytest.approx(0.5 * V)
    assert acc <= 0.25 * ACC * 1.0001
    assert 0.9 * 0.125 * JERK < jerk <= 0.125 * JERK * 1.0001


def test_vel_factor_above_one_needs_the_acceleration_and_jerk_factors(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    """VelFactor 1.5 with AccFactor and JerkFactor 1 keeps the line at its Velocity (1.5 would
    take 2.25 times its acceleration); with AccFactor 2.25 and JerkFactor 3.375 it runs at
    1.5 times it."""
    machine, group = xy
    speed, acc, _ = path_figures(run_line(machine, group, VelFactor=1.5))
    assert speed == pytest.approx(V) and acc <= ACC * 1.0001
    line = mcl.MC_MoveLinearAbsolute(AxesGroup=group, **{**LINE, "Position": [0.0, 0.0]})
    machine.run(lambda: line(Execute=True), until=lambda: line.Done, timeout=5.0)
    speed, acc, _ = path_figures(run_line(machine, group, VelFactor=1.5, AccFactor=2.25,
                                          JerkFactor=3.375))  # fmt: skip
    assert speed == pytest.approx(1.5 * V)
    assert acc == pytest.approx(2.25 * ACC, rel=0.05)


def test_a_lower_acc_factor_in_motion_is_ramped(xy: tuple[mcl.SimMachine, mcl.AxesGroup]) -> None:
    """At full speed on a long line AccFactor drops to 0.25: the path velocity ramps down to
    half within the members' default deceleration × 0.25, never steps, and the line ends at its
    end point; the block is Enabled and Busy while the group follows it."""
    machine, group = xy
    override = mcl.MC_GroupSetOverride(AxesGroup=group, Enable=True)
    line = mcl.MC_MoveLinearAbsolute(AxesGroup=group, **{**LINE, "Position": [120.0, 160.0]})
    rec = record(machine, "XY")

    def program() -> None:
        line(Execute=True)
        override()

    scans(machine, program, 0.3)
    assert rec.speeds()[-1] == pytest.approx(V)
    override.AccFactor = 0.25
    start = len(rec.t)
    scans(machine, program, 0.6)
    assert override.Enabled and override.Busy and not override.Error
    assert rec.speeds()[-1] == pytest.approx(0.5 * V)
    _, acc, _ = path_figures(rec, start - 1)
    decel = group.axes[0].config.deceleration
    assert 0.9 * 0.25 * decel < acc <= 0.25 * decel * 1.0001
    machine.run(program, until=lambda: line.Done, timeout=10.0)
    assert [a.sp_pos for a in group.axes] == pytest.approx([120.0, 160.0], abs=1e-9)


def test_a_lower_jerk_factor_in_motion_ramps_with_its_jerk(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    """At full speed JerkFactor drops to 0.125: the path velocity ramps down to half, its jerk
    within the members' default jerk × 0.125 (× 1.5 in the cycle the ramp lands, see
    mcl.path_clock)."""
    machine, group = xy
    for axis in group.axes:
        axis.config = replace(axis.config, jerk=JERK)  # the default ramp's (none by default)
    override = mcl.MC_GroupSetOverride(AxesGroup=group, Enable=True)
    line = mcl.MC_MoveLinearAbsolute(AxesGroup=group, **{**LINE, "Position": [120.0, 160.0]})
    rec = record(machine, "XY")

    def program() -> None:
        line(Execute=True)
        override()

    scans(machine, program, 0.3)
    override.JerkFactor = 0.125
    start = len(rec.t)
    scans(machine, program, 0.6)
    assert rec.speeds()[-1] == pytest.approx(0.5 * V)
    _, _, jerk = path_figures(rec, start - 1)
    assert 0.125 * JERK * 0.9 < jerk <= 1.5 * 0.125 * JERK * 1.0001


def test_the_factors_start_at_one_and_take_their_largest_values(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup],
) -> None:
    """A group's override factors are 1.0 until a block sets them; AccFactor 4.0 and
    JerkFactor 8.0, the largest, are taken."""
    _, group = xy
    clock = group.clock
    assert (clock.override, clock.acc_factor, clock.jerk_factor) == (1.0, 1.0, 1.0)
    full = mcl.MC_GroupSetOverride(AxesGroup=group, Enable=True, AccFactor=4.0, JerkFactor=8.0)
    full()
    assert full.Enabled and not full.Error
    assert (clock.acc_factor, clock.jerk_factor) == (4.0, 8.0)


@pytest.mark.parametrize(
    "inputs",
    [
        {"AccFactor": 0.0},
        {"JerkFactor": 0.0},
        {"AccFactor": 4.5},
        {"JerkFactor": 8.5},
        {"AccFactor": -0.5},
        {"AccFactor": math.nan},
        {"JerkFactor": math.inf},
    ],
)
def test_factors_out_of_range_are_refused_and_the_group_keeps_its_own(
    xy: tuple[mcl.SimMachine, mcl.AxesGroup], inputs: dict[str, float]
) -> None:
    """PLCopen: AccFactor and JerkFactor 0 are not allowed; above 4.0 and 8.0 (the acceleration
    and jerk of VelFactor 2.0) neither: EParam, and the group keeps the factors it had."""
    _, group = xy
    good = mcl.MC_GroupSetOverride(AxesGroup=group, Enable=True, AccFactor=0.5, JerkFactor=0.8)
    good()
    bad = mcl.MC_GroupSetOverride(AxesGroup=group, Enable=True, **inputs)
    bad()
    assert bad.Error and bad.ErrorID == ErrorID.EParam and not (bad.Enabled or bad.Busy)
    clock = group.clock
    assert (clock.override, clock.acc_factor, clock.jerk_factor) == (1.0, 0.5, 0.8)
    assert clock.scale == pytest.approx(math.sqrt(0.5))
