"""Commissioning of a servo axis: identify the drive on the physics, derive the servo constants.

Run ``python -m scenes.tools.commissioning gantry X`` (any registered machine and electric
axis). The procedure is the one a commissioning engineer runs on a velocity-mode servo amplifier:

1. **Velocity steps on the amplifier alone** (position loop open, the bare MuJoCo model): the
   axis runs at a base command of ``±base`` volts, then a small step ``±step`` volts is added and
   removed. From the joint velocity: the gain ``K`` [u/s per V] (velocity change over voltage
   change), the equivalent lag ``T`` [s] (area between the step and the response, divided by its
   height: the sum of the time constants, which is exactly what a feed-forward must lead by) and
   the velocity at 0 V (a hanging axis drifts under its weight). The step stays small enough that
   the amplifier does not reach its force limit (it is halved until it does not).
2. **Constants** (rules below), with the module's own delays added to the drive's lag:
   ``T_loop = T + (output_delay + 1/2)·servo_period`` (the command leaves one cycle after the
   sample and is held for one cycle).

   - velocity feed-forward ``Ff = Vmax/(10·K)``: the commanded velocity is reached exactly;
   - acceleration feed-forward ``Ka = Ff·T_loop``: the distance the drive loses while it
     follows a velocity change, put back in advance;
   - position gain ``Kv = 1/(2·T_loop)`` (the "technical optimum" of an integrating loop with one
     lag: damping 0.7), ``Kp = Kv/K`` [V/u];
   - friction feed-forward ``Kf = c/K`` [V], ``c`` the velocity the friction takes away (the
     steady velocities at ``±base`` fall short of ``K·base`` by ``c``);
   - integral gain ``Ki = Kp·Kv/8``: its corner three octaves below ``Kv``, so it removes
     what is left (on a hanging axis the weight: ``−v0/K`` volts, printed as the holding
     voltage) without adding phase where the loop crosses over.
3. **Verification**: a jerk-limited move each way with the derived constants, on the whole stack
   (PLC scan, mcl servo cycle, encoder, the module's delay), measured on the physics: peak
   following error, overshoot at the stop and settling time into the axis' in-position window
   (±5 µm on the gantry). A joint of a parallel robot (an axis of a group with a kinematic
   transformation, the delta picker's arms) cannot move alone: its closed chains tie it to the
   other joints. It moves with them, each by the same distance (the delta's effector then moves
   straight along z), out from the machine's start pose and back; the figures are the tuned
   joint's.
"""

from __future__ import annotations

__all__ = [
    "DriveResponse",
    "LimitStop",
    "MoveFigures",
    "Tuning",
    "derive",
    "identify",
    "main",
    "measure_move",
    "robot_joints",
    "run_into_limit",
    "verify",
]

import argparse
import math
import sys
from collections.abc import Sequence
from dataclasses import dataclass, replace

import mujoco
import numpy as np

import mcl
from scenes.definition import AxisDef, MachineDef, unit_and_scale
from scenes.scene import Scene, compose


@dataclass(frozen=True)
class DriveResponse:
    """What the velocity steps measured on one amplifier (user units u, e.g. mm).

    Attributes:
        gain: velocity change per volt of command change [u/s per V].
        lag: equivalent first-order lag (sum of the time constants) [s].
        t63: time to 63 % of a velocity step [s].
        drift: velocity at 0 V (weight against the amplifier's finite stiffness) [u/s].
        friction: velocity the Coulomb friction takes away while the axis moves (viscous
            damping is part of the gain) [u/s].
        step: the step that stayed below the force limit [V].
    """

    gain: float
    lag: float
    t63: float
    drift: float
    friction: float
    step: float

    @property
    def bandwidth(self) -> float:
        """−3 dB bandwidth of the velocity loop taken as first order, 1/(2π·lag) [Hz]."""
        return 1.0 / (2.0 * math.pi * self.lag)


def _axis_names(machine: MachineDef, axis: str) -> tuple[AxisDef, str, str]:
    if axis not in machine.axes:
        raise KeyError(f"machine {machine.name!r} has no axis {axis!r}; axes: {list(machine.axes)}")
    spec = machine.axes[axis]
    if spec.drive != "electric" or not machine.model:
        raise ValueError(f"axis {axis}: commissioning needs an electric drive on an MJCF model")
    return spec, f"{machine.name}/{spec.joint or axis}", f"{machine.name}/{axis}_amp"


def identify(
    machine: MachineDef, axis: str, base: float = 1.0, step: float = 0.2, hold: float = 0.06
) -> DriveResponse:
    """Velocity steps on the amplifier of ``axis`` alone (bare physics, other drives at 0 V).

    Args:
        machine: the machine definition.
        axis: the axis name.
        base: base command [V], both signs (runs the axis clear of stiction).
        step: the step added on top [V]; halved until the force stays below the limit.
        hold: duration of each command level [s].

    Returns:
        The measured response in the axis' user units.
    """
    spec, joint_name, amp_name = _axis_names(machine, axis)
    model, data = compose([machine])
    joint = model.joint(joint_name).id
    amp = model.actuator(amp_name).id
    dof = int(model.jnt_dofadr[joint])
    qadr = int(model.jnt_qposadr[joint])
    _, scale = unit_and_scale(spec, rotary=model.jnt_type[joint] == mujoco.mjtJoint.mjJNT_HINGE)
    travel = model.numeric(f"{machine.name}/{axis}_travel").data
    fmax = float(model.actuator_forcerange[amp][1])
    dt = float(model.opt.timestep)
    n = round(hold / dt)
    while True:
        levels = [base, base + step, base, -base, -base - step, -base]
        mujoco.mj_resetData(model, data)
        for name, q in machine.demo_start.items():
            data.joint(f"{machine.name}/{machine.axes[name].joint or name}").qpos[0] = q
        # start where the whole sequence stays inside the travel
        data.qpos[qadr] = float(np.mean(travel))
        mujoco.mj_forward(model, data)
        v = np.empty((len(levels), n))
        saturated = False
        for i, u in enumerate(levels):
            data.ctrl[amp] = u
            for k in range(n):
                mujoco.mj_step(model, data)
                v[i, k] = data.qvel[dof] * scale
                if i in (1, 2, 4, 5) and abs(data.actuator_force[amp]) >= fmax * 0.999:
                    saturated = True
        if not saturated or step < 1e-3:
            break
        step /= 2.0
    tail = v[:, -n // 5 :].mean(axis=1)
    gains, lags, t63s = [], [], []
    for before, i in ((0, 1), (1, 2), (3, 4), (4, 5)):
        jump = tail[i] - tail[before]
        gains.append(abs(jump) / step)
        rest = (tail[i] - v[i]) / jump  # 1 → 0
        lags.append(float(rest.sum() * dt))
        t63s.append(float(np.argmax(rest <= 1.0 / math.e) + 1) * dt)
    gain = float(np.mean(gains))
    up, down = tail[0], tail[3]
    return DriveResponse(
        gain=gain,
        lag=float(np.mean(lags)),
        t63=float(np.mean(t63s)),
        drift=float((up + down) / 2.0),
        friction=float(gain * base - (up - down) / 2.0),
        step=step,
    )


@dataclass(frozen=True)
class Tuning:
    """The servo constants derived from a drive response, and the loop figures behind them.

    Attributes:
        constants: Kp, Ki, Ff, Ka, Kf set; the rest taken from the axis' current constants.
        loop_lag: drive lag plus the module's delays [s].
        kv: position-loop gain [1/s].
    """

    constants: mcl.ServoConstants
    loop_lag: float
    kv: float


def derive(spec: AxisDef, response: DriveResponse, servo_period: float = 0.001) -> Tuning:
    """Servo constants from a measured drive response (the rules of the module docstring).

    Args:
        spec: the axis definition (its constants give Vmax and the rest).
        response: the measured drive response.
        servo_period: servo cycle [s].
    """
    base = spec.constants or mcl.ServoConstants()
    if base.Vmax <= 0.0:
        raise ValueError("the axis' ServoConstants need Vmax (velocity at 10 V) to derive Ff")
    delay = (spec.sensors or mcl.Sensors()).output_delay
    loop_lag = response.lag + (delay + 0.5) * servo_period
    ff = base.Vmax / (10.0 * response.gain)
    kv = 1.0 / (2.0 * loop_lag)
    kp = kv / response.gain
    constants = replace(
        base,
        Kp=round(kp, 4),
        Ki=round(kp * kv / 8.0, 2),
        Ff=round(ff, 4),
        Ka=round(ff * loop_lag, 5),
        Kf=round(response.friction / response.gain, 4),
    )
    return Tuning(constants, loop_lag, kv)


@dataclass(frozen=True)
class MoveFigures:
    """One point-to-point move measured on the physics (user units u, times in s).

    Attributes:
        peak_error: largest |set point − joint position| during the move [u].
        overshoot: largest travel past the target after the set point stopped [u].
        settling: time from the set point's stop until the joint stays within ±window [s]
            (measured over ``settle`` seconds after the stop).
        final: joint position minus target at the end [u].
    """

    peak_error: float
    overshoot: float
    settling: float
    final: float


def measure_move(
    scene: Scene,
    axis: str,
    distance: float,
    velocity: float,
    acceleration: float = 0.0,
    jerk: float = 0.0,
    window: float = 0.005,
    settle: float = 0.2,
    together: Sequence[str] = (),
) -> MoveFigures:
    """Power ``axis`` on, run MC_MoveRelative and measure it on the joint (not the encoder).

    The axis coordinate is its joint coordinate in user units, offset as its encoder reads it.

    Args:
        scene: a scene whose axis is Disabled (or powered by an earlier measurement).
        axis: the axis name.
        distance, velocity, acceleration, jerk: the move (0: the axis' defaults) [u, u/s, ...].
        window: settling window [u].
        settle: how long to watch after the set point stopped [s].
        together: other axes powered and moved the same way in the same scans (a parallel
            robot's joints that close a chain with ``axis``).
    """
    axes = [scene.axes[name] for name in (axis, *together)]
    a = axes[0]
    scale = scene.scales[axis]
    powers = [mcl.MC_Power(Axis=x) for x in axes]
    moves = [mcl.MC_MoveRelative(Axis=x) for x in axes]

    def power_on() -> None:
        for power in powers:
            power(Enable=True)

    scene.run(power_on, until=lambda: all(p.Status for p in powers), timeout=1.0)
    scene.run(power_on, timeout=0.2)
    # the joint's coordinate against the encoder's (not the set point's: a loaded joint stands
    # off its set point until the integral has taken the load)
    origin = scene.joint_position(axis) * scale - a.actual
    samples: list[tuple[float, float, float, float]] = []

    def observe(t: float) -> None:
        samples.append((t, a.sp_pos, scene.joint_position(axis) * scale - origin, a.sp_vel))

    def program() -> None:
        power_on()
        for block in moves:
            block(
                Execute=True,
                Distance=distance,
                Velocity=velocity,
                Acceleration=acceleration,
                Deceleration=acceleration,
                Jerk=jerk,
            )

    scene.runtime.observers.append(observe)
    try:
        scene.run(
            program,
            until=lambda: all(m.Done for m in moves) or any(m.Error for m in moves),
            timeout=30.0,
        )
        failed = next((m for m in moves if m.Error), None)
        if failed is not None:
            name = failed.Axis.name if failed.Axis is not None else axis
            raise RuntimeError(f"axis {name}: the move ended in error {failed.ErrorID}")
        t_done = scene.time
        scene.run(program, until=lambda: scene.time - t_done >= settle, timeout=settle + 1.0)
    finally:
        scene.runtime.observers.remove(observe)
    return _move_figures(samples, distance, window)


def _move_figures(
    samples: list[tuple[float, float, float, float]], distance: float, window: float
) -> MoveFigures:
    """A move's figures from its samples (time [s], set point, joint [u], set velocity [u/s])
    of a move by ``distance`` [u] with the settling ``window`` [u]."""
    t, sp, q, v = np.array(samples).T
    stop = t[np.nonzero(v)[0][-1] + 1]
    after = t >= stop
    target = sp[-1]
    past = (q[after] - target) * math.copysign(1.0, distance)
    outside = np.nonzero(np.abs(past) > window)[0]
    settling = float(t[after][outside[-1]] + (t[1] - t[0]) - stop) if outside.size else 0.0
    return MoveFigures(
        peak_error=float(np.abs(sp - q).max()),
        overshoot=max(0.0, float(past.max())),
        settling=settling,
        final=float(past[-1]),
    )


@dataclass(frozen=True)
class LimitStop:
    """A run at full speed into a limit switch, measured on the physics (joint coordinates, m).

    Attributes:
        speed: joint speed when the switch tripped [m/s].
        trip: joint coordinate where the axis went to ErrorStop (LIM seen) [m].
        furthest: furthest joint coordinate reached [m].
        hard_stop: the joint's end of range (the hard stop) on that side [m].
        stop_force: largest force of the hard stop (the joint-limit constraint) [N]; 0 = never
            touched.
        error_id: the axis error latched (2004 LIM+, 2005 LIM−).
    """

    speed: float
    trip: float
    furthest: float
    hard_stop: float
    stop_force: float
    error_id: int

    @property
    def distance(self) -> float:
        """Stopping distance from the trip point [m]."""
        return abs(self.furthest - self.trip)

    @property
    def margin(self) -> float:
        """Room left to the hard stop [m]."""
        return abs(self.hard_stop - self.furthest)


def run_into_limit(scene: Scene, axis: str, direction: int, acceleration: float) -> LimitStop:
    """MC_MoveVelocity at Vmax towards LIM+ (``direction`` +1) or LIM− (−1) until the axis stops.

    Args:
        scene: a scene whose axis is still Disabled, started with room to reach Vmax.
        axis: the axis name.
        direction: +1 or −1.
        acceleration: run-up acceleration [u/s²].
    """
    a = scene.axes[axis]
    io = scene.io(axis)
    model, data = scene.model, scene.data
    assert a.constants is not None
    hard_stop = float(model.jnt_range[io.joint][0 if direction < 0 else 1])
    power, move = mcl.MC_Power(), mcl.MC_MoveVelocity()
    mode = mcl.MC_Direction.MC_Positive if direction > 0 else mcl.MC_Direction.MC_Negative
    trip: list[float] = []
    speed: list[float] = []
    furthest = [scene.joint_position(axis)]
    force = [0.0]

    def observe(t: float) -> None:
        q = scene.joint_position(axis)
        furthest[0] = max(furthest[0], q) if direction > 0 else min(furthest[0], q)
        for i in range(data.nefc):
            if data.efc_type[i] == mujoco.mjtConstraint.mjCNSTR_LIMIT_JOINT and (
                data.efc_id[i] == io.joint
            ):
                force[0] = max(force[0], abs(float(data.efc_force[i])))
        if not trip and a.state == mcl.AxisState.ErrorStop:
            trip.append(q)
            speed.append(abs(float(data.qvel[io.dof])))

    def program() -> None:
        power(Axis=a, Enable=True)
        move(
            Axis=a,
            Execute=power.Status,
            Velocity=a.constants.Vmax if a.constants else 0.0,
            Acceleration=acceleration,
            Direction=mode,
        )

    scene.runtime.observers.append(observe)
    try:
        scene.run(program, until=lambda: bool(trip), timeout=10.0)
        scene.run(program, until=lambda: a.active is None or abs(a.sp_vel) == 0.0, timeout=2.0)
        scene.run(program, timeout=0.2)
    finally:
        scene.runtime.observers.remove(observe)
    return LimitStop(speed[0], trip[0], furthest[0], hard_stop, force[0], a.AxErrorID)


def verify(
    machine: MachineDef,
    axis: str,
    constants: mcl.ServoConstants,
    velocity: float,
    distance: float,
) -> list[MoveFigures]:
    """A move each way across the middle of the travel with ``constants``, on the whole stack
    (PLC scan, servo cycle, encoder, the module's delay); figures from the physics, settled into
    the axis' in-position window. A joint of a parallel robot moves with the other joints of its
    group (:func:`robot_joints`), out from the machine's start pose and back."""
    spec, joint_name, _ = _axis_names(machine, axis)
    test = replace(machine, axes={**machine.axes, axis: replace(spec, constants=constants)})
    window = spec.config.in_position
    chain = robot_joints(machine, axis)
    if chain:
        scene = Scene([test], start=dict(machine.demo_start), trace_every=0)
        return [
            measure_move(scene, axis, d, velocity, window=window, together=chain)
            for d in (distance, -distance)
        ]
    model, _ = compose([machine])
    rotary = model.jnt_type[model.joint(joint_name).id] == mujoco.mjtJoint.mjJNT_HINGE
    _, scale = unit_and_scale(spec, rotary=bool(rotary))
    middle = float(np.mean(model.numeric(f"{machine.name}/{axis}_travel").data))
    out = []
    for sign in (1.0, -1.0):
        begin = middle - sign * distance / 2.0 / scale
        scene = Scene([test], start={**machine.demo_start, axis: begin}, trace_every=0)
        out.append(measure_move(scene, axis, sign * distance, velocity, window=window))
    return out


def _unit(machine: MachineDef, axis: str) -> str:
    """The user unit of ``axis`` (mm on a slide, deg on a hinge unless its definition says)."""
    spec, joint_name, _ = _axis_names(machine, axis)
    model, _ = compose([machine])
    rotary = model.jnt_type[model.joint(joint_name).id] == mujoco.mjtJoint.mjJNT_HINGE
    return unit_and_scale(spec, rotary=bool(rotary))[0]


def robot_joints(machine: MachineDef, axis: str) -> tuple[str, ...]:
    """The other joints of the parallel robot ``axis`` belongs to (the members of its group
    when the group has a kinematic transformation), empty for an axis that moves alone."""
    if machine.kinematics is None or axis not in machine.group:
        return ()
    return tuple(name for name in machine.group if name != axis)


ROBOT_DISTANCE = 20.0
"""The verification's default distance for a parallel robot's joint [u] (deg on the delta
picker: the effector 136 mm along z, clear of the belt)."""


def main(argv: list[str] | None = None) -> int:
    """Command line: identify the drive, print the derived constants and the verification."""
    import scenes

    parser = argparse.ArgumentParser(
        prog="python -m scenes.tools.commissioning",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("machine", help="registered machine, e.g. gantry")
    parser.add_argument("axis", help="axis name, e.g. X")
    parser.add_argument("--velocity", type=float, default=400.0, help="verification [u/s]")
    parser.add_argument(
        "--distance",
        type=float,
        default=None,
        help=f"verification [u]; default 150, a parallel robot's joint {ROBOT_DISTANCE:g}",
    )
    args = parser.parse_args(argv)
    machine = scenes.definition(args.machine)
    spec, _, _ = _axis_names(machine, args.axis)
    response = identify(machine, args.axis)
    tuning = derive(spec, response, machine.servo_period)
    c, u = tuning.constants, _unit(machine, args.axis)
    milli = "µm" if u == "mm" else f"m{u}"  # the figures' thousandths
    print(f"{args.machine} {args.axis}: velocity steps of {response.step:g} V on the amplifier")
    print(f"  gain K        {response.gain:10.3f} {u}/s per V")
    print(
        f"  lag T         {response.lag * 1e3:10.3f} ms  (t63 {response.t63 * 1e3:.2f} ms, "
        f"~{response.bandwidth:.0f} Hz)"
    )
    print(f"  drift at 0 V  {response.drift:10.3f} {u}/s")
    print(f"  friction loss {response.friction:10.3f} {u}/s")
    print(f"  loop lag      {tuning.loop_lag * 1e3:10.3f} ms  Kv {tuning.kv:.1f} 1/s")
    print(f"ServoConstants(Kp={c.Kp}, Ki={c.Ki}, Ff={c.Ff}, Ka={c.Ka}, Kf={c.Kf})")
    print(f"  holding voltage {-response.drift / response.gain:.4f} V")
    chain = robot_joints(machine, args.axis)
    distance = args.distance or (ROBOT_DISTANCE if chain else 150.0)
    figures = verify(machine, args.axis, c, args.velocity, distance)
    if chain:
        print(f"  {args.axis} moves with {', '.join(chain)} (closed chains), out and back")
    for fig, sign in zip(figures, "+-", strict=True):
        print(
            f"  move {sign}{distance:g} at {args.velocity:g}: peak following error "
            f"{fig.peak_error * 1e3:.1f} {milli}, overshoot {fig.overshoot * 1e3:.1f} {milli}, "
            f"settled to {spec.config.in_position * 1e3:g} {milli} in {fig.settling * 1e3:.0f} ms"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
