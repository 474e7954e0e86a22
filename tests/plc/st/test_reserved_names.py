"""A keyword of IEC 61131-3 used as a name (IEC 61131-3 2.1.2, 2.1.3: keywords are no
identifiers) is refused at its ``file:line:column`` as the reserved keyword it is, with a name
that would do; a syntax error that only looks alike keeps its own message."""

from __future__ import annotations

import pytest

import plc.st

CONVEYOR = """PROGRAM Conveyor
VAR
    speed : REAL;
    {name} : INT;
END_VAR
speed := 0.5;
END_PROGRAM
"""

KEYWORDS = ["by", "to", "do", "of", "at", "action", "exit", "return", "then", "until", "type"]
"""Keywords an engineer picks as a name: a step width, a target, a counter, an action."""


@pytest.mark.parametrize("name", KEYWORDS)
def test_a_keyword_declared_as_a_variable_is_refused_as_a_keyword(name):
    with pytest.raises(plc.st.STError) as error:
        plc.st.from_source(CONVEYOR.format(name=name), filename="conveyor.st")
    assert str(error.value) == (
        f"conveyor.st:4:5: {name.upper()} is a reserved keyword of IEC 61131-3 and cannot name"
        f" a variable; expected another name, such as {name}Value"
    )


@pytest.mark.parametrize(
    ("source", "message"),
    [
        (  # one of a list of names, written in capitals
            "PROGRAM Feeder\nVAR\n    FROM, TO : DINT;\nEND_VAR\nEND_PROGRAM\n",
            "3:11: TO is a reserved keyword of IEC 61131-3 and cannot name a variable; "
            "expected another name, such as TO_VALUE",
        ),
        (  # on one line with VAR, as the address's AT
            "PROGRAM Feeder\nVAR at : BOOL; END_VAR\nEND_PROGRAM\n",
            "2:5: AT is a reserved keyword of IEC 61131-3 and cannot name a variable; "
            "expected another name, such as atValue",
        ),
        (  # the AT of a located variable before it
            "PROGRAM Feeder\nVAR\n    AT %IX0.0 : BOOL;\n    At : INT;\nEND_VAR\nEND_PROGRAM\n",
            "4:5: AT is a reserved keyword of IEC 61131-3 and cannot name a variable; "
            "expected another name, such as AtValue",
        ),
        (  # read as the attribute of the VAR block before it
            "PROGRAM Feeder\nVAR\n    Persistent : BOOL;\nEND_VAR\nEND_PROGRAM\n",
            "3:5: PERSISTENT is a reserved keyword of IEC 61131-3 and cannot name a variable; "
            "expected another name, such as PersistentValue",
        ),
        (  # the variable of a FOR loop
            "PROGRAM Feeder\nVAR\n    n : INT;\nEND_VAR\nFOR do := 1 TO 3 DO\n    n := n + 1;\n"
            "END_FOR\nEND_PROGRAM\n",
            "5:5: DO is a reserved keyword of IEC 61131-3 and cannot name a variable; "
            "expected another name, such as doValue",
        ),
        (  # the name of a PROGRAM, a comment before it on the line
            "(* the cell *) PROGRAM Action\nVAR\n    n : INT;\nEND_VAR\nEND_PROGRAM\n",
            "1:24: ACTION is a reserved keyword of IEC 61131-3 and cannot name a PROGRAM; "
            "expected another name, such as ActionValue",
        ),
        (
            "FUNCTION_BLOCK Step\nEND_FUNCTION_BLOCK\nFUNCTION_BLOCK Exit\nVAR_INPUT\n"
            "    Execute : BOOL;\nEND_VAR\nEND_FUNCTION_BLOCK\n",
            "3:16: EXIT is a reserved keyword of IEC 61131-3 and cannot name a FUNCTION_BLOCK; "
            "expected another name, such as ExitValue",
        ),
        (
            "FUNCTION Of : INT\nVAR_INPUT\n    a : INT;\nEND_VAR\nOf := a;\nEND_FUNCTION\n",
            "1:10: OF is a reserved keyword of IEC 61131-3 and cannot name a FUNCTION; "
            "expected another name, such as OfValue",
        ),
    ],
)
def test_a_keyword_as_a_name_is_named_at_its_line_and_column(source, message):
    with pytest.raises(plc.st.STError) as error:
        plc.st.from_source(source, filename="feeder.st")
    assert str(error.value) == f"feeder.st:{message}"


@pytest.mark.parametrize(
    ("source", "message"),
    [
        (  # the PROGRAM's name forgotten: VAR is no name meant
            "PROGRAM\nVAR\n    n : INT;\nEND_VAR\nEND_PROGRAM\n",
            "2:1: unexpected 'VAR'; expected a name",
        ),
        (  # the list of names not ended: END_VAR is no name meant
            "PROGRAM p\nVAR\n    a,\nEND_VAR\nEND_PROGRAM\n",
            "4:1: unexpected 'END_VAR'; expected a name",
        ),
        (  # a name's address forgotten after its AT
            "PROGRAM p\nVAR\n    limit AT : BOOL;\nEND_VAR\nEND_PROGRAM\n",
            "3:14: unexpected ':'; expected '%'",
        ),
        (  # a colon after ELSE, as after a CASE label
            "PROGRAM p\nVAR\n    n : INT;\nEND_VAR\nCASE n OF\n1: n := 2;\nELSE:\n    n := 3;\n"
            "END_CASE\nEND_PROGRAM\n",
            "7:5: unexpected ':'; expected 'END_CASE', '%', ';', 'CASE', 'CONTINUE', 'EXIT', "
            "'FOR', 'IF'",
        ),
        (  # an END_IF without its IF
            "PROGRAM p\nVAR\n    n : INT;\nEND_VAR\nn := 1;\nEND_IF;\nEND_PROGRAM\n",
            "6:1: unexpected 'END_IF'; expected 'END_PROGRAM', '%', ';', 'CASE', 'CONTINUE', "
            "'EXIT', 'FOR', 'IF'",
        ),
    ],
)
def test_a_keyword_where_a_name_may_stand_but_none_was_meant_keeps_its_message(source, message):
    with pytest.raises(plc.st.STError) as error:
        plc.st.from_source(source, filename="p.st")
    assert str(error.value) == f"p.st:{message}"


def test_a_keyword_as_a_name_in_a_later_item_names_its_line_in_the_file():
    """The items parse one by one: the line is the file's, not the item's."""
    source = (
        "FUNCTION_BLOCK FB_Axis\nVAR_INPUT\n    Enable : BOOL;\nEND_VAR\nEND_FUNCTION_BLOCK\n"
        + CONVEYOR.format(name="BY")
    )
    with pytest.raises(plc.st.STError) as error:
        plc.st.from_source(source, filename="cell.st")
    assert str(error.value).startswith("cell.st:9:5: BY is a reserved keyword of IEC 61131-3")


def test_iec_keywords_that_programs_use_as_names_name_variables():
    """STEP, TASK, ON (IEC's SFC and configuration keywords) and TwinCAT's REFERENCE name
    variables here, as in TwinCAT: a program reports its ``step``."""
    program = plc.st.from_source(
        "PROGRAM Cell\nVAR\n    step, task, on, reference : INT;\nEND_VAR\n"
        "step := 1;\ntask := step + 1;\non := task + 1;\nreference := on + 1;\nEND_PROGRAM\n",
        filename="cell.st",
    )
    program()
    assert (program.step, program.task, program.on, program.reference) == ("1", 2, 3, 4)
