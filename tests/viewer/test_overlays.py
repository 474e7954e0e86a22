"""The viewer's commissioning overlays on the real machines, without a browser: the set-point
ghost, the forces (contacts, hard stops, the press tool), the follow camera and jogging while a
key is held.

The session is driven synchronously (``Session.advance``) with a fake wall clock that the app's
jog holds share, so dead-man deadlines are deterministic. Pages are real websocket clients of
the viser server (a camera to follow, hotkeys that pass the gate).
"""

from __future__ import annotations

import asyncio
import threading
import time
from collections.abc import Callable, Iterator
from typing import Any

import msgspec
import mujoco
import numpy as np
import pytest
import viser
import websockets.asyncio.client

from plc.operator.hmi import Move
from scenes.machines import press
from scenes.machines.press.devices import ContactForce
from tests.viewer.test_scene import limit_and_friction_forces
from tests.viewer.test_session import FakeClock, run, view
from viewer.pages.app import ViewerApp
from viewer.serving.control import KEY_JOG_FIRST, KEY_JOG_REPEAT
from viewer.sim.session import Session
from viewer.view3d.views import FOLLOW_STEP

OBSTACLE_AHEAD = 0.01
"""Distance [m] from X's start to the point where the obstacle stops the bridge."""


@pytest.fixture
def clock() -> FakeClock:
    return FakeClock()


@pytest.fixture
def session(clock: FakeClock) -> Session:
    """The gantry, not running (driven by :func:`run`), X powered and at rest."""
    s = Session("gantry", clock=clock)
    s.requests("X").set_power(True)
    run(s, clock, 0.3)
    assert view(s).powered
    return s


def block_x(session: Session) -> float:
    """Park the gantry's obstacle so that it stops the bridge :data:`OBSTACLE_AHEAD` ahead of
    X; the X coordinate [m] where it stops it."""
    model = session.scene.model
    q_block = session.scene.joint_position("X") + OBSTACLE_AHEAD
    touching = model.numeric("gantry/X_obstacle_blockpos").data
    model.body_pos[model.body("gantry/X_obstacle").id] = touching + np.array([q_block, 0, 0])
    return q_block


def push_into_obstacle(session: Session, clock: FakeClock) -> float:
    """Move X 50 mm toward the obstacle 10 mm ahead; return once the bridge rests on it and the
    set point ran 2 mm beyond (before the following-error limit stops the axis): the X
    coordinate [m] where the obstacle stops the bridge."""
    q_block = block_x(session)
    session.requests("X").move(Move("relative", 50.0, 50.0, 500.0))
    for _ in range(400):
        session.advance(1)
        clock.now += session.scene.runtime.plc_period
        if view(session).following_error > 2.0:
            return q_block
    raise AssertionError(f"X never pressed on the obstacle: {view(session)}")


def test_the_ghost_shows_the_set_point_ahead_of_a_blocked_axis(
    server: viser.ViserServer, session: Session, clock: FakeClock
) -> None:
    """At rest the ghost covers the bridge; pressed against the obstacle the bridge stays put
    while the ghost runs on with the set point (forward kinematics at the set point)."""
    app = ViewerApp(session, server, clock=clock)
    app.show_ghost = True
    app.frame()
    ghost = app.ghost
    assert ghost is not None and ghost.visible
    assert {a.name for a in ghost.axes} == {"X", "Y", "Z"}
    bridge = session.scene.model.body("gantry/bridge").id
    drawn = ghost.scene.body_handles["gantry/bridge"]
    np.testing.assert_allclose(drawn.position, session.scene.data.xpos[bridge], atol=2e-6)

    q_block = push_into_obstacle(session, clock)
    app.frame()
    snapshot = session.snapshot
    q = session.scene.joint_position("X")
    set_point = view(session).position + view(session).following_error  # [mm]
    assert q == pytest.approx(q_block, abs=2e-4)  # the bridge rests on the obstacle
    at_set_point = mujoco.MjData(session.scene.model)
    at_set_point.qpos[:] = snapshot.qpos
    x = session.scene.io("X").qpos_adr
    at_set_point.qpos[x] = q + (set_point - view(session).position) / 1e3  # 1000 mm per m
    mujoco.mj_kinematics(session.scene.model, at_set_point)
    for name in ("gantry/bridge", "gantry/carriage", "gantry/ram"):
        np.testing.assert_allclose(
            ghost.scene.body_handles[name].position, at_set_point.body(name).xpos, atol=1e-9
        )
    lead = drawn.position[0] - snapshot.xpos[bridge][0]
    assert lead == pytest.approx(view(session).following_error / 1e3, abs=2e-6)
    assert lead > 0.002

    app.show_ghost = False
    app._redraw = True
    app.frame()
    assert not ghost.visible


def test_contacts_on_the_obstacle_are_drawn_with_the_force_of_the_physics(
    server: viser.ViserServer, session: Session, clock: FakeClock
) -> None:
    app = ViewerApp(session, server, clock=clock)
    contacts = app.contacts
    assert contacts is not None
    push_into_obstacle(session, clock)
    app.frame()
    assert contacts.drawn.shape[0] == 0  # off by default

    app.show_contacts = True
    app._redraw = True
    app.frame()
    model, data = session.scene.model, session.scene.data
    drawn = contacts.drawn
    assert 1 <= drawn.shape[0] == data.ncon
    wrench = np.zeros(6)
    for i in range(data.ncon):
        mujoco.mj_contactForce(model, data, i, wrench)
        np.testing.assert_allclose(drawn[i, :3], data.contact[i].pos, atol=1e-12)
        np.testing.assert_allclose(drawn[i, 3:], wrench[0] * data.contact[i].frame[:3], rtol=1e-9)
    # the bridge pushes along +x: the obstacle pushes back with a sizeable force
    assert abs(drawn[:, 3].sum()) > 20.0
    np.testing.assert_allclose(drawn[:, 4:], 0.0, atol=1e-6 * abs(drawn[:, 3].sum()))

    app.show_contacts = False
    app._redraw = True
    app.frame()
    assert contacts.drawn.shape[0] == 0 and data.ncon >= 1


def test_the_shear_knife_cutting_the_strip_shows_its_contact_force(
    server: viser.ViserServer, clock: FakeClock
) -> None:
    session = Session("flying_shear", clock=clock)
    app = ViewerApp(session, server, clock=clock)
    app.show_contacts = True
    session.start_demo()
    model = session.scene.model
    knife = model.geom("flying_shear/knife_blade").id
    for _ in range(200):  # until the knife is down in the strip (its first cut)
        run(session, clock, 0.05)
        data = session.scene.data
        if any(knife in (data.contact[i].geom1, data.contact[i].geom2) for i in range(data.ncon)):
            break
    app.frame()
    contacts = app.contacts
    assert contacts is not None and contacts.drawn.shape[0] >= 1
    assert np.linalg.norm(contacts.drawn[:, 3:], axis=1).max() > 100.0  # the cutting force [N]


PUSH = 500.0
"""Force [N] with which the gantry's unpowered bridge is pushed into a hard stop."""


@pytest.mark.parametrize(("start", "push"), [(1.04, PUSH), (-0.04, -PUSH)], ids=["+x", "-x"])
def test_the_gantry_pushed_into_a_hard_stop_shows_the_stop_force(
    server: viser.ViserServer, clock: FakeClock, start: float, push: float
) -> None:
    """The bridge, unpowered 10 mm before an end stop, pushed towards it: at rest on the stop the
    arrow at X's anchor points back along x with the push, less what the rails' friction takes;
    stop and friction together are MuJoCo's constraint force on X."""
    session = Session("gantry", clock=clock, overrides={"start": {"X": start}})
    app = ViewerApp(session, server, clock=clock)
    model, data = session.scene.model, session.scene.data
    joint = model.joint("gantry/X").id
    dof = int(model.jnt_dofadr[joint])
    data.qfrc_applied[dof] = push
    run(session, clock, 0.5)
    app.frame()
    forces = app.contacts
    assert forces is not None
    assert forces.drawn_constraints.shape[0] == 0  # off by default

    app.show_contacts = True
    app._redraw = True
    app.frame()
    assert session.scene.joint_position("X") == pytest.approx(
        model.jnt_range[joint][int(push > 0)], abs=2e-4
    )
    (row,) = forces.drawn_constraints
    np.testing.assert_allclose(row[:3], data.xanchor[joint], atol=1e-12)
    np.testing.assert_allclose(row[4:], 0.0, atol=1e-9 * PUSH)
    stop = row[3]
    assert -stop == pytest.approx(push, abs=model.dof_frictionloss[dof])  # back against the push
    limit, friction = limit_and_friction_forces(model, data, dof)
    assert stop == pytest.approx(limit, rel=1e-12)
    assert stop + friction == pytest.approx(data.qfrc_constraint[dof], rel=1e-12)
    assert data.qfrc_constraint[dof] == pytest.approx(-push, rel=1e-6)  # at rest: all of it
    assert forces.drawn.shape[0] == 0  # no contact: the stop is a joint limit
    assert forces.constraint_labels == [f"{abs(stop):.0f} N"]  # over the bridge

    app.show_contacts = False
    app._redraw = True
    app.frame()
    assert forces.drawn_constraints.shape[0] == 0


def test_the_press_homing_to_block_shows_the_top_stop_holding_the_cylinder(
    server: viser.ViserServer, clock: FakeClock
) -> None:
    """Homing to block drives the ram up against the cylinder's top stop (a joint limit): the
    arrow at the ram's anchor points down, the stop holding the cylinder's push less the ram's
    weight, within the seal friction."""
    session = Session("press", clock=clock)
    app = ViewerApp(session, server, clock=clock)
    app.show_contacts = True
    session.start_demo()
    run(session, clock, 0.1)
    assert session.snapshot.demo.step == "home to block"
    app.frame()
    forces = app.contacts
    assert forces is not None
    model, data = session.scene.model, session.scene.data
    joint = model.joint("press/R").id
    dof = int(model.jnt_dofadr[joint])
    (row,) = forces.drawn_constraints
    np.testing.assert_allclose(row[:3], data.xanchor[joint], atol=1e-12)
    np.testing.assert_allclose(row[3:5], 0.0, atol=1e-6)
    stop = -row[5]  # down, along +R
    assert stop > 10e3  # the valve's 1 V against the stop: tens of kN
    pushed = data.qfrc_applied[dof] - data.qfrc_bias[dof]  # the cylinder up, the weight down
    assert abs(stop + pushed) <= model.dof_frictionloss[dof] + 1e-3 * stop
    limit, friction = limit_and_friction_forces(model, data, dof)
    assert stop == pytest.approx(limit, rel=1e-12)
    assert stop + friction == pytest.approx(data.qfrc_constraint[dof], rel=1e-12)


@pytest.mark.parametrize("stiffness", [None, 1e7], ids=["part", "soft part on its block"])
def test_the_press_tool_force_on_the_part_is_drawn_as_the_load_cell_reads_it(
    server: viser.ViserServer, clock: FakeClock, stiffness: float | None
) -> None:
    """Holding 75 kN on the part: the arrow at the punch face points down onto the part with the
    part's spring force plus its hard block's (the load cell), which balances the cylinder's
    force and the ram's weight within the seal friction. The model's part stops short of its
    block; a part of 1e7 N/m ends on it."""
    session = Session("press", clock=clock)
    model, data = session.scene.model, session.scene.data
    if stiffness is not None:
        model.tendon_stiffness[model.tendon("press/workpiece").id] = stiffness
    app = ViewerApp(session, server, clock=clock)
    app.show_contacts = True
    session.start_demo()
    held = 0.0
    for _ in range(100):  # 5 s at most: 0.3 s into the dwell
        run(session, clock, 0.05)
        held += 0.05 if session.snapshot.demo.step == "hold the force" else 0.0
        if held >= 0.3:
            break
    assert session.snapshot.demo.step == "hold the force"
    app.frame()
    forces = app.contacts
    assert forces is not None
    (row,) = forces.drawn_constraints
    load = ContactForce(model, data, session.scene.namespace.prefix)()
    np.testing.assert_allclose(row[:3], data.site("press/punch_face").xpos, atol=1e-12)
    np.testing.assert_allclose(row[3:], [0.0, 0.0, -load], rtol=1e-9)
    assert forces.constraint_labels == [f"{load / 1e3:.1f} kN"]  # over the ram and the part
    block = float(data.sensor("press/workpiece_block").data[0])
    assert (block > 10e3) == (stiffness is not None)
    dof = int(model.joint("press/R").dofadr[0])
    pushed = data.qfrc_applied[dof] - data.qfrc_bias[dof]  # the cylinder and the weight, down
    assert abs(load - pushed) <= model.dof_frictionloss[dof] + 1e-3 * load
    if stiffness is None:  # the force loop holds its set point on the spring
        assert load == pytest.approx(press.HOLD_FORCE * 1e3, rel=0.01)


class Page:
    """A page connected to the viewer over the websocket (no browser), in a thread of its own:
    it reports a camera, as a browser does, and can send messages (a hotkey, a GUI value)."""

    def __init__(self, server: viser.ViserServer, position: tuple[float, float, float]) -> None:
        self._loop = asyncio.new_event_loop()
        self._thread = threading.Thread(target=self._loop.run_forever, daemon=True)
        self._thread.start()
        before = set(server.get_clients())
        self._connection: Any = self._call(self._connect(server.get_port(), position))
        deadline = time.monotonic() + 10.0
        while not set(server.get_clients()) - before:
            assert time.monotonic() < deadline, "the page did not connect"
            time.sleep(0.01)
        (self.client_id,) = set(server.get_clients()) - before

    def _call(self, coroutine: Any) -> Any:
        return asyncio.run_coroutine_threadsafe(coroutine, self._loop).result(10.0)

    async def _connect(self, port: int, position: tuple[float, float, float]) -> Any:
        connection = await websockets.asyncio.client.connect(
            f"ws://127.0.0.1:{port}/",
            subprotocols=[f"viser-v{viser.__version__}"],  # type: ignore[list-item]
            max_size=None,
        )
        self._reader = asyncio.ensure_future(self._drain(connection))
        camera = {
            "wxyz": [1.0, 0.0, 0.0, 0.0],
            "position": list(position),
            "fov": 1.0,
            "near": 0.01,
            "far": 100.0,
            "image_height": 600,
            "image_width": 800,
            "look_at": [0.0, 0.0, 1.0],
            "up_direction": [0.0, 0.0, 1.0],
        }
        await connection.send(msgspec.msgpack.encode({"type": "ViewerCameraMessage", **camera}))
        return connection

    @staticmethod
    async def _drain(connection: Any) -> None:
        async for _ in connection:  # what the server sends is read and dropped
            pass

    def send(self, kind: str, **fields: Any) -> None:
        """Send one message of type ``kind``."""
        self._call(self._connection.send(msgspec.msgpack.encode({"type": kind, **fields})))

    def close(self) -> None:
        """Leave (once)."""
        if not self._thread.is_alive():
            return
        self._call(self._connection.close())
        self._loop.call_soon_threadsafe(self._loop.stop)
        self._thread.join(5.0)


@pytest.fixture
def page(server: viser.ViserServer) -> Iterator[Page]:
    p = Page(server, (2.0, -2.0, 2.0))
    try:
        yield p
    finally:
        p.close()


def choose(page: Page, handle: Any, value: Any) -> None:
    """The page sets a GUI element to ``value``."""
    page.send("GuiUpdateMessage", uuid=handle._impl.uuid, updates={"value": value})


def wait_for(condition: Callable[[], bool], what: str) -> None:
    deadline = time.monotonic() + 10.0
    while not condition():
        assert time.monotonic() < deadline, what
        time.sleep(0.005)


def test_the_follow_camera_keeps_its_offset_to_the_body(
    server: viser.ViserServer, session: Session, clock: FakeClock, page: Page
) -> None:
    app = ViewerApp(session, server, clock=clock)
    follow = next(h for h in app._scene_inputs if getattr(h, "label", "") == "Follow")
    assert "gantry/bridge" in follow.options and "gantry/ram" in follow.options
    choose(page, follow, "gantry/bridge")  # for everyone: no control needed
    wait_for(lambda: app.follow == "gantry/bridge", "the page's choice did not reach the app")
    camera = server.get_clients()[page.client_id].camera
    app.frame()
    start_camera, start_look = camera.position.copy(), camera.look_at.copy()
    bridge = session.scene.model.body("gantry/bridge").id
    start_body = session.scene.data.xpos[bridge].copy()

    session.requests("X").move(Move("relative", 100.0, 200.0, 2000.0))
    for _ in range(30):  # 1.5 s, a frame every 50 ms
        run(session, clock, 0.05)
        app.frame()
    travel = session.scene.data.xpos[bridge] - start_body
    assert travel[0] == pytest.approx(0.1, abs=1e-3)
    np.testing.assert_allclose(camera.position - start_camera, travel, atol=FOLLOW_STEP)
    np.testing.assert_allclose(camera.look_at - start_look, travel, atol=FOLLOW_STEP)

    choose(page, follow, "off")
    wait_for(lambda: app.follow == "off", "the page's choice did not reach the app")
    session.requests("X").move(Move("relative", -100.0, 200.0, 2000.0))
    for _ in range(30):
        run(session, clock, 0.05)
        app.frame()
    assert session.scene.data.xpos[bridge][0] == pytest.approx(start_body[0], abs=1e-3)
    np.testing.assert_allclose(camera.position - start_camera, travel, atol=FOLLOW_STEP)


def test_a_held_jog_key_jogs_and_silence_stops_the_axis(
    server: viser.ViserServer, session: Session, clock: FakeClock, page: Page
) -> None:
    """The page sends the Alt+→ hotkey on the press and on each auto-repeat: the axis jogs
    while they come and stops a renewal time after the last one, also when the page loses
    control or leaves."""
    app = ViewerApp(session, server, clock=clock)
    jog_plus = next(c for c in app._commands if c._impl.props.label == "X jog +")
    assert (jog_plus._impl.props.hotkey, jog_plus._impl.props.modifier) == ("arrowright", "alt")
    jog_velocity = 0.1 * view(session).vmax  # the default jog velocity [mm/s]
    frame = 0.05  # [s] of simulated and wall time between two frames of the app

    def press() -> None:
        """One trigger of the key (first press or auto-repeat), applied by the app."""
        page.send("CommandTriggerMessage", uuid=jog_plus._impl.uuid)
        wait_for(
            lambda: (hold := app._holds.get(page.client_id)) is not None and hold.last == clock.now,
            "the trigger did not reach the app",
        )

    def frames(seconds: float, repeat: bool = False) -> list[tuple[float, float]]:
        """Run the app's frames (renewing holds) for ``seconds``; (time since start, X velocity
        [mm/s]) after each; with ``repeat`` the key repeats every frame."""
        samples = []
        for k in range(round(seconds / frame)):
            if repeat:
                press()
            app.renew_holds()
            run(session, clock, frame)
            samples.append(((k + 1) * frame, view(session).velocity))
        return samples

    page.send("CommandTriggerMessage", uuid=jog_plus._impl.uuid)  # not in control
    wait_for(
        lambda: any("take control first" in e.text for e in session._events),
        "the gate did not refuse the key",
    )
    assert page.client_id not in app._holds
    app.control.take(page.client_id)

    press()  # a single press: the jog bridges the browser's repeat delay, then stops
    single = frames(1.2)
    assert all(v > 0.9 * jog_velocity for t, v in single if 2 * frame <= t <= KEY_JOG_FIRST)
    stop = next(t for t, v in single if v < 0.5 * jog_velocity)
    # the renewal time, the frame that notices it ran out, half the ramp down
    assert KEY_JOG_FIRST < stop <= KEY_JOG_FIRST + 2 * frame + 1e-9
    assert view(session).jogging == 0 and abs(single[-1][1]) < 0.01 * jog_velocity

    press()  # held: the key repeats every frame for 1.5 s, well past the first renewal
    held = frames(1.5, repeat=True)
    assert all(v > 0.9 * jog_velocity for t, v in held if t >= 2 * frame)
    after = frames(0.6)  # let go: the repeats stop
    stop = next(t for t, v in after if v < 0.5 * jog_velocity)
    assert stop <= KEY_JOG_REPEAT + 2 * frame + 1e-9
    assert view(session).jogging == 0 and abs(after[-1][1]) < 0.01 * jog_velocity

    press()  # control passes to another operator: the jog ends at the next frame
    frames(0.1)
    assert view(session).jogging == 1
    app.control.take(page.client_id + 100)
    frames(0.1)
    assert view(session).jogging == 0 and page.client_id not in app._holds

    app.control.take(page.client_id)
    press()  # the page leaves while its key is held: the jog ends
    frames(0.1)
    assert view(session).jogging == 1
    page.close()
    wait_for(lambda: page.client_id not in app._holds, "the page's hold outlived it")
    frames(0.1)
    assert view(session).jogging == 0
