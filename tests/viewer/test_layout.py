"""The layout without a browser: the page's columns leave the 3-D view half of a 1280 px page,
and the camera frames every machine whole — the corners of the box around its parts — in a 3-D
view that narrow (the cell's gantry and press both)."""

from __future__ import annotations

import math
from collections.abc import Iterator

import mujoco
import numpy as np
import pytest
import viser

import scenes
from tests.viewer.test_browser import _free_port
from viewer.pages import layout
from viewer.sim.session import Session
from viewer.view3d import views


@pytest.fixture(scope="module")
def server() -> Iterator[viser.ViserServer]:
    s = viser.ViserServer(host="127.0.0.1", port=_free_port(), verbose=False)
    yield s
    s.stop()


def test_the_columns_leave_half_of_a_1280_px_page() -> None:
    cell_tabs = 324  # the cell's four axis tabs widen the control panel (measured)
    assert layout.COLUMN_WIDTH + max(layout.CONTROL_WIDTH, cell_tabs) + 8 <= 640


@pytest.mark.parametrize(
    "machine", sorted(name for name in scenes.MACHINES if name != "single_axis")
)
def test_the_camera_frames_the_machine_in_a_3d_view_of_aspect_0_8(
    server: viser.ViserServer, machine: str
) -> None:
    session = Session(machine)
    model = session.snapshot.model
    assert model is not None
    data = mujoco.MjData(model)
    data.qpos[:] = session.snapshot.qpos
    mujoco.mj_kinematics(model, data)
    views.Views(server, lambda: None).frame(model, data)
    camera = server.initial_camera
    eye, look = np.asarray(camera.position), np.asarray(camera.look_at)
    axis = (look - eye) / np.linalg.norm(look - eye)
    narrowest = 640 / 800  # the 3-D view of a 1280×800 page, width / height
    half = math.atan(math.tan(0.5 * camera.fov) * narrowest)  # its horizontal half angle
    solid = np.asarray(model.geom_type) != mujoco.mjtGeom.mjGEOM_PLANE
    rbound = np.asarray(model.geom_rbound)
    solid &= rbound <= views.FRAME_OUTLIER * float(np.median(rbound[solid]))
    centres, radii = np.asarray(data.geom_xpos)[solid], rbound[solid][:, None]
    low, high = (centres - radii).min(axis=0), (centres + radii).max(axis=0)
    corners = [np.where(np.array(bits), high, low) for bits in np.ndindex(2, 2, 2)]
    for corner in corners:  # the box around every part of the machine
        ray = corner - eye
        off_axis = math.acos(float(np.clip(ray @ axis / np.linalg.norm(ray), -1.0, 1.0)))
        assert off_axis <= half + 1e-9, (machine, corner)
    session.close()
