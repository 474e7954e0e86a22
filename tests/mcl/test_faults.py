"""Injected faults (:mod:`mcl.faults`) and what a user sees, judged by the physics.

One scenario per fault on the MuJoCo gantry (X horizontal, Z vertical with a holding brake) or on
a simulated axis: the error the module reports, or the documented behaviour where the module
cannot detect the fault, measured from the joint (``scene.joint_position``), never from the
library's own view. Every scenario also checks that no value went NaN, that a moving axis came
to rest within a stated distance, and that the fault is in ``faults.events``. The figures are
the table of docs/faults.md (measured with these scenarios; the bounds leave honest margins).
"""

from __future__ import annotations

import itertools
import math
import statistics
from collections.abc import Callable

import pytest

import mcl
from mcl import AxisState, ErrorID
from mcl import faults as flt
from plc.procedures import HomeAxis
from scenes.machines import gantry
from scenes.scene import Scene
from tests.helpers import make_machine

PARK = {"X": 0.3, "Y": 0.3, "Z": -0.1}
"""Start positions of the axes [m] (an axis a test does not move stays disabled; Z on its brake)."""

QUICK_STOP = 0.1
"""AxisConfig.quick_stop_time of the gantry axes [s] (the default)."""
LATCH = 0.001
"""The module's outputs reach the drive one servo cycle after it computes them [s]."""


def build(**start: float) -> Scene:
    return gantry.build(start={**PARK, **start}, trace_every=0)


class Watch:
    """Observer of one gantry axis after :meth:`mark` (the fault): extremes of the joint
    coordinate, finiteness of POS, VEL, the volts and the physics, the first axis error and the
    moment the drive enable dropped (time and joint coordinate), the peak joint speed, the VEL
    samples."""

    def __init__(self, scene: Scene, axis: str) -> None:
        self.scene, self.name = scene, axis
        self.axis, self.io = scene.axes[axis], scene.io(axis)
        self.finite = True
        self.mark()
        scene.runtime.observers.append(self)

    def mark(self) -> None:
        """Start measuring here (call right before injecting the fault)."""
        self.t0 = self.scene.time
        self.q0 = self.q_min = self.q_max = self.scene.joint_position(self.name)
        self.t_error: float | None = None
        self.q_error = math.nan
        self.t_off: float | None = None
        self.q_off = math.nan
        self.was_enabled = self.io.enabled
        self.peak_speed = 0.0
        self.vel: list[float] = []

    def __call__(self, t: float) -> None:
        scene, axis, io = self.scene, self.axis, self.io
        q = scene.joint_position(self.name)
        self.q_min, self.q_max = min(self.q_min, q), max(self.q_max, q)
        values = (axis.POS, axis.VEL, axis.volts, io.volts, *scene.data.qpos, *scene.data.qvel)
        self.finite = self.finite and all(math.isfinite(v) for v in values)
        if self.t_error is None and axis.AxErrorID:
            self.t_error, self.q_error = t, q
        if self.t_off is None and self.was_enabled and not io.enabled:
            self.t_off, self.q_off = t, q
        self.was_enabled = io.enabled
        self.peak_speed = max(self.peak_speed, self.speed())
        self.vel.append(axis.VEL)

    def mm(self, q: float) -> float:
        """Joint travel from the mark to ``q`` [mm]."""
        return (q - self.q0) * 1e3

    @property
    def now_mm(self) -> float:
        return self.mm(self.scene.joint_position(self.name))

    @property
    def span_mm(self) -> float:
        """Largest joint excursion from the mark [mm]."""
        return max(self.q_max - self.q0, self.q0 - self.q_min) * 1e3

    def speed(self) -> float:
        """Joint speed now [m/s]."""
        return abs(float(self.scene.data.qvel[self.io.dof]))


def finite(*values: float) -> bool:
    return all(math.isfinite(v) for v in values)


def logged(machine: mcl.Machine, axis: str, fault: flt.Fault, active: bool = True) -> bool:
    """The fault change is in ``faults.events`` (and, on a scene, in the trace's events)."""
    events = machine.faults.events
    if isinstance(machine, Scene):
        assert machine.trace.events == events
    return any(e.axis == axis and e.fault == fault and e.active == active for e in events)


def cruise(
    scene: Scene, axis: str, velocity: float, distance: float
) -> tuple[Callable[[], None], mcl.MC_Power, mcl.MC_MoveRelative]:
    """Power ``axis`` and start a move; returns its program 50 ms into constant velocity."""
    ax = scene.axes[axis]
    power, move = mcl.MC_Power(), mcl.MC_MoveRelative()

    def program() -> None:
        power(Axis=ax, Enable=True)
        move(Axis=ax, Execute=True, Distance=distance, Velocity=velocity)

    scene.run(program, until=lambda: abs(ax.sp_vel) >= velocity, timeout=3.0)
    scene.run(program, timeout=0.05)
    assert ax.state == AxisState.DiscreteMotion and ax.AxErrorID == 0
    return program, power, move


def powered(scene: Scene, axis: str, settle: float = 0.3) -> Callable[[], None]:
    """Power ``axis`` at standstill; returns the program after ``settle`` seconds."""
    ax, power = scene.axes[axis], mcl.MC_Power()

    def program() -> None:
        power(Axis=ax, Enable=True)

    scene.run(program, timeout=settle)
    assert power.Status and ax.state == AxisState.StandStill
    return program


# ----------------------------------------------------------------------------- encoder


def test_encoder_freeze_at_200_mm_s_trips_errpos_and_the_amplifier_stops_the_axis():
    scene = build()
    X = scene.axes["X"]
    program, power, move = cruise(scene, "X", 200.0, 400.0)
    w = Watch(scene, "X")
    pos = X.POS
    fault = flt.EncoderFreeze()
    scene.faults.set("X", fault)
    scene.run(program, timeout=0.5)

    assert X.AxErrorID == ErrorID.ERRPOS and X.state == AxisState.ErrorStop
    assert move.Error and move.ErrorID == ErrorID.ERRPOS and not power.Status
    assert w.t_error is not None and w.t_off is not None
    # the counter stopped: the set point runs away by DevMax 2 mm in 10 ms at 200 mm/s
    assert abs(X.POS - pos) < 0.25  # frozen at the previous sample (0.2 mm)
    assert 0.008 <= w.t_error - w.t0 <= 0.012
    assert 2.0 < w.mm(w.q_error) < 3.2  # measured 2.58 mm
    assert 0.3 < w.peak_speed < 0.45, "the loop chased the frozen count (measured 375 mm/s)"
    # quick stop: enable on at 0 V for quick_stop_time, the amplifier stops the axis, then off
    assert w.t_off - w.t_error == pytest.approx(QUICK_STOP + LATCH, abs=0.0015)
    assert 5.5 < w.now_mm < 8.5  # measured 6.94 mm after the fault
    assert abs(w.now_mm - w.mm(w.q_off)) < 0.01, "at rest before the enable dropped"
    assert w.speed() < 1e-4 and not scene.io("X").enabled
    assert w.finite and logged(scene, "X", fault)


def test_encoder_wire_break_trips_errpos_at_once():
    scene = build()
    X = scene.axes["X"]
    program, _, move = cruise(scene, "X", 200.0, 400.0)
    w = Watch(scene, "X")
    fault = flt.EncoderWireBreak()
    scene.faults.set("X", fault)
    scene.run(program, timeout=0.5)

    assert X.AxErrorID == ErrorID.ERRPOS and move.ErrorID == ErrorID.ERRPOS
    assert not scene.io("X").encoder_ok
    assert w.t_error is not None and w.t_off is not None
    assert w.t_error == pytest.approx(w.t0), "the line monitor trips in the first servo cycle"
    assert w.t_off - w.t_error == pytest.approx(QUICK_STOP + LATCH, abs=0.0015)
    assert 0.7 < w.now_mm < 1.5  # measured 1.00 mm: the amplifier's own stop from 200 mm/s
    assert w.speed() < 1e-4
    assert w.finite and logged(scene, "X", fault)


def test_power_status_stays_true_through_the_quick_stop_and_falls_with_the_enable():
    """MC_Power.Status is the effective state of the power stage: after a wire break (2001) it
    stays TRUE while the amplifier, still enabled at 0 V, brakes X to rest, and falls with the
    drive enable the plant sees, quick_stop_time later."""
    scene = build()
    X, io = scene.axes["X"], scene.io("X")
    program, power, _ = cruise(scene, "X", 200.0, 400.0)
    rows: list[tuple[float, bool, bool, float]] = []  # t, Status, plant's enable, joint speed
    speed = Watch(scene, "X").speed
    scene.runtime.observers.append(lambda t: rows.append((t, power.Status, io.enabled, speed())))
    scene.faults.set("X", flt.EncoderWireBreak())
    scene.run(program, timeout=0.3)

    assert X.AxErrorID == ErrorID.ERRPOS and X.state == AxisState.ErrorStop
    t0 = rows[0][0]
    t_status = next(t for t, status, _, _ in rows if not status)
    t_enable = next(t for t, _, enabled, _ in rows if not enabled)
    plc = scene.runtime.plc_period
    assert t_enable - t0 == pytest.approx(QUICK_STOP + LATCH, abs=0.0015)
    # Status is updated once per PLC scan, the enable reaches the drive one servo cycle late
    assert abs(t_enable - t_status) <= plc + LATCH, "Status falls with the plant's enable"
    assert all(status for t, status, _, _ in rows if t < t_status)
    assert all(enabled for t, _, enabled, _ in rows if t < t_enable)
    assert not any(status or enabled for t, status, enabled, _ in rows if t > t_status + plc)
    # while Status was TRUE the enabled amplifier stopped X from 200 mm/s (measured 1.0 mm)
    assert rows[0][3] > 0.15 and max(v for t, _, _, v in rows if t_status - 0.02 <= t) < 1e-3


def test_encoder_noise_makes_vel_noisy_but_raises_no_error():
    scene = build()
    X = scene.axes["X"]
    program = powered(scene, "X")
    w = Watch(scene, "X")
    fault = flt.EncoderNoise(counts=2, seed=1)
    scene.faults.set("X", fault)
    positions: set[float] = set()
    scene.runtime.observers.append(lambda t: positions.add(round(X.POS, 6)))
    scene.run(program, timeout=1.0)

    assert X.AxErrorID == 0 and X.state == AxisState.StandStill
    vel = w.vel[100:]
    assert 0.6 < max(abs(v) for v in vel) < 2.5  # measured ±1.21 mm/s
    assert 0.25 < statistics.pstdev(vel) < 1.0  # measured 0.51 mm/s rms (0 without the fault)
    assert len(positions) >= 4, "POS jumps by up to ±2 counts"
    assert max(positions) - min(positions) <= 0.0055  # 5 counts: ±2 about a count boundary
    assert w.span_mm < 0.002, "the axis itself does not move (< 2 µm)"
    assert w.finite and logged(scene, "X", fault)


@pytest.mark.parametrize(("fraction", "distance"), [(0.01, 300.0), (0.05, -200.0)])
def test_lost_counts_let_the_position_drift_by_fraction_times_travel(fraction, distance):
    scene = build()
    X = scene.axes["X"]
    program = powered(scene, "X", settle=0.05)
    power, move = mcl.MC_Power(), mcl.MC_MoveRelative()

    def moving() -> None:
        power(Axis=X, Enable=True)
        move(Axis=X, Execute=True, Distance=distance, Velocity=200.0)

    w = Watch(scene, "X")
    pos = X.POS
    fault = flt.EncoderLostCounts(fraction)
    scene.faults.set("X", fault)
    scene.run(moving, until=lambda: move.Done or move.Error, timeout=5.0)
    scene.run(program, timeout=0.3)

    assert move.Done and X.AxErrorID == 0, "the module cannot see lost counts"
    assert X.POS - pos == pytest.approx(distance, abs=0.01)
    travel = w.now_mm
    drift = travel - (X.POS - pos)
    assert drift == pytest.approx(fraction * travel, abs=0.002)  # within 2 counts
    assert travel == pytest.approx(distance / (1.0 - fraction), abs=0.02)
    assert w.speed() < 1e-3
    assert w.finite and logged(scene, "X", fault)


# ----------------------------------------------------------------------------- drive


@pytest.mark.parametrize(
    ("axis", "velocity", "distance", "error_mm", "stop_mm"),
    [
        # X has no brake: it coasts on friction (measured: 2001 after 11.75 mm, at rest 25.57 mm)
        ("X", 200.0, 400.0, (10.0, 13.5), (22.0, 29.0)),
        # Z's brake engages at once (measured: 2001 after 0.39 mm, at rest 0.39 mm below)
        ("Z", 100.0, -100.0, (0.25, 0.6), (0.25, 0.6)),
    ],
)
def test_amplifier_fault_during_motion_trips_errpos(axis, velocity, distance, error_mm, stop_mm):
    scene = build()
    ax = scene.axes[axis]
    program, _, move = cruise(scene, axis, velocity, distance)
    w = Watch(scene, axis)
    fault = flt.AmplifierFault()
    scene.faults.set(axis, fault)
    scene.run(program, timeout=1.0)

    io = scene.io(axis)
    assert ax.AxErrorID == ErrorID.ERRPOS and move.ErrorID == ErrorID.ERRPOS
    assert w.t_off == pytest.approx(w.t0), "the amplifier switched off at once"
    assert io.brake and not io.enabled
    assert w.t_error is not None
    assert error_mm[0] < abs(w.mm(w.q_error)) < error_mm[1]
    assert stop_mm[0] < abs(w.now_mm) < stop_mm[1]
    assert w.speed() < 1e-4
    assert w.finite and logged(scene, axis, fault)

    # the amplifier is repaired: MC_Reset (→ Disabled), MC_Power, and the axis moves again
    scene.faults.clear(axis, fault)
    power, reset, back = mcl.MC_Power(), mcl.MC_Reset(), mcl.MC_MoveRelative()
    scene.run(lambda: reset(Axis=ax, Execute=True), until=lambda: reset.Done, timeout=0.1)
    assert ax.state == AxisState.Disabled and ax.AxErrorID == 0
    w.mark()

    def recover() -> None:
        power(Axis=ax, Enable=True)
        back(
            Axis=ax,
            Execute=power.Status,
            Distance=-math.copysign(10.0, distance),
            Velocity=50.0,
        )

    scene.run(recover, until=lambda: back.Done or back.Error, timeout=2.0)
    assert back.Done and ax.AxErrorID == 0
    scene.run(recover, timeout=0.2)
    assert w.now_mm == pytest.approx(-math.copysign(10.0, distance), abs=0.01)
    assert logged(scene, axis, fault, active=False) and w.finite


@pytest.mark.parametrize("axis", ["X", "Z"])
def test_drive_not_ready_powers_but_does_not_move_and_trips_errpos(axis):
    scene = build()
    ax = scene.axes[axis]
    fault = flt.DriveNotReady()
    scene.faults.set(axis, fault)
    w = Watch(scene, axis)
    power, move = mcl.MC_Power(), mcl.MC_MoveRelative()
    go = False

    def program() -> None:
        power(Axis=ax, Enable=True)
        move(Axis=ax, Execute=go, Distance=-50.0, Velocity=100.0)

    scene.run(program, timeout=0.3)
    # the module does not see the amplifier's ready signal: the loop closes, Status is TRUE
    assert power.Status and ax.state == AxisState.StandStill and ax.AxErrorID == 0
    assert not scene.io(axis).enabled and scene.io(axis).brake
    go, t_go = True, scene.time
    scene.run(program, timeout=1.0)

    assert ax.AxErrorID == ErrorID.ERRPOS and move.ErrorID == ErrorID.ERRPOS
    # the set point runs away while the axis stands: 2001 when it is DevMax (2 mm) ahead
    assert w.t_error is not None and 0.055 <= w.t_error - t_go <= 0.07  # measured 63 ms
    assert w.span_mm < 0.005, "the axis did not move (Z: held by its brake)"
    assert w.finite and logged(scene, axis, fault)


# ----------------------------------------------------------------------------- brake


def test_brake_failure_lets_z_fall_onto_its_lower_stop_when_the_drive_is_disabled():
    scene = build()
    Z = scene.axes["Z"]
    power = mcl.MC_Power()
    scene.run(lambda: power(Axis=Z, Enable=True), timeout=0.3)
    w = Watch(scene, "Z")
    fault = flt.BrakeFailure()
    scene.faults.set("Z", fault)
    scene.run(lambda: power(Axis=Z, Enable=True), timeout=0.3)
    assert w.span_mm < 0.005, "the position loop holds Z; the brake is not needed"

    w.mark()
    fallen: list[float] = []
    lo = float(scene.model.jnt_range[scene.io("Z").joint][0])
    scene.runtime.observers.append(
        lambda t: fallen.append(t) if not fallen and scene.joint_position("Z") < lo + 1e-3 else None
    )
    scene.run(lambda: power(Axis=Z, Enable=False), timeout=2.0)

    assert Z.state == AxisState.Disabled and not scene.io("Z").brake
    assert scene.joint_position("Z") == pytest.approx(lo, abs=0.5e-3), "on the lower stop"
    assert fallen and 1.0 < fallen[0] - w.t0 < 1.6  # measured: 160 mm in 1.27 s
    assert w.speed() < 1e-3
    assert w.finite and logged(scene, "Z", fault)


@pytest.mark.parametrize(
    ("delay", "sag_mm"),
    [(0.1, 1.67), (0.2, 6.22)],  # measured sag until at rest on the brake (no fault: 1.3 µm)
)
def test_slow_brake_lets_z_sag_before_it_engages(delay, sag_mm):
    scene = build()
    Z = scene.axes["Z"]
    power = mcl.MC_Power()
    scene.run(lambda: power(Axis=Z, Enable=True), timeout=0.5)
    fault = flt.BrakeSlow(delay)
    scene.faults.set("Z", fault)
    w = Watch(scene, "Z")
    engaged: list[float] = []
    scene.runtime.observers.append(
        lambda t: engaged.append(t) if not engaged and scene.io("Z").brake else None
    )
    scene.run(lambda: power(Axis=Z, Enable=False), timeout=0.6)
    assert engaged and engaged[0] - w.t0 == pytest.approx(delay + LATCH, abs=0.0015)
    sag = -w.now_mm
    assert sag == pytest.approx(sag_mm, rel=0.15)
    scene.run(lambda: power(Axis=Z, Enable=False), timeout=0.5)
    assert abs(-w.now_mm - sag) < 0.005, "then the brake holds"
    assert w.speed() < 1e-4 and Z.state == AxisState.Disabled
    assert w.finite and logged(scene, "Z", fault)


# ----------------------------------------------------------------------------- analog command


@pytest.mark.parametrize("volts", [0.5, -0.5])
def test_analog_offset_is_absorbed_by_the_integrator(volts):
    scene = build()
    X = scene.axes["X"]
    program = powered(scene, "X")
    w = Watch(scene, "X")
    fault = flt.AnalogOffset(volts)
    scene.faults.set("X", fault)
    scene.run(program, timeout=0.5)
    transient = w.span_mm
    w.mark()
    scene.run(program, timeout=1.0)

    assert X.AxErrorID == 0 and X.state == AxisState.StandStill
    assert 0.2 < transient < 0.5  # measured 0.35 mm jump, back within 5 µm after 0.32 s
    assert w.span_mm < 0.005, "at standstill within 5 µm once absorbed"
    assert abs(X.following_error) <= 0.003
    # the integrator holds the offset: the module writes −offset, the drive gets ~0 V
    assert X.volts == pytest.approx(-volts, abs=0.05)
    assert scene.io("X").volts == pytest.approx(0.0, abs=0.05)
    assert w.finite and logged(scene, "X", fault)


@pytest.mark.parametrize(
    ("volts", "low_mm", "high_mm"),
    # measured: 0.05 V (500 N through X's stiff amplifier, above its friction) dithers it by
    # a 14 µm span; 0.5 V by 0.17 mm, VEL up to 41 mm/s
    [(0.05, 0.005, 0.03), (0.5, 0.1, 0.35)],
)
def test_analog_noise_dithers_the_axis_without_an_error(volts, low_mm, high_mm):
    scene = build()
    X = scene.axes["X"]
    program = powered(scene, "X")
    w = Watch(scene, "X")
    fault = flt.AnalogNoise(volts, seed=3)
    scene.faults.set("X", fault)
    noise: list[float] = []  # what the drive gets minus what the module wrote [V]
    written = [X.volts]  # the drive gets it one servo cycle later

    def compare(t: float) -> None:
        noise.append(scene.io("X").volts - written[0])
        written[0] = X.volts

    scene.runtime.observers.append(compare)
    scene.run(program, timeout=1.0)

    assert X.AxErrorID == 0 and X.state == AxisState.StandStill
    assert max(abs(n) for n in noise) <= volts + 1e-9 and max(noise) - min(noise) > volts
    assert low_mm <= w.span_mm < high_mm
    assert w.finite and logged(scene, "X", fault)


# ----------------------------------------------------------------------------- switches


@pytest.mark.parametrize(
    ("switch", "into", "error"),
    [("lim_pos", 100.0, ErrorID.ERRLIP), ("lim_neg", -100.0, ErrorID.ERRLIN)],
)
def test_stuck_limit_switch_trips_at_once_when_moving_into_it(switch, into, error):
    scene = build()
    X = scene.axes["X"]
    fault = flt.SwitchStuck(switch, True)
    scene.faults.set("X", fault)
    scene.run(None, timeout=0.05)  # seen while disabled: no edge when the loop closes
    power, move, away = mcl.MC_Power(), mcl.MC_MoveRelative(), mcl.MC_MoveRelative()
    w = Watch(scene, "X")
    step = 0

    def program() -> None:
        power(Axis=X, Enable=True)
        away(Axis=X, Execute=step == 1, Distance=-into, Velocity=200.0)
        move(Axis=X, Execute=step == 2, Distance=into, Velocity=200.0)

    scene.run(program, timeout=0.05)
    assert power.Status and X.AxErrorID == 0
    step = 1  # away from the switch: allowed
    scene.run(program, until=lambda: away.Done or away.Error, timeout=2.0)
    scene.run(program, timeout=0.2)
    assert away.Done and w.now_mm == pytest.approx(-into, abs=0.01)
    step, w_into = 2, Watch(scene, "X")
    scene.run(program, until=lambda: move.Done or move.Error, timeout=2.0)
    scene.run(program, timeout=0.2)

    assert move.Error and move.ErrorID == error and X.AxErrorID == error
    assert w_into.t_error is not None and w_into.t_error - w_into.t0 <= 0.003
    assert w_into.span_mm < 0.01, "stopped before it moved (measured 0.0 mm)"
    assert X.loop_closed and X.state == AxisState.ErrorStop
    assert w.finite and w_into.finite and logged(scene, "X", fault)


def test_limit_switch_sticking_at_standstill_trips_at_once():
    scene = build()
    X = scene.axes["X"]
    program = powered(scene, "X")
    w = Watch(scene, "X")
    fault = flt.SwitchStuck("lim_pos", True)
    scene.faults.set("X", fault)
    scene.run(program, timeout=0.2)
    assert X.AxErrorID == ErrorID.ERRLIP and w.t_error == pytest.approx(w.t0)
    assert w.span_mm < 0.005 and w.finite and logged(scene, "X", fault)


def test_limit_switch_stuck_off_lets_the_axis_run_onto_the_hard_stop():
    scene = build(X=0.95)
    X = scene.axes["X"]
    fault = flt.SwitchStuck("lim_pos", False)  # a cut wire, wired normally open
    scene.faults.set("X", fault)
    program, _, move = cruise(scene, "X", 100.0, 150.0)  # target 1.10 m: past the hard stop
    w = Watch(scene, "X")
    scene.run(program, until=lambda: move.Error or move.Done, timeout=2.0)
    scene.run(program, timeout=0.3)

    hi = float(scene.model.jnt_range[scene.io("X").joint][1])
    assert X.AxErrorID == ErrorID.ERRPOS and move.ErrorID == ErrorID.ERRPOS
    assert w.q_max > float(scene.model.numeric("gantry/X_lim_pos_trip").data[0])
    assert w.q_error == pytest.approx(hi, abs=0.5e-3), "2001 when blocked by the hard stop"
    assert w.q_max < hi + 0.5e-3 and w.speed() < 1e-3
    assert w.finite and logged(scene, "X", fault)


def home_z(scene: Scene, timeout: float = 30.0) -> tuple[HomeAxis, Watch, list[bool]]:
    """Home Z with the gantry's recipe (REF + index); returns the procedure, a watch from the
    start and the REF levels the module sampled."""
    Z = scene.axes["Z"]
    power, home = mcl.MC_Power(), HomeAxis(Z, gantry.HOMING["Z"])
    w = Watch(scene, "Z")
    ref: list[bool] = []
    scene.runtime.observers.append(lambda t: ref.append(scene.io("Z").ref))

    def program() -> None:
        power(Axis=Z, Enable=True)
        home(Execute=power.Status)

    scene.run(program, until=lambda: home.Done or home.Error, timeout=timeout)
    scene.run(program, timeout=0.3)
    return home, w, ref


def edges(levels: list[bool]) -> int:
    return sum(a != b for a, b in itertools.pairwise(levels))


@pytest.mark.parametrize(
    ("level", "error"),
    # stuck on: the search goes up to LIM+, reverses, ends at LIM− (measured 14.6 s);
    # stuck off: down to LIM−, reverses, ends at LIM+ (16.6 s)
    [(True, ErrorID.ERRLIN), (False, ErrorID.ERRLIP)],
)
def test_stuck_ref_switch_homing_searches_both_limits_and_fails(level, error):
    scene = build(Z=-0.1)
    Z = scene.axes["Z"]
    fault = flt.SwitchStuck("ref", level)
    scene.faults.set("Z", fault)
    scene.run(None, timeout=0.01)
    home, w, _ = home_z(scene)

    assert home.Error and home.ErrorID == error and Z.AxErrorID == error
    assert not Z.Ref and Z.state == AxisState.ErrorStop
    assert w.t_error is not None and 13.0 < w.t_error - w.t0 < 18.0
    lo, hi = (float(v) for v in scene.model.jnt_range[scene.io("Z").joint])
    trips = [
        float(scene.model.numeric(f"gantry/Z_{k}_trip").data[0]) for k in ("lim_neg", "lim_pos")
    ]
    assert w.q_min < trips[0] and w.q_max > trips[1], "both limit switches reached"
    assert w.q_min > lo + 4e-3 and w.q_max < hi - 4e-3, "clear of the hard stops (measured 4.8 mm)"
    assert w.speed() < 1e-3
    assert w.finite and logged(scene, "Z", fault)


def test_bouncing_ref_switch_homing_is_repeatable():
    """REF chatters after each real edge; the index pulse (5 mm away) sets the origin, so
    homing ends on the same count as without the fault (measured: within 1 µm, for chatter up
    to 0.5 s long, i.e. 12 mm of search travel)."""
    origins = []
    chatter = []
    for fault in (None, flt.SwitchBounce("ref"), flt.SwitchBounce("ref", 0.5, 0.01)):
        # REF off: above its edge; ideal sensors, so that only the bouncing differs
        scene = gantry.build(start={**PARK, "Z": -0.01}, trace_every=0, sensors=mcl.IDEAL_SENSORS)
        scene.run(None, timeout=0.51)
        if fault is not None:
            scene.faults.set("Z", fault)
        home, w, ref = home_z(scene)
        assert home.Done and scene.axes["Z"].Ref and scene.axes["Z"].AxErrorID == 0
        origins.append(scene.joint_position("Z") - scene.axes["Z"].POS / 1000.0)
        chatter.append(edges(ref))
        assert w.q_min > -27e-3 and w.q_max <= -0.01 + 1e-6, "no run-away search"
        assert w.speed() < 1e-3 and w.finite
        assert fault is None or logged(scene, "Z", fault)
    # without the fault: REF on moving down, off moving up (no overshoot back across the edge)
    assert chatter[0] == 2 and chatter[1] > 2 and chatter[2] > chatter[1], chatter
    assert max(origins) - min(origins) < 1.5e-6, [f"{o * 1e6:.2f} µm" for o in origins]


# ----------------------------------------------------------------------------- analog input


def test_analog_input_fault_shows_in_mc_read_analog_input():
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2, analog=(2.5, 6.0))})
    X = machine.axes["X"]
    read = [mcl.MC_ReadAnalogInput(), mcl.MC_ReadAnalogInput()]
    values: list[tuple[float, float]] = []

    def program() -> None:
        for n, fb in enumerate(read):
            fb(Axis=X, Enable=True, InputNumber=n)
        values.append((read[0].Value, read[1].Value))

    machine.run(program, timeout=0.01)
    assert values[-1] == (2.5, 6.0) and read[0].Valid
    offset = flt.AnalogInputFault(channel=0, offset=0.3)
    machine.faults.set("X", offset)
    machine.run(program, timeout=0.01)
    assert values[-1] == pytest.approx((2.8, 6.0)), "channel 0 reads the offset, 1 does not"

    noisy = flt.AnalogInputFault(channel=0, offset=0.3, noise=0.05, seed=1)
    machine.faults.set("X", noisy)  # replaces the offset-only fault (same channel)
    values.clear()
    machine.run(program, timeout=0.2)
    first = [v for v, _ in values]
    assert all(2.75 <= v <= 2.85 for v in first) and statistics.pstdev(first) > 0.01
    assert all(v == 6.0 for _, v in values) and read[0].Valid and not read[0].Error

    machine.faults.clear("X", noisy)
    machine.run(program, timeout=0.01)
    assert values[-1] == (2.5, 6.0)
    sim = machine.sims["X"]
    assert sim.x == 0.2 and finite(X.POS, X.VEL, X.volts, sim.volts)
    assert logged(machine, "X", offset) and logged(machine, "X", noisy)
    assert logged(machine, "X", noisy, active=False)


# ----------------------------------------------------------------------------- scheduling


def test_schedule_sets_and_clears_at_the_servo_instants():
    machine = make_machine("X")
    X, sim = machine.axes["X"], machine.sims["X"]
    move = mcl.MC_MoveVelocity()

    def program() -> None:
        move(Axis=X, Execute=True, Velocity=50.0)

    machine.run(program, timeout=0.1)
    t0 = machine.time
    fault = flt.EncoderFreeze()
    log = machine.faults
    with pytest.raises(ValueError, match="until"):
        log.schedule("X", fault, at=t0 + 0.02, until=t0 + 0.02)
    with pytest.raises(KeyError, match="no axis 'Y'"):
        log.schedule("Y", fault, at=t0)
    log.schedule("X", fault, at=t0 + 0.0125, until=t0 + 0.0205)  # between servo instants
    assert log.pending and log.events == []
    counts: dict[int, int] = {}
    active: dict[int, bool] = {}

    def observe(t: float) -> None:
        ms = round((t - t0) * 1e3)
        counts[ms], active[ms] = sim.counts, bool(log.active("X"))

    machine.runtime.observers.append(observe)
    machine.run(program, timeout=0.03)

    # applied at the first servo instant at or after each time: 13 ms and 21 ms
    assert [(e.t, e.fault, e.active) for e in log.events] == [
        (pytest.approx(t0 + 0.013), fault, True),
        (pytest.approx(t0 + 0.021), fault, False),
    ]
    assert [ms for ms in range(30) if active[ms]] == list(range(13, 21))
    frozen = [ms for ms in range(1, 30) if counts[ms] == counts[ms - 1]]
    assert frozen == list(range(13, 21)), "the counter stood still exactly while set"
    assert not log.pending and log.active("X") == [] and X.AxErrorID == 0
    assert finite(X.POS, X.VEL, X.volts, sim.x, sim.v, sim.volts)


@pytest.mark.parametrize(
    "companion",
    [
        None,
        flt.SwitchStuck("tp", False),  # any fault in another slot keeps the slow path
    ],
    ids=["alone", "with-another-fault-set"],
)
def test_clearing_a_freeze_resumes_the_counter_from_where_it_stopped(companion):
    machine = make_machine("X")
    X, sim = machine.axes["X"], machine.sims["X"]
    move = mcl.MC_MoveRelative()

    def program() -> None:
        move(Axis=X, Execute=True, Distance=20.0, Velocity=50.0)

    machine.run(program, timeout=0.1)
    if companion is not None:
        machine.faults.set("X", companion)
    fault = flt.EncoderFreeze()
    machine.faults.set("X", fault)
    machine.run(program, timeout=0.01)  # 10 ms frozen at >= 50 mm/s: >= 500 counts missed
    frozen = sim.counts
    machine.faults.clear("X", fault)
    machine.run(program, timeout=0.001)  # one servo cycle: ~100 counts (the loop sped up)
    assert 0 < sim.counts - frozen < 250, f"resumed {sim.counts - frozen} counts on"

    machine.run(program, until=lambda: move.Done or move.Error, timeout=2.0)
    machine.run(program, timeout=0.2)
    assert move.Done and X.AxErrorID == 0
    lost = round((sim.x - 0.2) * 1e6) - sim.counts  # true travel − counted travel, at rest
    assert 450 < lost < 1200, f"{lost} counts: the travel while frozen stays uncounted"
    assert abs(sim.v) < 1e-4
    assert finite(X.POS, X.VEL, X.volts, sim.x, sim.volts)
    assert logged(machine, "X", fault) and logged(machine, "X", fault, active=False)


# ----------------------------------------------------------------------------- edge cases


@pytest.mark.parametrize(("start", "idle"), [(0.2, 0.0), (0.05, 0.1)], ids=["off", "on"])
def test_bounce_chatters_only_after_a_real_edge(start, idle):
    machine = make_machine({"X": mcl.SimAxisParams(start=start)}, powered=False)
    sim = machine.sims["X"]
    if idle:
        machine.run(timeout=idle)
    level = sim.ref
    fault = flt.SwitchBounce("ref", duration=0.05, period=0.002)
    machine.faults.set("X", fault)
    seen: list[bool] = []
    machine.runtime.observers.append(lambda t: seen.append(sim.ref))
    machine.run(timeout=0.06)
    assert sim.x == start and finite(sim.x, sim.v, sim.volts) and logged(machine, "X", fault)
    assert all(v == level for v in seen), "REF chattered on a standing axis"


def test_wire_break_holds_the_index_low():
    machine = make_machine("X", powered=False)
    sim = machine.sims["X"]
    assert sim.index, "at power-up the counter stands on an index pulse (start 0.2 m)"
    fault = flt.EncoderWireBreak()
    machine.faults.set("X", fault)
    machine.run(timeout=0.01)
    assert not sim.encoder_ok and logged(machine, "X", fault)
    assert finite(machine.axes["X"].POS, machine.axes["X"].VEL, sim.x)
    assert not sim.index


def test_slow_brake_on_an_idle_z_keeps_its_engaged_brake():
    scene = build()
    w = Watch(scene, "Z")
    fault = flt.BrakeSlow(0.2)
    scene.faults.set("Z", fault)
    scene.run(None, timeout=0.5)
    assert w.finite and logged(scene, "Z", fault)
    assert w.span_mm < 0.01
