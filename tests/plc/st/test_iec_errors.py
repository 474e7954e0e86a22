"""IEC 61131-3 conformance, errors: what the standard calls an error is refused with one message
naming ``file:line:column`` (2nd edition Annex E, 3rd edition Annex E), and an error that only
shows at run time stops the program naming ``file:line``. Each case names the clause whose rule
it breaks."""

from __future__ import annotations

import pytest

from tests.plc.st.iec import fault, program, refused

TYPES = "TYPE Color : (Red, Green); E_Seq : (Idle, Run); P : STRUCT a : INT; END_STRUCT; END_TYPE"
"""Types of the cases that use them (the PROGRAM then starts on line 2: its declarations are on
line 4, its statements on line 6)."""

FUNCTIONS = """FUNCTION F : INT
VAR_INPUT a : INT; END_VAR
VAR_IN_OUT io : INT; END_VAR
VAR_OUTPUT o : INT; END_VAR
F := a; io := a; o := a;
END_FUNCTION"""
"""A function with an input, an in-out and an output (the PROGRAM's statements on line 11)."""


def error(clause: str, decls: str, body: str, where: str, text: str, before: str = "") -> object:
    """A case: the program is refused at ``where`` (``line:column``) with ``text``."""
    return pytest.param(program(decls, body, before), f"iec.st:{where}: ", text, id=clause)


COMPILE = [
    # lexical elements and literals
    error("2.1.2 (6.1.2) two underscores in a row", "a__b : INT;", "", "3:1", "two underscores"),
    error("2.1.3 (6.1.3) a keyword as a name", "IF : INT;", "", "3:1",
        "IF is a reserved keyword of IEC 61131-3 and cannot name a variable"),
    error("2.1.3 (6.1.3) END_IF missing", "x : INT;", "IF x > 1 THEN x := 1;", "5:1",
        "IF at 5:1 has no END_IF; expected END_IF before 'END_PROGRAM' at 6:1"),
    error("3.3.2 (7.3.3.1) a statement without ;", "x : INT;", "x := 1\nx := 2;", "5:7",
        "missing ';' at the end of line 5"),
    error("2.2.1 (6.3.2) a digit outside base 16", "x : INT;", "x := 16#FG;", "5:10", "unexpected"),
    error("2.2.1 (6.3.2) a digit outside base 2", "x : INT;", "x := 2#102;", "5:10", "unexpected"),
    error("2.2.3.2 (6.3.5) a day the month lacks", "d : DATE;", "d := D#2023-02-29;", "5:6",
        "the date 2023-02-29"),
    error("2.2.3.2 (6.3.5) an hour past 23", "t : TOD;", "t := TOD#24:00:00;", "5:6",
        "the time of day 24:00:00"),
    # declarations
    error("2.4.3 (6.5.1) a name declared twice", "x : INT; x : BOOL;", "", "3:10",
        "'x' is declared twice"),
    error("2.4.3 (6.5.1) an undeclared variable", "x : INT;", "y := 1;", "5:1",
        "unknown variable 'y'"),
    error("2.3.3 (6.4.4) an unknown type", "x : Colour;", "", "3:5", "unknown type 'Colour'"),
    error("2.3.3.1 (6.4.4.5) array bounds reversed", "a : ARRAY[3..1] OF INT;", "", "3:11",
        "bounds 3..1"),
    error("2.3.3.1 (6.4.4.4) subrange bounds reversed", "s : INT (5..1);", "", "3:10",
        "the subrange 5..1"),
    error("2.3.3.1 (6.4.4.4) subrange of a REAL", "s : REAL (0..1);", "", "3:12", "unexpected"),
    error("2.3.3.1 (6.4.4.4) subrange beyond its type", "s : SINT (0..300);", "", "3:11",
        "the subrange 0..300"),
    error("2.3.1 (6.4.2) a STRING of length 0", "s : STRING(0);", "", "3:11",
        "a STRING of length 0"),
    error("2.4.3.2 (6.5.1) an initial value of the wrong type", "x : INT := 'a';", "", "3:12",
        "a STRING value where INT is expected"),
    error("2.4.3.2 (6.5.1) an initial value outside the subrange", "s : INT (1..10) := 11;", "",
        "3:20", "11 outside INT (1..10)"),
    error("2.4.3.2 (6.5.1) too many array initial values", "a : ARRAY[1..2] OF INT := [1, 2, 3];",
        "", "3:27", "3 initial values"),
    error("2.4.3.2 (6.5.1) an unknown field initialised", "p : P := (b := 1);", "", "4:11",
        "P has no field 'b'", TYPES),
    error("2.4.3.2 (6.5.1) an enumeration value of another type", "c : Color := Run;", "", "4:14",
        "an E_Seq value where Color is expected", TYPES),
    error("2.4.3 (6.5.4) a CONSTANT without a constant value", "y : INT;", "y := 1;", "2:32",
        "a value that is not constant",
        "VAR_GLOBAL g : INT; END_VAR\nVAR_GLOBAL CONSTANT K : INT := g; END_VAR"),
    error("2.4.3 (6.5.4) a CONSTANT assigned", "y : INT;", "K := 2;", "6:1", "K is a CONSTANT",
        "VAR_GLOBAL CONSTANT K : INT := 1; END_VAR"),
    error("2.4.3 (6.5.4) a CONSTANT array's element assigned", "y : INT;", "T[1] := 2;", "6:1",
        "T is a CONSTANT", "VAR_GLOBAL CONSTANT T : ARRAY[1..2] OF INT := [1, 2]; END_VAR"),
    # expressions and types
    error("2.5.1.4 (6.6.1.6) an INT into a BOOL", "b : BOOL; i : INT;", "b := i;", "5:1",
        "an INT value where BOOL is expected"),
    error("2.5.1.4 (6.6.1.6) a REAL into an INT", "i : INT; r : REAL;", "i := r;", "5:1",
        "a REAL value where INT is expected"),
    error("2.5.1.4 (6.6.1.6) a BOOL into an INT", "i : INT;", "i := TRUE;", "5:1",
        "a BOOL value where INT is expected"),
    error("2.5.1.4 (6.6.1.6) a TIME into a DINT", "i : DINT;", "i := T#1s;", "5:1",
        "a TIME value where DINT is expected"),
    error("2.5.1.4 (6.6.1.6) a STRING into an INT", "i : INT;", "i := '1';", "5:1",
        "a STRING value where INT is expected"),
    error("3.3.1 (7.3.2) STRING + STRING", "s : STRING;", "s := 'a' + 'b';", "5:6",
        "STRING + STRING"),
    error("3.3.1 (7.3.2) INT + BOOL", "i : INT;", "i := i + TRUE;", "5:6", "INT + BOOL"),
    error("3.3.1 (7.3.2) MOD of reals", "r : REAL;", "r := r MOD 2.0;", "5:6", "integer operands"),
    error("3.3.1 (7.3.2) NOT of a REAL", "r : REAL; b : BOOL;", "b := NOT r;", "5:6",
        "NOT on REAL"),
    error("3.3.1 (7.3.2) - of a BOOL", "b : BOOL;", "b := -b;", "5:6", "- on BOOL"),
    error("3.3.1 (7.3.2) AND of an INT and a BOOL", "b : BOOL; i : INT;", "b := i AND b;", "5:6",
        "INT AND BOOL"),
    error("3.3.1 (7.3.2) two enumerations compared", "c : Color; s : E_Seq; b : BOOL;",
        "b := c = s;", "6:6", "Color = E_Seq", TYPES),
    error("3.3.1 (7.3.2) structures compared", "p, q : P; b : BOOL;", "b := p = q;", "6:6",
        "P = P", TYPES),
    error("3.3.1 (7.3.2) DATE + DATE", "d : DATE;", "d := d + d;", "5:6", "DATE + DATE"),
    error("3.3.1 (7.3.2) a constant division by zero", "i : INT;", "i := 1 / 0;", "5:6",
        "integer division by zero"),
    error("2.4.1.2 (6.4.4.5) a REAL index", "a : ARRAY[1..2] OF INT; r : REAL;", "a[r] := 1;",
        "5:3", "an index of type REAL"),
    error("2.4.1.2 (6.4.4.5) a constant index outside the bounds", "a : ARRAY[1..2] OF INT;",
        "a[3] := 1;", "5:3", "index 3 outside 1..2"),
    error("2.4.1.2 (6.4.4.5) too many indices", "a : ARRAY[1..2] OF INT;", "a[1, 1] := 1;", "5:2",
        "2 indices"),
    error("2.4.1.2 (6.4.4.5) an index on a non-array", "i : INT;", "i[1] := 1;", "5:2",
        "INT is not an ARRAY"),
    error("2.4.1.2 (6.4.4.6) an unknown field", "p : P;", "p.b := 1;", "6:2", "P has no field 'b'",
        TYPES),
    error("2.4.1.2 (6.4.4.6) a field of an INT", "i : INT;", "i.a := 1;", "5:2",
        "INT has no fields"),
    error("3rd ed. 6.6.1.3 a bit beyond the width", "w : WORD; b : BOOL;", "b := w.16;", "5:7",
        "WORD has no bit 16"),
    error("3rd ed. 6.6.1.3 a byte beyond the width", "w : WORD; b : BYTE;", "b := w.%B2;", "5:7",
        "WORD has no part %B 2"),
    error("3rd ed. 6.6.1.3 a bit of a BOOL", "x : BOOL; b : BOOL;", "b := x.0;", "5:7",
        "BOOL has no bit 0"),
    error("3rd ed. 6.4.4.10 a dereference of no reference", "i : INT;", "i := i^;", "5:6",
        "dereferences an INT"),
    error("3rd ed. 6.4.4.10 a reference of another type", "r : REF_TO INT; x : REAL;",
        "r := REF(x);", "5:1", "a REF_TO REAL value where REF_TO INT is expected"),
    error("3rd ed. 6.4.4.10 REF of a constant", "r : REF_TO INT;", "r := REF(1);", "5:10",
        "REF of 1"),
    error("3rd ed. 6.4.4.10 references ordered", "r, q : REF_TO INT; b : BOOL;", "b := r < q;",
        "5:6", "= or <> of references alike"),
    # statements
    error("3.3.2.3 (7.3.3.4.1) an IF on an INT", "i : INT;", "IF i THEN i := 1; END_IF", "5:4",
        "a condition of type INT"),
    error("3.3.2.4 (7.3.3.5.3) a WHILE on an INT", "i : INT;", "WHILE i DO i := 1; END_WHILE",
        "5:7", "a condition of type INT"),
    error("3.3.2.4 (7.3.3.5.4) an UNTIL on a REAL", "r : REAL;",
        "REPEAT r := 1.0; UNTIL r END_REPEAT", "5:24", "a condition of type REAL"),
    error("3.3.2.3 (7.3.3.4.2) a CASE on a REAL", "r : REAL;", "CASE r OF 1: r := 2.0; END_CASE",
        "5:6", "CASE on REAL"),
    error("3.3.2.3 (7.3.3.4.2) a CASE label of another type", "i : INT;",
        "CASE i OF 'a': i := 2; END_CASE", "5:11", "a STRING label"),
    error("3.3.2.3 (7.3.3.4.2) an enumeration label on an INT", "i : INT;",
        "CASE i OF Red: i := 2; END_CASE", "6:11", "a Color label", TYPES),
    error("3.3.2.3 (7.3.3.4.2) a CASE label that is a variable", "i, j : INT;",
        "CASE i OF j: i := 2; END_CASE", "5:11", "not constant"),
    error("3.3.2.4 (7.3.3.5.2) a FOR over a REAL", "r : REAL;", "FOR r := 1.0 TO 2.0 DO ; END_FOR",
        "5:5", "a FOR variable of type REAL"),
    error("3.3.2.4 (7.3.3.5.6) EXIT outside a loop", "i : INT;", "EXIT;", "5:1",
        "EXIT outside a loop"),
    error("3rd ed. 7.3.3.5.5 CONTINUE outside a loop", "i : INT;", "CONTINUE;", "5:1",
        "CONTINUE outside a loop"),
    # functions and function blocks
    error("2.5.1.1 (6.6.2.3) an unknown function", "i : INT;", "i := FOO(1);", "5:6",
        "unknown function 'FOO'"),
    error("2.5.1.5.4 (6.6.2.5.11) LIMIT with two inputs", "i : INT;", "i := LIMIT(1, 2);", "5:6",
        "a parameter is missing"),
    error("2.5.1.5.2 (6.6.2.5.8) SUB with three inputs", "i : INT;", "i := SUB(1, 2, 3);", "5:6",
        "SUB with 3 argument(s); expected 2"),
    error("2.5.1.1 (6.6.2.3) an unknown parameter", "i, v : INT;", "i := F(b := 1, io := v);",
        "11:8", "F has no parameter 'B'", FUNCTIONS),
    error("2.5.1.1 (6.6.2.3) too many arguments", "i, v, w : INT;", "i := F(1, v, w, 4);", "11:17",
        "too many arguments to F", FUNCTIONS),
    error("3rd ed. 6.6.2.3 a VAR_IN_OUT not given", "i : INT;", "i := F(a := 1);", "11:6",
        "F's VAR_IN_OUT io is not given", FUNCTIONS),
    error("3rd ed. 6.6.2.3 a VAR_IN_OUT given an expression", "i : INT;",
        "i := F(a := 1, io := i + 1);", "11:16", "cannot take F's io", FUNCTIONS),
    error("3rd ed. 6.6.2.3 an output given with :=", "i, v : INT;",
        "i := F(a := 1, io := v, o := i);", "11:25", "O is an output of F", FUNCTIONS),
    error("3rd ed. 6.6.2.3 an input given with =>", "i, v : INT;", "i := F(a => i, io := v);",
        "11:8", "A is not an output of F", FUNCTIONS),
    error("2.5.2.1 (6.6.3.4) a call of an INT", "i : INT;", "i();", "5:1", "not a block instance"),
    error("2.5.2.1 (6.6.3.4) a call of a block type", "t : TON;", "TON(IN := TRUE);", "5:1",
        "TON is a block type"),
    error("2.5.2.1 (6.6.3.4) an unknown input", "t : TON;", "t(PV := T#1s);", "5:3",
        "TON has no input or output 'PV'"),
    error("2.5.2.1 (6.6.3.4) an output given with :=", "t : TON; q : BOOL;", "t(Q := q);", "5:3",
        "Q is an output"),
    error("2.5.2.1 (6.6.3.4) an output written from outside", "t : TON;", "t.Q := TRUE;", "5:1",
        "t.Q is an output of TON"),
    error("2.5.2.1 (6.6.3.4) a block in an expression", "t : TON; b : BOOL;",
        "b := TON(IN := TRUE);", "5:6", "TON is a function block"),
]  # fmt: skip


@pytest.mark.parametrize(("source", "where", "text"), COMPILE)
def test_an_iec_error_is_refused_at_its_place(source, where, text):
    message = refused(source)
    assert message.startswith(where) and text in message, message


RUNTIME = [
    pytest.param("i, z : INT;", "i := 1 / z;", "5: integer division by zero",
        id="2.5.1.5.2 (Annex E) division by zero"),
    pytest.param("r, z : REAL;", "r := 1.0 / z;", "5: division by zero",
        id="2.5.1.5.2 (Annex E) real division by zero"),
    pytest.param("a : ARRAY[1..2] OF INT; i : INT := 3;", "a[i] := 1;",
        "5: array index 3 outside 1..2", id="2.4.1.2 (Annex E) an index out of range"),
    pytest.param("s : INT (1..10) := 10;", "s := s + 1;", "5: 11 outside the subrange 1..10",
        id="2.3.3.1 (Annex E) a value outside its subrange"),
    pytest.param("r : REF_TO INT; i : INT;", "i := r^;", "5: dereference of a NULL reference",
        id="3rd ed. 6.4.4.10.3 a NULL dereference"),
    pytest.param("i : INT; k : INT := 3;", "i := MUX(k, 1, 2);", "5: MUX selector 3 outside 0..1",
        id="2.5.1.5.4 (Annex E) MUX beyond its inputs"),
]  # fmt: skip


@pytest.mark.parametrize(("decls", "body", "message"), RUNTIME)
def test_an_iec_error_at_run_time_stops_the_program_at_its_line(decls, body, message):
    assert fault(program(decls, body)) == f"iec.st:{message}; the program stopped"


def test_a_vendor_pointer_is_refused_naming_ref_to():
    """3rd ed. 6.4.4.10: IEC's references are REF_TO; TwinCAT's POINTER TO is refused."""
    message = refused(program("p : POINTER TO INT;", ""))
    assert message.startswith("iec.st:3:5: POINTER TO (a vendor's pointer)") and "REF_TO" in message
