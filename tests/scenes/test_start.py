"""Start positions are checked against the physics for every machine: a start that puts bodies
into one another (a contact, a part) or past an end stop is refused with one message naming the
axis, its start and the range it may start in."""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import pytest

import scenes
from scenes.scene import MODELS, Scene

BLOCK = 0.6
"""Where the gantry's obstacle stops X in these tests [m]."""


def gantry_with_obstacle(tmp_path: Path) -> scenes.MachineDef:
    """The gantry with its obstacle moved from its parking place to block X at :data:`BLOCK`
    from the +x side (models/README.md, gantry, Obstacle)."""
    text = (MODELS / "gantry.xml").read_text()
    parked = '<body name="X_obstacle" pos="0 -0.90 0.03">'
    assert text.count(parked) == 1
    x, y, z = -0.47 + BLOCK, -0.575, 0.98  # X_obstacle_blockpos + [BLOCK, 0, 0]
    path = tmp_path / "gantry_blocked.xml"
    path.write_text(text.replace(parked, f'<body name="X_obstacle" pos="{x} {y} {z}">'))
    return replace(scenes.definition("gantry"), model=str(path))


def test_a_start_into_an_obstacle_is_refused_with_the_range_up_to_the_contact(tmp_path):
    machine = gantry_with_obstacle(tmp_path)
    with pytest.raises(ValueError) as refused:
        Scene([machine], start={"X": BLOCK + 0.01}, trace_every=0)
    text = str(refused.value)
    print(text)
    assert text.startswith("start X = 0.61 m is physically impossible: the geoms ")
    assert "interpenetrate" in text
    found = re.search(r"X may start in (\S+) … (\S+) m$", text)
    assert found is not None
    assert float(found[1]) == -0.05  # the joint's lower end stop
    assert float(found[2]) == pytest.approx(BLOCK, abs=1e-4)  # the bumper on the obstacle
    # the range is where the bodies touch: just before it, the start is taken
    scene = Scene([machine], start={"X": float(found[2]) - 1e-4}, trace_every=0)
    assert scene.data.ncon == 0 or min(c.dist for c in scene.data.contact) > -1e-6


def test_a_start_past_an_end_stop_is_refused_for_any_machine():
    with pytest.raises(ValueError, match=r"^start X = 1.2 m .* X may start in -0.05 … 1.05 m$"):
        scenes.load("gantry", start={"X": 1.2}, trace_every=0)
    with pytest.raises(ValueError, match=r"^start S = -0.1 m .* S may start in -0.05 … 1.55 m$"):
        scenes.load("flying_shear", start={"S": -0.1}, trace_every=0)
    hard_stop = r"^start X = 2 m .*hard stop; X may start in -0.01 … 1.01 m$"
    with pytest.raises(ValueError, match=hard_stop):
        scenes.load("single_axis", start={"X": 2.0})  # simulated axes: their hard stops


def test_the_demo_starts_of_every_machine_are_taken():
    for name, machine in scenes.MACHINES.items():
        scene = scenes.load(name, start=machine.demo_start, trace_every=0)
        assert scene.name == name
