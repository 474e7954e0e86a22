"""An OPC UA client (asyncua) that homes the gantry's X axis and moves it to 300 mm through the
PLCopen methods, as an external PLC would (docs/bridge.md). Start the server first:

    python -m scenes bridge opcua gantry --port 4840
    python examples/bridge_opcua_client.py --port 4840
"""

from __future__ import annotations

import argparse
import asyncio
import time
from collections.abc import Awaitable, Callable
from typing import Any

from asyncua import Client, ua

NAMESPACE = "urn:mcl-testbench:bridge"
"""The bridge's namespace; a variable's NodeId is ``ns=<its index>;s=<field name>``."""

COMMANDS = {"home": 6, "move_absolute": 3}
"""``X.command`` while a command is the current one: its control bit + 1 (docs/bridge.md)."""


class Axis:
    """The nodes of one axis of the machine."""

    def __init__(self, client: Client, ns: int, name: str) -> None:
        self.client, self.ns, self.name = client, ns, name
        self.object = client.get_node(f"ns={ns};s={name}")

    async def value(self, field: str) -> Any:
        """The value of the axis' variable ``field`` (``status.done``, ``actual_position``)."""
        return await self.client.get_node(f"ns={self.ns};s={self.name}.{field}").read_value()

    async def call(self, method: str, *args: ua.Variant) -> None:
        """Call the PLCopen method ``method`` of the axis."""
        await self.object.call_method(f"{self.ns}:{method}", *args)

    async def done(self, command: str, before: int) -> bool:
        """``command``, started after number ``before`` of ``command_count``, is Done (its
        Error raises): the handshake of docs/bridge.md."""
        if await self.value("command_count") == before:
            return False  # not started yet: the status is still the last command's
        if await self.value("command") != COMMANDS[command]:
            raise RuntimeError(f"{command}: another command started")
        if await self.value("status.error"):
            raise RuntimeError(f"{command}: ErrorID {await self.value('error_id')}")
        return bool(await self.value("status.done"))


async def wait(condition: Callable[[], Awaitable[bool]], seconds: float) -> None:
    """Poll ``condition`` every 20 ms for at most ``seconds``."""
    deadline = time.monotonic() + seconds
    while not await condition():
        if time.monotonic() > deadline:
            raise TimeoutError("no answer in time")
        await asyncio.sleep(0.02)


async def home_and_move(port: int, target: float = 300.0) -> float:
    """Power X, home it with its recipe, move it to ``target`` [mm]; its actual position [mm]."""
    async with Client(f"opc.tcp://127.0.0.1:{port}/", timeout=10) as client:
        x = Axis(client, await client.get_namespace_index(NAMESPACE), "X")
        await x.call("MC_Power", ua.Variant(True, ua.VariantType.Boolean))
        await wait(lambda: x.value("status.power"), 5.0)
        before = await x.value("command_count")
        await x.call("MC_Home")
        await wait(lambda: x.done("home", before), 30.0)
        # MC_MoveAbsolute(Position, Velocity, Acceleration, Deceleration, Jerk, BufferMode)
        ramp = [ua.Variant(v, ua.VariantType.Double) for v in (target, 200.0, 1000.0, 1000.0, 0.0)]
        before = await x.value("command_count")
        await x.call("MC_MoveAbsolute", *ramp, ua.Variant(0, ua.VariantType.UInt16))
        await wait(lambda: x.done("move_absolute", before), 15.0)
        return float(await x.value("actual_position"))


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--port", type=int, default=4840)
    parser.add_argument("--position", type=float, default=300.0, help="target of X [mm]")
    args = parser.parse_args()
    print(f"X at {asyncio.run(home_and_move(args.port, args.position)):.3f} mm")
