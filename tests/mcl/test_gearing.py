"""Master/slave blocks on simulated axes: MC_GearIn, MC_GearInPos, MC_GearOut.

The master is either a driven axis (read by its set point) or a measuring wheel: an encoder-only
axis with 0.025 mm per count whose material speed the test sets every servo instant (a line
speed with ±1 % ripple at 2 Hz). Relative positions are measured from the simulated physics
(``SimAxis.x``), not from the library's own figures.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass

import pytest

import mcl
from mcl.simaxis import SimAxis, SimPlant
from tests.helpers import configure, make_machine, power_on

WHEEL_RES = 0.025
"""Measuring wheel: travel per count [mm]."""
SLAVE_ORIGIN = 200.0
"""Physical position of the slave's coordinate 0 [mm]."""
LATE = 200.0 * 0.003 + WHEEL_RES
"""How far past a position the 200 mm/s master can be when a PLC program sees the output it
set there: one servo period to the first instant past it, one PLC scan to the program, and
the reading after it [mm]."""


class Line(mcl.Machine):
    """A measuring wheel on moving material (the master M) and a carriage (the slave S).

    Args:
        speed: material speed [mm/s] as a function of time [s].
        probe: print marks on the material (master's touch probe), with ``probe_delay`` [s].
    """

    def __init__(
        self,
        speed: Callable[[float], float],
        probe: mcl.Marks | None = None,
        probe_delay: float = 0.0,
    ) -> None:
        far = 1.0e9
        wheel = mcl.SimAxisParams(
            has_drive=False,
            coulomb=0.0,
            viscous=0.0,
            stop_neg=-far,
            stop_pos=far,
            lim_neg=-far,
            lim_pos=far,
            resolution=WHEEL_RES * 1e-3,
            lead=0.25,
            probe=probe,
            probe_delay=probe_delay,
        )
        self.sims = {"M": SimAxis(wheel), "S": SimAxis(mcl.SimAxisParams(start=0.2))}
        self.axes = {
            "M": mcl.Axis(self.sims["M"], mcl.AxisConfig(resolution=WHEEL_RES), "M"),
            "S": mcl.Axis(self.sims["S"], mcl.AxisConfig(), "S"),
        }
        self.runtime = mcl.Runtime(SimPlant(list(self.sims.values())), self.axes.values(), 0.002)
        self.speed = speed
        self.records: list[Record] = []
        self.runtime.observers.append(self._instant)
        S = self.axes["S"]
        configure(S)
        power_on(self, S)

    def _instant(self, t: float) -> None:
        M, S = self.axes["M"], self.axes["S"]
        wheel, carriage = self.sims["M"], self.sims["S"]
        self.records.append(
            Record(t, wheel.x * 1e3, M.actual, carriage.x * 1e3 - SLAVE_ORIGIN, S.sp_vel)
        )
        wheel.v = self.speed(t) * 1e-3  # the material drives the wheel during the next step


@dataclass(frozen=True)
class Record:
    """One servo instant: time [s], true material position [mm], master reading [mm], true
    slave position in its coordinate [mm], slave set-point velocity [mm/s]."""

    t: float
    material: float
    master: float
    slave: float
    slave_velocity: float


def rippling(mean: float, ripple: float = 0.01, hz: float = 2.0) -> Callable[[float], float]:
    """A line speed [mm/s] with a sinusoidal ripple (±``ripple`` of ``mean`` at ``hz``)."""
    return lambda t: mean * (1.0 + ripple * math.sin(2.0 * math.pi * hz * t))


SYNC = dict(
    RatioNumerator=1,
    RatioDenominator=1,
    MasterSyncPosition=300.0,
    SlaveSyncPosition=100.0,
    MasterStartDistance=150.0,
    Velocity=450.0,
    Acceleration=5000.0,
    Deceleration=5000.0,
    Jerk=200000.0,
)
"""A flying-shear synchronisation: the carriage waits at 0 and is at 100 mm, with the material,
when the wheel reads 300 mm; it starts when the wheel reads 150 mm."""


def gear_in_pos(line: Line, **inputs: object) -> mcl.MC_GearInPos:
    return mcl.MC_GearInPos(Master=line.axes["M"], Slave=line.axes["S"], **{**SYNC, **inputs})


def run_until(line: Line, program: Callable[[], None], until: Callable[[], bool], timeout: float):
    line.run(program, until=until, timeout=timeout)


def relative_error(record: Record, material_at_sync: float, slave_sync: float) -> float:
    """How far the carriage is from where the gear puts it, from the physics [mm] (ratio 1)."""
    return record.slave - slave_sync - (record.material - material_at_sync)


# --------------------------------------------------------------------------- MC_GearInPos


def test_gear_in_pos_synchronises_at_the_sync_position_with_a_rippling_master():
    line = Line(rippling(200.0))
    M, S = line.axes["M"], line.axes["S"]
    gear = gear_in_pos(line)
    seen: list[tuple[float, bool, bool]] = []

    def program() -> None:
        gear(Execute=True)
        seen.append((M.actual, gear.StartSync, gear.InSync))

    run_until(line, program, lambda: gear.InSync or gear.Error, timeout=3.0)
    assert gear.InSync and gear.Busy and gear.Active and not gear.StartSync
    assert S.state == mcl.AxisState.SynchronizedMotion
    # StartSync when the wheel passed 150 mm, InSync when it passed 300 mm
    start = next(m for m, started, _ in seen if started)
    assert 150.0 <= start <= 150.0 + LATE
    assert all(m < 150.0 + LATE for m, started, _ in seen if not started and m < 300.0)
    assert 300.0 <= M.actual <= 300.0 + LATE
    # the slave is on the gear when the wheel crosses 300 mm (set point and physics)
    crossing = next(r for r in line.records if r.master >= 300.0)
    assert crossing.slave_velocity == pytest.approx(line.speed(crossing.t), rel=0.002)
    material_at_sync = crossing.material - (crossing.master - 300.0)
    assert abs(relative_error(crossing, material_at_sync, 100.0)) <= 2 * WHEEL_RES
    # never backing up: the set point never runs back, nor does the carriage
    velocities = [r.slave_velocity for r in line.records]
    assert min(velocities) >= 0.0
    peak = -math.inf
    for r in line.records:
        peak = max(peak, r.slave)
        assert r.slave >= peak - 0.002
    assert S.optional(24) == pytest.approx(100.0, abs=LATE)  # GT_SInfo 24: captured at InSync
    # locked afterwards: the carriage runs with the material
    line.run(lambda: gear(Execute=True), timeout=0.3)
    errors = [relative_error(r, material_at_sync, 100.0) for r in line.records[-250:]]
    assert max(abs(e) for e in errors) <= 2 * WHEEL_RES
    assert gear.InSync and not gear.Done


def test_a_negative_ratio_synchronises_the_slave_against_the_master():
    line = Line(rippling(200.0))
    M = line.axes["M"]
    gear = gear_in_pos(line, RatioNumerator=-1, SlaveSyncPosition=-100.0)
    line.run(lambda: gear(Execute=True), until=lambda: gear.InSync or gear.Error, timeout=3.0)
    assert gear.InSync
    crossing = next(r for r in line.records if r.master >= 300.0)
    material_at_sync = crossing.material - (crossing.master - 300.0)
    moved = crossing.slave + 100.0 + (crossing.material - material_at_sync)
    assert abs(moved) <= 2 * WHEEL_RES
    assert crossing.slave_velocity == pytest.approx(-line.speed(crossing.t), rel=0.002)
    assert max(r.slave_velocity for r in line.records) <= 0.0
    assert M.actual >= 300.0


@pytest.mark.parametrize(("ratio", "slave_sync"), [(2, 150.0), (-1, -100.0)])
def test_after_in_sync_the_slave_runs_ratio_times_the_masters_travel(ratio: int, slave_sync: float):
    """Locked after InSync: the slave's true position (SimAxis) is SlaveSyncPosition + ratio ×
    the material's travel since the wheel read MasterSyncPosition, for as long as it runs."""
    line = Line(rippling(200.0))
    S = line.axes["S"]
    gear = gear_in_pos(line, RatioNumerator=ratio, SlaveSyncPosition=slave_sync)
    line.run(lambda: gear(Execute=True), until=lambda: gear.InSync or gear.Error, timeout=3.0)
    assert gear.InSync, gear.ErrorID
    line.run(lambda: gear(Execute=True), timeout=0.4)
    assert gear.InSync and S.state == mcl.AxisState.SynchronizedMotion and not S.AxErrorID
    crossing = next(r for r in line.records if r.master >= 300.0)
    material_at_sync = crossing.material - (crossing.master - 300.0)
    locked = [r for r in line.records if r.t >= crossing.t + 0.05]
    assert locked[-1].t - locked[0].t >= 0.3
    for r in locked:
        expected = slave_sync + ratio * (r.material - material_at_sync)
        assert r.slave == pytest.approx(expected, abs=abs(ratio) * 2 * WHEEL_RES + 0.01), r
    # the plant's true travel over the locked run is ratio × the material's
    first, last = locked[0], locked[-1]
    assert last.slave - first.slave == pytest.approx(
        ratio * (last.material - first.material), rel=0.002
    )


def test_the_slave_waits_in_its_previous_motion_until_start_sync():
    line = Line(rippling(200.0))
    M, S = line.axes["M"], line.axes["S"]
    creep = mcl.MC_MoveVelocity(Axis=S, Velocity=20.0, Acceleration=1000.0)
    line.run(lambda: creep(Execute=True), until=lambda: creep.InVelocity, timeout=0.5)
    gear = gear_in_pos(line, SlaveSyncPosition=120.0)
    line.run(lambda: gear(Execute=True), until=lambda: M.actual >= 140.0, timeout=2.0)
    # PLCopen: the velocity command reports CommandAborted at once, its motion goes on
    creep(Execute=False)
    assert creep.CommandAborted and S.state == mcl.AxisState.SynchronizedMotion
    assert not gear.StartSync and pytest.approx(20.0, abs=1.0) == S.VEL
    line.run(lambda: gear(Execute=True), until=lambda: gear.InSync or gear.Error, timeout=2.0)
    assert gear.InSync


def test_a_returning_slave_starts_to_synchronise_only_once_it_moves_with_the_master():
    line = Line(rippling(200.0))
    M, S = line.axes["M"], line.axes["S"]
    move = mcl.MC_MoveAbsolute(Axis=S, Position=150.0, Velocity=450.0, Acceleration=5000.0)
    line.run(lambda: move(Execute=True), until=lambda: move.Done, timeout=2.0)
    back = mcl.MC_MoveAbsolute(Axis=S, Position=0.0, Velocity=100.0, Acceleration=5000.0)
    gear = gear_in_pos(line, MasterSyncPosition=M.actual + 600.0, MasterStartDistance=560.0)
    line.records.clear()
    starts: list[float] = []

    def program() -> None:
        back(Execute=True)
        gear(Execute=back.Busy)
        if gear.StartSync and not starts:
            starts.append(S.sp_pos)

    line.run(program, until=lambda: gear.InSync or gear.Error, timeout=4.0)
    assert gear.InSync and back.CommandAborted
    # the wheel passed the start point while the carriage still ran back at 100 mm/s; the
    # return went on to its end, and the synchronisation began from there
    assert starts and starts[0] == pytest.approx(0.0, abs=0.5)
    velocities = [r.slave_velocity for r in line.records]
    first_forward = next(i for i, v in enumerate(velocities) if v > 0.0)
    assert min(velocities[first_forward:]) >= 0.0


@pytest.mark.parametrize("change", [1.2, 0.7])
def test_a_master_that_changes_speed_after_start_sync_is_followed(change: float):
    def speed(t: float) -> float:  # StartSync at 0.75 s; from 0.9 s a ramp over 0.1 s
        return 200.0 * (1.0 + (change - 1.0) * min(1.0, max(0.0, (t - 0.9) / 0.1)))

    line = Line(speed)
    M = line.axes["M"]
    gear = gear_in_pos(line)
    started: list[float] = []

    def program() -> None:
        gear(Execute=True)
        if gear.StartSync and not started:
            started.append(line.time)

    line.run(program, until=lambda: gear.InSync or gear.Error, timeout=4.0)
    assert gear.InSync and started and started[0] < 0.9
    crossing = next(r for r in line.records if r.master >= 300.0)
    material_at_sync = crossing.material - (crossing.master - 300.0)
    assert abs(relative_error(crossing, material_at_sync, 100.0)) <= 2 * WHEEL_RES
    assert crossing.slave_velocity == pytest.approx(200.0 * change, rel=0.002)
    velocities = [r.slave_velocity for r in line.records]
    assert min(velocities) >= 0.0
    assert max(velocities) <= 450.0 * (1.0 + mcl.gearing.REPLAN)
    assert M.actual >= 300.0


def test_a_master_that_reverses_before_in_sync_stops_the_slave_with_an_error():
    line = Line(lambda t: 200.0 if t < 1.0 else -100.0)
    S = line.axes["S"]
    gear = gear_in_pos(line)
    line.run(lambda: gear(Execute=True), until=lambda: gear.Error, timeout=3.0)
    assert gear.ErrorID == mcl.ErrorID.EMasterReversed and not gear.InSync
    assert S.state == mcl.AxisState.ErrorStop and S.AxErrorID == mcl.ErrorID.EMasterReversed
    line.run(timeout=0.5)
    assert min(r.slave_velocity for r in line.records) >= 0.0
    assert pytest.approx(0.0, abs=1.0) == S.VEL
    text = mcl.GT_AxErrStringEN()
    text(Axis=S, Enable=True)
    reset = mcl.MC_Reset()
    line.run(lambda: reset(Axis=S, Execute=True), until=lambda: reset.Done, timeout=0.5)
    assert S.state == mcl.AxisState.StandStill


@pytest.mark.parametrize(
    ("inputs", "speed"),
    [
        ({"Velocity": 150.0}, 200.0),  # ratio × master velocity above Velocity
        ({"MasterStartDistance": 20.0}, 200.0),  # 100 mm to catch up within 20 mm of master
        ({"MasterSyncPosition": -50.0, "MasterStartDistance": 100.0}, 200.0),  # already past
    ],
)
def test_an_unreachable_synchronisation_is_an_error_not_a_late_sync(
    inputs: dict[str, float], speed: float
):
    line = Line(lambda t: speed)
    S = line.axes["S"]
    gear = gear_in_pos(line, **inputs)
    line.run(lambda: gear(Execute=True), until=lambda: gear.Error, timeout=3.0)
    assert gear.ErrorID == mcl.ErrorID.ESyncUnreachable and not gear.InSync
    assert S.AxErrorID == mcl.ErrorID.ESyncUnreachable
    assert mcl.error_text(15) == "synchronisation not reachable before MasterSyncPosition"
    assert max(abs(r.slave) for r in line.records) < 0.01  # the carriage never left


def test_zeroing_1_makes_master_sync_position_the_cut_length():
    length = 430.0  # 2.15 s of material: every cut meets the ripple at another phase
    line = Line(rippling(200.0))
    M, S = line.axes["M"], line.axes["S"]
    gear = gear_in_pos(line, MasterSyncPosition=length, Zeroing=1)
    back = mcl.MC_MoveAbsolute(Axis=S, Position=0.0, Velocity=450.0, Acceleration=5000.0)
    cuts: list[float] = []
    state = {"phase": 0, "since": 0.0}

    def program() -> None:
        phase = state["phase"]
        gear(Execute=phase < 2)
        back(Execute=phase == 2)
        if phase == 0 and gear.InSync:
            state["phase"], state["since"] = 1, line.time
            r = line.records[-1]
            cuts.append(r.material - r.slave)  # the material point under the knife
        elif phase == 1 and line.time - state["since"] >= 0.1:
            state["phase"] = 2  # cut made: the carriage returns (Aborting)
        elif phase == 2 and back.Done:
            state["phase"] = 0

    line.run(program, until=lambda: len(cuts) == 5 or gear.Error, timeout=15.0)
    assert not gear.Error and len(cuts) == 5
    lengths = [b - a for a, b in itertools.pairwise(cuts)]
    assert all(abs(cut - length) <= 2 * WHEEL_RES for cut in lengths), lengths
    assert M.actual < 10.0  # zeroed at the last sync point


def test_zeroing_1_zeroes_a_driven_master_without_a_jump():
    machine = make_machine("MS")
    M, S = machine.axes["M"], machine.axes["S"]
    line = mcl.MC_MoveVelocity(Axis=M, Velocity=100.0, Acceleration=1000.0)
    gear = mcl.MC_GearInPos(
        Master=M,
        Slave=S,
        **{**SYNC, "MasterSyncPosition": 200.0, "MasterStartDistance": 100.0},
        Zeroing=1,
    )
    errors: list[float] = []

    def program() -> None:
        line(Execute=True)
        gear(Execute=line.InVelocity)
        errors.append(abs(M.following_error))

    machine.run(program, until=lambda: gear.InSync or gear.Error, timeout=4.0)
    assert gear.InSync and 0.0 <= M.actual <= LATE / 2.0  # 100 mm/s
    machine.run(program, timeout=0.2)
    assert max(errors) < 0.05 and M.state == mcl.AxisState.ContinuousMotion
    assert S.actual - M.actual == pytest.approx(100.0, abs=0.05)  # locked 100 mm apart


@pytest.mark.parametrize(("delay", "expected"), [(1.0, 0.0), (0.0, 0.2)])
def test_zeroing_2_synchronises_to_the_print_mark(delay: float, expected: float):
    mark = 137.3  # [mm] on the material, seen 1 ms late by the mark sensor
    line = Line(rippling(200.0), probe=mcl.Marks(first=mark * 1e-3, width=0.002), probe_delay=0.001)
    M = line.axes["M"]
    gear = gear_in_pos(line, MasterSyncPosition=200.0, MasterStartDistance=150.0, Zeroing=2)
    gear.Delay = delay
    line.run(lambda: gear(Execute=True), until=lambda: gear.InSync or gear.Error, timeout=3.0)
    assert gear.InSync and 200.0 <= M.actual <= 200.0 + LATE
    r = line.records[-1]
    # the carriage is at 100 mm when the material point 200 mm past the mark is at the knife;
    # without the delay's compensation it is late by speed × delay
    error = relative_error(r, mark + 200.0, 100.0)
    assert error == pytest.approx(-expected, abs=2 * WHEEL_RES)


def test_a_stop_before_in_sync_aborts_the_synchronisation():
    line = Line(rippling(200.0))
    S = line.axes["S"]
    gear = gear_in_pos(line)
    stop = mcl.MC_Stop(Axis=S, Deceleration=5000.0)
    line.run(lambda: gear(Execute=True), until=lambda: gear.StartSync, timeout=2.0)
    line.run(lambda: gear(Execute=True), timeout=0.1)
    stop(Execute=True)
    gear(Execute=True)
    assert gear.CommandAborted and not gear.InSync and not gear.Busy and not gear.Active
    assert S.state == mcl.AxisState.Stopping
    line.run(lambda: stop(Execute=True), until=lambda: stop.Done, timeout=1.0)
    stop(Execute=False)
    line.run(timeout=0.01)
    assert S.state == mcl.AxisState.StandStill


def test_an_aborting_move_after_in_sync_ends_the_gear_and_a_buffered_one_starts_at_in_sync():
    line = Line(rippling(200.0))
    S = line.axes["S"]
    gear = gear_in_pos(line)
    back = mcl.MC_MoveAbsolute(Axis=S, Position=0.0, Velocity=450.0, Acceleration=5000.0)
    line.run(lambda: gear(Execute=True), until=lambda: gear.InSync, timeout=3.0)
    back(Execute=True)
    gear(Execute=True)
    assert gear.CommandAborted and not gear.InSync
    assert S.state == mcl.AxisState.DiscreteMotion
    line.run(lambda: back(Execute=True), until=lambda: back.Done, timeout=2.0)
    assert S.actual == pytest.approx(0.0, abs=0.05)

    # Buffered: a velocity move queued behind the synchronisation takes over at InSync
    M = line.axes["M"]
    sync = M.actual + 300.0
    gear2 = gear_in_pos(line, MasterSyncPosition=sync)
    after = mcl.MC_MoveVelocity(Axis=S, Velocity=50.0, Acceleration=5000.0, BufferMode=1)

    def program() -> None:
        gear2(Execute=True)
        after(Execute=True)

    line.run(program, until=lambda: after.Active or after.Error, timeout=4.0)
    assert gear2.CommandAborted and sync <= M.actual <= sync + LATE
    line.run(program, until=lambda: after.InVelocity, timeout=1.0)


# --------------------------------------------------------------------------- MC_GearIn


def driven_pair(
    lim_pos: float = 0.0, lim_neg: float = 0.0
) -> tuple[mcl.SimMachine, mcl.Axis, mcl.Axis]:
    """Two driven axes M and S, powered and referenced; SW limits of both [mm] (0, 0: none)."""
    machine = make_machine("MS", LimPos=lim_pos, LimNeg=lim_neg)
    return machine, machine.axes["M"], machine.axes["S"]


def geared(line: mcl.MC_MoveVelocity, gear: mcl.MC_GearIn) -> Callable[[], None]:
    """A program: the master runs at its velocity, then the slave is geared to it."""

    def program() -> None:
        line(Execute=True)
        gear(Execute=line.InVelocity)

    return program


def test_gear_in_ramps_to_the_ratio_and_locks_without_catching_up():
    machine, M, S = driven_pair()
    line = mcl.MC_MoveVelocity(Axis=M, Velocity=200.0, Acceleration=2000.0)
    gear = mcl.MC_GearIn(
        Master=M, Slave=S, RatioNumerator=1, RatioDenominator=2, Acceleration=1000.0
    )
    machine.run(lambda: line(Execute=True), until=lambda: line.InVelocity, timeout=1.0)
    m0, s0 = M.sp_pos, S.sp_pos
    velocities: list[float] = []

    def program() -> None:
        line(Execute=True)
        gear(Execute=True)
        velocities.append(S.sp_vel)

    machine.run(program, until=lambda: gear.InGear, timeout=1.0)
    assert gear.Busy and gear.Active and S.state == mcl.AxisState.SynchronizedMotion
    assert S.sp_vel == pytest.approx(100.0)
    assert all(b >= a - 1e-9 for a, b in itertools.pairwise(velocities))
    # ramping 0 → 100 mm/s at 1000 mm/s² loses 100²/2000 = 5 mm on the gear; it stays lost
    lost = (M.sp_pos - m0) / 2.0 - (S.sp_pos - s0)
    assert lost == pytest.approx(5.0, abs=0.2)
    gap = S.actual - M.actual / 2.0
    machine.run(program, timeout=0.5)
    assert S.actual - M.actual / 2.0 == pytest.approx(gap, abs=0.02)
    assert gear.InGear and not gear.Done


def test_a_new_gear_in_changes_the_ratio_on_the_fly():
    machine, M, S = driven_pair()
    line = mcl.MC_MoveVelocity(Axis=M, Velocity=200.0, Acceleration=2000.0)
    first = mcl.MC_GearIn(Master=M, Slave=S, RatioNumerator=1, RatioDenominator=2)
    second = mcl.MC_GearIn(Master=M, Slave=S, RatioNumerator=3, RatioDenominator=4)

    def program() -> None:
        line(Execute=True)
        first(Execute=line.InVelocity)

    machine.run(program, until=lambda: first.InGear, timeout=1.0)
    assert S.sp_vel == pytest.approx(100.0)

    def program2() -> None:
        program()
        second(Execute=True)

    machine.run(program2, until=lambda: second.InGear, timeout=1.0)
    assert first.CommandAborted and not first.InGear and second.Active
    assert S.sp_vel == pytest.approx(150.0)


def test_any_aborting_command_ends_gear_in_and_nothing_queues_behind_it():
    machine, M, S = driven_pair()
    line = mcl.MC_MoveVelocity(Axis=M, Velocity=100.0, Acceleration=2000.0)
    gear = mcl.MC_GearIn(Master=M, Slave=S)
    queued = mcl.MC_MoveRelative(Axis=S, Distance=5.0, Velocity=100.0, BufferMode=1)
    machine.run(geared(line, gear), until=lambda: gear.InGear, timeout=1.0)
    queued(Execute=True)
    assert queued.Error and queued.ErrorID == mcl.ErrorID.EParam
    assert gear.Active and S.state == mcl.AxisState.SynchronizedMotion
    halt = mcl.MC_Halt(Axis=S, Deceleration=2000.0)
    halt(Execute=True)
    gear(Execute=True)
    assert gear.CommandAborted and not gear.InGear
    machine.run(lambda: halt(Execute=True), until=lambda: halt.Done, timeout=1.0)
    assert S.state == mcl.AxisState.StandStill


def test_gear_in_follows_an_encoder_only_master_and_a_master_encoder_fault_stops_the_slave():
    line = Line(rippling(200.0))
    M, S = line.axes["M"], line.axes["S"]
    gear = mcl.MC_GearIn(Master=M, Slave=S, Acceleration=2000.0)
    line.run(lambda: gear(Execute=True), until=lambda: gear.InGear, timeout=1.0)
    line.run(lambda: gear(Execute=True), timeout=0.5)
    recent = line.records[-500:]
    spread = [r.slave - r.material for r in recent]
    assert max(spread) - min(spread) <= 2 * WHEEL_RES
    line.faults.set("M", mcl.faults.EncoderWireBreak())
    line.run(lambda: gear(Execute=True), until=lambda: gear.Error, timeout=0.1)
    assert gear.ErrorID == mcl.ErrorID.EMasterError
    assert S.state == mcl.AxisState.ErrorStop and S.AxErrorID == mcl.ErrorID.EMasterError


# --------------------------------------------------------------------------- MC_GearOut


def test_gear_out_keeps_the_slaves_velocity_as_a_velocity_motion():
    machine, M, S = driven_pair()
    line = mcl.MC_MoveVelocity(Axis=M, Velocity=200.0, Acceleration=2000.0)
    gear = mcl.MC_GearIn(Master=M, Slave=S, RatioNumerator=1, RatioDenominator=2)
    out = mcl.MC_GearOut(Slave=S)
    machine.run(geared(line, gear), until=lambda: gear.InGear, timeout=1.0)
    out(Execute=True)
    gear(Execute=True)
    assert out.Done and not out.Busy and gear.CommandAborted
    assert S.state == mcl.AxisState.ContinuousMotion
    halt = mcl.MC_Halt(Axis=M, Deceleration=2000.0)
    machine.run(lambda: halt(Execute=True), until=lambda: halt.Done, timeout=1.0)
    assert S.sp_vel == pytest.approx(100.0) and pytest.approx(100.0, abs=1.0) == S.VEL
    out(Execute=False)
    out(Execute=True)
    assert out.Error and out.ErrorID == mcl.ErrorID.ENotGeared


# --------------------------------------------------------------------------- input checks


@pytest.mark.parametrize(
    "inputs",
    [
        {"RatioDenominator": 0},
        {"RatioNumerator": 40000},
        {"RatioNumerator": 1.5},
        {"Acceleration": math.nan},
        {"Jerk": -1.0},
        {"BufferMode": 9},
    ],
)
def test_gear_in_refuses_bad_inputs_and_leaves_the_axis_alone(inputs: dict[str, object]):
    _, M, S = driven_pair()
    gear = mcl.MC_GearIn(Master=M, Slave=S)
    gear(Execute=True, **inputs)
    assert gear.Error and gear.ErrorID == mcl.ErrorID.EParam and not gear.Busy
    assert S.state == mcl.AxisState.StandStill and S.active is None


@pytest.mark.parametrize(
    ("inputs", "error"),
    [
        ({"MasterSyncPosition": math.nan}, mcl.ErrorID.EParam),
        ({"SlaveSyncPosition": math.inf}, mcl.ErrorID.EParam),
        ({"MasterStartDistance": math.nan}, mcl.ErrorID.EParam),
        ({"RatioNumerator": 0}, mcl.ErrorID.EParam),
        ({"RatioDenominator": 0}, mcl.ErrorID.EParam),
        ({"Zeroing": 3}, mcl.ErrorID.EParam),
        ({"Kv": -1.0}, mcl.ErrorID.EParam),
        ({"Delay": math.nan}, mcl.ErrorID.EParam),
        ({"Velocity": 0.0}, mcl.ErrorID.EParam),
        ({"SlaveSyncPosition": 900.0}, mcl.ErrorID.Ecil),
    ],
)
def test_gear_in_pos_refuses_bad_inputs_and_leaves_the_axis_alone(
    inputs: dict[str, object], error: mcl.ErrorID
):
    _, M, S = driven_pair(lim_pos=800.0, lim_neg=-200.0)
    gear = mcl.MC_GearInPos(Master=M, Slave=S, **{**SYNC, **inputs})
    gear(Execute=True)
    assert gear.Error and gear.ErrorID == error and not gear.Busy and not gear.StartSync
    assert S.state == mcl.AxisState.StandStill and S.active is None


def test_the_master_must_not_be_the_slave_and_gear_in_pos_needs_ref():
    _, _, S = driven_pair()
    same = mcl.MC_GearIn(Master=S, Slave=S)
    same(Execute=True)
    assert same.Error and same.ErrorID == mcl.ErrorID.EParam
    machine = make_machine("MS", referenced=False)
    gear = mcl.MC_GearInPos(Master=machine.axes["M"], Slave=machine.axes["S"], **SYNC)
    gear(Execute=True)
    assert gear.Error and gear.ErrorID == mcl.ErrorID.Ehome
    with pytest.raises(TypeError, match="Axis"):
        mcl.MC_GearIn(Axis=S)


def test_new_error_codes_have_both_texts():
    for code in (15, 16, 17, 18):
        assert not mcl.error_text(code).startswith("unknown")
        assert not mcl.error_text(code, "cz").startswith("neznámá")
