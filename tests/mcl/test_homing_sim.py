"""The homing step blocks on a pure-Python simulated axis, judged by where it ends up.

Every block on its own: MC_StepAbsSwitch (REF), MC_StepLimitSwitch, MC_StepBlock (an obstacle),
MC_StepRefPulse (index pulse), MC_StepDirect and MC_FinishHoming: Done, the axis state and
``Ref``, where the axis stands physically and which coordinate that point gets; the
MC_SwitchPositive/Negative direction rules, the REF search turned round by a limit switch, the
TimeLimit/DistanceLimit/TorqueLimit errors, and parameter errors that leave the axis alone.

Layout of the simulated axis (physical positions [m]): hard stops at 0.09 and 0.51, LIM− at or
below 0.10, LIM+ at or above 0.50, REF between 0.2035 and 0.2537, an index pulse every 10 mm
(at multiples of 0.01), start at 0.3023 (encoder 0 there).
"""

from __future__ import annotations

import math
from typing import Any

import pytest

import mcl
from mcl import AxisState, ErrorID, MC_BufferMode, MC_Direction, MC_SwitchMode
from tests.helpers import make_machine

LAYOUT: dict[str, float] = dict(
    start=0.3023,
    stop_neg=0.09,
    stop_pos=0.51,
    lim_neg=0.10,
    lim_pos=0.50,
    ref_low=0.2035,
    ref_high=0.2537,
    lead=0.01,
)
COUNT = 0.001
"""One encoder count [mm]."""
V = 20.0
"""Search velocity [mm/s]."""
SERVO = mcl.AxisConfig().servo_period
CAPTURE = V * SERVO + mcl.AxisConfig().in_position
"""How far from a switch edge a search that returns to its captured position may stand [mm]:
the switch is sampled once per servo cycle, and the axis settles within its in-position window."""
ACCELERATION = mcl.AxisConfig().acceleration
"""The default acceleration a search speeds up with [mm/s²]."""
SEARCHES = [mcl.MC_StepAbsSwitch, mcl.MC_StepLimitSwitch, mcl.MC_StepBlock, mcl.MC_StepRefPulse]
POSITIVE, NEGATIVE = MC_Direction.MC_Positive, MC_Direction.MC_Negative


def homing_axis(referenced: bool = False, **params: float) -> tuple[mcl.SimMachine, mcl.Axis]:
    """The powered axis X in StandStill, referenced or not (``params`` change the layout)."""
    layout: dict[str, Any] = {**LAYOUT, **params}
    machine = make_machine({"X": mcl.SimAxisParams(**layout)}, referenced=referenced)
    X = machine.axes["X"]
    assert X.state == AxisState.StandStill and X.Ref == referenced
    return machine, X


def x_of(machine: mcl.SimMachine) -> float:
    """Physical position of the simulated axis [m]."""
    return machine.sims["X"].x


def coordinate_of(machine: mcl.SimMachine, x: float) -> float:
    """The axis coordinate [mm] of the physical position ``x`` [m] (the axis at rest)."""
    return machine.axes["X"].actual + (x - x_of(machine)) * 1000.0


class Track:
    """Observer: the range of physical positions, the states seen and the first direction of
    motion (+1/−1)."""

    def __init__(self, machine: mcl.SimMachine) -> None:
        self.machine = machine
        self.x0 = self.lo = self.hi = x_of(machine)
        self.states: set[AxisState] = set()
        self.direction = 0
        machine.runtime.observers.append(self)

    def __call__(self, t: float) -> None:
        x = x_of(self.machine)
        self.lo, self.hi = min(self.lo, x), max(self.hi, x)
        self.states.add(self.machine.axes["X"].state)
        if not self.direction and abs(x - self.x0) > 0.0005:
            self.direction = 1 if x > self.x0 else -1


def execute(
    machine: mcl.SimMachine, *blocks: tuple[Any, dict[str, Any]], timeout: float = 30.0
) -> None:
    """Call the blocks with Execute=TRUE every scan until the last one is Done or any reports
    Error, then 0.3 s more (the axis settles)."""

    def program() -> None:
        for fb, inputs in blocks:
            fb(Axis=machine.axes["X"], Execute=True, **inputs)

    def ended() -> bool:
        return blocks[-1][0].Done or any(fb.Error for fb, _ in blocks)

    machine.run(program, until=ended, timeout=timeout)
    machine.run(program, timeout=0.3)


def search(fb_type: type[Any], **inputs: Any) -> tuple[Any, dict[str, Any]]:
    """A searching block with the search velocity ``V`` unless told otherwise."""
    return fb_type(), {"Velocity": V, **inputs}


# ---------------------------------------------------------------------- MC_StepAbsSwitch
def test_abs_switch_returns_to_the_ref_edge_and_stays_homing() -> None:
    """Searching negative for the rising edge of REF: Done, the axis stands at the REF edge,
    Homing; the search took the axis' Ref (its coordinate is no longer valid) and a normal
    move is refused (Ehome 9) until homing is finished."""
    machine, X = homing_axis(referenced=True)
    track = Track(machine)
    approach = search(mcl.MC_StepAbsSwitch, Direction=NEGATIVE, SwitchMode=MC_SwitchMode.MC_EdgeOn)
    execute(machine, approach)
    fb = approach[0]
    assert fb.Done and not fb.Error
    assert X.state == AxisState.Homing and not X.Ref and X.AxErrorID == 0
    assert abs(x_of(machine) - LAYOUT["ref_high"]) * 1000.0 <= CAPTURE
    assert track.lo < LAYOUT["ref_high"], "it went past the edge before coming back"
    move = mcl.MC_MoveRelative()
    move(Axis=X, Execute=True, Distance=10.0, Velocity=V)
    assert move.Error and move.ErrorID == ErrorID.Ehome


@pytest.mark.parametrize("mode", [MC_SwitchMode.MC_EdgeOn, MC_SwitchMode.MC_EdgeOff])
def test_abs_switch_edge_modes_end_on_either_side_of_the_edge(mode: MC_SwitchMode) -> None:
    """Searching positive from below REF, both modes end at the lower REF edge: EdgeOn where
    REF comes on (the axis stands on REF), EdgeOff where REF goes off, after turning round
    on REF (the axis stands just off REF)."""
    machine, X = homing_axis(start=0.15)
    track = Track(machine)
    fb, inputs = search(mcl.MC_StepAbsSwitch, Direction=POSITIVE, SwitchMode=mode)
    execute(machine, (fb, inputs))
    assert fb.Done and X.state == AxisState.Homing
    assert abs(x_of(machine) - LAYOUT["ref_low"]) * 1000.0 <= CAPTURE
    assert X.io.ref == (mode == MC_SwitchMode.MC_EdgeOn)
    assert track.hi < LAYOUT["ref_high"], "it did not search the upper edge"


@pytest.mark.parametrize(
    ("start", "direction", "expected"),
    [
        (0.3023, MC_Direction.MC_SwitchPositive, +1),  # REF off: positive
        (0.2300, MC_Direction.MC_SwitchPositive, -1),  # REF on: negative
        (0.3023, MC_Direction.MC_SwitchNegative, -1),
        (0.2300, MC_Direction.MC_SwitchNegative, +1),
    ],
)
def test_switch_directions_depend_on_the_ref_level(
    start: float, direction: MC_Direction, expected: int
) -> None:
    """MC_SwitchPositive starts positive while REF is off and negative while it is on;
    MC_SwitchNegative the other way round (the axis moves off in that direction)."""
    machine, X = homing_axis(start=start, lim_pos=0.9, stop_pos=0.91)
    track = Track(machine)
    fb, inputs = search(
        mcl.MC_StepAbsSwitch, Direction=direction, SwitchMode=MC_SwitchMode.MC_EdgeOn
    )
    machine.run(lambda: fb(Axis=X, Execute=True, **inputs), timeout=0.1)
    assert fb.Busy and not fb.Error
    assert track.direction == expected


@pytest.mark.parametrize("velocity", [20.0, 200.0])
def test_ref_search_the_wrong_way_turns_round_at_the_limit_switch(velocity: float) -> None:
    """Started above REF searching positive: LIM+ turns the search round before the hard stop,
    without an axis error, and it ends at the REF edge."""
    machine, X = homing_axis(start=0.45)
    track = Track(machine)
    fb, inputs = search(
        mcl.MC_StepAbsSwitch,
        Direction=POSITIVE,
        SwitchMode=MC_SwitchMode.MC_EdgeOn,
        Velocity=velocity,
    )
    execute(machine, (fb, inputs))
    assert fb.Done, (fb.ErrorID, X.AxErrorID)
    assert track.hi >= LAYOUT["lim_pos"], "the search met LIM+"
    assert track.hi < LAYOUT["stop_pos"], "and turned before the hard stop"
    assert AxisState.ErrorStop not in track.states and X.AxErrorID == 0
    assert abs(x_of(machine) - LAYOUT["ref_high"]) * 1000.0 <= velocity * SERVO + 0.005


def test_ref_search_between_both_limit_switches_without_ref_ends_in_errlin() -> None:
    """No REF between the limit switches: LIM+ turns the search round, LIM− ends it with the
    limit-switch error (ERRLIN 2005), the axis in ErrorStop between the switches."""
    machine, X = homing_axis(ref_low=2.0, ref_high=2.1)
    track = Track(machine)
    fb, inputs = search(mcl.MC_StepAbsSwitch, Direction=POSITIVE, Velocity=100.0)
    execute(machine, (fb, inputs), timeout=60.0)
    assert fb.Error and fb.ErrorID == ErrorID.ERRLIN == X.AxErrorID
    assert X.state == AxisState.ErrorStop and not X.Ref
    assert track.hi >= LAYOUT["lim_pos"] and track.lo <= LAYOUT["lim_neg"]
    assert LAYOUT["stop_neg"] < track.lo and track.hi < LAYOUT["stop_pos"]


@pytest.mark.parametrize(
    ("mode", "start", "direction", "edge"),
    [
        (MC_SwitchMode.MC_EdgeSwitchPositive, 0.15, POSITIVE, "ref_low"),
        (MC_SwitchMode.MC_EdgeSwitchPositive, 0.3023, NEGATIVE, "ref_low"),
        (MC_SwitchMode.MC_EdgeSwitchNegative, 0.15, POSITIVE, "ref_high"),
        (MC_SwitchMode.MC_EdgeSwitchNegative, 0.3023, NEGATIVE, "ref_high"),
    ],
)
def test_edge_switch_modes_pick_the_ref_edge_whatever_the_search_direction(
    mode: MC_SwitchMode, start: float, direction: MC_Direction, edge: str
) -> None:
    """MC_EdgeSwitchPositive ends at the REF edge where REF comes on in the positive direction
    (its lower edge), MC_EdgeSwitchNegative at the one where it comes on in the negative
    direction (its upper edge), whether the search runs positive from below REF or negative
    from above it; MC_StepDirect then gives that physical edge the coordinate."""
    machine, X = homing_axis(start=start)
    fb, inputs = search(mcl.MC_StepAbsSwitch, Direction=direction, SwitchMode=mode)
    direct = (mcl.MC_StepDirect(), {"SetPosition": 0.0, "BufferMode": MC_BufferMode.Buffered})
    execute(machine, (fb, inputs), direct)
    assert fb.Done and not fb.Error, (fb.ErrorID, X.AxErrorID)
    assert abs(x_of(machine) - LAYOUT[edge]) * 1000.0 <= CAPTURE
    assert abs(coordinate_of(machine, LAYOUT[edge])) <= CAPTURE


# ---------------------------------------------------------------------- MC_StepLimitSwitch
@pytest.mark.parametrize(("direction", "switch"), [(NEGATIVE, "lim_neg"), (POSITIVE, "lim_pos")])
def test_limit_switch_search_ends_on_the_switch_edge(direction: MC_Direction, switch: str) -> None:
    """The limit switch in the search direction: Done at its edge, Homing, no axis error
    (standing on the switch is no error while homing); MC_StepDirect then sets the
    coordinate there and the axis can move off the switch."""
    machine, X = homing_axis()
    fb, inputs = search(
        mcl.MC_StepLimitSwitch, Direction=direction, SwitchMode=MC_SwitchMode.MC_EdgeOn
    )
    execute(machine, (fb, inputs))
    assert fb.Done, (fb.ErrorID, X.AxErrorID)
    assert X.state == AxisState.Homing and not X.Ref and X.AxErrorID == 0
    assert abs(x_of(machine) - LAYOUT[switch]) * 1000.0 <= CAPTURE

    direct = mcl.MC_StepDirect()
    execute(machine, (direct, {"SetPosition": -5.0}))
    assert direct.Done and X.state == AxisState.StandStill and X.Ref
    assert coordinate_of(machine, LAYOUT[switch]) == pytest.approx(-5.0, abs=CAPTURE)
    move = mcl.MC_MoveRelative()
    away = 20.0 if direction == NEGATIVE else -20.0
    execute(machine, (move, {"Distance": away, "Velocity": V}))
    assert move.Done and X.AxErrorID == 0


# ---------------------------------------------------------------------- MC_StepBlock
@pytest.mark.parametrize("start", [0.30, 0.3377])
def test_block_search_stops_at_the_obstacle_and_stops_pushing(start: float) -> None:
    """Driving positive against an obstacle: Done just clear of it (backed off by the
    in-position window), Homing, the drive no longer pushes (the following error is gone); a
    buffered MC_StepDirect gives that point the coordinate 0, so the obstacle lies at the
    in-position window within one count, from any start."""
    machine, X = homing_axis(start=start)
    obstacle = 0.3456
    window = X.config.in_position
    machine.sims["X"].blocked_at = obstacle
    track = Track(machine)
    block = search(mcl.MC_StepBlock, Direction=POSITIVE, TorqueLimit=0.5)
    direct = (mcl.MC_StepDirect(), {"SetPosition": 0.0, "BufferMode": MC_BufferMode.Buffered})
    execute(machine, block)
    assert block[0].Done, (block[0].ErrorID, X.AxErrorID)
    assert X.state == AxisState.Homing and X.AxErrorID == 0
    assert 0.0 < (obstacle - x_of(machine)) * 1000.0 <= 2 * window + COUNT, "clear of it"
    assert track.hi <= obstacle
    assert abs(X.following_error) <= window, "still pushing against the obstacle"
    execute(machine, block, direct)
    assert direct[0].Done and X.state == AxisState.StandStill and X.Ref
    assert coordinate_of(machine, obstacle) == pytest.approx(window, abs=COUNT + 1e-9)


# ---------------------------------------------------------------------- MC_StepRefPulse
@pytest.mark.parametrize(("direction", "index"), [(POSITIVE, 0.31), (NEGATIVE, 0.30)])
def test_ref_pulse_sets_the_coordinate_at_the_index_edge(
    direction: MC_Direction, index: float
) -> None:
    """The next index pulse in the search direction gets SetPosition (within one count); the
    axis stops beyond it without coming back; Done, Ref, StandStill."""
    machine, X = homing_axis()
    fb, inputs = search(mcl.MC_StepRefPulse, Direction=direction, SetPosition=123.4)
    execute(machine, (fb, inputs))
    assert fb.Done, (fb.ErrorID, X.AxErrorID)
    assert X.state == AxisState.StandStill and X.Ref and X.AxErrorID == 0
    assert abs(coordinate_of(machine, index) - 123.4) <= COUNT + 1e-9
    beyond = (x_of(machine) - index) * (1 if direction == POSITIVE else -1)
    assert 0.0 < beyond < 0.001, "stopped just beyond the index, on the maximum ramp"


@pytest.mark.parametrize("start", [0.2300, 0.3023])
def test_ref_switch_then_index_gives_the_same_origin_from_any_start(start: float) -> None:
    """MC_StepAbsSwitch (MC_SwitchNegative, falling edge) then a buffered MC_StepRefPulse: on
    REF or above it, the first index above the REF edge gets the coordinate 0."""
    machine, X = homing_axis(start=start)
    approach = search(
        mcl.MC_StepAbsSwitch,
        Direction=MC_Direction.MC_SwitchNegative,
        SwitchMode=MC_SwitchMode.MC_EdgeOff,
    )
    pulse = search(
        mcl.MC_StepRefPulse,
        Direction=POSITIVE,
        SetPosition=0.0,
        BufferMode=MC_BufferMode.Buffered,
    )
    execute(machine, approach, pulse)
    assert approach[0].Done and not approach[0].Error
    assert pulse[0].Done and X.state == AxisState.StandStill and X.Ref
    first_index = math.ceil(LAYOUT["ref_high"] / LAYOUT["lead"]) * LAYOUT["lead"]
    assert abs(coordinate_of(machine, first_index)) <= COUNT + 1e-9


def _first_offset_by_step_direct(machine: mcl.SimMachine) -> None:
    execute(machine, (mcl.MC_StepDirect(), {"SetPosition": 500.0}))


def _first_offset_by_ref_pulse(machine: mcl.SimMachine) -> None:
    execute(machine, search(mcl.MC_StepRefPulse, Direction=NEGATIVE, SetPosition=-77.7))


@pytest.mark.parametrize("first", [_first_offset_by_step_direct, _first_offset_by_ref_pulse])
def test_ref_pulse_on_an_axis_with_a_shifted_coordinate_sets_it_at_the_index(
    first: Any,
) -> None:
    """Homing again: after MC_StepDirect or a first MC_StepRefPulse moved the coordinate away
    from the counter, a second MC_StepRefPulse still gives the physical index edge exactly
    SetPosition (within one count), not SetPosition plus the old offset."""
    machine, X = homing_axis()
    first(machine)
    assert X.Ref and X.state == AxisState.StandStill
    assert abs(X.offset) > 50.0, "the first step shifted the coordinate"
    fb, inputs = search(mcl.MC_StepRefPulse, Direction=POSITIVE, SetPosition=123.4)
    execute(machine, (fb, inputs))
    assert fb.Done, (fb.ErrorID, X.AxErrorID)
    assert X.state == AxisState.StandStill and X.Ref
    index = math.floor(x_of(machine) / LAYOUT["lead"]) * LAYOUT["lead"]  # just passed it
    assert abs(coordinate_of(machine, index) - 123.4) <= COUNT + 1e-9


# ---------------------------------------------------------------------- MC_StepDirect, FinishHoming
def test_step_direct_sets_the_coordinate_where_the_axis_stands() -> None:
    """From StandStill: the current position gets SetPosition, no motion; Ref, StandStill."""
    machine, X = homing_axis()
    track = Track(machine)
    x = x_of(machine)
    fb = mcl.MC_StepDirect()
    execute(machine, (fb, {"SetPosition": 42.5}))
    assert fb.Done and X.state == AxisState.StandStill and X.Ref
    assert abs(coordinate_of(machine, x) - 42.5) <= COUNT + 1e-9
    assert track.hi - track.lo < 1e-5


def test_finish_homing_keeps_the_coordinate() -> None:
    """After a coarse step (Homing): MC_FinishHoming sets Ref and StandStill without motion
    and without changing the coordinate."""
    machine, X = homing_axis()
    approach = search(mcl.MC_StepAbsSwitch, Direction=NEGATIVE, SwitchMode=MC_SwitchMode.MC_EdgeOn)
    execute(machine, approach)
    assert X.state == AxisState.Homing
    x, position = x_of(machine), X.actual
    track = Track(machine)
    finish = mcl.MC_FinishHoming()
    execute(machine, (finish, {}))
    assert finish.Done and X.state == AxisState.StandStill and X.Ref
    assert coordinate_of(machine, x) == pytest.approx(position, abs=COUNT + 1e-9)
    assert track.hi - track.lo < 1e-5


def test_step_direct_waits_for_a_search_when_buffered_and_refuses_a_moving_axis() -> None:
    """A buffered MC_StepDirect sets the coordinate once the search has ended (at rest);
    aborting a moving axis it is refused (EParam 5) and the search goes on."""
    machine, X = homing_axis()
    fb, inputs = search(mcl.MC_StepAbsSwitch, Direction=NEGATIVE)
    machine.run(lambda: fb(Axis=X, Execute=True, **inputs), timeout=0.2)
    assert X.moving
    for refused in (mcl.MC_StepDirect(), mcl.MC_FinishHoming()):
        refused(Axis=X, Execute=True)
        assert refused.Error and refused.ErrorID == ErrorID.EParam
    machine.run(lambda: fb(Axis=X, Execute=True, **inputs), timeout=0.1)
    assert fb.Busy and X.state == AxisState.Homing and X.moving


# ---------------------------------------------------------------------- supervision errors
def _limit_case(fb_type: type[Any]) -> dict[str, Any]:
    """Inputs for a search that finds nothing within 20 mm (positive from the start)."""
    if fb_type is mcl.MC_StepBlock:
        return {"Direction": POSITIVE, "TorqueLimit": 1.0}
    if fb_type is mcl.MC_StepRefPulse:
        return {"Direction": POSITIVE}
    return {"Direction": POSITIVE, "SwitchMode": MC_SwitchMode.MC_EdgeOn}


@pytest.mark.parametrize("fb_type", SEARCHES, ids=lambda t: t.__name__)
@pytest.mark.parametrize(
    ("limit", "code", "travel"),
    [
        ({"TimeLimit": 0.3}, ErrorID.ETime, V * 0.3 - V * V / (2.0 * ACCELERATION)),
        ({"DistanceLimit": 5.0}, ErrorID.EDistance, 5.0),
    ],
    ids=["TimeLimit", "DistanceLimit"],
)
def test_time_and_distance_limits_end_the_search_with_an_error(
    fb_type: type[Any], limit: dict[str, float], code: ErrorID, travel: float
) -> None:
    """A search that exceeds TimeLimit (ETime 1) or DistanceLimit (EDistance 2) ends with that
    error: ErrorStop with AxErrorID, stopped on a ramp with the loop closed after about the
    allowed travel (TimeLimit: less the distance lost speeding up; then a short stop on the
    maximum ramp); MC_Reset brings the axis back to StandStill."""
    machine, X = homing_axis(lead=1.0)  # no index pulse within reach
    track = Track(machine)
    fb = fb_type()
    inputs: dict[str, Any] = {"Velocity": V, **_limit_case(fb_type), **limit}
    execute(machine, (fb, inputs))
    assert fb.Error and fb.ErrorID == code == X.AxErrorID, (fb.ErrorID, X.AxErrorID)
    assert X.state == AxisState.ErrorStop and X.loop_closed and not X.Ref
    assert not X.moving and abs(machine.sims["X"].v) < 1e-4
    moved = (track.hi - track.x0) * 1000.0
    assert travel - 0.02 <= moved <= travel + 0.15, moved
    reset = mcl.MC_Reset()
    execute(machine, (reset, {}))
    assert reset.Done and X.state == AxisState.StandStill and X.AxErrorID == 0


@pytest.mark.parametrize(
    "fb_type",
    [mcl.MC_StepAbsSwitch, mcl.MC_StepLimitSwitch, mcl.MC_StepRefPulse],
    ids=lambda t: t.__name__,
)
def test_torque_limit_on_an_obstacle_gives_edev_and_stops_pushing(fb_type: type[Any]) -> None:
    """A search that runs into an obstacle exceeds TorqueLimit (following error 0.5 mm): EDev 3,
    not the following error 2001; the axis stays at the obstacle and the drive stops pushing."""
    machine, X = homing_axis(lead=1.0)
    obstacle = LAYOUT["start"] + 0.003
    machine.sims["X"].blocked_at = obstacle
    track = Track(machine)
    fb = fb_type()
    inputs = {"Velocity": V, **_limit_case(fb_type), "TorqueLimit": 0.5}
    execute(machine, (fb, inputs))
    assert fb.Error and fb.ErrorID == ErrorID.EDev == X.AxErrorID, (fb.ErrorID, X.AxErrorID)
    assert X.state == AxisState.ErrorStop and X.loop_closed
    assert obstacle - 1e-5 < track.hi <= obstacle
    assert abs(X.following_error) < 0.05, "still pushing against the obstacle"


# ---------------------------------------------------------------------- parameter errors
BAD_INPUTS: list[tuple[type[Any], dict[str, Any]]] = [
    *[(t, {"Velocity": 0.0}) for t in SEARCHES],
    *[(t, {"Velocity": -V}) for t in SEARCHES],
    *[(t, {"Velocity": math.nan}) for t in SEARCHES],
    *[(t, {"Velocity": 1.0}) for t in SEARCHES],  # below 1 % of Vmax
    *[(t, {"TimeLimit": -1.0}) for t in SEARCHES],
    *[(t, {"DistanceLimit": math.inf}) for t in SEARCHES],
    *[(t, {"TorqueLimit": math.nan}) for t in SEARCHES],
    *[(t, {"Direction": MC_Direction.MC_Shortest}) for t in SEARCHES],
    *[(t, {"Direction": 0}) for t in SEARCHES],
    *[
        (t, {"Direction": MC_Direction.MC_SwitchPositive})
        for t in (mcl.MC_StepLimitSwitch, mcl.MC_StepBlock, mcl.MC_StepRefPulse)
    ],
    (mcl.MC_StepAbsSwitch, {"SwitchMode": 6}),
    (mcl.MC_StepAbsSwitch, {"SwitchMode": -1}),
    (mcl.MC_StepLimitSwitch, {"SwitchMode": MC_SwitchMode.MC_EdgeSwitchPositive}),
    (mcl.MC_StepBlock, {"TorqueLimit": 0.0}),
    (mcl.MC_StepBlock, {"TorqueLimit": mcl.AxisConfig().dev_max}),
    (mcl.MC_StepRefPulse, {"SetPosition": math.nan}),
    (mcl.MC_StepRefPulse, {"SetPosition": math.inf}),
    (mcl.MC_StepDirect, {"SetPosition": math.nan}),
    (mcl.MC_StepDirect, {"SetPosition": -math.inf}),
    *[(t, {"BufferMode": 9}) for t in (*SEARCHES, mcl.MC_StepDirect, mcl.MC_FinishHoming)],
]


def _valid_inputs(fb_type: type[Any]) -> dict[str, Any]:
    if fb_type in (mcl.MC_StepDirect, mcl.MC_FinishHoming):
        return {}
    return {"Velocity": V, **_limit_case(fb_type)}


@pytest.mark.parametrize(
    ("fb_type", "bad"),
    BAD_INPUTS,
    ids=[f"{t.__name__}-{next(iter(b))}={next(iter(b.values()))}" for t, b in BAD_INPUTS],
)
def test_parameter_errors_leave_the_axis_alone(fb_type: type[Any], bad: dict[str, Any]) -> None:
    """An invalid input: Error with EParam 5 at once; the referenced axis keeps its state,
    Ref, coordinate and position."""
    machine, X = homing_axis()
    finish = mcl.MC_FinishHoming()
    execute(machine, (finish, {}))
    assert X.Ref and X.state == AxisState.StandStill
    x, position = x_of(machine), X.actual
    track = Track(machine)
    fb = fb_type()
    inputs = {**_valid_inputs(fb_type), **bad}
    fb(Axis=X, Execute=True, **inputs)
    assert fb.Error and fb.ErrorID == ErrorID.EParam and not fb.Busy
    machine.run(lambda: fb(Axis=X, Execute=True, **inputs), timeout=0.2)
    assert X.state == AxisState.StandStill and X.Ref and X.AxErrorID == 0
    assert coordinate_of(machine, x) == pytest.approx(position, abs=COUNT + 1e-9)
    assert track.hi - track.lo < 1e-5


def test_the_valid_inputs_of_the_parameter_test_are_accepted() -> None:
    """The inputs the parameter errors start from are valid: each block starts (Busy or
    Done) with them."""
    for fb_type in (*SEARCHES, mcl.MC_StepDirect, mcl.MC_FinishHoming):
        _, X = homing_axis()
        fb = fb_type()
        fb(Axis=X, Execute=True, **_valid_inputs(fb_type))
        assert not fb.Error and (fb.Busy or fb.Done), (fb_type.__name__, fb.ErrorID)


def test_homing_blocks_refuse_a_disabled_axis() -> None:
    """Homing needs a powered axis (Epower 10); nothing moves."""
    machine, X = homing_axis()
    power = mcl.MC_Power()
    machine.run(lambda: power(Axis=X, Enable=False), timeout=0.01)
    for fb_type in (*SEARCHES, mcl.MC_StepDirect, mcl.MC_FinishHoming):
        fb = fb_type()
        fb(Axis=X, Execute=True, **_valid_inputs(fb_type))
        assert fb.Error and fb.ErrorID == ErrorID.Epower, fb_type.__name__
    assert X.state == AxisState.Disabled and not X.Ref
