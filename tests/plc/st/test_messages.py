"""Messages as a PLC engineer needs them: a type error names the conversion that would be right
(and speaks its types with "a" or "an" as they are said), a statement left open is reported
where it begins, several PROGRAMs without a TASK say how to choose one, and TwinCAT's words that
IEC does not reserve name variables."""

from __future__ import annotations

import pytest

import plc.st
from plc.st.errors import indefinite
from scenes.tools import cli
from tests.plc.st.iec import program, refused, run
from tests.plc.st.test_projects import _pou

TYPES = "TYPE E_Seq : (Idle, Run, Stop, Fault); P : STRUCT a : INT; END_STRUCT; END_TYPE"
"""The types of the cases (the PROGRAM's statement is then on line 6)."""


@pytest.mark.parametrize(
    ("decls", "body", "message"),
    [
        (
            "x : INT; r : LREAL;",
            "x := r;",
            "an LREAL value where INT is expected: convert it with LREAL_TO_INT(...) "
            "(it rounds to the nearest integer)",
        ),
        (
            "x : INT;",
            "x := 1.5;",
            "an ANY_REAL value where INT is expected: convert it with TO_INT(...) "
            "(it rounds to the nearest integer)",
        ),
        (
            "b : BOOL; i : INT;",
            "b := i;",
            "an INT value where BOOL is expected: convert it with INT_TO_BOOL(...)",
        ),
        (
            "i : SINT; b : BOOL;",
            "i := b;",
            "a BOOL value where SINT is expected: convert it with BOOL_TO_SINT(...)",
        ),
        (
            "s : STRING(25); i : INT;",
            "i := s;",
            "a STRING(25) value where INT is expected: convert it with STRING_TO_INT(...)",
        ),
        (
            "t : TIME; d : DINT;",
            "d := t;",
            "a TIME value where DINT is expected: convert it with TIME_TO_DINT(...)",
        ),
        (
            "u : UDINT; r : REAL;",
            "u := r;",
            "a REAL value where UDINT is expected: convert it with REAL_TO_UDINT(...) "
            "(it rounds to the nearest integer)",
        ),
        (
            "d : DT; t : TOD;",
            "t := d;",
            "a DT value where TOD is expected: convert it with DT_TO_TOD(...)",
        ),
        (
            "d : DATE; t : TOD;",
            "t := d;",
            "a DATE value where TOD is expected: no conversion makes a TOD of it",
        ),
        (
            "s : E_Seq; i : INT;",
            "s := i;",
            "an INT value where E_Seq is expected: no conversion makes an E_Seq: write one of its "
            "values, E_Seq.Idle, E_Seq.Run, E_Seq.Stop, ...",
        ),
        (
            "p : P; i : INT;",
            "p := i;",
            "an INT value where P is expected: no conversion makes a P of it",
        ),
    ],
)
def test_a_type_error_names_the_conversion_that_would_be_right(decls, body, message):
    """The standard conversion function for the two types (TO_INT for a literal), that it
    rounds where it does, or that none exists; at the statement's place."""
    assert refused(program(decls, body, TYPES)) == f"iec.st:6:1: {message}"


def test_the_conversions_named_are_the_translators():
    """What a message proposes translates and gives the value: LREAL_TO_INT(2.5) is 2 (halves
    to even), TO_INT(1.5) is 2, DT_TO_TOD keeps the time of day."""
    prog = run(
        program(
            "x, y : INT; r : LREAL := 2.5; d : DT := DT#2024-01-02-03:04:05; t : TOD;",
            "x := LREAL_TO_INT(r); y := TO_INT(1.5); t := DT_TO_TOD(d);",
        )
    )
    assert (prog.x, prog.y, prog.t) == (2, 2, (3 * 3600 + 4 * 60 + 5) * 1000)


@pytest.mark.parametrize(
    ("name", "spoken"),
    [
        ("INT", "an INT"),
        ("LREAL", "an LREAL"),
        ("SINT", "an SINT"),
        ("LINT", "an LINT"),
        ("LWORD", "an LWORD"),
        ("DINT", "a DINT"),
        ("BOOL", "a BOOL"),
        ("REAL", "a REAL"),
        ("UDINT", "a UDINT"),
        ("USINT", "a USINT"),
        ("ARRAY[1..3] OF INT", "an ARRAY[1..3] OF INT"),
        ("STRING(25)", "a STRING(25)"),
        ("TIME", "a TIME"),
        ("TOD", "a TOD"),
        ("AXIS_REF", "an AXIS_REF"),
        ("ANY_INT", "an ANY_INT"),
        ("E_Step", "an E_Step"),
        ("ST_Point", "an ST_Point"),
        ("FB_HomeAxis", "an FB_HomeAxis"),
        ("MC_Power", "an MC_Power"),
        ("R_TRIG", "an R_TRIG"),
        ("RS", "an RS"),
        ("TON", "a TON"),
        ("TP", "a TP"),
        ("CTUD", "a CTUD"),
        ("I_Sensor", "an I_Sensor"),
        ("GVL_Axes", "a GVL_Axes"),
        ("Aa_Point", "an Aa_Point"),
        ("REF_TO INT", "a REF_TO INT"),
        ("Color", "a Color"),
        ("Axis", "an Axis"),
    ],
)
def test_a_type_takes_a_or_an_as_it_is_said(name, spoken):
    """A word by its first sound ("an INT", "an ARRAY", "a UDINT": U is said "you"), letters
    said one by one by the first letter's name ("an LREAL", "an SINT", "an ST_Point")."""
    assert indefinite(name) == spoken


@pytest.mark.parametrize(
    ("body", "message"),
    [
        (
            "CASE s OF\n  1: IF a THEN\n       x := 1;\n  2: x := 2;\nEND_CASE;",
            "5:6: IF at 5:6 has no END_IF; expected END_IF before '2' at 7:3",
        ),
        (
            "CASE s OF\n  1: x := 2;\n  2: IF a THEN\n       x := 1;\nEND_CASE;",
            "6:6: IF at 6:6 has no END_IF; expected END_IF before 'END_CASE' at 8:1",
        ),
        (
            "CASE s OF\n  Idle: IF a THEN\n       x := 1;\n  Run: x := 2;\nEND_CASE;",
            "5:9: IF at 5:9 has no END_IF; expected END_IF before 'END_CASE' at 8:1",
        ),
        (
            "FOR x := 1 TO 3 DO\n  s := s + x;",
            "4:1: FOR at 4:1 has no END_FOR; expected END_FOR before 'END_PROGRAM' at 6:1",
        ),
        (
            "IF a THEN\n  WHILE x < 3 DO\n    x := x + 1;\nEND_IF;",
            "5:3: WHILE at 5:3 has no END_WHILE; expected END_WHILE before 'END_IF' at 7:1",
        ),
        (
            "REPEAT\n  x := x + 1;",
            "4:1: REPEAT at 4:1 has no UNTIL ... END_REPEAT; expected UNTIL ... END_REPEAT "
            "before 'END_PROGRAM' at 6:1",
        ),
        (
            "CASE s OF\n  1: x := 2;",
            "4:1: CASE at 4:1 has no END_CASE; expected END_CASE before 'END_PROGRAM' at 6:1",
        ),
        (
            "IF a THEN x := 1; END_IF;\nIF a THEN (* END_IF *) x := 'END_IF';",
            "5:1: IF at 5:1 has no END_IF; expected END_IF before 'END_PROGRAM' at 6:1",
        ),
        (
            "FOR x := 1 TO 3 DO\n  IF a THEN s := 1; END_IF;",
            "4:1: FOR at 4:1 has no END_FOR; expected END_FOR before 'END_PROGRAM' at 6:1",
        ),
        (
            "(* a long comment *) IF a THEN\n  x := 1;",
            "4:22: IF at 4:22 has no END_IF; expected END_IF before 'END_PROGRAM' at 6:1",
        ),
        (
            "REPEAT\n  IF a THEN x := 1;\nUNTIL x > 3 END_REPEAT;",
            "5:3: IF at 5:3 has no END_IF; expected END_IF before 'UNTIL' at 6:1",
        ),
        (
            "IF a THEN\n  FOR x := 1 TO 3 DO s := 1;\nELSE\n  s := 2;\nEND_IF;",
            "5:3: FOR at 5:3 has no END_FOR; expected END_FOR before 'ELSE' at 6:1",
        ),
        (
            "IF a THEN\n  WHILE a DO s := 1;\nELSIF s > 1 THEN\n  s := 2;\nEND_IF;",
            "5:3: WHILE at 5:3 has no END_WHILE; expected END_WHILE before 'ELSIF' at 6:1",
        ),
        (
            "IF a THEN\n  CASE s OF\n    1: IF a THEN x := 1;\n    2: x := 2;\n"
            "  END_CASE;\nEND_IF;",
            "6:8: IF at 6:8 has no END_IF; expected END_IF before '2' at 7:5",
        ),
    ],
)
def test_a_statement_left_open_is_reported_where_it_begins(body, message):
    """An IF without END_IF in a CASE branch (the next label, or END_CASE, shows it), and a
    FOR, WHILE, REPEAT or CASE left open: the message names the open statement's place;
    an END_IF in a comment or a string closes nothing."""
    kind = "E" if "Idle:" in body else "INT"
    source = (
        f"TYPE E : (Idle, Run); END_TYPE\nPROGRAM t\nVAR s : {kind}; a : BOOL; x : INT; END_VAR\n"
    )
    assert refused(f"{source}{body}\nEND_PROGRAM\n") == f"iec.st:{message}"


@pytest.mark.parametrize(
    "body",
    [
        "IF a THEN x := 1 END_IF;",  # a missing ; before END_IF: not an open IF
        "IF a THEN x := ; END_IF;",
        "IF a THEN 2 := x; END_IF;",
        "IF a THEN x := 1; 2: x := 3; END_IF;",  # a label-like token outside a CASE
    ],
)
def test_other_errors_inside_an_if_keep_their_message(body):
    """An error inside a closed IF is not called an open IF."""
    message = refused(program("a : BOOL; x : INT;", body))
    assert "has no END_IF" not in message and message.startswith("iec.st:5:")


def test_an_open_if_in_a_twincat_pou_names_its_file_and_line(tmp_path):
    """In a .TcPOU the IF's place is its line and column in that file (after
    ``      <ST><![CDATA[``)."""
    (tmp_path / "main.TcPOU").write_text(
        _pou("main", "PROGRAM main\nVAR a : BOOL; x : INT; END_VAR\n", "IF a THEN\n  x := 1;\n")
    )
    with pytest.raises(plc.st.STError) as error:
        plc.st.load(tmp_path)
    path = tmp_path / "main.TcPOU"
    assert str(error.value) == (
        f"{path}:8:20: IF at 8:20 has no END_IF; expected END_IF before 'END_PROGRAM' at 9:1"
    )


TWO = """PROGRAM Main
VAR a : INT; END_VAR
a := 1;
END_PROGRAM

PROGRAM Test
VAR a : INT; END_VAR
a := 2;
END_PROGRAM
"""


def test_two_programs_without_a_task_are_one_message_saying_how_to_choose():
    """Two PROGRAMs and no CONFIGURATION: refused with the place of both and the ways to
    choose (the API's ``program=``, the CLI's ``--pou``, a TASK), instead of running the
    first."""
    assert refused(TWO, "two.st") == (
        "two.st:1:1: 2 PROGRAMs (Main at 1:1, Test at 6:1) and no TASK that runs one of them; "
        "choose one: plc.st.load(..., program='Main'), python -m scenes run ... --pou Main, or "
        "a CONFIGURATION whose TASK runs it (PROGRAM main WITH t : Main;)"
    )


def test_a_program_chosen_by_name_or_by_a_task_runs():
    """``program="Test"`` runs Test; a CONFIGURATION's TASK running Test does too."""
    prog = plc.st.from_source(TWO, filename="two.st", period=0.01, program="Test")
    prog()
    assert prog.a == 2
    config = TWO + (
        "CONFIGURATION c RESOURCE r ON PLC TASK t(INTERVAL := T#10ms); "
        "PROGRAM i WITH t : Test; END_RESOURCE END_CONFIGURATION\n"
    )
    assert run(config, filename="two.st").a == 2


def test_the_cli_chooses_the_program_with_pou(tmp_path, capsys):
    """``python -m scenes run single_axis --program two.st --pou Test`` runs Test to its
    ``done``; without ``--pou`` the message says how to choose (exit status 2)."""
    path = tmp_path / "two.st"
    path.write_text(
        TWO.replace("a := 2;", "a := 2;\ndone := TRUE;").replace(
            "PROGRAM Test\nVAR a : INT;", "PROGRAM Test\nVAR a : INT; done : BOOL;"
        )
    )
    assert cli.main(["run", "single_axis", "--program", str(path), "--pou", "Test"]) == 0
    capsys.readouterr()
    assert cli.main(["run", "single_axis", "--program", str(path), "--timeout", "0.1"]) == 2
    assert f"{path}:1:1: 2 PROGRAMs (Main at 1:1, Test at 6:1)" in capsys.readouterr().err


@pytest.mark.parametrize(
    "name",
    [
        "reference",
        "and_then",
        "or_else",
        "functionblock",
        "property",
        "union",
        "var_stat",
        "var_inst",
    ],
)
def test_twincat_words_that_iec_does_not_reserve_name_variables(name):
    """A variable may be named as TwinCAT's words that are no IEC keyword."""
    assert getattr(run(program(f"{name} : INT;", f"{name} := 3;")), name) == 3


def test_the_viewer_names_the_choice_when_a_file_has_two_programs(tmp_path):
    """The viewer's Program list shows the message for a .st file and a TwinCAT folder of two
    PROGRAMs (the folder's naming each .TcPOU), before the program is run."""
    import scenes
    from viewer.sim.programs import ProgramCatalog

    (tmp_path / "two.st").write_text(TWO)
    folder = tmp_path / "tc"
    folder.mkdir()
    for name, value in (("Main", 1), ("Test", 2)):
        (folder / f"{name}.TcPOU").write_text(
            _pou(name, f"PROGRAM {name}\nVAR a : INT; END_VAR\n", f"a := {value};\n")
        )
    catalog = ProgramCatalog([tmp_path])
    scene = scenes.load("single_axis", trace_every=0)
    error = catalog.translate(scene, tmp_path / "two.st")
    assert error.startswith(f"{tmp_path / 'two.st'}:1:1: 2 PROGRAMs (Main at 1:1, Test at 6:1)")
    error = catalog.translate(scene, folder)
    main, test = folder / "Main.TcPOU", folder / "Test.TcPOU"
    assert error.startswith(f"{main}:4:27: 2 PROGRAMs (Main at 4:27, Test at {test}:4:27)")
