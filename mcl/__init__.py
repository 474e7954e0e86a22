"""mcl — the PLCopen motion library of the Teco MotionControlLib (GT-x75x servo modules).

Function blocks keep PLCopen's and Teco's names; see docs/reference.md for the behaviour contract.
``mcl`` imports neither mujoco nor viser: it drives any plant that subclasses
:class:`AxisChannel` (the :class:`AxisIO` contract).

The public API is this namespace (``__all__``) and the modules used by name: :mod:`mcl.faults`,
:mod:`mcl.trace`, :mod:`mcl.cam_table`, :mod:`mcl.errors`, :mod:`mcl.channel` (what a plant
subclasses), :mod:`mcl.simaxis`, :mod:`mcl.runtime`, :mod:`mcl.extras`, and the tools
``python -m mcl.build`` (:mod:`mcl.native`) and ``python -m mcl.reference``. The modules of the
blocks by topic (``mcl.motion``, ``mcl.homing``, …) declare what they define, and the blocks are
imported from ``mcl``. Internal to the library, imported by no other package (``lint-imports``
checks it): :mod:`mcl.axis_state`, :mod:`mcl.cam_coupling`, :mod:`mcl.command`, :mod:`mcl.fb`
(but its base :class:`MotionFB`), :mod:`mcl.handover`, :mod:`mcl.path`, :mod:`mcl.probe_latch`,
:mod:`mcl.software_limits`, :mod:`mcl.time_scale` and :mod:`mcl.trajectory`.
``mcl.st`` is the deprecated alias of :mod:`plc.st`.
"""

from mcl import native

COMPILED = native.activate("mcl", __path__)
"""The package runs its compiled build (see :mod:`mcl.native`); False: pure Python."""

from mcl import faults
from mcl.administrative import (
    GT_Analog,
    GT_AxErrStringCZ,
    GT_AxErrStringEN,
    GT_AxStatusString,
    GT_SetConstant,
    GT_SInfo,
    GT_SWLim,
    MC_Power,
    MC_ReadActualPosition,
    MC_ReadAxisError,
    MC_ReadStatus,
    MC_Reset,
    MC_SetPosition,
)
from mcl.axis import Axis, AxisConfig, AxisSnapshot
from mcl.cam import MC_CamIn, MC_CamOut, MC_CamTableSelect, MC_Phasing, MC_StartMode
from mcl.cam_readout import CamProfile, RunningCam, cam_profile, running_cam
from mcl.cam_table import MC_CAM_REF, Cam, CamLaw, MC_CamPoint, rotary_knife
from mcl.channel import IDEAL as IDEAL_SENSORS
from mcl.channel import AxisChannel, ChannelSnapshot, Marks, Sensors
from mcl.coordinate_system import ProductFrame
from mcl.delta_kinematics import DeltaKinematics
from mcl.encoder import AbsoluteEncoder
from mcl.enums import (
    MC_CIRC_MODE,
    MC_CIRC_PATHCHOICE,
    MC_COORD_SYSTEM,
    MC_TRANSITION_MODE,
    AxisState,
    GroupState,
    MC_BufferMode,
    MC_Direction,
    MC_ExecutionMode,
    MC_SwitchMode,
)
from mcl.errors import ErrorID, StateError, error_text
from mcl.fb import MotionFB
from mcl.flying_reference import MC_StepRefFlyingRefPulse, MC_StepRefFlyingSwitch
from mcl.force import MC_ForceControl
from mcl.gcode import GCodeError, MC_PathSelect, parse_gcode, read_gcode
from mcl.gearing import MC_GearIn, MC_GearInPos, MC_GearOut
from mcl.group import AxesGroup
from mcl.group_control import (
    MC_GroupContinue,
    MC_GroupHalt,
    MC_GroupHome,
    MC_GroupInterrupt,
    MC_GroupReadActualAcceleration,
    MC_GroupReadActualVelocity,
    MC_GroupReadConfiguration,
    MC_GroupSetOverride,
    MC_GroupSetPosition,
)
from mcl.group_fb import (
    MC_AddAxisToGroup,
    MC_GroupDisable,
    MC_GroupEnable,
    MC_GroupReadActualPosition,
    MC_GroupReadError,
    MC_GroupReadStatus,
    MC_GroupReset,
    MC_GroupStop,
    MC_MoveCircularAbsolute,
    MC_MoveCircularRelative,
    MC_MoveDirectAbsolute,
    MC_MoveDirectRelative,
    MC_MoveLinearAbsolute,
    MC_MoveLinearRelative,
    MC_UngroupAllAxes,
)
from mcl.group_sync import MC_MovePathSynchronized, MC_SyncAxisToGroup
from mcl.homing import (
    MC_FinishHoming,
    MC_StepAbsolute,
    MC_StepAbsSwitch,
    MC_StepBlock,
    MC_StepDirect,
    MC_StepLimitSwitch,
    MC_StepRefPulse,
)
from mcl.inputs_outputs import (
    MC_ReadAnalogInput,
    MC_ReadDigitalInput,
    MC_ReadDigitalOutput,
    MC_WriteDigitalOutput,
)
from mcl.io import AxisIO
from mcl.kin_fb import MC_ReadKinTransform, MC_SetKinTransform
from mcl.kinematics import KinematicsError, KinTransform, TcpLimits
from mcl.module import Module
from mcl.motion import (
    GT_EStop,
    GT_Jog,
    GT_MoveAbsBlock,
    MC_Halt,
    MC_MoveAbsolute,
    MC_MoveAdditive,
    MC_MoveContinuousAbsolute,
    MC_MoveContinuousRelative,
    MC_MoveRelative,
    MC_MoveVelocity,
    MC_Stop,
)
from mcl.override import MC_SetOverride
from mcl.parameters import (
    MC_ReadBoolParameter,
    MC_ReadParameter,
    MC_WriteBoolParameter,
    MC_WriteParameter,
)
from mcl.path_table import MC_PATH_DATA_REF, MC_PATH_SEGMENT, MC_MovePath
from mcl.profiles import (
    MC_TA,
    MC_TA_REF,
    MC_TP,
    MC_TP_REF,
    MC_TV,
    MC_TV_REF,
    MC_AccelerationProfile,
    MC_PositionProfile,
    MC_VelocityProfile,
)
from mcl.runtime import ConditionTimeout, Machine, MachineState, Plant, Runtime
from mcl.servo import ServoConstants
from mcl.simaxis import SimAxis, SimAxisParams, SimMachine, SimPlant, SimPlantState
from mcl.touch_probe import MC_AbortTrigger, MC_TouchProbe
from mcl.tracking import (
    MC_SetCartesianTransform,
    MC_SetCoordinateTransform,
    MC_TrackConveyorBelt,
    MC_TrackRotaryTable,
)

__all__ = [
    "IDEAL_SENSORS",
    "MC_CAM_REF",
    "MC_CIRC_MODE",
    "MC_CIRC_PATHCHOICE",
    "MC_COORD_SYSTEM",
    "MC_PATH_DATA_REF",
    "MC_PATH_SEGMENT",
    "MC_TA",
    "MC_TA_REF",
    "MC_TP",
    "MC_TP_REF",
    "MC_TRANSITION_MODE",
    "MC_TV",
    "MC_TV_REF",
    "AbsoluteEncoder",
    "AxesGroup",
    "Axis",
    "AxisChannel",
    "AxisConfig",
    "AxisIO",
    "AxisSnapshot",
    "AxisState",
    "Cam",
    "CamLaw",
    "CamProfile",
    "ChannelSnapshot",
    "ConditionTimeout",
    "DeltaKinematics",
    "ErrorID",
    "GCodeError",
    "GT_Analog",
    "GT_AxErrStringCZ",
    "GT_AxErrStringEN",
    "GT_AxStatusString",
    "GT_EStop",
    "GT_Jog",
    "GT_MoveAbsBlock",
    "GT_SInfo",
    "GT_SWLim",
    "GT_SetConstant",
    "GroupState",
    "KinTransform",
    "KinematicsError",
    "MC_AbortTrigger",
    "MC_AccelerationProfile",
    "MC_AddAxisToGroup",
    "MC_BufferMode",
    "MC_CamIn",
    "MC_CamOut",
    "MC_CamPoint",
    "MC_CamTableSelect",
    "MC_Direction",
    "MC_ExecutionMode",
    "MC_FinishHoming",
    "MC_ForceControl",
    "MC_GearIn",
    "MC_GearInPos",
    "MC_GearOut",
    "MC_GroupContinue",
    "MC_GroupDisable",
    "MC_GroupEnable",
    "MC_GroupHalt",
    "MC_GroupHome",
    "MC_GroupInterrupt",
    "MC_GroupReadActualAcceleration",
    "MC_GroupReadActualPosition",
    "MC_GroupReadActualVelocity",
    "MC_GroupReadConfiguration",
    "MC_GroupReadError",
    "MC_GroupReadStatus",
    "MC_GroupReset",
    "MC_GroupSetOverride",
    "MC_GroupSetPosition",
    "MC_GroupStop",
    "MC_Halt",
    "MC_MoveAbsolute",
    "MC_MoveAdditive",
    "MC_MoveCircularAbsolute",
    "MC_MoveCircularRelative",
    "MC_MoveContinuousAbsolute",
    "MC_MoveContinuousRelative",
    "MC_MoveDirectAbsolute",
    "MC_MoveDirectRelative",
    "MC_MoveLinearAbsolute",
    "MC_MoveLinearRelative",
    "MC_MovePath",
    "MC_MovePathSynchronized",
    "MC_MoveRelative",
    "MC_MoveVelocity",
    "MC_PathSelect",
    "MC_Phasing",
    "MC_PositionProfile",
    "MC_Power",
    "MC_ReadActualPosition",
    "MC_ReadAnalogInput",
    "MC_ReadAxisError",
    "MC_ReadBoolParameter",
    "MC_ReadDigitalInput",
    "MC_ReadDigitalOutput",
    "MC_ReadKinTransform",
    "MC_ReadParameter",
    "MC_ReadStatus",
    "MC_Reset",
    "MC_SetCartesianTransform",
    "MC_SetCoordinateTransform",
    "MC_SetKinTransform",
    "MC_SetOverride",
    "MC_SetPosition",
    "MC_StartMode",
    "MC_StepAbsSwitch",
    "MC_StepAbsolute",
    "MC_StepBlock",
    "MC_StepDirect",
    "MC_StepLimitSwitch",
    "MC_StepRefFlyingRefPulse",
    "MC_StepRefFlyingSwitch",
    "MC_StepRefPulse",
    "MC_Stop",
    "MC_SwitchMode",
    "MC_SyncAxisToGroup",
    "MC_TouchProbe",
    "MC_TrackConveyorBelt",
    "MC_TrackRotaryTable",
    "MC_UngroupAllAxes",
    "MC_VelocityProfile",
    "MC_WriteBoolParameter",
    "MC_WriteDigitalOutput",
    "MC_WriteParameter",
    "Machine",
    "MachineState",
    "Marks",
    "Module",
    "MotionFB",
    "Plant",
    "ProductFrame",
    "RunningCam",
    "Runtime",
    "Sensors",
    "ServoConstants",
    "SimAxis",
    "SimAxisParams",
    "SimMachine",
    "SimPlant",
    "SimPlantState",
    "StateError",
    "TcpLimits",
    "cam_profile",
    "error_text",
    "faults",
    "parse_gcode",
    "read_gcode",
    "rotary_knife",
    "running_cam",
]
