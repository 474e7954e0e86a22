"""The delta picker's photo eye on the model, the belt standing: parts are put where they are
wanted by their slide joints and the physics stepped. The light curtain gives one lateral
reading per pass of a part through the beam (a fresh one when the same part comes back), none
while the beam stays cut, none before the beam is cut and none for a part held above the belt;
the trigger coordinate is how far the leading edge has crossed the beam."""

from __future__ import annotations

import pytest

import scenes
from scenes.machines.delta_picker.devices import PART_LENGTH, PhotoEye


class Belt:
    """The machine's parts on the standing belt, moved by their slides [m, world]."""

    def __init__(self) -> None:
        self.scene = scenes.load("delta_picker", trace_every=0)
        self.eye = self.scene.device("eye", PhotoEye)

    def put(self, k: int, x: float, y: float, lift: float = 0.0) -> None:
        """Part ``k``'s centre to ``x``, ``y`` (its lateral offset) and ``lift`` above the
        belt, at rest; then one physics step (the eye looks before it)."""
        model, data = self.scene.model, self.scene.data
        slide = int(model.joint(self.scene.model_name(f"part{k}_x")).qposadr[0])
        dof = int(model.joint(self.scene.model_name(f"part{k}_x")).dofadr[0])
        body = model.body(self.scene.model_name(f"part{k}")).id
        centre = data.xpos[body] - data.qpos[slide : slide + 3]
        data.qpos[slide] = x - centre[0]
        data.qpos[slide + 1] = y
        data.qpos[slide + 2] = lift
        data.qvel[dof : dof + 4] = 0.0
        self.scene.plant.step()

    def front(self, k: int, x: float, y: float, lift: float = 0.0) -> None:
        """Part ``k`` with its leading edge ``x`` [m] past the beam."""
        self.put(k, self.eye.eye_x + x - 0.5 * PART_LENGTH, y, lift)

    def readings(self) -> list[float]:
        """The lateral positions measured so far [mm]."""
        return list(self.eye.lateral)


def centre_y(belt: Belt, y: float) -> float:
    """A part's lateral offset ``y`` as the curtain reports it [mm, MCS y]."""
    return 1000.0 * (belt.eye.belt_y + y)


@pytest.fixture
def belt() -> Belt:
    return Belt()


# the leading edge's way through the beam and past it [m]: the part covers it from 0 to 60 mm
PASS = [-0.010, -0.002, 0.0, 0.003, 0.020, 0.045, 0.059, 0.061, 0.100]


def test_a_part_passing_is_measured_once_when_its_edge_cuts_the_beam(belt: Belt) -> None:
    for edge in PASS:
        belt.front(0, edge, 0.012)
        # past the beam, the part no longer counts: the next one (part 1) is far before it
        coordinate = belt.eye.probe_coordinate()
        assert coordinate == pytest.approx(edge, abs=1e-4) if edge < 0.06 else coordinate < -0.1
        assert belt.readings() == ([] if edge < 0.0 else [pytest.approx(centre_y(belt, 0.012))])


def test_a_part_laid_again_at_once_is_measured_afresh(belt: Belt) -> None:
    """Part 0 passes, is laid again before the beam with another lateral offset and passes
    again, no other part between: a second reading, its new position (twice more)."""
    offsets = (0.012, -0.020, 0.005)
    for y in offsets:
        for edge in PASS:
            belt.front(0, edge, y)
    assert belt.readings() == [pytest.approx(centre_y(belt, y)) for y in offsets]


def test_no_reading_while_the_beam_stays_cut(belt: Belt) -> None:
    """The part stands in the beam (the belt stopped) for 100 steps, then creeps on within it:
    still its one reading."""
    belt.front(0, 0.010, -0.015)
    for _ in range(100):
        belt.scene.plant.step()
    for edge in (0.011, 0.030, 0.050):
        belt.front(0, edge, -0.015)
    assert belt.readings() == [pytest.approx(centre_y(belt, -0.015))]


def test_parts_one_after_the_other_are_measured_each_in_turn(belt: Belt) -> None:
    """Part 1 follows part 0 with its leading edge 10 mm behind part 0's trailing edge."""
    for edge in PASS[:-1]:
        belt.front(0, edge, 0.010)
        belt.front(1, edge - PART_LENGTH - 0.010, -0.010)
    for edge in PASS:
        belt.front(1, edge, -0.010)
    assert belt.readings() == [
        pytest.approx(centre_y(belt, 0.010)),
        pytest.approx(centre_y(belt, -0.010)),
    ]


def test_a_part_held_by_the_cup_over_the_beam_is_not_measured(belt: Belt) -> None:
    """Part 0 carried through the beam 25 mm above the belt: no reading, and the trigger
    coordinate is the nearest part on the belt's (the model's part 1 upstream)."""
    for edge in PASS:
        belt.front(0, edge, 0.0, lift=0.025)
        assert belt.eye.probe_coordinate() < -0.1
    assert belt.readings() == []


def test_a_saved_state_keeps_what_the_eye_has_seen(belt: Belt) -> None:
    """Saved with the beam cut, restored: that part is not measured again; saved with the beam
    free, restored: the part coming next is measured."""
    scene = belt.scene
    belt.front(0, 0.010, 0.008)
    cut = scene.save_state()
    for edge in PASS[4:]:
        belt.front(0, edge, 0.008)
    free = scene.save_state()
    scene.restore_state(cut)
    for edge in PASS[4:]:
        belt.front(0, edge, 0.008)
    assert belt.readings() == [pytest.approx(centre_y(belt, 0.008))]
    scene.restore_state(free)
    for edge in PASS:
        belt.front(1, edge, -0.008)
    assert belt.readings() == [
        pytest.approx(centre_y(belt, 0.008)),
        pytest.approx(centre_y(belt, -0.008)),
    ]
