"""Where the viewer draws a robot group's PCS in the world (viewer.sim.product_frames), with a
delta group of simulated axes and a small MuJoCo model whose effector body carries the
``tool`` site: a PCS set at the tool point stands at that body, one 100 mm along its x axis
100 mm further in the world, turned with its angle and named with the axis that carries it;
a model without a tool site, or no model or data, shows none."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

import mcl
from mcl.coordinate_system import ProductFrame
from tests.helpers import make_machine
from tests.mcl.test_group import build_group
from tests.mcl.test_group_kinematics import ARMS, DELTA
from viewer.sim.product_frames import ProductFrames

EFFECTOR = (0.25, -0.5, 1.75)
"""Where the model's effector body (and its tool site) stands in the world [m]."""


def model_with(site: str) -> tuple[mujoco.MjModel, mujoco.MjData]:
    """A robot base with an effector body at :data:`EFFECTOR` carrying ``site`` (and a decoy
    site ``toolbox`` on the base), placed by mj_forward."""
    x, y, z = EFFECTOR
    model = mujoco.MjModel.from_xml_string(
        f"""<mujoco><worldbody><body name="base" pos="0 0 2"><site name="toolbox"/>
        <body name="effector" pos="{x} {y} {z - 2.0}"><geom size="0.01"/><site name="{site}"/>
        </body></body></worldbody></mujoco>"""
    )
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data


def delta_group() -> tuple[mcl.SimMachine, mcl.AxesGroup]:
    """The arms grouped with the delta kinematics at a standstill, and a belt axis ``D``."""
    machine = make_machine(ARMS + "D")
    group = build_group(machine, ARMS)
    kin = mcl.MC_SetKinTransform()
    kin(AxesGroup=group, Execute=True, KinTransform=DELTA)
    assert kin.Done
    return machine, group


def tool_point(group: mcl.AxesGroup) -> list[float]:
    """The tool point of the arms' actual positions [mm, MCS]."""
    return [float(v) for v in DELTA.forward([axis.actual for axis in group.axes])]


@pytest.mark.parametrize("site", ["tool", "robot/tool"])
def test_a_pcs_at_the_tool_point_stands_at_the_effector_and_moves_with_its_origin(
    site: str,
) -> None:
    machine, group = delta_group()
    model, data = model_with(site)
    frames = ProductFrames()
    assert frames([group], model, data) == ()  # no PCS set: none drawn
    tcp = tool_point(group)
    group.kin.frame = ProductFrame(tcp, master=machine.axes["D"])
    (view,) = frames([group], model, data)
    np.testing.assert_allclose(view.origin, EFFECTOR, atol=1e-9)
    np.testing.assert_allclose(view.x_axis, (1.0, 0.0, 0.0), atol=1e-12)
    assert (view.group, view.master) == ("G", "D")
    group.kin.frame = ProductFrame([tcp[0] + 100.0, tcp[1], tcp[2]], angle=90.0)
    (view,) = frames([group], model, data)
    np.testing.assert_allclose(view.origin, np.add(EFFECTOR, (0.1, 0.0, 0.0)), atol=1e-9)
    np.testing.assert_allclose(view.x_axis, (0.0, 1.0, 0.0), atol=1e-12)
    assert view.master == ""  # a fixed PCS
    assert math.isclose(float(np.linalg.norm(view.x_axis)), 1.0)


def test_no_pcs_without_a_tool_site_a_model_or_its_data() -> None:
    _, group = delta_group()
    group.kin.frame = ProductFrame(tool_point(group))
    frames = ProductFrames()
    assert frames([group], None, None) == ()  # before any model
    model, data = model_with("gripper")
    assert frames([group], model, data) == ()  # no tool site
    model, data = model_with("tool")
    assert frames([group], model, None) == ()
    assert len(frames([group], model, data)) == 1
    assert frames([group], None, data) == ()  # the model gone (another scene loading)


def test_each_group_with_a_pcs_is_drawn_whatever_the_groups_before_it() -> None:
    """Groups without kinematics, with a PCS that has no finite origin, or without a PCS are
    left out; a group after them with a PCS is drawn."""
    machine = make_machine("ABCEFHJKMNP")
    plain = build_group(machine, "JK")  # no kinematic transformation
    broken, bare, good = (build_group(machine, names) for names in ("ABC", "EFH", "MNP"))
    for group in (broken, bare, good):
        kin = mcl.MC_SetKinTransform()
        kin(AxesGroup=group, Execute=True, KinTransform=DELTA)
        assert kin.Done
    plain.kin.frame = ProductFrame(tool_point(good))
    broken.kin.frame = ProductFrame([math.nan, 0.0, 0.0])
    good.kin.frame = ProductFrame(tool_point(good))
    model, data = model_with("tool")
    (view,) = ProductFrames()([plain, broken, bare, good], model, data)
    np.testing.assert_allclose(view.origin, EFFECTOR, atol=1e-9)
