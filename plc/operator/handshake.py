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

_OUTPUTS = {"done": "Done", "error": "Error", "command_aborted": "CommandAborted"}
"""The status bits of a command's result, each with the block output it holds."""

RESULTS = tuple(_OUTPUTS)
"""The status bits of a command's result, held until the master acknowledges it."""


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
        bits: Its control bits, bit 0 (the ``enable`` level) first, one of them ``stop``.
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
        self._stop = 1 << self.bits.index("stop")
        """The stop bit."""
        self._last_client = 0
        """The client's control word of the last scan."""
        self._serial = -1
        """The serial number of the last method call taken (-1: none yet)."""
        self._requested = 0
        """The bit the method call holds (0: none)."""
        self._deferred = 0
        """The bit of a method call that first gets one scan low (0: none)."""
        self._pending = 0
        """Rising bits of the client's word that wait one scan (after a call it ends)."""
        self._held: set[str]
        """The current command's result bits held until acknowledged (:data:`RESULTS`)."""
        self._held_error: int
        """The ErrorID held with the error bit (0: none held)."""
        self._armed: bool
        """The held result was last published while the master's command bit was set: the
        bit's fall acknowledges it."""
        self._release()  # nothing held yet

    def _words(self) -> tuple[int, int]:
        """This scan's control word of the client and the whole control word: the client's
        with the bit of the command last requested (a method call), held until the block's next
        command (see the module docstring for the scans it waits)."""
        client = self.registers.take_control() | self._pending
        self._pending = 0
        bit, serial = self.registers.requested()
        if serial != self._serial:
            self._serial = serial
            self._requested = 0
            call = 1 << bit
            if self.word & (call | self._stop):  # its bit, or a stop, falls first
                self._deferred = call
            else:
                self._requested, self._deferred = call, 0
        elif self._deferred:
            self._requested, self._deferred = self._deferred, 0
        elif rising := client & ~self._last_client & ~1:
            # the control word starts a command: a call held ends; the call's bit rising in
            # the word, or after a held stop every rising bit, waits one scan
            waiting = rising if self._requested == self._stop else rising & self._requested
            client &= ~waiting
            self._pending, self._requested = waiting, 0
        return client, client | self._requested

    def take(self) -> int:
        """Start a scan: this scan's control word (:attr:`word`, :attr:`rising`); a held result
        is released if the master acknowledged it (its command's bit fell)."""
        client, word = self._words()
        if self._armed and self._last_client & ~client & self._bit():
            self._release()
        self._last_client = client
        self.rising = word & ~self.word
        self.word = word
        return word

    def observe(self) -> None:
        """A scan while the master is not in control: the block's commands are not given; the
        control word's edges and requests are taken so that none fires later (nor does a bit's
        fall acknowledge a result)."""
        self._last_client, self.word = self._words()
        self.rising = 0

    def settle(self, block_of: Callable[[str], Any]) -> list[str]:
        """End a scan whose orders were given: the commands whose bits rose start (the last is
        the current one; ``block_of`` gives a command's block, None: the block refuses it, and
        the status shows Error with EParam); the current command's result is held. The
        commands refused."""
        refused = []
        for i, name in enumerate(self.bits):
            if i and self.rising >> i & 1:
                self.command = i + 1
                self.count = (self.count + 1) & 0xFFFF
                self._release()
                self.current = block_of(name)
                if self.current is None:
                    self._held.add("error")
                    self._held_error = mcl.ErrorID.EParam
                    refused.append(name)
        self._hold()
        return refused

    def _bit(self) -> int:
        """The current command's control bit (a command started)."""
        return 1 << self.command - 1

    def _hold(self) -> None:
        """Hold the current command's result: its outputs of :data:`RESULTS` that are set."""
        current = self.current
        if current is None:
            return
        for name, output in _OUTPUTS.items():
            if getattr(current, output, False):
                self._held.add(name)
        if current.Error:
            self._held_error = int(current.ErrorID)

    def _release(self) -> None:
        """Forget the held result (acknowledged, or another command started)."""
        self._held = set()
        self._held_error = 0
        self._armed = False

    def result(self) -> tuple[dict[str, bool], int]:
        """The held result to publish: its bits (:data:`RESULTS`) and the ErrorID (0: no
        error). Published while the master's command bit is set, its fall acknowledges it."""
        if self._held:
            self._armed = bool(self._last_client & self._bit())
        return {name: name in self._held for name in RESULTS}, self._held_error
