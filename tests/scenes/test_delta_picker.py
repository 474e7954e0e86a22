"""The delta picker on the physics: the demo tracks every part on the running belt, picks it and
places it in the tray (pick error from the physics: the cup's centre against the part's centre
at the grip, no part lost); on a faster belt a part out of reach is refused with its ErrorID and
the next one picked; the photo eye latches each part where its body cuts the beam; a Cartesian
line of the group keeps the cup's face on the line (MuJoCo's site, not the set points), and the
closed chains hold the effector level."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

import mcl
import scenes
from mcl import ErrorID
from scenes.machines.delta_picker import DELTA, PICK, SLOTS, VacuumGripper
from scenes.machines.delta_picker.axes import ARMS, BELT_Y, EYE_X, PART_X
from scenes.machines.delta_picker.demo import MOVE
from scenes.machines.delta_picker.devices import PART_LENGTH, PhotoEye

TOOL = "delta_picker/tool"
LINE = {"Velocity": 2000.0, "Acceleration": 20000.0, "Deceleration": 20000.0, "Jerk": 1.0e6}


@pytest.fixture(scope="module")
def finished() -> tuple[scenes.Scene, object, list[np.ndarray]]:
    """The demo run to its end; the parts' centres [mm] at each release."""
    scene = scenes.load("delta_picker", trace_every=0)
    program = scenes.demo(scene)
    gripper = scene.device("vacuum", VacuumGripper)
    placed: list[np.ndarray] = []
    state = {"on": False}

    def watch() -> bool:
        if state["on"] and not gripper.on:  # released: where does the part stand?
            placed.append(1000.0 * gripper.part_position(len(placed)))
        state["on"] = gripper.on
        return program.done or bool(program.error)

    scene.run(program, until=watch, timeout=120.0)
    assert program.done and not program.error, program.step
    return scene, program, placed


def test_every_part_is_picked_and_placed_without_a_loss(
    finished: tuple[scenes.Scene, object, list[np.ndarray]],
) -> None:
    scene, program, placed = finished
    gripper = scene.device("vacuum", VacuumGripper)
    assert [g.part for g in gripper.grips] == list(range(len(PART_X)))
    assert gripper.lost == 0
    errors = [g.error for g in gripper.grips]
    assert max(errors) < 0.5  # the cup's centre within 0.5 mm of the part's (horizontal)
    assert all(abs(g.height) < 1.0 for g in gripper.grips)  # the cup on the part's top face
    rows = program.results  # type: ignore[attr-defined]
    for k, centre in enumerate(placed):
        x, y = SLOTS[rows[k]["place"]]
        # the place in the tray in the MCS, whose origin is 1.6 m above the floor
        assert math.hypot(centre[0] - x, centre[1] - y) < 1.0, (k, centre)
        assert centre[2] == pytest.approx(1600.0 + PICK[2] - 50.0 - 15.0, abs=1.0)
    assert [row["part"] for row in rows] == list(range(len(PART_X)))
    assert all(row["picked"] for row in rows)


def test_a_cartesian_line_keeps_the_cup_on_the_line(
    finished: tuple[scenes.Scene, object, list[np.ndarray]],
) -> None:
    """The arms homed and grouped by the demo: a line across the working cylinder at 2 m/s; the
    cup's face (the model's site) stays within 0.5 mm of the line
    and reaches its end within 0.1 mm; the effector stays level."""
    scene = scenes.load("delta_picker", trace_every=0)
    program = scenes.demo(scene)
    scene.run(program, until=lambda: program.step == "over the belt", timeout=10.0)
    group = program.group  # type: ignore[attr-defined]
    start = [PICK[0], PICK[1], PICK[2] + 25.0]  # over the belt, in the middle
    over = mcl.MC_MoveLinearAbsolute(AxesGroup=group, Position=start, **LINE)
    scene.run(lambda: over(Execute=True), until=lambda: over.Done, timeout=1.0)
    end = [250.0, 100.0, PICK[2] + 10.0]  # the cup 40 mm above the tray
    line = mcl.MC_MoveLinearAbsolute(AxesGroup=group, Position=end, **LINE)
    model, data = scene.model, scene.data
    tool = model.site(TOOL).id
    effector = model.body("delta_picker/effector").id
    offset = np.array([0.0, 0.0, 1600.0 - 50.0])
    a, b = np.array(start) + offset, np.array(end) + offset
    worst, tilt = 0.0, 0.0

    def scan() -> None:
        nonlocal worst, tilt
        line(Execute=True)
        p = 1000.0 * data.site_xpos[tool]
        u = (b - a) / np.linalg.norm(b - a)
        along = float(np.clip((p - a) @ u, 0.0, np.linalg.norm(b - a)))
        worst = max(worst, float(np.linalg.norm(p - (a + along * u))))
        tilt = max(tilt, float(2.0 * np.linalg.norm(data.xquat[effector][1:])))

    scene.run(scan, until=lambda: line.Done or line.Error, timeout=2.0)
    assert line.Done, line.ErrorID
    scene.run(scan, timeout=0.2)
    print(f"line: worst {worst:.3f} mm, tilt {tilt:.2e} rad")
    assert worst < 0.5
    # at the end within the arms' in-position window (0.01° ≈ 0.06 mm at the elbow) and what
    # the parallelograms' constraints yield under the effector's weight
    assert np.linalg.norm(1000.0 * data.site_xpos[tool] - b) < 0.1
    assert tilt < 1e-3
    angles = [scene.axes[a].POS for a in ARMS]
    assert angles == pytest.approx(DELTA.inverse(end), abs=0.01)


RATE_PARTS = 12
"""Parts latched in the rate test at 0.5 m/s."""
RATE_FLOOR = 80.0
"""Picks per minute the demo keeps up at 0.5 m/s [1/min]."""


def test_at_half_a_metre_per_second_every_part_is_picked_at_over_80_a_minute() -> None:
    """At 0.5 m/s (a part about every 0.6 s) the robot picks every latched part, none
    refused, none dropped, the cup within 0.5 mm of the part's centre (from the physics), at
    over :data:`RATE_FLOOR` picks a minute: the grips' count over the simulated time from the
    first grip to the last. Each part is placed in a free place of the tray: at its release no
    other part's centre lies within 80 mm of its own (the places are 90 mm apart)."""
    scene = scenes.load("delta_picker", trace_every=0)
    program = scenes.demo(scene)
    program.run.Velocity = 500.0  # type: ignore[attr-defined]
    program.parts = RATE_PARTS  # type: ignore[attr-defined]
    gripper = scene.device("vacuum", VacuumGripper)
    gaps: list[float] = []
    state = {"on": False, "held": -1}

    def watch() -> bool:
        if state["on"] and not gripper.on:  # released: how near is the next part?
            centres = [gripper.part_position(k) for k in range(len(PART_X))]
            mine = centres[state["held"]]
            gaps.append(
                min(1000.0 * float(np.hypot(*(c - mine)[:2])) for c in centres if c is not mine)
            )
        state["on"], state["held"] = gripper.on, gripper.held
        return program.done or bool(program.error)

    scene.run(program, until=watch, timeout=60.0)
    assert program.done, (program.step, program.error)
    rows = program.results  # type: ignore[attr-defined]
    assert len(rows) == RATE_PARTS
    assert all(row["picked"] for row in rows), [row["error id"] for row in rows]
    assert len(gripper.grips) == RATE_PARTS and gripper.lost == 0
    assert len(gaps) == RATE_PARTS and min(gaps) > 80.0, gaps
    assert max(g.error for g in gripper.grips) < 0.5, [g.error for g in gripper.grips]
    span = gripper.grips[-1].time - gripper.grips[0].time
    rate = 60.0 * (RATE_PARTS - 1) / span
    print(f"{rate:.1f} picks/min at 0.5 m/s over {RATE_PARTS} parts")
    assert rate > RATE_FLOOR


def test_a_part_out_of_reach_is_refused_and_the_next_one_picked() -> None:
    """At 0.75 m/s the parts come faster than the robot picks them: one that will have left the
    reach before it can be picked is refused with EWorkspace (the robot does not move for it)
    and the next one is tracked and picked; none is lost. (Picked far down the belt, near the
    reach's edge, the cup lands within 1 mm here; at the demo's 0.25 m/s within 0.5 mm.)"""
    scene = scenes.load("delta_picker", trace_every=0)
    program = scenes.demo(scene)
    program.run.Velocity = 750.0  # type: ignore[attr-defined]
    scene.run(program, until=lambda: program.done or bool(program.error), timeout=60.0)
    assert program.done, program.step
    rows = program.results  # type: ignore[attr-defined]
    refused = [k for k, row in enumerate(rows) if not row["picked"]]
    assert refused, rows
    for k in refused:
        assert rows[k]["error id"] == mcl.ErrorID.EWorkspace
        if k + 1 < len(rows) and k + 1 not in refused:
            assert rows[k + 1]["picked"]
    gripper = scene.device("vacuum", VacuumGripper)
    assert len(gripper.grips) == len(rows) - len(refused)
    assert max(g.error for g in gripper.grips) < 1.0
    assert gripper.lost == 0


def test_at_1_m_s_every_part_is_picked_within_half_a_millimetre_or_refused() -> None:
    """At 1.0 m/s the parts come three times faster than the robot picks them: each latched
    part is either picked with the cup's centre within 0.5 mm of the part's (from the physics:
    the eye latches where the part is now, the vacuum comes on once the tool point's following
    error has settled) or refused with its ErrorID; no part is dropped (lifted while tracked, it
    is carried off the belt's parts before it goes along the belt)."""
    scene = scenes.load("delta_picker", trace_every=0)
    program = scenes.demo(scene)
    program.run.Velocity = 1000.0  # type: ignore[attr-defined]
    program.parts = 6  # type: ignore[attr-defined]
    scene.run(program, until=lambda: program.done or bool(program.error), timeout=60.0)
    assert program.done, (program.step, program.error)
    rows = program.results  # type: ignore[attr-defined]
    assert len(rows) == 6
    picked = [row for row in rows if row["picked"]]
    assert picked, rows
    assert all(
        row["error id"] in (ErrorID.EWorkspace, ErrorID.ETrackTooFast)
        for row in rows
        if not row["picked"]
    ), rows
    gripper = scene.device("vacuum", VacuumGripper)
    assert len(gripper.grips) == len(picked)
    assert max(g.error for g in gripper.grips) < 0.5, [g.error for g in gripper.grips]
    # the cup's face on the part's top: the part rests 1 mm deep in the belt's soft contact, the
    # tool point's height follows within 0.5 mm
    assert all(abs(g.height) < 2.0 for g in gripper.grips), [g.height for g in gripper.grips]
    assert gripper.lost == 0


def test_the_photo_eye_latches_where_a_part_cuts_its_beam() -> None:
    """The belt runs; the touch probe's latch is the belt's position when part 0's leading edge
    (its slide in the physics, at the same instant as the belt's) crossed the beam, plus the
    eye's 0.5 ms response time; the eye reports the part's lateral position."""
    scene = scenes.load("delta_picker", trace_every=0)
    program = scenes.demo(scene)
    scene.run(program, until=lambda: program.step == "group the arms", timeout=10.0)
    belt, joint = scene.axes["C"], scene.joint("C")
    offset = belt.actual - 1000.0 * joint.position  # the belt stands: its encoder's zero
    scene.run(program, until=lambda: program.step == "wait for a part", timeout=10.0)
    eye = scene.device("eye", PhotoEye)
    gripper = scene.device("vacuum", VacuumGripper)
    probe = mcl.MC_TouchProbe(Axis=belt)
    slide = scene.joint("part0_x")  # part 0's centre: its place at C = 0 plus its slide
    samples: list[tuple[float, float]] = []  # (part 0's front [mm], belt [mm]) of the physics

    def scan() -> None:
        program.run(Execute=True)  # type: ignore[attr-defined]
        probe(Execute=True)
        front = PART_X[0] + 1000.0 * (slide.position + 0.5 * PART_LENGTH)
        samples.append((front, 1000.0 * joint.position + offset))

    scene.run(scan, until=lambda: probe.Done, timeout=5.0)
    (f0, b0), (f1, b1) = next(
        (a, b) for a, b in itertools.pairwise(samples) if a[0] < EYE_X <= b[0]
    )
    crossing = b0 + (EYE_X - f0) / (f1 - f0) * (b1 - b0)
    speed = program.run.Velocity  # type: ignore[attr-defined]
    assert probe.RecordedPosition == pytest.approx(crossing + speed * 0.0005, abs=0.02)
    assert eye.lateral[0] == pytest.approx(1000.0 * gripper.part_position(0)[1], abs=0.01)


@pytest.mark.parametrize("edge", [LINE, MOVE], ids=["2 m/s", "the demo's move"])
def test_a_point_refused_during_a_stop_ramps_the_arms_within_their_stop_distance(
    edge: dict[str, float],
) -> None:
    """A line toward the workspace's edge, stopped (MC_GroupStop) with a gentle deceleration:
    the stop ramp would run on along the line beyond its end, where arm A2 would pass its 85°
    and the kinematics refuses the point; the ramp is refused when it is planned. Every arm
    ramps from its last set point to standstill on its own fastest ramp: no step of a set point
    velocity beyond what that ramp changes in a servo cycle, each arm (on the physics) within
    its stop distance, inside its SW limits; the group in GroupErrorStop with EWorkspace until
    MC_GroupReset. (Refused where the ramp reached the edge, a 3 m/s line left A2 at
    88.7°, beyond its 86° SW limit.)"""
    scene = scenes.load("delta_picker", trace_every=0)
    program = scenes.demo(scene)
    scene.run(program, until=lambda: program.step == "over the belt", timeout=10.0)
    group = program.group  # type: ignore[attr-defined]
    over = program.moves["over the belt"][0]  # type: ignore[attr-defined]
    scene.run(lambda: over(Execute=True), until=lambda: over.Done, timeout=1.0)
    axes = [scene.axes[a] for a in ARMS]
    set_points: list[tuple[list[float], list[float], list[float], int]] = []
    scene.runtime.observers.append(
        lambda t: set_points.append(
            (
                [a.sp_pos for a in axes],
                [a.sp_vel for a in axes],
                [a.sp_acc for a in axes],
                group.GroupErrorID,
            )
        )
    )
    line = mcl.MC_MoveLinearAbsolute(AxesGroup=group, Position=[505.0, BELT_Y, -775.0], **edge)
    stop = mcl.MC_GroupStop(AxesGroup=group, Deceleration=8000.0)
    read = mcl.MC_GroupReadActualPosition(AxesGroup=group)

    def scan() -> None:
        line(Execute=True)
        read(Enable=True)
        stop(Execute=stop.Busy or (read.Valid and read.Position[0] > 300.0))

    scene.run(scan, until=lambda: stop.Error or stop.Done, timeout=2.0)
    assert stop.Error and stop.ErrorID == ErrorID.EWorkspace
    assert group.state == mcl.GroupState.GroupErrorStop and group.GroupErrorID == 24
    scene.run(scan, timeout=0.2)
    assert line.CommandAborted  # the stop aborted it (read on its next call)
    k = next(k for k, row in enumerate(set_points) if row[3]) - 1  # the last point of the path
    last, speed, acc, _ = set_points[k]
    assert max(last) <= DELTA.theta_max  # the last point the kinematics gave
    assert max(speed) > 50.0  # deg/s: arm A2 ran fast when its point was refused
    for i, axis in enumerate(axes):
        ramp = axis.max_ramp()
        steps = [abs(b[1][i] - a[1][i]) for a, b in itertools.pairwise(set_points)]
        assert max(steps) <= ramp.deceleration * axis.servo_period * (1.0 + 1e-9), (i, max(steps))
        end = mcl.trajectory.stop(last[i], speed[i], acc[i], ramp.deceleration, ramp.jerk)
        angle = math.degrees(scene.joint_position(axis.name))
        assert angle == pytest.approx(end.end_position, abs=0.02), axis.name
        assert axis.constants is not None
        assert axis.state == mcl.AxisState.StandStill and angle < axis.constants.LimPos
    reset = mcl.MC_GroupReset(AxesGroup=group)
    scene.run(lambda: reset(Execute=True), until=lambda: reset.Done, timeout=0.1)
    assert group.state == mcl.GroupState.GroupStandby


def test_a_group_stop_while_tracking_brings_the_cup_to_rest_in_the_mcs() -> None:
    """The cup on the part, following it on the belt (0.25 m/s): MC_GroupStop (2.5 m/s², jerk
    1e5 mm/s³) brings the cup (MuJoCo's site) to rest in the MCS within the stop's distance
    from the belt's velocity; it no longer follows the part."""
    scene = scenes.load("delta_picker", trace_every=0)
    program = scenes.demo(scene)
    scene.run(program, until=lambda: program.step == "grip", timeout=20.0)
    group = program.group  # type: ignore[attr-defined]
    tool = scene.model.site(TOOL).id
    stop = mcl.MC_GroupStop(AxesGroup=group, Deceleration=2500.0, Jerk=1.0e5)
    stop(Execute=True)
    start = 1000.0 * scene.data.site_xpos[tool].copy()
    scene.run(lambda: stop(Execute=True), until=lambda: stop.Done or stop.Error, timeout=1.0)
    assert stop.Done, stop.ErrorID
    scene.run(lambda: stop(Execute=False), timeout=0.2)
    rest = 1000.0 * scene.data.site_xpos[tool].copy()
    scene.run(lambda: None, timeout=0.3)
    end = 1000.0 * scene.data.site_xpos[tool]
    speed = program.run.Velocity  # type: ignore[attr-defined]
    distance = mcl.trajectory.stop(0.0, speed, 0.0, 2500.0, 1.0e5).end_position
    print(f"stop: {np.linalg.norm(end - start):.2f} mm of {distance:.2f} mm")
    # at rest (the servo's give under the belt's drag on the gripped part; following the
    # part, the cup went on 75 mm)
    assert np.linalg.norm(end - rest) < 1.0
    assert np.linalg.norm(end - start) == pytest.approx(distance, abs=1.0)
    assert group.state == mcl.GroupState.GroupStandby
