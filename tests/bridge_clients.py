"""A PLC's view of the bridge for the tests: the same calls (write a field, read one, run PLC
cycles) in-process on a machine's signal table, or over Modbus TCP or OPC UA to a lockstep server
in its own process; and the scenarios the machines' acceptance runs through any of them."""

from __future__ import annotations

import os
import random
import socket
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

from asyncua import ua
from asyncua.sync import Client as SyncUaClient
from pymodbus.client import ModbusTcpClient

import scenes
from scenes.bridge.program import BridgeProgram
from scenes.bridge.table import CONTROL_BITS, STATUS_BITS, SignalTable, decode, encode

Condition = Callable[[], bool]


def bits(*names: str) -> int:
    """A control word with the bits ``names`` set."""
    return sum(1 << CONTROL_BITS.index(name) for name in names)


class Plc:
    """The calls of a PLC on a machine's table; subclasses say how they reach it."""

    table: SignalTable
    plc_period: float

    def write(self, name: str, value: float) -> None:
        """Write field ``name`` as a client does (raw registers)."""
        raise NotImplementedError

    def read(self, name: str) -> float:
        """Read field ``name``."""
        raise NotImplementedError

    def run(self, seconds: float) -> None:
        """Let the scene run ``seconds`` of PLC cycles."""
        raise NotImplementedError

    def status(self, axis: str, name: str) -> bool:
        """Status bit ``name`` of ``axis``."""
        return bool(int(self.read(f"{axis}.status")) >> STATUS_BITS.index(name) & 1)

    def until(self, condition: Condition, timeout: float, what: str, step: float = 0.01) -> float:
        """Run in ``step`` s until ``condition`` (at least one step: the status of a command
        just written comes with the next scan); the simulated time it took [s].

        Raises:
            AssertionError: not within ``timeout`` simulated seconds.
        """
        waited = 0.0
        while True:
            self.run(step)
            waited += step
            if condition():
                return waited
            assert waited < timeout, f"{what}: not within {timeout} s"

    def write_all(self, values: dict[str, float]) -> None:
        """Write several fields."""
        for name, value in values.items():
            self.write(name, value)

    def power_and_home(self, axes: tuple[str, ...], homed: str) -> None:
        """Enable ``axes``, then home ``homed`` with its recipe; leaves the enable bits set."""
        for axis in axes:
            self.write(f"{axis}.control", bits("enable"))
        self.until(lambda: all(self.status(a, "power") for a in axes), 2.0, "power")
        self.write(f"{homed}.control", bits("enable", "home"))
        self.until(lambda: self.status(homed, "done"), 60.0, "homing", 0.05)
        assert self.status(homed, "homed")
        self.write(f"{homed}.control", bits("enable"))


class InProcess(Plc):
    """The table of a scene of ``machine`` in this process, published after each run of scans
    as a lockstep server publishes it; written and read as registers (as a Modbus client does:
    REALs as f32) or, ``by_name``, as values (as an OPC UA client does: REALs as Double)."""

    def __init__(self, machine: str, by_name: bool = False) -> None:
        self.scene = scenes.load(machine, trace_every=0)
        self.table = SignalTable(scenes.definition(machine))
        homing = scenes.homing(self.scene)
        self.program = BridgeProgram(self.scene, [self.table], homing, publish_every_scan=False)
        self.plc_period = self.scene.runtime.plc_period
        self.by_name = by_name

    def write(self, name: str, value: float) -> None:
        if self.by_name:
            self.table.put(name, value)
            return
        f = self.table.by_name[name]
        self.table.write(f.address, encode(f.kind, value))

    def read(self, name: str) -> float:
        if self.by_name:
            return self.table.get(name)
        f = self.table.by_name[name]
        return decode(f.kind, self.table.read(f.address, f.width))  # as a client reads it

    def run(self, seconds: float) -> None:
        self.scene.run(self.program, timeout=round(seconds / self.plc_period) * self.plc_period)
        self.program.publish()


class ModbusLockstep(Plc):
    """A Modbus client of a lockstep server of ``machine``: each run writes the target and is
    answered when the scene is there."""

    def __init__(self, machine: str, client: ModbusTcpClient) -> None:
        self.table = SignalTable(scenes.definition(machine))
        self.client = client
        self.plc_period = scenes.definition(machine).plc_period
        self.target = 0

    def write(self, name: str, value: float) -> None:
        f = self.table.by_name[name]
        reply = self.client.write_registers(f.address, encode(f.kind, value))
        assert not reply.isError(), f"write {name}: {reply}"

    def read(self, name: str) -> float:
        f = self.table.by_name[name]
        reply = self.client.read_holding_registers(f.address, count=f.width)
        assert not reply.isError(), f"read {name}: {reply}"
        return decode(f.kind, reply.registers)

    def run(self, seconds: float) -> None:
        self.target += round(seconds / self.plc_period)
        self.write("sim.target", self.target)
        assert int(self.read("sim.cycle")) == self.target  # answered when the scene is there


UA_TYPE = {
    "u16": ua.VariantType.UInt16,
    "i16": ua.VariantType.Int16,
    "u32": ua.VariantType.UInt32,
    "f32": ua.VariantType.Double,
}
"""The OPC UA type of a field's variable (docs/bridge.md)."""

NAMESPACE = "urn:mcl-testbench:bridge"


def ua_variant(table: SignalTable, name: str, value: float) -> ua.Variant:
    """The variant a client writes to field ``name``'s variable."""
    kind = UA_TYPE[table.by_name[name].kind]
    return ua.Variant(float(value) if kind == ua.VariantType.Double else int(value), kind)


class OpcuaLockstep(Plc):
    """An OPC UA client (asyncua's synchronous one) of a lockstep server of ``machine`` at
    ``url``: each run writes ``sim.target`` and is answered when the scene is there."""

    def __init__(self, machine: str, client: SyncUaClient) -> None:
        self.table = SignalTable(scenes.definition(machine))
        self.client = client
        self.plc_period = scenes.definition(machine).plc_period
        self.target = 0
        ns = client.get_namespace_index(NAMESPACE)
        self.nodes = {f.name: client.get_node(f"ns={ns};s={f.name}") for f in self.table.fields}

    def write(self, name: str, value: float) -> None:
        self.nodes[name].write_value(ua.DataValue(ua_variant(self.table, name, value)))

    def read(self, name: str) -> float:
        return float(self.nodes[name].read_value())

    def run(self, seconds: float) -> None:
        self.target += round(seconds / self.plc_period)
        self.write("sim.target", self.target)
        assert int(self.read("sim.cycle")) == self.target  # answered when the scene is there


def free_port() -> int:
    """A free TCP port on loopback."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@contextmanager
def modbus_server(machine: str, log: Path, *options: str) -> Iterator[ModbusTcpClient]:
    """The Modbus server of ``machine`` in its own process, and a client connected to it."""
    port = free_port()
    env = {**os.environ, "MCL_PURE_PYTHON": os.environ.get("MCL_PURE_PYTHON", "")}
    command = [sys.executable, "-m", "scenes", "bridge", "modbus", machine, "--port", str(port)]
    with log.open("w") as stderr:
        process = subprocess.Popen(
            [*command, *options], env=env, stdout=subprocess.PIPE, stderr=stderr, text=True
        )
    try:
        assert process.stdout is not None
        assert "Modbus TCP on 127.0.0.1" in process.stdout.readline()
        modbus = ModbusTcpClient("127.0.0.1", port=port, timeout=10)
        assert modbus.connect()
        yield modbus
        modbus.close()
        assert process.poll() is None
    finally:
        process.terminate()
        process.wait(10)
    assert "Traceback" not in log.read_text()


@contextmanager
def opcua_server(
    machine: str, log: Path, *options: str, env: dict[str, str] | None = None
) -> Iterator[int]:
    """The OPC UA server of ``machine`` in its own process (``env``: more of its environment),
    listening; its port. Checks at the end that it stayed up and logged no traceback."""
    port = free_port()
    environ = {**os.environ, "MCL_PURE_PYTHON": os.environ.get("MCL_PURE_PYTHON", "")}
    command = [sys.executable, "-m", "scenes", "bridge", "opcua", machine, "--port", str(port)]
    with log.open("w") as stderr:
        process = subprocess.Popen(
            [*command, *options],
            env={**environ, **(env or {})},
            stdout=subprocess.PIPE,
            stderr=stderr,
            text=True,
        )
    try:
        assert process.stdout is not None
        line = process.stdout.readline()
        assert f"{machine}: OPC UA on opc.tcp://" in line, log.read_text()
        yield port
        assert process.poll() is None
    finally:
        process.terminate()
        process.wait(10)
    assert "Traceback" not in log.read_text()


@contextmanager
def opcua_client(port: int) -> Iterator[SyncUaClient]:
    """asyncua's synchronous client connected to a loopback server without security."""
    client = SyncUaClient(f"opc.tcp://127.0.0.1:{port}/", timeout=10)
    client.connect()
    try:
        yield client
    finally:
        client.disconnect()


MOVING: dict[str, float] = {"X.control": bits("enable", "move_absolute")}
"""Power on and MC_MoveAbsolute's Execute."""

SCENARIO: tuple[tuple[int, dict[str, float]], ...] = (
    (50, {"X.control": bits("enable")}),
    (2000, {"X.control": bits("enable", "home")}),
    (10, {"X.control": bits("enable"), "X.position": 300.0, "X.velocity": 200.0}),
    (10, {"X.acceleration": 1000.0, "X.deceleration": 1000.0}),
    *[(40, MOVING)] * 30,
)
"""The gantry's lockstep scenario: (PLC cycles to run, fields written before) — power, home,
move X to 300 mm."""

WATCHED = ("X.actual_position", "X.following_error", "X.status", "sim.cycle")
"""The fields the lockstep trace records after every step."""


def gantry_lockstep(plc: Plc, rng: random.Random | None = None) -> list[list[float]]:
    """The values of :data:`WATCHED` after every step of :data:`SCENARIO` run by ``plc``
    (``rng``: a random pause of up to 3 ms after each write, whatever the network timing)."""
    trace = []
    for cycles, writes in SCENARIO:
        for name, value in writes.items():
            plc.write(name, value)
            if rng is not None:
                time.sleep(rng.uniform(0.0, 0.003))
        plc.run(cycles * plc.plc_period)
        trace.append([plc.read(name) for name in WATCHED])
    return trace


SHEAR_SPEED = 1000.0
"""Strip speed of the shear scenario [mm/s] (60 m/min)."""
SHEAR_LENGTH = 1500.0
"""Cut length of the shear scenario [mm]."""
PARK = 100.0
"""Carriage park position [mm]."""


def shear_cuts(plc: Plc, cuts: int) -> list[float]:
    """The flying shear cuts to length through the table: the line at speed, the carriage
    geared in with MC_GearInPos (Zeroing 1) to the measuring wheel, the knife down through
    digital output 0 at InSync, then back to park; each piece measured from the physics
    (``signal.last_piece``, read to 0.1 mm as a length gauge would) corrects the wheel's scale
    for the next cut; the pieces' lengths [mm]."""
    approach = 150.0
    plc.power_and_home(("L", "S"), "S")
    plc.write_all({"S.position": PARK, "S.velocity": 1000.0})
    plc.write_all({"S.acceleration": 5000.0, "S.deceleration": 5000.0})
    plc.write_all({"L.velocity": SHEAR_SPEED, "L.acceleration": 1000.0})
    plc.write_all({"L.deceleration": 1000.0, "L.jerk": 5000.0})
    plc.write("S.control", bits("enable", "move_absolute"))
    plc.write("L.control", bits("enable", "move_velocity"))
    plc.until(lambda: plc.status("S", "done") and plc.status("L", "in_velocity"), 10.0, "start")
    gear = {
        "S.master": plc.table.axes.index("W"),
        "S.ratio_numerator": 1000,
        "S.ratio_denominator": 1000,
        "S.slave_sync_position": PARK + approach,
        "S.master_start_distance": 2.0 * approach,
        "S.velocity": 3000.0,
        "S.acceleration": 10000.0,
        "S.deceleration": 10000.0,
        "S.zeroing": 1,
    }
    plc.write_all(gear)
    pieces: list[float] = []
    scale = 1.0  # the wheel's: master travel per strip travel, learned from the pieces
    for cut in range(cuts + 1):
        first = plc.read("W.actual_position") + 2.0 * approach + 200.0
        plc.write("S.master_sync_position", first if cut == 0 else SHEAR_LENGTH * scale)
        plc.write("S.ratio_denominator", round(1000 * scale))  # the carriage at strip speed
        plc.write("S.control", bits("enable", "gear_in_pos"))
        plc.until(lambda: plc.status("S", "in_sync"), 5.0, f"cut {cut}: InSync")
        before = plc.read("signal.last_piece")
        plc.write("S.outputs", 1)  # the knife down
        plc.run(0.08)
        plc.write("S.outputs", 0)
        plc.run(0.06)
        plc.write("S.position", PARK)  # back at the gearing's velocity and ramps
        plc.write("S.control", bits("enable", "move_absolute"))
        plc.until(lambda: plc.status("S", "done"), 5.0, f"cut {cut}: back to park")
        if cut:
            piece = plc.read("signal.last_piece")
            assert piece != before, f"cut {cut}: no new piece"
            pieces.append(piece)
            scale = SHEAR_LENGTH * scale / round(piece, 1)  # a gauge of 0.1 mm
    return pieces


PRESS_FORCE = 75.0
"""Force the press holds [kN]."""


def press_holds(plc: Plc, seconds: float) -> list[float]:
    """The press homes, approaches the part and holds :data:`PRESS_FORCE` with MC_ForceControl
    on its two pressure transducers through the table; the load cell's force (from the physics,
    ``signal.force``) every 10 ms of the last ``seconds`` of the hold [kN]."""
    from scenes.machines.press import demo
    from scenes.machines.press.devices import CylinderDevice

    cylinder = scenes.load("press", trace_every=0).device("cylinder", CylinderDevice)
    inputs = demo.force_inputs(cylinder.hydraulics.cylinder)
    plc.power_and_home(("R",), "R")
    plc.write_all({"R.position": demo.PART - 5.0, "R.velocity": 250.0})
    plc.write_all({"R.acceleration": 3000.0, "R.deceleration": 3000.0})
    plc.write("R.control", bits("enable", "move_absolute"))
    plc.until(lambda: plc.status("R", "done"), 5.0, "approach")
    plc.write_all(
        {
            "R.force": PRESS_FORCE,
            "R.force_ramp": 200.0,
            "R.velocity": 20.0,
            "R.gain": demo.FORCE_GAIN,
            "R.tolerance": 0.5,
            "R.input_number": inputs["InputNumber"],
            "R.scale": inputs["Scale"],
            "R.input_number2": inputs["InputNumber2"],
            "R.scale2": inputs["Scale2"],
            "R.offset": inputs["Offset"],
        }
    )
    plc.write("R.control", bits("enable", "force_control"))
    plc.until(lambda: plc.status("R", "in_force"), 3.0, "in force")
    plc.run(0.2)
    forces = []
    for _ in range(round(seconds / 0.01)):
        plc.run(0.01)
        assert plc.status("R", "active") and not plc.status("R", "error")
        forces.append(plc.read("signal.force"))
    return forces
