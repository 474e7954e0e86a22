"""The delta picker's standard cycle on the physics (up 25 mm, across 305 mm, down 25 mm and
back, a 0.1 kg part picked and placed at each end): every pick grips the part, none is dropped,
each place leaves it where it belongs, and the corners are blended (the cup never stops on its
way; the rate is the benchmark's, tests/benchmarks/delta_picker.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mcl
import scenes
from scenes.machines.delta_picker import VacuumGripper
from scenes.machines.delta_picker.cycle import PLACES, StandardCycle, Z, prepare
from scenes.machines.delta_picker.demo import CLEAR, VACUUM_OFF, VACUUM_ON, Demo

CYCLES = 3


@pytest.fixture(scope="module")
def run() -> tuple[scenes.Scene, StandardCycle, list[tuple[float, np.ndarray, np.ndarray, bool]]]:
    """The cycle run ``CYCLES`` times; every scan's time, cup (the model's site), part 0's
    centre [mm, world] and whether the vacuum valve is open."""
    scene = scenes.load("delta_picker", trace_every=0)
    group = prepare(scene)
    program = StandardCycle(scene, group, CYCLES)
    tool = scene.model.site(scene.model_name("tool")).id
    gripper = scene.device("vacuum", VacuumGripper)
    samples: list[tuple[float, np.ndarray, np.ndarray, bool]] = []
    scene.runtime.observers.append(
        lambda t: samples.append(
            (
                t,
                1000.0 * scene.data.site_xpos[tool],
                1000.0 * gripper.part_position(0),
                gripper.on,
            )
        )
    )
    scene.run(program, until=lambda: program.done or bool(program.error), timeout=30.0)
    assert program.done and program.phase == "done" and program.error == "", (
        program.phase,
        program.error,
    )
    scene.run(lambda: None, timeout=0.1)  # the part comes to rest at its place
    return scene, program, samples


def test_every_pick_grips_the_part_and_every_place_leaves_it_there(run) -> None:
    scene, program, samples = run
    gripper = scene.device("vacuum", VacuumGripper)
    assert [g.part for g in gripper.grips] == [0] * (2 * CYCLES)
    assert gripper.lost == 0
    # the cup on the part's top face, within 0.5 mm of its centre (the part laid at the first
    # place, then where the cycle put it), at every grip
    assert all(g.error < 0.5 and abs(g.height) < 2.0 for g in gripper.grips), gripper.grips
    times = np.array([t for t, *_ in samples])
    for k in range(len(program.legs)):
        # the part released at the other place: there at the next grip, or at rest at the end
        if k + 1 < len(gripper.grips):
            part = samples[int(np.searchsorted(times, gripper.grips[k + 1].time))][2]
        else:
            part = samples[-1][2]
        x, y = PLACES[(k + 1) % 2]
        assert math.hypot(part[0] - x, part[1] - y) < 2.0, (k, part)


def test_the_cup_never_stops_between_lift_off_and_set_down(run) -> None:
    """The corners blended: from 5 mm above the place it left until 5 mm above the place it
    comes down on, the cup (the model's site) keeps moving faster than 0.2 m/s (stopping at
    a corner, it came to rest there)."""
    _, program, samples = run
    times = np.array([t for t, *_ in samples])
    cup = np.array([c for _, c, *_ in samples])
    low = float(cup[:, 2].min())
    for start, end in program.legs:
        window = (times >= start) & (times <= end)
        z, t = cup[window, 2], times[window]
        up = np.nonzero(z > low + 5.0)[0]
        assert len(up), (start, end)
        first, last = up[0], up[-1]
        path = cup[window][first : last + 1]
        speed = np.linalg.norm(np.diff(path, axis=0), axis=1) / np.diff(t[first : last + 1])
        print(f"leg {start:.3f}: slowest {speed.min():.0f} mm/s")
        assert speed.min() > 200.0


def test_the_cup_lifts_a_part_only_once_the_vacuum_holds_it(run) -> None:
    """At every grip the cup (the model's site) does not rise until the vacuum has built up
    (:data:`VACUUM_ON` after the valve opened, less a scan; the cup may still settle onto the
    part meanwhile)."""
    scene, _, samples = run
    times = np.array([t for t, *_ in samples])
    cup = np.array([c for _, c, *_ in samples])
    for grip in scene.device("vacuum", VacuumGripper).grips:
        k0 = int(np.searchsorted(times, grip.time))
        k1 = int(np.searchsorted(times, grip.time + VACUUM_ON - 0.003))
        assert cup[k1][2] - cup[k0][2] < 0.2, (grip.time, cup[k0], cup[k1])


def test_the_vacuum_is_shut_at_every_place_until_it_has_let_the_part_go(run) -> None:
    """At every place the valve closes once the cup has come down, and stays shut
    :data:`VACUUM_OFF` (to within a scan) before it opens for the next leg's grip: the cup vents and
    lets the part go; the cup does not rise meanwhile (it may still settle)."""
    _, program, samples = run
    times = np.array([t for t, *_ in samples])
    cup = np.array([c for _, c, *_ in samples])
    valve = np.array([on for *_, on in samples])
    closed = np.nonzero(valve[:-1] & ~valve[1:])[0] + 1  # first scans with the valve shut
    opened = np.nonzero(~valve[:-1] & valve[1:])[0] + 1
    assert len(closed) == len(program.legs) == 2 * CYCLES
    for k, start in enumerate(closed):
        again = opened[opened > start]
        end = again[0] if len(again) else len(times) - 1
        print(f"place {k}: valve shut {1000.0 * (times[end] - times[start]):.1f} ms")
        if k + 1 < len(closed):  # the last place: the cycle has ended, the valve stays shut
            assert times[end] - times[start] == pytest.approx(VACUUM_OFF, abs=0.0015), k
        assert cup[end][2] - cup[start][2] < 0.2, (k, cup[start], cup[end])


def test_a_move_refused_stops_the_cycle_with_its_error() -> None:
    """A move of the first leg to a place out of the robot's reach is refused: the cycle stops
    there and says which block failed with which ErrorID; no leg was completed."""
    scene = scenes.load("delta_picker", trace_every=0)
    group = prepare(scene)
    program = StandardCycle(scene, group, 1)
    across = program.moves[0][1]
    across.Position = [0.0, 2000.0, Z + CLEAR]
    scene.run(program, until=lambda: program.done or bool(program.error), timeout=2.0)
    assert across.Error and across.ErrorID
    assert program.error == f"MC_MoveLinearAbsolute ErrorID {across.ErrorID}"
    assert not program.legs and not program.done


def test_prepare_lays_part_0_at_rest_on_the_first_place() -> None:
    """Part 0, laid by :func:`prepare`, lies centred on the first place (the belt's centre
    line) to within 0.02 mm, and stays there."""
    scene = scenes.load("delta_picker", trace_every=0)
    prepare(scene)
    gripper = scene.device("vacuum", VacuumGripper)
    scene.run(lambda: None, timeout=0.05)
    laid = 1000.0 * gripper.part_position(0)
    scene.run(lambda: None, timeout=0.05)
    x, y = PLACES[0]
    assert abs(laid[0] - x) < 0.02 and abs(laid[1] - y) < 0.02, laid
    assert np.allclose(1000.0 * gripper.part_position(0), laid, atol=0.01)


def test_prepare_fails_with_the_demo_s_error() -> None:
    """An arm in another group cannot be homed: :func:`prepare` raises the error the demo
    gives, as the demo words it."""

    def sabotaged() -> scenes.Scene:
        scene = scenes.load("delta_picker", trace_every=0)
        add = mcl.MC_AddAxisToGroup(AxesGroup=mcl.AxesGroup("other"), Axis=scene.axes["A1"])
        add(Execute=True)
        assert add.Done
        return scene

    scene = sabotaged()
    demo = Demo(scene)
    scene.run(demo, until=lambda: bool(demo.error), timeout=1.0)
    assert demo.error
    with pytest.raises(RuntimeError) as raised:
        prepare(sabotaged())
    assert str(raised.value) == demo.error
