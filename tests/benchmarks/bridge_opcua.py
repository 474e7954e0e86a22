"""Benchmark: the OPC UA bridge on loopback (printed by :mod:`tests.benchmarks.bridge`).

Starts ``python -m scenes bridge opcua gantry`` free-running at 1× and measures with an asyncua
client, over 2000 requests each, the median and p99 latency of reading X's status (one Read of
its ten status variables: status … inputs), of writing its control word and of calling MC_Reset;
then starts it in lockstep and runs the gantry demo (:func:`tests.benchmarks.bridge.gantry_demo`)
from a PLC with a 10 ms cycle: one Advance(5) call per cycle, answered when the scene is there,
one Read of the three status words, commands written (parameters and control word in one Write)
when they change; its real-time factor.

The client runs in this thread's own event loop (no thread between the PLC and its socket).

Run: ``python -m tests.benchmarks.bridge_opcua`` (``python -m tests.benchmarks.bridge`` runs it
too).
"""

from __future__ import annotations

import asyncio
import json
import tempfile
from collections.abc import Awaitable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any, TypeVar

from asyncua import Client, ua

from tests.benchmarks.bridge import STEP_CYCLES, TABLE, LockstepPlc, latency, lockstep
from tests.bridge_clients import NAMESPACE, opcua_server, ua_variant

T = TypeVar("T")

STATUS_FIELDS = (
    "status",
    "state",
    "error_id",
    "axis_error_id",
    "actual_position",
    "actual_velocity",
    "following_error",
    "volts",
    "command",
    "inputs",
)
"""X's status variables read in one request (the Modbus status block's fields)."""


class Session:
    """An asyncua client connected to the server on ``port``, driven from this thread."""

    def __init__(self, port: int) -> None:
        self.loop = asyncio.new_event_loop()
        self.client = Client(f"opc.tcp://127.0.0.1:{port}/", timeout=10)
        self.run(self.client.connect())
        self.ns = self.run(self.client.get_namespace_index(NAMESPACE))

    def run(self, coroutine: Awaitable[T]) -> T:
        """Run ``coroutine`` to its end in the session's loop."""
        return self.loop.run_until_complete(coroutine)

    def node(self, name: str) -> ua.NodeId:
        """The NodeId of ``name`` (a field's name, ``sim``, ``X.MC_Reset``)."""
        return ua.NodeId(ua.String(name), ua.Int16(self.ns))

    def close(self) -> None:
        """Disconnect and close the loop."""
        self.run(self.client.disconnect())
        self.loop.close()


@contextmanager
def session(*options: str) -> Iterator[Session]:
    """The gantry's OPC UA server in its own process and a session on it."""
    with (
        tempfile.TemporaryDirectory() as scratch,
        opcua_server("gantry", Path(scratch) / "stderr.txt", *options) as port,
    ):
        s = Session(port)
        try:
            yield s
        finally:
            s.close()


class OpcuaPlc(LockstepPlc):
    """A PLC on the gantry's lockstep OPC UA server with a 10 ms cycle (as
    :class:`tests.benchmarks.bridge.LockstepPlc` on the Modbus one)."""

    def __init__(self, s: Session) -> None:
        self.s = s
        self.target = 0
        self.cycles = 0
        self.words = {axis: -1 for axis in TABLE.axes}
        self.status = {axis: 0 for axis in TABLE.axes}
        self.status_nodes = [s.node(f"{axis}.status") for axis in TABLE.axes]
        self.advance = ua.CallMethodRequest(
            ObjectId=s.node("sim"),
            MethodId=s.node("sim.Advance"),
            InputArguments=[ua.Variant(STEP_CYCLES, ua.VariantType.UInt32)],
        )

    def command(self, axis: str, word: int, **params: float) -> None:
        """Parameters and the control word of ``axis``, in one Write."""
        values = {f"{axis}.{name}": value for name, value in params.items()}
        if word != self.words[axis]:
            values[f"{axis}.control"] = word
            self.words[axis] = word
        if not values:
            return
        nodes = [self.s.node(name) for name in values]
        data = [ua.DataValue(ua_variant(TABLE, n, v)) for n, v in values.items()]
        for status in self.s.run(self.s.client.uaclient.write_attributes(nodes, data)):
            status.check()

    def cycle(self) -> None:
        """One PLC cycle: Advance(5), answered when the scene is there; the status words."""
        self.target += STEP_CYCLES
        self.cycles += 1
        result = self.s.run(self.s.client.uaclient.call([self.advance]))[0]
        result.StatusCode.check()
        values = self.s.run(
            self.s.client.uaclient.read_attributes(self.status_nodes, ua.AttributeIds.Value)
        )
        for axis, value in zip(TABLE.axes, values, strict=True):
            self.status[axis] = int(value.Value.Value) if value.Value else 0


def measure() -> dict[str, Any]:
    """The latencies and the lockstep demo's real-time factor."""
    with session() as s:
        nodes = [s.node(f"X.{name}") for name in STATUS_FIELDS]
        uaclient = s.client.uaclient
        read = latency(lambda: s.run(uaclient.read_attributes(nodes, ua.AttributeIds.Value)))
        control = [s.node("X.control")]
        zero = [ua.DataValue(ua.Variant(0, ua.VariantType.UInt16))]
        write = latency(lambda: s.run(uaclient.write_attributes(control, zero)))
        reset = ua.CallMethodRequest(ObjectId=s.node("X"), MethodId=s.node("X.MC_Reset"))
        call = latency(lambda: s.run(uaclient.call([reset])))
    with session("--lockstep") as s:
        factor = lockstep(OpcuaPlc(s))
    return {
        "read_status": read,
        "write_command": write,
        "call_method": call,
        "lockstep_gantry_demo_10ms": factor,
    }


if __name__ == "__main__":
    print(json.dumps(measure(), indent=2))
