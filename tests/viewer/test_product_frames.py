"""The delta picker's tracked coordinate system in the 3-D view: while MC_TrackConveyorBelt
carries the PCS, its triad stands over the tracked part (the part's centre from the physics)
and moves on with the belt at the belt's speed, labelled with the group and the belt; once the
group stops tracking (the PCS is the MCS again) the triad is hidden. The session is stepped
scan by scan (no thread); the triad's node is the one the viewer's pages are sent."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
import pytest
import viser

from scenes.machines.delta_picker import VacuumGripper
from scenes.machines.delta_picker.axes import PART_X
from viewer.sim.session import Session
from viewer.view3d.frame_marks import FrameMarks

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
