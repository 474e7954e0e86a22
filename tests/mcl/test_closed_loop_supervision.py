"""Supervision in every state where the position loop is closed, on a simulated axis.

In ErrorStop after an error that keeps the loop closed (limit switch, software limit, a cam's
or a gearing's error, a homing step's supervision, MC_Power on with an error pending), in
Stopping, in Homing and as a member of an axes group in the group's error stop, the module
supervises the axis as in every other state: an encoder line fault, or a following error beyond
DevMax, opens the loop with ERRPOS 2001, the amplifier stops the axis at 0 V for
quick_stop_time, then the drive enable drops; 2001 stays the axis' error (it replaces the one
that stopped it) and MC_Reset leaves the axis Disabled. Judged from the simulated carriage (its
position and velocity), the volts and the enable the amplifier sees, and AxErrorID.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import pytest

import mcl
from mcl import AxisState, ErrorID
from mcl import faults as flt
from tests.helpers import configure, make_machine, scan
from tests.mcl.test_cam import cam_in

AXES = {
    # the axis under test: 0 at 500 mm, LIM− and LIM+ at ∓100, its hard stops at ∓110, REF
    # below −50 (mm of its coordinate)
    "X": mcl.SimAxisParams(
        start=0.5, lim_neg=0.4, lim_pos=0.6, stop_neg=0.39, stop_pos=0.61, ref_high=0.45
    ),
    "M": mcl.SimAxisParams(start=0.2),  # a master, a second group member (travel ±800 mm)
}
SHOVE = 5.0
"""How far a collision shoves the carriage [mm]: beyond DevMax (2 mm)."""
SERVO = 0.001
"""The servo period of the simulated machines [s]."""
POSITIVE, NEGATIVE = mcl.MC_Direction.MC_Positive, mcl.MC_Direction.MC_Negative


@dataclass
class Setup:
    """A machine with X brought into a closed-loop state by a program (keep calling it)."""

    machine: mcl.SimMachine
    program: Callable[[], None]
    group: mcl.AxesGroup | None = None


def _machine() -> mcl.SimMachine:
    return make_machine(AXES)


def _until_error_stop(machine: mcl.SimMachine, program: Callable[[], None], code: int) -> None:
    """Run until X is in ErrorStop with ``code``, then until its stop ramp has ended."""
    X = machine.axes["X"]
    machine.run(program, until=lambda: X.state == AxisState.ErrorStop, timeout=5.0)
    assert X.AxErrorID == code
    machine.run(program, timeout=0.2)
    assert X.state == AxisState.ErrorStop and X.loop_closed and not X.moving


def _onto_limit(direction: int, code: int, sw_limits: bool = False) -> Setup:
    machine = _machine()
    X = machine.axes["X"]
    if sw_limits:
        configure(X, LimPos=50.0, LimNeg=-50.0)
    move = mcl.MC_MoveVelocity(Axis=X, Velocity=100.0, Direction=direction)
    program = scan(lambda: move(Execute=True))
    _until_error_stop(machine, program, code)
    return Setup(machine, program)


def lim_pos() -> Setup:
    return _onto_limit(POSITIVE, ErrorID.ERRLIP)


def lim_neg() -> Setup:
    return _onto_limit(NEGATIVE, ErrorID.ERRLIN)


def sw_limit_pos() -> Setup:
    return _onto_limit(POSITIVE, ErrorID.ERRSWP, sw_limits=True)


def sw_limit_neg() -> Setup:
    return _onto_limit(NEGATIVE, ErrorID.ERRSWN, sw_limits=True)


def cam_limit() -> Setup:
    """The master speeds up beyond what the cam allows the slave X: ECamLimit 23."""
    machine = _machine()
    M, X = machine.axes["M"], machine.axes["X"]
    cam = cam_in(M, X, SlaveScaling=1.5)
    line = mcl.MC_MoveVelocity(Axis=M, Velocity=100.0, Acceleration=2000.0)
    faster = mcl.MC_MoveVelocity(Axis=M, Velocity=400.0, Acceleration=500.0)
    machine.run(scan(lambda: line(Execute=True), lambda: cam(Execute=True)), timeout=0.3)
    assert cam.InSync
    program = scan(lambda: cam(Execute=True), lambda: faster(Execute=True))
    _until_error_stop(machine, program, ErrorID.ECamLimit)
    return Setup(machine, program)


def master_error() -> Setup:
    """The master of the geared X loses its encoder: X stops with EMasterError 17."""
    machine = _machine()
    M, X = machine.axes["M"], machine.axes["X"]
    line = mcl.MC_MoveVelocity(Axis=M, Velocity=100.0, Acceleration=2000.0)
    gear = mcl.MC_GearIn(Master=M, Slave=X, RatioNumerator=1, RatioDenominator=2)
    program = scan(lambda: line(Execute=True), lambda: gear(Execute=True))
    machine.run(program, until=lambda: gear.InGear, timeout=1.0)
    machine.faults.set("M", flt.EncoderWireBreak())
    _until_error_stop(machine, program, ErrorID.EMasterError)
    return Setup(machine, program)


def _search_stopped_by(error: ErrorID, **inputs: float) -> Setup:
    """A REF search away from the cam (MC_StepAbsSwitch with ``inputs``) ends in ``error``."""
    machine = _machine()
    search = mcl.MC_StepAbsSwitch(Axis=machine.axes["X"], Direction=POSITIVE, **inputs)
    program = scan(lambda: search(Execute=True))
    _until_error_stop(machine, program, error)
    return Setup(machine, program)


def homing_time_limit() -> Setup:
    """A REF search away from the cam runs out of its TimeLimit: ETime 1."""
    return _search_stopped_by(ErrorID.ETime, Velocity=20.0, TimeLimit=0.05)


def homing_torque_limit() -> Setup:
    """A REF search whose TorqueLimit the following error exceeds: EDev 3 (stops pushing)."""
    return _search_stopped_by(ErrorID.EDev, Velocity=200.0, TorqueLimit=0.0005)


def powered_with_error() -> Setup:
    """LIM+ tripped, MC_Power off (the error stays) and on again: ErrorStop, the loop closed."""
    setup = lim_pos()
    machine, X = setup.machine, setup.machine.axes["X"]
    power = mcl.MC_Power(Axis=X)
    machine.run(lambda: power(Enable=False), until=lambda: X.state == AxisState.Disabled)
    machine.run(lambda: power(Enable=True), until=lambda: power.Status, timeout=0.1)
    assert X.state == AxisState.ErrorStop and X.AxErrorID == ErrorID.ERRLIP and X.loop_closed
    return Setup(machine, lambda: power(Enable=True))


def stopping() -> Setup:
    """MC_Stop held (Execute TRUE) after a move: Stopping."""
    machine = _machine()
    X = machine.axes["X"]
    move = mcl.MC_MoveVelocity(Axis=X, Velocity=50.0)
    stop = mcl.MC_Stop(Axis=X)
    machine.run(lambda: move(Execute=True), timeout=0.1)
    program = scan(lambda: stop(Execute=True))
    machine.run(program, until=lambda: stop.Done, timeout=1.0)
    assert X.state == AxisState.Stopping
    return Setup(machine, program)


def homing() -> Setup:
    """A REF search running: Homing."""
    machine = _machine()
    X = machine.axes["X"]
    search = mcl.MC_StepAbsSwitch(Axis=X, Direction=POSITIVE, Velocity=20.0)
    program = scan(lambda: search(Execute=True))
    machine.run(program, timeout=0.1)
    assert X.state == AxisState.Homing and X.moving
    return Setup(machine, program)


def _group_onto_lim_pos() -> Setup:
    """X and M in a group; the group's line runs X onto LIM+: GroupErrorStop."""
    machine = _machine()
    X, M = machine.axes["X"], machine.axes["M"]
    group = mcl.AxesGroup()
    for axis in (X, M):
        add = mcl.MC_AddAxisToGroup(AxesGroup=group, Axis=axis)
        add(Execute=True)
        assert add.Done
    enable = mcl.MC_GroupEnable(AxesGroup=group)
    enable(Execute=True)
    move = mcl.MC_MoveLinearRelative(AxesGroup=group, Distance=[200.0, 100.0], Velocity=100.0)
    program = scan(lambda: move(Execute=True))
    _until_error_stop(machine, program, ErrorID.ERRLIP)
    machine.run(program, until=lambda: not M.moving, timeout=1.0)
    assert group_error(group) == ErrorID.ERRLIP
    return Setup(machine, program, group)


def group_error(group: mcl.AxesGroup) -> int:
    """The group's error as MC_GroupReadError shows it (checks GroupErrorStop)."""
    status, error = mcl.MC_GroupReadStatus(AxesGroup=group), mcl.MC_GroupReadError(AxesGroup=group)
    status(Enable=True)
    error(Enable=True)
    assert status.GroupErrorStop and error.Valid
    return error.GroupErrorID


def group_member() -> Setup:
    return _group_onto_lim_pos()


STATES: dict[str, Callable[[], Setup]] = {
    "ErrorStop 2004 (LIM+)": lim_pos,
    "ErrorStop 2005 (LIM-)": lim_neg,
    "ErrorStop 2006 (SW limit +)": sw_limit_pos,
    "ErrorStop 2007 (SW limit -)": sw_limit_neg,
    "ErrorStop 23 (cam)": cam_limit,
    "ErrorStop 17 (gearing master)": master_error,
    "ErrorStop 1 (homing TimeLimit)": homing_time_limit,
    "ErrorStop 3 (homing TorqueLimit)": homing_torque_limit,
    "ErrorStop by MC_Power with an error pending": powered_with_error,
    "Stopping": stopping,
    "Homing": homing,
    "group member in ErrorStop 2004": group_member,
}


def wire_break(machine: mcl.SimMachine, name: str) -> None:
    machine.faults.set(name, flt.EncoderWireBreak())


def shove(machine: mcl.SimMachine, name: str) -> None:
    """A collision shoves the carriage by :data:`SHOVE` (the physics, not the axis' view)."""
    machine.sims[name].x += SHOVE / 1000.0


DISTURBANCES = {"encoder wire break": wire_break, "following error": shove}


class Samples:
    """Per servo instant: AxErrorID, the volts and enable the amplifier sees, the carriage."""

    def __init__(self, machine: mcl.SimMachine, name: str) -> None:
        self.axis, self.sim = machine.axes[name], machine.sims[name]
        self.rows: list[tuple[float, int, float, bool, float, float]] = []
        machine.runtime.observers.append(self)

    def __call__(self, t: float) -> None:
        sim = self.sim
        self.rows.append((t, self.axis.AxErrorID, sim.volts, sim.enabled, sim.x, sim.v))


def assert_loop_opened(setup: Setup, name: str, disturb: Callable[..., None]) -> None:
    """Disturb axis ``name`` and check what the user sees: 2001 at once, 0 V, the enable
    dropping after quick_stop_time, the carriage at rest, 2001 kept."""
    machine = setup.machine
    axis = machine.axes[name]
    samples = Samples(machine, name)
    t0 = machine.time
    disturb(machine, name)
    machine.run(setup.program, timeout=0.4)

    rows = samples.rows
    x_first = rows[0][4]
    moved = max(abs(x - x_first) for *_, x, _ in rows)
    assert moved < 0.001, f"the loop drove the carriage {moved * 1000:.1f} mm on (stays: < 1 mm)"
    t_error = next((t for t, code, *_ in rows if code == ErrorID.ERRPOS), None)
    assert t_error is not None, f"no 2001: AxErrorID {axis.AxErrorID}, state {axis.state.name}"
    assert t_error - t0 <= 2 * SERVO, "the supervision trips in the servo cycle that sees it"
    after = [r for r in rows if r[0] > t_error + SERVO]  # the output reaches the amplifier
    assert all(code == ErrorID.ERRPOS for _, code, *_ in after), "2001 is kept"
    assert all(volts == 0.0 for _, _, volts, *_ in after), "the loop is open: 0 V"
    quick_stop = axis.config.quick_stop_time
    enabled = [t for t, _, _, on, *_ in after if on]
    assert enabled and max(enabled) == pytest.approx(t_error + quick_stop, abs=2 * SERVO)
    assert axis.state == AxisState.ErrorStop and not machine.sims[name].enabled
    x_off = next(x for t, _, _, on, x, _ in after if t > max(enabled))
    assert abs(machine.sims[name].x - x_off) < 1e-4 and abs(machine.sims[name].v) < 1e-4


def assert_reset_disables(machine: mcl.SimMachine, axis: mcl.Axis) -> None:
    """MC_Reset after a 2001: the axis is Disabled (the loop was open), its error cleared."""
    reset = mcl.MC_Reset(Axis=axis)
    machine.run(lambda: reset(Execute=True), until=lambda: reset.Done, timeout=0.1)
    assert axis.state == AxisState.Disabled and axis.AxErrorID == 0


@pytest.mark.parametrize("disturbance", DISTURBANCES)
@pytest.mark.parametrize("state", STATES)
def test_every_closed_loop_state_opens_the_loop_on_an_encoder_or_following_error(
    state: str, disturbance: str
) -> None:
    """X in ``state``: an encoder wire break or a collision that shoves it beyond DevMax opens
    the loop with 2001, as in every other state."""
    setup = STATES[state]()
    assert_loop_opened(setup, "X", DISTURBANCES[disturbance])
    if setup.group is not None:
        assert group_error(setup.group) == ErrorID.ERRPOSG, "a member's 2001 is the group's 8001"
    assert_reset_disables(setup.machine, setup.machine.axes["X"])


@pytest.mark.parametrize("disturbance", DISTURBANCES)
def test_the_other_member_of_a_group_in_its_error_stop_is_supervised(disturbance: str) -> None:
    """X stopped on LIM+, the group stopped M along the line: M stands in the group's error
    stop with its loop closed, and is supervised there."""
    setup = _group_onto_lim_pos()
    M = setup.machine.axes["M"]
    assert M.state == AxisState.StandStill and M.loop_closed
    assert_loop_opened(setup, "M", DISTURBANCES[disturbance])
    assert setup.group is not None and group_error(setup.group) == ErrorID.ERRPOSG
    assert_reset_disables(setup.machine, M)


def test_an_error_that_keeps_the_loop_closed_does_not_replace_the_first_one() -> None:
    """LIM+ at 100 mm trips first; the stop ramp then carries X past its software limit at
    100.1 mm: X stays in ErrorStop with 2004 and its loop closed (only an error that opens the
    loop replaces the first one)."""
    machine = _machine()
    X = machine.axes["X"]
    configure(X, LimPos=100.1, LimNeg=-300.0)
    move = mcl.MC_MoveVelocity(Axis=X, Velocity=100.0)
    _until_error_stop(machine, scan(lambda: move(Execute=True)), ErrorID.ERRLIP)
    assert X.POS > 100.1 and machine.sims["X"].x > 0.6001, "past the software limit"
    assert X.AxErrorID == ErrorID.ERRLIP and move.ErrorID == ErrorID.ERRLIP
    assert X.state == AxisState.ErrorStop and X.loop_closed and machine.sims["X"].enabled
