"""DATE, TIME_OF_DAY and DATE_AND_TIME (IEC 61131-3 2.3.1, 2.2.3.2; 3rd ed. 6.4.2, 6.3.5): their
literals ``D#2024-03-01``, ``TOD#12:30:15.5``, ``DT#2024-03-01-12:30:00``, the arithmetic IEC
defines on them (2.5.1.5.6, Table 30; 3rd ed. 6.6.2.5.14, Table 35) and their conversions.

Each is held in ms, as TIME is: a DATE since 1970-01-01, a TIME_OF_DAY since midnight (a result
outside the day wraps into it), a DATE_AND_TIME since 1970-01-01-00:00:00.
"""

from __future__ import annotations

__all__ = ["conversion", "literal", "result_type", "wrapped"]

import datetime
from typing import TYPE_CHECKING, Any

import blark.transform as tf

from plc.st.runtime.functions import DAY
from plc.st.semantics import types as T  # noqa: N812
from plc.st.semantics.types import Elementary

if TYPE_CHECKING:
    from plc.st.codegen.expressions import E, Expressions

_SUMS = {
    ("+", "tod", "TIME"): T.TOD,
    ("+", "dt", "TIME"): T.DT,
    ("-", "date", "date"): T.TIME,
    ("-", "tod", "TIME"): T.TOD,
    ("-", "tod", "tod"): T.TIME,
    ("-", "dt", "TIME"): T.DT,
    ("-", "dt", "dt"): T.TIME,
}
"""(operator, kind of IN1, kind of IN2, TIME standing for TIME itself) → the result's type."""

_EPOCH = datetime.date(1970, 1, 1)


def literal(x: Expressions, node: Any) -> E:
    """``D#…``, ``TOD#…``, ``DT#…`` as a constant [ms]."""
    from plc.st.codegen.expressions import const

    if isinstance(node, tf.DateTime):
        return const(_date(x, node.date, node) + _time(x, node.time, node), T.DT)
    if isinstance(node, tf.Date):
        return const(_date(x, node, node), T.DATE)
    return const(_time(x, node, node), T.TOD)


def _date(x: Expressions, date: tf.Date, node: Any) -> int:
    try:
        day = datetime.date(int(date.year), int(date.month), int(date.day or 1))
    except ValueError as error:
        raise x.error(node, f"the date {date.value} ({error})", "a date YYYY-MM-DD") from None
    return (day - _EPOCH).days * DAY


def _time(x: Expressions, time: tf.TimeOfDay, node: Any) -> int:
    hour, minute = int(time.hour), int(time.minute)
    second = float(str(time.second).replace("_", "")) if time.second is not None else 0.0
    if not (hour < 24 and minute < 60 and second < 60):
        raise x.error(node, f"the time of day {time.value}", "hh:mm:ss below 24:00:00")
    return hour * 3_600_000 + minute * 60_000 + round(second * 1000)


def result_type(op: str, ta: Elementary, tb: Elementary) -> Elementary | None:
    """The type of ``ta op tb`` where one operand is a date type, None where IEC defines no
    such operation."""
    key = (op, ta.kind, "TIME" if tb is T.TIME else tb.kind)
    return _SUMS.get(key)


def wrapped(code: str, t: Elementary) -> str:
    """A TIME_OF_DAY result wrapped into the day."""
    return f"({code} % {DAY})" if t is T.TOD else code


def conversion(x: Expressions, node: Any, arg: E, to: Elementary) -> str | None:
    """The code of a conversion to or from a date type (``DT_TO_DATE``, ``DT_TO_TOD``,
    ``DATE_TO_DT``, ``*_TO_STRING``), None where there is none."""
    kind, c = arg.type.kind, arg.code
    if to.kind == kind:
        return c
    if to.kind == "string":
        return f"_f.{kind}_text({c})" if kind in ("date", "tod", "dt") else None
    if kind == "dt" and to.kind == "date":
        return f"({c} - {c} % {DAY})"
    if kind == "dt" and to.kind == "tod":
        return f"({c} % {DAY})"
    if kind == "date" and to.kind == "dt":
        return c
    return None
