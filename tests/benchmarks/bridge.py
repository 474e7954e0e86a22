"""Benchmark: the Modbus bridge on loopback.

Starts ``python -m scenes bridge modbus gantry`` free-running at 1× and measures, over 2000
requests each, the median and p99 latency of reading X's status block (14 registers) and of
writing its control word; then starts it in lockstep and drives 1000 PLC cycles of 10 ms (5 scans
of the gantry's 2 ms): a status read, a command write, the target and its acknowledgement per
cycle, as a real-time factor. Prints JSON (the server in the mode of this process:
MCL_PURE_PYTHON passes on).

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

from pymodbus.client import ModbusTcpClient

import scenes
from scenes.bridge.table import SignalTable, decode, encode

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


def cycle(client: ModbusTcpClient, address: int) -> float:
    """The server's PLC cycle counter."""
    return decode("u32", client.read_holding_registers(address, count=2).registers)


def lockstep(client: ModbusTcpClient, steps: int = 1000) -> float:
    """Real-time factor of ``steps`` client cycles of 10 ms in lockstep."""
    target_address = TABLE.by_name["sim.target"].address
    cycle_address = TABLE.by_name["sim.cycle"].address
    target = 0
    start = time.perf_counter()
    for _ in range(steps):
        client.read_holding_registers(STATUS, count=14)
        client.write_register(CONTROL, 1)
        target += STEP_CYCLES
        client.write_registers(target_address, encode("u32", target))
        while cycle(client, cycle_address) < target:
            pass
    return steps * 0.01 / (time.perf_counter() - start)


def main() -> None:
    """Print the measurements as JSON."""
    with server() as client:
        read = latency(lambda: client.read_holding_registers(STATUS, count=14))
        write = latency(lambda: client.write_register(CONTROL, 0))
    with server("--lockstep") as client:
        factor = lockstep(client)
    pure = os.environ.get("MCL_PURE_PYTHON") == "1"
    report = {"pure_python": pure, "read_status": read, "write_command": write}
    print(json.dumps({**report, "lockstep_10ms_real_time_factor": factor}, indent=2))


if __name__ == "__main__":
    main()
