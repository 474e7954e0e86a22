"""A cell of two machines in one world: composed, each machine's code in its own namespace, both
demos to done, and the zone interlock held, judged on the joints of the physics."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

import scenes
from scenes.errors import WiringError
from scenes.machines.cell import RAM_UP, ZONE_X, Demo
from scenes.machines.press.devices import CylinderDevice
from scenes.scene import MODELS


@pytest.fixture
def cell() -> scenes.Scene:
    return scenes.load("cell", start=scenes.MACHINES["cell"].demo_start, trace_every=0)


def test_the_cell_composes_both_machines_in_one_world(cell: scenes.Scene):
    assert list(cell.axes) == ["gantry/X", "gantry/Y", "gantry/Z", "press/R"]
    press = cell.machine("press")
    assert list(press.axes) == ["R"] and press.axes["R"] is cell.axes["press/R"]
    assert press.device("cylinder", CylinderDevice) is cell.devices["press/cylinder"]
    assert press.signal("pressure_A") == cell.signal("press/pressure_A")
    # the press stands beside the gantry: its frame is 2.4 m along x in the world
    assert cell.data.body("press/").xpos[0] == pytest.approx(2.4)
    assert cell.model.opt.timestep == 0.0005


def run_cell(cell: scenes.Scene, interlock: bool) -> tuple[Demo, float]:
    """The cell's demo to done; how long both machines were in the shared zone at once [s],
    read from the joints (the gantry's X beyond the zone's edge while the ram is down)."""
    demo = Demo(cell, interlock=interlock)
    x, r = cell.joint("gantry/X"), cell.joint("press/R")
    both = [0.0]

    def watch(t: float) -> None:
        if x.position > ZONE_X and r.position > RAM_UP:
            both[0] += cell.runtime.servo_period

    cell.runtime.observers.append(watch)
    cell.run(demo, until=lambda: demo.done or bool(demo.error), timeout=60.0)
    return demo, both[0]


def test_both_demos_run_to_done_and_never_share_the_zone(cell: scenes.Scene):
    demo, both = run_cell(cell, interlock=True)
    assert demo.done and not demo.error, demo.step
    assert demo.cycles >= 2  # the press went on cycling while the gantry worked
    assert demo.gantry.waited > 0.0 and demo.press.waited > 0.0  # each was held once
    assert both == 0.0
    # the gantry put its part down in the zone: X reached the place position
    assert cell.joint("gantry/X").position < ZONE_X  # and left it again (parked)


def test_without_the_interlock_the_machines_meet_in_the_zone(cell: scenes.Scene):
    """What the interlock prevents: the same demos unguarded overlap in the zone."""
    demo, both = run_cell(cell, interlock=False)
    assert demo.done and not demo.error, demo.step
    assert both > 0.5


def test_machines_that_disagree_on_the_physics_do_not_compose(tmp_path: Path):
    press = scenes.MACHINES["press"]
    text = (MODELS / press.model).read_text().replace('timestep="0.0005"', 'timestep="0.001"')
    (tmp_path / "press.xml").write_text(text)
    machines = [scenes.MACHINES["gantry"], replace(press, model=str(tmp_path / "press.xml"))]
    with pytest.raises(WiringError, match=r"press\.xml: <option timestep=\"0\.001\">: .*0\.0005"):
        scenes.Scene(machines, trace_every=0)
