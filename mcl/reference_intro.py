"""The opening of the function-block reference (docs/reference.md): what mcl is, how a block is
called, the state machines; ``{transitions}`` takes the table of the axis state machine's
transitions (:func:`mcl.reference.generate`)."""

__all__ = ["INTRO"]

INTRO = """\
# mcl reference

`mcl` implements the PLCopen function blocks of the Teco MotionControlLib for the GT-x75x servo
modules. This page lists every function block (FB) with its inputs and outputs, the state machines,
the enumerations and the error codes. The FB sections, the tables of enumeration values and the
error codes are generated from the code: `python -m mcl.reference --write` rewrites this file.

## Units
- Positions and distances are in the axis' user units [u] (mm on the linear axes of the models,
  degrees on rotary axes); velocities [u/s], accelerations and decelerations [u/s²], jerk [u/s³],
  times [s] unless a block says otherwise (`Filter` of GT_SetConstant is in ms).
- `Position` is absolute in the axis coordinate system, `Distance` is a difference of positions;
  both may be negative. Group blocks take one value per member, in the order the members were
  added.
- `Velocity` must be > 0 and at least 1 % of the axis' `Vmax`. `Acceleration`, `Deceleration`
  and `Jerk` must be >= 0; 0 means the axis default (no jerk limit where that default is 0 too).
  Values above the axis maxima are clamped, not refused.

## Calling a function block
An FB is an instance; one call is one PLC scan of that instance:

```python
move = mcl.MC_MoveAbsolute()
move(Axis=X, Execute=True, Position=100.0, Velocity=200.0)   # in every scan
```

- Inputs are keyword arguments with the PLCopen/Teco names. An input left out keeps the value of
  the previous call (at the first call: the default listed below). An unknown input name raises
  `TypeError` naming the valid ones. The in-out (`Axis`, `AxesGroup`) must be given at least
  once; `None` keeps the reference of the previous call.
- Blocks with `Execute` are edge-triggered: the rising edge of `Execute` samples the inputs and
  starts the job. To change a parameter, change it and give a new edge. A falling edge does not
  stop a running command. A new rising edge on a busy instance restarts it; the previous job then
  reports neither Done nor CommandAborted.
- Blocks with `Enable` are level-sensitive: evaluated in every call while `Enable` is TRUE,
  `Valid` while the outputs are valid; `Enable` FALSE resets the outputs. GT_Jog's `JogPos` and
  `JogNeg`, GT_MoveAbsBlock's `ExtStop` and MC_Stop's `Execute` (holding Stopping) are read every
  call as well.
- A running block reports problems through `Error`/`ErrorID` only, never by raising. A parameter
  error (out of range, NaN, infinite, wrong sign, target beyond a SW limit) sets `Error` on that
  instance and leaves the axis as it was. Several instances of one FB type are independent.

## Outputs
- `Busy`, `Done`, `Error` and `CommandAborted` are mutually exclusive; so are `Active`, `Done`,
  `Error` and `CommandAborted`. `Error` is TRUE exactly when `ErrorID` is not 0.
- `Busy` rises with the `Execute` edge and falls when `Done`, `CommandAborted` or `Error` rises.
  `Active` is TRUE while the instance's command controls the axis (a buffered command is `Busy`
  but not yet `Active`; a flying reference, which commands no motion: while it is armed).
- `Done`, `InVelocity`, `Error`, `ErrorID` and `CommandAborted` stay while `Execute` is TRUE and
  are reset by its falling edge. If `Execute` fell before the command ended, the final output is
  shown for exactly one call.
- A motion block whose command is taken over by another command reports `CommandAborted`
  (`Aborted` is the Teco name of the same output). An axis error ends the running commands with
  `Error` and the axis' error code.

## BufferMode
`BufferMode` (enum `MC_BufferMode`) says when a motion command takes over the axis.
- `Aborting`: at once; the active command and the queued ones report `CommandAborted`.
- `Buffered`: after the active command signals its output (`Done`; `InVelocity` for
  MC_MoveVelocity; `Done` AND NOT `Execute` for MC_Stop), starting from standstill.
- `BlendingLow`, `BlendingPrevious`, `BlendingNext`, `BlendingHigh`: like Buffered, but the axis
  does not stop: the first motion reaches its target with the lower, the first's, the second's or
  the higher of the two commanded velocities. When the second motion reverses the direction, the
  hand-over happens at zero velocity.

## Axis state machine
Every axis (`mcl.Axis`, the AXIS_REF) is in exactly one state of `mcl.AxisState`.

{transitions}

The motion states are DiscreteMotion, ContinuousMotion and SynchronizedMotion. A motion command
is refused with `Econst` 12 before GT_SetConstant, `Epower` 10 in Disabled, `Eerrstop` 11 in
ErrorStop, `EAxStop` 6 in Stopping, 1000 on a group member and `Ehome` 9 in Homing (except the
homing steps, MC_Halt and MC_Stop). MC_MoveAbsolute and GT_MoveAbsBlock need `Ref` (`Ehome` 9);
without `Ref` the SW limits are not checked. The reading blocks, GT_SetConstant, GT_SInfo,
MC_SetOverride, MC_SetPosition, the flying references (MC_StepRefFlyingSwitch,
MC_StepRefFlyingRefPulse: they set the coordinate and `Ref` at an edge while another command moves
the axis) and GT_Analog (Disabled only) do not change the state; an override of 0 holds a moving
axis on its path in its motion state.

Supervision: in every state in which the position loop is closed (StandStill, the motion states,
Homing, Stopping, and ErrorStop after an error that keeps the loop closed: a limit switch, a SW
limit, a cam's or gearing's error, a homing supervision error, MC_Power on with an error pending)
every servo cycle checks the following error (beyond MaxPositionLag, DevMax, while
EnablePosLagMonitoring is TRUE) and the encoder line. Either gives ERRPOS 2001 as described
above: the loop opens, the amplifier stops the axis at 0 V for `quick_stop_time`, then the enable
drops. In ErrorStop 2001 replaces the error the axis stopped with (MC_Reset then leaves it
Disabled); other errors are not taken there, the axis is stopping already. An error stop holds
the axis where its ramp ended (on a modulo axis too: the hold is the model position, not
wrapped); when something drags it from there beyond DevMax (a knife drum's blade stopped in a
running web), the loop opens and the drive lets go instead of fighting it.

## Axes groups
An axes group (`mcl.AxesGroup`, the AXES_GROUP_REF) holds up to three axes in the order they were
added and is in one state of `mcl.GroupState`: GroupDisabled until MC_GroupEnable and after
MC_GroupDisable or MC_UngroupAllAxes; GroupMoving while a group command runs (its members are in
SynchronizedMotion); GroupStopping from MC_GroupStop until its `Done` AND NOT `Execute`;
GroupHoming while a member is homing; GroupErrorStop while a member is in ErrorStop or the group
error is set (8001 when a member exceeded its following error during a group motion or in the
group's error stop; a member's 2001 replaces an earlier group error), left only through
MC_GroupReset; GroupStandby otherwise. Single-axis motion commands on a member are refused
with 1000. A group moves along a path of lines, arcs and helices, run along its arc length with
the speed the curvature and every member's limits allow (Function blocks of axes groups, below).
"""
