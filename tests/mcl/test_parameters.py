"""Bad parameters and bad axis states give Error with the documented code and do not touch
the axis.

A parameter error (out of range, NaN, infinite, wrong sign, target beyond the SW
limit) raises Error/ErrorID on that instance and the axis keeps doing what it did. The same holds
for a command refused because of the axis state (Ehome, Epower, Eerrstop, Econst, EAxStop,
EpowerOff).

Every case is run twice on identical, deterministic machines: once with the bad call issued in the
middle of the scenario (a running move, a stop ramp, an error stop ramp, a standing axis ...) and
once without it. The two recordings of the axis (state, positions, velocities, analog output,
error code) and of the running block's outputs must be identical scan by scan, and the running move
still reaches its target.

Also: values above the axis maxima are clamped, not refused; 0 for Acceleration, Deceleration
and Jerk means the axis default (docs/reference.md, Units).
"""

from __future__ import annotations

import functools
import itertools
import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Any

import pytest

import mcl
from mcl import AxisState, ErrorID, MC_Direction
from tests.helpers import CONSTANTS, configure, power_on, scan

PLC = 0.002
LIMITS = {"LimNeg": -100.0, "LimPos": 700.0}
"""Software limits of the test axis [mm] (active: LimPos > LimNeg)."""
TARGET = 300.0
"""Target of the running move of the "moving" scenarios [mm]."""
NAN, INF = math.nan, math.inf

MOTION_FBS = (
    "MC_MoveAbsolute",
    "GT_MoveAbsBlock",
    "MC_MoveRelative",
    "MC_MoveAdditive",
    "MC_MoveVelocity",
    "MC_Halt",
    "MC_Stop",
    "GT_Jog",
)

VALID: dict[str, dict[str, Any]] = {
    "MC_MoveAbsolute": {"Position": 250.0, "Velocity": 100.0},
    "GT_MoveAbsBlock": {"Position": 250.0, "Velocity": 100.0},
    "MC_MoveRelative": {"Distance": 50.0, "Velocity": 100.0},
    "MC_MoveAdditive": {"Distance": 50.0, "Velocity": 100.0},
    "MC_MoveVelocity": {"Velocity": 100.0, "Direction": MC_Direction.MC_Positive},
    "MC_Halt": {},
    "MC_Stop": {},
    "GT_Jog": {"JogVelo": 100.0, "JogPos": True},
    "GT_SetConstant": {**CONSTANTS, **LIMITS},
    "MC_Power": {"SpeedMode": 0},
    "GT_Analog": {"Analog": -200, "Par": 0},
    "GT_SInfo": {"What1": 23, "What2": 22},
}
"""Inputs each block accepts (used together with one bad input, or in a bad axis state)."""

TRIGGER = {"MC_Power": "Enable", "GT_Jog": "Enable"}
"""The level that starts the block (default: Execute)."""


# ---------------------------------------------------------------------------- scenarios
@dataclass
class Scenario:
    """A machine doing something, into which the bad call is dropped.

    Attributes:
        program: the PLC program that keeps the scenario going (called every scan).
        ready: when the bad call is issued.
        running: the block that controls the axis (its outputs are recorded), if any.
        scans: how many scans are recorded after the bad call.
        target: where the running move must end [mm], if it is a move.
    """

    machine: mcl.SimMachine
    axis: mcl.Axis
    program: Callable[[], None]
    ready: Callable[[], bool]
    running: list[Any] = field(default_factory=list)
    scans: int = 150
    target: float | None = None


def machine(
    constants: bool = True, config: mcl.AxisConfig | None = None, **overrides: float
) -> tuple[mcl.SimMachine, mcl.Axis]:
    m = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2)}, config=config)
    axis = m.axes["X"]
    if constants:
        configure(axis, **{**LIMITS, **overrides})
    return m, axis


def modulo_machine() -> tuple[mcl.SimMachine, mcl.Axis]:
    params = mcl.SimAxisParams(stop_neg=-1e6, stop_pos=1e6, lim_neg=-1e6, lim_pos=1e6)
    m = mcl.SimMachine({"R": params}, config=mcl.AxisConfig(modulo=360.0))
    axis = m.axes["R"]
    configure(axis)
    return m, axis


def after(m: mcl.SimMachine, seconds: float) -> Callable[[], bool]:
    start = m.time
    return lambda: m.time >= start + seconds - 1e-9


def standstill(referenced: bool = True) -> Scenario:
    m, x = machine()
    power = power_on(m, x, referenced)
    return Scenario(m, x, lambda: power(Axis=x, Enable=True), after(m, 0.05))


def moving(referenced: bool = True) -> Scenario:
    """A move to TARGET at 200 mm/s, caught at 100 mm."""
    m, x = machine()
    power = power_on(m, x, referenced)
    move: Any
    if referenced:
        move = mcl.MC_MoveAbsolute()
        inputs: dict[str, Any] = {"Position": TARGET}
    else:
        move = mcl.MC_MoveRelative()
        inputs = {"Distance": TARGET}

    def program() -> None:
        power(Axis=x, Enable=True)
        move(Axis=x, Execute=True, Velocity=200.0, **inputs)

    return Scenario(m, x, program, lambda: x.POS >= 100.0, [move], scans=800, target=TARGET)


def disabled() -> Scenario:
    m, x = machine()
    return Scenario(m, x, lambda: None, after(m, 0.05))


def unconfigured() -> Scenario:
    m, x = machine(constants=False)
    return Scenario(m, x, lambda: None, after(m, 0.05))


def analog() -> Scenario:
    """Disabled axis driven by GT_Analog (about +0.5 V: the axis drifts forward)."""
    m, x = machine()
    dac = mcl.GT_Analog()
    program = scan(lambda: dac(Axis=x, Execute=True, Analog=-200, Par=0))
    return Scenario(m, x, program, after(m, 0.2), [dac])


def stopping(ramp: bool) -> Scenario:
    """MC_Stop (Execute held) ramping down from 200 mm/s at 200 mm/s², caught in the middle of
    the ramp or after it (still Stopping)."""
    m, x = machine()
    power = power_on(m, x)
    move, stop = mcl.MC_MoveVelocity(), mcl.MC_Stop()

    def program() -> None:
        power(Axis=x, Enable=True)
        move(Axis=x, Execute=True, Velocity=200.0)
        if x.POS >= 100.0 or stop.Busy or stop.Done:
            stop(Axis=x, Execute=True, Deceleration=200.0)

    def ready() -> bool:
        if x.state != AxisState.Stopping:
            return False
        return 50.0 < x.sp_vel < 150.0 if ramp else stop.Done

    return Scenario(m, x, program, ready, [move, stop], scans=800 if ramp else 150)


def errorstop(ramp: bool) -> Scenario:
    """A velocity move runs over the SW limit 150 mm: ERRSWP, error stop ramp at 400 mm/s²;
    caught in the middle of the ramp or after it."""
    m, x = machine(config=mcl.AxisConfig(max_deceleration=400.0), LimPos=150.0)
    power = power_on(m, x)
    move = mcl.MC_MoveVelocity()

    def program() -> None:
        power(Axis=x, Enable=True)
        move(Axis=x, Execute=True, Velocity=200.0)

    def ready() -> bool:
        if x.state != AxisState.ErrorStop:
            return False
        return 50.0 < x.sp_vel < 150.0 if ramp else x.sp_vel == 0.0

    return Scenario(m, x, program, ready, [move], scans=800 if ramp else 150)


def modulo(move: bool) -> Scenario:
    """Rotary axis (360°), standing or turning from 0° to 300° the positive way."""
    m, x = modulo_machine()
    power = power_on(m, x)
    if not move:
        return Scenario(m, x, lambda: power(Axis=x, Enable=True), after(m, 0.05))
    mv = mcl.MC_MoveAbsolute()
    positive = MC_Direction.MC_Positive
    program = scan(
        lambda: power(Axis=x, Enable=True),
        lambda: mv(Axis=x, Execute=True, Position=300.0, Velocity=200.0, Direction=positive),
    )
    return Scenario(m, x, program, lambda: x.POS >= 100.0, [mv], scans=800, target=300.0)


def run_powered(m: mcl.SimMachine, x: mcl.Axis, call: Callable[[], None], **run: Any) -> None:
    """Power `x` and run `call` every scan with MC_Power enabled (`run`: until or timeout)."""
    power = power_on(m, x)
    m.run(scan(lambda: power(Axis=x, Enable=True), call), **run)


SCENARIOS: dict[str, Callable[[], Scenario]] = {
    "standstill": standstill,
    "moving": moving,
    "standstill_unreferenced": lambda: standstill(referenced=False),
    "moving_unreferenced": lambda: moving(referenced=False),
    "disabled": disabled,
    "analog": analog,
    "unconfigured": unconfigured,
    "stop_ramp": lambda: stopping(ramp=True),
    "stopped": lambda: stopping(ramp=False),
    "errorstop_ramp": lambda: errorstop(ramp=True),
    "errorstop": lambda: errorstop(ramp=False),
    "modulo_standstill": lambda: modulo(move=False),
    "modulo_moving": lambda: modulo(move=True),
}


# ---------------------------------------------------------------------------- recording
def snapshot(s: Scenario) -> tuple[Any, ...]:
    x, sim = s.axis, next(iter(s.machine.sims.values()))
    axis = (
        x.state,
        x.POS,
        x.VEL,
        x.volts,
        x.sp_pos,
        x.sp_vel,
        x.AxErrorID,
        x.Ref,
        x.OPT1n,
        x.OPT2n,
        sim.volts,
        sim.enabled,
    )
    outputs = tuple(
        tuple(
            getattr(fb, name, None)
            for name in ("Busy", "Active", "Done", "CommandAborted", "Error", "ErrorID")
        )
        for fb in s.running
    )
    return axis, outputs


FIELDS = "state POS VEL volts sp_pos sp_vel AxErrorID Ref OPT1n OPT2n sim.volts sim.enabled"


@dataclass
class Recording:
    scenario: Scenario
    trace: list[tuple[Any, ...]]
    bad: Any = None
    first: tuple[bool, int] = (False, 0)
    last: tuple[bool, int] = (False, 0)
    aborted: bool = False
    done: bool = False


def record(context: str, fb_name: str | None, inputs: dict[str, Any]) -> Recording:
    """Run the scenario to its ready point, then ``scans`` scans; with ``fb_name`` a new instance
    of that block is called in every one of them (inputs on the first, trigger held)."""
    s = SCENARIOS[context]()
    s.machine.run(s.program, until=s.ready, timeout=10.0)
    rec = Recording(s, [snapshot(s)])
    bad = getattr(mcl, fb_name)() if fb_name else None
    rec.bad = bad
    trigger = TRIGGER.get(fb_name or "", "Execute")
    for n in range(s.scans):

        def program(n: int = n) -> None:
            s.program()
            if bad is not None:
                bad(Axis=s.axis, **({**inputs, trigger: True} if n == 0 else {trigger: True}))
                if n == 0:
                    rec.first = (bool(bad.Error), int(bad.ErrorID))

        s.machine.run(program, timeout=PLC)
        rec.trace.append(snapshot(s))
        for fb in s.running:
            rec.aborted |= bool(getattr(fb, "CommandAborted", False))
            rec.done |= bool(getattr(fb, "Done", False))
    if bad is not None:
        rec.last = (bool(bad.Error), int(bad.ErrorID))
    return rec


def assert_untouched(context: str, fb_name: str, inputs: dict[str, Any], expected: int) -> None:
    with_bad = record(context, fb_name, inputs)
    assert with_bad.first == (True, expected), (
        f"{fb_name}{inputs} in {context}: (Error, ErrorID) = {with_bad.first}, "
        f"expected (True, {expected})"
    )
    assert with_bad.last == (True, expected), "Error must stay while Execute/Enable is TRUE"
    reference = record(context, None, {})
    for n, (got, want) in enumerate(zip(with_bad.trace, reference.trace, strict=True)):
        if got != want:
            diff = [
                f"{name}: {g!r} != {w!r}"
                for name, g, w in zip(FIELDS.split(), got[0], want[0], strict=True)
                if g != w
            ]
            pytest.fail(
                f"the bad {fb_name} call touched the axis ({context}), scan {n}: "
                f"{'; '.join(diff) or f'running block outputs {got[1]} != {want[1]}'}"
            )
    s = with_bad.scenario
    if s.target is not None:  # the running move goes on to its target
        assert not with_bad.aborted, "the running move was aborted"
        assert with_bad.done, "the running move did not end Done"
        assert abs(s.axis.POS - s.target) < 0.05, f"POS {s.axis.POS}, target {s.target}"
        assert s.axis.state == AxisState.StandStill


# ---------------------------------------------------------------------------- the table
PARAM_CONTEXTS = ("standstill", "moving")


@dataclass(frozen=True)
class Bad:
    fb: str
    inputs: dict[str, Any]
    expected: int
    contexts: tuple[str, ...] = PARAM_CONTEXTS


def bad_values(fbs: Iterable[str], name: str, values: Iterable[Any], **kw: Any) -> list[Bad]:
    expected = kw.pop("expected", ErrorID.EParam)
    return [Bad(fb, {**VALID[fb], name: value}, expected, **kw) for fb in fbs for value in values]


MOVES = ("MC_MoveAbsolute", "GT_MoveAbsBlock", "MC_MoveRelative", "MC_MoveAdditive")
VELOCITY_FBS = (*MOVES, "MC_MoveVelocity")
BAD_VELOCITY = [NAN, INF, -INF, -100.0, 0.0, -0.0, 4.99, 1e-300]
"""Velocity <= 0, NaN, infinite, below 1 % of Vmax (500 mm/s → 5 mm/s)."""
BAD_RAMP = [NAN, INF, -INF, -1.0, -1e-9]
"""Acceleration, Deceleration, Jerk: negative, NaN, infinite (0 = axis default is valid)."""
SLOW_RAMP = [0.99, 1e-6]
"""Too small to reach 100 mm/s within 100 s."""
BAD_BUFFER_MODE = [-1, 6, 255, 32767]
NOT_FINITE = [NAN, INF, -INF]

CASES: list[Bad] = [
    # ---- velocity, ramps, BufferMode of every motion block
    *bad_values(VELOCITY_FBS, "Velocity", BAD_VELOCITY),
    *bad_values(VELOCITY_FBS, "Acceleration", BAD_RAMP + SLOW_RAMP),
    *bad_values(VELOCITY_FBS, "Deceleration", BAD_RAMP + SLOW_RAMP),
    *bad_values(VELOCITY_FBS, "Jerk", BAD_RAMP),
    *bad_values((*VELOCITY_FBS, "MC_Halt", "MC_Stop"), "BufferMode", BAD_BUFFER_MODE),
    *bad_values(("MC_Halt", "MC_Stop"), "Deceleration", BAD_RAMP),
    *bad_values(("MC_Halt", "MC_Stop"), "Jerk", BAD_RAMP),
    # ---- targets
    *bad_values(("MC_MoveAbsolute", "GT_MoveAbsBlock"), "Position", NOT_FINITE),
    *bad_values(("MC_MoveRelative", "MC_MoveAdditive"), "Distance", NOT_FINITE),
    *bad_values(("GT_MoveAbsBlock",), "TorqueLimit", [NAN, INF, -INF, -1.0]),
    *bad_values(
        ("MC_MoveAbsolute", "GT_MoveAbsBlock"), "Position", [750.0, -150.0], expected=ErrorID.Ecil
    ),
    *bad_values(
        ("MC_MoveRelative", "MC_MoveAdditive"), "Distance", [1000.0, -1000.0], expected=ErrorID.Ecil
    ),
    # ---- Direction
    *bad_values(("MC_MoveVelocity",), "Direction", [0, MC_Direction.MC_Shortest, 5, 6, 99, NAN]),
    *bad_values(
        ("MC_MoveAbsolute", "GT_MoveAbsBlock"),
        "Direction",
        [0, 5, 6, 99, -1, NAN],
        contexts=("modulo_standstill", "modulo_moving"),
    ),
    # ---- GT_Jog (pressed JogPos)
    *bad_values(("GT_Jog",), "JogVelo", BAD_VELOCITY),
    *bad_values(("GT_Jog",), "JogAcc", BAD_RAMP + SLOW_RAMP),
    *bad_values(("GT_Jog",), "JogDec", BAD_RAMP + SLOW_RAMP),
    *bad_values(("GT_Jog",), "JogJerk", BAD_RAMP),
    # ---- administrative blocks
    *bad_values(("GT_SetConstant",), "Vmax", [NAN, INF, -INF, 0.0, -500.0]),
    *(
        bad
        for name in ("Kp", "Ki", "Kd", "Ff", "Kc", "Ki1", "Filter", "Ka")
        for bad in bad_values(("GT_SetConstant",), name, [NAN, INF, -1.0])
    ),
    *bad_values(("GT_SetConstant",), "LimPos", NOT_FINITE),
    *bad_values(("GT_SetConstant",), "LimNeg", NOT_FINITE),
    *bad_values(("MC_Power",), "SpeedMode", [2, -1, 255, NAN, 0.5]),
    *bad_values(("GT_SInfo",), "What1", [19, 25, 0, -20, NAN]),
    *bad_values(("GT_SInfo",), "What2", [19, 25, NAN]),
    *bad_values(
        ("GT_Analog",), "Analog", [4096, -4096, 32767, NAN, INF], contexts=("disabled", "analog")
    ),
    *bad_values(("GT_Analog",), "Par", [2, -1, NAN], contexts=("disabled", "analog")),
    # ---- valid inputs, wrong axis state
    Bad("GT_Analog", VALID["GT_Analog"], ErrorID.EpowerOff),
    *(
        Bad(fb, VALID[fb], ErrorID.Ehome, ("standstill_unreferenced", "moving_unreferenced"))
        for fb in ("MC_MoveAbsolute", "GT_MoveAbsBlock")
    ),
    *(Bad(fb, VALID[fb], ErrorID.Epower, ("disabled", "analog")) for fb in MOTION_FBS),
    *(Bad(fb, VALID[fb], ErrorID.Econst, ("unconfigured",)) for fb in (*MOTION_FBS, "MC_Power")),
    *(Bad(fb, VALID[fb], ErrorID.Eerrstop, ("errorstop_ramp", "errorstop")) for fb in MOTION_FBS),
    *(
        Bad(fb, VALID[fb], ErrorID.EAxStop, ("stop_ramp", "stopped"))
        for fb in MOTION_FBS
        if fb != "MC_Stop"
    ),
]


def case_id(bad: Bad, context: str) -> str:
    changed = {k: v for k, v in bad.inputs.items() if VALID[bad.fb].get(k, object()) != v}
    what = ",".join(f"{k}={v!r}" for k, v in changed.items()) or "valid"
    return f"{bad.fb}[{what}]-{context}-E{bad.expected}"


PARAMS = [
    pytest.param(bad, context, id=case_id(bad, context))
    for bad in CASES
    for context in bad.contexts
]


@pytest.mark.parametrize(("bad", "context"), PARAMS)
def test_bad_call_errors_and_leaves_axis_untouched(bad: Bad, context: str):
    assert_untouched(context, bad.fb, bad.inputs, bad.expected)


# ---------------------------------------------------------------------------- same instance
@pytest.mark.parametrize(
    ("name", "value"),
    [("Velocity", NAN), ("Velocity", -100.0), ("Acceleration", -1.0), ("Position", INF)],
)
def test_bad_new_edge_on_the_running_instance_leaves_its_move_running(name: str, value: float):
    """Rules 7 and 9: a new Execute edge with a bad input on the busy instance reports Error;
    the axis goes on with the move it was doing (identical to a run where Execute just fell)."""

    def run(bad: bool) -> tuple[list[tuple[Any, ...]], mcl.MC_MoveAbsolute]:
        m, x = machine()
        move = mcl.MC_MoveAbsolute()
        start = functools.partial(move, Axis=x, Execute=True, Position=TARGET, Velocity=200.0)
        run_powered(m, x, start, until=lambda: x.POS >= 100.0)
        m.run(lambda: move(Axis=x, Execute=False), timeout=PLC)
        if bad:
            move(Axis=x, Execute=True, **{name: value})
            assert (move.Error, move.ErrorID) == (True, ErrorID.EParam)
        trace = []
        for _ in range(800):
            m.run(lambda: move(Axis=x), timeout=PLC)
            trace.append((x.state, x.POS, x.sp_pos, x.sp_vel, x.volts))
        assert abs(x.POS - TARGET) < 0.05
        assert x.state == AxisState.StandStill
        return trace, move

    reference, _ = run(bad=False)
    trace, move = run(bad=True)
    assert trace == reference
    assert move.Error and move.ErrorID == ErrorID.EParam  # Execute still TRUE: still shown
    assert not move.Done and not move.CommandAborted


# ---------------------------------------------------------------------------- GT_Jog
@pytest.mark.parametrize(
    ("button", "inputs"),
    [
        ("JogPos", {"JogVelo": NAN}),
        ("JogPos", {"JogJerk": -1.0}),
        ("JogNeg", {"JogVelo": 0.0}),
        ("JogNeg", {"JogAcc": INF}),
    ],
)
def test_jog_press_with_bad_input_during_its_own_ramp(button: str, inputs: dict[str, float]):
    """GT_Jog running, then a button pressed with a bad input: Error EParam, the axis keeps doing
    what it did (a parameter error leaves the axis alone) and Busy and Error are not both TRUE."""

    def run(bad: bool) -> tuple[list[tuple[Any, ...]], list[tuple[bool, int, bool]]]:
        m, x = machine()
        jog = mcl.GT_Jog()
        start = functools.partial(
            jog, Axis=x, Enable=True, JogPos=True, JogVelo=200.0, JogDec=200.0
        )
        run_powered(m, x, start, timeout=0.5)
        m.run(lambda: jog(Axis=x, JogPos=False), timeout=0.2)  # released: ramps down (1 s)
        trace: list[tuple[Any, ...]] = []
        outputs: list[tuple[bool, int, bool]] = []
        for n in range(600):
            press: dict[str, Any] = {button: True, **inputs} if bad and n == 0 else {}
            m.run(functools.partial(jog, Axis=x, **press), timeout=PLC)
            trace.append((x.state, x.POS, x.sp_pos, x.sp_vel, x.volts))
            outputs.append((jog.Error, jog.ErrorID, jog.Busy))
        return trace, outputs

    reference, _ = run(bad=False)
    trace, outputs = run(bad=True)
    assert trace == reference
    assert outputs[0][:2] == (True, ErrorID.EParam)
    assert not any(e and b for e, _, b in outputs), "Busy and Error both TRUE"


def test_jog_switching_to_a_refused_direction_still_releases_the_first():
    """Jogging with JogPos, the operator lets go of JogPos and presses JogNeg with a bad JogVelo:
    the negative jog is refused (EParam) and does not touch the axis, so the axis does
    exactly what a plain release of JogPos does: it ramps down to standstill (hold-to-run)."""

    def run(press_neg: bool) -> list[tuple[Any, ...]]:
        m, x = machine()
        jog = mcl.GT_Jog()
        run_powered(
            m,
            x,
            functools.partial(jog, Axis=x, Enable=True, JogPos=True, JogVelo=100.0),
            timeout=0.5,
        )
        jog(Axis=x, JogPos=False, **({"JogNeg": True, "JogVelo": NAN} if press_neg else {}))
        if press_neg:
            assert jog.Error and jog.ErrorID == ErrorID.EParam
        trace = []
        for _ in range(300):
            m.run(functools.partial(jog, Axis=x), timeout=PLC)
            trace.append((x.state, x.POS, x.sp_pos, x.sp_vel, x.volts))
        return trace

    reference = run(press_neg=False)
    assert reference[-1][0] == AxisState.StandStill
    trace = run(press_neg=True)
    assert trace[-1][0] == AxisState.StandStill and trace[-1][3] == 0.0, (
        f"JogPos released, JogNeg refused, yet the axis is {trace[-1][0].name} at "
        f"{trace[-1][3]} mm/s"
    )
    assert trace == reference


# ---------------------------------------------------------------------------- tiny jerk
@pytest.mark.parametrize("jerk", [5e-324, 1e-300])
@pytest.mark.parametrize(
    ("fb_name", "inputs"),
    [
        ("MC_MoveAbsolute", {"Position": 1.0, "Velocity": 5.0}),
        ("MC_MoveAbsolute", {"Position": 250.0, "Velocity": 100.0}),
        ("MC_MoveRelative", {"Distance": 50.0, "Velocity": 100.0}),
        ("MC_MoveVelocity", {"Velocity": 100.0}),
    ],
)
def test_tiny_jerk_never_raises(fb_name: str, inputs: dict[str, float], jerk: float):
    """A positive Jerk so small that no profile can be planned: the block reports EParam and
    the axis stays as it was; it never raises out of the PLC program."""
    m, x = machine()
    power_on(m, x)
    m.run(timeout=0.05)
    before = (x.state, x.POS, x.sp_pos, x.volts)
    fb = getattr(mcl, fb_name)()
    m.run(lambda: fb(Axis=x, Execute=True, Jerk=jerk, **inputs), timeout=PLC)
    if fb.Error:
        assert fb.ErrorID == ErrorID.EParam
        assert (x.state, x.POS, x.sp_pos, x.volts) == before


# ---------------------------------------------------------------------------- clamping
def model_samples(m: mcl.SimMachine, x: mcl.Axis) -> list[tuple[float, float]]:
    """Model velocity and acceleration after every servo cycle."""
    samples: list[tuple[float, float]] = []
    m.runtime.observers.append(lambda t: samples.append((x.sp_vel, x.sp_acc)))
    return samples


def sampled_move(
    fb_name: str = "MC_MoveVelocity",
    *,
    config: mcl.AxisConfig | None = None,
    **inputs: Any,
) -> tuple[mcl.Axis, list[tuple[float, float]], Any]:
    """A powered axis runs `fb_name` (Execute held) until InVelocity (MC_MoveVelocity) or Done.

    Returns the axis, its model samples (velocity, acceleration) and the block."""
    m, x = machine(config=config)
    power_on(m, x)
    samples = model_samples(m, x)
    fb = getattr(mcl, fb_name)()
    output = "InVelocity" if fb_name == "MC_MoveVelocity" else "Done"
    m.run(lambda: fb(Axis=x, Execute=True, **inputs), until=lambda: getattr(fb, output))
    return x, samples, fb


def sampled_stop(
    fb_name: str, deceleration: float, config: mcl.AxisConfig | None = None
) -> tuple[list[tuple[float, float]], Any]:
    """`fb_name` (MC_Stop or MC_Halt) with `deceleration` stops an axis running at 200 mm/s.

    Returns the model samples of the stop (velocity, acceleration) and the stopping block."""
    m, x = machine(config=config)
    move = mcl.MC_MoveVelocity()
    start = functools.partial(move, Axis=x, Execute=True, Velocity=200.0)
    run_powered(m, x, start, until=lambda: move.InVelocity)
    samples = model_samples(m, x)
    stop = getattr(mcl, fb_name)()
    m.run(lambda: stop(Axis=x, Execute=True, Deceleration=deceleration), until=lambda: stop.Done)
    return samples, stop


@pytest.mark.parametrize("velocity", [501.0, 1e6, 1e300, 1.7e308])
def test_velocity_above_vmax_is_clamped(velocity: float):
    x, samples, move = sampled_move(Velocity=velocity)
    assert not move.Error
    assert max(v for v, _ in samples) == pytest.approx(500.0)
    assert x.OPT2n == pytest.approx(500.0)  # model velocity = Vmax


@pytest.mark.parametrize("fb_name", ["MC_MoveAbsolute", "MC_MoveRelative", "GT_MoveAbsBlock"])
def test_move_velocity_above_vmax_is_clamped_and_reaches_target(fb_name: str):
    inputs: dict[str, Any] = (
        {"Distance": 400.0} if fb_name == "MC_MoveRelative" else {"Position": 400.0}
    )
    x, samples, _ = sampled_move(fb_name, Velocity=1e9, **inputs)
    assert max(v for v, _ in samples) == pytest.approx(500.0)
    assert abs(x.POS - 400.0) < 0.05


def test_jog_velocity_above_vmax_is_clamped():
    m, x = machine()
    power_on(m, x)
    samples = model_samples(m, x)
    jog = mcl.GT_Jog()
    m.run(lambda: jog(Axis=x, Enable=True, JogPos=True, JogVelo=1e6), timeout=0.5)
    assert not jog.Error and jog.Busy
    assert max(v for v, _ in samples) == pytest.approx(500.0)


@pytest.mark.parametrize("acceleration", [1e6, 1e300])
def test_acceleration_above_maximum_is_clamped(acceleration: float):
    """AxisConfig.max_acceleration (20000 mm/s²) caps Acceleration."""
    _, samples, move = sampled_move(Velocity=200.0, Acceleration=acceleration)
    assert not move.Error
    assert max(a for _, a in samples) == pytest.approx(20000.0)
    speeds = [v for v, _ in samples]
    assert max(b - a for a, b in itertools.pairwise(speeds)) <= 20000.0 * 1e-3 + 1e-6


@pytest.mark.parametrize("fb_name", ["MC_Stop", "MC_Halt"])
def test_deceleration_above_maximum_is_clamped(fb_name: str):
    """AxisConfig.max_deceleration (20000 mm/s²) caps Deceleration: from 200 mm/s the stop takes
    at least 10 ms."""
    samples, stop = sampled_stop(fb_name, 1e12)
    assert not stop.Error
    assert min(a for _, a in samples) == pytest.approx(-20000.0)
    assert sum(1 for v, _ in samples if v > 0.0) >= 9  # servo cycles of 1 ms


def test_jerk_above_maximum_is_clamped():
    """AxisConfig.max_jerk caps Jerk."""
    config = mcl.AxisConfig(max_jerk=1e5)
    _, samples, move = sampled_move(config=config, Velocity=200.0, Jerk=1e12)
    assert not move.Error
    accelerations = [a for _, a in samples]
    steps = [abs(b - a) for a, b in itertools.pairwise(accelerations)]
    assert max(steps) <= 1e5 * 1e-3 * (1 + 1e-9)


def test_lowest_valid_values_are_accepted():
    """Exactly 1 % of Vmax and an acceleration that reaches it in exactly 100 s are valid."""
    m, x = machine()
    power_on(m, x)
    move = mcl.MC_MoveVelocity()
    m.run(
        lambda: move(Axis=x, Execute=True, Velocity=5.0, Acceleration=0.05, Deceleration=0.05),
        timeout=0.1,
    )
    assert not move.Error and move.Busy
    assert x.state == AxisState.ContinuousMotion


# ---------------------------------------------------------------------------- 0 = default
def test_zero_acceleration_means_axis_default():
    """AxisConfig.acceleration (1000 mm/s²) when Acceleration = 0; no jerk limit (default 0)."""
    _, samples, move = sampled_move(Velocity=200.0, Acceleration=0.0, Jerk=0.0)
    assert not move.Error
    assert samples[0][1] == pytest.approx(1000.0)  # full acceleration at once: no jerk limit
    assert max(a for _, a in samples) == pytest.approx(1000.0)
    assert len(samples) == pytest.approx(200, abs=3)  # 200 mm/s at 1000 mm/s²: 0.2 s


def test_zero_deceleration_means_axis_default():
    """AxisConfig.deceleration (1000 mm/s²) when Deceleration = 0."""
    config = mcl.AxisConfig(acceleration=500.0, deceleration=2500.0)
    _, samples, _ = sampled_move("MC_MoveAbsolute", config=config, Position=100.0, Velocity=200.0)
    assert max(a for _, a in samples) == pytest.approx(500.0)
    assert min(a for _, a in samples) == pytest.approx(-2500.0)


@pytest.mark.parametrize("fb_name", ["MC_Stop", "MC_Halt"])
def test_zero_stop_deceleration_means_axis_default(fb_name: str):
    samples, _ = sampled_stop(fb_name, 0.0, config=mcl.AxisConfig(deceleration=2500.0))
    assert min(a for _, a in samples) == pytest.approx(-2500.0)


def test_zero_jerk_means_axis_default_jerk():
    """AxisConfig.jerk (here 50000 mm/s³) when Jerk = 0: the acceleration ramps up."""
    config = mcl.AxisConfig(jerk=50000.0)
    _, samples, _ = sampled_move(config=config, Velocity=200.0, Jerk=0.0)
    accelerations = [a for _, a in samples]
    assert accelerations[0] == pytest.approx(50.0)  # 1 ms at 50000 mm/s³
    steps = [abs(b - a) for a, b in itertools.pairwise(accelerations)]
    assert max(steps) <= 50.0 * (1 + 1e-9)


def test_zero_jog_ramps_mean_axis_defaults():
    m, x = machine(config=mcl.AxisConfig(acceleration=500.0, deceleration=2500.0))
    power_on(m, x)
    samples = model_samples(m, x)
    jog = mcl.GT_Jog()
    m.run(lambda: jog(Axis=x, Enable=True, JogPos=True, JogVelo=200.0), timeout=0.6)
    m.run(lambda: jog(Axis=x, Enable=True, JogPos=False), timeout=0.3)
    assert max(a for _, a in samples) == pytest.approx(500.0)
    assert min(a for _, a in samples) == pytest.approx(-2500.0)
    assert x.sp_vel == 0.0
