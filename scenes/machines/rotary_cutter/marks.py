"""The print marks on the rotary cutter's web and the mark sensor that sees them
(:class:`PrintMarks`): where each mark is printed (the truth a registered cut is judged
against) and where the sensor switches on it (print error and sensor jitter)."""

from __future__ import annotations

__all__ = [
    "COUNT",
    "MARKS",
    "MARK_FIRST",
    "MARK_PITCH",
    "PRINT_ERROR",
    "PRINT_MARKS",
    "SENSOR_JITTER",
    "PrintMarks",
]

import random
from dataclasses import dataclass

import mcl

MARK_PITCH = 0.5
"""Print-mark pitch on the web [m] (one mark per 500 mm piece)."""
MARK_FIRST = 1.0
"""Web travel M [m] at which the first mark, printed without error, would pass the sensor."""
PRINT_ERROR = 2.0e-4
"""Print error of a mark: uniform within ± this [m] (seeded)."""
SENSOR_JITTER = 2.5e-5
"""Mark sensor jitter at 1 m/s: its switching point scatters uniformly within ± this [m]
(±25 µs of a contrast scanner's response)."""
COUNT = 256
"""Marks with their own errors; then they repeat."""


@dataclass(frozen=True)
class PrintMarks:
    """Print marks at the pitch :data:`MARK_PITCH`, each printed ``printed[k]`` off its place
    and seen by the sensor ``jitter[k]`` off where it is printed [m] (cycled).

    Args:
        print_error, jitter: the bounds of the uniform print error and sensor jitter [m] (0 and
            0: ideal marks and an ideal sensor).
        seed: the seed of both.
    """

    print_error: float = PRINT_ERROR
    jitter: float = SENSOR_JITTER
    seed: int = 25

    def __post_init__(self) -> None:
        if not (0.0 <= self.print_error < 0.01 and 0.0 <= self.jitter < 0.01):
            raise ValueError(
                f"print_error and jitter must be within 0 … 0.01 m, got {self.print_error}, "
                f"{self.jitter}"
            )

    def _errors(self, bound: float, salt: int) -> tuple[float, ...]:
        rng = random.Random(self.seed * 7919 + salt)
        return tuple(round(rng.uniform(-bound, bound), 7) for _ in range(COUNT))

    @property
    def printed(self) -> tuple[float, ...]:
        """Each mark's print error [m]."""
        return self._errors(self.print_error, 1)

    @property
    def sensed(self) -> mcl.Marks:
        """The marks as the sensor switches on them (on the web coordinate M), 4 mm long."""
        errors = tuple(
            p + j for p, j in zip(self.printed, self._errors(self.jitter, 2), strict=True)
        )
        return mcl.Marks(
            first=MARK_FIRST, pitch=MARK_PITCH, width=0.004, errors=errors if any(errors) else ()
        )

    def passing(self, k: int) -> float:
        """Web travel M [m] at which mark ``k`` as printed passes the sensor."""
        return MARK_FIRST + k * MARK_PITCH + self.printed[k % COUNT]


PRINT_MARKS = PrintMarks()
"""The model's print marks and mark sensor (the defaults of :class:`PrintMarks`)."""
MARKS = PRINT_MARKS.sensed
"""What the sensor wired to the wheel's touch probe sees."""
