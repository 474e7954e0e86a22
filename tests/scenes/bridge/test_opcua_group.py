"""The group's OPC UA methods, called by an asyncua client of a lockstep server in its own
process: the gantry's axes powered, the group enabled by MC_GroupEnable, a line and a full
circle by MC_MoveLinearRelative and MC_MoveCircularRelative, a path of a line and a half circle
by AppendLine, AppendArc and MC_MovePath, measured at the actual positions (the encoders on the
physics' joints); points of a wrong length or with a NaN refused with Bad status codes; a line
at 50 % override (MC_GroupSetOverride), held and resumed (MC_GroupInterrupt, MC_GroupContinue),
halted (MC_GroupHalt); MC_GroupStop, MC_GroupReset and MC_GroupDisable."""

from __future__ import annotations

import asyncio
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from asyncua import Client, ua

import mcl
from mcl.geometry import Line, arc
from plc.operator.group_bus import GROUP_STATUS_BITS
from tests.bridge_clients import NAMESPACE, opcua_server

pytestmark = pytest.mark.once  # see the marker in pyproject.toml

D = ua.VariantType.Double
U16 = ua.VariantType.UInt16
U32 = ua.VariantType.UInt32
codes = ua.StatusCodes


def bad(status: ua.StatusCode, code: int) -> bool:
    return status.value == code


def point(*values: float) -> ua.Variant:
    return ua.Variant(list(values), D, is_array=True)


def motion(
    velocity: float = 50.0, buffer_mode: int = 0, coord_system: int | None = None
) -> list[ua.Variant]:
    """Velocity, Acceleration, Deceleration, Jerk, a move's CoordSystem (None: a segment's
    arguments, which have none) and BufferMode."""
    ramp = [ua.Variant(v, D) for v in (velocity, 2000.0, 2000.0, 20000.0)]
    coord = [] if coord_system is None else [ua.Variant(coord_system, U16)]
    return [*ramp, *coord, ua.Variant(buffer_mode, U16)]


def move(velocity: float = 50.0) -> list[ua.Variant]:
    """A move's dynamics in ACS (the gantry has no kinematics: ACS is the machine's frame)."""
    return motion(velocity, coord_system=int(mcl.MC_COORD_SYSTEM.ACS))


def circle(radius: float, coord_system: int | None = 0) -> list[ua.Variant]:
    """A full counter-clockwise circle in XY by its centre, relative to the start."""
    return [
        ua.Variant(int(mcl.MC_CIRC_MODE.CENTER), U16),
        point(radius, 0.0, 0.0),
        point(0.0, 0.0, 0.0),
        ua.Variant(int(mcl.MC_CIRC_PATHCHOICE.COUNTERCLOCKWISE), U16),
        ua.Variant(17, U16),
        ua.Variant(0, U16),
        *motion(coord_system=coord_system),
    ]


class Gantry:
    """A client's handles on the gantry's nodes."""

    def __init__(self, client: Client, ns: int) -> None:
        self.client, self.ns = client, ns

    def node(self, name: str) -> Any:
        return self.client.get_node(f"ns={self.ns};s={name}")

    async def value(self, name: str) -> Any:
        return await self.node(name).read_value()

    async def call(self, obj: str, method: str, *args: ua.Variant) -> ua.CallMethodResult:
        request = ua.CallMethodRequest(
            ObjectId=self.node(obj).nodeid,
            MethodId=self.node(f"{obj}.{method}").nodeid,
            InputArguments=list(args),
        )
        return (await self.client.uaclient.call([request]))[0]

    async def group(self, method: str, *args: ua.Variant) -> None:
        result = await self.call("group", method, *args)
        assert result.StatusCode.is_good(), (method, result.StatusCode)

    async def advance(self, cycles: int) -> None:
        """Run ``cycles`` PLC cycles. Advance answers once the scene is there, or after 2 s with
        the cycle it has reached (a loaded computer): then Advance(0) waits for the rest."""
        sim = self.node("sim")
        reached = await sim.call_method(f"{self.ns}:Advance", ua.Variant(cycles, U32))
        target = await self.value("sim.target")
        for _ in range(100):
            if reached >= target:
                return
            reached = await sim.call_method(f"{self.ns}:Advance", ua.Variant(0, U32))
        raise AssertionError(f"the scene stands at cycle {reached}, short of {target}")

    async def actual(self) -> np.ndarray:
        """The members' actual positions X, Y, Z [mm]."""
        return np.array([await self.value(f"{a}.actual_position") for a in "XYZ"])

    async def status(self, name: str) -> bool:
        return bool(int(await self.value("group.status")) >> GROUP_STATUS_BITS.index(name) & 1)

    async def run_until_done(self, seconds: float) -> np.ndarray:
        """Advance until the group's command is done; the actual positions every 10 cycles."""
        samples = []
        for _ in range(int(seconds * 100)):
            await self.advance(10)
            samples.append(await self.actual())
            if await self.status("done"):
                return np.array(samples)
        state = [await self.value(f"group.{n}") for n in ("state", "status", "error_id")]
        raise AssertionError(f"not done within {seconds} s: {state} {samples[-1]}")


async def enable(g: Gantry) -> None:
    """The axes powered (MC_Power), the group enabled (MC_GroupEnable)."""
    names = {(await m.read_browse_name()).Name for m in await g.node("group").get_methods()}
    assert {"MC_GroupEnable", "MC_MoveCircularAbsolute", "MC_MovePath", "MC_GroupStop"} <= names
    for axis in "XYZ":
        result = await g.call(axis, "MC_Power", ua.Variant(True))
        assert result.StatusCode.is_good()
    await g.group("MC_GroupEnable")
    for _ in range(100):
        await g.advance(10)
        if await g.status("enabled"):
            break
    assert await g.value("group.state") == mcl.GroupState.GroupStandby


async def refusals(g: Gantry) -> None:
    """A point of two values, a NaN, a scalar for a point, a missing argument: refused, and no
    command starts."""
    count = await g.value("group.command_count")
    short = circle(30.0)
    short[1] = point(30.0, 0.0)
    result = await g.call("group", "MC_MoveCircularRelative", *short)
    assert bad(result.StatusCode, codes.BadInvalidArgument)
    assert bad(result.InputArgumentResults[1], codes.BadOutOfRange)
    assert all(r.is_good() for k, r in enumerate(result.InputArgumentResults) if k != 1)
    nan = [point(math.nan, 0.0, 0.0), *move()]
    result = await g.call("group", "MC_MoveLinearRelative", *nan)
    assert bad(result.InputArgumentResults[0], codes.BadOutOfRange)
    scalar = [ua.Variant(10.0, D), *move()]
    result = await g.call("group", "MC_MoveLinearAbsolute", *scalar)
    assert bad(result.InputArgumentResults[0], codes.BadTypeMismatch)
    result = await g.call("group", "MC_GroupStop", ua.Variant(1.0, D))
    assert bad(result.StatusCode, codes.BadArgumentsMissing)
    result = await g.call("group", "MC_GroupSetOverride", *[ua.Variant(math.inf, D)] * 3)
    assert bad(result.InputArgumentResults[0], codes.BadOutOfRange)
    await g.advance(20)
    assert await g.value("group.command_count") == count


async def line_and_circle(g: Gantry) -> None:
    """A line away from the limit switches, then a full circle of R = 30 mm: every actual
    position on it, back at the start."""
    start = await g.actual()
    await g.group("MC_MoveLinearRelative", point(100.0, 80.0, 0.0), *move(velocity=200.0))
    await g.run_until_done(5.0)
    await g.advance(200)
    assert await g.actual() - start == pytest.approx([100.0, 80.0, 0.0], abs=0.005)
    start = await g.actual()
    count = await g.value("group.command_count")
    await g.group("MC_MoveCircularRelative", *circle(30.0))
    points = await g.run_until_done(10.0) - start
    assert await g.value("group.command_count") == count + 1
    radius = np.linalg.norm(points[:, :2] - np.array([30.0, 0.0]), axis=1)
    assert np.abs(radius - 30.0).max() < 0.010
    assert np.abs(points[:, 2]).max() < 0.010
    angles = np.unwrap(np.arctan2(points[:, 1], points[:, 0] - 30.0))
    assert angles[-1] - angles[0] == pytest.approx(2 * math.pi, abs=0.02)
    await g.advance(200)
    assert np.abs(await g.actual() - start).max() < 0.005


async def path(g: Gantry) -> None:
    """A path of a line and a tangent half circle by its centre (AppendLine, AppendArc,
    MC_MovePath): the actual positions on it."""
    start = await g.actual()
    await g.group("ClearPath")
    line = [point(40.0, 0.0, 0.0), *motion(buffer_mode=mcl.MC_BufferMode.BlendingLow)]
    await g.group("AppendLine", *line, ua.Variant(True))
    await g.advance(2)  # one command a scan: the next call takes over from this one
    half = circle(10.0, coord_system=None)
    half[1], half[2] = point(0.0, 10.0, 0.0), point(0.0, 20.0, 0.0)
    await g.group("AppendArc", *half, ua.Variant(True))
    await g.advance(2)
    assert await g.value("group.segments") == 2
    await g.group("MC_MovePath", ua.Variant(0, U16), ua.Variant(0, U16))
    points = await g.run_until_done(10.0) - start
    pieces = [
        Line([0.0, 0.0], [40.0, 0.0]),
        arc([40.0, 0.0], mcl.MC_CIRC_MODE.CENTER, [40.0, 10.0], [40.0, 20.0], 1),
    ]
    assert max(min(piece.distance(p[:2]) for piece in pieces) for p in points) < 0.020
    assert points[:, 0].max() == pytest.approx(50.0, abs=0.02)  # around the half circle
    await g.advance(200)
    assert (await g.actual() - start)[:2] == pytest.approx([40.0, 20.0], abs=0.005)


async def speed(g: Gantry) -> float:
    """The path speed over the next 50 cycles (0.1 s) [mm/s]."""
    before = await g.actual()
    await g.advance(50)
    return float(np.linalg.norm(await g.actual() - before)) / 0.1


async def hold_override_halt(g: Gantry) -> None:
    """At 50 % override a line runs at half its velocity; interrupted it stands, continued it
    ends at its end; back at 100 % a halt stops the next line on the way, in GroupStandby."""
    start = await g.actual()
    await g.group("MC_GroupSetOverride", *[ua.Variant(v, D) for v in (0.5, 1.0, 1.0)])
    await g.advance(2)
    assert await g.status("done")
    await g.group("MC_MoveLinearRelative", point(-40.0, 0.0, 0.0), *move())
    await g.advance(300)
    assert await speed(g) == pytest.approx(25.0, abs=0.5)
    await g.group("MC_GroupInterrupt", ua.Variant(2000.0, D), ua.Variant(0.0, D))
    await g.advance(100)
    held = await g.actual()
    await g.advance(100)
    # the path stands: X, the line's axis, to the count; a standing axis whose carriage rests
    # on an encoder edge may show the neighbouring count
    assert (np.round(np.abs(await g.actual() - held) * 1000.0) <= [0, 1, 1]).all()
    assert 1.0 < start[0] - held[0] < 39.0
    await g.group("MC_GroupContinue")
    await g.advance(100)
    assert await speed(g) == pytest.approx(25.0, abs=0.5)
    await g.advance(1500)
    assert await g.actual() - start == pytest.approx([-40.0, 0.0, 0.0], abs=0.005)
    await g.group("MC_GroupSetOverride", *[ua.Variant(1.0, D)] * 3)
    await g.advance(2)
    await g.group("MC_MoveLinearRelative", point(40.0, 0.0, 0.0), *move())
    await g.advance(300)
    assert await speed(g) == pytest.approx(50.0, abs=0.5)
    await g.group("MC_GroupHalt", ua.Variant(2000.0, D), ua.Variant(0.0, D))
    await g.advance(100)
    assert await g.status("done")
    assert await g.value("group.state") == mcl.GroupState.GroupStandby
    halted = await g.actual()
    assert 1.0 < halted[0] - start[0] + 40.0 < 39.0


async def acceleration_factor(g: Gantry) -> None:
    """AccFactor 0 is refused (EParam); AccFactor 0.25 keeps the path's acceleration within a
    quarter, so the line runs at √0.25 of its velocity."""
    await g.group("MC_GroupSetOverride", *[ua.Variant(v, D) for v in (1.0, 0.0, 1.0)])
    await g.advance(2)
    assert await g.status("error")
    assert await g.value("group.error_id") == mcl.ErrorID.EParam
    await g.group("MC_GroupSetOverride", *[ua.Variant(v, D) for v in (1.0, 0.25, 1.0)])
    await g.advance(2)
    assert await g.status("done")
    await g.group("MC_MoveLinearRelative", point(0.0, 20.0, 0.0), *move())
    await g.advance(300)
    assert await speed(g) == pytest.approx(25.0, abs=0.5)
    await g.run_until_done(5.0)
    await g.group("MC_GroupSetOverride", *[ua.Variant(1.0, D)] * 3)
    await g.advance(2)


async def stop_reset_disable(g: Gantry) -> None:
    """A line stopped on the way (GroupStopping while the stop holds), reset, disabled."""
    start = await g.actual()
    await g.group("MC_MoveLinearRelative", point(-30.0, 0.0, 0.0), *move())
    await g.advance(200)
    await g.group("MC_GroupStop", ua.Variant(2000.0, D), ua.Variant(0.0, D))
    await g.advance(300)
    assert await g.value("group.state") == mcl.GroupState.GroupStopping
    stopped = await g.actual()
    assert 0.5 < start[0] - stopped[0] < 29.5  # stopped between the line's ends
    await g.group("MC_GroupReset")
    await g.advance(20)
    assert await g.value("group.state") == mcl.GroupState.GroupStandby
    await g.group("MC_GroupDisable")
    await g.advance(50)
    assert await g.value("group.state") == mcl.GroupState.GroupDisabled
    assert not await g.status("enabled")


async def session(port: int) -> None:
    async with Client(f"opc.tcp://127.0.0.1:{port}/", timeout=10) as client:
        g = Gantry(client, await client.get_namespace_index(NAMESPACE))
        for phase in (
            enable,
            refusals,
            line_and_circle,
            path,
            hold_override_halt,
            acceleration_factor,
        ):
            await phase(g)
        await stop_reset_disable(g)


def test_a_client_commands_the_group_by_its_methods(tmp_path: Path) -> None:
    with opcua_server("gantry", tmp_path / "stderr.txt", "--lockstep") as port:
        asyncio.run(session(port))
