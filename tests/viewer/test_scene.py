"""Tests of viewer.view3d.model_scene: a MuJoCo model becomes viser scene nodes that follow the
bodies."""

from __future__ import annotations

from collections.abc import Callable

import mujoco
import numpy as np
import pytest
import viser
import viser.infra

from scenes.machines import gantry
from scenes.scene import model_path
from viewer.view3d.model_scene import ModelScene, capsule_mesh
from viewer.view3d.overlays import (
    CONTACT_FIELDS,
    MAX_CONSTRAINT_FORCES,
    MAX_CONTACTS,
    ContactOverlay,
    GhostAxis,
    SetPointGhost,
    constraint_forces,
    contact_forces,
    tendon_spring_forces,
)

# Every geom type, a material, hidden geoms, static / jointed / free / mocap bodies.
MJCF = """
<mujoco model="viewer_scene_test">
  <compiler angle="radian" autolimits="true"/>
  <option timestep="0.001" gravity="0 0 0">
    <flag contact="disable"/>
  </option>
  <asset>
    <material name="steel" rgba="0.2 0.4 0.8 1"/>
    <mesh name="wedge" vertex="0 0 0  0.2 0 0  0 0.1 0  0 0 0.05"/>
  </asset>
  <worldbody>
    <geom name="floor" type="plane" size="1 1 0.1" rgba="0.8 0.8 0.8 1"/>
    <geom name="floor_inf" type="plane" size="0 0 0.5" pos="0 0 -1"/>
    <geom name="hidden_collision" type="box" size="0.1 0.1 0.1" group="3"/>
    <body name="frame" pos="0 0 0.5">
      <geom name="frame_beam" type="box" size="0.5 0.05 0.05" material="steel"/>
      <body name="bracket" pos="0.5 0 0" euler="0 0 0.3">
        <geom name="bracket_box" type="box" size="0.02 0.02 0.02"/>
      </body>
      <body name="carriage" pos="0 0 0.1">
        <joint name="slide_x" type="slide" axis="1 0 0" range="-0.4 0.4"/>
        <geom name="carriage_box" type="box" size="0.05 0.05 0.05" rgba="1 0.5 0 1"/>
        <geom name="cam" type="cylinder" size="0.01 0.03" pos="0.05 0 0" euler="0 1.5708 0"/>
        <body name="arm" pos="0 0 0.1">
          <joint name="hinge_y" type="hinge" axis="0 1 0"/>
          <geom name="arm_capsule" type="capsule" size="0.02 0.1" pos="0 0 0.1"/>
          <geom name="arm_tint" type="sphere" size="0.01" material="steel" rgba="0 1 0 1"/>
          <geom name="arm_invisible" type="sphere" size="0.01" rgba="1 1 1 0"/>
          <body name="tool" pos="0 0 0.2">
            <geom name="tool_ellipsoid" type="ellipsoid" size="0.03 0.02 0.01"/>
            <geom name="tool_mesh" type="mesh" mesh="wedge" pos="0.01 0 0" euler="0.1 0.2 0.3"/>
          </body>
        </body>
      </body>
    </body>
    <body name="ball" pos="0.3 0.2 1">
      <freejoint name="ball_free"/>
      <geom name="ball_geom" type="sphere" size="0.05"/>
    </body>
    <body name="target" mocap="true" pos="-0.5 0 0.3">
      <geom name="target_geom" type="sphere" size="0.02" contype="0" conaffinity="0"/>
      <body name="target_marker" pos="0 0 0.05">
        <geom name="target_marker_geom" type="box" size="0.01 0.01 0.01"
              contype="0" conaffinity="0"/>
      </body>
    </body>
  </worldbody>
  <actuator>
    <motor name="x_motor" joint="slide_x" gear="1"/>
    <motor name="arm_motor" joint="hinge_y" gear="1"/>
  </actuator>
</mujoco>
"""

MOVING_BODIES = {"carriage", "arm", "tool", "ball", "target", "target_marker"}
STATIC_BODIES = {"world", "frame", "bracket"}


@pytest.fixture
def model() -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_string(MJCF)


@pytest.fixture
def sent(monkeypatch: pytest.MonkeyPatch) -> list[viser.infra.Message]:
    """Every message the viser server queues for its clients from now on."""
    messages: list[viser.infra.Message] = []
    original: Callable[[viser.infra.WebsockServer, viser.infra.Message], None] = (
        viser.infra.WebsockServer.queue_message
    )

    def spy(self: viser.infra.WebsockServer, message: viser.infra.Message) -> None:
        messages.append(message)
        original(self, message)

    monkeypatch.setattr(viser.infra.WebsockServer, "queue_message", spy)
    return messages


def body_name(model: mujoco.MjModel, b: int) -> str:
    return mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, b)


def test_every_visible_geom_gets_a_node_of_its_type(
    server: viser.ViserServer, model: mujoco.MjModel
) -> None:
    scene = ModelScene(model, server, prefix="/test")
    expected = {
        "floor": viser.BoxHandle,
        "floor_inf": viser.BoxHandle,
        "frame_beam": viser.BoxHandle,
        "bracket_box": viser.BoxHandle,
        "carriage_box": viser.BoxHandle,
        "cam": viser.CylinderHandle,
        "arm_capsule": viser.MeshHandle,
        "arm_tint": viser.IcosphereHandle,
        "tool_ellipsoid": viser.IcosphereHandle,
        "tool_mesh": viser.MeshHandle,
        "ball_geom": viser.IcosphereHandle,
        "target_geom": viser.IcosphereHandle,
        "target_marker_geom": viser.BoxHandle,
    }
    assert {name: type(h) for name, h in scene.geom_handles.items()} == expected
    assert scene.skipped_geoms == []
    for name in expected:
        assert scene.geom_handle(name).name.startswith("/test/")
    with pytest.raises(KeyError, match="group 3"):
        scene.geom_handle("hidden_collision")
    with pytest.raises(KeyError, match="alpha 0"):
        scene.geom_handle("arm_invisible")
    with pytest.raises(KeyError, match="no geom of that name"):
        scene.geom_handle("nope")


def test_geom_shapes_and_colors_follow_the_model(
    server: viser.ViserServer, model: mujoco.MjModel
) -> None:
    scene = ModelScene(model, server)
    h = scene.geom_handles

    cam = h["cam"]
    assert isinstance(cam, viser.CylinderHandle)
    assert (cam.radius, cam.height) == pytest.approx((0.01, 0.06))
    box = h["carriage_box"]
    assert isinstance(box, viser.BoxHandle)
    assert box.dimensions == pytest.approx((0.1, 0.1, 0.1))
    ellipsoid = h["tool_ellipsoid"]
    assert isinstance(ellipsoid, viser.IcosphereHandle)
    assert ellipsoid.radius == 1.0
    assert ellipsoid.scale == pytest.approx((0.03, 0.02, 0.01))
    mesh = h["tool_mesh"]
    assert isinstance(mesh, viser.MeshHandle)
    mesh_id = model.geom_dataid[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "tool_mesh")]
    v0, nv = model.mesh_vertadr[mesh_id], model.mesh_vertnum[mesh_id]
    np.testing.assert_allclose(mesh.vertices, model.mesh_vert[v0 : v0 + nv], atol=1e-7)
    assert mesh.faces.shape == (model.mesh_facenum[mesh_id], 3)
    capsule = h["arm_capsule"]
    assert isinstance(capsule, viser.MeshHandle)
    extent = capsule.vertices.max(axis=0) - capsule.vertices.min(axis=0)
    assert extent == pytest.approx((0.04, 0.04, 0.24), abs=1e-6)  # axis along local z

    # Geom nodes sit in body-local coordinates.
    g = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "tool_mesh")
    np.testing.assert_allclose(mesh.position, model.geom_pos[g])
    np.testing.assert_allclose(mesh.wxyz, model.geom_quat[g])

    # Own rgba, material rgba (geom rgba left at default), own rgba overriding a material.
    assert box.color == (255, 128, 0)
    assert h["frame_beam"].color == (51, 102, 204)
    assert h["arm_tint"].color == (0, 255, 0)


def test_capsule_mesh_is_closed_and_faces_point_outwards() -> None:
    radius, half = 0.02, 0.1
    vertices, faces = capsule_mesh(radius, half)
    tri = vertices[faces]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    centroid = tri.mean(axis=1)
    axis_point = np.zeros_like(centroid)
    axis_point[:, 2] = np.clip(centroid[:, 2], -half, half)
    assert np.all(np.einsum("ij,ij->i", normals, centroid - axis_point) > 0.0)
    # Closed surface: every edge is shared by exactly two faces, in opposite directions.
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    directed = {tuple(e) for e in edges.tolist()}
    assert len(directed) == len(edges)
    assert all((b, a) in directed for a, b in directed)
    volume = np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum() / 6.0
    exact = np.pi * radius**2 * 2 * half + 4.0 / 3.0 * np.pi * radius**3
    assert volume == pytest.approx(exact, rel=0.03)


def test_update_moves_frames_of_moving_bodies_only(
    server: viser.ViserServer, model: mujoco.MjModel
) -> None:
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    scene = ModelScene(model, server, data=data)
    moving = {body_name(model, b) for b in scene.moving_body_ids}
    assert moving == MOVING_BODIES
    assert set(scene.body_handles) == MOVING_BODIES | STATIC_BODIES
    static_before = {n: scene.body_handles[n].position.copy() for n in STATIC_BODIES}

    data.ctrl[:] = [5.0, 0.01]
    data.qvel[2:8] = [0.1, 0.0, 0.2, 1.0, 0.0, 0.5]  # ball_free: linear [m/s], angular [rad/s]
    data.mocap_pos[0] = [-0.4, 0.1, 0.35]
    data.mocap_quat[0] = [np.cos(0.2), 0.0, 0.0, np.sin(0.2)]
    for _ in range(300):
        mujoco.mj_step(model, data)
    scene.update(data)

    for name in MOVING_BODIES:
        b = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, name)
        frame = scene.body_handles[name]
        np.testing.assert_allclose(frame.position, data.xpos[b], atol=1e-9, err_msg=name)
        np.testing.assert_allclose(frame.wxyz, data.xquat[b], atol=1e-9, err_msg=name)
    assert np.abs(data.qpos[:2]).min() > 1e-2  # the joints really moved
    for name, before in static_before.items():
        np.testing.assert_array_equal(scene.body_handles[name].position, before)

    # Frame pose composed with the geom's local pose is where MuJoCo has the geom.
    for geom in ("arm_capsule", "tool_mesh", "target_marker_geom", "bracket_box"):
        g = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, geom)
        frame = scene.body_handles[body_name(model, model.geom_bodyid[g])]
        node = scene.geom_handle(geom)
        world_pos = np.zeros(3)
        world_quat = np.zeros(4)
        mujoco.mju_mulPose(
            world_pos, world_quat, frame.position, frame.wxyz, node.position, node.wxyz
        )
        np.testing.assert_allclose(world_pos, data.geom_xpos[g], atol=1e-7, err_msg=geom)
        world_mat = np.zeros(9)
        mujoco.mju_quat2Mat(world_mat, world_quat)
        np.testing.assert_allclose(world_mat, data.geom_xmat[g], atol=1e-7, err_msg=geom)


def test_update_sends_poses_atomically_and_nothing_when_at_rest(
    server: viser.ViserServer, model: mujoco.MjModel, sent: list[viser.infra.Message]
) -> None:
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    scene = ModelScene(model, server, data=data)

    sent.clear()
    scene.update(data)
    assert sent == []

    data.qpos[0] = 0.2  # slide_x: carriage, arm and tool move
    mujoco.mj_kinematics(model, data)
    scene.update(data)
    kinds = [type(m).__name__ for m in sent]
    assert kinds == ["SetPositionMessage"] * 3
    assert {m.name for m in sent} == {  # type: ignore[attr-defined]
        scene.body_handles[n].name for n in ("carriage", "arm", "tool")
    }


def test_set_geom_color_sends_only_changes(
    server: viser.ViserServer, model: mujoco.MjModel, sent: list[viser.infra.Message]
) -> None:
    scene = ModelScene(model, server)
    handle = scene.geom_handle("cam")
    original = handle.color

    sent.clear()
    assert scene.set_geom_color("cam", (1.0, 0.0, 0.0)) is True
    assert handle.color == (255, 0, 0)
    assert len(sent) == 1
    assert scene.set_geom_color("cam", np.array([1.0, 0.0, 0.0])) is False
    assert len(sent) == 1
    assert scene.reset_geom_color("cam") is True
    assert handle.color == original
    assert scene.reset_geom_color("cam") is False
    assert len(sent) == 2
    with pytest.raises(KeyError, match="rendered geoms"):
        scene.set_geom_color("hidden_collision", (1.0, 1.0, 1.0))


def test_tinted_bodies_turn_red_keep_a_lit_lamp_and_send_only_changes(
    server: viser.ViserServer, model: mujoco.MjModel, sent: list[viser.infra.Message]
) -> None:
    """The carriage tinted red: its two geoms mix 60 % red into their colours (one message
    each), except the lit one, which keeps its light and shows the tint once reset; the same
    tint again sends nothing; an empty tint restores the model's colours."""
    scene = ModelScene(model, server)
    carriage = model.body("carriage").id
    box, cam = model.geom("carriage_box").id, model.geom("cam").id
    assert sorted(scene.body_geoms(carriage)) == sorted([box, cam])
    scene.set_geom_color("cam", (0.0, 0.0, 1.0))  # a lamp lit
    sent.clear()
    assert scene.tint_bodies([carriage], (1.0, 0.0, 0.0)) is True
    assert len(sent) == 1  # the box; the lit cam keeps its light
    r, g, b = scene.model_color(box)
    assert scene.geom_color(box) == (
        round(0.4 * r + 0.6 * 255),
        round(0.4 * g),
        round(0.4 * b),
    )
    assert scene.geom_color(cam) == (0, 0, 255)
    assert scene.tint_bodies([carriage], (1.0, 0.0, 0.0)) is False and len(sent) == 1
    scene.reset_geom_color("cam")  # the lamp goes off: the cam shows its tint
    cr, cg, cb = scene.geom_color(cam)
    assert cr > 150 and cr > cg + 60 and cr > cb + 60
    assert scene.tinted_bodies == {carriage}
    assert scene.tint_bodies([], (1.0, 0.0, 0.0)) is True
    assert scene.geom_color(box) == scene.model_color(box)
    assert scene.geom_color(cam) == scene.model_color(cam)
    assert not scene.tinted_bodies


def test_scene_can_be_removed(server: viser.ViserServer, model: mujoco.MjModel) -> None:
    scene = ModelScene(model, server, prefix="a/b")
    assert scene.prefix == "/a/b"
    scene.remove()
    assert scene.geom_handles == {}
    scene.update(mujoco.MjData(model))  # no moving frames left: a no-op


# ------------------------------------------------------------------ overlays


def test_a_subset_of_bodies_drawn_in_one_colour_and_opacity(
    server: viser.ViserServer, model: mujoco.MjModel
) -> None:
    ids = [model.body(n).id for n in ("carriage", "arm", "tool")]
    scene = ModelScene(model, server, prefix="/copy", bodies=ids, color=(0, 1, 1), opacity=0.3)
    assert set(scene.body_handles) == {"carriage", "arm", "tool"}
    assert set(scene.geom_handles) == {
        "carriage_box",
        "cam",
        "arm_capsule",
        "arm_tint",
        "tool_ellipsoid",
        "tool_mesh",
    }
    for handle in scene.geom_handles.values():
        assert handle.color == (0, 255, 255)
        assert handle.opacity == pytest.approx(0.3)
    with pytest.raises(ValueError, match=r"opacity must be in \[0, 1\]"):
        ModelScene(model, server, prefix="/bad", opacity=1.5)


def test_the_ghost_sits_where_the_set_point_puts_the_moving_bodies(
    server: viser.ViserServer, model: mujoco.MjModel
) -> None:
    """slide_x as an axis in mm: the ghost of carriage, arm and tool is posed by forward
    kinematics at the set point, the hinge as measured; at zero following error it is the
    machine."""
    data = mujoco.MjData(model)
    data.qpos[:2] = [0.1, 0.4]  # slide_x [m], hinge_y [rad]
    mujoco.mj_kinematics(model, data)
    axis = GhostAxis("X", int(model.joint("slide_x").qposadr[0]), 1000.0)
    ghost = SetPointGhost(model, server, [axis], prefix="/ghost")
    moved = {"carriage", "arm", "tool"}
    assert set(ghost.scene.body_handles) == moved

    ghost.update(data.qpos, [25.0])  # set point 25 mm ahead of the slide
    at_set_point = mujoco.MjData(model)
    at_set_point.qpos[:2] = [0.125, 0.4]
    mujoco.mj_kinematics(model, at_set_point)
    for name in moved:
        frame = ghost.scene.body_handles[name]
        np.testing.assert_allclose(frame.position, at_set_point.body(name).xpos, atol=1e-9)
        np.testing.assert_allclose(frame.wxyz, at_set_point.body(name).xquat, atol=1e-9)
        ahead = frame.position - data.body(name).xpos
        np.testing.assert_allclose(ahead, [0.025, 0.0, 0.0], atol=1e-9)

    ghost.update(data.qpos, [0.0])  # at rest: the ghost covers the machine
    for name in moved:
        np.testing.assert_allclose(
            ghost.scene.body_handles[name].position, data.body(name).xpos, atol=1e-12
        )


RESTING_BOX = """
<mujoco>
  <option timestep="0.002"/>
  <worldbody>
    <geom name="floor" type="plane" size="1 1 0.1"/>
    <body name="box" pos="0 0 0.05">
      <freejoint/>
      <geom type="box" size="0.1 0.05 0.05" mass="20"/>
    </body>
  </worldbody>
</mujoco>
"""


def test_the_contacts_of_a_resting_box_carry_its_weight() -> None:
    model = mujoco.MjModel.from_xml_string(RESTING_BOX)
    data = mujoco.MjData(model)
    for _ in range(500):
        mujoco.mj_step(model, data)
    rows = contact_forces(model, data)
    assert rows.shape == (data.ncon, CONTACT_FIELDS) and data.ncon >= 4
    weight = 20.0 * -model.opt.gravity[2]
    assert rows[:, 5].sum() == pytest.approx(weight, rel=1e-3)  # upward, on the box
    np.testing.assert_allclose(rows[:, 2], 0.0, atol=1e-3)  # on the floor
    assert contact_forces(model, data, limit=2).shape == (2, CONTACT_FIELDS)


def test_contacts_are_drawn_on_demand_bounded_in_two_reused_nodes(
    server: viser.ViserServer, sent: list[viser.infra.Message]
) -> None:
    overlay = ContactOverlay(server, prefix="/contacts", scale=1e-4)
    rows = np.array([[0.1, 0.2, 0.3, 0.0, 0.0, 500.0], [0.0, 0.0, 0.0, -1000.0, 0.0, 0.0]])
    sent.clear()
    overlay.update(rows)  # off: nothing drawn, nothing sent
    assert overlay.drawn.shape == (0, CONTACT_FIELDS) and sent == []

    overlay.enabled = True
    overlay.update(rows)
    np.testing.assert_array_equal(overlay.drawn, rows)
    np.testing.assert_allclose(
        overlay.arrows(),
        np.array([[[0.1, 0.2, 0.3], [0.1, 0.2, 0.35]], [[0.0, 0.0, 0.0], [-0.1, 0.0, 0.0]]]),
    )
    overlay.scale = 1e-5  # 1 kN: 10 mm
    np.testing.assert_allclose(overlay.arrows()[1, 1], [-0.01, 0.0, 0.0])

    many = np.tile(rows[:1], (10 * MAX_CONTACTS, 1))
    overlay.update(many)
    assert overlay.drawn.shape == (MAX_CONTACTS, CONTACT_FIELDS)
    overlay.enabled = False
    assert overlay.drawn.shape[0] == 0
    # the same two nodes throughout: updated and shown or hidden, never a node added
    assert {getattr(m, "name", None) for m in sent} == {"/contacts/points", "/contacts/forces"}
    assert {type(m).__name__ for m in sent} == {
        "SceneNodeUpdateMessage",
        "SetSceneNodeVisibilityMessage",
    }


LIMIT_JOINT = int(mujoco.mjtConstraint.mjCNSTR_LIMIT_JOINT)
LIMIT_TENDON = int(mujoco.mjtConstraint.mjCNSTR_LIMIT_TENDON)


def limit_and_friction_forces(
    model: mujoco.MjModel, data: mujoco.MjData, dof: int
) -> tuple[float, float]:
    """The generalized forces [N] of the joint-limit rows and of the friction-loss rows of
    ``dof``, each from its own rows of the constraint Jacobian (``J^T f``)."""
    sums = []
    for kind in (LIMIT_JOINT, int(mujoco.mjtConstraint.mjCNSTR_FRICTION_DOF)):
        forces = np.where(data.efc_type == kind, data.efc_force, 0.0)
        qfrc = np.zeros(model.nv)
        mujoco.mj_mulJacTVec(model, data, qfrc, forces)
        sums.append(float(qfrc[dof]))
    return sums[0], sums[1]


@pytest.mark.parametrize("joint", ["X", "Y", "Z"])
@pytest.mark.parametrize("side", [0, 1], ids=["lower stop", "upper stop"])
@pytest.mark.parametrize("jacobian", ["dense", "sparse"])
def test_a_gantry_axis_past_its_hard_stop_is_pushed_back_by_it(
    joint: str, side: int, jacobian: str
) -> None:
    """1 mm past either end of its range, the stop pushes the axis back inside: one arrow at the
    joint's anchor along its axis, the limit's share of ``qfrc_constraint`` (the rest is the
    guide's friction); the same with MuJoCo's sparse constraint Jacobian."""
    model = mujoco.MjModel.from_xml_path(str(model_path(gantry.MACHINE.model)))
    if jacobian == "sparse":
        model.opt.jacobian = mujoco.mjtJacobian.mjJAC_SPARSE
    assert bool(mujoco.mj_isSparse(model)) == (jacobian == "sparse")
    data = mujoco.MjData(model)
    j = model.joint(joint).id
    dof = int(model.jnt_dofadr[j])
    inward = 1.0 if side == 0 else -1.0
    data.qpos[model.jnt_qposadr[j]] = model.jnt_range[j][side] - 0.001 * inward
    mujoco.mj_forward(model, data)

    (row,) = constraint_forces(model, data)
    np.testing.assert_allclose(row[:3], data.xanchor[j], atol=1e-12)
    axial = float(row[3:] @ data.xaxis[j])
    np.testing.assert_allclose(row[3:], axial * data.xaxis[j], atol=1e-9 * abs(axial))
    assert inward * axial > 1000.0  # back into the range, 1 mm into a stiff stop
    limit, friction = limit_and_friction_forces(model, data, dof)
    assert axial == pytest.approx(limit, rel=1e-12)
    assert axial + friction == pytest.approx(data.qfrc_constraint[dof], rel=1e-12)
    assert abs(axial) == pytest.approx(
        data.efc_force[data.efc_type == LIMIT_JOINT].sum(), rel=1e-12
    )


SPRING_TENDON = """
<mujoco>
  <option gravity="0 0 0"/>
  <worldbody>
    <site name="anchor" pos="0 0 0"/>
    <body name="slider" pos="0 0 1">
      <joint name="slide" type="slide" axis="0 0 1" range="-0.9 0.9"/>
      <geom size="0.05" mass="1"/>
      <site name="end"/>
    </body>
    <body name="arm" pos="1 0 0">
      <joint name="hinge" type="hinge" axis="0 1 0" range="-0.5 0.5"/>
      <geom type="capsule" size="0.02" fromto="0 0 0 0.3 0 0" mass="1"/>
    </body>
  </worldbody>
  <tendon>
    <spatial name="spring" stiffness="1000" springlength="0.8 1.2" limited="true" range="0.5 1.5">
      <site site="end"/>
      <site site="anchor"/>
    </spatial>
    <fixed name="coupling" stiffness="50" springlength="1">
      <joint joint="hinge" coef="1"/>
    </fixed>
  </tendon>
</mujoco>
"""


@pytest.mark.parametrize("slide", [-0.3, -0.55, 0.4, 0.56])
def test_a_loaded_tendon_shows_its_spring_and_limit_force_at_its_first_point(
    slide: float,
) -> None:
    """A spring pushed 5 kN below (or pulled beyond) its band, also onto its length limit: the
    arrow at the first path point carries spring plus limit force, towards the next point when
    pressed, away from it when stretched; MuJoCo's passive force agrees with the spring part.
    The hinge's limit and the fixed tendon have no place: nothing is drawn for them."""
    model = mujoco.MjModel.from_xml_string(SPRING_TENDON)
    model.tendon_stiffnesspoly[0] = [2000.0, 5000.0]
    data = mujoco.MjData(model)
    data.qpos[model.joint("slide").qposadr[0]] = slide
    data.qfrc_applied[model.joint("slide").dofadr[0]] = 5000.0 * np.sign(slide)
    data.qpos[model.joint("hinge").qposadr[0]] = 0.6  # past its limit: a torque, not drawn
    mujoco.mj_forward(model, data)
    tendon = model.tendon("spring").id

    springs = tendon_spring_forces(model, data)
    ten_j = np.zeros(model.nv)  # the spring tendon's Jacobian, dense
    adr, nnz = model.ten_J_rowadr[tendon], model.ten_J_rownnz[tendon]
    ten_j[model.ten_J_colind[adr : adr + nnz]] = data.ten_J[adr : adr + nnz]
    slide_dof = model.joint("slide").dofadr[0]
    assert springs[tendon] * ten_j[slide_dof] == pytest.approx(
        data.qfrc_spring[slide_dof], rel=1e-12
    )
    on_limit = float(np.where(data.efc_type == LIMIT_TENDON, data.efc_force, 0.0).sum())
    assert (on_limit > 0.0) == (abs(slide) > 0.5)

    hinge_stop = (data.efc_type == LIMIT_JOINT) & (data.efc_force > 0.0)
    assert hinge_stop.any() and springs[model.tendon("coupling").id] != 0.0  # loaded, not drawn
    (row,) = constraint_forces(model, data)
    end = data.site("end").xpos
    np.testing.assert_allclose(row[:3], end, atol=1e-12)
    toward_next = (data.site("anchor").xpos - end) / np.linalg.norm(data.site("anchor").xpos - end)
    pressed = 1.0 if slide < 0 else -1.0
    assert pressed * springs[tendon] > 0.0
    np.testing.assert_allclose(
        row[3:], (springs[tendon] + pressed * on_limit) * toward_next, rtol=1e-12, atol=1e-9
    )


def test_stop_and_tendon_forces_are_drawn_on_demand_labelled_in_bounded_reused_nodes(
    server: viser.ViserServer, sent: list[viser.infra.Message]
) -> None:
    overlay = ContactOverlay(server, prefix="/contacts", scale=1e-4)
    contacts = np.array([[0.1, 0.2, 0.3, 0.0, 0.0, 500.0]])
    stops = np.array([[1.0, 0.5, 1.2, -2000.0, 0.0, 0.0], [0.0, 0.0, 1.2, 0.0, 0.0, -74_660.0]])
    sent.clear()
    overlay.update(contacts, stops)  # off: nothing drawn, nothing sent
    assert overlay.drawn_constraints.shape == (0, CONTACT_FIELDS) and sent == []
    assert overlay.constraint_labels == []

    overlay.enabled = True
    overlay.update(contacts, stops)
    np.testing.assert_array_equal(overlay.drawn, contacts)
    np.testing.assert_array_equal(overlay.drawn_constraints, stops)
    assert overlay.constraint_labels == ["2.0 kN", "74.7 kN"]
    np.testing.assert_allclose(overlay.constraint_arrows()[0], [[1.0, 0.5, 1.2], [0.8, 0.5, 1.2]])
    overlay.scale = 1e-6  # 75 kN: 75 mm
    np.testing.assert_allclose(overlay.constraint_arrows()[1, 1], [0.0, 0.0, 1.2 - 0.07466])
    np.testing.assert_allclose(overlay.arrows()[0, 1], [0.1, 0.2, 0.3005])

    overlay.update(contacts, stops[:1] * 0.25)  # one stop, 500 N: the second label hides
    assert overlay.constraint_labels == ["500 N"]
    overlay.update(contacts, np.tile(stops, (10 * MAX_CONSTRAINT_FORCES, 1)))
    assert overlay.drawn_constraints.shape == (MAX_CONSTRAINT_FORCES, CONTACT_FIELDS)
    assert len(overlay.constraint_labels) == MAX_CONSTRAINT_FORCES
    overlay.update(contacts)  # no stop or tendon loaded any more
    assert overlay.drawn_constraints.shape[0] == 0 and overlay.drawn.shape[0] == 1
    assert overlay.constraint_labels == []
    overlay.enabled = False
    assert overlay.drawn.shape[0] == 0 and overlay.drawn_constraints.shape[0] == 0
    # four nodes and a label per drawn force at most: labels are made once, then reused
    labels = {f"/contacts/constraint_label_{i}" for i in range(MAX_CONSTRAINT_FORCES)}
    assert {getattr(m, "name", None) for m in sent} == {
        "/contacts/points",
        "/contacts/forces",
        "/contacts/constraint_points",
        "/contacts/constraint_forces",
        *labels,
    }
    added = [str(getattr(m, "name", "")) for m in sent if type(m).__name__ == "LabelMessage"]
    assert sorted(added) == sorted(labels)  # each made once
    assert {type(m).__name__ for m in sent} == {
        "LabelMessage",
        "SceneNodeUpdateMessage",
        "SetSceneNodeVisibilityMessage",
        "SetPositionMessage",
    }


def test_the_cells_press_signals_read_on_the_press_in_the_panel_and_the_scope() -> None:
    """In the cell (two machines in one world) the press' pressures, force and valve are read
    on the press: the signal panel and the scope's channels show numbers, not NaN."""
    import math

    from tests.viewer.test_session import FakeClock
    from viewer.sim.session import Session

    session = Session("cell", clock=FakeClock())
    session.step(20)
    shown = {s.name: s.value for s in session.snapshot.signals}
    assert all(math.isfinite(v) for v in shown.values()), shown
    assert shown["press/pressure_A"] == session.scene.signal("press/pressure_A")
    session.recorder.record(session.scene.time)
    _, values = session.recorder.series()
    names = [c.name for c in session.recorder.channels]
    row = names.index("press/pressure_A")
    assert values[row][-1] == session.scene.signal("press/pressure_A")
