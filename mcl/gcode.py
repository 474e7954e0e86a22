"""G-code: a CAD/CAM contour as a path table (:func:`read_gcode`, MC_PathSelect).

The subset a contour needs, one block per line (ISO 6983 / RS-274, units mm):

- ``G00`` rapid line, ``G01`` line at the feed ``F`` [mm/min], ``G02`` / ``G03`` arc clockwise /
  counter-clockwise (seen from the positive normal of the plane) with its centre ``I J K``
  (relative to the arc's start, the offsets of the plane's axes) or its radius ``R`` (> 0: the
  arc of at most 180°, < 0: the longer one), ``P`` the number of turns (P2: one more full turn; a
  full circle has its end point on its start); a third axis word makes a helix;
- ``G17`` / ``G18`` / ``G19`` the XY, ZX, YZ plane; ``G90`` / ``G91`` absolute / incremental
  coordinates; ``G21`` mm (``G20`` inches is refused); ``G64`` blends the corners (default),
  ``G61`` stops exactly at each; ``G40``, ``G49``, ``G80`` and ``G94`` are taken as they change
  nothing here;
- ``X Y Z`` are the group's members 1, 2, 3; a missing one keeps its coordinate; the G-codes and
  ``F`` are modal (a line of coordinates repeats the last motion);
- comments ``( … )`` and ``; …``, ``%`` lines, and the words ``N`` (line number), ``O`` (program
  number), ``M``, ``S``, ``T`` (spindle, coolant, tool: the testbench has none) are skipped.

Anything else is refused with one :class:`GCodeError` naming ``file:line``, what is wrong and
what would be right. An arc whose start the program has already fixed (after absolute moves of
its plane's axes) is checked there too (a radius shorter than half the chord, an end point off
the circle).
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any, ClassVar, Final

from mcl.enums import MC_CIRC_MODE, MC_CIRC_PATHCHOICE, MC_BufferMode
from mcl.errors import ErrorID
from mcl.fb import ExecuteFB, non_negative, number
from mcl.geometry import PLANES, GeometryError, arc
from mcl.path_table import MC_PATH_DATA_REF, MC_PATH_SEGMENT

_WORD: Final = re.compile(r"\s*([A-Za-z])\s*([+-]?(?:\d+\.?\d*|\.\d+))\s*")
_COMMENT: Final = re.compile(r"\([^()]*\)")
_TAKEN: Final = "G, X, Y, Z, I, J, K, R, P, F (N, O, M, S, T are skipped)"
_G_TAKEN: Final = "G00, G01, G02, G03, G17, G18, G19, G21, G90, G91, G61, G64"
_NO_OPS: Final = frozenset({40, 49, 80, 94})
"""G-codes that change nothing here (cutter and length compensation off, canned cycles off,
feed per minute)."""
_SKIPPED: Final = frozenset("NOMST")
_AXES: Final = "XYZ"
_OFFSETS: Final = "IJK"


class GCodeError(ValueError):
    """A G-code line that cannot be read: the message names ``file:line``."""


class _Reader:
    """The modal state while a program is read, and the segments so far."""

    def __init__(self, name: str, rapid: float) -> None:
        self.name = name
        self.rapid = rapid
        self.motion = -1
        self.plane = 17
        self.absolute = True
        self.feed = 0.0
        self.exact = False
        self.position: list[float | None] = [None, None, None]
        self.segments: list[MC_PATH_SEGMENT] = []
        self.line = 0

    def fail(self, what: str) -> GCodeError:
        return GCodeError(f"{self.name}:{self.line}: {what}")

    def words(self, text: str) -> list[tuple[str, float]]:
        """The words of one line, comments removed."""
        text = _COMMENT.sub(" ", text.split(";", 1)[0])
        if "(" in text or ")" in text:
            raise self.fail("a comment ( … ) is not closed on its line")
        if text.strip() == "%":
            return []
        found: list[tuple[str, float]] = []
        pos = 0
        while pos < len(text):
            match = _WORD.match(text, pos)
            if match is None:
                rest = text[pos:].strip()
                if not rest:
                    break
                raise self.fail(
                    f"cannot read {rest[:20]!r}: a word is a letter and a number (X10.5)"
                )
            found.append((match.group(1).upper(), float(match.group(2))))
            pos = match.end()
        return found

    def read(self, number_: int, text: str) -> None:
        """Take one line."""
        self.line = number_
        values: dict[str, float] = {}
        for letter, value in self.words(text):
            if letter == "G":
                self.g_code(value)
            elif letter in _SKIPPED:
                continue
            elif letter not in "XYZIJKRPF":
                raise self.fail(f"{letter}{value:g} is not read here; this reader takes {_TAKEN}")
            elif letter in values:
                raise self.fail(f"{letter} appears twice on the line")
            else:
                values[letter] = value
        if "F" in values:
            if not values["F"] > 0.0:
                raise self.fail("F must be a feed > 0 [mm/min]")
            self.feed = values.pop("F") / 60.0
        if values:
            self.move(values)

    def g_code(self, value: float) -> None:
        code = int(value)
        if code != value:
            raise self.fail(f"G{value:g} is not taken; this reader takes {_G_TAKEN}")
        if code in (0, 1, 2, 3):
            self.motion = code
        elif code in PLANES:
            self.plane = code
        elif code in (90, 91):
            self.absolute = code == 90
        elif code in (61, 64):
            self.exact = code == 61
        elif code == 20:
            raise self.fail("G20 (inches) is not taken: give the program in mm (G21)")
        elif code != 21 and code not in _NO_OPS:
            raise self.fail(f"G{code:02d} is not taken; this reader takes {_G_TAKEN}")

    def move(self, values: dict[str, float]) -> None:
        """A motion block: a segment from the coordinates and the modal state."""
        if self.motion < 0:
            raise self.fail("coordinates without a motion: give G00, G01, G02 or G03 first")
        circular = self.motion in (2, 3)
        if not circular and any(k in values for k in "IJKRP"):
            raise self.fail("I, J, K, R and P belong to an arc (G02, G03)")
        if self.motion and not self.feed:
            raise self.fail("no feed: give F [mm/min] before the first G01, G02 or G03")
        end = [values.get(a, math.nan) for a in _AXES]
        segment = MC_PATH_SEGMENT(
            EndPoint=end,
            Relative=not self.absolute,
            Velocity=self.rapid if self.motion == 0 else self.feed,
            BufferMode=MC_BufferMode.Buffered if self.exact else MC_BufferMode.BlendingLow,
            Source=f"{self.name}:{self.line}",
        )
        if circular:
            self.arc(segment, values)
        self.segments.append(segment)
        self.advance(end)

    def arc(self, segment: MC_PATH_SEGMENT, values: dict[str, float]) -> None:
        """The arc fields of ``segment`` from the line's I, J, K, R and P."""
        first, second, _ = PLANES[self.plane]
        allowed = {_OFFSETS[first], _OFFSETS[second]}
        offsets = [k for k in _OFFSETS if k in values]
        for k in offsets:
            if k not in allowed:
                plane = f"G{self.plane}"
                raise self.fail(
                    f"{k} is no centre offset in {plane}: use {' and '.join(sorted(allowed))}"
                )
        if offsets and "R" in values:
            raise self.fail("an arc takes its centre (I, J, K) or its radius R, not both")
        if not offsets and "R" not in values:
            raise self.fail("an arc needs its centre (I, J, K) or its radius R")
        turns = values.get("P", 1.0)
        if turns != int(turns) or turns < 1 or ("P" in values and "R" in values):
            raise self.fail("P is the number of turns of an I/J/K arc: an integer >= 1")
        segment.Circular = True
        segment.PathChoice = (
            MC_CIRC_PATHCHOICE.CLOCKWISE
            if self.motion == 2
            else MC_CIRC_PATHCHOICE.COUNTERCLOCKWISE
        )
        segment.Plane = self.plane
        if offsets:
            segment.CircMode = MC_CIRC_MODE.CENTER
            segment.AuxPoint = [values.get(k, 0.0) for k in _OFFSETS]
            segment.AuxRelative = True
            segment.Turns = int(turns) - 1
        else:
            segment.CircMode = MC_CIRC_MODE.RADIUS
            segment.AuxPoint = [values["R"], 0.0, 0.0]
        self.check_arc(segment)

    def check_arc(self, segment: MC_PATH_SEGMENT) -> None:
        """Check the arc in its plane where the program has fixed its start."""
        axes = PLANES[self.plane][:2]
        known = [self.position[i] for i in axes]
        start = [x for x in known if x is not None]
        if len(start) < 2:
            return
        end = []
        for i, here in zip(axes, start, strict=True):
            value = segment.EndPoint[i]
            if math.isnan(value):
                end.append(here)
            else:
                end.append(here + value if segment.Relative else value)
        aux = segment.AuxPoint
        if segment.CircMode == MC_CIRC_MODE.CENTER:
            centre = [here + aux[i] for i, here in zip(axes, start, strict=True)]
        else:
            centre = [aux[0], 0.0]
        try:
            arc(start, segment.CircMode, centre, end, segment.PathChoice, 0, segment.Turns)
        except GeometryError as exc:
            raise self.fail(f"no such arc: {exc}") from None

    def advance(self, end: list[float]) -> None:
        """The known position after a move to ``end`` (NaN: unchanged)."""
        for i, x in enumerate(end):
            if math.isnan(x):
                continue
            known = self.position[i]
            if self.absolute:
                self.position[i] = x
            else:
                self.position[i] = None if known is None else known + x


def parse_gcode(text: str, name: str = "<G-code>", rapid: float = 0.0) -> MC_PATH_DATA_REF:
    """The path table of a G-code program (module docstring).

    Args:
        text: the program.
        name: its name in messages (the file name).
        rapid: the velocity of G00 moves [mm/s]; 0: MC_MovePath's rapid velocity.

    Raises:
        GCodeError: a line cannot be read (``name:line: what is wrong``), or the program has
            no motion.
    """
    reader = _Reader(name, rapid)
    for number_, line in enumerate(text.splitlines(), start=1):
        reader.read(number_, line)
    if not reader.segments:
        raise GCodeError(f"{name}: no motion in it (G00, G01, G02, G03 with coordinates)")
    return MC_PATH_DATA_REF(Segments=list(reader.segments), Name=name)


def read_gcode(path: str | Path, rapid: float = 0.0) -> MC_PATH_DATA_REF:
    """The path table of the G-code file ``path`` (:func:`parse_gcode`).

    Raises:
        OSError: the file cannot be read.
        GCodeError: a line cannot be read (``file:line: what is wrong``).
    """
    path = Path(path)
    return parse_gcode(path.read_text(encoding="utf-8"), str(path), rapid)


class MC_PathSelect(ExecuteFB):
    """Reads a path description into a path table (PLCopen Part 4): ``PathDescription`` is a
    G-code file (its name) or G-code text (a STRING with a line break); ``PathData`` is the
    table for MC_MovePath.

    Done in the scan of the Execute edge. A file that cannot be read or a line it cannot take
    → EParam 5, with the reason and ``file:line`` in ``ErrorText`` (beyond PLCopen).
    ``RapidVelocity`` (beyond PLCopen) [mm/s]: the velocity of G00 moves; 0: each at 80 % of
    the Vmax of the member that moves most.
    """

    REFS: ClassVar[tuple[str, ...]] = ()
    INPUTS: ClassVar[tuple[str, ...]] = ("PathDescription", "RapidVelocity")
    PathDescription: str = ""
    RapidVelocity: float = 0.0

    def __init__(self, **inputs: Any) -> None:
        self.PathData = MC_PATH_DATA_REF()
        self.ErrorText = ""
        super().__init__(**inputs)

    def _command_started(self) -> None:
        self.ErrorText = ""

    def _begin(self) -> int:
        rapid = number(self.RapidVelocity)
        description = self.PathDescription
        if not isinstance(description, str) or not description or not non_negative(rapid):
            self.ErrorText = "PathDescription: a G-code file name or G-code text"
            return ErrorID.EParam
        try:
            if "\n" in description:
                self.PathData = parse_gcode(description, "PathDescription", rapid)
            else:
                self.PathData = read_gcode(description, rapid)
        except (OSError, UnicodeDecodeError) as exc:
            self.ErrorText = f"{description}: cannot read it ({exc})"
            return ErrorID.EParam
        except GCodeError as exc:
            self.ErrorText = str(exc)
            return ErrorID.EParam
        return 0


__all__ = ["GCodeError", "MC_PathSelect", "parse_gcode", "read_gcode"]
