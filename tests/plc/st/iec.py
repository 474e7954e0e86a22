"""Helpers of the IEC 61131-3 tests: run an ST source for some scans, or get the message it is
refused with."""

from __future__ import annotations

import math
from typing import Any

import pytest

import plc.st


def run(source: str, scans: int = 1, filename: str = "iec.st") -> plc.st.STProgram:
    """The program of ``source`` after ``scans`` PLC scans of 10 ms (no run-time fault)."""
    prog = plc.st.from_source(source, filename=filename, period=0.01)
    for _ in range(scans):
        prog()
    assert not prog.fault, prog.fault
    return prog


def program(decls: str, body: str, before: str = "") -> str:
    """A PROGRAM ``t`` with the variables ``decls`` and the statements ``body``, after the
    declarations ``before`` (types, functions, globals)."""
    head = f"{before}\n" if before else ""
    return f"{head}PROGRAM t\nVAR\n{decls}\nEND_VAR\n{body}\nEND_PROGRAM\n"


def refused(source: str, filename: str = "iec.st") -> str:
    """The one-line message an erroneous source is refused with (``file:line:column: ...``)."""
    try:
        plc.st.from_source(source, filename=filename, period=0.01)
    except plc.st.STError as error:
        assert len(error.lines) == 1, error.lines
        return str(error)
    raise AssertionError("the source was accepted")


def fault(source: str, scans: int = 1) -> str:
    """The run-time fault that stops the program of ``source`` within ``scans`` scans."""
    prog = plc.st.from_source(source, filename="iec.st", period=0.01)
    for _ in range(scans):
        prog()
    assert prog.fault, "no fault"
    return prog.fault


def same(value: object, expected: object) -> bool:
    """``value`` is ``expected``: equal and of the same Python type; NaN is NaN; a real within
    a relative 1e-12."""
    if isinstance(expected, float) and math.isnan(expected):
        return isinstance(value, float) and math.isnan(value)
    if isinstance(expected, float):
        return isinstance(value, float) and math.isclose(value, expected, rel_tol=1e-12)
    return value == expected and type(value) is type(expected)


def case(clause: str, decls: str, body: str, name: str, expected: object, before: str = "") -> Any:
    """One conformance case: the PROGRAM's variable ``name`` after one scan is ``expected``;
    its id names the IEC 61131-3 clause it checks."""
    return pytest.param(decls, body, name, expected, before, id=clause)
