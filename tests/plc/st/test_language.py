"""Structured Text as PLC engineers write it: the IEC 61131-3 constructs a program may use
(2nd edition unless marked), each run for what a user sees (the values, the messages)."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

import plc.st
from tests.helpers import ROOT
from tests.plc.st.iec import program, refused, run

DIGITS = "0123456789" * 10
"""A STRING of 100 characters (longer than STRING's default of 80)."""


def test_a_string_declared_with_brackets_holds_its_length():
    prog = run(
        program(
            "s : STRING[100]; c : STRING[3]; n : INT;",
            f"s := '{DIGITS}'; c := 'abcdef'; n := LEN(s);",
        )
    )
    assert (prog.s, prog.c, prog.n) == (DIGITS, "abc", 100)


def test_a_function_returns_the_string_length_it_declares():
    source = f"""
FUNCTION Echo : STRING(100)
VAR_INPUT s : STRING(100); END_VAR
Echo := s;
END_FUNCTION
{program("r : STRING(100); n : INT;", f"r := Echo('{DIGITS}'); n := LEN(r);")}"""
    assert run(source).n == 100


TYPES = """
TYPE MyInt : DINT := 7; END_TYPE
TYPE YourInt : MyInt; END_TYPE
TYPE A5 : ARRAY[1..5] OF INT := [5(42)]; END_TYPE
TYPE S25 : STRING(25) := 'abcdefg'; END_TYPE
TYPE Holder : STRUCT m : MyInt; v : ARRAY[1..2] OF MyInt; END_STRUCT; END_TYPE
"""


def test_a_derived_type_gives_its_variables_its_initial_value():
    prog = run(program("x : MyInt; y : YourInt; h : Holder; z : MyInt := 3;", "", TYPES))
    assert (prog.x, prog.y, prog.z) == (7, 7, 3)
    assert prog.h.m == 7 and prog.h.v == [7, 7]


def test_an_array_type_and_a_string_type_give_their_initial_values():
    prog = run(program("a : A5; s : S25;", "", TYPES))
    assert prog.a == [42] * 5 and prog.s == "abcdefg"


def test_nested_structure_initialisers_and_arrays_of_structures():
    source = """
TYPE P2 : STRUCT x : INT; y : INT; END_STRUCT; END_TYPE
TYPE Outer : STRUCT p : P2; k : INT; END_STRUCT; END_TYPE
TYPE Item : STRUCT v : REAL; n : INT; END_STRUCT; END_TYPE
""" + program(
        "o : Outer := (p := (x := 1, y := 2), k := 3);"
        "items : ARRAY[1..2] OF Item := [(v := 5.0, n := 3), (v := 1.5, n := 4)];",
        "",
    )
    prog = run(source)
    assert (prog.o.p.x, prog.o.p.y, prog.o.k) == (1, 2, 3)
    assert [(i.v, i.n) for i in prog.items] == [(5.0, 3), (1.5, 4)]


SEGMENTS = """
TYPE P3 : STRUCT x : LREAL; y : LREAL; z : LREAL; END_STRUCT; END_TYPE
TYPE P4 : STRUCT w : LREAL; x : LREAL; y : LREAL; z : LREAL; END_STRUCT; END_TYPE
TYPE Seg : STRUCT a : P3; n : INT; END_STRUCT; END_TYPE
"""
"""Points of three and four members, a segment of a point (the declarations on line 7)."""


def test_structure_initialisers_the_full_parser_may_read_two_ways():
    """In an array of structures (read by the full parser, whose grammar lets ``:=`` be an
    operator too): three elements, a nested structure and a nested one of one element each
    give each member its value, the others their default."""
    source = SEGMENTS + program(
        "pts : ARRAY[1..2] OF P3 := [(x := 1.0, y := 2.0, z := 3.0), (z := 4.0)];"
        "quads : ARRAY[1..2] OF P4 := [(w := 0.5, x := 1.0, y := 2.0, z := 3.0), (y := 1.5)];"
        "segs : ARRAY[1..2] OF Seg := [(a := (x := 7.0, y := 8.0), n := 9), (a := (z := 5.0))];"
        "s : Seg := (a := (x := 6.0));",
        "",
    )
    prog = run(source)
    assert [(p.x, p.y, p.z) for p in prog.pts] == [(1.0, 2.0, 3.0), (0.0, 0.0, 4.0)]
    quads = [(q.w, q.x, q.y, q.z) for q in prog.quads]
    assert quads == [(0.5, 1.0, 2.0, 3.0), (0.0, 0.0, 1.5, 0.0)]
    segs = [(g.a.x, g.a.y, g.a.z, g.n) for g in prog.segs]
    assert segs == [(7.0, 8.0, 0.0, 9), (0.0, 0.0, 5.0, 0)]
    assert (prog.s.a.x, prog.s.a.z, prog.s.n) == (6.0, 0.0, 0)


@pytest.mark.parametrize(
    "declaration",
    [
        "pts : ARRAY[1..2] OF P3 := [(x := 1.0, y := 2.0, q := 3.0), (z := 4.0)];",
        "segs : ARRAY[1..2] OF Seg := [(n := 1), (a := (q := 5.0))];",
        "segs : ARRAY[1..2] OF Seg := [(n := 1, a := (x := 1.0, q := 5.0)), (n := 2)];",
    ],
)
def test_a_member_a_structure_lacks_is_named_where_it_is_written(declaration):
    """A member the structure has not, third of three, alone in a nested structure or second
    in one: refused at its own line and column."""
    column = declaration.index("q :=") + 1
    assert refused(SEGMENTS + program(declaration, "")) == (
        f"iec.st:7:{column}: P3 has no field 'q'; expected a field"
    )


def test_two_types_in_one_type_block():
    source = """
TYPE
  Color : (Red, Green, Blue);
  Pair : STRUCT a : INT; b : INT; END_STRUCT;
END_TYPE
""" + program("c : Color := Blue; p : Pair := (a := 1, b := 2); n : INT;", "n := p.a + p.b;")
    prog = run(source)
    assert prog.c == 2 and prog.n == 3


def test_an_array_constant_in_var_global_constant():
    globals_ = "VAR_GLOBAL CONSTANT\n  TBL : ARRAY[1..3] OF INT := [10, 20, 30];\nEND_VAR\n"
    assert run(program("w : INT;", "w := TBL[3];", globals_)).w == 30
    message = refused(program("w : INT;", "TBL[2] := 5;", globals_))
    assert message.startswith("iec.st:9:1: TBL is a CONSTANT")


def test_an_error_in_var_global_names_its_line_and_column():
    source = """TYPE E_Seq : (Idle, Run); END_TYPE
VAR_GLOBAL
  g : E_Seq := E_Seq.Idel;
END_VAR
""" + program("y : INT;", "")
    assert refused(source).startswith("iec.st:3:16: E_Seq has no value 'Idel' (did you mean Idle?)")


FUNCTIONS = """
FUNCTION Scale : INT
VAR_INPUT k : INT; END_VAR
VAR_IN_OUT x : INT; END_VAR
VAR_OUTPUT old : INT; END_VAR
VAR_TEMP t : INT; END_VAR
t := x;
x := x * k;
old := t;
Scale := t + 1;
END_FUNCTION
FUNCTION Bump : BOOL
VAR_IN_OUT n : INT; END_VAR
n := n + 1;
Bump := TRUE;
END_FUNCTION
"""


def test_a_function_with_in_out_output_and_temp_variables():
    prog = run(
        program(
            "y : INT := 5; o : INT; r : INT;", "r := Scale(k := 3, x := y, old => o);", FUNCTIONS
        )
    )
    assert (prog.y, prog.o, prog.r) == (15, 5, 6)


def test_a_function_called_without_names_and_for_its_effect():
    body = "ok := Bump(y); Bump(n := y); r := Scale(2, y, o);"
    prog = run(program("y : INT := 1; o : INT; r : INT; ok : BOOL;", body, FUNCTIONS))
    assert (prog.y, prog.o, prog.r, prog.ok) == (6, 3, 4, True)


def test_standard_functions_called_by_their_names():
    body = """a := ADD(1, 2, 3); s := SUB(10, 3); m := MUL(2, 3, 4); d := DIV(7, 2);
gt := GT(3, 2, 1); eq := EQ(2, 2); md := MOD(7, 3); x := XOR(TRUE, FALSE);
an := AND(TRUE, TRUE, FALSE);"""
    decls = "a, s, m, d, md : INT; gt, eq, x, an : BOOL;"
    prog = run(program(decls, body))
    assert (prog.a, prog.s, prog.m, prog.d, prog.md) == (6, 7, 24, 3, 1)
    assert (prog.gt, prog.eq, prog.x, prog.an) == (True, True, True, False)


def test_typed_standard_functions_and_blocks():
    body = """i := TRUNC_INT(-2.7); t := ADD_TIME(T#1s, T#2s); u := SUB_TIME(t, T#500ms);
k(CU := TRUE, PV := 100000); v := k.CV; w := ADD_INT(32767, 1);"""
    decls = "i : INT; t, u : TIME; k : CTU_DINT; v : DINT; w : INT;"
    prog = run(program(decls, body))
    assert (prog.i, prog.t, prog.u, prog.v, prog.w) == (-2, 3000, 2500, 1, -32768)
    assert not prog.k.Q  # CV 1 < PV 100000, a value no INT holds


def test_ampersand_and_typed_string_literals():
    prog = run(
        program("a : BOOL := TRUE; b : BOOL; s : STRING;", "b := a & NOT FALSE; s := STRING#'x';")
    )
    assert prog.b is True and prog.s == "x"


ENUMS = """
TYPE Color : (Red, Green, Blue); END_TYPE
TYPE E_Seq : (Idle, HomeZ, Run); END_TYPE
"""


def test_typed_enumeration_literals_and_qualified_case_labels():
    body = """c := Color#Green;
CASE step OF
  E_Seq.Idle: k := 1; step := E_Seq#Run;
  E_Seq.Run: k := 2;
END_CASE"""
    prog = run(program("c : Color; step : E_Seq; k : INT;", body, ENUMS), scans=2)
    assert (prog.c, prog.k, prog.step) == (1, 2, "Run")


def test_a_misspelled_case_label_names_its_line_and_column():
    body = "CASE s OF\n  E_Seq.Idle: k := 1;\n  E_Seq.Rnu: k := 2;\nEND_CASE"
    message = refused(program("s : E_Seq; k : INT;", body, ENUMS))
    assert message.startswith("iec.st:11:3: E_Seq has no value 'Rnu' (did you mean Run?)")


def test_an_inline_enumeration():
    prog = run(
        program("c : (Stopped, Moving, Done) := Moving; d : BOOL;", "d := c = Moving; c := Done;")
    )
    assert prog.d is True and prog.c == 2


def test_a_step_named_like_a_block_instance_is_the_step_where_a_step_is_expected():
    body = """homeZ(IN := TRUE, PT := T#1s);
IF step = Idle THEN step := HomeZ; END_IF
CASE step OF HomeZ: k := 1; END_CASE
q := homeZ.Q;"""
    prog = run(program("step : E_Seq; homeZ : TON; k : INT; q : BOOL;", body, ENUMS))
    assert (prog.step, prog.k, prog.q) == ("HomeZ", 1, False)


def test_a_misspelled_enumeration_value_suggests_the_right_one():
    message = refused(program("s : E_Seq;", "s := HomeX;", ENUMS))
    assert "unknown variable 'HomeX' (did you mean HomeZ?)" in message


def test_mod_zero_is_zero_and_the_program_runs_on():
    prog = run(
        program("a : INT := 7; z : INT; m : INT := 5; n : INT;", "m := a MOD z; n := n + 1;"),
        scans=2,
    )
    assert (prog.m, prog.n) == (0, 2)


def test_a_real_prints_at_real_precision():
    prog = run(
        program(
            "s : STRING; t : STRING; r : REAL := 0.1;",
            "s := REAL_TO_STRING(REAL#0.1); t := REAL_TO_STRING(r);",
        )
    )
    assert (prog.s, prog.t) == ("0.1", "0.1")


def test_bit_access_reads_and_writes_a_bit():
    body = "b := w.3; w.0 := b; w.%X15 := TRUE; lo := d.%B0; d.%B3 := 16#AB; d.%W1 := 16#0102;"
    prog = run(program("w : WORD := 16#0008; b : BOOL; d : DWORD := 16#12345678; lo : BYTE;", body))
    assert (prog.b, prog.w, prog.lo, prog.d) == (True, 0x8009, 0x78, 0x01025678)


def test_bit_access_on_a_real_is_an_error_with_its_position():
    assert refused(program("r : REAL; b : BOOL;", "b := r.3;")).startswith(
        "iec.st:5:7: REAL has no bit 3"
    )


@pytest.mark.once
def test_bit_access_runs_through_the_command_line_without_a_traceback(tmp_path):
    path = tmp_path / "bits.st"
    path.write_text(program("w : WORD := 16#0008; b : BOOL;", "b := w.3; w.0 := b;"))
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    command = [sys.executable, "-m", "scenes", "run", "single_axis", "--program", str(path)]
    done = subprocess.run(
        [*command, "--timeout", "0.05"], capture_output=True, text=True, env=env, timeout=600
    )
    assert done.returncode == 0 and "Traceback" not in done.stdout + done.stderr, done.stderr


def test_references_ref_to_ref_and_dereference():
    body = """r := REF(y); r^ := 5; z := r^ + 1; was := q = NULL; q := r; same := q = r;
pr := REF(p); pr^.b := 9; ra := REF(a[2]); ra^ := 4;"""
    decls = """y, z : INT; r, q : REF_TO INT; was, same : BOOL; p : Pair; pr : REF_TO Pair;
a : ARRAY[1..3] OF INT; ra : REF_TO INT;"""
    prog = run(program(decls, body, "TYPE Pair : STRUCT a : INT; b : INT; END_STRUCT; END_TYPE"))
    assert (prog.y, prog.z, prog.was, prog.same, prog.p.b, prog.a) == (
        5,
        6,
        True,
        True,
        9,
        [0, 4, 0],
    )


def test_dereferencing_null_stops_the_program_naming_its_line():
    prog = plc.st.from_source(program("r : REF_TO INT; y : INT;", "y := r^;"), filename="iec.st")
    prog()
    assert prog.fault == "iec.st:5: dereference of a NULL reference; the program stopped"


def test_case_labels_that_are_constant_expressions():
    body = "CASE a OF N + 1: k := 1; 2 * N + 1 .. 3 * N: k := 2; END_CASE"
    before = "VAR_GLOBAL CONSTANT N : INT := 4; END_VAR"
    assert run(program("a : INT := 5; k : INT;", body, before)).k == 1
    assert run(program("a : INT := 10; k : INT;", body, before)).k == 2


def test_date_time_of_day_date_and_time_and_their_arithmetic():
    body = """t2 := t1 + T#1h30m; span := DT#2024-03-02-00:00:00 - dt1; day := DT_TO_DATE(dt1);
tod2 := DT_TO_TOD(dt1); days := D#2024-03-01 - D#2024-02-01; late := t1 > TOD#20:00;
text := DT_TO_STRING(dt1 + T#30s);"""
    decls = """t1 : TOD := TOD#23:00:00; t2 : TIME_OF_DAY; dt1 : DT := DT#2024-03-01-12:30:00;
span, days : TIME; day : DATE; tod2 : TOD; late : BOOL; text : STRING;"""
    prog = run(program(decls, body))
    assert prog.t2 == 30 * 60_000  # 00:30, the next day
    assert prog.span == 11.5 * 3_600_000 and prog.days == 29 * 86_400_000
    assert prog.late is True and prog.tod2 == 12.5 * 3_600_000
    assert prog.text == "DT#2024-03-01-12:30:30"
    assert (
        run(program("d : DATE := D#2024-03-01; s : STRING;", "s := DATE_TO_STRING(d);")).s
        == "D#2024-03-01"
    )


def test_a_variable_named_reference():
    assert run(program("reference : INT; x : INT;", "reference := 3; x := reference * 2;")).x == 6


def test_the_watch_table_shows_dates_and_times_of_day_as_literals():
    from plc.st.runtime.watch import WatchedProgram

    prog = run(program("d : DATE := D#2024-03-01; t : TOD := TOD#12:00:01.5; z : DT;", ""))
    rows = {row.name: row.value for row in WatchedProgram(prog).rows()}
    assert rows == {"d": "D#2024-03-01", "t": "TOD#12:00:01.5", "z": "DT#0001-01-01-00:00:00"}
