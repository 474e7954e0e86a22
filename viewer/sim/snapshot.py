"""Snapshots: immutable copies of what the viewer shows (axes, signals, demo, error history,
physics), and how the simulation thread copies them from a scene between two PLC cycles."""

from __future__ import annotations

__all__ = [
    "RESULTS_SHOWN",
    "AxisInfo",
    "AxisView",
    "Channel",
    "DemoView",
    "Event",
    "SignalView",
    "Snapshot",
    "axis_info",
    "axis_view",
    "copy_array",
    "mujoco_of",
    "results_of",
    "sw_limits_reached",
]

import logging
import math
from collections.abc import Mapping
from dataclasses import dataclass

import mujoco
import numpy as np
import numpy.typing as npt

import mcl
from plc.commissioning.axis import CommissioningView
from plc.operator.hmi import Panel
from scenes import DemoProgram, MachineDef
from scenes.plant.mujoco import MujocoAxisIO
from scenes.scene import Scene
from viewer.sim.cam_view import CamView
from viewer.sim.product_frames import FrameView

log = logging.getLogger(__name__)

RESULTS_SHOWN = 10
"""Rows of a demo's results table a snapshot carries (the last ones)."""


@dataclass(frozen=True, slots=True)
class Event:
    """One entry of the error history: an axis error, a refused command, a refused page.

    Attributes:
        wall: Wall-clock time [s since the epoch] (shown as UTC).
        time: Simulated time [s].
        source: Axis, group or ``"viewer"``.
        text: What happened.
        scene: The machine it happened on (empty: not said).
    """

    wall: float
    time: float
    source: str
    text: str
    scene: str = ""


@dataclass(frozen=True, slots=True)
class Channel:
    """One signal the scope can show.

    Attributes:
        name: ``"X position"``, ``"X LIM+"``, ``"pressure_A"``.
        unit: ``"mm"``, ``"V"``, ``""`` for a digital signal (0 or 1).
        digital: It is 0 or 1 (edges can trigger the scope).
    """

    name: str
    unit: str
    digital: bool


@dataclass(frozen=True, slots=True)
class AxisView:
    """What the panel of one axis shows, copied between two PLC cycles.

    Attributes:
        name: Axis name in the scene (``"X"``).
        joint: Name of the axis joint in the model (``"gantry/X"``); switch geoms are named
            ``<joint>_lim_neg_geom``, ``<joint>_lim_pos_geom``, ``<joint>_ref_geom``. Empty for
            a simulated axis (no model).
        unit: The axis' user unit u (``axis.config.unit``: ``"mm"``, ``"deg"``, ...).
        has_drive: The axis has a drive; False for an encoder-only axis (no Power, no moves).
        switches: The switch inputs the axis has, of ``"lim_neg"``, ``"lim_pos"``, ``"ref"``
            (from its machine definition).
        homeable: The machine definition gives the axis a homing recipe.
        position: Actual position ``POS`` [u].
        velocity: Actual velocity ``VEL`` [u/s]; of an encoder-only axis its position
            difference over 0.2 s, filtered with 0.1 s (:mod:`~viewer.sim.velocity`; its
            ``VEL`` flickers by a count per cycle).
        following_error: Set point minus actual position [u].
        volts: Analog command of the last servo cycle [V].
        joint_position: Ground-truth joint coordinate [m or rad] (NaN if the plant has none).
        vmax: Velocity at 10 V [u/s] from the servo constants (NaN before they are set).
        state: ``GT_AxStatusString.StatStr`` (empty before the first scan).
        error: ``GT_AxErrStringEN.ErrStr`` (empty: no axis error).
        error_id: ``AxErrorID``.
        referenced: The axis has its reference (``Ref``).
        powered: The axis is not Disabled.
        lim_pos: LIM+ input.
        lim_neg: LIM− input.
        ref: REF input.
        index: Encoder index pulse level.
        inputs: Further digital inputs of the axis' channel (empty: none).
        outputs: Digital outputs of the axis' channel (empty: none), e.g. a knife valve.
        power_request: Level the operator's MC_Power gets (``None``: not called).
        jogging: Jog request of the last scan: +1, −1 or 0.
        homing: The operator's homing procedure runs.
        stopping: The operator's MC_Stop is executing.
        message: Outcome of the operator's last command.
        last_error: The operator's last refused command with its error (empty: none).
        group: Name of the axes group the axis belongs to (empty: none).
        constants: The axis' servo constants (None before they are set).
        set_position: Set point (model position, GT_SInfo 20) [u]; NaN without a drive.
        set_velocity: Set velocity (model velocity) [u/s]; NaN without a drive.
        peak_following_error: Largest |following error| since the last peak reset, taken
            every PLC scan (:class:`~viewer.sim.peaks.PeakHold`) [u].
        enabled: The drive enable is on (``MC_Power.Status``).
        standstill: The axis is in StandStill.
        moving: The set point is in motion (set velocity or acceleration ≠ 0).
        in_position: The position loop is closed, the set point at rest and |following
            error| within the axis' in-position window (``AxisConfig.in_position``).
        in_position_window: The axis' in-position window [u].
        sw_limit_pos: The positive software limit is reached (active, axis referenced, set
            point at or beyond ``LimPos``) or tripped (ERRSWP 2006).
        sw_limit_neg: The same for the negative limit (``LimNeg``, ERRSWN 2007).
        commissioning: Reversing sequence, step test and jog speed (None: not given).
        home_position: The position the machine's homing recipe gives the axis [u] (NaN: no
            recipe).
        last_error_kind: What :attr:`last_error` is: ``"Refused"`` (the command never ran) or
            ``"Aborted"`` (an axis error stopped it).
    """

    name: str
    joint: str
    unit: str
    has_drive: bool
    switches: tuple[str, ...]
    homeable: bool
    position: float
    velocity: float
    following_error: float
    volts: float
    joint_position: float
    vmax: float
    state: str
    error: str
    error_id: int
    referenced: bool
    powered: bool
    lim_pos: bool
    lim_neg: bool
    ref: bool
    index: bool
    inputs: tuple[bool, ...]
    outputs: tuple[bool, ...]
    power_request: bool | None
    jogging: int
    homing: bool
    stopping: bool
    message: str
    last_error: str = ""
    group: str = ""
    constants: mcl.ServoConstants | None = None
    set_position: float = math.nan
    set_velocity: float = math.nan
    peak_following_error: float = 0.0
    enabled: bool = False
    standstill: bool = False
    moving: bool = False
    in_position: bool = False
    in_position_window: float = 0.0
    sw_limit_pos: bool = False
    sw_limit_neg: bool = False
    commissioning: CommissioningView | None = None
    home_position: float = math.nan
    last_error_kind: str = "Refused"


@dataclass(frozen=True, slots=True)
class SignalView:
    """A value the machine publishes besides its axes (``scene.signals``), e.g. a pressure.

    Attributes:
        name: Its name in the scene (``"pressure_A"``).
        value: Its value when the snapshot was taken (NaN if reading it failed).
        unit: Its unit (``"bar"``, ``"N"``, ``"−1…1"``).
        label: What the page calls it (``"pressure A"``): the signal's label, else its name.
    """

    name: str
    value: float
    unit: str
    label: str = ""


@dataclass(frozen=True, slots=True)
class DemoView:
    """State of the scene's demo program.

    Attributes:
        available: The scene has a demo program.
        running: It is being called every PLC cycle.
        done: It reported ``done``.
        step: Its ``step`` text (empty before it first ran).
        error: What ended it: its own ``error`` report or an exception, as text (empty:
            none).
        runs: Times it was started since Run demo (repeats included).
        repeat: Repeat demo is on.
    """

    available: bool
    running: bool
    done: bool
    step: str
    error: str
    runs: int = 0
    repeat: bool = False


@dataclass(frozen=True, slots=True)
class Snapshot:
    """Everything the viewer shows, copied by the simulation thread between two PLC cycles.

    Attributes:
        generation: Increments with every (re)built scene; a viewer rebuilds its scene nodes
            when it changes.
        scene: Registry name of the scene.
        description: The machine's one-line description (``MachineDef.description``).
        time: Simulated time [s].
        wall: Wall clock [s] when the snapshot was taken.
        model: The scene's compiled model (shared, not copied: the viewer only reads it);
            None for a machine of simulated axes, which has no 3-D model.
        qpos: Joint coordinates of every joint [m, rad], shape (nq,) (empty without a model).
        xpos: World position of every body [m], shape (nbody, 3) (empty without a model).
        xquat: World orientation of every body (w, x, y, z), shape (nbody, 4) (empty without a
            model).
        axes: Axis views by axis name, in the scene's order.
        signals: The machine's published signals (``scene.signals``) in definition order;
            empty if it publishes none.
        paused: The simulation is paused.
        speed: Requested speed: simulated seconds per wall second (``inf``: as fast as possible).
        realtime_factor: Achieved simulated seconds per wall second over the last second.
        demo: State of the demo program.
        fault: Text of an exception that paused the simulation (empty: none).
        events: The error history, newest last (:data:`~viewer.sim.session.EVENTS_KEPT` at most).
        results: The demo's results table: (column names, last :data:`RESULTS_SHOWN` rows as
            texts); empty when the demo exposes none (see ``DemoProgram`` in scenes.definition).
        channels: The scope channels of the scene (:class:`~viewer.sim.recorder.Recorder`).
        groups: Names of the axes groups the axes belong to now.
        contacts: Active contacts of the physics (``viewer.view3d.overlays.contact_forces``: point
        [m],
            normal force [N]); None without a model.
        constraints: Hard-stop and tendon forces of the physics
            (``viewer.view3d.overlays.constraint_forces``: point [m], force [N]); None without a
            model.
        cams: The cammed axes with their table's profile and operating point
            (:class:`~viewer.sim.cam_view.CamView`); empty when no axis is cammed.
        frames: The product coordinate system of each robot group that has one, in the
            world (:class:`~viewer.sim.product_frames.FrameView`; tracking: it moves on).
    """

    generation: int
    scene: str
    description: str
    time: float
    wall: float
    model: mujoco.MjModel | None
    qpos: npt.NDArray[np.float64]
    xpos: npt.NDArray[np.float64]
    xquat: npt.NDArray[np.float64]
    axes: Mapping[str, AxisView]
    signals: tuple[SignalView, ...]
    paused: bool
    speed: float
    realtime_factor: float
    demo: DemoView
    fault: str
    events: tuple[Event, ...] = ()
    results: tuple[tuple[str, ...], tuple[tuple[str, ...], ...]] = ((), ())
    channels: tuple[Channel, ...] = ()
    groups: tuple[str, ...] = ()
    contacts: npt.NDArray[np.float64] | None = None
    constraints: npt.NDArray[np.float64] | None = None
    cams: tuple[CamView, ...] = ()
    frames: tuple[FrameView, ...] = ()


@dataclass(frozen=True, slots=True)
class AxisInfo:
    """What the machine definition says about an axis' panel (fixed while the scene lives)."""

    joint: str
    unit: str
    has_drive: bool
    switches: tuple[str, ...]
    homeable: bool


def axis_view(
    scene: Scene,
    name: str,
    panel: Panel,
    info: AxisInfo,
    peak: float = 0.0,
    velocity: float | None = None,
) -> AxisView:
    """What the panel of the axis ``name`` of ``scene`` shows now.

    Args:
        scene: The scene.
        name: The axis' name in the scene.
        panel: Its operator panel (request flags; its operator: the last command's outcome).
        info: What the machine definition says about it.
        peak: Its peak |following error| since the last reset [u].
        velocity: Its velocity as shown [u/s] (:class:`~viewer.sim.velocity.ShownVelocity`;
            None: ``VEL``).
    """
    axis = scene.axes[name]
    op = panel.operator
    io = axis.io
    drive = axis.has_drive
    powered = axis.state != mcl.AxisState.Disabled
    limit_neg, limit_pos = sw_limits_reached(axis)
    return AxisView(
        name=name,
        joint=info.joint,
        unit=info.unit,
        has_drive=info.has_drive,
        switches=info.switches,
        homeable=info.homeable,
        position=axis.POS,
        velocity=axis.VEL if velocity is None else velocity,
        following_error=axis.following_error,
        volts=axis.volts,
        joint_position=scene.joint_position(name),
        vmax=axis.constants.Vmax if axis.constants is not None else math.nan,
        state=panel.status.StatStr,
        error=panel.error_text.ErrStr,
        error_id=axis.AxErrorID,
        referenced=axis.Ref,
        powered=powered,
        lim_pos=bool(io.lim_pos),
        lim_neg=bool(io.lim_neg),
        ref=bool(io.ref),
        index=bool(io.index),
        inputs=tuple(bool(i) for i in io.inputs),
        outputs=tuple(bool(o) for o in io.outputs),
        power_request=panel.power_request,
        jogging=op.jogging,
        homing=op.homing,
        stopping=op.stopping,
        message=op.message,
        last_error=op.last_error,
        group=axis.group.name if isinstance(axis.group, mcl.AxesGroup) else "",
        constants=axis.constants,
        set_position=axis.optional(20) if drive else math.nan,
        set_velocity=axis.sp_vel if drive else math.nan,
        peak_following_error=peak,
        enabled=axis.drive_enabled,
        standstill=axis.state == mcl.AxisState.StandStill,
        moving=axis.moving,
        in_position=axis.loop_closed
        and not axis.moving
        and abs(axis.following_error) <= axis.config.in_position,
        in_position_window=axis.config.in_position,
        sw_limit_pos=limit_pos,
        sw_limit_neg=limit_neg,
        commissioning=panel.commissioning_view,
        home_position=op.recipe.recipe.set_position if op.recipe is not None else math.nan,
        last_error_kind=op.last_error_kind,
    )


def sw_limits_reached(axis: mcl.Axis) -> tuple[bool, bool]:
    """Whether the negative and the positive software limit is reached: switched on (by
    GT_SetConstant with ``LimPos`` > ``LimNeg``, GT_SWLim or MC_WriteBoolParameter; linear
    axis), the axis referenced and its set point at or beyond the limit (half a count:
    rounding), or the limit tripped (ERRSWN 2007, ERRSWP 2006)."""
    code = axis.AxErrorID
    negative, positive = code == mcl.ErrorID.ERRSWN, code == mcl.ErrorID.ERRSWP
    low, high = axis.sw_limit_range()
    margin = 0.5 * axis.config.resolution
    negative = negative or axis.sp_pos <= low + margin
    positive = positive or axis.sp_pos >= high - margin
    return negative, positive


def results_of(demo: DemoProgram) -> tuple[tuple[str, ...], tuple[tuple[str, ...], ...]]:
    """The last :data:`RESULTS_SHOWN` rows of a demo's optional ``results`` as texts."""
    try:
        rows = list(getattr(demo, "results", ()) or ())[-RESULTS_SHOWN:]
        if not rows:
            return (), ()
        columns = tuple(str(c) for c in rows[-1])
        return columns, tuple(tuple(_cell(row.get(c)) for c in columns) for row in rows)
    except Exception:  # a demo's table must not stop the simulation thread
        log.debug("results of the demo failed", exc_info=True)
        return (), ()


def _cell(value: object) -> str:
    """A table cell: numbers with 3 decimals, None empty, anything else as text."""
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:.3f}"
    return str(value)


def axis_info(definition: MachineDef, scene: Scene) -> dict[str, AxisInfo]:
    """What the machine definition and the built scene say about each axis' panel."""
    recipes = definition.homing
    info: dict[str, AxisInfo] = {}
    for name, axis in scene.axes.items():
        spec = definition.scene_axes.get(name)
        io = axis.io
        info[name] = AxisInfo(
            joint=io.name if isinstance(io, MujocoAxisIO) else "",
            unit=axis.config.unit,
            has_drive=axis.has_drive,
            switches=spec.switches if spec is not None else ("lim_neg", "lim_pos", "ref"),
            homeable=name in recipes,
        )
    return info


def mujoco_of(scene: Scene) -> tuple[mujoco.MjModel | None, mujoco.MjData | None]:
    """The MuJoCo model and data of a scene, ``(None, None)`` for a machine of simulated axes."""
    try:
        model, data = scene.model, scene.data
    except TypeError:  # simulated axes: the scene has no MuJoCo model
        return None, None
    if model is None or data is None:
        return None, None
    return model, data


def copy_array(array: npt.ArrayLike | None, empty: tuple[int, ...]) -> npt.NDArray[np.float64]:
    """A float copy of a MuJoCo array, or an empty one of shape ``empty`` without a model."""
    if array is None:
        return np.zeros(empty)
    return np.array(array, dtype=np.float64)
