"""The handshake of a block of registers that commands through a control word — an axis
(:mod:`plc.operator.bus`), an axes group (:mod:`plc.operator.group_bus`): the control word of a
scan, the commands its rising bits start, and their results held until the master acknowledges
them.

Bit 0 (``enable``) is a level and starts no command; every other bit that rises starts its
command, the last one is the current one (its outputs are the status) and each counts in
``command_count``. A method call (the registers' :meth:`Registers.requested`) sets its command's
bit at the next scan and holds it until the block's next command; a request whose bit was high
in the last scan, or a master's command on the bit a request holds, first gets one scan low (a
fresh rising edge). A held stop keeps its axis or group stopping, so when a call of ``stop`` is
held the next command — a call or the control word's — waits one scan: the stop ends (Done AND
NOT Execute) and it stands still when the command starts.

A result of the current command (Done, Error with its ErrorID, CommandAborted) is held until the
master acknowledges it — it clears the command's bit after the result was published while the
bit was set — or starts another command: a master that polls slowly, or clears the bit early,
still sees it.
"""

from __future__ import annotations

__all__ = ["RESULTS", "Handshake", "Registers"]

from collections.abc import Callable, Iterable, Sequence
from typing import Any, Protocol

import mcl

RESULTS = ("done", "error", "command_aborted")
"""The status bits of a command's result, held until the master acknowledges it."""

_OUTPUTS = ("Done", "Error", "CommandAborted")
"""The block outputs of :data:`RESULTS`."""


class Registers(Protocol):
    """A block's registers as a front end reads and writes them, by their names without the
    block's (``control``, ``position``, ``status``)."""

    @property
    def in_control(self) -> bool:
        """Whether the master may command (else the block is left alone)."""
        ...

    def has(self, name: str) -> bool:
        """Whether the block has register ``name``."""
        ...

    def get(self, name: str) -> float:
        """The value of register ``name`` (0.0: the block has none)."""
        ...

    def take_control(self) -> int:
        """The control word for this scan: the bits set now and those that rose since the last
        scan (a pulse shorter than a scan still gives its rising edge)."""
        ...

    def requested(self) -> tuple[int, int]:
        """The last method call: its control bit and a serial number (-1: none yet)."""
        ...

    def update(self, values: Iterable[tuple[str, float]]) -> None:
        """Write status registers."""
        ...


class Handshake:
    """The control word of one block of registers and the results of its commands (module
    docstring). A front end calls :meth:`take` at the start of a scan, gives its orders, then
    :meth:`settle`; :meth:`observe` while the master is not in control; :meth:`result` when it
    publishes.

    Args:
        registers: The block's registers.
        bits: Its control bits, bit 0 (the ``enable`` level) first.
    """

    def __init__(self, registers: Registers, bits: Sequence[str]) -> None:
        self.registers = registers
        self.bits = tuple(bits)
        self.current: Any = None
        """The block of the command last started by a rising edge (its outputs are the status;
        None: none, or refused)."""
        self.command = 0
        """The current command's control bit + 1 (0: none yet)."""
        self.count = 0
        """Commands started (``command_count``, modulo 65536)."""
        self.word = 0
        """This scan's control word (the client's with a method call's bit)."""
        self.rising = 0
        """Its bits that rose in this scan."""
        self._stop = self.bits.index("stop") if "stop" in self.bits else -1
        self._client = 0
        self._last_client = 0
        self._serial = -1
        self._requested = -1
        self._deferred = -1
        self._pending = 0
        self._held: dict[str, bool] = dict.fromkeys(RESULTS, False)
        """The current command's result bits held until acknowledged."""
        self._held_error = 0
        """The ErrorID held with the error bit."""
        self._armed = False
        """The held result was published while the master's command bit was set: the bit's
        fall acknowledges it."""

    def _words(self) -> tuple[int, int]:
        """This scan's control word of the client and the whole control word: the client's
        with the bit of the command last requested (a method call), held until the block's next
        command (see the module docstring for the scans it waits)."""
        client = self.registers.take_control() | self._pending
        self._pending = 0
        bit, serial = self.registers.requested()
        stop = 1 << self._stop if self._stop >= 0 else 0
        if serial != self._serial:
            self._serial = serial
            self._requested = -1
            if self.word & (1 << bit | stop):  # its bit, or a stop, falls first
                self._deferred = bit
            else:
                self._requested, self._deferred = bit, -1
        elif self._deferred >= 0:
            self._requested, self._deferred = self._deferred, -1
        elif self._requested >= 0 and client & ~self._last_client & ~1:
            # the control word starts a command: the call's ends; the call's bit rising in the
            # word, or after a held stop every rising bit, waits one scan
            rising = client & ~self._last_client & ~1
            waiting = rising if self._requested == self._stop else rising & 1 << self._requested
            client &= ~waiting
            self._pending = waiting
            self._requested = -1
        requested = 1 << self._requested if self._requested >= 0 else 0
        return client, client | requested

    def take(self) -> int:
        """Start a scan: this scan's control word (:attr:`word`, :attr:`rising`)."""
        self._client, word = self._words()
        self.rising = word & ~self.word
        self.word = word
        return word

    def observe(self) -> None:
        """A scan while the master is not in control: the block's commands are not given; the
        control word's edges and requests are taken so that none fires later."""
        self._last_client, self.word = self._words()
        self.rising = 0

    def settle(self, block_of: Callable[[str], Any]) -> list[str]:
        """End a scan whose orders were given: the commands whose bits rose start (the last is
        the current one; ``block_of`` gives a command's block, None: the block refuses it, and
        the status shows Error with EParam); the current command's result is held. The
        commands refused."""
        refused = []
        rising = self.rising
        for i, name in enumerate(self.bits):
            if i and rising >> i & 1:
                self.command = i + 1
                self.count = (self.count + 1) & 0xFFFF
                self._release()
                self.current = block_of(name)
                if self.current is None:
                    self._held["error"], self._held_error = True, mcl.ErrorID.EParam
                    refused.append(name)
        self._hold()
        return refused

    def _hold(self) -> None:
        """Hold the current command's result; release it when the master's bit falls after
        the result was published while the bit was set (the acknowledgement)."""
        client = self._client
        bit = 1 << (self.command - 1) if self.command else 0
        if self._armed and self._last_client & bit and not client & bit:
            self._release()
        self._last_client = client
        current = self.current
        for name, output in zip(RESULTS, _OUTPUTS, strict=True):
            if getattr(current, output, False):
                self._held[name] = True
        if getattr(current, "Error", False):
            self._held_error = int(getattr(current, "ErrorID", 0))

    def _release(self) -> None:
        """Forget the held result (acknowledged, or another command started)."""
        self._held = dict.fromkeys(RESULTS, False)
        self._held_error = 0
        self._armed = False

    def result(self) -> tuple[dict[str, bool], int]:
        """The held result to publish: its bits (:data:`RESULTS`) and the ErrorID (0: no
        error). Published while the master's command bit is set, its fall acknowledges it."""
        held = dict(self._held)
        if any(held.values()) and self.command:
            self._armed |= bool(self._last_client >> (self.command - 1) & 1)
        return held, self._held_error if held["error"] else 0
