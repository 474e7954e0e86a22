"""Servo core: 12-bit DAC and position regulator, GT_Analog's DAC mapping."""

from __future__ import annotations

import itertools
import math

import pytest

import mcl
from mcl.servo import Regulator, ServoConstants, dac, dac_code_volts
from tests.helpers import configure, power_on, scan

STEP = 10.5 / 4095
"""Volts per DAC code."""
PERIOD = 0.001


def codes(volts: float) -> float:
    return volts / STEP


# ---------------------------------------------------------------------------------- DAC
@pytest.mark.parametrize("volts", [0.0, 0.001, 0.00128, -0.0013, 1.0, -3.3333, 7.77, 9.999, -9.999])
def test_dac_quantizes_to_12_bit_codes(volts):
    out = dac(volts)
    n = codes(out)
    assert n == pytest.approx(round(n), abs=1e-9)
    assert abs(round(n)) <= 4095
    assert abs(out - volts) <= STEP / 2 + 1e-12


def test_dac_code_step_is_10_5_volts_over_4095():
    assert dac(STEP) == pytest.approx(STEP)
    assert dac(0.49 * STEP) == 0.0
    assert dac(0.51 * STEP) == pytest.approx(STEP)
    assert dac(-0.51 * STEP) == pytest.approx(-STEP)


@pytest.mark.parametrize(
    ("volts", "clipped"), [(10.0, 10.0), (10.3, 10.0), (25.0, 10.0), (-10.2, -10.0), (-1e6, -10.0)]
)
def test_dac_clips_at_10_volts(volts, clipped):
    assert dac(volts) == pytest.approx(clipped, abs=1e-12)


def test_dac_is_monotonic():
    values = [dac(-12.0 + i * 0.0007) for i in range(34286)]
    assert all(b >= a for a, b in itertools.pairwise(values))
    assert min(values) == pytest.approx(-10.0)
    assert max(values) == pytest.approx(10.0)


def test_gt_analog_code_mapping_is_inverted():
    assert dac_code_volts(-4095) == pytest.approx(10.5)
    assert dac_code_volts(4095) == pytest.approx(-10.5)
    assert dac_code_volts(0) == 0.0
    assert dac_code_volts(390) == pytest.approx(-1.0)
    assert dac_code_volts(-390) == pytest.approx(1.0)
    # out-of-range codes saturate at full scale
    assert dac_code_volts(-5000) == pytest.approx(10.5)


def test_gt_analog_drives_the_disabled_axis():
    """A negative code moves the axis in the positive direction (the inverted mapping the
    MotionControlLib manual documents)."""
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2)})
    X = machine.axes["X"]
    configure(X)
    analog = mcl.GT_Analog()
    machine.run(lambda: analog(Axis=X, Execute=True, Analog=-390, Par=0), timeout=0.3)
    assert analog.Done
    assert X.state == mcl.AxisState.Disabled
    assert X.volts == pytest.approx(1.0)
    assert X.VEL > 0.0
    x1 = X.actual
    analog2 = mcl.GT_Analog()
    machine.run(lambda: analog2(Axis=X, Execute=True, Analog=4095, Par=0), timeout=0.05)
    assert X.volts == pytest.approx(-10.5)  # full scale: not clipped while Disabled
    machine.run(timeout=0.3)
    assert X.actual < x1
    end = mcl.GT_Analog()
    machine.run(lambda: end(Axis=X, Execute=True, Par=1), timeout=0.05)
    assert X.volts == 0.0


def test_closed_loop_output_never_exceeds_10_volts(machine, X):
    """Blocked by an obstacle, a stiff regulator saturates: the output stays within ±10 V."""
    configure(X, Kp=20.0)
    machine.sims["X"].blocked_at = machine.sims["X"].x + 0.0005
    volts: list[float] = []
    machine.runtime.observers.append(lambda t: volts.append(X.volts))
    move = mcl.MC_MoveRelative()
    machine.run(
        scan(lambda: move(Axis=X, Execute=True, Distance=10.0, Velocity=100.0)),
        until=lambda: X.state == mcl.AxisState.ErrorStop,
        timeout=1.0,
    )
    assert max(volts) == pytest.approx(10.0)
    assert min(volts) >= -10.0
    assert all(abs(codes(v) - round(codes(v))) < 1e-9 for v in volts)


# ---------------------------------------------------------------------------------- regulator
def regulator(**values: float) -> Regulator:
    constants = ServoConstants(**{"Vmax": 500.0, **values})
    return Regulator(constants, PERIOD)


def test_proportional_term_only():
    reg = regulator(Kp=3.0, Ff=0.0)
    for _ in range(100):
        assert reg.output(0.5, 0.0, 0.0, False) == pytest.approx(dac(1.5))
    assert reg.output(-1.0, 0.0, 0.0, False) == pytest.approx(dac(-3.0))
    assert reg.output(0.0, 0.0, 0.0, False) == 0.0


@pytest.mark.parametrize(
    ("ff", "velocity", "volts"),
    [(1.0, 500.0, 10.0), (1.0, -250.0, -5.0), (0.5, 500.0, 5.0), (0.0, 500.0, 0.0)],
)
def test_velocity_feed_forward_is_10_volts_at_vmax(ff, velocity, volts):
    reg = regulator(Ff=ff)
    assert reg.output(0.0, velocity, 0.0, False) == pytest.approx(dac(volts))


def test_acceleration_feed_forward():
    reg = regulator(Ff=1.0, Ka=0.0065)
    # (10 V / Vmax) · Ka · a = 0.02 · 0.0065 · 4000 = 0.52 V
    assert reg.output(0.0, 0.0, 4000.0, False) == pytest.approx(dac(0.52))
    assert reg.output(0.0, 100.0, -4000.0, False) == pytest.approx(dac(2.0 - 0.52))


def test_integral_term_accumulates():
    reg = regulator(Ki=100.0, Ff=0.0)
    outputs = [reg.output(0.01, 0.0, 0.0, False) for _ in range(1000)]
    # after 1 s: Ki · e · t = 100 · 0.01 · 1 = 1 V
    assert outputs[-1] == pytest.approx(1.0, abs=2 * STEP)
    assert outputs[0] < outputs[500] < outputs[-1]


def _saturate_then_reverse(kc: float, seconds: float) -> list[float]:
    reg = regulator(Kp=3.0, Ki=150.0, Kc=kc, Ff=0.0)
    for _ in range(round(seconds / PERIOD)):
        out = reg.output(1.0, 0.0, 0.0, False)
    assert out == pytest.approx(10.0)  # saturated
    return [reg.output(-1.0, 0.0, 0.0, False) for _ in range(200)]


def test_anti_windup_keeps_the_integrator_bounded():
    with_kc = _saturate_then_reverse(50.0, 2.0)
    # the integrator stopped near the saturation: the output leaves +10 V at once
    assert with_kc[0] < 9.0
    # bounded: ten times longer in saturation changes nothing
    assert _saturate_then_reverse(50.0, 20.0) == pytest.approx(with_kc, abs=1e-9)
    # without anti-windup the integrator winds up and the output sticks at +10 V
    without = _saturate_then_reverse(0.0, 2.0)
    assert min(without) == pytest.approx(10.0)


def test_settling_integral_ki1_only_when_enabled():
    reg = regulator(Ki1=200.0, Ff=0.0)
    # moving model or inside the window: no settling integral
    for _ in range(500):
        assert reg.output(0.02, 0.0, 0.0, False) == 0.0
    # model at standstill outside the window: integrates
    outputs = [reg.output(0.02, 0.0, 0.0, True) for _ in range(500)]
    assert outputs[-1] == pytest.approx(200.0 * 0.02 * 0.5, abs=2 * STEP)


def _standstill_error_with_load(ki1: float) -> list[float]:
    """Kp-only axis with a constant 300 N load: following error samples at standstill."""
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2, load=-300.0)})
    X = machine.axes["X"]
    configure(X, Ki=0.0, Kc=0.0, Ki1=ki1)
    power_on(machine, X)
    errors: list[float] = []
    machine.runtime.observers.append(lambda t: errors.append(X.following_error))
    machine.run(timeout=2.0)
    return errors


def test_ki1_settles_the_standstill_error_into_the_in_position_window():
    without = _standstill_error_with_load(0.0)
    with_ki1 = _standstill_error_with_load(400.0)
    # Kp alone leaves a static error of load / (200 N/V · Kp) = 0.5 mm
    assert without[-1] == pytest.approx(0.5, rel=0.1)
    window = mcl.AxisConfig().in_position
    assert abs(with_ki1[-1]) <= window + 0.002
    assert abs(with_ki1[-1]) < abs(without[-1]) / 20
    # inside the window Ki1 stops: the remaining small error stays as it is
    last_second = with_ki1[-1000:]
    assert max(last_second) == min(last_second) != 0.0


def _moving_error(ki1: float) -> float:
    """Kp-only axis at constant velocity: friction leaves a steady following error."""
    machine = mcl.SimMachine({"X": mcl.SimAxisParams(start=0.2)})
    X = machine.axes["X"]
    configure(X, Ki=0.0, Kc=0.0, Ki1=ki1)
    power_on(machine, X)
    move = mcl.MC_MoveVelocity()
    machine.run(scan(lambda: move(Axis=X, Execute=True, Velocity=50.0)), timeout=0.6)
    assert move.InVelocity
    return X.following_error


def test_ki1_is_inactive_while_the_model_moves():
    without = _moving_error(0.0)
    assert without > 0.01  # friction needs force: a visible steady error
    assert _moving_error(400.0) == pytest.approx(without, abs=1e-6)


# ------------------------------------------------------------------ friction pulse
def _reversal(reg: Regulator, cycles: int = 400) -> list[float]:
    """The regulator's output [V] while the model velocity sweeps from +0.5 to −0.5 u/s in
    ``cycles`` servo cycles (no following error, no velocity feed-forward)."""
    return [reg.output(0.0, 0.5 - k / (cycles - 1), 0.0, False) for k in range(cycles)]


def test_the_friction_pulse_is_off_by_default():
    """Without Kfp the output passes through 0 V at the reversal (only Kf's ramp)."""
    out = _reversal(regulator(Ff=0.0, Kf=0.1))
    assert max(abs(v) for v in out) < 0.011  # 10 V/500 · 0.5 u/s = 0.01 V at the ends


def test_the_friction_pulse_jumps_at_the_reversal_and_decays():
    """Kfp = 0.2 V, Tfp = 20 ms: in the first cycle of negative model velocity the output jumps
    by −0.2 V, after one time constant it is down to 1/e of that, after 10 of them gone; a
    second reversal back gives a pulse of the other sign; the start from standstill none."""
    reg = regulator(Ff=0.0, Kfp=0.2, Tfp=0.02)
    assert reg.output(0.0, 0.0, 0.0, False) == 0.0
    assert reg.output(0.0, 0.001, 0.0, False) == pytest.approx(dac(0.0))  # a start: no pulse
    out = _reversal(reg)
    first = next(k for k in range(400) if 0.5 - k / 399 < 0.0)
    assert max(abs(v) for v in out[:first]) < STEP
    assert out[first] == pytest.approx(dac(-0.2))
    assert out[first + 20] == pytest.approx(-0.2 / math.e, abs=3 * STEP)
    assert abs(out[-1]) < STEP  # 199 cycles later
    back = [reg.output(0.0, 0.1, 0.0, False) for _ in range(2)]
    assert back[0] == pytest.approx(dac(0.2))
    assert back[1] < back[0]


def test_the_friction_pulse_is_part_of_the_regulator_state():
    """memory()/set_memory() carry the pulse, so a restored state repeats it."""
    reg = regulator(Ff=0.0, Kfp=0.2, Tfp=0.02)
    _reversal(reg, 250)
    saved = reg.memory()
    again = [reg.output(0.0, -0.1, 0.0, False) for _ in range(5)]
    reg.set_memory(saved)
    assert [reg.output(0.0, -0.1, 0.0, False) for _ in range(5)] == again


def test_the_friction_feed_forward_switches_within_its_band():
    """Kf = 0.1 V with the band Vf = 0.01 u/s: while the model velocity sweeps from +0.5 to
    −0.5 u/s (0.0025 u/s per cycle) the output holds +Kf down to +Vf, −Kf from −Vf on, and
    passes from one to the other in the 8 cycles between; without a band (Vf = 0) Kf's ramp
    over Kf·Vmax/10 = 5 u/s gives only ±0.01 V there."""
    out = _reversal(regulator(Ff=0.0, Kf=0.1, Vf=0.01))
    speeds = [0.5 - k / 399 for k in range(400)]
    outside = [(v, u) for v, u in zip(speeds, out, strict=True) if abs(v) >= 0.01]
    assert all(u == pytest.approx(dac(0.1 if v > 0 else -0.1)) for v, u in outside)
    inside = [u for v, u in zip(speeds, out, strict=True) if abs(v) < 0.01]
    assert len(inside) == 8
    assert all(-0.1 - STEP < u < 0.1 + STEP for u in inside)
    assert inside == sorted(inside, reverse=True)  # one way, no chatter
    wide = _reversal(regulator(Ff=0.0, Kf=0.1))
    assert max(abs(u) for u in wide) < 0.011


def test_gt_setconstant_refuses_a_negative_friction_pulse(machine, X):
    """Kfp, Tfp and the friction band Vf are checked like the other gains (>= 0)."""
    for name in ("Kfp", "Tfp", "Vf"):
        block = mcl.GT_SetConstant(Axis=X, Kp=1.0, Vmax=500.0, **{name: -0.1})
        block(Execute=True)
        assert block.Error and block.ErrorID == mcl.ErrorID.EParam
