"""The flying shear: strip line, measuring wheel, carriage geared in with MC_GearInPos, knife.

Every figure is measured from the physics: the strip joint M is the truth of every length, a cut
is where the knife edge sat on the strip when the blade came down on it.
"""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

import mcl
import scenes
from scenes.machines import flying_shear as fs
from scenes.plant.mujoco import MujocoPlant
from scenes.scene import Scene

P = f"{fs.MACHINE.name}/"
"""The prefix of the machine's names in the model of its scene."""


def load(ideal: bool = False) -> Scene:
    """The flying shear; ``ideal``: a perfect measuring wheel on a rigid strip."""
    scene = scenes.load("flying_shear", start=fs.MACHINE.demo_start, trace_every=0)
    if ideal:
        wheel(scene).ideal()
    return scene


def wheel(scene: Scene) -> fs.MeasuringWheel:
    return scene.device("wheel", fs.MeasuringWheel)


def cut(job: fs.CutJob, slip: float | None = None, ideal: bool = False) -> fs.Demo:
    """Run the demo with ``job`` to its end or its error (``ideal``: a perfect wheel; ``slip``:
    the wheel's constant slip instead of the model's)."""
    scene = load(ideal)
    if slip is not None:
        wheel(scene).slip = slip
    demo = fs.Demo(scene, job)
    scene.run(demo, until=lambda: demo.done or bool(demo.error), timeout=60.0)
    return demo


def strip_speed(scene: Scene) -> float:
    return float(scene.data.joint(f"{P}M").qvel[0])


def line_up(scene: Scene, speed: float = 1000.0) -> mcl.MC_MoveVelocity:
    """Power the line and bring it to ``speed`` [mm/s]; returns the block (call it on)."""
    power = mcl.MC_Power(Axis=scene.axes["L"], Enable=True)
    line = mcl.MC_MoveVelocity(Axis=scene.axes["L"], Velocity=speed, Acceleration=1000.0)

    def program() -> None:
        power()
        line(Execute=power.Status)

    scene.run(program, until=lambda: line.InVelocity, timeout=5.0)
    scene.run(program, timeout=0.5)
    return line


# ------------------------------------------------------------------------------ model
def test_the_model_matches_its_machine_definition_and_the_switch_formula():
    scene = load()
    model, data = scene.model, scene.data
    assert float(model.numeric(f"{P}L_radius").data[0]) == pytest.approx(fs.ROLL_RADIUS)
    assert float(model.numeric(f"{P}W_radius").data[0]) == pytest.approx(fs.WHEEL_RADIUS)
    assert scene.axes["W"].config.resolution == pytest.approx(0.025)  # 250 mm / 10 000
    assert not scene.axes["W"].has_drive
    # S switches: the README formula from the sites at a few coordinates
    joint = model.joint(f"{P}S")
    for q, expected in ((-0.006, (True, False, True)), (0.5, (False, False, False))):
        data.qpos[joint.qposadr[0]] = q
        mujoco.mj_forward(model, data)
        states = []
        for kind in ("lim_neg", "lim_pos", "ref"):
            e = data.xaxis[joint.id]
            d = (data.site_xpos[model.site(f"{P}S_{kind}_cam").id]
                 - data.site_xpos[model.site(f"{P}S_{kind}").id]) @ e  # fmt: skip
            lo, hi = model.numeric(f"{P}S_{kind}_window").data
            states.append(bool(lo <= d <= hi))
        assert tuple(states) == expected, q
    # the blade's edge reaches the strip's top face at K_contact
    data.qpos[model.joint(f"{P}K").qposadr[0]] = float(model.numeric(f"{P}K_contact").data[0])
    mujoco.mj_forward(model, data)
    strip = model.geom(f"{P}strip_geom")
    top = data.geom_xpos[strip.id][2] + strip.size[2]
    assert data.site_xpos[model.site(f"{P}knife_edge").id][2] == pytest.approx(top, abs=1e-6)


# ------------------------------------------------------------------------------ line, wheel
def test_the_eccentric_roll_ripples_the_strip_speed_at_the_roll_frequency():
    scene = load()
    line = line_up(scene)
    speeds: list[float] = []
    scene.runtime.observers.append(lambda t: speeds.append(strip_speed(scene)))
    scene.run(line, timeout=1.0)
    v = np.array(speeds)
    ripple = (v.max() - v.min()) / 2.0 / v.mean()
    assert ripple == pytest.approx(0.01, abs=0.0015)  # ±1 %
    crossings = np.count_nonzero(np.diff(np.sign(v - v.mean())) != 0)
    assert crossings == pytest.approx(4, abs=1)  # 2 Hz: two periods in 1 s
    ripple_device = scene.devices["ripple"]
    assert isinstance(ripple_device, fs.EccentricRoll)
    ripple_device.eccentricity = 0.02  # adjustable while running
    speeds.clear()
    scene.run(line, timeout=1.0)
    v = np.array(speeds)
    assert (v.max() - v.min()) / 2.0 / v.mean() == pytest.approx(0.02, abs=0.003)


def test_slip_belongs_to_the_wheel_not_to_the_strip():
    scene = load(ideal=True)
    line = line_up(scene)
    wheel(scene).slip = -0.005
    scene.run(line, timeout=0.01)
    W, m = scene.axes["W"], scene.data.joint(f"{P}M").qpos
    w0, m0 = W.POS, float(m[0])
    scene.run(line, timeout=1.0)
    travel = (float(m[0]) - m0) * 1000.0
    assert travel == pytest.approx(1000.0, rel=0.02)  # the strip runs as driven
    assert W.POS - w0 == pytest.approx(0.995 * travel, abs=3 * 0.025)


def wheel_against_strip(scene: Scene, line: mcl.MC_MoveVelocity, seconds: float):
    """Run ``seconds`` [s]; per servo instant the strip's travel and the wheel's reading minus
    it, both since the first instant [mm] (the count is read once per servo period)."""
    W, m = scene.axes["W"], scene.data.joint(f"{P}M").qpos
    rows: list[tuple[float, float]] = []

    def observe(t: float) -> None:
        rows.append((float(m[0]) * 1000.0, W.POS))

    scene.runtime.observers.append(observe)
    scene.run(line, timeout=seconds)
    scene.runtime.observers.remove(observe)
    strip, reading = np.array(rows).T
    travel = strip - strip[0]
    return np.column_stack([travel, reading - reading[0] - travel])


def test_each_error_of_the_wheel_shows_in_its_reading_against_the_strip():
    """From the physics (the strip joint M against the wheel's count), one error source at a
    time at 60 m/min: the rolling radius, the speed-dependent slip and the strip's stretch
    scale the reading, the runout adds ±runout once per wheel turn, a lift-off loses
    ½·(drag·r/J)·t² each time."""
    scene = load(ideal=True)
    line = line_up(scene)
    w = wheel(scene)
    count = 0.025
    base = wheel_against_strip(scene, line, 0.5)
    assert np.abs(base[:, 1]).max() <= 2 * count  # ideal: the strip's travel, to two counts
    for name, value, scale in (
        ("diameter", 0.002, 1.0 / 1.002),
        ("slip_per_speed", -0.002, 0.998),  # at 1 m/s
        ("tension", 0.01 * w.stiffness, 1.01),
    ):
        setattr(w, name, value)
        rows = wheel_against_strip(scene, line, 1.0)
        setattr(w, name, 0.0)
        travel, error = rows[-1]
        assert travel + error == pytest.approx(scale * travel, abs=3 * count), name
    w.runout = 0.0001
    rows = wheel_against_strip(scene, line, 1.0)  # four wheel turns
    w.runout = 0.0
    assert np.ptp(rows[:, 1]) == pytest.approx(2 * 0.1, abs=2 * count)
    w.liftoff_rate, w.liftoff_time = 4.0, 0.015
    before = w.liftoffs
    rows = wheel_against_strip(scene, line, 1.0)
    w.liftoff_rate = 0.0
    lifts = w.liftoffs - before
    loss = 0.5 * w.drag_torque * w.radius / w.inertia * w.liftoff_time**2 * 1000.0  # [mm]
    assert lifts >= 2
    assert -rows[-1, 1] == pytest.approx(lifts * loss, rel=0.25, abs=2 * count)


def test_a_real_wheel_holds_tenths_once_the_cut_length_correction_learned_its_scale():
    """The model's wheel (its errors on): without correction every piece is long by the
    wheel's scale error, scattered by lift-offs and random slip; with the correction (the
    run-out table's gauge), the first piece is as long, the next within ±0.3 mm."""
    scene = load()
    w = wheel(scene)
    scale = (1.0 + w.slip + w.slip_per_speed * 1.0) * (1.0 + w.stretch) / (1.0 + w.diameter)
    long = cut(fs.CutJob(cuts=9, correction=False))
    assert long.done, long.error
    errors = np.array(long.errors())
    # long by the scale error (2.10 mm), plus the lift-offs' lost travel (0.19 mm each)
    assert errors.mean() == pytest.approx(1500.0 * (1.0 / scale - 1.0), abs=0.3)
    assert errors.std() > 0.03  # the random sources scatter the pieces
    corrected = cut(fs.CutJob(cuts=9))
    assert corrected.done, corrected.error
    first, *rest = corrected.errors()
    assert first == pytest.approx(long.errors()[0], abs=0.05)
    # a lift-off in the piece loses 0.19 mm, the four-piece average of the scale carries those of
    # the pieces before: ±0.3 mm (the physics gives −0.26 … +0.20 over 20 pieces)
    assert max(abs(e) for e in rest) <= 0.3, rest
    assert abs(sum(rest) / len(rest)) <= 0.1
    assert corrected.scale == pytest.approx(scale, abs=2e-4)


# ------------------------------------------------------------------------------ knife
def test_a_knife_dropped_on_the_running_strip_drags_the_standing_carriage_and_brakes_the_line():
    scene = load()
    line = line_up(scene)
    S = scene.axes["S"]
    power = mcl.MC_Power(Axis=S, Enable=True)
    down = mcl.MC_WriteDigitalOutput(Axis=S, OutputNumber=0, Value=True)
    knife = scene.devices["knife"]
    assert isinstance(knife, fs.KnifeCylinder)
    drags: list[float] = []

    def program() -> None:
        line()
        power()
        down(Execute=power.Status)
        drags.append(knife.drag)

    scene.run(program, until=lambda: power.Status, timeout=1.0)
    carriage = float(scene.data.joint(f"{P}S").qpos[0])
    before = strip_speed(scene)
    scene.run(program, timeout=0.15)
    limit = knife.mu * (knife.force + knife.weight)
    assert min(drags) == pytest.approx(-limit, rel=0.02)  # the blade slips on the strip
    assert float(scene.data.joint(f"{P}S").qpos[0]) - carriage > 0.005  # dragged along
    assert strip_speed(scene) < 0.9 * before  # the line is braked


# ------------------------------------------------------------------------------ cutting
def test_cut_to_length_at_60_m_min_from_the_physics():
    """The controller's own precision: a perfect wheel on a rigid strip; what is left is the
    line-speed ripple and the wheel's counts (0.025 mm)."""
    demo = cut(fs.CutJob(cuts=7), ideal=True)
    assert demo.done, demo.error
    errors = demo.errors()
    assert len(errors) == 6
    assert all(abs(e) <= 0.1 for e in errors), errors
    assert abs(sum(errors) / len(errors)) <= 0.05
    for c in demo.recorder.cuts:
        assert c.speed_mismatch < 0.005  # carriage and strip at the same speed
        assert c.slide < 0.5  # the blade stays where it came down [mm]
        assert 0.0 < c.drag < 500.0  # and hardly pulls on the strip [N]
        assert c.contact > 0.02
    # the table the viewer shows: one row per cut, the first (the head cut) without a length
    rows = demo.results
    assert [row["cut"] for row in rows] == list(range(7))
    assert rows[0]["length [mm]"] is None
    assert [row["error [mm]"] for row in rows[1:]] == pytest.approx(errors)


def test_the_knife_goes_down_only_in_sync():
    scene = load()
    demo = fs.Demo(scene, fs.CutJob(cuts=2))
    outputs, S = scene.io("S").outputs, scene.axes["S"]
    edges: list[tuple[bool, float]] = []  # at each rising edge: locked, carriage/strip speed

    def program() -> None:
        was = outputs[0]
        demo()
        if outputs[0] and not was:
            locked = demo.gear.Active and S.state == mcl.AxisState.SynchronizedMotion
            edges.append((locked, float(scene.data.joint(f"{P}S").qvel[0]) / strip_speed(scene)))

    scene.run(program, until=lambda: demo.done or bool(demo.error), timeout=20.0)
    assert demo.done and len(demo.recorder.cuts) == 2 and len(edges) == 2
    for locked, ratio in edges:
        assert locked and ratio == pytest.approx(1.0, abs=0.005)


def test_sync_starts_at_the_start_distance_and_the_carriage_never_backs_up():
    """At PLC-scan resolution: StartSync once the master passed MasterSyncPosition −
    MasterStartDistance, InSync (Zeroing 1: the coordinate reads 0 there) when it reached
    MasterSyncPosition; in between the carriage (physics) never moves back."""
    scene = load()
    job = fs.CutJob(cuts=3)
    demo = fs.Demo(scene, job)
    W, gear = scene.axes["W"], demo.gear
    scan = 1000.0 * (scene.runtime.plc_period + scene.runtime.servo_period)  # [mm] at 1 m/s
    starts: list[float] = []
    syncs: list[float] = []
    syncing = [False]
    slowest = [0.0]

    def program() -> None:
        was_start, was_sync = gear.StartSync, gear.InSync
        demo()
        if gear.StartSync and not was_start:
            starts.append(W.POS - (gear.MasterSyncPosition - gear.MasterStartDistance))
        if gear.InSync and not was_sync:
            syncs.append(W.POS)
        syncing[0] = gear.StartSync

    def observe(t: float) -> None:
        if syncing[0]:
            slowest[0] = min(slowest[0], float(scene.data.joint(f"{P}S").qvel[0]))

    scene.runtime.observers.append(observe)
    scene.run(program, until=lambda: demo.done or bool(demo.error), timeout=30.0)
    assert demo.done, demo.error
    assert len(starts) == len(syncs) == 3
    assert all(0.0 <= d <= scan + 0.1 for d in starts), starts
    assert all(0.0 <= m <= scan + 0.1 for m in syncs), syncs
    assert slowest[0] > -0.001  # [m/s]


def test_slip_makes_length_cuts_long_and_the_mark_register_cuts_at_the_mark():
    long = cut(fs.CutJob(cuts=4, correction=False), slip=-0.005, ideal=True)
    assert long.done, long.error
    for c in long.recorder.cuts[1:]:
        assert c.length == pytest.approx(1500.0 / 0.995, abs=0.5)  # 0.5 % long
    mark = cut(fs.CutJob(cuts=4, mode="mark"), slip=-0.005, ideal=True)
    assert mark.done, mark.error
    assert mark.scale == pytest.approx(0.995, abs=0.0002)
    assert all(abs(c.mark) <= 0.5 for c in mark.recorder.cuts), [c.mark for c in mark.recorder.cuts]


def zeroing_errors(delay: float) -> tuple[list[float], list[float]]:
    """Mark mode without register, a perfect wheel: the zeroing errors
    (:class:`fs.ZeroingRecorder`) [mm] and the cuts' distances from their marks [mm]."""
    scene = load(ideal=True)
    demo = fs.Demo(scene, fs.CutJob(cuts=3, mode="mark", register=False, delay=delay))
    zeroing = fs.ZeroingRecorder(scene)
    scene.runtime.observers.append(zeroing)
    scene.run(demo, until=lambda: demo.done or bool(demo.error), timeout=30.0)
    assert demo.done, demo.error
    return zeroing.errors, [c.mark for c in demo.recorder.cuts]


def test_the_probe_delay_compensated_zeroes_the_master_at_the_mark():
    errors, marks = zeroing_errors(delay=1.0)
    assert len(errors) == 3
    assert all(abs(e) <= 2 * 0.025 for e in errors), errors  # at most two counts
    assert all(abs(e) <= 0.5 for e in marks), marks
    late, late_marks = zeroing_errors(delay=0.0)
    # without Delay the zero is where the strip was when the delayed edge came: the coordinate
    # reads line speed × sensor delay short, and the cut lands that much upstream of the mark
    shift = 1000.0 * fs.SENSOR_DELAY  # [mm] at 1000 mm/s
    for e, e0 in zip(late, errors, strict=True):
        assert e - e0 == pytest.approx(-shift, abs=0.1)
    for e, e0 in zip(late_marks, marks, strict=True):
        assert e - e0 == pytest.approx(shift, abs=0.15)


@pytest.mark.parametrize(("factor", "followed"), [(0.9, True), (1.1, True), (1.5, False)])
def test_a_master_speed_change_after_start_sync_is_followed_or_refused(
    factor: float, followed: bool
):
    """Slower: the plan follows the master's progress; 10 % faster: a new plan; either way the
    piece is right. 50 % faster: the sync cannot be reached in time, ESyncUnreachable, the
    carriage stops, no knife: never a cut at a wrong place. A perfect wheel (the
    controller's own behaviour)."""
    scene = load(ideal=True)
    demo = fs.Demo(scene, fs.CutJob(cuts=3))
    change = mcl.MC_MoveVelocity(
        Axis=scene.axes["L"], Velocity=1000.0 * factor, Acceleration=2000.0
    )
    started = [False]

    def program() -> None:
        demo()
        started[0] = started[0] or (demo.cut == 2 and demo.gear.StartSync)
        change(Execute=started[0])

    scene.run(program, until=lambda: demo.done or bool(demo.error), timeout=30.0)
    assert started[0]
    if followed:
        assert demo.done, demo.error
        assert demo.recorder.cuts[1].length == pytest.approx(1500.0, abs=0.5)
    else:
        assert demo.gear.Error and demo.gear.ErrorID == mcl.ErrorID.ESyncUnreachable
        assert scene.axes["S"].state == mcl.AxisState.ErrorStop
        assert len(demo.recorder.cuts) == 1  # no cut at a wrong place
        assert not scene.io("S").outputs[0]


def test_the_devices_belong_to_the_plant_state():
    scene = load()
    line_up(scene)
    plant = scene.plant
    assert isinstance(plant, MujocoPlant)
    start = plant.get_state()
    scene.io("S").outputs[0] = True

    def run() -> np.ndarray:
        rows = []
        for _ in range(150):
            plant.step(2)
            rows.append(scene.data.qpos.copy())
        return np.array(rows)

    first = run()
    plant.set_state(start)
    assert np.array_equal(first, run())


@pytest.mark.parametrize("ramp", [500.0, 1500.0, 2000.0])
def test_a_line_that_changes_speed_while_the_knife_is_down_is_followed(ramp: float):
    """The line slowed by 5 % at ``ramp`` [mm/s²] as soon as InSync rises: the knife comes down
    while the strip decelerates. The carriage's joint follows the strip's joint within 1 %
    while the blade is on the strip, and the blade hardly pulls on it (from the physics). A
    perfect wheel: the gearing's own following (a wheel's lift-off during the cut would add
    its own dip)."""
    scene = load(ideal=True)
    demo = fs.Demo(scene, fs.CutJob(cuts=3))
    change = mcl.MC_MoveVelocity(
        Axis=scene.axes["L"], Velocity=950.0, Acceleration=ramp, Deceleration=ramp
    )
    started = [False]
    later: list[float] = []  # the strip speed when the next cut begins [m/s]

    def program() -> None:
        demo()
        started[0] = started[0] or (demo.cut == 2 and demo.gear.InSync)
        change(Execute=started[0])
        if demo.cut == 3 and not later:
            later.append(strip_speed(scene))

    scene.run(program, until=lambda: demo.done or bool(demo.error), timeout=30.0)
    assert demo.done, demo.error
    assert later[0] == pytest.approx(0.95, rel=0.015)  # the line did slow down by 5 %
    cut = demo.recorder.cuts[1]  # the cut made while the line changed speed
    assert cut.speed_mismatch < 0.01, cut.speed_mismatch
    assert cut.drag < 200.0, cut.drag
