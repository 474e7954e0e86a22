"""Random sequences of FB calls against one simulated axis keep the invariants of the
reference (docs/reference.md: Axis state machine, Outputs).

Every example builds a fresh simulated machine, powers and references the axis, then runs 5–20
steps. A step picks one function block (a new instance or one already used), gives it an
Execute/Enable edge pattern and random inputs (NaN, ±inf, negative, zero, tiny and huge values
included) and runs a few PLC cycles. Every instance used so far is called in every PLC scan, as
in a real PLC program. After every scan:

* Busy, Done, Error, CommandAborted are mutually exclusive, and so are Active,
  Done, Error, CommandAborted; InVelocity is never shown together with Error or CommandAborted;
  Error and a non-zero ErrorID go together;
* the axis is in exactly one of the eight states of :class:`mcl.AxisState`;
* no exception escapes from a block or from the servo cycle;
* POS, VEL, the analog output and the model position/velocity are finite; |volts| <= 10 V in
  closed loop (the DAC output is clipped at ±10 V); a Disabled axis' drive is not enabled;
* the simulated plant (position, velocity, amplifier force) is finite, between its hard stops
  and no faster than +10 V drives it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from hypothesis import HealthCheck, event, example, given, settings
from hypothesis import strategies as st

import mcl
from tests.helpers import CONSTANTS, configure, power_on

PLC_PERIOD = 0.002

NASTY_FLOATS = [
    math.nan,
    math.inf,
    -math.inf,
    0.0,
    -0.0,
    5e-324,
    1e-300,
    1e-9,
    -1e-9,
    1e300,
    1.7e308,
    -1.7e308,
    -1.0,
]

floats = st.one_of(
    st.sampled_from(NASTY_FLOATS),
    st.floats(min_value=-2000.0, max_value=2000.0),
    st.floats(allow_nan=True, allow_infinity=True),
)
"""Any float, biased to the awkward ones."""

ints = st.one_of(st.integers(min_value=-1, max_value=7), st.sampled_from([-32768, 255, 32767]))
"""Enumerations (BufferMode, Direction, SpeedMode) including invalid values."""

patterns = st.lists(st.booleans(), min_size=1, max_size=4)
"""Execute/Enable level in the first scans of a step; the last level is then held."""

ramps = st.one_of(st.just(0.0), st.floats(min_value=50.0, max_value=30000.0))
jerks = st.one_of(st.just(0.0), st.floats(min_value=1e3, max_value=1e7))
MOVE = {
    "Velocity": st.floats(min_value=5.0, max_value=600.0),
    "Acceleration": ramps,
    "Deceleration": ramps,
    "Jerk": jerks,
    "BufferMode": st.integers(min_value=0, max_value=5),
}
SANE: dict[str, dict[str, st.SearchStrategy[Any]]] = {
    "MC_MoveAbsolute": {
        **MOVE,
        "Position": st.floats(min_value=-250.0, max_value=850.0),
        "Direction": st.integers(min_value=1, max_value=4),
    },
    "GT_MoveAbsBlock": {
        **MOVE,
        "Position": st.floats(min_value=-250.0, max_value=850.0),
        "Direction": st.integers(min_value=1, max_value=4),
        "ExtStop": st.booleans(),
        "TorqueLimit": st.one_of(st.just(0.0), st.floats(min_value=0.01, max_value=5.0)),
    },
    "MC_MoveRelative": {**MOVE, "Distance": st.floats(min_value=-600.0, max_value=600.0)},
    "MC_MoveAdditive": {**MOVE, "Distance": st.floats(min_value=-600.0, max_value=600.0)},
    "MC_MoveVelocity": {**MOVE, "Direction": st.sampled_from([1, 3, 4])},
    "MC_Stop": {"Deceleration": ramps, "Jerk": jerks, "BufferMode": st.just(0)},
    "MC_Halt": {
        "Deceleration": ramps,
        "Jerk": jerks,
        "BufferMode": st.integers(min_value=0, max_value=5),
    },
    "GT_Jog": {
        "JogPos": st.booleans(),
        "JogNeg": st.booleans(),
        "JogVelo": st.floats(min_value=5.0, max_value=600.0),
        "JogAcc": ramps,
        "JogDec": ramps,
        "JogJerk": jerks,
    },
    "MC_Reset": {},
    "MC_Power": {"SpeedMode": st.sampled_from([0, 0, 0, 1])},
    "GT_SetConstant": {name: st.just(value) for name, value in CONSTANTS.items()},
}
"""Inputs a block accepts: the command is carried out."""


def awkward(name: str, strategy: st.SearchStrategy[Any]) -> st.SearchStrategy[Any]:
    """An input that may also be any float or an invalid enumeration value."""
    if name in ("BufferMode", "Direction", "SpeedMode"):
        return st.one_of(strategy, ints)
    if name in ("JogPos", "JogNeg", "ExtStop"):
        return strategy
    return st.one_of(strategy, floats)


AWKWARD = {
    fb: {name: awkward(name, strategy) for name, strategy in inputs.items()}
    for fb, inputs in SANE.items()
}
"""Every input may also be any float (NaN, ±inf, negative, zero, tiny, huge) or invalid enum."""

TRIGGERS: dict[str, list[str]] = {"MC_Power": ["Enable"], "GT_Jog": ["Enable", "JogPos", "JogNeg"]}
"""The input that the edge pattern drives (default Execute); GT_Jog: Enable or a jog button."""


@dataclass
class Step:
    """One step: which block instance, its edge pattern, its inputs, how many PLC scans
    (2–50 ms, sometimes 0.2 s to let motions end)."""

    fb: str
    instance: int
    trigger: str
    pattern: list[bool]
    inputs: dict[str, Any]
    scans: int


FB_NAMES = sorted(SANE)
SCANS = st.one_of(st.integers(min_value=1, max_value=25), st.just(100))


@st.composite
def step_sequences(draw: st.DrawFn) -> list[Step]:
    """5–20 steps; half of them on the block instance of the previous step (new edges and new
    inputs on an instance that may still be busy: edge sampling, restarts)."""
    steps: list[Step] = []
    for _ in range(draw(st.integers(min_value=5, max_value=20))):
        reuse: bool = draw(st.booleans())
        if steps and reuse:
            fb, instance = steps[-1].fb, steps[-1].instance
        else:
            fb = draw(st.sampled_from(FB_NAMES))
            instance = draw(st.integers(min_value=0, max_value=1))
        table = SANE if draw(st.booleans()) else AWKWARD
        inputs = {name: draw(strategy) for name, strategy in table[fb].items()}
        if fb == "GT_Jog":
            inputs["Enable"] = draw(st.booleans())
        steps.append(
            Step(
                fb=fb,
                instance=instance,
                trigger=draw(st.sampled_from(TRIGGERS.get(fb, ["Execute"]))),
                pattern=draw(patterns),
                inputs=inputs,
                scans=draw(SCANS),
            )
        )
    return steps


@dataclass
class Harness:
    """The machine, the axis and the block instances used so far."""

    machine: mcl.SimMachine
    axis: mcl.Axis
    blocks: dict[tuple[str, int], Any] = field(default_factory=dict)
    visited: set[str] = field(default_factory=set)

    def block(self, name: str, instance: int) -> Any:
        key = (name, instance)
        if key not in self.blocks:
            self.blocks[key] = getattr(mcl, name)()
        return self.blocks[key]


def check_outputs(name: str, fb: Any) -> None:
    """The mutually exclusive outputs (and InVelocity never with Error or CommandAborted) of one
    block instance."""
    busy = bool(getattr(fb, "Busy", False))
    done = bool(getattr(fb, "Done", False))
    error = bool(getattr(fb, "Error", False))
    aborted = bool(getattr(fb, "CommandAborted", False))
    active = bool(getattr(fb, "Active", False))
    state = f"{name}: Busy={busy} Active={active} Done={done} Error={error} Aborted={aborted}"
    assert busy + done + error + aborted <= 1, state
    assert active + done + error + aborted <= 1, state
    if hasattr(fb, "InVelocity"):
        assert not (fb.InVelocity and (error or aborted)), f"{state} InVelocity={fb.InVelocity}"
    assert error == (fb.ErrorID != 0), f"{name}: Error={error} ErrorID={fb.ErrorID}"


def check_axis(axis: mcl.Axis, sim: mcl.SimAxis) -> None:
    """A state of :class:`mcl.AxisState`, finite signals, at most ±10 V in closed loop, no drive
    enable while Disabled; the simulated plant finite, between its hard stops (give or take
    what the amplifier's peak force and an impact can press into them) and no faster than +10 V
    drives it."""
    assert type(axis.state) is mcl.AxisState, f"state {axis.state!r} is not an AxisState"
    for name in ("POS", "VEL", "volts", "sp_pos", "sp_vel"):
        value = getattr(axis, name)
        assert math.isfinite(value), f"{name} = {value}"
    assert abs(axis.volts) <= 10.0, axis.volts
    if axis.state == mcl.AxisState.Disabled:
        assert not sim.enabled, "the drive is enabled while the axis is Disabled"
    p = sim.params
    for name in ("x", "v", "force"):
        value = getattr(sim, name)
        assert math.isfinite(value), f"the plant's {name} = {value}"
    # how far the stop's spring gives under the amplifier's peak force and the kinetic energy
    # of the fastest allowed speed: k·d²/2 = F·d + m·v²/2 [m]
    static, speed = p.force_limit / p.stop_stiffness, 1.1 * p.vmax
    squeeze = static + math.sqrt(static**2 + p.mass * speed**2 / p.stop_stiffness)
    assert p.stop_neg - squeeze <= sim.x <= p.stop_pos + squeeze, f"the plant at x = {sim.x} m"
    assert abs(sim.v) <= 1.1 * p.vmax, f"the plant at v = {sim.v} m/s"


def run_step(h: Harness, step: Step) -> None:
    axis = h.axis
    chosen = h.block(step.fb, step.instance)
    trigger = step.trigger
    for scan in range(step.scans):
        level = step.pattern[min(scan, len(step.pattern) - 1)]

        def program(scan: int = scan, level: bool = level) -> None:
            for (name, _), fb in h.blocks.items():
                if fb is chosen:
                    inputs = {**step.inputs, trigger: level} if scan == 0 else {trigger: level}
                    fb(Axis=axis, **inputs)
                else:
                    fb(Axis=axis)
                check_outputs(name, fb)

        h.machine.run(program, timeout=PLC_PERIOD)
        check_axis(axis, h.machine.sims["X"])
        h.visited.add(axis.state.name)


JOG = {"JogPos": True, "JogNeg": False, "JogVelo": 100.0, "JogAcc": 0.0, "JogDec": 0.0}
JOG_REVERSED_WITH_BAD_JERK = [
    Step("GT_Jog", 0, "Enable", [True], {**JOG, "JogJerk": 0.0}, 100),
    Step("GT_Jog", 0, "JogNeg", [True], {**JOG, "JogPos": False, "JogJerk": math.nan}, 2),
]
"""Found by this test: jogging, then the other button with a bad JogJerk (Busy and Error)."""
HUGE_KC_THEN_MOVE = [
    Step("GT_SetConstant", 0, "Execute", [True], {**CONSTANTS, "Kc": 1e12}, 1),
    Step("MC_MoveVelocity", 0, "Execute", [True], {"Velocity": 100.0}, 100),
]
"""Found by this test: a finite anti-windup gain Kc that GT_SetConstant accepts drives the
regulator's integrator to NaN; the servo cycle then raises."""


@settings(
    max_examples=1000 if mcl.COMPILED else 250,  # the same source: fewer in the second pass
    derandomize=True,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
@given(steps=step_sequences())
@example(steps=JOG_REVERSED_WITH_BAD_JERK)
@example(steps=HUGE_KC_THEN_MOVE)
def test_random_fb_sequences_keep_invariants(steps: list[Step]) -> None:
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2)})
    axis = machine.axes["X"]
    configure(axis)
    power_on(machine, axis)
    h = Harness(machine, axis)
    check_axis(axis, machine.sims["X"])
    for step in steps:
        run_step(h, step)
    for state in sorted(h.visited):
        event(f"visited {state}")  # coverage, shown by --hypothesis-show-statistics
