"""Faults injected at the I/O boundary: what goes wrong with switches, encoders, drives and brakes.

A fault is a small frozen value. :class:`mcl.channel.AxisChannel` applies the sensor, analog and
drive faults of its axis; the plant behind the channel applies the drive and brake faults to the
physics. :class:`FaultLog` schedules faults by time, sets and clears them from a program, and
records every change (time, axis, fault, set or cleared) so a trace shows them.

What the module does about each fault (the outcome a user sees) is the table in the README.
"""

from __future__ import annotations

__all__ = [
    "SWITCH_NAMES",
    "AbsoluteFrameError",
    "AmplifierFault",
    "AnalogInputFault",
    "AnalogNoise",
    "AnalogOffset",
    "BrakeFailure",
    "BrakeSlow",
    "DriveNotReady",
    "EncoderFreeze",
    "EncoderLostCounts",
    "EncoderNoise",
    "EncoderWireBreak",
    "Fault",
    "FaultEvent",
    "FaultLog",
    "FaultLogState",
    "Injectable",
    "SwitchBounce",
    "SwitchName",
    "SwitchStuck",
]

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Literal, Protocol

SwitchName = Literal["lim_pos", "lim_neg", "ref", "tp"]
SWITCH_NAMES: tuple[SwitchName, ...] = ("lim_pos", "lim_neg", "ref", "tp")


class Fault:
    """Base of every fault. Subclasses are frozen dataclasses; equal faults are the same fault."""

    slot: str = ""
    """Faults of one slot replace each other on an axis (a switch's level, the encoder, ...)."""

    def key(self) -> str:
        """The slot this fault occupies on its axis."""
        return self.slot


@dataclass(frozen=True)
class SwitchStuck(Fault):
    """A digital input reads ``level`` whatever the cam does (a welded contact, a cut wire)."""

    switch: SwitchName
    level: bool | int

    def key(self) -> str:
        return f"switch:{self.switch}"


@dataclass(frozen=True)
class SwitchBounce(Fault):
    """A contact chatters for ``duration`` [s] after each real edge: the input toggles every
    ``period`` [s] before it settles at the true level."""

    switch: SwitchName
    duration: float = 0.005
    period: float = 0.001

    def key(self) -> str:
        return f"switch:{self.switch}"


@dataclass(frozen=True)
class EncoderFreeze(Fault):
    """The counter stops counting (a slipping coupling, a stalled counter chip)."""

    slot = "encoder"


@dataclass(frozen=True)
class EncoderNoise(Fault):
    """Electrical noise: each sample reads up to ±``counts`` off the true count (seeded)."""

    counts: int = 2
    seed: int = 0
    slot = "encoder"


@dataclass(frozen=True)
class EncoderLostCounts(Fault):
    """Pulses lost on the line: ``fraction`` of the counts moved is missed (position drifts)."""

    fraction: float = 0.01
    slot = "encoder"


@dataclass(frozen=True)
class EncoderWireBreak(Fault):
    """A broken encoder cable: the counter stops, the index stays low and the module's line
    monitor reports it (encoder status bit 5); the module raises ERRPOS 2001 at once."""

    slot = "encoder"


@dataclass(frozen=True)
class AbsoluteFrameError(Fault):
    """The absolute sensor's serial frames (SSI) arrive corrupted (interference on the clock or
    data pair): the parity / CRC check fails, the module discards the word and reports it;
    MC_StepAbsolute then refuses (``EAbsFrame`` 22) instead of using a wrong position."""

    slot = "absolute"


@dataclass(frozen=True)
class DriveNotReady(Fault):
    """The amplifier does not switch on (no ready signal): no force, its brake stays engaged."""

    slot = "drive"


@dataclass(frozen=True)
class AmplifierFault(Fault):
    """The amplifier trips (overcurrent, overtemperature): force off, brake engaged."""

    slot = "drive"


@dataclass(frozen=True)
class BrakeFailure(Fault):
    """The holding brake does not hold (worn lining): no brake force when engaged."""

    slot = "brake"


@dataclass(frozen=True)
class BrakeSlow(Fault):
    """The holding brake engages ``delay`` [s] after the drive is disabled."""

    delay: float = 0.2
    slot = "brake"


@dataclass(frozen=True)
class AnalogOffset(Fault):
    """A DC offset on the ±10 V command line [V]."""

    volts: float = 0.1
    slot = "analog_out"


@dataclass(frozen=True)
class AnalogNoise(Fault):
    """Noise on the ±10 V command line: each servo cycle up to ±``volts`` [V] (seeded)."""

    volts: float = 0.05
    seed: int = 0
    slot = "analog_out"


@dataclass(frozen=True)
class AnalogInputFault(Fault):
    """Offset and noise on analog input ``channel`` [V] (a drifting or noisy transducer)."""

    channel: int = 0
    offset: float = 0.0
    noise: float = 0.0
    seed: int = 0

    def key(self) -> str:
        return f"analog_in:{self.channel}"


@dataclass(frozen=True, slots=True)
class FaultEvent:
    """One change of the injected faults, as the trace records it.

    Attributes:
        t: simulated time [s].
        axis: the axis' name.
        fault: the fault (``repr`` is readable).
        active: True when set, False when cleared.
    """

    t: float
    axis: str
    fault: Fault
    active: bool


@dataclass(frozen=True, slots=True)
class FaultLogState:
    """A :class:`FaultLog` at one instant: the changes so far and those still scheduled.

    Attributes:
        events: every change up to then, oldest first.
        pending: the scheduled changes not yet due: (time [s], axis, fault, set or clear).
    """

    events: tuple[FaultEvent, ...] = ()
    pending: tuple[tuple[float, str, Fault, bool], ...] = ()


class Injectable(Protocol):
    """What can carry faults: an :class:`~mcl.channel.AxisChannel` (and its plant)."""

    def set_fault(self, fault: Fault) -> None:
        """Apply ``fault`` (it replaces a fault of the same slot)."""
        ...

    def clear_fault(self, fault: Fault) -> None:
        """Remove ``fault`` if it is set."""
        ...


class FaultLog:
    """Sets, schedules and clears faults on named channels; records every change.

    Args:
        channels: axis name → the channel that applies its faults.
        clock: the simulated time [s] now.
    """

    def __init__(self, channels: Mapping[str, Injectable], clock: Callable[[], float]) -> None:
        self.channels = dict(channels)
        self._clock = clock
        self.events: list[FaultEvent] = []
        """Every change so far, oldest first."""
        self._pending: list[tuple[float, str, Fault, bool]] = []

    def _channel(self, axis: str) -> Injectable:
        try:
            return self.channels[axis]
        except KeyError:
            raise KeyError(
                f"no axis {axis!r} to inject into; axes: {sorted(self.channels)}"
            ) from None

    def set(self, axis: str, fault: Fault) -> None:
        """Inject ``fault`` on ``axis`` now (it replaces a fault of the same slot)."""
        if not isinstance(fault, Fault):
            raise TypeError(f"expected an mcl.faults fault, got {type(fault).__name__}")
        self._channel(axis).set_fault(fault)
        self.events.append(FaultEvent(self._clock(), axis, fault, True))

    def clear(self, axis: str, fault: Fault) -> None:
        """Remove ``fault`` from ``axis`` now (nothing happens if it is not set)."""
        self._channel(axis).clear_fault(fault)
        self.events.append(FaultEvent(self._clock(), axis, fault, False))

    def schedule(self, axis: str, fault: Fault, at: float, until: float | None = None) -> None:
        """Inject ``fault`` at simulated time ``at`` [s] and clear it at ``until`` (None: never)."""
        self._channel(axis)
        if until is not None and not until > at:
            raise ValueError(f"until ({until}) must be after at ({at})")
        self._pending.append((at, axis, fault, True))
        if until is not None:
            self._pending.append((until, axis, fault, False))
        self._pending.sort(key=lambda item: item[0])

    def snapshot(self) -> FaultLogState:
        """The changes so far and the scheduled ones (the channels keep the faults set)."""
        return FaultLogState(tuple(self.events), tuple(self._pending))

    def restore(self, state: FaultLogState) -> None:
        """Return to a state taken with :meth:`snapshot` (the channels' faults return with
        the channels' own state)."""
        self.events[:] = state.events
        self._pending = list(state.pending)

    @property
    def pending(self) -> bool:
        """Scheduled changes are waiting."""
        return bool(self._pending)

    def due(self, t: float) -> None:
        """Apply the scheduled changes whose time has come (called every servo cycle)."""
        while self._pending and self._pending[0][0] <= t + 1e-12:
            _, axis, fault, active = self._pending.pop(0)
            if active:
                self.set(axis, fault)
            else:
                self.clear(axis, fault)

    def active(self, axis: str) -> list[Fault]:
        """The faults now set on ``axis``."""
        on: dict[str, Fault] = {}
        for event in self.events:
            if event.axis != axis:
                continue
            if event.active:
                on[event.fault.key()] = event.fault
            elif on.get(event.fault.key()) == event.fault:
                del on[event.fault.key()]
        return list(on.values())
