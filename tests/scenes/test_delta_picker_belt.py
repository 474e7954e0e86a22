"""The delta picker's conveyor on the model: the belt never runs out however far it has moved, a
part rides on it at the belt's speed wherever the belt body stands, and a part that rides past
the belt's end falls off there and comes back on the infeed (the feeder).

The belt is moved in the physics alone (its slide put where wanted, its amplifier given a
constant command), so that it can stand kilometres on without its axis seeing the jump."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

import scenes
from scenes.machines.delta_picker.devices import FALLEN, SPACING, Belt, Feeder

PARTS = range(8)


class Line:
    """The machine's belt and parts in the physics [m, world]."""

    def __init__(self) -> None:
        self.scene = scenes.load("delta_picker", trace_every=0)
        self.feeder = self.scene.device("feeder", Feeder)
        self.belt = self.scene.joint("C")
        self.amplifier = int(self.scene.model.actuator(self.scene.model_name("C_amp")).id)
        self.scene.model.opt.disableactuator = 0  # every amplifier enabled

    def put_belt(self, at: float) -> None:
        """The belt body ``at`` [m] along its slide, as if it had run so far."""
        self.scene.data.qpos[self.belt.qpos_adr] = at

    def run(self, seconds: float, volts: float = 3.41) -> None:
        """Physics steps for ``seconds``, the belt's amplifier at ``volts`` (3.41 V: 0.5 m/s)."""
        self.scene.data.ctrl[self.amplifier] = volts
        self.scene.plant.step(round(seconds / 0.0005))

    def centre(self, k: int) -> np.ndarray:
        """Part ``k``'s centre [m]."""
        model, data = self.scene.model, self.scene.data
        return np.array(data.xpos[model.body(self.scene.model_name(f"part{k}")).id])

    def slide(self, k: int) -> int:
        """The qpos address of part ``k``'s x slide."""
        return int(self.scene.model.joint(self.scene.model_name(f"part{k}_x")).qposadr[0])

    def on_belt(self) -> float:
        """Where a part's centre lies on the belt [m]."""
        return self.feeder.belt_top + 0.015


@pytest.fixture
def line() -> Line:
    return Line()


@pytest.mark.parametrize("at", [0.0, 150.0, -60.0, 5000.0])
def test_parts_ride_the_belt_however_far_it_has_run(line: Line, at: float) -> None:
    """Wherever the belt body stands (5 km: 1.4 h at 1 m/s), the parts lie on the belt and move
    with it: every part's way along the belt within 0.5 mm of the belt's own over 0.2 s."""
    line.put_belt(at)
    line.run(0.1)  # the belt and the parts take up speed
    belt0 = line.belt.position
    before = [line.centre(k) for k in PARTS]
    line.run(0.2)
    moved = line.belt.position - belt0
    assert moved == pytest.approx(0.1, abs=0.002)
    for k in PARTS:
        after = line.centre(k)
        assert after[2] == pytest.approx(line.on_belt(), abs=0.001)
        assert after[0] - before[k][0] == pytest.approx(moved, abs=0.0005)


def test_the_belt_is_drawn_where_it_carries_the_parts(line: Line) -> None:
    """The drawn top run and the hidden box that carries the parts cover the same place, the
    belt 150 m on from its start and running."""
    model, data = line.scene.model, line.scene.data
    drawn = model.geom(line.scene.model_name("belt_top_run")).id
    carrier = model.geom(line.scene.model_name("belt_geom")).id
    line.put_belt(150.0)
    line.run(0.01)
    assert np.allclose(data.geom_xpos[carrier], data.geom_xpos[drawn], atol=0.001)
    assert np.allclose(model.geom_size[carrier], model.geom_size[drawn])
    assert int(model.geom_group[carrier]) >= 3  # not drawn by the viewer
    assert int(model.geom_contype[drawn]) == 0 and int(model.geom_conaffinity[drawn]) == 0


def test_a_part_past_the_belts_end_falls_off_and_is_laid_on_the_infeed_again(line: Line) -> None:
    """Part 0 put 20 mm before the belt's end, the belt at 0.5 m/s, 40 m on: it rides off the
    end, falls and is laid again before the photo eye, on the belt, as the next part of the
    infeed; no other part is taken."""
    model, data = line.scene.model, line.scene.data
    carrier = model.geom(line.scene.model_name("belt_geom")).id
    line.put_belt(40.0)
    line.run(0.05)
    end = float(data.geom_xpos[carrier][0] + model.geom_size[carrier][0])
    assert end == pytest.approx(1.5)  # the conveyor frame's end
    data.qpos[line.slide(0)] += end - 0.02 - line.centre(0)[0]
    laid, fell_at = line.feeder.laid, []
    for _ in range(200):  # 1 s
        line.run(0.005)
        centre = line.centre(0)
        if centre[2] < line.feeder.belt_top - FALLEN / 2:
            fell_at.append(centre[0])
        if line.feeder.fallen:
            break
    assert fell_at and fell_at[0] > end  # it fell past the end, and was taken
    assert line.feeder.fallen == 1
    assert line.feeder.next == [laid, *range(1, 8)] and line.feeder.laid == laid + 1
    line.run(0.05)
    centre = line.centre(0)
    assert centre[0] < line.feeder.eye_x - 0.3
    assert centre[2] == pytest.approx(line.on_belt(), abs=0.001)


def test_a_restored_state_puts_the_belt_back(line: Line) -> None:
    """A plant state saved with the belt at 0 and restored after the belt body was put 150 m
    on: the parts lie on the belt and ride it at once."""
    state = line.scene.plant.get_state()
    line.put_belt(150.0)
    line.scene.plant.set_state(state)
    line.run(0.1)
    belt0 = line.belt.position
    before = [line.centre(k) for k in PARTS]
    line.run(0.05)
    moved = line.belt.position - belt0
    assert moved > 0.02
    for k in PARTS:
        assert line.centre(k)[2] == pytest.approx(line.on_belt(), abs=0.001)
        assert line.centre(k)[0] - before[k][0] == pytest.approx(moved, abs=0.0005)


def test_a_belt_made_with_the_belt_run_on_holds_the_box_at_its_place(line: Line) -> None:
    """A Belt device built while the belt stands 2 m on puts the box where it is at C = 0."""
    model, data = line.scene.model, line.scene.data
    carrier = model.geom(line.scene.model_name("belt_geom")).id
    home = np.array(data.geom_xpos[carrier])
    line.put_belt(2.0)
    Belt(model, data, line.scene.model_name(""))  # it places the box as it is made
    mujoco.mj_kinematics(model, data)
    assert np.allclose(data.geom_xpos[carrier], home, atol=1e-9)


def put_in_tray(line: Line, k: int, x: float) -> None:
    """Part ``k`` at rest on the tray, its centre at MCS ``x`` [m]."""
    model, data = line.scene.model, line.scene.data
    joint = model.joint(line.scene.model_name(f"part{k}_x"))
    q, dof = int(joint.qposadr[0]), int(joint.dofadr[0])
    centre = line.centre(k)
    data.qpos[q] += x - centre[0]
    data.qpos[q + 1] += 0.155 - centre[1]  # the tray's top is as high as the belt's
    data.qvel[dof : dof + 6] = 0.0


def test_a_part_resting_in_the_tray_a_second_is_laid_on_the_infeed(line: Line) -> None:
    """Parts 0 and 1 put in the tray half a second on: 0.95 s later both still lie there; 1.05 s
    later both are on the belt before the eye, as the next two parts, part 0 first, a random
    spacing (at least 240 mm) behind the model's last part."""
    line.run(0.5)
    laid = line.feeder.laid
    put_in_tray(line, 0, -0.1)
    put_in_tray(line, 1, 0.1)
    line.run(0.95)
    assert line.feeder.laid == laid
    assert all(line.centre(k)[1] == pytest.approx(0.155, abs=0.002) for k in (0, 1))
    line.run(0.1)
    assert line.feeder.laid == laid + 2 and line.feeder.next[:2] == [laid, laid + 1]
    assert line.feeder.fallen == 0
    line.run(0.05)
    for k in (0, 1):
        centre = line.centre(k)
        assert centre[0] < line.feeder.eye_x - 0.3
        assert centre[2] == pytest.approx(line.on_belt(), abs=0.001)
    assert line.centre(1)[0] < line.centre(0)[0]  # laid after it: further upstream
    assert line.centre(0)[0] <= line.centre(7)[0] - SPACING[0] + 0.001


def test_parts_that_fell_together_are_all_laid_again(line: Line) -> None:
    """Parts 2 and 3 dropped off the belt's side at once: both are laid again, counted."""
    model, data = line.scene.model, line.scene.data
    laid = line.feeder.laid
    for k in (2, 3):
        q = int(model.joint(line.scene.model_name(f"part{k}_x")).qposadr[0])
        data.qpos[q + 1] += 0.5  # off the belt's side, onto the floor
    line.run(0.5)
    assert line.feeder.fallen == 2 and line.feeder.laid == laid + 2
    assert sorted(line.feeder.next[2:4]) == [laid, laid + 1]
    assert all(line.centre(k)[2] == pytest.approx(line.on_belt(), abs=0.001) for k in (2, 3))


def test_the_feeders_state_is_restored_whole(line: Line) -> None:
    """The feeder's sequence numbers, rest times, parts laid, last place and fallen count after
    a part fell and another rests in the tray, saved, changed and restored: as saved."""
    model, data = line.scene.model, line.scene.data
    q = int(model.joint(line.scene.model_name("part2_x")).qposadr[0])
    data.qpos[q + 1] += 0.5
    put_in_tray(line, 0, 0.0)
    line.run(0.5)
    feeder = line.feeder
    saved = feeder.get_state()
    before = (list(feeder.next), list(feeder.rest), feeder.laid, feeder._last, feeder.fallen)
    assert before[4] == 1 and before[1][0] > 0.0
    feeder.next, feeder.rest = [0] * 8, [-1.0] * 8
    feeder.laid, feeder._last, feeder.fallen = 0, 0.0, 0
    feeder.set_state(saved)
    assert (feeder.next, feeder.rest, feeder.laid, feeder._last, feeder.fallen) == before
