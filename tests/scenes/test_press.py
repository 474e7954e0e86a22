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
from scenes.machines.press import (
    BAR_PER_VOLT,
    FORCE_GAIN,
    FORCE_INPUTS,
    PART,
    PRESSURE_STOP,
    REFERENCE,
    TOP,
    WEIGHT,
    Demo,
)
from scenes.machines.press import STEP_BLOCK_INPUTS as HOMING
from scenes.machines.press.devices import CylinderDevice
from scenes.machines.press.hydraulics import BAR
from scenes.tools.cli import main

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


# ------------------------------------------------------------------ starts and relief valves
def test_a_start_inside_the_part_is_refused_naming_the_axis_and_its_range():
    with pytest.raises(ValueError) as refused:
        scenes.load("press", start={"R": 0.275}, trace_every=0)
    text = str(refused.value)
    print(text)
    assert text.startswith("start R = 0.275 m is physically impossible")
    assert "press/workpiece" in text and "by 25 mm" in text
    assert text.endswith("R may start in 0 … 0.25 m")
    with pytest.raises(ValueError, match=r"end stop .* R may start in 0 … 0.25 m"):
        scenes.load("press", start={"R": -0.002}, trace_every=0)
    # touching the part is a start
    scene = scenes.load("press", start={"R": PART / 1000.0}, trace_every=0)
    assert scene.joint("press/R").position == PART / 1000.0


def peaks(
    scene: scenes.Scene, phases: list[tuple[float, bool, float]]
) -> tuple[float, float, float]:
    """Drive the valve directly through ``phases`` of (volts, enabled, seconds); the highest
    pressures A and B of every physics step [Pa] and the fastest ram speed [m/s]."""
    dev = device(scene)
    h, joint = dev.hydraulics, scene.joint("press/R")
    p_a, p_b, speed = h.p_a, h.p_b, 0.0
    for volts, enabled, seconds in phases:
        dev.apply(volts, enabled, not enabled)
        for _ in range(round(seconds / scene.plant.timestep)):
            scene.plant.step(1)
            p_a, p_b = max(p_a, h.p_a), max(p_b, h.p_b)
            speed = max(speed, abs(joint.velocity))
    return p_a, p_b, speed


def test_no_start_and_no_full_valve_stroke_takes_a_chamber_past_its_relief_valve():
    """Fuzz: starts across the joint's range and a little beyond, each either refused or run
    at full valve into the part or into the top stop, the drive disabled (load-holding valves
    slamming shut) at a random moment of the stroke."""
    rng = np.random.default_rng(19)
    supply = device(scenes.load("press", trace_every=0)).hydraulics.supply
    limit = supply.relief + supply.relief_override
    worst, refused, fastest = 0.0, 0, 0.0
    for start in [*rng.uniform(-0.005, 0.305, 24), 0.0, PART / 1000.0]:
        try:
            scene = scenes.load("press", start={"R": float(start)}, trace_every=0)
        except ValueError as error:
            assert not 0.0 <= start <= PART / 1000.0
            assert str(error).endswith("R may start in 0 … 0.25 m")
            refused += 1
            continue
        volts = 10.0 if rng.uniform() < 0.5 else -10.0
        stroke = float(rng.uniform(0.005, 1.0))
        p_a, p_b, speed = peaks(scene, [(volts, True, stroke), (0.0, False, 0.3)])
        worst, fastest = max(worst, p_a, p_b), max(fastest, speed)
    print(
        f"{26 - refused} starts run, {refused} refused: highest chamber pressure "
        f"{worst / BAR:.1f} bar (relief {supply.relief / BAR:.0f} + "
        f"{supply.relief_override / BAR:.0f} bar), fastest "
        f"{1000 * fastest:.0f} mm/s"
    )
    assert worst <= limit
    assert refused >= 4


def test_reversing_the_valve_at_full_force_ejects_the_ram_within_the_relief_setting():
    scene = scenes.load("press", start={"R": (PART - 1.0) / 1000.0}, trace_every=0)
    supply = device(scene).hydraulics.supply
    limit = supply.relief + supply.relief_override
    pressing = peaks(scene, [(10.0, True, 0.3)])  # onto the hard block: 100 kN
    assert device(scene).load_force > 100e3
    p_a, p_b, speed = peaks(scene, [(-10.0, True, 0.5)])  # the part's spring ejects the ram
    print(
        f"full valve reversed at {supply.supply / BAR:.0f} bar on the "
        f"part: peaks A {p_a / BAR:.1f}, B {p_b / BAR:.1f} bar, up to {1000 * speed:.0f} mm/s"
    )
    assert max(pressing[:2]) <= limit and max(p_a, p_b) <= limit


# ------------------------------------------------------------------ the disabled ram holds
@pytest.mark.parametrize("start", [0.03, 0.245])
def test_a_disabled_ram_holds_its_position_for_a_minute(start):
    scene = scenes.load("press", start={"R": start}, trace_every=0)
    joint = scene.joint("press/R")
    scene.run(lambda: None, timeout=60.0)  # never powered: the drive stays disabled
    sag = joint.position - start
    print(f"disabled at R = {1000 * start:.0f} mm: sank {1000 * sag:.4f} mm in 60 s")
    assert abs(sag) < 0.1e-3


def test_a_ram_disabled_after_a_stroke_holds_its_position_for_a_minute():
    scene = scenes.load("press", start={"R": 0.03}, trace_every=0)
    R, joint = scene.axes["R"], scene.joint("press/R")
    power = mcl.MC_Power(Axis=R)
    move = mcl.MC_MoveRelative(Axis=R, Distance=120.0, Velocity=200.0, Acceleration=2000.0)
    state = {"on": True}

    def program() -> None:
        power(Enable=state["on"])
        move(Execute=power.Status)

    scene.run(program, until=lambda: bool(move.Done), timeout=3.0)
    scene.run(program, timeout=0.2)
    state["on"] = False
    scene.run(program, until=lambda: R.state == mcl.AxisState.Disabled, timeout=1.0)
    scene.run(program, timeout=0.5)
    held = joint.position
    scene.run(program, timeout=60.0)
    sag = joint.position - held
    h = device(scene).hydraulics
    print(
        f"disabled at R = {1000 * held:.2f} mm after a stroke (p_A {h.p_a / BAR:.1f}, "
        f"p_B {h.p_b / BAR:.1f} bar): moved {1000 * sag:.4f} mm in 60 s"
    )
    assert held == pytest.approx(0.15, abs=0.5e-3)
    assert abs(sag) < 0.1e-3
