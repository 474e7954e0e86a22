"""IEC 61131-3 conformance of the ST translation: one snippet per case and the value IEC (and
CODESYS/TwinCAT where IEC leaves it open, see docs/st.md) gives."""

import math
import re

import pytest

import plc.st

REAL_0_1 = 0.10000000149011612  # 0.1 as a 32-bit REAL
_USES_LIBRARY = re.compile(r"\b(E_C|ST_P|F_Add|F_Fact|FB_Count|g_Count|N|Red|Green|Blue)\b")


def run(decls: str, body: str, scans: int = 1, extra: str = "", period: float = 0.01):
    if not _USES_LIBRARY.search(decls + body):
        extra = ""  # parsing is the slow part: only the cases that need it get the library
    source = f"{extra}\nPROGRAM t\nVAR\n{decls};\nEND_VAR\n{body}\nEND_PROGRAM\n"
    prog = plc.st.from_source(source, filename="case.st", period=period)
    for _ in range(scans):
        prog()
    assert not prog.error, prog.error
    return prog


CASES = [
    # integers wrap at their width
    ("x : INT", "x := 32767; x := x + 1;", "x", -32768),
    ("x : INT", "x := -32768; x := x - 1;", "x", 32767),
    ("x : SINT", "x := 127; x := x + 1;", "x", -128),
    ("x : USINT", "x := 255; x := x + 1;", "x", 0),
    ("x : UINT", "x := 0; x := x - 1;", "x", 65535),
    ("x : DINT", "x := 2147483647; x := x + 1;", "x", -2147483648),
    ("x : UDINT", "x := 0; x := x - 1;", "x", 4294967295),
    ("x : LINT", "x := 9223372036854775807; x := x + 1;", "x", -(2**63)),
    ("x : ULINT", "x := 0; x := x - 1;", "x", 2**64 - 1),
    # a mixed operation takes the wider type: DINT + LINT is LINT and does not wrap at 32 bits
    ("x : LINT; a : DINT := 2147483647; b : LINT := 1", "x := a + b;", "x", 2**31),
    ("x : LINT; a : DINT := 2147483647; b : LINT := 1", "x := b + a;", "x", 2**31),
    ("x : LINT", "x := 2147483647 + LINT#1;", "x", 2**31),
    ("x : LINT; a : DINT := -2147483648; b : LINT := 2", "x := a * b;", "x", -(2**32)),
    ("x : BYTE", "x := 16#FF; x := x + 1;", "x", 0),
    ("x : WORD", "x := 16#FFFF; x := x + 2;", "x", 1),
    ("x : INT", "x := 300 * 300;", "x", 90000 - 65536),
    ("x : SINT", "x := 200;", "x", -56),
    ("x : INT; y : DINT", "y := 70000; x := y;", "x", 70000 - 65536),
    ("x : DINT; y : INT", "y := -5; x := y;", "x", -5),
    ("x : UINT; y : INT", "y := -1; x := y;", "x", 65535),
    ("x : INT", "x := INT#16#7FFF;", "x", 32767),
    ("x : INT", "x := 2#1010_1010;", "x", 170),
    ("x : INT", "x := 8#17;", "x", 15),
    ("x : DINT", "x := 1_000_000;", "x", 1000000),
    # integer division truncates toward zero, MOD has the sign of the dividend
    ("x : INT", "x := 7 / 2;", "x", 3),
    ("x : INT; a : INT := -7", "x := a / 2;", "x", -3),
    ("x : INT; a : INT := 7; b : INT := -2", "x := a / b;", "x", -3),
    ("x : INT; a : INT := -7; b : INT := -2", "x := a / b;", "x", 3),
    ("x : INT; a : INT := 7", "x := a MOD 3;", "x", 1),
    ("x : INT; a : INT := -7", "x := a MOD 3;", "x", -1),
    ("x : INT; a : INT := 7", "x := a MOD -3;", "x", 1),
    ("x : INT; a : INT := -7", "x := a MOD -3;", "x", -1),
    ("x : DINT; a : DINT := -1", "x := a / 3;", "x", 0),
    ("x : INT", "x := 2 + 3 * 4;", "x", 14),
    ("x : INT", "x := (2 + 3) * 4;", "x", 20),
    ("x : INT", "x := 10 - 4 - 3;", "x", 3),
    ("x : INT", "x := 100 / 10 / 5;", "x", 2),
    ("x : INT", "x := -2 * 3;", "x", -6),
    ("x : INT; a : INT := 5", "x := -a + 2;", "x", -3),
    ("x : INT", "x := 2 + 7 MOD 4 * 2;", "x", 8),
    # exponent: REAL/LREAL result, unary minus binds tighter (IEC ed. 3)
    ("x : LREAL", "x := 2 ** 10;", "x", 1024.0),
    ("x : LREAL", "x := 2 ** 3 ** 2;", "x", 64.0),
    ("x : LREAL; a : LREAL := 2.0", "x := -a ** 2;", "x", 4.0),
    ("x : LREAL", "x := 2.0 ** -1;", "x", 0.5),
    ("x : LREAL; a : LREAL := -8.0", "x := a ** 0.5;", "x", math.nan),
    ("x : LREAL", "x := EXPT(3.0, 2);", "x", 9.0),
    ("x : LREAL", "x := 2 * 3 ** 2;", "x", 18.0),
    # REAL is 32-bit, LREAL 64-bit
    ("x : REAL", "x := 0.1;", "x", REAL_0_1),
    ("x : LREAL", "x := 0.1;", "x", 0.1),
    ("x : REAL; y : LREAL", "x := 0.1; y := x;", "y", REAL_0_1),
    ("x : REAL", "x := 16777216.0; x := x + 1.0;", "x", 16777216.0),
    ("x : LREAL", "x := 16777216.0; x := x + 1.0;", "x", 16777217.0),
    ("x : REAL", "x := 1.0 / 3.0;", "x", 0.3333333432674408),
    ("x : REAL", "x := 1.0E38; x := x * 10.0;", "x", math.inf),
    ("x : REAL; i : INT := 3", "x := i;", "x", 3.0),
    ("x : REAL; i : INT := 7", "x := i / 2;", "x", 3.0),
    ("x : REAL; i : INT := 7", "x := INT_TO_REAL(i) / 2;", "x", 3.5),
    ("x : LREAL", "x := 1.5E3;", "x", 1500.0),
    ("x : LREAL", "x := 7.0 / 2;", "x", 3.5),
    ("x : LREAL", "x := -7.0 / 2.0;", "x", -3.5),
    # conversions: reals round to nearest, halves to even (IEC 60559)
    ("x : INT", "x := REAL_TO_INT(1.5);", "x", 2),
    ("x : INT", "x := REAL_TO_INT(2.5);", "x", 2),
    ("x : INT", "x := REAL_TO_INT(-1.5);", "x", -2),
    ("x : INT", "x := REAL_TO_INT(-2.5);", "x", -2),
    ("x : INT", "x := REAL_TO_INT(1.4);", "x", 1),
    ("x : INT", "x := REAL_TO_INT(-1.6);", "x", -2),
    ("x : DINT", "x := LREAL_TO_DINT(3.5);", "x", 4),
    ("x : INT", "x := REAL_TO_INT(40000.0);", "x", 40000 - 65536),
    ("x : DINT", "x := TRUNC(2.9);", "x", 2),
    ("x : DINT", "x := TRUNC(-2.9);", "x", -2),
    ("x : INT", "x := DINT_TO_INT(70000);", "x", 4464),
    ("x : BYTE", "x := INT_TO_BYTE(-1);", "x", 255),
    ("x : INT", "x := BOOL_TO_INT(TRUE);", "x", 1),
    ("x : BOOL", "x := INT_TO_BOOL(5);", "x", True),
    ("x : BOOL", "x := INT_TO_BOOL(0);", "x", False),
    ("x : DINT", "x := TIME_TO_DINT(T#1s);", "x", 1000),
    ("x : TIME", "x := DINT_TO_TIME(2500);", "x", 2500),
    ("x : TIME", "x := LREAL_TO_TIME(2.7);", "x", 3),
    ("x : TIME; r : LREAL := 2.7", "x := LREAL_TO_TIME(r);", "x", 3),
    ("x : TIME; r : REAL := -2.7", "x := REAL_TO_TIME(r);", "x", -3),
    ("x : LREAL", "x := DINT_TO_LREAL(7);", "x", 7.0),
    ("x : STRING", "x := INT_TO_STRING(-42);", "x", "-42"),
    ("x : STRING", "x := BOOL_TO_STRING(TRUE);", "x", "TRUE"),
    ("x : INT", "x := STRING_TO_INT('123');", "x", 123),
    ("x : LREAL", "x := STRING_TO_LREAL('2.5');", "x", 2.5),
    ("x : UINT", "x := TO_UINT(-1);", "x", 65535),
    ("x : STRING", "x := TIME_TO_STRING(T#1m2s);", "x", "T#1m2s"),
    ("x : REAL", "x := LREAL_TO_REAL(0.1);", "x", REAL_0_1),
    # bit strings: bitwise AND/OR/XOR/NOT, shifts and rotations
    ("x : BYTE", "x := NOT BYTE#16#0F;", "x", 0xF0),
    ("x : WORD; a : WORD := 16#00FF", "x := NOT a;", "x", 0xFF00),
    ("x : BYTE", "x := 16#F0 AND 16#3C;", "x", 0x30),
    ("x : BYTE", "x := 16#F0 OR 16#0F;", "x", 0xFF),
    ("x : BYTE", "x := 16#FF XOR 16#0F;", "x", 0xF0),
    ("x : BYTE; a : BYTE := 16#81", "x := SHL(a, 1);", "x", 0x02),
    ("x : BYTE; a : BYTE := 16#81", "x := SHR(a, 1);", "x", 0x40),
    ("x : BYTE; a : BYTE := 16#81", "x := ROL(a, 1);", "x", 0x03),
    ("x : BYTE; a : BYTE := 16#81", "x := ROR(a, 1);", "x", 0xC0),
    ("x : WORD; a : WORD := 16#8001", "x := ROL(a, 4);", "x", 0x0018),
    ("x : DWORD; a : DWORD := 1", "x := SHL(a, 31);", "x", 0x80000000),
    ("x : DWORD; a : DWORD := 1", "x := SHL(a, 32);", "x", 0),
    ("x : INT; a : INT := 5", "x := NOT a;", "x", -6),
    ("x : BOOL", "x := NOT TRUE;", "x", False),
    ("x : BOOL; a : BOOL := TRUE", "x := a AND NOT FALSE;", "x", True),
    ("x : BOOL; a : BOOL := TRUE", "x := a XOR TRUE;", "x", False),
    ("x : BOOL; a : BOOL := FALSE; b : BOOL := TRUE", "x := a OR b AND FALSE;", "x", False),
    ("x : BOOL", "x := TRUE OR FALSE AND FALSE;", "x", True),
    ("x : BOOL", "x := 1 < 2 AND 3 > 2;", "x", True),
    ("x : BOOL", "x := 2 = 2 AND 3 <> 3;", "x", False),
    ("x : BOOL; a : INT := 3", "x := a >= 3 AND a <= 3;", "x", True),
    ("x : BOOL; a : BOOL := FALSE", "x := a AND_THEN TRUE;", "x", False),
    # standard numeric functions
    ("x : INT", "x := ABS(-5);", "x", 5),
    ("x : LREAL", "x := ABS(-2.5);", "x", 2.5),
    ("x : LREAL", "x := SQRT(16.0);", "x", 4.0),
    ("x : LREAL", "x := SQRT(-1.0);", "x", math.nan),
    # of a REAL: a REAL (rounded to 32 bits), also when stored into an LREAL
    ("x : LREAL; r : REAL := 2.0", "x := SQRT(r);", "x", 1.4142135381698608),
    ("x : LREAL", "x := SQRT(REAL#2.0);", "x", 1.4142135381698608),
    ("x : LREAL; r : LREAL := 2.0", "x := SQRT(r);", "x", math.sqrt(2.0)),
    ("x : INT", "x := MIN(3, 7, -2);", "x", -2),
    ("x : INT", "x := MAX(3, 7, -2);", "x", 7),
    ("x : INT; a : INT := 15", "x := LIMIT(0, a, 10);", "x", 10),
    ("x : INT; a : INT := -3", "x := LIMIT(0, a, 10);", "x", 0),
    ("x : LREAL", "x := LIMIT(0.0, 5.5, 10.0);", "x", 5.5),
    ("x : INT", "x := SEL(TRUE, 1, 2);", "x", 2),
    ("x : INT", "x := SEL(FALSE, 1, 2);", "x", 1),
    ("x : INT; k : INT := 2", "x := MUX(k, 10, 20, 30);", "x", 30),
    ("x : LREAL", "x := LN(1.0);", "x", 0.0),
    ("x : LREAL", "x := LOG(1000.0);", "x", 3.0),
    ("x : LREAL", "x := EXP(0.0);", "x", 1.0),
    ("x : LREAL", "x := SIN(0.0) + COS(0.0);", "x", 1.0),
    ("x : LREAL", "x := ATAN(1.0) * 4.0;", "x", math.pi),
    ("x : INT", "x := MOVE(9);", "x", 9),
    # TIME
    ("x : TIME", "x := T#1s500ms;", "x", 1500),
    ("x : TIME", "x := TIME#2m;", "x", 120000),
    ("x : TIME", "x := T#1h2m3s4ms;", "x", 3723004),
    ("x : TIME", "x := T#1.5s;", "x", 1500),
    ("x : TIME", "x := T#1s + T#250ms;", "x", 1250),
    ("x : TIME", "x := T#1s * 3;", "x", 3000),
    ("x : TIME", "x := T#1s / 4;", "x", 250),
    ("x : BOOL", "x := T#1s > T#999ms;", "x", True),
    ("x : LTIME", "x := LTIME#1ms;", "x", 1000000),
    ("x : TIME", "x := T#1d;", "x", 86400000),
    # strings
    ("x : STRING", "x := 'ab$'c';", "x", "ab'c"),
    ("x : STRING", "x := 'a$$b';", "x", "a$b"),
    ("x : STRING", "x := '$41$42';", "x", "AB"),
    ("x : STRING", "x := CONCAT('ab', 'cd');", "x", "abcd"),
    ("x : STRING", "x := CONCAT('a', 'b', 'c');", "x", "abc"),
    ("x : INT", "x := LEN('hello');", "x", 5),
    ("x : STRING", "x := LEFT('hello', 2);", "x", "he"),
    ("x : STRING", "x := RIGHT('hello', 3);", "x", "llo"),
    ("x : STRING", "x := MID('hello', 3, 2);", "x", "ell"),
    ("x : STRING", "x := INSERT('hlo', 'el', 1);", "x", "hello"),
    ("x : STRING", "x := DELETE('hello', 2, 2);", "x", "hlo"),
    ("x : STRING", "x := REPLACE('hello', 'EL', 2, 2);", "x", "hELlo"),
    ("x : INT", "x := FIND('hello', 'll');", "x", 3),
    ("x : INT", "x := FIND('hello', 'z');", "x", 0),
    ("x : STRING(3)", "x := 'abcdef';", "x", "abc"),
    ("x : BOOL", "x := 'abc' = 'abc';", "x", True),
    ("x : BOOL", "x := 'abc' < 'abd';", "x", True),
    ("x : STRING(4); s : STRING := 'xy'", "x := CONCAT(s, s, s);", "x", "xyxy"),
    # control flow
    ("x : INT; i : INT", "FOR i := 1 TO 10 DO x := x + i; END_FOR", "x", 55),
    ("x : INT; i : INT", "FOR i := 10 TO 1 BY -2 DO x := x + i; END_FOR", "x", 30),
    ("x : INT; i : INT", "FOR i := 1 TO 10 DO x := i; IF i = 4 THEN EXIT; END_IF END_FOR", "x", 4),
    ("i : INT", "FOR i := 1 TO 5 DO ; END_FOR", "i", 6),
    ("x : INT; i : INT", "FOR i := 5 TO 1 DO x := x + 1; END_FOR", "x", 0),
    ("x : INT; i : INT; n : INT := 3", "FOR i := 1 TO n * 2 BY n DO x := x + 1; END_FOR", "x", 2),
    ("x : INT", "WHILE x < 7 DO x := x + 2; END_WHILE", "x", 8),
    ("x : INT", "REPEAT x := x + 5; UNTIL x > 12 END_REPEAT", "x", 15),
    ("x : INT", "REPEAT x := x + 1; UNTIL TRUE END_REPEAT", "x", 1),
    ("x : INT", "WHILE TRUE DO x := x + 1; IF x >= 3 THEN EXIT; END_IF END_WHILE", "x", 3),
    (
        "x : INT; i : INT; j : INT",
        "FOR i := 1 TO 3 DO FOR j := 1 TO 3 DO IF j = 2 THEN EXIT; END_IF x := x + 1; END_FOR"
        " END_FOR",
        "x",
        3,
    ),
    ("x : INT", "x := 1; RETURN; x := 2;", "x", 1),
    (
        "x : INT; a : INT := 5",
        "IF a > 3 THEN x := 1; ELSIF a > 1 THEN x := 2; ELSE x := 3; END_IF",
        "x",
        1,
    ),
    (
        "x : INT; a : INT := 2",
        "IF a > 3 THEN x := 1; ELSIF a > 1 THEN x := 2; ELSE x := 3; END_IF",
        "x",
        2,
    ),
    (
        "x : INT; a : INT := 0",
        "IF a > 3 THEN x := 1; ELSIF a > 1 THEN x := 2; ELSE x := 3; END_IF",
        "x",
        3,
    ),
    # CASE with lists and ranges
    (
        "x : INT; a : INT := 2",
        "CASE a OF 1, 2: x := 10; 3..5: x := 20; ELSE x := 30; END_CASE",
        "x",
        10,
    ),
    (
        "x : INT; a : INT := 4",
        "CASE a OF 1, 2: x := 10; 3..5: x := 20; ELSE x := 30; END_CASE",
        "x",
        20,
    ),
    (
        "x : INT; a : INT := 5",
        "CASE a OF 1, 2: x := 10; 3..5: x := 20; ELSE x := 30; END_CASE",
        "x",
        20,
    ),
    (
        "x : INT; a : INT := 9",
        "CASE a OF 1, 2: x := 10; 3..5: x := 20; ELSE x := 30; END_CASE",
        "x",
        30,
    ),
    ("x : INT; a : INT := 9", "CASE a OF 1: x := 10; END_CASE", "x", 0),
    ("x : INT; a : INT := -3", "CASE a OF -5..-1: x := 1; 0: x := 2; END_CASE", "x", 1),
    ("x : INT; a : INT := 7", "CASE a OF 1..3, 7, 9..10: x := 1; END_CASE", "x", 1),
    ("x : INT; a : INT := 1", "CASE a OF 1: x := 1; 1..2: x := 2; END_CASE", "x", 1),
    # arrays: any lower bound, several dimensions, initial values
    ("a : ARRAY[1..3] OF INT := [4, 5, 6]; x : INT", "x := a[1] + a[3];", "x", 10),
    ("a : ARRAY[-2..2] OF INT; x : INT", "a[-2] := 7; x := a[-2];", "x", 7),
    ("a : ARRAY[0..4] OF INT := [2(1), 3(9)]; x : INT", "x := a[1] * 10 + a[4];", "x", 19),
    ("a : ARRAY[1..2, 1..3] OF INT; x : INT", "a[2, 3] := 5; x := a[2, 3];", "x", 5),
    ("a : ARRAY[1..2, 0..1] OF INT := [1, 2, 3, 4]; x : INT", "x := a[2, 0];", "x", 3),
    (
        "a : ARRAY[1..5] OF INT; i : INT; x : INT",
        "FOR i := 1 TO 5 DO a[i] := i * i; END_FOR x := a[4];",
        "x",
        16,
    ),
    ("a, b : ARRAY[1..2] OF INT; x : INT", "a[1] := 3; b := a; a[1] := 4; x := b[1];", "x", 3),
    ("a : ARRAY[1..3] OF REAL; x : REAL", "a[2] := 0.1; x := a[2];", "x", REAL_0_1),
    ("a : ARRAY[1..2] OF BOOL; x : BOOL", "a[2] := TRUE; x := a[2] AND NOT a[1];", "x", True),
    ("a : ARRAY[0..N] OF INT; x : INT", "x := 1; a[N] := 2; x := a[N];", "x", 2),
    # structs and enumerations
    ("p : ST_P; x : INT", "p.a := 3; p.b := 4; x := p.a * p.b;", "x", 12),
    ("p : ST_P; x : INT", "x := p.a;", "x", 5),
    ("p : ST_P := (a := 8); x : INT", "x := p.a;", "x", 8),
    ("p, q : ST_P; x : INT", "p.a := 1; q := p; p.a := 2; x := q.a;", "x", 1),
    ("p : ST_P; x : INT", "p.v[2] := 6; x := p.v[2];", "x", 6),
    ("c : E_C; x : INT", "c := E_C.Blue; x := TO_INT(c) * 2;", "x", 22),
    ("c : E_C; x : BOOL", "c := Green; x := c = E_C.Green;", "x", True),
    ("c : E_C; x : INT", "CASE c OF Red: x := 1; Green: x := 2; END_CASE", "x", 1),
    ("c : E_C := Blue; x : INT", "x := TO_INT(c);", "x", 11),
    # user functions and blocks
    ("x : DINT", "x := F_Add(2, 3);", "x", 5),
    ("x : DINT", "x := F_Add(b := 3, a := 4);", "x", 7),
    ("x : DINT", "x := F_Add(1);", "x", 11),
    ("x : DINT", "x := F_Fact(5);", "x", 120),
    ("c : FB_Count; x : INT", "c(step := 2); c(); x := c.total;", "x", 4),
    ("c : FB_Count; x : INT", "c(step := 3, total => x);", "x", 3),
    ("c : FB_Count; x : INT; v : INT := 10", "c(step := 1, acc := v); x := v;", "x", 11),
    (
        "c1, c2 : FB_Count; x : INT",
        "c1(step := 1); c2(step := 5); x := c1.total + c2.total;",
        "x",
        6,
    ),
    ("x : INT", "x := g_Count; g_Count := g_Count + 1;", "g_Count", 8),
    ("x : INT", "x := N * 2;", "x", 20),
]

LIBRARY = """
TYPE E_C : (Red, Green := 10, Blue); END_TYPE
TYPE ST_P :
STRUCT
  a : INT := 5;
  b : INT;
  v : ARRAY[1..3] OF INT;
END_STRUCT
END_TYPE
VAR_GLOBAL CONSTANT N : INT := 10; END_VAR
VAR_GLOBAL g_Count : INT := 7; END_VAR
FUNCTION F_Add : DINT
VAR_INPUT a : DINT; b : DINT := 10; END_VAR
F_Add := a + b;
END_FUNCTION
FUNCTION F_Fact : DINT
VAR_INPUT n : DINT; END_VAR
VAR i : DINT; END_VAR
F_Fact := 1;
FOR i := 2 TO n DO F_Fact := F_Fact * i; END_FOR
END_FUNCTION
FUNCTION_BLOCK FB_Count
VAR_INPUT step : INT; END_VAR
VAR_OUTPUT total : INT; END_VAR
VAR_IN_OUT acc : INT; END_VAR
total := total + step;
acc := acc + step;
END_FUNCTION_BLOCK
"""


def _same(value, expected):
    if isinstance(expected, float) and math.isnan(expected):
        return isinstance(value, float) and math.isnan(value)
    if isinstance(expected, float):
        return value == pytest.approx(expected, rel=1e-12, abs=0.0) and type(value) is float
    return value == expected and type(value) is type(expected)


@pytest.mark.parametrize(("decls", "body", "name", "expected"), CASES)
def test_statement_gives_the_iec_value(decls, body, name, expected):
    prog = run(decls, body, extra=LIBRARY)
    assert _same(getattr(prog, name), expected), getattr(prog, name)


def test_the_table_has_at_least_150_cases():
    assert len(CASES) + len(TIMED) >= 150


VAR_TEMP_SOURCE = """
FUNCTION_BLOCK FB_Temp
VAR_OUTPUT o : INT; END_VAR
VAR_TEMP t : INT; u : INT := 5; END_VAR
t := t + 1; u := u + 1; o := t * 100 + u;
END_FUNCTION_BLOCK
PROGRAM t
VAR n : INT; f : FB_Temp; r : INT; END_VAR
VAR_TEMP k : INT; m : INT := 3; END_VAR
k := k + 1; m := m + 1; n := k * 10 + m;
f(); r := f.o;
END_PROGRAM
"""


def test_var_temp_starts_fresh_every_scan():
    """A VAR_TEMP of a PROGRAM or FUNCTION_BLOCK holds its initial value (or 0) at the start of
    every call; a VAR keeps its value across scans."""
    prog = plc.st.from_source(VAR_TEMP_SOURCE, filename="case.st", period=0.01)
    for _ in range(3):
        prog()
        assert not prog.error, prog.error
        assert (prog.n, prog.r) == (14, 106)


TIMED = [
    # (declarations, body, scans of 10 ms, variable, expected); time is the scan count × 10 ms
    ("t : TON; q : BOOL", "t(IN := TRUE, PT := T#50ms); q := t.Q;", 5, "q", False),
    ("t : TON; q : BOOL", "t(IN := TRUE, PT := T#50ms); q := t.Q;", 6, "q", True),
    ("t : TON; e : TIME", "t(IN := TRUE, PT := T#50ms, ET => e);", 4, "e", 30),
    ("t : TON; e : TIME", "t(IN := TRUE, PT := T#50ms, ET => e);", 20, "e", 50),
    (
        "t : TON; n : INT; q : BOOL",
        "n := n + 1; t(IN := n < 8, PT := T#50ms); q := t.Q;",
        9,
        "q",
        False,
    ),
    (
        "t : TOF; n : INT; q : BOOL",
        "n := n + 1; t(IN := n < 3, PT := T#50ms); q := t.Q;",
        7,
        "q",
        True,
    ),
    (
        "t : TOF; n : INT; q : BOOL",
        "n := n + 1; t(IN := n < 3, PT := T#50ms); q := t.Q;",
        8,
        "q",
        False,
    ),
    ("t : TOF; q : BOOL", "t(IN := FALSE, PT := T#50ms); q := t.Q;", 1, "q", False),
    (
        "t : TP; n : INT; q : BOOL",
        "n := n + 1; t(IN := n = 1, PT := T#50ms); q := t.Q;",
        5,
        "q",
        True,
    ),
    (
        "t : TP; n : INT; q : BOOL",
        "n := n + 1; t(IN := n = 1, PT := T#50ms); q := t.Q;",
        6,
        "q",
        False,
    ),
    ("t : TP; q : BOOL", "t(IN := TRUE, PT := T#50ms); q := t.Q;", 10, "q", False),
    ("t : TP; e : TIME", "t(IN := TRUE, PT := T#50ms); e := t.ET;", 10, "e", 50),
    ("r : R_TRIG; n : INT", "r(CLK := TRUE); IF r.Q THEN n := n + 1; END_IF", 5, "n", 1),
    (
        "r : R_TRIG; n, k : INT",
        "k := k + 1; r(CLK := k MOD 2 = 0); IF r.Q THEN n := n + 1; END_IF",
        6,
        "n",
        3,
    ),
    ("f : F_TRIG; n : INT", "f(CLK := FALSE); IF f.Q THEN n := n + 1; END_IF", 3, "n", 0),
    (
        "f : F_TRIG; n, k : INT",
        "k := k + 1; f(CLK := k < 3); IF f.Q THEN n := n + 1; END_IF",
        5,
        "n",
        1,
    ),
    ("c : CTU; k : INT", "k := k + 1; c(CU := k MOD 2 = 1, PV := 3);", 6, "c", None),
    (
        "c : CTU; k : INT; q : BOOL; v : INT",
        "k := k + 1; c(CU := k MOD 2 = 1, PV := 3, Q => q, CV => v);",
        5,
        "q",
        True,
    ),
    (
        "c : CTU; k : INT; v : INT",
        "k := k + 1; c(CU := k MOD 2 = 1, R := k = 4, PV := 3, CV => v);",
        6,
        "v",
        1,
    ),
    (
        "c : CTD; k : INT; v : INT",
        "k := k + 1; c(CD := k MOD 2 = 0, LD := k = 1, PV := 5, CV => v);",
        6,
        "v",
        2,
    ),
    (
        "c : CTD; k : INT; q : BOOL",
        "k := k + 1; c(CD := k MOD 2 = 0, LD := k = 1, PV := 1, Q => q);",
        3,
        "q",
        True,
    ),
    (
        "c : CTUD; k : INT; v : INT",
        "k := k + 1; c(CU := k MOD 2 = 0, CD := k = 5, PV := 2, CV => v);",
        6,
        "v",
        2,
    ),
    (
        "c : CTUD; k : INT; u : BOOL",
        "k := k + 1; c(CU := k MOD 2 = 0, PV := 2, QU => u);",
        4,
        "u",
        True,
    ),
    (
        "s : SR; k : INT; q : BOOL",
        "k := k + 1; s(S1 := k = 1, R := k = 3); q := s.Q1;",
        2,
        "q",
        True,
    ),
    (
        "s : SR; k : INT; q : BOOL",
        "k := k + 1; s(S1 := k = 1, R := k = 3); q := s.Q1;",
        3,
        "q",
        False,
    ),
    ("s : SR; q : BOOL", "s(S1 := TRUE, R := TRUE); q := s.Q1;", 1, "q", True),
    ("s : RS; q : BOOL", "s(S := TRUE, R1 := TRUE); q := s.Q1;", 1, "q", False),
    ("s : RS; k : INT; q : BOOL", "k := k + 1; s(S := k = 1); q := s.Q1;", 4, "q", True),
]


@pytest.mark.parametrize(("decls", "body", "scans", "name", "expected"), TIMED)
def test_block_over_scans_gives_the_iec_value(decls, body, scans, name, expected):
    prog = run(decls, body, scans=scans)
    if expected is None:  # the counter's own output
        assert prog.c.CV == 3 and prog.c.Q
        return
    assert _same(getattr(prog, name), expected), getattr(prog, name)
