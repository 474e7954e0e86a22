"""IEC 61131-3 conformance, the language: ST expressions and statements (2nd edition 3.3, 3rd
edition 7.3), functions and function blocks (2.5, 6.6), the standard functions (2.5.1.5,
6.6.2.5) and function blocks (2.5.2.3, 6.6.3.5). Each case names its clause; the expected value
is the standard's (where it leaves the value to the implementation: CODESYS's and TwinCAT's,
see docs/st.md)."""

from __future__ import annotations

import math

import pytest

from tests.plc.st.iec import case, program, run, same

R01 = 0.10000000149011612
"""0.1 as a 32-bit REAL."""

POUS = """
FUNCTION Twice : INT
VAR_INPUT a : INT; END_VAR
Twice := a * 2;
END_FUNCTION

FUNCTION Sum3 : DINT
VAR_INPUT a : DINT; b : DINT := 10; c : DINT := 100; END_VAR
Sum3 := a + b + c;
END_FUNCTION

FUNCTION Fresh : INT
VAR n : INT; END_VAR
n := n + 1;
Fresh := n;
END_FUNCTION

FUNCTION Early : INT
VAR_INPUT a : INT; END_VAR
Early := 1;
IF a > 0 THEN RETURN; END_IF
Early := 2;
END_FUNCTION

FUNCTION Swap : BOOL
VAR_IN_OUT a : INT; b : INT; END_VAR
VAR t : INT; END_VAR
t := a; a := b; b := t;
Swap := TRUE;
END_FUNCTION

FUNCTION Divmod : INT
VAR_INPUT a : INT; b : INT; END_VAR
VAR_OUTPUT q : INT; r : INT; END_VAR
q := a / b;
r := a MOD b;
Divmod := q;
END_FUNCTION

FUNCTION_BLOCK Counter
VAR_INPUT step : INT := 1; END_VAR
VAR_OUTPUT total : INT; END_VAR
VAR_IN_OUT acc : INT; END_VAR
total := total + step;
acc := acc + step;
END_FUNCTION_BLOCK

FUNCTION_BLOCK Latch
VAR_INPUT set : BOOL; END_VAR
VAR_OUTPUT q : BOOL; END_VAR
VAR inner : R_TRIG; END_VAR
inner(CLK := set);
IF inner.Q THEN q := NOT q; END_IF
END_FUNCTION_BLOCK
"""
"""The functions and function blocks of the cases that use them."""

EXPRESSIONS = [
    case("3.3.1 (7.3.2) Table 55 parentheses first", "x : INT;", "x := (2 + 3) * 4;", "x", 20),
    case("3.3.1 (7.3.2) Table 55 * before +", "x : INT;", "x := 2 + 3 * 4;", "x", 14),
    case("3.3.1 (7.3.2) Table 55 / before -", "x : INT;", "x := 20 - 8 / 2;", "x", 16),
    case("3.3.1 (7.3.2) Table 55 MOD with *", "x : INT;", "x := 7 MOD 4 * 3;", "x", 9),
    case("3.3.1 (7.3.2) Table 55 left to right -", "x : INT;", "x := 10 - 4 - 3;", "x", 3),
    case("3.3.1 (7.3.2) Table 55 left to right /", "x : INT;", "x := 64 / 8 / 2;", "x", 4),
    case("3.3.1 (7.3.2) Table 55 unary minus", "x : INT; a : INT := 3;", "x := -a * 2;", "x", -6),
    case("3.3.1 (7.3.2) Table 55 double negation", "x : INT; a : INT := 3;", "x := -(-a);", "x", 3),
    case("3.3.1 (7.3.2) Table 55 NOT before AND", "x : BOOL;", "x := NOT FALSE AND TRUE;", "x",
        True),
    case("3.3.1 (7.3.2) Table 55 comparison before AND", "x : BOOL;", "x := 1 < 2 AND 2 < 3;", "x",
        True),
    case("3.3.1 (7.3.2) Table 55 < before =", "x : BOOL;", "x := 1 < 2 = TRUE;", "x", True),
    case("3.3.1 (7.3.2) Table 55 AND before XOR", "x : BOOL;", "x := TRUE XOR TRUE AND FALSE;",
        "x", True),
    case("3.3.1 (7.3.2) Table 55 XOR before OR", "x : BOOL;", "x := TRUE OR TRUE XOR TRUE;", "x",
        True),
    case("3.3.1 (7.3.2) Table 55 AND before OR", "x : BOOL;", "x := TRUE OR FALSE AND FALSE;", "x",
        True),
    case("3.3.1 (7.3.2) Table 55 & is AND", "x : BOOL;", "x := TRUE & FALSE;", "x", False),
    case("3.3.1 (7.3.2) Table 55 & on bit strings", "x : BYTE;", "x := 16#F0 & 16#3C;", "x", 0x30),
    case("3.3.1 (7.3.2) Table 55 = on numbers", "x : BOOL; a : REAL := 2.0;", "x := a = 2;", "x",
        True),
    case("3.3.1 (7.3.2) Table 55 <>", "x : BOOL;", "x := 3 <> 3;", "x", False),
    case("3.3.1 (7.3.2) Table 55 >=", "x : BOOL;", "x := 3 >= 3;", "x", True),
    case("3.3.1 (7.3.2) Table 55 <= on TIME", "x : BOOL;", "x := T#1s <= T#999ms;", "x", False),
    case("3.3.1 (7.3.2) Table 55 on STRINGs", "x : BOOL;", "x := 'abc' < 'abd';", "x", True),
    case("3rd ed. 7.3.2 Table 71 ** power", "x : LREAL;", "x := 2.0 ** 10;", "x", 1024.0),
    case("3rd ed. 7.3.2 Table 71 ** before *", "x : LREAL;", "x := 3.0 * 2.0 ** 2;", "x", 12.0),
    case("3rd ed. 7.3.2 Table 71 ** left to right", "x : LREAL;", "x := 2.0 ** 3.0 ** 2.0;", "x",
        64.0),
    case("3rd ed. 7.3.2 Table 71 - before **", "x : LREAL;", "x := -2.0 ** 2;", "x", 4.0),
    case("3.3.1 (7.3.2) a function call in an expression", "x : INT;", "x := Twice(3) + 1;", "x",
        7, POUS),
    case("3.3.1 (7.3.2) nested function calls", "x : INT;", "x := Twice(Twice(2));", "x", 8, POUS),
    case("2.5.1.4 (6.6.1.6) an integer widens to a real", "x : REAL; i : INT := 3;",
        "x := i + 0.5;", "x", 3.5),
    case("2.5.1.4 (6.6.1.6) INT + DINT is DINT", "x : DINT; a : INT := 32767; b : DINT := 1;",
        "x := a + b;", "x", 32768),
    case("2.5.1.4 (6.6.1.6) REAL + LREAL is LREAL",
        "x : LREAL; a : REAL := 0.1; b : LREAL := 0.0;", "x := a + b;", "x", R01),
    case("2.5.1.4 (6.6.1.6) SINT widens to INT", "x : INT; a : SINT := -100;", "x := a;", "x",
        -100),
    case("2.5.1.4 (6.6.1.6) USINT widens to UINT", "x : UINT; a : USINT := 200;", "x := a;", "x",
        200),
    case("2.5.1.4 (6.6.1.6) BYTE widens to WORD", "x : WORD; a : BYTE := 16#AB;", "x := a;", "x",
        0xAB),
    case("2.5.1.4 (6.6.1.6) an integer result wraps at its width", "x : INT; a : INT := 32767;",
        "x := a + 1;", "x", -32768),
    case("2.5.1.5.2 (6.6.2.5.8) integer / truncates", "x : INT; a : INT := -7;", "x := a / 2;",
        "x", -3),
    case("2.5.1.5.2 (6.6.2.5.8) MOD has the dividend's sign", "x : INT; a : INT := -7;",
        "x := a MOD 2;", "x", -1),
    case("2.5.1.5.2 (6.6.2.5.8) MOD 0 is 0", "x : INT := 5; a : INT := 7; z : INT;",
        "x := a MOD z;", "x", 0),
    case("2.5.1.5.2 (6.6.2.5.8) real division", "x : LREAL;", "x := 7.0 / 2.0;", "x", 3.5),
    case("2.5.1.5.2 (6.6.2.5.8) REAL arithmetic is REAL", "x : LREAL; a : REAL := 0.1;",
        "x := a * 3.0;", "x", 0.30000001192092896),
]  # fmt: skip

STATEMENTS = [
    case("3.3.2.1 (7.3.3.2) assignment", "x : INT;", "x := 5;", "x", 5),
    case("3.3.2.1 (7.3.3.2) an assignment copies an array", "a, b : ARRAY[1..2] OF INT; x : INT;",
        "a[1] := 1; b := a; a[1] := 2; x := b[1];", "x", 1),
    case("3.3.2.1 (7.3.3.2) an assignment copies a structure", "p, q : P2; x : INT;",
        "p.a := 1; q := p; p.a := 2; x := q.a;", "x", 1,
        "TYPE P2 : STRUCT a : INT; END_STRUCT; END_TYPE"),
    case("3.3.2.1 (7.3.3.2) a structure in an array copied",
        "ps : ARRAY[1..2] OF P2; q : P2; x : INT;",
        "ps[1].a := 3; q := ps[1]; ps[1].a := 4; x := q.a;", "x", 3,
        "TYPE P2 : STRUCT a : INT; END_STRUCT; END_TYPE"),
    case("3.3.2.3 (7.3.3.4.1) IF THEN", "x : INT;", "IF TRUE THEN x := 1; END_IF", "x", 1),
    case("3.3.2.3 (7.3.3.4.1) IF ELSE", "x : INT;", "IF FALSE THEN x := 1; ELSE x := 2; END_IF",
        "x", 2),
    case("3.3.2.3 (7.3.3.4.1) the first true ELSIF", "x : INT; a : INT := 5;",
        "IF a > 9 THEN x := 1; ELSIF a > 4 THEN x := 2; ELSIF a > 1 THEN x := 3; END_IF", "x", 2),
    case("3.3.2.3 (7.3.3.4.1) nested IF", "x : INT;",
        "IF TRUE THEN IF FALSE THEN x := 1; ELSE x := 2; END_IF END_IF", "x", 2),
    case("3.3.2.3 (7.3.3.4.1) an empty branch", "x : INT := 4;",
        "IF TRUE THEN ; ELSE x := 1; END_IF", "x", 4),
    case("3.3.2.3 (7.3.3.4.2) CASE a value", "x : INT; a : INT := 2;",
        "CASE a OF 1: x := 10; 2: x := 20; END_CASE", "x", 20),
    case("3.3.2.3 (7.3.3.4.2) CASE a list", "x : INT; a : INT := 4;",
        "CASE a OF 1, 4, 9: x := 1; END_CASE", "x", 1),
    case("3.3.2.3 (7.3.3.4.2) CASE a range", "x : INT; a : INT := 7;",
        "CASE a OF 5..8: x := 1; END_CASE", "x", 1),
    case("3.3.2.3 (7.3.3.4.2) CASE ranges and values", "x : INT; a : INT := 12;",
        "CASE a OF 1..3, 12: x := 1; 4..11: x := 2; END_CASE", "x", 1),
    case("3.3.2.3 (7.3.3.4.2) CASE ELSE", "x : INT; a : INT := 99;",
        "CASE a OF 1: x := 1; ELSE x := 3; END_CASE", "x", 3),
    case("3.3.2.3 (7.3.3.4.2) CASE no match, no ELSE", "x : INT := 6; a : INT := 99;",
        "CASE a OF 1: x := 1; END_CASE", "x", 6),
    case("3.3.2.3 (7.3.3.4.2) CASE negative labels", "x : INT; a : INT := -2;",
        "CASE a OF -3..-1: x := 1; END_CASE", "x", 1),
    case("3.3.2.3 (7.3.3.4.2) CASE on an enumeration", "x : INT; c : Color := Blue;",
        "CASE c OF Red: x := 1; Green, Blue: x := 2; END_CASE", "x", 2,
        "TYPE Color : (Red, Green, Blue); END_TYPE"),
    case("3.3.2.3 (7.3.3.4.2) CASE several statements", "x, y : INT; a : INT := 1;",
        "CASE a OF 1: x := 1; y := 2; END_CASE", "y", 2),
    case("3rd ed. 7.3.3.4.2 CASE on a bit string", "x : INT; w : WORD := 16#10;",
        "CASE w OF 16#10: x := 1; END_CASE", "x", 1),
    case("3rd ed. 7.3.3.4.2 a constant expression label", "x : INT; a : INT := 6;",
        "CASE a OF 2 * 3: x := 1; END_CASE", "x", 1),
    case("3.3.2.4 (7.3.3.5.2) FOR", "x : INT; i : INT;", "FOR i := 1 TO 4 DO x := x + i; END_FOR",
        "x", 10),
    case("3.3.2.4 (7.3.3.5.2) FOR BY", "x : INT; i : INT;",
        "FOR i := 0 TO 10 BY 5 DO x := x + 1; END_FOR", "x", 3),
    case("3.3.2.4 (7.3.3.5.2) FOR downward", "x : INT; i : INT;",
        "FOR i := 3 TO 1 BY -1 DO x := x * 10 + i; END_FOR", "x", 321),
    case("3.3.2.4 (7.3.3.5.2) FOR not entered", "x : INT; i : INT;",
        "FOR i := 5 TO 1 DO x := 1; END_FOR", "x", 0),
    case("3.3.2.4 (7.3.3.5.2) FOR once", "x : INT; i : INT;",
        "FOR i := 2 TO 2 DO x := x + 1; END_FOR", "x", 1),
    case("3.3.2.4 (7.3.3.5.2) FOR over DINT", "x : DINT; i : DINT;",
        "FOR i := 100000 TO 100002 DO x := i; END_FOR", "x", 100002),
    case("3.3.2.4 (7.3.3.5.2) FOR to an expression", "x : INT; i : INT; n : INT := 3;",
        "FOR i := 1 TO n * 2 BY n - 1 DO x := x + 1; END_FOR", "x", 3),
    case("3.3.2.4 (7.3.3.5.2) the control variable after FOR", "i : INT;",
        "FOR i := 1 TO 3 DO ; END_FOR", "i", 4),
    case("3.3.2.4 (7.3.3.5.3) WHILE", "x : INT;", "WHILE x < 5 DO x := x + 2; END_WHILE", "x", 6),
    case("3.3.2.4 (7.3.3.5.3) WHILE not entered", "x : INT := 9;",
        "WHILE x < 5 DO x := 0; END_WHILE", "x", 9),
    case("3.3.2.4 (7.3.3.5.4) REPEAT", "x : INT;", "REPEAT x := x + 3; UNTIL x > 7 END_REPEAT",
        "x", 9),
    case("3.3.2.4 (7.3.3.5.4) REPEAT runs once", "x : INT;",
        "REPEAT x := x + 1; UNTIL TRUE END_REPEAT", "x", 1),
    case("3.3.2.4 (7.3.3.5.6) EXIT", "x : INT; i : INT;",
        "FOR i := 1 TO 9 DO IF i = 3 THEN EXIT; END_IF x := i; END_FOR", "x", 2),
    case("3.3.2.4 (7.3.3.5.6) EXIT leaves the innermost loop", "x : INT; i, j : INT;",
        "FOR i := 1 TO 3 DO FOR j := 1 TO 3 DO IF j = 2 THEN EXIT; END_IF x := x + 1; END_FOR\n"
        "END_FOR",
        "x", 3),
    case("3.3.2.4 (7.3.3.5.6) EXIT from WHILE", "x : INT;",
        "WHILE TRUE DO x := x + 1; IF x = 4 THEN EXIT; END_IF END_WHILE", "x", 4),
    case("3rd ed. 7.3.3.5.5 CONTINUE", "x : INT; i : INT;",
        "FOR i := 1 TO 5 DO IF i MOD 2 = 0 THEN CONTINUE; END_IF x := x + i; END_FOR", "x", 9),
    case("3rd ed. 7.3.3.5.5 CONTINUE in WHILE", "x, n : INT;",
        "WHILE n < 4 DO n := n + 1; IF n = 2 THEN CONTINUE; END_IF x := x + n; END_WHILE", "x", 8),
    case("3.3.2.2 (7.3.3.3) RETURN ends the program's scan", "x : INT;", "x := 1; RETURN; x := 2;",
        "x", 1),
    case("3.3.2 (7.3.3.1) an empty statement", "x : INT := 3;", ";;", "x", 3),
    case("3.3.2 (7.3.3.1) statements over lines", "x : INT;", "x :=\n  1\n  + 2;", "x", 3),
]  # fmt: skip

POU_CASES = [
    case("2.5.1.1 (6.6.2.3) a call without names", "x : DINT;", "x := Sum3(1, 2, 3);", "x", 6,
        POUS),
    case("2.5.1.1 (6.6.2.3) a call with names", "x : DINT;", "x := Sum3(c := 1, a := 2, b := 3);",
        "x", 6, POUS),
    case("2.5.1.1 (6.6.2.3) an omitted input takes its initial value", "x : DINT;",
        "x := Sum3(a := 1);", "x", 111, POUS),
    case("2.5.1.1 (6.6.2.3) an omitted input among named ones", "x : DINT;",
        "x := Sum3(a := 1, c := 5);", "x", 16, POUS),
    case("2.5.1.3 (6.6.2.2) the function's name is its result", "x : INT;", "x := Twice(21);", "x",
        42, POUS),
    case("2.5.1.3 (6.6.2.2) a function has no memory", "x : INT;",
        "x := Fresh(); x := x + Fresh();", "x", 2, POUS),
    case("2.5.1.3 (6.6.2.2) RETURN in a function", "x : INT;", "x := Early(1) * 10 + Early(0);",
        "x", 12, POUS),
    case("3rd ed. 6.6.2.2 VAR_IN_OUT of a function", "a : INT := 1; b : INT := 2; ok : BOOL;",
        "ok := Swap(a, b);", "a", 2, POUS),
    case("3rd ed. 6.6.2.2 VAR_IN_OUT both ways", "a : INT := 1; b : INT := 2; ok : BOOL;",
        "ok := Swap(a := a, b := b);", "b", 1, POUS),
    case("3rd ed. 6.6.2.2 VAR_OUTPUT of a function", "q, r, x : INT;",
        "x := Divmod(a := 17, b := 5, q => q, r => r);", "r", 2, POUS),
    case("3rd ed. 6.6.2.2 an output left out", "q, x : INT;",
        "x := Divmod(a := 17, b := 5, q => q);", "x", 3, POUS),
    case("3rd ed. 6.6.2.3 a function called as a statement", "a : INT := 1; b : INT := 2;",
        "Swap(a, b);", "a", 2, POUS),
    case("2.5.2.1 (6.6.3.4) a block keeps its state", "c : Counter; x : INT;",
        "c(step := 2); c(); x := c.total;", "x", 4, POUS),
    case("2.5.2.1 (6.6.3.4) an input keeps its last value", "c : Counter; x : INT;",
        "c(step := 5); c(); x := c.total;", "x", 10, POUS),
    case("2.5.2.1 (6.6.3.4) an input's initial value", "c : Counter; x : INT;",
        "c(); x := c.total;", "x", 1, POUS),
    case("2.5.2.1 (6.6.3.4) instances are independent", "c1, c2 : Counter; x : INT;",
        "c1(step := 1); c2(step := 10); x := c1.total;", "x", 1, POUS),
    case("2.5.2.1 (6.6.3.4) an output by =>", "c : Counter; x : INT;", "c(step := 3, total => x);",
        "x", 3, POUS),
    case("2.5.2.1 (6.6.3.4) a VAR_IN_OUT of a block", "c : Counter; v : INT := 5;",
        "c(step := 2, acc := v);", "v", 7, POUS),
    case("3rd ed. 6.6.3.4 an input set outside the call", "c : Counter; x : INT;",
        "c.step := 4; c(); x := c.total;", "x", 4, POUS),
    case("2.5.2.2 (6.6.3.2) a block inside a block", "l : Latch; x : BOOL;",
        "l(set := TRUE); l(set := TRUE); x := l.q;", "x", True, POUS),
    case("2.5.2 (6.6.3.3) an array of blocks", "cs : ARRAY[1..2] OF Counter; x : INT;",
        "cs[2](step := 6); x := cs[2].total;", "x", 6, POUS),
]  # fmt: skip

NUMERIC = [
    case("2.5.1.5.2 (6.6.2.5.8) ABS", "x : INT;", "x := ABS(-7);", "x", 7),
    case("2.5.1.5.2 (6.6.2.5.8) ABS of a real", "x : LREAL;", "x := ABS(-0.5);", "x", 0.5),
    case("2.5.1.5.2 (6.6.2.5.8) SQRT", "x : LREAL;", "x := SQRT(2.25);", "x", 1.5),
    case("2.5.1.5.2 (6.6.2.5.8) LN", "x : LREAL;", "x := LN(EXP(2.0));", "x", 2.0),
    case("2.5.1.5.2 (6.6.2.5.8) LOG", "x : LREAL;", "x := LOG(100.0);", "x", 2.0),
    case("2.5.1.5.2 (6.6.2.5.8) EXP", "x : LREAL;", "x := EXP(1.0);", "x", math.e),
    case("2.5.1.5.2 (6.6.2.5.8) SIN", "x : LREAL;", "x := SIN(0.5);", "x", math.sin(0.5)),
    case("2.5.1.5.2 (6.6.2.5.8) COS", "x : LREAL;", "x := COS(0.5);", "x", math.cos(0.5)),
    case("2.5.1.5.2 (6.6.2.5.8) TAN", "x : LREAL;", "x := TAN(0.5);", "x", math.tan(0.5)),
    case("2.5.1.5.2 (6.6.2.5.8) ASIN", "x : LREAL;", "x := ASIN(0.5);", "x", math.asin(0.5)),
    case("2.5.1.5.2 (6.6.2.5.8) ACOS", "x : LREAL;", "x := ACOS(0.5);", "x", math.acos(0.5)),
    case("2.5.1.5.2 (6.6.2.5.8) ATAN", "x : LREAL;", "x := ATAN(0.5);", "x", math.atan(0.5)),
    case("2.5.1.5.2 (6.6.2.5.8) SQRT of a REAL is a REAL", "x : LREAL; r : REAL := 2.0;",
        "x := SQRT(r);", "x", 1.4142135381698608),
    case("2.5.1.5.2 (6.6.2.5.8) ADD", "x : INT;", "x := ADD(2, 3);", "x", 5),
    case("2.5.1.5.2 (6.6.2.5.8) ADD extensible", "x : INT;", "x := ADD(1, 2, 3, 4);", "x", 10),
    case("2.5.1.5.2 (6.6.2.5.8) ADD named inputs", "x : INT;", "x := ADD(IN1 := 4, IN2 := 5);",
        "x", 9),
    case("2.5.1.5.2 (6.6.2.5.8) MUL extensible", "x : INT;", "x := MUL(2, 3, 4);", "x", 24),
    case("2.5.1.5.2 (6.6.2.5.8) SUB", "x : INT;", "x := SUB(10, 4);", "x", 6),
    case("2.5.1.5.2 (6.6.2.5.8) DIV", "x : INT;", "x := DIV(10, 4);", "x", 2),
    case("2.5.1.5.2 (6.6.2.5.8) DIV of reals", "x : LREAL;", "x := DIV(10.0, 4.0);", "x", 2.5),
    case("2.5.1.5.2 (6.6.2.5.8) MOD", "x : INT;", "x := MOD(10, 4);", "x", 2),
    case("2.5.1.5.2 (6.6.2.5.8) MOD by 0", "x : INT := 3; z : INT;", "x := MOD(10, z);", "x", 0),
    case("2.5.1.5.2 (6.6.2.5.8) EXPT", "x : LREAL;", "x := EXPT(2.0, 3);", "x", 8.0),
    case("2.5.1.5.2 (6.6.2.5.8) MOVE", "x : INT;", "x := MOVE(6);", "x", 6),
    case("2.5.1.4 (6.6.2.4) typed ADD_INT", "x : INT;", "x := ADD_INT(30000, 2767);", "x", 32767),
    case("2.5.1.4 (6.6.2.4) typed ADD_INT wraps", "x : DINT;", "x := ADD_INT(32767, 1);", "x",
        -32768),
    case("2.5.1.4 (6.6.2.4) typed MUL_REAL", "x : LREAL;", "x := MUL_REAL(0.1, 1.0);", "x", R01),
    case("2.5.1.4 (6.6.2.4) typed GT_DINT", "x : BOOL;", "x := GT_DINT(3, 2);", "x", True),
]  # fmt: skip

BITS = [
    case("2.5.1.5.3 (6.6.2.5.9) SHL", "x : BYTE;", "x := SHL(BYTE#16#81, 1);", "x", 0x02),
    case("2.5.1.5.3 (6.6.2.5.9) SHR", "x : BYTE;", "x := SHR(BYTE#16#81, 1);", "x", 0x40),
    case("2.5.1.5.3 (6.6.2.5.9) ROL", "x : BYTE;", "x := ROL(BYTE#16#81, 1);", "x", 0x03),
    case("2.5.1.5.3 (6.6.2.5.9) ROR", "x : BYTE;", "x := ROR(BYTE#16#81, 1);", "x", 0xC0),
    case("2.5.1.5.3 (6.6.2.5.9) SHL named", "x : WORD;", "x := SHL(IN := WORD#1, N := 15);", "x",
        0x8000),
    case("2.5.1.5.3 (6.6.2.5.9) SHR fills with zeros", "x : WORD;", "x := SHR(WORD#16#8000, 15);",
        "x", 1),
    case("2.5.1.5.3 (6.6.2.5.9) ROL of a DWORD", "x : DWORD;", "x := ROL(DWORD#16#80000001, 4);",
        "x", 0x18),
    case("2.5.1.5.3 (6.6.2.5.10) AND", "x : WORD;", "x := AND(WORD#16#FF0F, WORD#16#0FF0);", "x",
        0x0F00),
    case("2.5.1.5.3 (6.6.2.5.10) OR extensible", "x : BYTE;", "x := OR(BYTE#1, BYTE#2, BYTE#4);",
        "x", 7),
    case("2.5.1.5.3 (6.6.2.5.10) XOR", "x : BYTE;", "x := XOR(BYTE#16#FF, BYTE#16#0F);", "x", 0xF0),
    case("2.5.1.5.3 (6.6.2.5.10) NOT", "x : BYTE;", "x := NOT BYTE#16#0F;", "x", 0xF0),
    case("2.5.1.5.3 (6.6.2.5.10) AND of BOOLs", "x : BOOL;", "x := AND(TRUE, TRUE, TRUE);", "x",
        True),
    case("2.5.1.5.3 (6.6.2.5.10) XOR of BOOLs", "x : BOOL;", "x := XOR(TRUE, TRUE);", "x", False),
]  # fmt: skip

SELECTION = [
    case("2.5.1.5.4 (6.6.2.5.11) SEL", "x : INT;", "x := SEL(TRUE, 1, 2);", "x", 2),
    case("2.5.1.5.4 (6.6.2.5.11) SEL named", "x : INT;",
        "x := SEL(G := FALSE, IN0 := 1, IN1 := 2);", "x", 1),
    case("2.5.1.5.4 (6.6.2.5.11) MAX", "x : INT;", "x := MAX(3, 9, -1);", "x", 9),
    case("2.5.1.5.4 (6.6.2.5.11) MIN", "x : INT;", "x := MIN(3, 9, -1);", "x", -1),
    case("2.5.1.5.4 (6.6.2.5.11) MAX of TIME", "x : TIME;", "x := MAX(T#1s, T#2s);", "x", 2000),
    case("2.5.1.5.4 (6.6.2.5.11) LIMIT above", "x : INT;", "x := LIMIT(0, 15, 10);", "x", 10),
    case("2.5.1.5.4 (6.6.2.5.11) LIMIT below", "x : INT;", "x := LIMIT(0, -3, 10);", "x", 0),
    case("2.5.1.5.4 (6.6.2.5.11) LIMIT inside", "x : LREAL;", "x := LIMIT(0.0, 2.5, 10.0);", "x",
        2.5),
    case("2.5.1.5.4 (6.6.2.5.11) MUX", "x : INT; k : INT := 1;", "x := MUX(k, 10, 20, 30);", "x",
        20),
    case("2.5.1.5.4 (6.6.2.5.12) GT", "x : BOOL;", "x := GT(2, 1);", "x", True),
    case("2.5.1.5.4 (6.6.2.5.12) GT extensible, ordered", "x : BOOL;", "x := GT(3, 2, 1);", "x",
        True),
    case("2.5.1.5.4 (6.6.2.5.12) GT extensible, not ordered", "x : BOOL;", "x := GT(3, 1, 2);",
        "x", False),
    case("2.5.1.5.4 (6.6.2.5.12) GE extensible", "x : BOOL;", "x := GE(3, 3, 2);", "x", True),
    case("2.5.1.5.4 (6.6.2.5.12) EQ extensible", "x : BOOL;", "x := EQ(2, 2, 2);", "x", True),
    case("2.5.1.5.4 (6.6.2.5.12) LE", "x : BOOL;", "x := LE(1, 1, 2);", "x", True),
    case("2.5.1.5.4 (6.6.2.5.12) LT", "x : BOOL;", "x := LT(1, 1);", "x", False),
    case("2.5.1.5.4 (6.6.2.5.12) NE", "x : BOOL;", "x := NE(1, 2);", "x", True),
    case("2.5.1.5.7 (6.6.2.5.16) EQ of enumeration values", "x : BOOL; c : Color := Red;",
        "x := EQ(c, Red);", "x", True, "TYPE Color : (Red, Green); END_TYPE"),
    case("2.5.1.5.7 (6.6.2.5.16) SEL of enumeration values", "c : Color;",
        "c := SEL(TRUE, Red, Green);", "c", 1, "TYPE Color : (Red, Green); END_TYPE"),
    case("2.5.1.5.7 (6.6.2.5.16) MUX of enumeration values", "c : Color; k : INT := 1;",
        "c := MUX(k, Red, Green);", "c", 1, "TYPE Color : (Red, Green); END_TYPE"),
]  # fmt: skip

STRINGS = [
    case("2.5.1.5.5 (6.6.2.5.13) LEN", "x : INT;", "x := LEN('ASTRING');", "x", 7),
    case("2.5.1.5.5 (6.6.2.5.13) LEN of ''", "x : INT := 9;", "x := LEN('');", "x", 0),
    case("2.5.1.5.5 (6.6.2.5.13) LEFT", "s : STRING;", "s := LEFT(IN := 'ASTR', L := 3);", "s",
        "AST"),
    case("2.5.1.5.5 (6.6.2.5.13) RIGHT", "s : STRING;", "s := RIGHT(IN := 'ASTR', L := 3);", "s",
        "STR"),
    case("2.5.1.5.5 (6.6.2.5.13) MID", "s : STRING;", "s := MID(IN := 'ASTR', L := 2, P := 2);",
        "s", "ST"),
    case("2.5.1.5.5 (6.6.2.5.13) CONCAT", "s : STRING;", "s := CONCAT('AB', 'CD', 'E');", "s",
        "ABCDE"),
    case("2.5.1.5.5 (6.6.2.5.13) INSERT", "s : STRING;",
        "s := INSERT(IN1 := 'ABC', IN2 := 'XY', P := 2);", "s", "ABXYC"),
    case("2.5.1.5.5 (6.6.2.5.13) DELETE", "s : STRING;",
        "s := DELETE(IN := 'ABXYC', L := 2, P := 3);", "s", "ABC"),
    case("2.5.1.5.5 (6.6.2.5.13) REPLACE", "s : STRING;",
        "s := REPLACE(IN1 := 'ABCDE', IN2 := 'X', L := 2, P := 3);", "s", "ABXE"),
    case("2.5.1.5.5 (6.6.2.5.13) FIND", "x : INT;", "x := FIND(IN1 := 'ABCBC', IN2 := 'BC');", "x",
        2),
    case("2.5.1.5.5 (6.6.2.5.13) FIND absent", "x : INT := 5;", "x := FIND('ABC', 'Z');", "x", 0),
    case("2.5.1.5.5 (6.6.2.5.13) = on strings", "x : BOOL; s : STRING := 'ab';", "x := s = 'ab';",
        "x", True),
    case("2.5.1.5.5 (6.6.2.5.13) > on strings", "x : BOOL;", "x := 'b' > 'abc';", "x", True),
]  # fmt: skip

CONVERSIONS = [
    case("2.5.1.5.1 (6.6.2.5.3) INT_TO_REAL", "x : REAL;", "x := INT_TO_REAL(-3);", "x", -3.0),
    case("2.5.1.5.1 (6.6.2.5.3) REAL_TO_INT rounds", "x : INT;", "x := REAL_TO_INT(2.7);", "x", 3),
    case("2.5.1.5.1 (6.6.2.5.3) REAL_TO_INT rounds halves to even", "x : INT;",
        "x := REAL_TO_INT(2.5);", "x", 2),
    case("2.5.1.5.1 (6.6.2.5.3) REAL_TO_INT of -1.5", "x : INT;", "x := REAL_TO_INT(-1.5);", "x",
        -2),
    case("2.5.1.5.1 (6.6.2.5.3) LREAL_TO_DINT", "x : DINT;", "x := LREAL_TO_DINT(-1234.4);", "x",
        -1234),
    case("2.5.1.5.1 (6.6.2.5.3) DINT_TO_INT wraps", "x : INT;", "x := DINT_TO_INT(65537);", "x", 1),
    case("2.5.1.5.1 (6.6.2.5.3) INT_TO_UINT", "x : UINT;", "x := INT_TO_UINT(-1);", "x", 65535),
    case("2.5.1.5.1 (6.6.2.5.3) TO_DINT (3rd ed. overloaded)", "x : DINT;", "x := TO_DINT(7.6);",
        "x", 8),
    case("2.5.1.5.1 (6.6.2.5.2) TRUNC toward zero", "x : DINT;", "x := TRUNC(-7.9);", "x", -7),
    case("3rd ed. 6.6.2.5.2 TRUNC_INT", "x : INT;", "x := TRUNC_INT(7.9);", "x", 7),
    case("3rd ed. 6.6.2.5.2 REAL_TRUNC_DINT", "x : DINT;", "x := REAL_TRUNC_DINT(-2.5);", "x", -2),
    case("2.5.1.5.1 (6.6.2.5.5) BOOL_TO_INT", "x : INT;", "x := BOOL_TO_INT(TRUE);", "x", 1),
    case("2.5.1.5.1 (6.6.2.5.5) INT_TO_BOOL", "x : BOOL;", "x := INT_TO_BOOL(-3);", "x", True),
    case("2.5.1.5.1 (6.6.2.5.4) BYTE_TO_WORD", "x : WORD;", "x := BYTE_TO_WORD(16#FF);", "x", 0xFF),
    case("2.5.1.5.1 (6.6.2.5.4) WORD_TO_BYTE keeps the low bits", "x : BYTE;",
        "x := WORD_TO_BYTE(16#1234);", "x", 0x34),
    case("2.5.1.5.1 (6.6.2.5.5) DWORD_TO_DINT", "x : DINT;", "x := DWORD_TO_DINT(16#FFFFFFFF);",
        "x", -1),
    case("2.5.1.5.1 (6.6.2.5.7) INT_TO_STRING", "s : STRING;", "s := INT_TO_STRING(-42);", "s",
        "-42"),
    case("2.5.1.5.1 (6.6.2.5.7) STRING_TO_INT", "x : INT;", "x := STRING_TO_INT('123');", "x", 123),
    case("2.5.1.5.1 (6.6.2.5.7) REAL_TO_STRING at REAL precision", "s : STRING;",
        "s := REAL_TO_STRING(REAL#0.1);", "s", "0.1"),
    case("2.5.1.5.1 (6.6.2.5.7) LREAL_TO_STRING", "s : STRING;", "s := LREAL_TO_STRING(2.5);", "s",
        "2.5"),
    case("2.5.1.5.1 (6.6.2.5.7) STRING_TO_REAL", "x : LREAL;", "x := STRING_TO_LREAL('2.5');", "x",
        2.5),
    case("2.5.1.5.1 (6.6.2.5.7) BOOL_TO_STRING", "s : STRING;", "s := BOOL_TO_STRING(FALSE);", "s",
        "FALSE"),
    case("2.5.1.5.1 (6.6.2.5.6) TIME_TO_DINT", "x : DINT;", "x := TIME_TO_DINT(T#2s);", "x", 2000),
    case("2.5.1.5.1 (6.6.2.5.6) DINT_TO_TIME", "x : TIME;", "x := DINT_TO_TIME(1500);", "x", 1500),
    case("2.5.1.5.1 (6.6.2.5.7) TIME_TO_STRING", "s : STRING;", "s := TIME_TO_STRING(T#1m5s);",
        "s", "T#1m5s"),
    case("2.5.1.5.6 (6.6.2.5.6) DT_TO_DATE", "d : DATE;",
        "d := DT_TO_DATE(DT#1970-01-02-10:00:00);", "d", 86_400_000),
    case("2.5.1.5.6 (6.6.2.5.6) DT_TO_TOD", "t : TOD;", "t := DT_TO_TOD(DT#1970-01-02-10:00:00);",
        "t", 36_000_000),
    case("2.5.1.5.1 (6.6.2.5.7) DATE_TO_STRING", "s : STRING;",
        "s := DATE_TO_STRING(D#2024-02-29);", "s", "D#2024-02-29"),
    case("2.5.1.5.1 (6.6.2.5.7) TOD_TO_STRING", "s : STRING;", "s := TOD_TO_STRING(TOD#8:05:09);",
        "s", "TOD#08:05:09"),
    case("2.5.1.5.1 (6.6.2.5.7) DT_TO_STRING", "s : STRING;",
        "s := DT_TO_STRING(DT#2024-02-29-23:59:59);", "s", "DT#2024-02-29-23:59:59"),
    case("2.5.1.5.1 (6.6.2.5.3) an enumeration to an integer", "x : INT; c : Color := Blue;",
        "x := TO_INT(c);", "x", 2, "TYPE Color : (Red, Green, Blue); END_TYPE"),
]  # fmt: skip

TIMES = [
    case("2.5.1.5.6 (6.6.2.5.14) TIME + TIME", "t : TIME;", "t := T#1s + T#500ms;", "t", 1500),
    case("2.5.1.5.6 (6.6.2.5.14) ADD_TIME", "t : TIME;", "t := ADD_TIME(T#1s, T#2s);", "t", 3000),
    case("2.5.1.5.6 (6.6.2.5.14) SUB_TIME", "t : TIME;", "t := SUB_TIME(T#1s, T#2s);", "t", -1000),
    case("2.5.1.5.6 (6.6.2.5.14) TIME * number", "t : TIME;", "t := T#1s * 2.5;", "t", 2500),
    case("2.5.1.5.6 (6.6.2.5.14) MULTIME", "t : TIME;", "t := MULTIME(T#2s, 3);", "t", 6000),
    case("3rd ed. 6.6.2.5.14 MUL_TIME", "t : TIME;", "t := MUL_TIME(T#2s, 3);", "t", 6000),
    case("2.5.1.5.6 (6.6.2.5.14) DIVTIME", "t : TIME;", "t := DIVTIME(T#3s, 2);", "t", 1500),
    case("2.5.1.5.6 (6.6.2.5.14) TOD + TIME", "t : TOD;", "t := TOD#10:00 + T#90m;", "t",
        41_400_000),
    case("2.5.1.5.6 (6.6.2.5.14) ADD_TOD_TIME", "t : TOD;", "t := ADD_TOD_TIME(TOD#10:00, T#1s);",
        "t", 36_001_000),
    case("2.5.1.5.6 (6.6.2.5.14) DT + TIME", "t : DT;", "t := DT#1970-01-01-00:00:00 + T#1d;", "t",
        86_400_000),
    case("2.5.1.5.6 (6.6.2.5.14) ADD_DT_TIME", "t : DT;",
        "t := ADD_DT_TIME(DT#1970-01-01-23:00:00, T#2h);", "t", 90_000_000),
    case("2.5.1.5.6 (6.6.2.5.14) DATE - DATE", "t : TIME;", "t := D#1970-01-03 - D#1970-01-01;",
        "t", 172_800_000),
    case("2.5.1.5.6 (6.6.2.5.14) SUB_DATE_DATE", "t : TIME;",
        "t := SUB_DATE_DATE(D#1970-01-02, D#1970-01-01);", "t", 86_400_000),
    case("2.5.1.5.6 (6.6.2.5.14) TOD - TIME", "t : TOD;", "t := TOD#10:00 - T#1h;", "t",
        32_400_000),
    case("2.5.1.5.6 (6.6.2.5.14) TOD - TOD", "t : TIME;", "t := TOD#10:00 - TOD#09:30;", "t",
        1_800_000),
    case("2.5.1.5.6 (6.6.2.5.14) SUB_TOD_TOD", "t : TIME;",
        "t := SUB_TOD_TOD(TOD#09:30, TOD#10:00);", "t", -1_800_000),
    case("2.5.1.5.6 (6.6.2.5.14) DT - TIME", "t : DT;", "t := DT#1970-01-02-00:00:00 - T#1h;", "t",
        82_800_000),
    case("2.5.1.5.6 (6.6.2.5.14) DT - DT", "t : TIME;",
        "t := DT#1970-01-02-00:00:00 - DT#1970-01-01-12:00:00;", "t", 43_200_000),
    case("2.5.1.5.6 (6.6.2.5.14) SUB_DT_DT", "t : TIME;",
        "t := SUB_DT_DT(DT#1970-01-01-00:00:10, DT#1970-01-01-00:00:00);", "t", 10_000),
    case("2.5.1.5.6 (6.6.2.5.14) CONCAT_DATE_TOD", "t : DT;",
        "t := CONCAT_DATE_TOD(D#1970-01-02, TOD#01:00);", "t", 90_000_000),
    case("2.5.1.5.6 (6.6.2.5.14) a TOD past midnight", "t : TOD;", "t := TOD#23:00 + T#2h;", "t",
        3_600_000),
    case("2.3.1 (6.4.2) DATEs compared", "x : BOOL;", "x := D#2024-01-01 < D#2024-01-02;", "x",
        True),
    case("2.3.1 (6.4.2) TODs compared", "x : BOOL;", "x := TOD#12:00 = TOD#12:00:00;", "x", True),
]  # fmt: skip

BLOCKS = [
    case("2.5.2.3.1 (6.6.3.5.2) SR set", "s : SR; q : BOOL;",
        "s(S1 := TRUE, R := FALSE); q := s.Q1;", "q", True),
    case("2.5.2.3.1 (6.6.3.5.2) SR set dominant", "s : SR; q : BOOL;",
        "s(S1 := TRUE, R := TRUE); q := s.Q1;", "q", True),
    case("2.5.2.3.1 (6.6.3.5.2) SR holds", "s : SR; q : BOOL;",
        "s(S1 := TRUE); s(S1 := FALSE); q := s.Q1;", "q", True),
    case("2.5.2.3.1 (6.6.3.5.2) RS reset dominant", "s : RS; q : BOOL;",
        "s(S := TRUE, R1 := TRUE); q := s.Q1;", "q", False),
    case("2.5.2.3.1 (6.6.3.5.2) RS set", "s : RS; q : BOOL;",
        "s(S := TRUE, R1 := FALSE); q := s.Q1;", "q", True),
    case("2.5.2.3.2 (6.6.3.5.3) R_TRIG on the edge", "r : R_TRIG; q : BOOL;",
        "r(CLK := TRUE); q := r.Q;", "q", True),
    case("2.5.2.3.2 (6.6.3.5.3) R_TRIG one call only", "r : R_TRIG; q : BOOL;",
        "r(CLK := TRUE); r(CLK := TRUE); q := r.Q;", "q", False),
    case("2.5.2.3.2 (6.6.3.5.3) F_TRIG no edge at start", "f : F_TRIG; q : BOOL;",
        "f(CLK := FALSE); q := f.Q;", "q", False),
    case("2.5.2.3.2 (6.6.3.5.3) F_TRIG on the edge", "f : F_TRIG; q : BOOL;",
        "f(CLK := TRUE); f(CLK := FALSE); q := f.Q;", "q", True),
    case("2.5.2.3.3 (6.6.3.5.4) CTU counts edges", "c : CTU; v : INT;",
        "c(CU := TRUE); c(CU := FALSE); c(CU := TRUE); v := c.CV;", "v", 2),
    case("2.5.2.3.3 (6.6.3.5.4) CTU Q at PV", "c : CTU; q : BOOL;",
        "c(CU := TRUE, PV := 1); q := c.Q;", "q", True),
    case("2.5.2.3.3 (6.6.3.5.4) CTU reset", "c : CTU; v : INT;",
        "c(CU := TRUE); c(CU := FALSE, R := TRUE); v := c.CV;", "v", 0),
    case("2.5.2.3.3 (6.6.3.5.4) CTD load", "c : CTD; v : INT;",
        "c(LD := TRUE, PV := 5); v := c.CV;", "v", 5),
    case("2.5.2.3.3 (6.6.3.5.4) CTD counts down", "c : CTD; v : INT;",
        "c(LD := TRUE, PV := 5); c(LD := FALSE, CD := TRUE); v := c.CV;", "v", 4),
    case("2.5.2.3.3 (6.6.3.5.4) CTD Q at 0", "c : CTD; q : BOOL;",
        "c(LD := TRUE, PV := 1); c(LD := FALSE, CD := TRUE); q := c.Q;", "q", True),
    case("2.5.2.3.3 (6.6.3.5.4) CTUD up", "c : CTUD; v : INT;", "c(CU := TRUE); v := c.CV;", "v",
        1),
    case("2.5.2.3.3 (6.6.3.5.4) CTUD QD", "c : CTUD; q : BOOL;", "c(CD := TRUE); q := c.QD;", "q",
        True),
    case("2.5.2.3.3 (6.6.3.5.4) CTUD both edges: no change", "c : CTUD; v : INT;",
        "c(CU := TRUE, CD := TRUE); v := c.CV;", "v", 0),
    case("3rd ed. 6.6.3.5.4 CTU_DINT", "c : CTU_DINT; v : DINT;",
        "c(CU := TRUE, PV := 70000); v := c.CV;", "v", 1),
    case("3rd ed. 6.6.3.5.4 CTD_UDINT", "c : CTD_UDINT; v : UDINT;",
        "c(LD := TRUE, PV := 4000000000); v := c.CV;", "v", 4_000_000_000),
    case("2.5.2.3.4 (6.6.3.5.5) TON Q waits", "t : TON; q : BOOL;",
        "t(IN := TRUE, PT := T#50ms); q := t.Q;", "q", False),
    case("2.5.2.3.4 (6.6.3.5.5) TON ET starts at 0", "t : TON; e : TIME;",
        "t(IN := TRUE, PT := T#50ms, ET => e);", "e", 0),
    case("2.5.2.3.4 (6.6.3.5.5) TON of PT 0", "t : TON; q : BOOL;",
        "t(IN := TRUE, PT := T#0s); q := t.Q;", "q", True),
    case("2.5.2.3.4 (6.6.3.5.5) TOF Q with IN", "t : TOF; q : BOOL;",
        "t(IN := TRUE, PT := T#50ms); q := t.Q;", "q", True),
    case("2.5.2.3.4 (6.6.3.5.5) TP pulse starts", "t : TP; q : BOOL;",
        "t(IN := TRUE, PT := T#50ms); q := t.Q;", "q", True),
]  # fmt: skip

TIMED = [
    # (clause, declarations, statements, scans of 10 ms, variable, expected)
    ("2.5.2.3.4 (6.6.3.5.5) TON Q after PT", "t : TON; q : BOOL;",
        "t(IN := TRUE, PT := T#50ms); q := t.Q;", 6, "q", True),
    ("2.5.2.3.4 (6.6.3.5.5) TON ET stops at PT", "t : TON; e : TIME;",
        "t(IN := TRUE, PT := T#30ms); e := t.ET;", 9, "e", 30),
    ("2.5.2.3.4 (6.6.3.5.5) TON reset by IN", "t : TON; n : INT; q : BOOL;",
        "n := n + 1; t(IN := n < 9, PT := T#30ms); q := t.Q;", 9, "q", False),
    ("2.5.2.3.4 (6.6.3.5.5) TOF Q falls after PT", "t : TOF; n : INT; q : BOOL;",
        "n := n + 1; t(IN := n = 1, PT := T#30ms); q := t.Q;", 5, "q", False),
    ("2.5.2.3.4 (6.6.3.5.5) TOF Q holds within PT", "t : TOF; n : INT; q : BOOL;",
        "n := n + 1; t(IN := n = 1, PT := T#30ms); q := t.Q;", 3, "q", True),
    ("2.5.2.3.4 (6.6.3.5.5) TP lasts PT", "t : TP; q : BOOL;",
        "t(IN := TRUE, PT := T#30ms); q := t.Q;", 3, "q", True),
    ("2.5.2.3.4 (6.6.3.5.5) TP ends after PT", "t : TP; q : BOOL;",
        "t(IN := TRUE, PT := T#30ms); q := t.Q;", 4, "q", False),
    ("2.5.2.3.4 (6.6.3.5.5) TP ignores IN meanwhile", "t : TP; n : INT; q : BOOL;",
        "n := n + 1; t(IN := n = 1, PT := T#30ms); q := t.Q;", 3, "q", True),
    ("2.5.3 (6.6.4) a PROGRAM keeps its variables", "n : INT;", "n := n + 1;", 4, "n", 4),
    ("2.5.2.3.2 (6.6.3.5.3) R_TRIG every rising edge", "r : R_TRIG; k, n : INT;",
        "k := k + 1; r(CLK := k MOD 2 = 1); IF r.Q THEN n := n + 1; END_IF", 6, "n", 3),
]  # fmt: skip


@pytest.mark.parametrize(
    ("decls", "body", "name", "expected", "before"),
    [
        *EXPRESSIONS,
        *STATEMENTS,
        *POU_CASES,
        *NUMERIC,
        *BITS,
        *SELECTION,
        *STRINGS,
        *CONVERSIONS,
        *TIMES,
        *BLOCKS,
    ],
)
def test_iec_language(decls, body, name, expected, before):
    prog = run(program(decls, body, before))
    assert same(getattr(prog, name), expected), getattr(prog, name)


@pytest.mark.parametrize(
    ("decls", "body", "scans", "name", "expected"),
    [pytest.param(*c[1:], id=c[0]) for c in TIMED],
)
def test_iec_over_scans(decls, body, scans, name, expected):
    prog = run(program(decls, body), scans=scans)
    assert same(getattr(prog, name), expected), getattr(prog, name)


TASKED = """
PROGRAM fast
VAR n : INT; END_VAR
n := n + 1;
END_PROGRAM
CONFIGURATION plant
  RESOURCE cpu ON PLC
    TASK cyclic(INTERVAL := T#20ms, PRIORITY := 1);
    PROGRAM main WITH cyclic : fast;
  END_RESOURCE
END_CONFIGURATION
"""


def test_a_task_runs_its_program_at_its_interval():
    """2.7.2 (6.8.2): a cyclic TASK runs its PROGRAM every INTERVAL (here every 2nd scan of
    10 ms)."""
    prog = run(TASKED, scans=6)
    assert prog.n == 3 and prog.every == 2
