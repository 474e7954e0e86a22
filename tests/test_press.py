"""The hydraulic press on MuJoCo: homing to block, pressing to pressure, holding the force,
decompression and return, measured from the physics (ram joint, contact force, chamber
pressures)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pytest

import mcl
import scenes
from scenes.__main__ import main
from scenes.hydraulics import BAR, CylinderDevice
from scenes.press import (
    BAR_PER_VOLT,
    FORCE_GAIN,
    FORCE_INPUTS,
    HOMING,
    PART,
    PRESSURE_STOP,
    REFERENCE,
    TOP,
    WEIGHT,
    Demo,
)

FULL_SCALE = 200.0 * BAR * np.pi / 4.0 * 0.080**2 / 1000.0
"""The press' rated force: supply pressure on the piston [kN] (100.5 kN)."""


def device(scene: scenes.Scene) -> CylinderDevice:
    cylinder = scene.devices["cylinder"]
    assert isinstance(cylinder, CylinderDevice)
    return cylinder


@dataclass
class Record:
    """Per servo cycle: time, program step, pressures [bar], forces [kN], joint [mm]."""

    rows: list[tuple[float, str, float, float, float, float, float]] = field(default_factory=list)

    def of(self, step: str) -> np.ndarray:
        return np.array([r[0:1] + r[2:] for r in self.rows if r[1] == step])


@pytest.fixture(scope="module")
def cycle() -> tuple[scenes.Scene, Record, dict[str, float]]:
    """One pressing cycle from 5 mm above the part, coordinate set where the ram stands."""
    scene = scenes.load("press", start={"R": (PART - 5.0) / 1000.0}, trace_every=0)
    R = scene.axes["R"]
    dev = device(scene)
    power = mcl.MC_Power(Axis=R)
    direct = mcl.MC_StepDirect(Axis=R, SetPosition=PART - 5.0)
    read = mcl.MC_ReadAnalogInput(Axis=R, InputNumber=0)
    press = mcl.GT_MoveAbsBlock(Axis=R, Position=PART + 10.0, Velocity=20.0)
    hold = mcl.MC_ForceControl(
        Axis=R, Force=75.0, ForceRamp=200.0, Velocity=20.0, Gain=FORCE_GAIN, Tolerance=0.5,
        BufferMode=mcl.MC_BufferMode.Buffered, **FORCE_INPUTS,
    )  # fmt: skip
    decompress = mcl.MC_ForceControl(
        Axis=R, Force=2.0, ForceRamp=730.0, Velocity=20.0, Gain=FORCE_GAIN, Tolerance=1.0,
        **FORCE_INPUTS,
    )  # fmt: skip
    back = mcl.MC_MoveAbsolute(Axis=R, Position=TOP + 200.0, Velocity=200.0, Acceleration=2000.0)
    state = {"step": "reference"}
    record = Record()
    marks: dict[str, float] = {}

    def observe(t: float) -> None:
        h = dev.hydraulics
        record.rows.append(
            (
                t,
                state["step"],
                h.p_a / BAR,
                h.p_b / BAR,
                scene.signal("force"),
                h.force() / 1000.0 + WEIGHT,
                scene.joint_position("R") * 1000.0,
            )
        )

    scene.runtime.observers.append(observe)

    def program() -> None:
        step = state["step"]
        power(Enable=True)
        read(Enable=True)
        direct(Execute=power.Status)
        press(Execute=step == "press", ExtStop=read.Value * BAR_PER_VOLT >= PRESSURE_STOP)
        hold(Execute=step in ("press", "hold"))  # buffered: takes over when the press stops
        decompress(Execute=step == "decompress")
        back(Execute=step == "return")

    def go(step: str, until: object = None, timeout: float = 10.0) -> None:
        state["step"] = step
        marks[step] = scene.time
        if until is None:
            scene.run(program, timeout=timeout)
        else:
            scene.run(program, until=until, timeout=timeout)  # type: ignore[arg-type]

    go("reference", lambda: direct.Done)
    go("press", lambda: press.Done)
    go("hold", timeout=0.5)
    marks["in_force"] = float(hold.InForce)
    go("decompress", timeout=0.15)
    go("return", timeout=0.3)
    marks["end"] = scene.time
    return scene, record, marks


def test_the_stroke_stops_on_pressure_with_little_overshoot(cycle):
    _, record, _ = cycle
    rows = np.vstack([record.of("press"), record.of("hold")])
    assert rows[:, 5].max() == pytest.approx(PART + 1.6, abs=0.3)  # into the part's spring
    # the stop: from the pressure reaching 150 bar until the ram stands (its deepest point)
    crossing = int(np.argmax(rows[:, 1] >= PRESSURE_STOP))
    deepest = crossing + int(np.argmax(np.diff(rows[crossing:, 5]) <= 0.0))
    peak = rows[crossing : deepest + 1, 1].max()
    print(
        f"stop at 150 bar from 20 mm/s: peak p_A {peak:.1f} bar "
        f"({100 * (peak / PRESSURE_STOP - 1):.1f} %), ram at rest "
        f"{1000 * (rows[deepest, 0] - rows[crossing, 0]):.0f} ms after the crossing"
    )
    assert PRESSURE_STOP <= peak <= 1.05 * PRESSURE_STOP


def test_the_force_is_held_on_the_part_within_one_percent_of_full_scale(cycle):
    _, record, marks = cycle
    hold = record.of("hold")
    steady = hold[hold[:, 0] > hold[0, 0] + 0.3]
    true, hydraulic = steady[:, 3], steady[:, 4]
    error = np.abs(true - 75.0).max()
    friction = float(np.mean(hydraulic - true))
    print(
        f"force hold: true {true.mean():.2f} kN (worst {error:.2f} kN = "
        f"{100 * error / FULL_SCALE:.2f} % FS); pressure-derived minus true (friction) "
        f"{friction:.2f} kN"
    )
    assert error <= 0.01 * FULL_SCALE
    assert marks["in_force"] == 1.0
    # the difference is the seal friction: at most its Coulomb value at these pressures
    pressures = steady[:, 1:3].mean(axis=0) * BAR
    seal = 250.0 + 0.005 * (
        pressures[0] * np.pi / 4 * 0.08**2 + pressures[1] * np.pi / 4 * (0.08**2 - 0.056**2)
    )
    assert abs(friction) <= seal / 1000.0 + 0.1


def test_decompression_and_reversal_have_no_pressure_step(cycle):
    _, record, _ = cycle
    rows = np.vstack([record.of("decompress"), record.of("return")])
    steps = np.abs(np.diff(rows[:, 1:3], axis=0)).max(axis=0)  # per servo cycle = per ms
    print(f"decompression and reversal: largest step A {steps[0]:.1f}, B {steps[1]:.1f} bar/ms")
    assert steps.max() <= 20.0
    force = record.of("decompress")[-1, 3]
    assert force < 10.0  # decompressed before the return stroke
    assert record.of("return")[-1, 5] < PART - 20.0  # and it returned


def test_homing_to_block_repeats_within_one_count():
    offsets, peaks, durations = [], [], []
    for start in np.linspace(0.002, 0.020, 10):
        scene = scenes.load("press", start={"R": float(start)}, trace_every=0)
        R = scene.axes["R"]
        dev = device(scene)
        power = mcl.MC_Power(Axis=R)
        block = mcl.MC_StepBlock(Axis=R, **HOMING)
        direct = mcl.MC_StepDirect(
            Axis=R, SetPosition=REFERENCE, BufferMode=mcl.MC_BufferMode.Buffered
        )
        seen = {"contact": -1.0, "peak": 0.0}

        def observe(t: float, scene=scene, dev=dev, seen=seen) -> None:
            if seen["contact"] < 0.0 and scene.joint_position("R") <= 0.0:
                seen["contact"] = t
            seen["peak"] = max(seen["peak"], dev.hydraulics.p_a, dev.hydraulics.p_b)

        scene.runtime.observers.append(observe)

        def program(power=power, block=block, direct=direct) -> None:
            power(Enable=True)
            block(Execute=power.Status)
            direct(Execute=power.Status)

        def homed(direct: mcl.MC_StepDirect = direct) -> bool:
            return bool(direct.Done)

        scene.run(program, until=homed, timeout=5.0)
        durations.append(scene.time - seen["contact"])
        scene.run(program, timeout=0.3)
        assert R.Ref and R.state == mcl.AxisState.StandStill
        # the joint coordinate [mm] where the homed coordinate reads REFERENCE: the encoder
        # counts from the power-up position, the homing set the coordinate offset
        res = R.config.resolution
        counted_from = np.floor(round(start / (res / 1000.0), 6)) * res
        offsets.append(counted_from + REFERENCE - R.offset)
        peaks.append(seen["peak"] / BAR)
    spread = (max(offsets) - min(offsets)) / R.config.resolution
    print(
        f"homing to block, 10 starts: spread {spread:.2f} counts, peak pressure "
        f"{max(peaks):.1f} bar, done {max(durations):.3f} s after contact"
    )
    assert spread <= 2.0  # within ±1 count
    assert max(peaks) <= 220.0
    assert max(durations) <= 2.5


def test_the_press_publishes_its_pressures_and_force():
    scene = scenes.load("press", trace_every=0)
    assert {"pressure_A", "pressure_B", "force"} <= set(scene.signals)
    # hanging on its oil: side B carries the ram's weight
    assert scene.signal("pressure_B") == pytest.approx(
        WEIGHT * 1000.0 / (np.pi / 4 * (0.08**2 - 0.056**2)) / BAR, rel=0.02
    )
    assert scene.signal("force") == 0.0


def test_the_press_cycle_runs_from_the_command_line(capsys):
    assert main(["run", "press"]) == 0
    out = capsys.readouterr().out
    assert "return" in out


@pytest.mark.parametrize(
    "bad",
    [
        {"InputNumber": 3},  # the press has three analog inputs: 0, 1, 2
        {"InputNumber2": 7},
        {"Gain": 0.0},
        {"Scale": math.nan},
        {"ForceRamp": -1.0},
        {"Velocity": 0.0},
    ],
)
def test_force_control_refuses_bad_inputs_and_leaves_the_axis_alone(bad):
    scene = scenes.load("press", start={"R": 0.1}, trace_every=0)
    R = scene.axes["R"]
    power = mcl.MC_Power(Axis=R)
    inputs = {"Force": 10.0, "Velocity": 10.0, "Gain": FORCE_GAIN, **FORCE_INPUTS, **bad}
    force = mcl.MC_ForceControl(Axis=R, **inputs)
    scene.run(lambda: power(Enable=True), until=lambda: bool(power.Status), timeout=1.0)
    force(Execute=True)
    assert force.Error and force.ErrorID == mcl.ErrorID.EParam
    assert R.state == mcl.AxisState.StandStill


def test_the_demo_reports_each_step_with_pressure_and_force_from_the_physics():
    scene = scenes.load("press", start=scenes.definition("press").demo_start, trace_every=0)
    program = scenes.demo(scene)
    assert isinstance(program, Demo)
    scene.run(program, until=lambda: program.done or bool(program.error), timeout=30.0)
    rows = {row["step"]: row for row in program.results}
    assert program.done and list(rows)[-1] == "return"
    held = rows["hold the force"]
    assert held["took [s]"] == pytest.approx(0.5, abs=0.002)
    force, pressure = float(held["force [kN]"]), float(held["p_A [bar]"])
    assert 70.0 < force < 80.0 and 140.0 < pressure < 165.0
    assert rows["return"]["force [kN]"] == 0.0
