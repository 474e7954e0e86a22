"""A machine's own names in a scene: the scene resolves them (a machine's code never says its
prefix), in a scene of the machine alone and in the machine's own view of a cell, which the scene
makes over the one physics, runtime and trace the machines share."""

from __future__ import annotations

from dataclasses import replace

import pytest

import mcl
import scenes
from scenes.errors import WiringError
from scenes.machines.press.devices import CylinderDevice
from scenes.namespace import Namespace
from scenes.scene import MachineScene


@pytest.fixture(scope="module")
def cell() -> scenes.Scene:
    return scenes.load("cell", start=scenes.MACHINES["cell"].demo_start, trace_every=0)


def test_a_namespace_turns_a_machines_own_names_into_the_scenes() -> None:
    alone, shared, whole = Namespace("press"), Namespace("press", shared=True), Namespace()
    assert alone.prefix == shared.prefix == "press/" and whole.prefix == ""
    assert alone.model("R_amp") == shared.model("R_amp") == "press/R_amp"
    assert alone.model("gantry/X") == shared.model("gantry/X") == whole.model("gantry/X")
    assert whole.model("gantry/X") == "gantry/X" and whole.model("X") == "X"
    assert (alone.scene("R"), shared.scene("R"), whole.scene("press/R")) == (
        "R",
        "press/R",
        "press/R",
    )
    named = {"gantry/X": 1, "press/R": 2, "press/T": 3, "ram_up": 4}
    assert list(shared.own(named).items()) == [("R", 2), ("T", 3)]
    assert whole.own(named) == named and whole.own(named) is not named
    assert alone.own({"R": 2}) == {"R": 2}


def test_a_machine_alone_names_its_joints_and_actuators_by_its_own_names() -> None:
    scene = scenes.load("rotary_cutter", trace_every=0)
    drum = scene.joint("D")
    assert scene.joint("D") is drum  # read once, kept
    assert drum.name == "rotary_cutter/D"
    assert drum.qpos_adr == int(scene.model.joint("rotary_cutter/D").qposadr[0])
    assert scene.joint("rotary_cutter/D").qpos_adr == drum.qpos_adr  # the model's name too
    assert scene.model_name("D_amp") == "rotary_cutter/D_amp"
    assert (
        scene.data.actuator(scene.model_name("D_amp")).id
        == scene.model.actuator("rotary_cutter/D_amp").id
    )
    scene.data.joint("rotary_cutter/D").qpos[0] = 0.7
    assert drum.position == 0.7  # the physics itself
    assert scene.name == "rotary_cutter" and scene.cell is None and scene.whole is scene
    assert scene.machine("rotary_cutter") is scene and scene.parts == {"rotary_cutter": scene}
    assert [m.name for m in scene.machines] == ["rotary_cutter"]
    with pytest.raises(WiringError, match=r"rotary_cutter has no joint 'Q'; joints: \['M', 'L',"):
        scene.joint("Q")


def test_in_a_cell_each_machine_sees_its_own_names_over_the_one_physics(
    cell: scenes.Scene,
) -> None:
    press = cell.machine("press")
    assert isinstance(press, MachineScene) and press is cell.machine("press")
    assert press.world is cell.world and press.whole is cell
    assert press.model is cell.model and press.data is cell.data and press.has_model
    assert (press.plant, press.runtime, press.trace) == (cell.plant, cell.runtime, cell.trace)
    assert press.name == "press" and press.cell is None and press.machines == [cell.machines[1]]
    assert press.axes == {"R": cell.axes["press/R"]} and press.scales == {"R": 1000.0}
    assert press.devices == {"cylinder": cell.devices["press/cylinder"]}
    assert list(press.signals) == list(scenes.MACHINES["press"].signals)
    assert press.modules == [m for m in cell.modules if cell.axes["press/R"] in m.axes]
    assert len(press.modules) == 1 and len(cell.modules) == 2
    assert press.joint("R").name == "press/R" and press.model_name("R_valve") == "press/R_valve"
    cell.data.joint("press/R").qpos[0] = 0.123
    assert press.joint("R").position == 0.123 == cell.joint("press/R").position
    assert press.joint_position("R") == 0.123
    assert press.parts == {"press": press}
    with pytest.raises(WiringError, match=r"press has no joint 'X'; joints: \['R'\]"):
        press.joint("X")
    with pytest.raises(KeyError, match=r"no machine 'gantry'.*\['press'\]"):
        press.machine("gantry")
    gantry = cell.machine("gantry")
    assert list(gantry.axes) == ["X", "Y", "Z"] and gantry.devices == {}
    assert all(gantry.axes[a] is cell.axes[f"gantry/{a}"] for a in "XYZ")
    assert gantry.signals == {} and gantry.joint("X").name == "gantry/X"


def test_the_whole_cell_names_everything_by_the_scenes_names(cell: scenes.Scene) -> None:
    assert cell.name == "cell" and cell.cell is scenes.MACHINES["cell"] and cell.whole is cell
    assert [m.name for m in cell.machines] == ["gantry", "press"]
    assert list(cell.parts) == ["gantry", "press"]
    assert cell.model_name("X") == "X" and cell.model_name("gantry/X") == "gantry/X"
    with pytest.raises(WiringError, match=r"cell has no joint 'X'; joints: \['gantry/X', "):
        cell.joint("X")  # several machines: whose X?
    assert list(cell.signals)[-2:] == ["gantry_in_zone", "ram_up"]
    assert cell.signal("ram_up") == float(cell.joint("press/R").position < 0.020)
    cylinder = cell.machine("press").device("cylinder", CylinderDevice)
    assert cell.signal("press/valve") == cylinder.hydraulics.spool
    assert cell.machine("press").signal("valve") == cylinder.hydraulics.spool
    with pytest.raises(KeyError, match="no signal 'valve'"):
        cell.signal("valve")


def test_what_belongs_to_the_whole_cell_is_done_on_it(cell: scenes.Scene) -> None:
    press = cell.machine("press")
    assert press.faults is cell.faults
    assert "press/R" in cell.faults.channels
    with pytest.raises(mcl.StateError, match="machine press shares its physics"):
        press.save_state()
    with pytest.raises(mcl.StateError, match="restore the whole scene"):
        press.restore_state(cell.save_state())


def test_a_cell_starts_its_demo_where_its_parts_start_theirs() -> None:
    cell = scenes.MACHINES["cell"]
    assert cell.demo_start == {
        **{f"gantry/{a}": q for a, q in scenes.MACHINES["gantry"].demo_start.items()},
        "press/R": scenes.MACHINES["press"].demo_start["R"],
    }
    assert replace(cell, demo_start={"press/R": 0.05}).demo_start == {"press/R": 0.05}
    assert list(cell.scene_axes) == ["gantry/X", "gantry/Y", "gantry/Z", "press/R"]
    assert cell.homing == {
        **{f"gantry/{a}": r for a, r in scenes.MACHINES["gantry"].homing.items()},
        "press/R": scenes.MACHINES["press"].homing["R"],
    }
