"""Tests of viewer.model_scene: a MuJoCo model becomes viser scene nodes that follow the bodies."""

from __future__ import annotations

from collections.abc import Callable, Iterator

import mujoco
import numpy as np
import pytest
import viser
import viser.infra

from viewer.model_scene import ModelScene, capsule_mesh

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
def server() -> Iterator[viser.ViserServer]:
    """A viser server on a free port of the loopback interface, always stopped afterwards."""
    srv = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    try:
        yield srv
    finally:
        srv.stop()


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


def test_scene_can_be_removed(server: viser.ViserServer, model: mujoco.MjModel) -> None:
    scene = ModelScene(model, server, prefix="a/b")
    assert scene.prefix == "/a/b"
    scene.remove()
    assert scene.geom_handles == {}
    scene.update(mujoco.MjData(model))  # no moving frames left: a no-op
