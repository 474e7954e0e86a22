"""Every registered machine's demo ends with its axes at rest and runs again.

A demo is done only once every driven axis stands in StandStill, outside any axes group (its
couplings ended, the Execute of its MC_Stop fallen), and the physics stands with it: run, end,
run again on the same scene. In the viewer (:class:`viewer.sim.session.Session`) Repeat demo then
starts the demo afresh after each run, and a program that finishes with an axis not at rest is
reported and not repeated. The tests iterate the registry (:data:`scenes.MACHINES`).
"""

from __future__ import annotations

import numpy as np
import pytest

import mcl
import scenes
from plc.sequence import DemoProgram
from scenes.machines.flying_shear import Demo as FlyingShearDemo
from scenes.machines.rotary_cutter import CamDemo
from scenes.scene import Scene
from tests.viewer.test_session import FakeClock, run
from viewer.sim.session import Session

NAMES = [name for name in sorted(scenes.MACHINES) if scenes.MACHINES[name].demo is not None]
"""Every registered machine with a demo."""
SETTLE = 0.5
"""How long the physics is watched after a demo ended [s]."""
STILL = 0.1
"""The most a joint may move over :data:`SETTLE` once the demo ended [mm or °]: a loop settling
into its standstill, nothing a user would see move (a web or drum coasting on moves metres or
turns)."""


def run_to_end(scene: Scene) -> DemoProgram:
    """A fresh demo of ``scene``'s machine, run until it is done (or fails)."""
    program = scenes.demo(scene)
    scene.run(program, until=lambda: program.done or bool(program.error), timeout=300.0)
    assert program.done and not program.error, f"{scene.name}: {program.step}"
    return program


def assert_at_rest(scene: Scene) -> None:
    """Every driven axis in StandStill, in no group, and, from the physics, every joint
    standing over :data:`SETTLE` without a program (it moves less than :data:`STILL`)."""
    for name, axis in scene.axes.items():
        if axis.has_drive:
            assert axis.state == mcl.AxisState.StandStill, (name, axis.state)
            assert axis.group is None, f"{name} is still in an axes group"
    start = {name: scene.joint_position(name) * scene.scales[name] for name in scene.axes}
    travel = dict.fromkeys(scene.axes, 0.0)

    def watch() -> None:
        for name in scene.axes:
            here = scene.joint_position(name) * scene.scales[name]
            travel[name] = max(travel[name], abs(here - start[name]))

    scene.run(watch, timeout=SETTLE)
    assert max(travel.values()) < STILL, travel


@pytest.mark.parametrize("name", NAMES)
def test_the_demo_ends_with_every_axis_at_rest_and_runs_again(name: str) -> None:
    scene = scenes.load(name, start=scenes.MACHINES[name].demo_start, trace_every=0)
    for _ in range(2):
        run_to_end(scene)
        assert_at_rest(scene)


def test_the_cutters_cut_again_what_they_cut_the_first_time() -> None:
    """The rotary cutter's and the flying shear's demos again on the same scene: each run
    cuts its own pieces, as many and as right as the first time (from the physics)."""
    scene = scenes.load("rotary_cutter", trace_every=0)
    for _ in range(2):
        cam = run_to_end(scene)
        assert isinstance(cam, CamDemo)
        pieces = [(cut.length, target) for cut, target in cam.pieces()]
        assert [t for _, t in pieces] == [300.0] * 6 + [900.0] * 4
        assert all(x is not None and abs(x - target) < 0.5 for x, target in pieces), pieces
    scene = scenes.load("flying_shear", trace_every=0)
    runs = []
    cuts = 0
    for _ in range(2):
        shear = run_to_end(scene)
        assert isinstance(shear, FlyingShearDemo)
        runs.append(np.array(shear.errors()))
        cuts = shear.job.cuts
    assert len(runs[1]) == len(runs[0]) == cuts - 1
    assert abs(runs[1].mean() - runs[0].mean()) < 0.1 and np.abs(runs[1]).max() < 3.0, runs


@pytest.mark.parametrize("name", NAMES)
def test_repeat_demo_runs_the_demo_again_in_the_viewer(name: str) -> None:
    """Run demo with Repeat demo on: the demo ends, starts again after the pause and ends
    again, without an error."""
    clock = FakeClock()
    session = Session(name, clock=clock)
    session.repeat_demo = True
    session.start_demo()
    for _ in range(2000):
        run(session, clock, 0.5)
        demo = session.snapshot.demo
        if demo.error or (demo.runs == 2 and demo.done):
            break
    demo = session.snapshot.demo
    assert not demo.error and demo.runs == 2 and demo.done, (demo.runs, demo.step, demo.error)
    for axis in session.scene.axes.values():
        assert not axis.has_drive or axis.state == mcl.AxisState.StandStill


class EndsInStopping:
    """A demo that finishes holding its MC_Stop's Execute: the axis stays in Stopping."""

    def __init__(self, scene: Scene) -> None:
        self.power = mcl.MC_Power(Axis=scene.axes["X"], Enable=True)
        self.stop = mcl.MC_Stop(Axis=scene.axes["X"], Execute=True)
        self.step, self.error = "stop", ""

    @property
    def done(self) -> bool:
        return self.stop.Done

    def __call__(self) -> None:
        self.power()
        if self.power.Status:
            self.stop()


def test_a_demo_that_finishes_with_an_axis_not_at_rest_is_reported_and_not_repeated() -> None:
    clock = FakeClock()
    session = Session("single_axis", clock=clock, demo=EndsInStopping)
    session.repeat_demo = True
    session.start_demo()
    run(session, clock, 3.0)  # beyond the repeat's pause
    demo = session.snapshot.demo
    assert demo.done and not demo.running and demo.runs == 1
    assert "X Stopping" in demo.error and "at rest" in demo.error, demo.error
    assert any("X Stopping" in e.text for e in session.snapshot.events)
