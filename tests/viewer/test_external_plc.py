"""An external PLC in the viewer (``--modbus PORT``, ``--opcua PORT``): it commands the gantry
through the bridge's register map or node tree while its Program entry runs; STOP all, a Power
button or another scene take the machine back at once (its writes refused with DEVICE_BUSY or
BadInvalidState, the axis stopped, measured on the joint), Run demo hands it back; every page's
Operator line says who commands."""

from __future__ import annotations

import math
import os
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from asyncua import ua
from pymodbus.client import ModbusTcpClient
from pymodbus.constants import ExcCodes

import mcl
from scenes.bridge.table import CONTROL_BITS, STATUS_BITS
from tests.bridge_clients import NAMESPACE, opcua_client
from tests.scenes.bridge.test_modbus import address, free_port, read_float, write_float
from viewer.pages.control_page import control_html
from viewer.serving.control import Control
from viewer.sim.external_plc import ExternalPlc
from viewer.sim.programs import ProgramCatalog
from viewer.sim.session import Session


def read_u16(modbus: ModbusTcpClient, name: str) -> int:
    reply = modbus.read_holding_registers(address(name), count=1)
    assert not reply.isError()
    return int(reply.registers[0])


def write_control(modbus: ModbusTcpClient, *bits: str) -> int:
    """Write X's control word; the Modbus exception code (0: accepted)."""
    word = sum(1 << CONTROL_BITS.index(b) for b in bits)
    reply = modbus.write_register(address("X.control"), word)
    return int(reply.exception_code) if reply.isError() else 0


def status(modbus: ModbusTcpClient, bit: str) -> bool:
    return bool(read_u16(modbus, "X.status") >> STATUS_BITS.index(bit) & 1)


def wait(condition: Callable[[], bool], seconds: float, what: str) -> None:
    deadline = time.monotonic() + seconds
    while not condition():
        assert time.monotonic() < deadline, f"{what}: not within {seconds} s"
        time.sleep(0.02)


@pytest.fixture
def viewer_session() -> Iterator[tuple[Session, ExternalPlc, ModbusTcpClient]]:
    """A viewer's session of the gantry with an external PLC on a free port, the PLC chosen and
    running (as ``python -m viewer --modbus PORT`` starts), and a connected Modbus client."""
    plc = ExternalPlc("gantry", port=free_port())
    session = Session("gantry", speed=2.0, programs=ProgramCatalog(external=plc))
    assert plc.label in session.programs.labels
    session.programs.choose(plc.label)
    session.start()
    session.start_demo()
    modbus = ModbusTcpClient("127.0.0.1", port=int(plc.label.rsplit(":", 1)[1].rstrip(")")))
    assert modbus.connect()
    try:
        yield session, plc, modbus
    finally:
        modbus.close()
        session.close()
        plc.close()


def test_the_plc_commands_until_stop_all_takes_the_machine_back(
    viewer_session: tuple[Session, ExternalPlc, ModbusTcpClient],
) -> None:
    session, plc, modbus = viewer_session
    wait(lambda: read_u16(modbus, "sim.control") == 1, 5.0, "the PLC in control")
    assert session.plc_in_control == plc.label
    line = control_html(3, Control(), None, plc=session.plc_in_control)
    assert "commands the machine" in line and "Modbus TCP 127.0.0.1" in line
    assert "client connected" in session.snapshot.demo.step

    for name, value in (("velocity", 150.0), ("acceleration", 1000.0), ("deceleration", 1000.0)):
        write_float(modbus, f"X.{name}", value)
    assert write_control(modbus, "enable") == 0
    wait(lambda: status(modbus, "power"), 5.0, "power")
    assert write_control(modbus, "enable", "move_velocity") == 0
    wait(lambda: status(modbus, "in_velocity"), 5.0, "InVelocity")
    scene = session.scene
    joint_velocity = lambda: scene.data.qvel[scene.io("X").dof] * 1000.0  # noqa: E731 [mm/s]
    assert joint_velocity() == pytest.approx(150.0, rel=0.03)  # measured on the joint

    session.stop_all()  # any page may press it
    wait(lambda: read_u16(modbus, "sim.control") == 0, 2.0, "the PLC refused")
    assert session.plc_in_control == ""
    assert "commands the machine" not in control_html(3, Control(), None, plc="")
    assert write_control(modbus, "enable", "move_absolute") == ExcCodes.DEVICE_BUSY
    wait(lambda: abs(read_float(modbus, "X.actual_velocity")) < 0.5, 5.0, "X stopped")
    stopped_at = read_float(modbus, "X.actual_position")
    time.sleep(0.5)  # the PLC keeps writing: refused, and X stands
    assert write_control(modbus, "enable", "jog_pos") == ExcCodes.DEVICE_BUSY
    assert read_float(modbus, "X.actual_position") == pytest.approx(stopped_at, abs=0.01)
    assert abs(joint_velocity()) < 1.0
    assert math.isfinite(read_float(modbus, "sim.time"))  # the status stays live

    session.start_demo()  # Run demo hands the machine back
    wait(lambda: read_u16(modbus, "sim.control") == 1, 2.0, "the PLC in control again")
    assert write_control(modbus, "enable") == 0
    session.toggle_power("X")  # a Power button takes it back too
    wait(lambda: read_u16(modbus, "sim.control") == 0, 2.0, "the PLC refused after Power")


def test_another_scene_detaches_the_plc_and_its_own_reattaches(
    viewer_session: tuple[Session, ExternalPlc, ModbusTcpClient],
) -> None:
    session, plc, modbus = viewer_session
    wait(lambda: read_u16(modbus, "sim.control") == 1, 5.0, "the PLC in control")
    session.load("press")
    wait(lambda: session.scene_name == "press", 5.0, "the press loaded")
    assert plc.label not in session.programs.labels  # it serves the gantry's map only
    wait(lambda: read_u16(modbus, "sim.control") == 0, 2.0, "the PLC refused")
    with pytest.raises(ValueError, match="serves gantry"):
        plc.program(session.scene)
    session.load("gantry")
    wait(lambda: session.scene_name == "gantry", 5.0, "the gantry back")
    assert plc.label in session.programs.labels
    session.programs.choose(plc.label)
    session.start_demo()
    wait(lambda: read_u16(modbus, "sim.control") == 1, 2.0, "the PLC in control again")


def test_the_viewer_serves_a_plc_from_its_own_process(tmp_path: Path) -> None:
    http, port = free_port(), free_port()
    env = {**os.environ, "MCL_PURE_PYTHON": "1"}
    command = [sys.executable, "-m", "viewer", "--port", str(http), "--modbus", str(port)]
    log = tmp_path / "stderr.txt"
    with log.open("w") as stderr:
        process = subprocess.Popen(
            command, env=env, stdout=subprocess.PIPE, stderr=stderr, text=True
        )
    try:
        assert process.stdout is not None
        lines = [process.stdout.readline(), process.stdout.readline()]
        assert f"external PLC (Modbus TCP 127.0.0.1:{port}), unit id 1 gantry" in lines[1]
        modbus = ModbusTcpClient("127.0.0.1", port=port)
        assert modbus.connect()
        wait(lambda: read_u16(modbus, "sim.control") == 1, 10.0, "the PLC in control at start")
        assert write_control(modbus, "enable") == 0
        wait(lambda: status(modbus, "power"), 5.0, "power")
        modbus.close()
    finally:
        process.terminate()
        process.wait(10)
    assert "Traceback" not in log.read_text()


@pytest.mark.parametrize(
    ("options", "message"),
    [
        (["--modbus-host", "0.0.0.0"], "name the PLC's address with --modbus-allow"),
        (["--modbus-host", "0.0.0.0", "--modbus-allow", "plc.local"], "takes IP addresses"),
    ],
)
def test_a_modbus_server_beyond_loopback_needs_an_allow_list(
    options: list[str], message: str
) -> None:
    command = [sys.executable, "-m", "viewer", "--modbus", str(free_port()), *options]
    env = {**os.environ, "MCL_PURE_PYTHON": "1"}
    done = subprocess.run(command, env=env, capture_output=True, text=True, timeout=60)
    assert done.returncode == 2
    assert message in done.stderr and "Traceback" not in done.stderr


def test_a_taken_modbus_port_is_one_clear_message() -> None:
    plc = ExternalPlc("gantry", port=free_port())
    try:
        taken = plc.label.rsplit(":", 1)[1].rstrip(")")
        command = [sys.executable, "-m", "viewer", "--port", str(free_port()), "--modbus", taken]
        env = {**os.environ, "MCL_PURE_PYTHON": "1"}
        done = subprocess.run(command, env=env, capture_output=True, text=True, timeout=60)
    finally:
        plc.close()
    assert done.returncode == 2
    assert f"cannot serve Modbus TCP on 127.0.0.1:{taken}" in done.stderr
    assert "Traceback" not in done.stderr


def test_over_opcua_the_plc_commands_until_stop_all_takes_the_machine_back() -> None:
    """The same with ``--opcua``: the PLC's method calls move X (measured on the joint); after
    STOP all its calls and writes are refused with BadInvalidState and X stands."""
    plc = ExternalPlc("gantry", port=free_port(), protocol="opcua")
    session = Session("gantry", speed=2.0, programs=ProgramCatalog(external=plc))
    try:
        session.programs.choose(plc.label)
        session.start()
        session.start_demo()
        assert "OPC UA opc.tcp://127.0.0.1" in plc.label
        with opcua_client(int(plc.label.rsplit(":", 1)[1].rstrip(")"))) as client:
            ns = client.get_namespace_index(NAMESPACE)
            value = lambda name: client.get_node(f"ns={ns};s={name}").read_value()  # noqa: E731
            x = client.get_node(f"ns={ns};s=X")
            wait(lambda: value("sim.control") == 1, 5.0, "the PLC in control")
            step = lambda: session.snapshot.demo.step  # noqa: E731 (published with the frames)
            wait(lambda: "1 client connected" in step(), 2.0, "the client shown")
            x.call_method(f"{ns}:MC_Power", ua.Variant(True, ua.VariantType.Boolean))
            wait(lambda: value("X.status.power"), 5.0, "power")
            ramp = [ua.Variant(v, ua.VariantType.Double) for v in (150.0, 1000.0, 1000.0, 0.0)]
            direction = ua.Variant(int(mcl.MC_Direction.MC_Positive), ua.VariantType.Int32)
            mode = ua.Variant(0, ua.VariantType.UInt16)
            x.call_method(f"{ns}:MC_MoveVelocity", *ramp, direction, mode)
            wait(lambda: value("X.status.in_velocity"), 5.0, "InVelocity")
            scene = session.scene
            joint_velocity = lambda: scene.data.qvel[scene.io("X").dof] * 1000.0  # noqa: E731
            assert joint_velocity() == pytest.approx(150.0, rel=0.03)  # measured on the joint

            session.stop_all()
            wait(lambda: value("sim.control") == 0, 2.0, "the PLC refused")
            with pytest.raises(ua.UaStatusCodeError, match="BadInvalidState"):
                x.call_method(f"{ns}:MC_MoveVelocity", *ramp, direction, mode)
            wait(lambda: abs(value("X.actual_velocity")) < 0.5, 5.0, "X stopped")
            stopped_at = value("X.actual_position")
            position = client.get_node(f"ns={ns};s=X.position")
            with pytest.raises(ua.UaStatusCodeError, match="BadInvalidState"):
                position.write_value(ua.DataValue(ua.Variant(500.0, ua.VariantType.Double)))
            time.sleep(0.3)
            assert value("X.actual_position") == pytest.approx(stopped_at, abs=0.01)
            assert abs(joint_velocity()) < 1.0
    finally:
        session.close()
        plc.close()


@pytest.mark.parametrize(
    ("options", "message"),
    [
        (["--modbus", "5020", "--opcua", "4840"], "one external PLC at a time"),
        (["--opcua", "4840", "--opcua-host", "0.0.0.0"], "needs the password of user 'plc'"),
    ],
)
def test_a_refused_opcua_option_is_one_line(
    options: list[str],
    message: str,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    from viewer.__main__ import main

    monkeypatch.delenv("MCL_OPCUA_PASSWORD", raising=False)
    assert main(["--port", str(free_port()), *options]) == 2
    stderr = capsys.readouterr().err
    assert message in stderr and len(stderr.strip().splitlines()) == 1
