"""The gantry demo end to end on MuJoCo: homing, grouping, linear interpolation of a 3-D path.

Measured from the physics: the `tool` site against the ideal straight segments, and the tool's
speed through the blended corners.
"""

from __future__ import annotations

import numpy as np
import pytest

import mcl
from scenes.machines import gantry
from scenes.tools.contour import distance_to_polyline

MOVING = ("move over the part", "carry to the place position", "return to park")


@pytest.fixture(scope="module")
def run() -> dict[str, object]:
    scene = gantry.build(start={"X": 0.43, "Y": 0.27, "Z": -0.12}, trace_every=0)
    program = gantry.Demo(scene)
    tool = scene.model.site("gantry/tool").id
    samples: list[tuple[str, np.ndarray]] = []

    def sample(t: float) -> None:
        if program.step in MOVING:
            samples.append((program.step, scene.data.site_xpos[tool].copy()))

    scene.runtime.observers.append(sample)
    scene.run(program, until=lambda: program.done or bool(program.error), timeout=120.0)
    return {"scene": scene, "program": program, "samples": samples}


def test_demo_homes_groups_and_completes_the_cycle(run):
    scene, program = run["scene"], run["program"]
    assert program.error == ""
    assert program.done
    for name, axis in scene.axes.items():
        assert axis.Ref, name
        assert axis.state == mcl.AxisState.StandStill, name
        assert axis.AxErrorID == 0, name
    # the park position, measured from the joints (homed coordinates = joint coordinates in mm)
    park = (500.0, 300.0, gantry.SAFE_Z)
    for name, target in zip("XYZ", park, strict=True):
        assert scene.joint_position(name) * 1000.0 == pytest.approx(target, abs=0.05), name


def _vertices(run):
    scene = run["scene"]
    data, tool = scene.data, scene.model.site("gantry/tool").id
    offset = data.site_xpos[tool] - np.array([scene.joint_position(a) for a in "XYZ"])
    corners = [offset + np.array(p) / 1000.0 for batch in gantry.PATH for p, _ in batch]
    return [run["samples"][0][1], *corners]


def test_tool_stays_on_the_straight_segments_and_within_the_corner_tolerance(run):
    """Contour error of the tool point: under 20 µm away from the blended corners, within the
    group's corner tolerance at them."""
    vertices = _vertices(run)
    points = np.array([p for _, p in run["samples"]])
    errors = distance_to_polyline(points, vertices)
    away = np.min([np.linalg.norm(points - v, axis=1) for v in vertices], axis=0) > 0.005
    assert away.sum() > 1000  # most of the path is straight
    assert errors[away].max() < 20e-6
    tolerance = run["program"].group.corner_tolerance * 1e-3  # mm → m
    assert errors.max() <= tolerance, f"{errors.max() * 1e6:.1f} µm"


def test_blended_corners_do_not_stop_the_tool(run):
    """At each blended corner (BlendingLow) the tool keeps moving; at Buffered corners it stops."""
    points = np.array([p for _, p in run["samples"]])
    speed = np.linalg.norm(np.diff(points, axis=0), axis=1) / 0.001  # m/s, one servo period
    vertices = _vertices(run)[1:]
    modes = [mode for batch in gantry.PATH for _, mode in batch]
    blended = [
        v
        for v, nxt in zip(vertices, modes[1:], strict=False)
        if nxt == mcl.MC_BufferMode.BlendingLow
    ]
    assert blended
    for corner in blended:
        near = np.linalg.norm(points[1:] - corner, axis=1) < 0.002
        assert near.any()
        assert speed[near].min() > 0.005  # > 5 mm/s through the corner
