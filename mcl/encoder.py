"""Incremental encoder with hardware index latch.

Shared by every plant (simulated axes, MuJoCo): it turns a physical position into the counter,
index level and latched index count that :class:`mcl.io.AxisIO` exposes.
"""

from __future__ import annotations

__all__ = ["AbsoluteEncoder", "EncoderState", "IncrementalEncoder", "Normal", "gray_decode"]

import math
from dataclasses import dataclass
from typing import Protocol


class Normal(Protocol):
    """A source of standard normal numbers."""

    def next(self) -> float:
        """The next number (mean 0, standard deviation 1)."""
        ...


@dataclass(frozen=True, slots=True)
class EncoderState:
    """What an :class:`IncrementalEncoder` counted so far (its configuration is not part of it).

    Attributes:
        origin: the count of the power-up position from the physical zero [counts].
        absolute: the count of the last position from the physical zero [counts].
        counts: the counter, 0 at the power-up position [counts].
        index: the index pulse level.
        index_count: the counter value the last index edge latched [counts].
        index_seq: how many index edges were latched.
    """

    origin: int
    absolute: int
    counts: int
    index: bool
    index_count: int
    index_seq: int


class IncrementalEncoder:
    """Quantizes a position [m] into counts and latches the index pulse NI like the module's FPGA.

    The index pulse is high while the absolute count modulo ``counts_per_rev`` is below
    ``index_width``: once per motor revolution. Its rising edge is latched between two samples
    (no sampling jitter): moving forward at the first count of the window, moving backward at the
    last, give or take the edge's own jitter (``index_jitter``, rounded to whole counts).
    The counter starts at 0 at ``origin`` (the position at power-up of the module), so the axis
    coordinate means nothing until the axis is homed.

    Args:
        resolution: travel per count [m].
        counts_per_rev: counts per motor revolution (lead / resolution).
        origin: physical position [m] where the counter reads 0.
        index_width: width of the index pulse [counts].
        index_jitter: standard deviation of the latched count [counts] (0: exact).
        rng: the random source of the jitter (needed when ``index_jitter`` > 0).
    """

    __slots__ = (
        "_abs",
        "_inv_res",
        "_jitter",
        "_n",
        "_origin",
        "_rng",
        "_width",
        "counts",
        "index",
        "index_count",
        "index_seq",
    )

    def __init__(
        self,
        resolution: float,
        counts_per_rev: int,
        origin: float = 0.0,
        index_width: int = 1,
        index_jitter: float = 0.0,
        rng: Normal | None = None,
    ) -> None:
        if not resolution > 0.0:
            raise ValueError(f"encoder resolution must be > 0 m/count, got {resolution}")
        if counts_per_rev < 1 or not 1 <= index_width < counts_per_rev:
            raise ValueError(
                f"need counts_per_rev >= 1 and 1 <= index_width < counts_per_rev, got "
                f"{counts_per_rev} and {index_width}"
            )
        self._inv_res = 1.0 / resolution
        self._n = int(counts_per_rev)
        self._width = int(index_width)
        if index_jitter and rng is None:
            raise ValueError("an encoder with index jitter needs a random source (rng)")
        self._jitter = float(index_jitter)
        self._rng = rng
        self._origin = self._absolute(origin)
        self._abs = self._origin
        self.counts = 0
        self.index = self._abs % self._n < self._width
        self.index_count = 0
        self.index_seq = 0

    def _absolute(self, position: float) -> int:
        # the small bias keeps exact multiples of the resolution on their own count
        return math.floor(position * self._inv_res + 1e-9)

    def count_at(self, position: float) -> int:
        """The counter value at ``position`` [m] (for a latch between two samples) [counts]."""
        return self._absolute(position) - self._origin

    def update(self, position: float) -> None:
        """Advance the counter to ``position`` [m], latching an index edge passed on the way."""
        c = self._absolute(position)
        prev = self._abs
        if c == prev:
            return
        n, width = self._n, self._width
        if c > prev:
            edge = (c // n) * n  # first count of the last window entered from below
            if edge > prev:
                self._latch(edge)
        else:
            edge = (
                ((prev - width) // n) * n + width - 1
            )  # last count of a window entered from above
            if c <= edge < prev:
                self._latch(edge)
        self._abs = c
        self.counts = c - self._origin
        self.index = c % n < width

    def snapshot(self) -> EncoderState:
        """The counter and index latch now (the random source is the owner's to save)."""
        return EncoderState(
            self._origin, self._abs, self.counts, self.index, self.index_count, self.index_seq
        )

    def restore(self, state: EncoderState) -> None:
        """Return to a state taken with :meth:`snapshot`."""
        self._origin = state.origin
        self._abs = state.absolute
        self.counts = state.counts
        self.index = state.index
        self.index_count = state.index_count
        self.index_seq = state.index_seq

    def _latch(self, absolute_count: int) -> None:
        if self._jitter and self._rng is not None:
            absolute_count += round(self._jitter * self._rng.next())
        self.index_count = absolute_count - self._origin
        self.index_seq += 1


def gray_decode(word: int) -> int:
    """The binary value of a Gray-coded word."""
    value = word
    shift = word >> 1
    while shift:
        value ^= shift
        shift >>= 1
    return value


@dataclass(frozen=True, slots=True)
class AbsoluteEncoder:
    """An absolute measuring system: its word is a function of the position, known at power-on.

    One model for both kinds: a multi-turn absolute rotary encoder on the motor (word = turns ·
    2**single-turn bits + angle; :meth:`rotary`) and an SSI linear transducer (:meth:`ssi`). The
    reading counts ``resolution`` steps from ``offset`` and wraps after ``2**bits`` of them (a
    multi-turn encoder past its 4096 turns, an SSI transducer past its word length).

    Attributes:
        resolution: travel per count at the axis [m or rad].
        bits: word length: the reading wraps modulo ``2**bits``.
        offset: physical position where the reading is 0 [m or rad].
        gray: the word is transmitted Gray-coded (an SSI option); the channel decodes it.
    """

    resolution: float
    bits: int = 29
    offset: float = 0.0
    gray: bool = False

    def __post_init__(self) -> None:
        if not (math.isfinite(self.resolution) and self.resolution > 0.0):
            raise ValueError(f"AbsoluteEncoder.resolution must be > 0, got {self.resolution!r}")
        if not 1 <= self.bits <= 48:
            raise ValueError(f"AbsoluteEncoder.bits must be 1 .. 48, got {self.bits!r}")
        if not math.isfinite(self.offset):
            raise ValueError(f"AbsoluteEncoder.offset must be finite, got {self.offset!r}")

    @staticmethod
    def rotary(
        travel_per_rev: float, single_turn: int = 17, multi_turn: int = 12, offset: float = 0.0
    ) -> AbsoluteEncoder:
        """A multi-turn absolute encoder on the motor: ``single_turn`` bits per revolution,
        ``multi_turn`` bits of revolutions; ``travel_per_rev`` is the axis travel per motor
        revolution [m or rad] (the screw lead over the gear ratio)."""
        resolution = travel_per_rev / float(1 << single_turn)
        return AbsoluteEncoder(resolution, single_turn + multi_turn, offset)

    @staticmethod
    def ssi(
        resolution: float = 1.0e-6, bits: int = 24, offset: float = 0.0, gray: bool = False
    ) -> AbsoluteEncoder:
        """An SSI linear transducer (magnetostrictive, e.g. 1 µm or 5 µm, 24 or 25 bit)."""
        return AbsoluteEncoder(resolution, bits, offset, gray)

    @property
    def span(self) -> float:
        """Travel before the reading wraps [m or rad]."""
        return self.resolution * float(1 << self.bits)

    def word(self, position: float) -> int:
        """The word the sensor sends at ``position`` [m or rad] (Gray-coded if :attr:`gray`)."""
        count = math.floor((position - self.offset) / self.resolution + 1e-9) % (1 << self.bits)
        return count ^ (count >> 1) if self.gray else count

    def count(self, word: int) -> int:
        """The count a received word stands for (0 .. 2**bits − 1)."""
        return gray_decode(word) if self.gray else word

    def position(self, word: int) -> float:
        """The position a received word stands for [m or rad]: offset + count · resolution."""
        return self.offset + self.count(word) * self.resolution
