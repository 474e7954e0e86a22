"""Benchmark: the bridge's servers on loopback, Modbus TCP and OPC UA.

Modbus: starts ``python -m scenes bridge modbus gantry`` free-running at 1× and measures, over
2000 requests each, the median and p99 latency of reading X's status block (14 registers) and of
writing its control word; then starts it in lockstep and runs the gantry demo from a PLC with a
10 ms cycle (5 scans of the gantry's 2 ms; :func:`gantry_demo`): one read/write request per cycle
writes the target and is answered with X's status when the scene is there, one more reads Y's
and Z's status words (one request of 101 registers); the real-time factor of the whole demo,
against the gantry's bare physics (MuJoCo with its
devices, a servo period per call) over the same simulated time in this process.

OPC UA (:mod:`tests.benchmarks.bridge_opcua`): the same with ``python -m scenes bridge opcua
gantry`` and an asyncua client: reading X's status variables (one Read of ten), writing its
control word, calling MC_Reset; the demo in lockstep with one Advance call and one Read of the
three status words per 10 ms cycle.

Prints JSON (the servers in the mode of this process: MCL_PURE_PYTHON passes on).

Run: ``python -m tests.benchmarks.bridge``.
"""

from __future__ import annotations

import json
import os
import socket
import statistics
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Protocol

from pymodbus.client import ModbusTcpClient

import scenes
from scenes.bridge.table import CONTROL_BITS, STATUS_BITS, SignalTable, encode

TABLE = SignalTable(scenes.definition("gantry"))
STATUS = TABLE.by_name["X.status"].address
CONTROL = TABLE.by_name["X.control"].address
STEP_CYCLES = 5
"""Gantry PLC cycles per client cycle of 10 ms."""


@contextmanager
def server(*options: str) -> Iterator[ModbusTcpClient]:
    """The gantry's server in its own process and a connected client."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = int(s.getsockname()[1])
    command = [sys.executable, "-m", "scenes", "bridge", "modbus", "gantry", "--port", str(port)]
    process = subprocess.Popen(
        [*command, *options], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True
    )
    try:
        assert process.stdout is not None
        process.stdout.readline()
        client = ModbusTcpClient("127.0.0.1", port=port)
        client.connect()
        yield client
        client.close()
    finally:
        process.terminate()
        process.wait(10)


def latency(request: Callable[[], object], count: int = 2000) -> dict[str, float]:
    """Median and p99 of ``request`` [ms]."""
    times = []
    for _ in range(count):
        start = time.perf_counter()
        request()
        times.append(time.perf_counter() - start)
    times.sort()
    return {"median_ms": statistics.median(times) * 1e3, "p99_ms": times[int(0.99 * count)] * 1e3}


STATUS_WORDS = 14
"""Registers of an axis' status block (status … inputs)."""


class LockstepPlc:
    """A PLC on the gantry's lockstep server with a 10 ms cycle: each cycle one read/write
    request (FC 23) writes the target and reads X's status block (answered when the scene is
    there), Y's and Z's status words read in one request, command words written when they
    change."""

    def __init__(self, client: ModbusTcpClient) -> None:
        self.client = client
        self.target = 0
        self.cycles = 0
        self.words = {axis: -1 for axis in TABLE.axes}
        self.status = {axis: 0 for axis in TABLE.axes}

    def command(self, axis: str, word: int, **params: float) -> None:
        """Parameters and the control word of ``axis`` (written with the next cycle)."""
        for name, value in params.items():
            f = TABLE.by_name[f"{axis}.{name}"]
            self.client.write_registers(f.address, encode(f.kind, value))
        if word != self.words[axis]:
            self.client.write_register(TABLE.by_name[f"{axis}.control"].address, word)
            self.words[axis] = word

    def cycle(self) -> None:
        """One PLC cycle: the scene runs 10 ms, the status comes back."""
        self.target += STEP_CYCLES
        self.cycles += 1
        x = TABLE.by_name["X.status"].address
        reply = self.client.readwrite_registers(
            read_address=x,
            read_count=STATUS_WORDS,
            write_address=TABLE.by_name["sim.target"].address,
            values=encode("u32", self.target),
        )
        self.status["X"] = reply.registers[0]
        y, z = (TABLE.by_name[f"{axis}.status"].address for axis in ("Y", "Z"))
        block = self.client.read_holding_registers(y, count=z - y + 1).registers
        self.status["Y"], self.status["Z"] = block[0], block[z - y]

    def bit(self, axis: str, name: str) -> bool:
        """Status bit ``name`` of ``axis`` as of the last cycle."""
        return bool(self.status[axis] >> STATUS_BITS.index(name) & 1)

    def until(self, condition: Callable[[], bool], limit: int = 20000) -> None:
        """Cycle until ``condition`` (at least once)."""
        for _ in range(limit):
            self.cycle()
            if condition():
                return
        raise RuntimeError("the gantry did not get there")


def bits(*names: str) -> int:
    return sum(1 << CONTROL_BITS.index(n) for n in names)


class DemoPlc(Protocol):
    """What :func:`gantry_demo` needs of a PLC with a 10 ms cycle."""

    cycles: int

    def command(self, axis: str, word: int, **params: float) -> None: ...

    def bit(self, axis: str, name: str) -> bool: ...

    def until(self, condition: Callable[[], bool], limit: int = 20000) -> None: ...


def gantry_demo(plc: DemoPlc) -> None:
    """Power and home X, Y, Z with their recipes, then move through four corners of a
    rectangle, each axis on its own (MC_MoveAbsolute), as a PLC program of 10 ms would."""
    axes = ("X", "Y", "Z")
    for axis in axes:
        plc.command(axis, bits("enable"), velocity=300.0, acceleration=3000.0)
        plc.command(axis, bits("enable"), deceleration=3000.0)
    plc.until(lambda: all(plc.bit(a, "power") for a in axes))
    for axis in axes:
        plc.command(axis, bits("enable", "home"))
    plc.until(lambda: all(plc.bit(a, "done") and plc.bit(a, "homed") for a in axes))
    for x, y in ((400.0, 100.0), (400.0, 300.0), (100.0, 300.0), (100.0, 100.0)):
        plc.command("X", bits("enable"), position=x)
        plc.command("Y", bits("enable"), position=y)
        plc.command("X", bits("enable", "move_absolute"))
        plc.command("Y", bits("enable", "move_absolute"))
        plc.until(lambda: plc.bit("X", "done") and plc.bit("Y", "done"))


def lockstep(plc: DemoPlc) -> dict[str, float]:
    """The gantry demo through a lockstep server: PLC cycles, simulated seconds, wall seconds
    and their ratio (the real-time factor)."""
    start = time.perf_counter()
    gantry_demo(plc)
    wall = time.perf_counter() - start
    simulated = plc.cycles * 0.01
    return {
        "plc_cycles": plc.cycles,
        "simulated_s": simulated,
        "wall_s": wall,
        "real_time_factor": simulated / wall,
    }


def bare_physics(simulated: float) -> float:
    """The gantry's bare physics stepped for ``simulated`` seconds: its real-time factor."""
    from tests.benchmarks.machines import BarePhysics

    scene = scenes.load("gantry", trace_every=0)
    physics = BarePhysics(scene, devices=True)
    physics.sync()
    ticks = round(scene.runtime.servo_period / scene.plant.timestep)
    start = time.perf_counter()
    for _ in range(round(simulated / scene.runtime.servo_period)):
        physics.step(ticks)
    return simulated / (time.perf_counter() - start)


def main() -> None:
    """Print the measurements as JSON."""
    from tests.benchmarks import bridge_opcua

    with server() as client:
        read = latency(lambda: client.read_holding_registers(STATUS, count=14))
        write = latency(lambda: client.write_register(CONTROL, 0))
    with server("--lockstep") as client:
        factor = lockstep(LockstepPlc(client))
    opcua = bridge_opcua.measure()
    bare = bare_physics(factor["simulated_s"])
    for demo in (factor, opcua["lockstep_gantry_demo_10ms"]):
        demo |= {"bare_physics_real_time_factor": bare, "ratio": demo["real_time_factor"] / bare}
    pure = os.environ.get("MCL_PURE_PYTHON") == "1"
    modbus = {"read_status": read, "write_command": write, "lockstep_gantry_demo_10ms": factor}
    print(json.dumps({"pure_python": pure, "modbus": modbus, "opcua": opcua}, indent=2))


if __name__ == "__main__":
    main()
