"""IEC 61131-3 converts no integer to a TIME implicitly (2.3.1 and 2.5.1.5.6: a duration is
written ``T#20S``): an integer literal where a TIME is expected — an assignment, a declaration's
initial value, a timer's PT, a comparison, TIME arithmetic — is refused at its file:line with
the duration literal to write; a duration literal and an explicit conversion run."""

from __future__ import annotations

import pytest

from tests.plc.st.iec import refused, run

SEQUENCE = """PROGRAM Sequence
VAR
    tStepTimeout : TIME;
    tWait : TON;
    tElapsed : TIME;
    bTimeout : BOOL;
END_VAR
{statement}
END_PROGRAM
"""
"""A program with TIME variables and a TON; its statement on line 8."""


@pytest.mark.parametrize(
    ("statement", "message"),
    [
        (
            "tStepTimeout := 20000;",
            "8:1: the integer 20000 where TIME is expected: write a duration literal: T#20S "
            "(or T#20000MS)",
        ),
        (
            "tWait(IN := TRUE, PT := 500);",
            "8:19: the integer 500 where TIME is expected: write a duration literal: T#500MS",
        ),
        (
            "bTimeout := tElapsed > 1500;",
            "8:13: TIME > the integer 1500: write a duration literal: T#1.5S (or T#1500MS)",
        ),
        (
            "bTimeout := 250 <= tElapsed;",
            "8:13: the integer 250 <= TIME: write a duration literal: T#250MS",
        ),
        (
            "tStepTimeout := tElapsed + 100;",
            "8:17: TIME + the integer 100: write a duration literal: T#100MS",
        ),
        (
            "tStepTimeout := -2000;",
            "8:1: the integer -2000 where TIME is expected: write a duration literal: T#-2S "
            "(or T#-2000MS)",
        ),
    ],
)
def test_an_integer_where_a_time_is_expected_is_refused_with_the_literal_to_write(
    statement, message
):
    """Each is refused at its place, with the duration literal of the integer read as ms."""
    assert refused(SEQUENCE.format(statement=statement), "seq.st") == f"seq.st:{message}"


def test_an_integer_initial_value_of_a_time_is_refused():
    """``tStepTimeout : TIME := 20000;``: refused at the value."""
    source = SEQUENCE.replace("tStepTimeout : TIME;", "tStepTimeout : TIME := 20000;")
    assert refused(source.format(statement=""), "seq.st") == (
        "seq.st:3:28: the integer 20000 where TIME is expected: write a duration literal: T#20S "
        "(or T#20000MS)"
    )


def test_a_duration_literal_and_an_explicit_conversion_run():
    """``T#20S``, ``DINT_TO_TIME(20000)``, a TON's ``PT := T#500MS`` and TIME scaled by an
    integer (``T#1S * 2``, IEC's MUL_TIME) are what the refused forms become."""
    statement = (
        "tStepTimeout := T#20S; tElapsed := DINT_TO_TIME(20000) - T#1S * 2;"
        "tWait(IN := TRUE, PT := T#500MS); bTimeout := tElapsed > T#1.5S;"
    )
    prog = run(SEQUENCE.format(statement=statement))
    assert (prog.tStepTimeout, prog.tElapsed, prog.bTimeout) == (20000, 18000, True)
