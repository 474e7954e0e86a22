"""Single-axis administrative blocks (MotionControlLib chapter 3), the error texts,
GT_EStop, and MC_MoveAbsolute's Direction on a modulo axis."""

from __future__ import annotations

import math
from collections.abc import Callable

import pytest

import mcl
from mcl import AxisState, ErrorID, MC_Direction
from tests.helpers import CONSTANTS, configure, power_on, scan

PLC = 0.002
VMAX = CONSTANTS["Vmax"]
DAC_STEP = 10.5 / 4095
"""One DAC code [V]."""
POSITIVE, NEGATIVE, SHORTEST = (
    MC_Direction.MC_Positive,
    MC_Direction.MC_Negative,
    MC_Direction.MC_Shortest,
)


def fresh(
    referenced: bool = True, powered: bool = True, constants: dict[str, float] | None = None
) -> tuple[mcl.SimMachine, mcl.Axis]:
    """Axis X like the conftest fixtures (constants written, powered, referenced)."""
    m = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2)})
    x = m.axes["X"]
    configure(x, **(constants or {}))
    if powered:
        power_on(m, x, referenced)
    return m, x


# ---------------------------------------------------------------------------- GT_SetConstant
def test_set_constant_is_done_in_one_scan_and_values_reach_the_axis():
    m = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2)})
    x = m.axes["X"]
    values = {**CONSTANTS, "Kp": 2.5, "Ki": 100.0, "Vmax": 400.0, "LimPos": 600.0}
    values |= {"LimNeg": -50.0, "Ki1": 1.0, "Filter": 4.0}
    fb = mcl.GT_SetConstant()
    fb(Axis=x, Execute=True, **values)
    assert fb.Done and not fb.Busy and not fb.Error
    assert x.constants is not None
    for name, value in values.items():
        assert getattr(x.constants, name) == value, name
    fb(Axis=x, Execute=True)
    assert fb.Done  # shown while Execute stays TRUE
    fb(Axis=x, Execute=False)
    assert not fb.Done


def test_set_constant_vmax_and_sw_limits_take_effect():
    """The new Vmax clamps the velocity; the new SW limits refuse targets beyond them."""
    m, x = fresh()
    fb = mcl.GT_SetConstant()
    fb(Axis=x, Execute=True, **{**CONSTANTS, "Vmax": 250.0, "LimPos": 300.0, "LimNeg": -50.0})
    assert fb.Done
    move = mcl.MC_MoveVelocity()
    m.run(lambda: move(Axis=x, Execute=True, Velocity=400.0), until=lambda: move.InVelocity)
    assert x.OPT2n == pytest.approx(250.0)  # model velocity clamped to the new Vmax
    halt = mcl.MC_Halt()
    m.run(lambda: halt(Axis=x, Execute=True), until=lambda: halt.Done)
    absolute = mcl.MC_MoveAbsolute()
    absolute(Axis=x, Execute=True, Position=350.0, Velocity=100.0)
    assert absolute.Error and absolute.ErrorID == ErrorID.Ecil


@pytest.mark.parametrize(("name", "value"), [("Kc", 1e12), ("Kc", 1e300), ("Kp", 1e300)])
def test_large_accepted_constants_never_crash_the_servo(name: str, value: float):
    """Finite, non-negative gains: GT_SetConstant either refuses them (EParam) or the servo keeps
    running; a move never makes the servo cycle raise and the output stays finite within ±10 V."""
    m, x = fresh()
    fb = mcl.GT_SetConstant()
    fb(Axis=x, Execute=True, **{**CONSTANTS, name: value})
    if fb.Error:
        assert fb.ErrorID == ErrorID.EParam
        return
    move = mcl.MC_MoveVelocity()
    for _ in range(500):
        m.run(lambda: move(Axis=x, Execute=True, Velocity=100.0), timeout=PLC)
        assert math.isfinite(x.volts) and abs(x.volts) <= 10.0


# ---------------------------------------------------------------------------- MC_Power
def test_power_speed_mode_1_is_open_loop_volts_follow_the_model_velocity():
    m, x = fresh(powered=False)
    power, move = mcl.MC_Power(), mcl.MC_MoveVelocity()
    m.run(lambda: power(Axis=x, Enable=True, SpeedMode=1), timeout=0.01)
    assert power.Status and not power.Error
    assert x.state == AxisState.StandStill
    samples: list[tuple[float, float, float]] = []
    m.runtime.observers.append(lambda t: samples.append((x.sp_vel, x.volts, x.following_error)))
    m.run(
        scan(
            lambda: power(Axis=x, Enable=True, SpeedMode=1),
            lambda: move(Axis=x, Execute=True, Velocity=100.0),
        ),
        timeout=1.0,
    )
    # volts = model velocity × 10 V / Vmax (quantized by the DAC), every servo cycle
    for sp_vel, volts, _ in samples:
        assert volts == pytest.approx(sp_vel * 10.0 / VMAX, abs=DAC_STEP)
    # the axis runs at about the commanded velocity
    assert move.InVelocity
    assert pytest.approx(100.0, rel=0.1) == x.VEL
    assert m.sims["X"].v * 1000.0 == pytest.approx(100.0, rel=0.1)
    # the loop does not correct: the following error changes, the output does not
    cruise = samples[-300:]
    assert len({volts for _, volts, _ in cruise}) == 1
    errors = [e for _, _, e in cruise]
    assert max(errors) - min(errors) > 0.5


def test_power_status_stays_true_while_the_drive_quick_stops_after_a_following_error():
    """Status is the effective state of the power stage: after ERRPOS 2001 the loop opens but
    the drive stays enabled at 0 V for quick_stop_time (its own velocity loop brakes the axis),
    so Status stays TRUE until the enable the simulated drive sees drops, then falls with it."""
    m, x = fresh()
    sim = m.sims["X"]
    power, move = mcl.MC_Power(), mcl.MC_MoveVelocity()
    program = scan(
        lambda: power(Axis=x, Enable=True), lambda: move(Axis=x, Execute=True, Velocity=200.0)
    )
    m.run(program, until=lambda: move.InVelocity, timeout=2.0)
    rows: list[tuple[float, bool, bool, int]] = []  # t, Status, drive enable, AxErrorID
    m.runtime.observers.append(lambda t: rows.append((t, power.Status, sim.enabled, x.AxErrorID)))
    m.faults.set("X", mcl.faults.EncoderFreeze())
    m.run(program, timeout=0.4)

    t_error = next(t for t, _, _, err in rows if err == ErrorID.ERRPOS)
    t_status = next(t for t, status, _, _ in rows if not status)
    t_enable = next(t for t, _, enabled, _ in rows if not enabled)
    quick_stop, servo = x.config.quick_stop_time, x.config.servo_period
    assert t_enable - t_error == pytest.approx(quick_stop, abs=2 * servo)
    assert abs(t_status - t_enable) <= PLC + servo, "Status falls with the drive's enable"
    during = [(status, enabled) for t, status, enabled, _ in rows if t_error <= t < t_enable]
    assert during and all(enabled for _, enabled in during)
    assert all(status for t, status, _, _ in rows if t_error <= t < t_enable - PLC)
    assert not any(status or enabled for t, status, enabled, _ in rows if t > t_status + PLC)
    assert x.state == AxisState.ErrorStop and not power.Status and not power.Error
    assert abs(sim.v) < 1e-3, "the drive braked the axis before its enable dropped"


def test_a_reset_during_the_quick_stop_waits_until_the_drive_is_off():
    """MC_Reset right after ERRPOS 2001 stays Busy while the drive still brakes the axis; it is
    Done, and the axis Disabled, only once the drive's enable has dropped: a Disabled axis never
    has its power stage on."""
    m, x = fresh()
    sim = m.sims["X"]
    power, move, reset = mcl.MC_Power(), mcl.MC_MoveVelocity(), mcl.MC_Reset()
    program = scan(
        lambda: power(Axis=x, Enable=True), lambda: move(Axis=x, Execute=True, Velocity=200.0)
    )
    m.run(program, until=lambda: move.InVelocity, timeout=2.0)
    m.faults.set("X", mcl.faults.EncoderFreeze())
    m.run(program, until=lambda: x.AxErrorID == ErrorID.ERRPOS, timeout=1.0)
    rows: list[tuple[bool, bool, bool]] = []  # reset Busy, reset Done, drive enable

    def with_reset() -> None:
        program()
        reset(Axis=x, Execute=True)
        rows.append((reset.Busy, reset.Done, sim.enabled))
        assert x.state != AxisState.Disabled or not sim.enabled, "Disabled with the drive on"

    m.run(with_reset, until=lambda: reset.Done, timeout=1.0)
    busy = [enabled for was_busy, _, enabled in rows if was_busy]
    assert busy and all(busy), "Busy exactly while the drive is still enabled"
    assert rows[-1] == (False, True, False)
    assert x.state == AxisState.Disabled and x.AxErrorID == 0


def test_power_speed_mode_0_closes_the_loop():
    """Control for the test above: in closed loop the following error stays small at cruise."""
    m, x = fresh()
    move = mcl.MC_MoveVelocity()
    m.run(lambda: move(Axis=x, Execute=True, Velocity=100.0), timeout=1.0)
    assert abs(x.following_error) < 0.1
    assert pytest.approx(100.0, rel=0.02) == x.VEL


# ---------------------------------------------------------------------------- MC_ReadStatus
def read_flags(x: mcl.Axis) -> tuple[mcl.MC_ReadStatus, set[str]]:
    fb = mcl.MC_ReadStatus()
    fb(Axis=x, Enable=True)
    flags = {state.name for state in AxisState if getattr(fb, state.name)}
    return fb, flags


def bring_to(state: str) -> tuple[mcl.SimMachine, mcl.Axis, Callable[[], None]]:
    """A machine whose axis X is in ``state``; the returned program keeps it there."""
    if state == "Disabled":
        m, x = fresh(powered=False)
        return m, x, lambda: None
    if state == "ErrorStop":
        m, x = fresh(constants={"LimPos": 50.0, "LimNeg": -50.0})
    elif state == "Homing":
        m, x = fresh(referenced=False)
    else:
        m, x = fresh()
    program: Callable[[], None] = lambda: None  # noqa: E731
    if state == "DiscreteMotion":
        mv = mcl.MC_MoveAbsolute()
        program = lambda: mv(Axis=x, Execute=True, Position=300.0, Velocity=100.0)  # noqa: E731
    elif state in ("ContinuousMotion", "ErrorStop"):
        vel = mcl.MC_MoveVelocity()
        program = lambda: vel(Axis=x, Execute=True, Velocity=100.0)  # noqa: E731
    elif state == "Stopping":
        stop = mcl.MC_Stop()
        program = lambda: stop(Axis=x, Execute=True)  # noqa: E731
    elif state == "Homing":
        step = mcl.MC_StepAbsSwitch()
        program = lambda: step(  # noqa: E731
            Axis=x,
            Execute=True,
            Direction=MC_Direction.MC_Negative,
            Velocity=100.0,
            SwitchMode=mcl.MC_SwitchMode.MC_EdgeOn,
        )
    elif state == "SynchronizedMotion":
        group = mcl.AxesGroup("G")
        add, enable = mcl.MC_AddAxisToGroup(), mcl.MC_GroupEnable()
        add(AxesGroup=group, Axis=x, Execute=True)
        enable(AxesGroup=group, Execute=True)
        assert add.Done and enable.Done
        line = mcl.MC_MoveLinearAbsolute()
        program = lambda: line(  # noqa: E731
            AxesGroup=group, Execute=True, Position=[300.0], Velocity=100.0
        )
    m.run(program, until=lambda: x.state == AxisState[state], timeout=2.0)
    m.run(program, timeout=0.1)
    assert x.state == AxisState[state]
    return m, x, program


@pytest.mark.parametrize("state", [s.name for s in AxisState])
def test_read_status_shows_exactly_the_axis_state(state: str):
    _m, x, _program = bring_to(state)
    fb, flags = read_flags(x)
    assert fb.Valid and not fb.Error
    assert flags == {state}
    assert fb.Ref == x.Ref
    assert x.state == AxisState[state]  # reading did not change it
    fb(Axis=x, Enable=False)
    assert not fb.Valid
    assert not any(getattr(fb, s.name) for s in AxisState)


def test_read_status_ref_flag():
    _m, x = fresh(referenced=False)
    fb, _ = read_flags(x)
    assert fb.Ref is False
    x.Ref = True
    fb(Axis=x, Enable=True)
    assert fb.Ref is True


# ---------------------------------------------------------------------------- MC_ReadAxisError
def test_read_axis_error_shows_the_axis_error_until_reset():
    m, x, _program = bring_to("ErrorStop")
    fb = mcl.MC_ReadAxisError()
    fb(Axis=x, Enable=True)
    assert fb.Valid
    assert fb.AxisErrorID == ErrorID.ERRSWP == x.AxErrorID
    reset = mcl.MC_Reset()
    m.run(lambda: reset(Axis=x, Execute=True), until=lambda: reset.Done)
    fb(Axis=x, Enable=True)
    assert fb.Valid and fb.AxisErrorID == 0


def test_read_axis_error_reports_the_axis_error_while_valid():
    """MotionControlLib §3.4: MC_ReadAxisError.Error "signals that an
    error occurred in the axis"; the reading itself is valid, so Valid stays TRUE."""
    _m, x, _program = bring_to("ErrorStop")
    fb = mcl.MC_ReadAxisError()
    fb(Axis=x, Enable=True)
    assert fb.AxisErrorID == ErrorID.ERRSWP
    assert fb.Valid and fb.Error and fb.ErrorID == 0, (fb.Valid, fb.Error, fb.ErrorID)


def test_read_axis_error_without_error():
    _m, x = fresh()
    fb = mcl.MC_ReadAxisError()
    fb(Axis=x, Enable=True)
    assert fb.Valid and fb.AxisErrorID == 0 and not fb.Error


# ---------------------------------------------------------------------------- position
def test_read_actual_position_follows_the_axis():
    m, x = fresh()
    fb, move = mcl.MC_ReadActualPosition(), mcl.MC_MoveAbsolute()
    seen: list[tuple[float, float]] = []

    def program() -> None:
        move(Axis=x, Execute=True, Position=120.0, Velocity=200.0)
        fb(Axis=x, Enable=True)
        seen.append((fb.Position, x.POS))

    m.run(program, until=lambda: move.Done)
    assert fb.Valid and not fb.Error
    assert all(p == pos for p, pos in seen)
    assert len({p for p, _ in seen}) > 50  # it changed while moving
    fb(Axis=x, Enable=True)
    assert fb.Position == pytest.approx(120.0, abs=0.05)
    fb(Axis=x, Enable=False)
    assert not fb.Valid


# ---------------------------------------------------------------------------- GT_Analog
@pytest.mark.parametrize(("code", "volts"), [(-4095, 10.5), (4095, -10.5), (-390, 1.0)])
def test_analog_writes_the_dac_while_disabled(code: int, volts: float):
    """−4095 → +10.5 V, +4095 → −10.5 V (as the MotionControlLib manual documents it)."""
    m, x = fresh(powered=False)
    sim = m.sims["X"]
    fb = mcl.GT_Analog()
    fb(Axis=x, Execute=True, Analog=code, Par=0)
    assert fb.Done and not fb.Error
    m.run(timeout=0.1)
    assert sim.volts == pytest.approx(volts, abs=DAC_STEP)
    assert sim.enabled
    assert x.state == AxisState.Disabled
    assert math.copysign(1.0, x.POS) == math.copysign(1.0, volts)  # the axis moves that way
    assert abs(x.POS) > 1.0


def test_analog_par_1_ends_it():
    m, x = fresh(powered=False)
    sim = m.sims["X"]
    on, off = mcl.GT_Analog(), mcl.GT_Analog()
    on(Axis=x, Execute=True, Analog=-1000, Par=0)
    m.run(timeout=0.1)
    assert sim.volts > 2.0 and sim.enabled
    off(Axis=x, Execute=True, Analog=0, Par=1)
    assert off.Done
    m.run(timeout=0.3)
    assert sim.volts == 0.0 and not sim.enabled
    moved = x.POS
    m.run(timeout=0.2)
    assert pytest.approx(moved, abs=0.01) == x.POS  # coasted to rest


def test_power_ends_analog():
    m, x = fresh(powered=False)
    sim = m.sims["X"]
    fb, power = mcl.GT_Analog(), mcl.MC_Power()
    fb(Axis=x, Execute=True, Analog=-1000, Par=0)
    m.run(timeout=0.1)
    m.run(lambda: power(Axis=x, Enable=True), timeout=0.3)
    assert power.Status and x.state == AxisState.StandStill
    assert abs(sim.volts) < 2.0  # the regulator drives, not the DAC value (+2.56 V)
    m.run(lambda: power(Axis=x, Enable=False), timeout=0.3)
    assert x.state == AxisState.Disabled
    assert sim.volts == 0.0 and not sim.enabled  # the analog value does not come back


def test_analog_in_standstill_is_refused():
    m, x = fresh()
    fb = mcl.GT_Analog()
    fb(Axis=x, Execute=True, Analog=-4095, Par=0)
    assert fb.Error and fb.ErrorID == ErrorID.EpowerOff
    m.run(timeout=0.05)
    assert abs(m.sims["X"].volts) < 0.5


# ---------------------------------------------------------------------------- GT_SInfo
def test_sinfo_defaults_are_model_position_and_velocity():
    m, x = fresh()
    move = mcl.MC_MoveVelocity()
    m.run(lambda: move(Axis=x, Execute=True, Velocity=100.0), timeout=0.5)
    assert x.OPT1n == x.sp_pos
    assert x.OPT2n == x.sp_vel == pytest.approx(100.0)


@pytest.mark.parametrize("slot", ["What1", "What2"])
def test_sinfo_selectors(slot: str):
    m, x = fresh()
    fb = mcl.GT_SInfo()
    move = mcl.MC_MoveAbsolute()
    opt = "OPT1n" if slot == "What1" else "OPT2n"
    other = {"What1": 20, "What2": 21}

    def select(what: int) -> None:
        fb(Axis=x, Execute=False)
        fb(Axis=x, Execute=True, **{**other, slot: what})
        assert fb.Done and not fb.Error

    m.run(lambda: move(Axis=x, Execute=True, Position=-150.0, Velocity=100.0), timeout=0.5)
    select(20)
    assert getattr(x, opt) == x.sp_pos
    select(21)
    assert getattr(x, opt) == x.sp_vel == pytest.approx(-100.0)
    select(24)
    values = set()
    for _ in range(20):
        m.run(lambda: move(Axis=x), timeout=PLC)
        values.add(getattr(x, opt))
    assert len(values) == 1  # a captured value, not the moving position
    select(22)  # encoder status: bit 3 = REF (REF is actuated below −100 mm)
    ref_before = int(getattr(x, opt)) >> 3 & 1
    m.run(lambda: move(Axis=x), until=lambda: move.Done, timeout=5.0)
    ref_after = int(getattr(x, opt)) >> 3 & 1
    assert (ref_before, ref_after) == (0, 1)
    select(23)
    back = mcl.MC_MoveAbsolute()  # accelerating: the axis lags its set point
    m.run(
        lambda: back(Axis=x, Execute=True, Position=0.0, Velocity=100.0, Acceleration=2000.0),
        timeout=0.02,
    )
    assert getattr(x, opt) == pytest.approx(x.sp_pos - x.actual)
    assert abs(getattr(x, opt)) >= 0.002


# ---------------------------------------------------------------------------- strings
@pytest.mark.parametrize("state", [s.name for s in AxisState])
def test_status_string_names_the_state(state: str):
    _m, x, _program = bring_to(state)
    fb = mcl.GT_AxStatusString()
    fb(Axis=x, Enable=True)
    assert fb.Valid
    assert state.lower() in fb.StatStr.lower()


ERROR_TEXTS: dict[int, tuple[str, str]] = {
    1: ("time limit exceeded", "time limit"),
    2: ("distance limit exceeded", "distance limit"),
    3: ("following error limit exceeded", "polohová odchylka limit"),
    4: ("blending not possible", "nejde udělat blending"),
    5: ("invalid command parameter", "chybný parametr příkazu"),
    6: ("axis is stopped by MC_Stop", "osa je ve stopu příkazem MC_Stop"),
    7: ("hard axis error – error stop", "tvrdá chyba osy - errorstop"),
    8: ("target beyond SW limit", "cíl osy je za SW limitou"),
    9: ("axis not referenced", "osa není v referenci"),
    10: ("axis not powered", "osa není power on"),
    11: ("axis is in ErrorStop", "osa je v stavu ErrorStop"),
    12: ("constants not set", "nejsou zadány konstanty"),
    13: ("axis is powered", "osa je power on"),
    14: ("axis has no drive (encoder only)", "osa nemá pohon (jen enkodér)"),
    15: (
        "synchronisation not reachable before MasterSyncPosition",
        "synchronizace není dosažitelná před MasterSyncPosition",
    ),
    16: ("master reversed during synchronisation", "master osa couvla během synchronizace"),
    17: ("master axis error", "chyba master osy"),
    18: ("slave is not geared", "slave osa není ve vazbě na master"),
    19: ("no parameter of this number and type", "parametr tohoto čísla a typu neexistuje"),
    20: ("parameter is read-only", "parametr je jen pro čtení"),
    21: ("axis has no absolute encoder", "osa nemá absolutní snímač"),
    22: ("absolute encoder frame error", "chyba rámce absolutního snímače"),
    23: (
        "cam needs more than the slave's maximum velocity or acceleration",
        "vačka vyžaduje víc než maximální rychlost nebo zrychlení slave osy",
    ),
    24: (
        "target beyond the workspace of the kinematics",
        "cíl je mimo pracovní prostor kinematiky",
    ),
    25: ("target near a singularity of the kinematics", "cíl je blízko singularity kinematiky"),
    26: (
        "the belt is too fast for the robot to follow the part",
        "pás je příliš rychlý, robot nemůže díl sledovat",
    ),
    1000: ("axis is a group member, command refused", "osa je členem Group, příkaz nelze provést"),
    1001: ("group full", "Group je plná, nelze již přidat osu"),
    1003: ("axis is not a group member", "osa není členem Group"),
    1004: (
        "axis already in another group",
        "osa už je členem Group, nelze ji přidat do jiné Group",
    ),
    1005: ("group has no axes", "Group už nemá žádné osy"),
    2001: ("following error exceeded", "překročení polohové odchylky"),
    2004: ("positive limit switch LIM+ reached", "osa najela na pozitivní limitu LIM+"),
    2005: ("negative limit switch LIM− reached", "osa najela na negativní limitu LIM-"),
    2006: ("positive SW limit reached", "osa najela na pozitivní SW limitu"),
    2007: ("negative SW limit reached", "osa najela na negativní SW limitu"),
    8001: (
        "group member exceeded its following error",
        "osa v grupe překročila polohovou odchylku",
    ),
}
"""The English and Czech texts of every error code (docs/reference.md, Error codes)."""


@pytest.mark.parametrize("code", sorted(ERROR_TEXTS))
def test_error_text_in_both_languages(code: int):
    english, czech = ERROR_TEXTS[code]
    assert mcl.error_text(code) == english
    assert mcl.error_text(code, "en") == english
    assert mcl.error_text(code, "cz") == czech


def test_every_error_code_has_a_spec_text():
    assert {int(e) for e in ErrorID if e} == set(ERROR_TEXTS)


@pytest.mark.parametrize(
    ("limits", "velocity", "code"),
    [
        ({"LimPos": 50.0, "LimNeg": -50.0}, 100.0, ErrorID.ERRSWP),
        ({"LimPos": 50.0, "LimNeg": -50.0}, -100.0, ErrorID.ERRSWN),
        ({}, 300.0, ErrorID.ERRLIP),
    ],
)
def test_error_strings_show_the_active_axis_error(
    limits: dict[str, float], velocity: float, code: int
):
    m, x = fresh(constants=limits)
    move = mcl.MC_MoveVelocity()
    direction = MC_Direction.MC_Positive if velocity > 0 else MC_Direction.MC_Negative
    m.run(
        lambda: move(Axis=x, Execute=True, Velocity=abs(velocity), Direction=direction),
        until=lambda: x.state == AxisState.ErrorStop,
        timeout=5.0,
    )
    assert x.AxErrorID == code
    en, cz = mcl.GT_AxErrStringEN(), mcl.GT_AxErrStringCZ()
    en(Axis=x, Enable=True)
    cz(Axis=x, Enable=True)
    assert (en.ErrStr, cz.ErrStr) == ERROR_TEXTS[code]
    assert en.Error and cz.Error
    reset = mcl.MC_Reset()
    m.run(lambda: reset(Axis=x, Execute=True), until=lambda: reset.Done)
    en(Axis=x, Enable=True)
    cz(Axis=x, Enable=True)
    assert not en.Error and not cz.Error
    assert en.ErrStr not in {text for pair in ERROR_TEXTS.values() for text in pair}


# ---------------------------------------------------------------------------- GT_EStop
def test_estop_disables_every_axis_of_the_module_and_only_that_module():
    names = [f"A{i}" for i in range(7)]  # six axes to a module: A6 is on the second module
    m = mcl.SimMachine({n: mcl.SimAxisParams(start=0.2, brake_force=500.0) for n in names})
    axes = [m.axes[n] for n in names]
    for axis in axes:
        configure(axis, LimPos=40.0, LimNeg=-500.0)
        power_on(m, axis)
    moving, faulty, other = axes[0], axes[1], axes[6]
    vel, fault, far = mcl.MC_MoveVelocity(), mcl.MC_MoveVelocity(), mcl.MC_MoveVelocity()
    m.run(
        scan(
            lambda: vel(Axis=moving, Execute=True, Velocity=100.0, Direction=NEGATIVE),
            lambda: fault(Axis=faulty, Execute=True, Velocity=200.0),
            lambda: far(Axis=other, Execute=True, Velocity=100.0, Direction=NEGATIVE),
        ),
        until=lambda: faulty.state == AxisState.ErrorStop and vel.InVelocity and far.InVelocity,
        timeout=2.0,
    )
    assert faulty.AxErrorID == ErrorID.ERRSWP
    estop = mcl.GT_EStop()
    estop(Axis=moving, Enable=True)
    for axis in axes[:6]:
        assert axis.state == AxisState.Disabled, axis.name
        assert axis.AxErrorID == 0, axis.name
    m.run(lambda: estop(Axis=moving, Enable=True), timeout=0.05)
    assert estop.Done
    for axis in axes[:6]:
        sim = m.sims[axis.name]
        assert not sim.enabled and sim.volts == 0.0, axis.name  # loop open, brake on
        assert axis.sp_vel == 0.0
    assert abs(m.sims[moving.name].v) < 0.02  # braking hard: almost stopped after 50 ms
    assert other.state == AxisState.ContinuousMotion  # another module
    assert m.sims[other.name].enabled
    estop(Axis=moving, Enable=False)
    assert not estop.Done


# ---------------------------------------------------------------------------- modulo axis
def rotary() -> tuple[mcl.SimMachine, mcl.Axis]:
    params = mcl.SimAxisParams(stop_neg=-1e6, stop_pos=1e6, lim_neg=-1e6, lim_pos=1e6)
    m = mcl.SimMachine({"R": params}, config=mcl.AxisConfig(modulo=360.0))
    axis = m.axes["R"]
    configure(axis)
    power_on(m, axis)
    return m, axis


def turn(m: mcl.SimMachine, r: mcl.Axis, position: float, direction: int) -> list[float]:
    """MoveAbsolute on the rotary axis; returns the model velocities seen."""
    move = mcl.MC_MoveAbsolute()
    velocities: list[float] = []
    m.runtime.observers.append(lambda t: velocities.append(r.sp_vel))
    m.run(
        lambda: move(Axis=r, Execute=True, Position=position, Velocity=300.0, Direction=direction),
        until=lambda: move.Done or move.Error,
        timeout=10.0,
    )
    m.runtime.observers.clear()
    assert move.Done, move.ErrorID
    m.run(timeout=0.1)
    return velocities


@pytest.mark.parametrize(
    ("start", "target", "direction", "way", "travel"),
    [
        (None, 300.0, POSITIVE, +1, 300.0),
        (None, 300.0, NEGATIVE, -1, 60.0),
        (None, 300.0, SHORTEST, -1, 60.0),
        (None, 90.0, POSITIVE, +1, 90.0),
        (None, 90.0, NEGATIVE, -1, 270.0),
        (None, 90.0, SHORTEST, +1, 90.0),
        (350.0, 10.0, SHORTEST, +1, 20.0),
        (350.0, 10.0, NEGATIVE, -1, 340.0),
        (10.0, 350.0, SHORTEST, -1, 20.0),
        (10.0, 350.0, POSITIVE, +1, 340.0),
    ],
)
def test_modulo_move_absolute_direction(
    start: float | None, target: float, direction: int, way: int, travel: float
):
    m, r = rotary()
    if start is not None:
        turn(m, r, start, SHORTEST)
        assert pytest.approx(start, abs=0.05) == r.POS
    begin = r.actual  # continuous (not wrapped) position
    velocities = turn(m, r, target, direction)
    assert all(v * way >= 0.0 for v in velocities), "moved the wrong way"
    assert (r.actual - begin) * way == pytest.approx(travel, abs=0.05)
    assert 0.0 <= r.POS < 360.0
    assert pytest.approx(target, abs=0.05) == r.POS


def test_modulo_position_stays_in_one_period_over_several_turns():
    m, r = rotary()
    for _ in range(3):
        turn(m, r, 180.0, POSITIVE)
        assert pytest.approx(180.0, abs=0.05) == r.POS
        turn(m, r, 0.0, POSITIVE)
        assert 0.0 <= r.POS < 360.0
        assert min(r.POS, 360.0 - r.POS) < 0.05
    assert r.actual == pytest.approx(3 * 360.0, abs=0.1)  # three full turns forward
