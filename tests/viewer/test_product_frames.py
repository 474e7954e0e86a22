"""The delta picker's tracked coordinate system in the 3-D view: while MC_TrackConveyorBelt
carries the PCS, its triad stands over the tracked part (the part's centre from the physics)
and moves on with the belt at the belt's speed, labelled with the group and the belt; once the
group stops tracking (the PCS is the MCS again) the triad is hidden. The session is stepped
scan by scan (no thread); the triad's node is the one the viewer's pages are sent."""

from __future__ import annotations

import math
from collections.abc import Iterator
from types import SimpleNamespace
from typing import cast

import numpy as np
import pytest
import viser

from scenes.machines.delta_picker import VacuumGripper
from scenes.machines.delta_picker.axes import PART_X
from viewer.sim.product_frames import FrameView
from viewer.sim.session import Session
from viewer.sim.snapshot import Snapshot
from viewer.view3d.frame_marks import TRIAD_LENGTH, FrameMarks

TRACKING = ("down onto it", "settle", "grip", "lift it")
"""The demo's steps during which the PCS moves with the belt."""


@pytest.fixture
def server() -> Iterator[viser.ViserServer]:
    server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    try:
        yield server
    finally:
        server.stop()


def test_the_tracked_frame_moves_with_the_belt_over_the_part_and_hides_after(
    server: viser.ViserServer,
) -> None:
    session = Session("delta_picker")
    marks = FrameMarks(server)
    gripper = session.scene.device("vacuum", VacuumGripper)
    belt = session.scene.joint("C")
    session.start_demo()
    tracked: list[tuple[np.ndarray, float]] = []
    hidden_after = False
    while session.snapshot.time < 12.0 and not hidden_after:
        session.advance(10)
        snapshot = session.snapshot
        marks.update(snapshot)
        step = snapshot.demo.step
        drawn = marks.origin("delta")
        if step in TRACKING:
            assert drawn is not None, step
            assert marks.label("delta") == "PCS delta · on C"
            view = snapshot.frames[0]
            np.testing.assert_allclose(drawn, view.origin)
            parts = np.array([gripper.part_position(k) for k in range(len(PART_X))])
            gap = np.min(np.linalg.norm(parts[:, :2] - drawn[:2], axis=1))
            assert gap < 0.003, (step, gap)  # over the part's centre (within 3 mm)
            tracked.append((drawn, belt.position))
        elif tracked and step in ("carry to the tray", "release"):
            assert drawn is None and not snapshot.frames, step  # no PCS: no triad
            hidden_after = True
    assert hidden_after and len(tracked) > 10
    (p0, b0), (p1, b1) = tracked[0], tracked[-1]
    assert p1[0] - p0[0] == pytest.approx(b1 - b0, rel=0.02)  # along x with the belt
    assert abs(p1[1] - p0[1]) < 1e-6 and abs(p1[2] - p0[2]) < 1e-6
    marks.remove()
    session.close()


def turned(wxyz: np.ndarray, vector: tuple[float, float, float]) -> np.ndarray:
    """``vector`` turned by the quaternion ``wxyz``."""
    w, x, y, z = (float(c) for c in wxyz)
    u, v = np.array([x, y, z]), np.asarray(vector, dtype=np.float64)
    return v + 2.0 * w * np.cross(u, v) + 2.0 * np.cross(u, np.cross(u, v))


def frames_of(*views: FrameView) -> Snapshot:
    """A snapshot carrying only the PCS ``views`` (all FrameMarks reads)."""
    return cast(Snapshot, SimpleNamespace(frames=views))


@pytest.mark.parametrize("degrees", [90.0, 30.0, -135.0])
def test_a_fixed_pcs_triad_stands_turned_with_its_x_axis_labelled_above_it(
    server: viser.ViserServer, degrees: float
) -> None:
    """A PCS set with MC_SetCoordinateTransform: the triad (arms 0.15 m) at its origin, its x
    arm along the PCS x axis, z up; the label "PCS delta" above it, drawn over the robot."""
    marks = FrameMarks(server, prefix="/pcs")
    x_axis = (math.cos(math.radians(degrees)), math.sin(math.radians(degrees)), 0.0)
    marks.update(frames_of(FrameView("delta", (0.5, -0.25, 1.0), x_axis, "")))
    np.testing.assert_allclose(cast(np.ndarray, marks.origin("delta")), (0.5, -0.25, 1.0))
    frame = server.scene._handle_from_node_name["/pcs/delta"]
    assert isinstance(frame, viser.FrameHandle)
    np.testing.assert_allclose(turned(frame.wxyz, (1.0, 0.0, 0.0)), x_axis, atol=1e-9)
    np.testing.assert_allclose(turned(frame.wxyz, (0.0, 0.0, 1.0)), (0, 0, 1), atol=1e-9)
    assert frame.axes_length == TRIAD_LENGTH and frame.axes_radius == 0.04 * TRIAD_LENGTH
    label = server.scene._handle_from_node_name["/pcs/delta/label"]
    assert isinstance(label, viser.LabelHandle) and marks.label("delta") == "PCS delta"
    np.testing.assert_allclose(label.position, (0.0, 0.0, 1.2 * TRIAD_LENGTH))
    assert label.depth_test is False and label.anchor == "bottom-center"


def test_a_triad_hides_shows_again_relabelled_and_is_removed(server: viser.ViserServer) -> None:
    marks = FrameMarks(server, prefix="/pcs")
    assert marks.origin("delta") is None and marks.label("delta") == ""  # never drawn
    on_belt = FrameView("delta", (0.1, 0.0, 0.8), (1.0, 0.0, 0.0), "C")
    other = FrameView("delta2", (0.4, 0.0, 0.8), (1.0, 0.0, 0.0), "")
    marks.update(frames_of(on_belt, other))
    assert marks.label("delta") == "PCS delta · on C" and marks.label("delta2") == "PCS delta2"
    marks.update(frames_of(other))  # delta's PCS gone: its triad hidden, the other stays
    assert marks.origin("delta") is None and marks.origin("delta2") is not None
    fixed = FrameView("delta", (0.2, 0.0, 0.8), (0.0, 1.0, 0.0), "")
    marks.update(frames_of(fixed, other))
    np.testing.assert_allclose(cast(np.ndarray, marks.origin("delta")), (0.2, 0.0, 0.8))
    assert marks.label("delta") == "PCS delta"
    marks.remove()
    names = server.scene._handle_from_node_name
    assert not any(n.startswith("/pcs/") for n in names)  # triads and labels
    assert marks.origin("delta") is None and marks.label("delta") == ""
