"""The run-time helpers of translated ST code and the IEC 61131-3 standard functions that need
more than an operator (see docs/st.md for the rules chosen where IEC leaves them open).

A fault a PLC stops on (an integer division by zero, an array index out of range) raises
:class:`STFault`; the program that ran it then stops (see :mod:`plc.st.runtime.program`).
"""

from __future__ import annotations

__all__ = [
    "STFault",
    "clone",
    "delete",
    "div",
    "expt",
    "f32",
    "fdiv",
    "find",
    "index",
    "insert",
    "left",
    "limit",
    "ln",
    "log10",
    "mid",
    "mod",
    "mux",
    "real_text",
    "reals",
    "replace",
    "right",
    "rol",
    "ror",
    "shl",
    "shr",
    "sqrt",
    "time_text",
    "to_int",
    "to_number",
    "trunc",
    "watchdog",
]

import datetime
import math
import struct
from collections.abc import Sequence
from typing import Any

_F32 = struct.Struct("f")


class STFault(ArithmeticError):
    """A fault a PLC stops on; the message says what (the program adds file:line)."""


def f32(x: float) -> float:
    """``x`` rounded to a 32-bit REAL (beyond its range: ±infinity)."""
    try:
        value: float = _F32.unpack(_F32.pack(x))[0]
    except OverflowError:
        return math.copysign(math.inf, x)
    return value


def div(a: int, b: int) -> int:
    """Integer division truncating toward zero (IEC); by zero: :class:`STFault`."""
    if not b:
        raise STFault("integer division by zero")
    q = abs(a) // abs(b)
    return q if (a < 0) == (b < 0) else -q


def fdiv(a: float, b: float) -> float:
    """Real division; by zero: :class:`STFault` (the PLC stops, as on a CODESYS target with
    floating-point exceptions enabled)."""
    if not b:
        raise STFault("division by zero")
    return a / b


def mod(a: int, b: int) -> int:
    """``a MOD b``: the remainder of :func:`div`, with the sign of ``a``; 0 where ``b`` is 0
    (IEC 61131-3 2.5.1.5.2, 3rd ed. 6.6.2.5.8: ``IF IN2 = 0 THEN OUT := 0``)."""
    if not b:
        return 0
    return a - b * div(a, b)


def expt(a: float, b: float) -> float:
    """``a ** b`` (EXPT); NaN where it is not a real number."""
    try:
        return math.pow(a, b)
    except (ValueError, ZeroDivisionError):
        return math.nan
    except OverflowError:
        return math.inf


def within(value: int, low: int, high: int) -> int:
    """``value`` stored into a subrange ``low..high``; outside: :class:`STFault`."""
    if low <= value <= high:
        return value
    raise STFault(f"{value} outside the subrange {low}..{high}")


def index(i: int, low: int, size: int) -> int:
    """The list position of array index ``i`` (bounds ``low``..``low + size - 1``); outside:
    :class:`STFault`."""
    k = i - low
    if 0 <= k < size:
        return k
    raise STFault(f"array index {i} outside {low}..{low + size - 1}")


def to_int(x: float) -> int:
    """A real converted to an integer: rounded to the nearest, halves to the even neighbour
    (IEC 60559 round-to-nearest, as the FPU conversion of CODESYS and TwinCAT targets: 1.5 → 2,
    -1.5 → -2, 2.5 → 2); NaN and infinities give 0."""
    if not math.isfinite(x):
        return 0
    return round(x)


def trunc(x: float) -> int:
    """TRUNC: toward zero; NaN and infinities give 0."""
    return math.trunc(x) if math.isfinite(x) else 0


def sqrt(x: float) -> float:
    """SQRT; NaN for a negative argument."""
    return math.sqrt(x) if x >= 0.0 else math.nan


def ln(x: float) -> float:
    """LN; -inf at 0, NaN below."""
    return math.log(x) if x > 0.0 else (-math.inf if x == 0.0 else math.nan)


def log10(x: float) -> float:
    """LOG (base 10); -inf at 0, NaN below."""
    return math.log10(x) if x > 0.0 else (-math.inf if x == 0.0 else math.nan)


def limit(low: Any, x: Any, high: Any) -> Any:
    """LIMIT(MN, IN, MX)."""
    return low if x < low else high if x > high else x


def mux(k: int, *values: Any) -> Any:
    """MUX(K, IN0, ...); K outside: :class:`STFault`."""
    if 0 <= k < len(values):
        return values[k]
    raise STFault(f"MUX selector {k} outside 0..{len(values) - 1}")


def shl(x: int, n: int, bits: int) -> int:
    """SHL on a ``bits``-wide bit string."""
    return (x << n) & ((1 << bits) - 1) if n < bits else 0


def shr(x: int, n: int, bits: int) -> int:
    """SHR: shifted right, zeros in (the value taken as unsigned)."""
    return (x & ((1 << bits) - 1)) >> n


def rol(x: int, n: int, bits: int) -> int:
    """ROL on a ``bits``-wide bit string."""
    m = (1 << bits) - 1
    n %= bits
    x &= m
    return ((x << n) | (x >> (bits - n))) & m


def ror(x: int, n: int, bits: int) -> int:
    """ROR on a ``bits``-wide bit string."""
    return rol(x, bits - n % bits, bits)


# ------------------------------------------------------------------ strings (1-based positions)
def left(s: str, n: int) -> str:
    """LEFT(IN, L)."""
    return s[: max(n, 0)]


def right(s: str, n: int) -> str:
    """RIGHT(IN, L)."""
    return s[len(s) - n :] if 0 < n <= len(s) else (s if n > 0 else "")


def mid(s: str, n: int, p: int) -> str:
    """MID(IN, L, P): ``n`` characters from position ``p`` (1 = the first)."""
    if p < 1 or n <= 0:
        return ""
    return s[p - 1 : p - 1 + n]


def insert(s: str, t: str, p: int) -> str:
    """INSERT(IN1, IN2, P): ``t`` inserted after position ``p``."""
    p = min(max(p, 0), len(s))
    return s[:p] + t + s[p:]


def delete(s: str, n: int, p: int) -> str:
    """DELETE(IN, L, P): ``n`` characters removed from position ``p``."""
    if p < 1 or n <= 0:
        return s
    return s[: p - 1] + s[p - 1 + n :]


def replace(s: str, t: str, n: int, p: int) -> str:
    """REPLACE(IN1, IN2, L, P): ``n`` characters from position ``p`` replaced by ``t``."""
    if p < 1:
        return s
    return s[: p - 1] + t + s[p - 1 + max(n, 0) :]


def find(s: str, t: str) -> int:
    """FIND(IN1, IN2): the position of ``t`` in ``s`` (1 = the first), 0 if absent."""
    return s.find(t) + 1


def real_text(x: float, single: bool = False) -> str:
    """A real as a STRING (REAL_TO_STRING, LREAL_TO_STRING): the shortest text that reads back
    as the value, at the precision of its type (``single``: a 32-bit REAL, 0.1 not
    0.10000000149011612)."""
    if math.isnan(x):
        return "NaN"
    if math.isinf(x):
        return "INF" if x > 0 else "-INF"
    if single:
        for digits in range(1, 10):
            text = repr(float(f"{x:.{digits}g}"))
            if f32(float(text)) == x:
                return text
    return repr(x)


def to_number(s: str, integral: bool) -> float | int:
    """STRING_TO_INT / STRING_TO_REAL: the leading number of ``s``, 0 if there is none."""
    text = s.strip()
    try:
        return int(float(text)) if integral else float(text)
    except ValueError:
        return 0


def time_text(ms: int) -> str:
    """A TIME as its literal (``T#1s500ms``)."""
    sign, ms = ("-", -ms) if ms < 0 else ("", ms)
    parts = []
    for unit, size in (("d", 86_400_000), ("h", 3_600_000), ("m", 60_000), ("s", 1000)):
        if ms >= size:
            parts.append(f"{ms // size}{unit}")
            ms %= size
    if ms or not parts:
        parts.append(f"{ms}ms")
    return f"T#{sign}{''.join(parts)}"


def set_bits(x: int, shift: int, width: int, value: int) -> int:
    """``x`` with its ``width`` bits from bit ``shift`` replaced by ``value`` (a partial write
    ``w.3 := TRUE``, ``w.%B1 := 16#FF``)."""
    mask = ((1 << width) - 1) << shift
    return (x & ~mask) | ((int(value) << shift) & mask)


class Ref:
    """A REF_TO value (IEC 61131-3 3rd ed. 6.4.4.10): the variable ``key`` of ``owner`` (an
    attribute name, or an index of a list); :attr:`v` reads and writes it (``r^``)."""

    __slots__ = ("key", "owner")

    def __init__(self, owner: Any, key: str | int) -> None:
        self.owner = owner
        self.key = key

    @property
    def v(self) -> Any:
        """The variable referred to."""
        key = self.key
        return self.owner[key] if isinstance(key, int) else getattr(self.owner, key)

    @v.setter
    def v(self, value: Any) -> None:
        key = self.key
        if isinstance(key, int):
            self.owner[key] = value
        else:
            setattr(self.owner, key, value)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Ref) and self.owner is other.owner and self.key == other.key

    def __hash__(self) -> int:
        return hash((id(self.owner), self.key))


class _Null(Ref):
    """NULL: a reference to nothing; a dereference is a fault."""

    @property
    def v(self) -> Any:
        raise STFault("dereference of a NULL reference")

    @v.setter
    def v(self, value: Any) -> None:
        raise STFault("dereference of a NULL reference")


NULL = _Null(None, "")
"""The REF_TO value of no variable (a REF_TO's initial value)."""

DAY = 86_400_000
"""A day [ms]: the range of a TIME_OF_DAY."""


def date_text(ms: int) -> str:
    """A DATE as its literal, ``D#2024-03-01``."""
    day = (_EPOCH + datetime.timedelta(milliseconds=ms - ms % DAY)).date()
    return f"D#{day.isoformat()}"


def tod_text(ms: int) -> str:
    """A TIME_OF_DAY as its literal, ``TOD#12:30:05.25`` (the fraction where there is one)."""
    ms %= DAY
    seconds, fraction = divmod(ms % 60_000, 1000)
    text = f"{ms // 3_600_000:02d}:{ms // 60_000 % 60:02d}:{seconds:02d}"
    return f"TOD#{text}.{fraction:03d}".rstrip("0") if fraction else f"TOD#{text}"


def dt_text(ms: int) -> str:
    """A DATE_AND_TIME as its literal, ``DT#2024-03-01-12:30:00``."""
    return f"DT#{date_text(ms)[2:]}-{tod_text(ms)[4:]}"


_EPOCH = datetime.datetime(1970, 1, 1)
FIRST_DAY = (datetime.datetime(1, 1, 1) - _EPOCH) // datetime.timedelta(milliseconds=1)
"""D#0001-01-01 [ms from 1970-01-01]: the initial value of a DATE and a DATE_AND_TIME."""


def watchdog(kind: str, line: int, limit: float) -> None:
    """The task's watchdog tripped in the ``kind`` loop (WHILE, REPEAT, FOR) of ``line``:
    :class:`STFault` (``limit`` the watchdog [s])."""
    raise STFault(
        f"the scan ran over the task's watchdog of {limit * 1e3:g} ms in the {kind} loop of "
        f"line {line}"
    )


def reals(values: Sequence[float], size: int) -> list[float]:
    """A group block's per-axis values (``MC_GroupReadActualPosition.Position`` [mm]) as an
    ARRAY of ``size`` LREALs: the elements it lacks (a disabled block has none) are 0.0; more
    values than elements: :class:`STFault`."""
    if len(values) > size:
        raise STFault(f"{len(values)} values into an ARRAY of {size}")
    return [*values, *[0.0] * (size - len(values))]


def clone(value: Any) -> Any:
    """A copy of an ARRAY or STRUCT value (assignment copies in IEC); elementary values as
    they are."""
    if type(value) is list:
        return [clone(v) for v in value]
    copy = getattr(value, "_copy", None)
    return copy() if copy is not None else value
