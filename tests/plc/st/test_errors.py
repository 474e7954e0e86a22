"""Malformed ST programs give one ``file:line:column`` message; a run-time fault stops the
program with file:line and the axes at standstill."""

import pytest

import plc.st

BAD = [
    ("x : INT", "x := 3 +;", "3:9: unexpected ';'; expected an expression"),
    ("x : INT", "IF x > 1 THEN x := 1;", "3:1: IF at 3:1 has no END_IF; expected END_IF before"),
    ("x : INT", "y := 1;", "3:1: unknown variable 'y'"),
    ("count : INT", "cuont := 1;", "did you mean count"),
    ("x : INT", "x := 1.5;", "3:1: an ANY_REAL value where INT is expected"),
    ("x : BOOL", "x := 1;", "an ANY_INT value where BOOL is expected"),
    ("x : INT; b : BOOL", "x := b;", "a BOOL value where INT is expected"),
    ("t : TONN", "t();", "2:9: unknown type 'TONN' (did you mean TON"),
    ("m : MC_MoveAbsolut", "m();", "unknown type 'MC_MoveAbsolut' (did you mean MC_MoveAbsolute"),
    (
        "h : MC_Home",
        "h();",
        "unknown type 'MC_Home': the library homes with the step blocks MC_StepAbsSwitch",
    ),
    ("t : TON", "t(INN := TRUE);", "3:3: TON has no input or output 'INN' (did you mean IN"),
    ("t : TON; q : BOOL", "t(Q := q);", "Q is an output; expected Q => variable"),
    ("t : TON; q : BOOL", "t(IN => q);", "IN is not an output"),
    ("x : INT", "x := 1 / 0;", "integer division by zero"),
    ("a : ARRAY[1..3] OF INT", "a[4] := 1;", "3:3: index 4 outside 1..3"),
    ("x : INT", "x := MOD(1);", "3:6: a parameter is missing; expected IN1, IN2"),
    ("x : INT", "x := FOO(1);", "3:6: unknown function 'FOO'"),
    ("x : INT", "IF x THEN x := 1; END_IF", "a condition of type INT; expected BOOL"),
    ("x : INT", "EXIT;", "EXIT outside a loop"),
    ("x : REAL", "x := 2.0 MOD 1;", "expected integer operands"),
    ("x : INT", "x := x + TRUE;", "INT + BOOL"),
    ("x : STRING", "x := 'a' + 'b';", "expected CONCAT(a, b)"),
    ("x : INT; x : INT", "x := 1;", "'x' is declared twice"),
    ("p : ST_X", "p := 1;", "unknown type 'ST_X'"),
    ("a : ARRAY[1..3] OF INT", "a[1, 2] := 1;", "2 indices"),
    ("ax : AXIS_REF", "ax := ax;", "AXIS_REF ax is bound to no axis"),
]


@pytest.mark.parametrize(("decls", "body", "message"), BAD)
def test_a_malformed_program_names_file_line_column(decls, body, message):
    source = f"PROGRAM p\nVAR {decls}; END_VAR\n{body}\nEND_PROGRAM\n"
    with pytest.raises(plc.st.STError) as raised:
        plc.st.from_source(source, filename="bad.st")
    text = str(raised.value)
    assert text.startswith("bad.st:") and len(raised.value.lines) == 1
    assert message in text


def test_an_index_out_of_range_at_run_time_stops_the_program_naming_its_line():
    source = (
        "PROGRAM p\nVAR a : ARRAY[1..3] OF INT; i : INT; n : INT; END_VAR\n"
        "n := n + 1;\ni := i + 2;\na[i] := 1;\nEND_PROGRAM\n"
    )
    prog = plc.st.from_source(source, filename="run.st")
    for _ in range(5):
        prog()
    assert prog.error == "run.st:5: array index 4 outside 1..3; the program stopped"
    assert prog.n == 2  # no longer scanned after the fault


@pytest.mark.parametrize(
    ("source", "message"),
    [
        (
            "INTERFACE I\nEND_INTERFACE\n"
            + "PROGRAM p\nVAR x : INT; END_VAR\nx := 1;\nEND_PROGRAM\n",
            "bad.st:1:1: Interface; expected PROGRAM, FUNCTION_BLOCK, FUNCTION, TYPE, VAR_GLOBAL",
        ),
        (
            "PROGRAM p\nVAR x : INT; END_VAR\nx := 1;\nEND_PROGRAM\n"
            + "ACTION a:\nx := 2;\nEND_ACTION\n",
            "bad.st:5:1: Action; expected PROGRAM, FUNCTION_BLOCK, FUNCTION, TYPE, VAR_GLOBAL",
        ),
    ],
    ids=["interface", "action"],
)
def test_an_item_of_a_kind_the_translator_does_not_run_is_named_at_its_line(source, message):
    with pytest.raises(plc.st.STError) as raised:
        plc.st.from_source(source, filename="bad.st")
    assert str(raised.value) == message
