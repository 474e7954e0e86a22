"""The handshake of a block of the bridge's signal table that commands through a control word
(an axis, a group): the control word of a scan, the commands its rising bits start and their
results held until the master acknowledges them (docs/bridge.md, The handshake)."""

from __future__ import annotations

import logging
import math
from typing import Any

from mcl.errors import ErrorID
from scenes.bridge.table import CONTROL_BITS, SignalTable

log = logging.getLogger("scenes.bridge.program")

Command = Any
"""A command block (MC_MoveAbsolute, HomeAxis, …): Done, Busy, Error, ErrorID; maybe Active,
CommandAborted."""


RESULTS = ("done", "error", "command_aborted")
"""The status bits of a command's result, held until the master acknowledges it."""


def _int(value: float) -> int:
    """An INT input from a register value (0 for a value that is not finite)."""
    return round(value) if math.isfinite(value) and abs(value) < 2**31 else 0


class CommandWord:
    """The handshake of a block of the table that commands through a control word (an axis, a
    group): the control word of a scan (with a method call's Execute), the commands its rising
    bits start (the last is the current one, each counts), and the current command's result
    held until the master acknowledges it (module docstring).

    Subclasses name their control bits (``BITS``), make their command blocks and say which
    block a bit starts (:meth:`_block_for`).

    Args:
        name: the block's name in the table (an axis, ``group``).
        table: the signal table.
    """

    BITS: tuple[str, ...] = CONTROL_BITS
    """The control bits, bit 0 first."""

    def __init__(self, name: str, table: SignalTable) -> None:
        self.name = name
        self.table = table
        self.current: Command | None = None
        """The command last started by a rising edge (its outputs are the status)."""
        self.command = 0
        """The current command's control bit + 1 (0: none yet)."""
        self.count = 0
        """Commands started (``command_count``, modulo 65536)."""
        self._last_word = 0
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

    def __call__(self) -> None:
        """One PLC scan: control word → blocks."""
        raise NotImplementedError

    def publish(self) -> None:
        """Write the block's status into the table."""
        raise NotImplementedError

    def _block_for(self, name: str) -> Command | None:
        """The block a rising bit ``name`` starts (None: the block refuses it)."""
        raise NotImplementedError

    def _refusal(self, name: str) -> str:
        """What the block lacks when it refuses bit ``name`` (for the log)."""
        return f"command {name}"

    def _words(self) -> tuple[int, int]:
        """This scan's control word of the client and the whole control word: the client's
        with the Execute of the command last requested (a method call), held until the axis'
        next command. A request whose bit was high in the last scan, or a client's command
        on the bit a request holds, first gets one scan low (a fresh rising edge)."""
        client = self.table.take_control(self.name) | self._pending
        self._pending = 0
        bit, serial = self.table.requested(self.name)
        if serial != self._serial:
            self._serial = serial
            self._requested = -1
            if self._last_word >> bit & 1:
                self._deferred = bit
            else:
                self._requested, self._deferred = bit, -1
        elif self._deferred >= 0:
            self._requested, self._deferred = self._deferred, -1
        elif self._requested >= 0 and client & ~self._last_client & ~1:
            held = 1 << self._requested  # the control word starts a command: the call's ends
            if client & ~self._last_client & held:
                client &= ~held
                self._pending = held
            self._requested = -1
        requested = 1 << self._requested if self._requested >= 0 else 0
        return client, client | requested

    def _started(self, rising: int) -> None:
        """The commands whose bits rose: the last is the current one (each counts); a bit the
        block has no command for is refused with EParam."""
        for i, name in enumerate(self.BITS):
            if rising >> i & 1 and name != "enable":
                self.command = i + 1
                self.count = (self.count + 1) & 0xFFFF
                self._release()
                self.current = self._block_for(name)
                if self.current is None:
                    self._held["error"], self._held_error = True, ErrorID.EParam
                    log.warning(
                        "%s: %s refused: it has no %s", self.name, name, self._refusal(name)
                    )

    def _hold(self, client: int) -> None:
        """Hold the current command's result; release it when the master's bit falls after
        the result was published while the bit was set (the acknowledgement)."""
        bit = 1 << (self.command - 1) if self.command else 0
        if self._armed and self._last_client & bit and not client & bit:
            self._release()
        self._last_client = client
        current = self.current
        for name, output in zip(RESULTS, ("Done", "Error", "CommandAborted"), strict=True):
            if getattr(current, output, False):
                self._held[name] = True
        if getattr(current, "Error", False):
            self._held_error = int(getattr(current, "ErrorID", 0))

    def _release(self) -> None:
        """Forget the held result (acknowledged, or another command started)."""
        self._held = dict.fromkeys(RESULTS, False)
        self._held_error = 0
        self._armed = False

    def observe(self) -> None:
        """A scan while the PLC is not in control: the blocks are not called; the control
        word's edges and requests are taken so that none fires later."""
        client, self._last_word = self._words()
        self._last_client = client

    def _arm(self) -> None:
        """A held result is being published: seen while the bit is set, the bit's fall acks
        it."""
        if any(self._held.values()) and self.command:
            self._armed |= bool(self._last_client >> (self.command - 1) & 1)


def _showing(block: Command) -> bool:
    """Whether a block is busy or shows an output (so it must see the next scan)."""
    return bool(block.Busy or block.Done or block.Error or getattr(block, "CommandAborted", False))
