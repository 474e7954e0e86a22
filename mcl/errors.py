"""Error codes of the MotionControlLib and their texts (MotionControlLib chapter 7.1)."""

from __future__ import annotations

__all__ = ["ConditionTimeout", "ErrorID", "StateError", "check_finite", "error_text"]

import math
from enum import IntEnum


class ConditionTimeout(TimeoutError):
    """``until`` did not become true within the simulated ``timeout`` (:meth:`mcl.Machine.run`)."""


class StateError(RuntimeError):
    """A machine state cannot be saved now (an axis moves) or does not fit the machine it is
    restored into (:meth:`mcl.Machine.save_state`); the message says which and what to do."""


class ErrorID(IntEnum):
    """Error codes reported in ``ErrorID`` of a function block or ``AxErrorID`` of an axis."""

    NoError = 0
    ETime = 1
    EDistance = 2
    EDev = 3
    EBlending = 4
    EParam = 5
    EAxStop = 6
    EAxis = 7
    Ecil = 8
    Ehome = 9
    Epower = 10
    Eerrstop = 11
    Econst = 12
    EpowerOff = 13
    ENoDrive = 14
    """Beyond the Teco library: a motion or power command on an encoder-only axis (no drive)."""
    ESyncUnreachable = 15
    """Beyond the Teco library (MC_GearInPos): the slave cannot synchronise before
    MasterSyncPosition within Velocity/Acceleration/Deceleration/Jerk without backing up."""
    EMasterReversed = 16
    """Beyond the Teco library (MC_GearInPos): the master moved back during synchronisation."""
    EMasterError = 17
    """Beyond the Teco library (gearing): the master is in ErrorStop or its encoder failed."""
    ENotGeared = 18
    """Beyond the Teco library (MC_GearOut): the slave is not geared to a master."""
    ENoParameter = 19
    """Beyond the Teco library (MC_ReadParameter, MC_WriteParameter and their BOOL forms): no
    parameter of this number and type (a BOOL parameter read or written as REAL, or the other
    way round)."""
    EReadOnly = 20
    """Beyond the Teco library (MC_WriteParameter): the parameter can only be read."""
    ENoAbsolute = 21
    """Beyond the Teco library (MC_StepAbsolute): the axis has no absolute measuring system."""
    EAbsFrame = 22
    """Beyond the Teco library (MC_StepAbsolute): the absolute sensor's frame failed its check
    (parity / CRC; :class:`mcl.faults.AbsoluteFrameError`): the reading is not used."""
    ECamLimit = 23
    """Beyond the Teco library (MC_CamIn): at the master's speed the cam needs more than the
    slave's Vmax or maximum acceleration."""
    EWorkspace = 24
    """Beyond the Teco library (kinematic transformation, :mod:`mcl.kinematics`): a target or a
    point of the path is beyond the robot's reach or a joint's range."""
    ESingular = 25
    """Beyond the Teco library (kinematic transformation): a target or a point of the path is
    in or too near a singular pose of the kinematics."""
    ETrackTooFast = 26
    """Beyond the Teco library (MC_TrackConveyorBelt): the belt moves faster than the tool
    point's velocity limit, or than a joint can follow the part."""
    EGroupMember = 1000
    EGroupFull = 1001
    ENotGroupMember = 1003
    EInOtherGroup = 1004
    EGroupEmpty = 1005
    ERRPOS = 2001
    ERRLIP = 2004
    ERRLIN = 2005
    ERRSWP = 2006
    ERRSWN = 2007
    ERRPOSG = 8001


_TEXTS: dict[int, tuple[str, str]] = {
    0: ("no error", "bez chyby"),
    1: ("time limit exceeded", "time limit"),
    2: ("distance limit exceeded", "distance limit"),
    3: ("following error limit exceeded", "polohová odchylka limit"),
    4: ("blending not possible", "nejde udělat blending"),
    5: ("invalid command parameter", "chybný parametr příkazu"),
    6: ("axis is stopped by MC_Stop", "osa je ve stopu příkazem MC_Stop"),
    7: ("hard axis error – error stop", "tvrdá chyba osy - errorstop"),
    8: ("target beyond SW limit", "cíl osy je za SW limitou"),
    9: ("axis not referenced", "osa není v referenci"),
    10: ("axis not powered", "osa není power on"),
    11: ("axis is in ErrorStop", "osa je v stavu ErrorStop"),
    12: ("constants not set", "nejsou zadány konstanty"),
    13: ("axis is powered", "osa je power on"),
    14: ("axis has no drive (encoder only)", "osa nemá pohon (jen enkodér)"),
    15: (
        "synchronisation not reachable before MasterSyncPosition",
        "synchronizace není dosažitelná před MasterSyncPosition",
    ),
    16: ("master reversed during synchronisation", "master osa couvla během synchronizace"),
    17: ("master axis error", "chyba master osy"),
    18: ("slave is not geared", "slave osa není ve vazbě na master"),
    19: ("no parameter of this number and type", "parametr tohoto čísla a typu neexistuje"),
    20: ("parameter is read-only", "parametr je jen pro čtení"),
    21: ("axis has no absolute encoder", "osa nemá absolutní snímač"),
    22: ("absolute encoder frame error", "chyba rámce absolutního snímače"),
    23: (
        "cam needs more than the slave's maximum velocity or acceleration",
        "vačka vyžaduje víc než maximální rychlost nebo zrychlení slave osy",
    ),
    24: (
        "target beyond the workspace of the kinematics",
        "cíl je mimo pracovní prostor kinematiky",
    ),
    25: ("target near a singularity of the kinematics", "cíl je blízko singularity kinematiky"),
    26: (
        "the belt is too fast for the robot to follow the part",
        "pás je příliš rychlý, robot nemůže díl sledovat",
    ),
    1000: ("axis is a group member, command refused", "osa je členem Group, příkaz nelze provést"),
    1001: ("group full", "Group je plná, nelze již přidat osu"),
    1003: ("axis is not a group member", "osa není členem Group"),
    1004: (
        "axis already in another group",
        "osa už je členem Group, nelze ji přidat do jiné Group",
    ),
    1005: ("group has no axes", "Group už nemá žádné osy"),
    2001: ("following error exceeded", "překročení polohové odchylky"),
    2004: ("positive limit switch LIM+ reached", "osa najela na pozitivní limitu LIM+"),
    2005: ("negative limit switch LIM− reached", "osa najela na negativní limitu LIM-"),
    2006: ("positive SW limit reached", "osa najela na pozitivní SW limitu"),
    2007: ("negative SW limit reached", "osa najela na negativní SW limitu"),
    8001: (
        "group member exceeded its following error",
        "osa v grupe překročila polohovou odchylku",
    ),
}


def error_text(code: int, language: str = "en") -> str:
    """The text of an error code.

    Args:
        code: an :class:`ErrorID` value.
        language: ``"en"`` for English, ``"cz"`` for Czech.

    Returns:
        The text; an unknown code gives ``"unknown error <code>"`` / ``"neznámá chyba <code>"``.
    """
    if language not in ("en", "cz"):
        raise ValueError(f"language must be 'en' or 'cz', not {language!r}")
    texts = _TEXTS.get(int(code))
    if texts is None:
        return f"unknown error {code}" if language == "en" else f"neznámá chyba {code}"
    return texts[0] if language == "en" else texts[1]


def check_finite(owner: object, names: tuple[str, ...], positive: bool) -> None:
    """Raise ValueError unless each attribute ``names`` of ``owner`` (machine data, a
    dataclass) is a finite number, > 0 if ``positive``, else >= 0; the message names the class,
    the field and the value."""
    for name in names:
        value = getattr(owner, name)
        if not (math.isfinite(value) and (value > 0.0 if positive else value >= 0.0)):
            raise ValueError(
                f"{type(owner).__name__}.{name} must be a finite number "
                f"{'> 0' if positive else '>= 0'}, got {value!r}"
            )
