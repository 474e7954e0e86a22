"""IEC 61131-3 conformance, data: the common elements, literals, data types and variables
(2nd edition clauses 2.1-2.4, 3rd edition 6.1-6.5). Each case names its clause; the expected
value is the standard's (where it leaves the value to the implementation: CODESYS's and
TwinCAT's, see docs/st.md)."""

from __future__ import annotations

import math

import pytest

from tests.plc.st.iec import case, program, run, same

R01 = 0.10000000149011612
"""0.1 as a 32-bit REAL."""

DAY = 86_400_000
"""A day [ms]: DATE, TIME_OF_DAY and DATE_AND_TIME are held in ms."""

D0001 = -719_162 * DAY
"""D#0001-01-01 (IEC's initial DATE) in ms from 1970-01-01."""

DERIVED = """
TYPE
  Color : (Red, Green, Blue);
  Level : (Low := 10, Mid := 20, High := 30);
  Small : INT (-5..5);
  Percent : INT (0..100) := 50;
  Vec3 : ARRAY[1..3] OF LREAL;
  Grid : ARRAY[0..1, 1..2] OF INT := [1, 2, 3, 4];
  Point : STRUCT x : INT; y : INT := 7; END_STRUCT;
  Line : STRUCT a : Point; b : Point := (x := 1, y := 2); END_STRUCT;
  Name : STRING(8) := 'anon';
  Count : UINT := 3;
  Counts : ARRAY[1..4] OF Count;
  Speed : LREAL := 1.5;
  Tagged : STRUCT c : Color := Blue; n : Count; END_STRUCT;
END_TYPE
"""
"""Derived types of the cases that use them (2.3.3, 3rd ed. 6.4.4)."""

COMMON = [
    case("2.1.1 (6.1.1) keywords in lower case", "x : int;", "if true then x := 1; end_if", "x", 1),
    case("2.1.1 (6.1.1) keywords in mixed case", "x : Int;", "If TRUE Then x := 2; End_If", "x", 2),
    case("2.1.2 (6.1.2) names are case-insensitive", "Count : INT;",
        "COUNT := 3; count := count + 1;", "Count", 4),
    case("2.1.2 (6.1.2) a name may start with _", "_a1 : INT;", "_a1 := 5;", "_a1", 5),
    case("2.1.2 (6.1.2) underscores inside a name", "a_b_c : INT;", "a_b_c := 6;", "a_b_c", 6),
    case("2.1.3 (6.1.3) REFERENCE is no keyword", "reference : INT;", "reference := 7;",
        "reference", 7),
    case("2.1.5 (6.1.5) a comment between tokens", "x : INT;", "x := (* one *) 8 (* two *);", "x",
        8),
    case("2.1.5 (6.1.5) a comment over lines", "x : INT;", "(* a\ncomment *) x := 9;", "x", 9),
    case("3rd ed. 6.1.5 Table 3 1 // comment", "x : INT;", "x := 10; // x := 11;", "x", 10),
    case("3rd ed. 6.1.5 Table 3 3a nested comment", "x : INT;", "(* a (* b *) c *) x := 12;", "x",
        12),
    case("2.1.6 (6.2) a pragma is ignored", "x : INT;", "{attribute 'x'} x := 13;", "x", 13),
]  # fmt: skip

LITERALS = [
    case("2.2.1 (6.3.2) Table 5 1 integer", "x : DINT;", "x := 12345;", "x", 12345),
    case("2.2.1 (6.3.2) Table 5 1 signed integer", "x : DINT;", "x := -12;", "x", -12),
    case("2.2.1 (6.3.2) Table 5 1 single underscores", "x : DINT;", "x := 1_000_000;", "x",
        1_000_000),
    case("2.2.1 (6.3.2) Table 5 2 real", "x : LREAL;", "x := -12.5;", "x", -12.5),
    case("2.2.1 (6.3.2) Table 5 3 real with exponent", "x : LREAL;", "x := 1.0E+6;", "x", 1e6),
    case("2.2.1 (6.3.2) Table 5 3 negative exponent", "x : LREAL;", "x := 1.5e-3;", "x", 0.0015),
    case("2.2.1 (6.3.2) Table 5 3 exponent of an integer", "x : LREAL;", "x := 2E3;", "x", 2000.0),
    case("2.2.1 (6.3.2) Table 5 4 base 2", "x : INT;", "x := 2#1111_1111;", "x", 255),
    case("2.2.1 (6.3.2) Table 5 5 base 8", "x : INT;", "x := 8#377;", "x", 255),
    case("2.2.1 (6.3.2) Table 5 6 base 16", "x : INT;", "x := 16#FF;", "x", 255),
    case("2.2.1 (6.3.2) Table 5 6 base 16 lower case", "x : INT;", "x := 16#ff;", "x", 255),
    case("2.2.1 (6.3.2) Table 5 7 BOOL 0 and 1", "x : BOOL;", "x := BOOL#1;", "x", True),
    case("2.2.1 (6.3.2) Table 5 7 FALSE", "x : BOOL := TRUE;", "x := FALSE;", "x", False),
    case("2.2.1 (6.3.2) Table 5 8 typed integer", "x : INT;", "x := INT#-5;", "x", -5),
    case("2.2.1 (6.3.2) Table 5 8 typed hex", "x : WORD;", "x := WORD#16#ABCD;", "x", 0xABCD),
    case("2.2.1 (6.3.2) Table 5 8 typed real", "x : LREAL;", "x := REAL#0.1;", "x", R01),
    case("2.2.1 (6.3.2) Table 5 8 typed BOOL", "x : BOOL;", "x := BOOL#TRUE;", "x", True),
    case("2.2.2 (6.3.3) Table 6 empty string", "s : STRING := 'x';", "s := '';", "s", ""),
    case("2.2.2 (6.3.3) Table 6 a string", "s : STRING;", "s := 'A';", "s", "A"),
    case("2.2.2 (6.3.3) Table 6 blank", "s : STRING;", "s := ' ';", "s", " "),
    case("2.2.2 (6.3.3) Table 6 $' a quote", "s : STRING;", "s := '$'';", "s", "'"),
    case("2.2.2 (6.3.3) Table 6 a double quote", "s : STRING;", "s := '\"';", "s", '"'),
    case("2.2.2 (6.3.3) Table 7 $$ a dollar", "s : STRING;", "s := '$$';", "s", "$"),
    case("2.2.2 (6.3.3) Table 7 $L line feed", "s : STRING;", "s := '$L';", "s", "\n"),
    case("2.2.2 (6.3.3) Table 7 $N newline", "s : STRING;", "s := '$N';", "s", "\n"),
    case("2.2.2 (6.3.3) Table 7 $P form feed", "s : STRING;", "s := '$P';", "s", "\f"),
    case("2.2.2 (6.3.3) Table 7 $R carriage return", "s : STRING;", "s := '$R';", "s", "\r"),
    case("2.2.2 (6.3.3) Table 7 $T tab", "s : STRING;", "s := '$T';", "s", "\t"),
    case("2.2.2 (6.3.3) Table 7 lower-case escape", "s : STRING;", "s := '$t';", "s", "\t"),
    case("2.2.2 (6.3.3) Table 6 $hh a code", "s : STRING;", "s := '$0A$41';", "s", "\nA"),
    case("3rd ed. 6.3.3 typed STRING# literal", "s : STRING;", "s := STRING#'typed';", "s",
        "typed"),
    case("2.2.3.1 (6.3.4) Table 8 T#", "t : TIME;", "t := T#14ms;", "t", 14),
    case("2.2.3.1 (6.3.4) Table 8 TIME#", "t : TIME;", "t := TIME#14.7s;", "t", 14700),
    case("2.2.3.1 (6.3.4) Table 8 lower-case t#", "t : TIME;", "t := t#5m;", "t", 300000),
    case("2.2.3.1 (6.3.4) Table 8 negative", "t : TIME;", "t := T#-14ms;", "t", -14),
    case("2.2.3.1 (6.3.4) Table 8 fraction of minutes", "t : TIME;", "t := T#14.7m;", "t", 882000),
    case("2.2.3.1 (6.3.4) Table 8 fraction of hours", "t : TIME;", "t := T#1.5h;", "t", 5400000),
    case("2.2.3.1 (6.3.4) Table 8 fraction of days", "t : TIME;", "t := T#0.5d;", "t", 43200000),
    case("2.2.3.1 (6.3.4) Table 8 all units", "t : TIME;", "t := T#1d2h3m4s5ms;", "t", 93784005),
    case("2.2.3.1 (6.3.4) Table 8 underscores", "t : TIME;", "t := T#1h_2m;", "t", 3720000),
    case("2.2.3.1 (6.3.4) Table 8 an overflowing unit", "t : TIME;", "t := T#25h;", "t", 90000000),
    case("3rd ed. 6.3.4 Table 8 LTIME# in ns", "t : LTIME;", "t := LTIME#5us;", "t", 5000),
    case("2.2.3.2 (6.3.5) Table 9 D#", "d : DATE;", "d := D#1970-01-02;", "d", DAY),
    case("2.2.3.2 (6.3.5) Table 9 DATE#", "d : DATE;", "d := DATE#2000-03-01;", "d", 11017 * DAY),
    case("2.2.3.2 (6.3.5) Table 9 TOD#", "t : TOD;", "t := TOD#15:36:30;", "t", 56190000),
    case("2.2.3.2 (6.3.5) Table 9 TIME_OF_DAY# fraction", "t : TOD;",
        "t := TIME_OF_DAY#00:00:01.5;", "t", 1500),
    case("2.2.3.2 (6.3.5) Table 9 DT#", "t : DT;", "t := DT#1970-01-01-00:01:00;", "t", 60000),
    case("2.2.3.2 (6.3.5) Table 9 DATE_AND_TIME#", "t : DT;",
        "t := DATE_AND_TIME#1970-01-02-00:00:00;", "t", DAY),
]  # fmt: skip

ELEMENTARY = [
    case("2.3.1 (6.4.2) Table 10 BOOL", "x : BOOL;", "x := NOT x;", "x", True),
    case("2.3.1 (6.4.2) Table 10 SINT largest", "x : SINT := 127;", "", "x", 127),
    case("2.3.1 (6.4.2) Table 10 SINT smallest", "x : SINT := -128;", "", "x", -128),
    case("2.3.1 (6.4.2) Table 10 INT largest", "x : INT := 32767;", "", "x", 32767),
    case("2.3.1 (6.4.2) Table 10 DINT smallest", "x : DINT := -2147483648;", "", "x", -(2**31)),
    case("2.3.1 (6.4.2) Table 10 LINT largest", "x : LINT := 9223372036854775807;", "", "x",
        2**63 - 1),
    case("2.3.1 (6.4.2) Table 10 USINT largest", "x : USINT := 255;", "", "x", 255),
    case("2.3.1 (6.4.2) Table 10 UINT largest", "x : UINT := 65535;", "", "x", 65535),
    case("2.3.1 (6.4.2) Table 10 UDINT largest", "x : UDINT := 4294967295;", "", "x", 2**32 - 1),
    case("2.3.1 (6.4.2) Table 10 ULINT largest", "x : ULINT := 18446744073709551615;", "", "x",
        2**64 - 1),
    case("2.3.1 (6.4.2) Table 10 REAL is 32 bits", "x : REAL;", "x := 1.0 / 3.0;", "x",
        0.3333333432674408),
    case("2.3.1 (6.4.2) Table 10 LREAL is 64 bits", "x : LREAL;", "x := 1.0 / 3.0;", "x",
        1.0 / 3.0),
    case("2.3.1 (6.4.2) Table 10 REAL 24-bit mantissa", "x : REAL := 16777216.0;", "x := x + 1.0;",
        "x", 16777216.0),
    case("2.3.1 (6.4.2) Table 10 BYTE 8 bits", "x : BYTE := 16#FF;", "x := x + 1;", "x", 0),
    case("2.3.1 (6.4.2) Table 10 WORD 16 bits", "x : WORD := 16#FFFF;", "x := x + 1;", "x", 0),
    case("2.3.1 (6.4.2) Table 10 DWORD 32 bits", "x : DWORD := 16#FFFFFFFF;", "x := x + 1;", "x",
        0),
    case("2.3.1 (6.4.2) Table 10 LWORD 64 bits", "x : LWORD;", "x := x - 1;", "x", 2**64 - 1),
    case("2.3.1 (6.4.2) Table 10 STRING(n)", "s : STRING(4);", "s := 'abcdef';", "s", "abcd"),
    case("2.3.1 (6.4.2) Table 10 STRING[n]", "s : STRING[2];", "s := 'abcdef';", "s", "ab"),
    case("2.3.1 (6.4.2) Table 10 TIME", "t : TIME := T#1s;", "t := t + T#1ms;", "t", 1001),
    case("2.3.1 (6.4.2) Table 10 TIME_OF_DAY", "t : TIME_OF_DAY := TOD#1:0:0;", "", "t", 3600000),
    case("2.3.1 (6.4.2) Table 10 DATE_AND_TIME", "t : DATE_AND_TIME := DT#1970-01-01-0:0:1;", "",
        "t", 1000),
    case("2.4.2 (6.4.2) Table 13 initial BOOL", "x : BOOL;", "", "x", False),
    case("2.4.2 (6.4.2) Table 13 initial INT", "x : INT;", "", "x", 0),
    case("2.4.2 (6.4.2) Table 13 initial REAL", "x : REAL;", "", "x", 0.0),
    case("2.4.2 (6.4.2) Table 13 initial TIME", "x : TIME;", "", "x", 0),
    case("2.4.2 (6.4.2) Table 13 initial DATE", "x : DATE;", "", "x", D0001),
    case("2.4.2 (6.4.2) Table 13 initial TIME_OF_DAY", "x : TOD;", "", "x", 0),
    case("2.4.2 (6.4.2) Table 13 initial DATE_AND_TIME", "x : DT;", "", "x", D0001),
    case("2.4.2 (6.4.2) Table 13 initial STRING", "x : STRING;", "", "x", ""),
    case("2.4.2 (6.4.2) Table 13 initial WORD", "x : WORD;", "", "x", 0),
]  # fmt: skip

DERIVED_TYPES = [
    case("2.3.3.1 (6.4.4.2) enumeration", "c : Color;", "c := Blue;", "c", 2, DERIVED),
    case("2.3.3.2 (6.4.4.2) an enumeration starts at its first value", "c : Color;", "", "c", 0,
        DERIVED),
    case("2.3.3.1 (6.4.4.2) Color#Green", "c : Color;", "c := Color#Green;", "c", 1, DERIVED),
    case("3rd ed. 6.4.4.2 Color.Green", "c : Color;", "c := Color.Green;", "c", 1, DERIVED),
    case("2.3.3.1 (6.4.4.2) compare values", "c : Color := Green; b : BOOL;", "b := c = Green;",
        "b", True, DERIVED),
    case("3rd ed. 6.4.4.3 named values", "v : Level;", "v := High;", "v", 30, DERIVED),
    case("3rd ed. 6.4.4.3 named values start at the first", "v : Level;", "", "v", 10, DERIVED),
    case("2.3.3.1 (6.4.4.2) inline enumeration", "c : (Off, On) := On;", "", "c", 1),
    case("2.3.3.1 (6.4.4.4) subrange", "s : Small;", "s := -5;", "s", -5, DERIVED),
    case("2.3.3.2 (6.4.4.4) a subrange starts at its lower limit", "s : Small;", "", "s", -5,
        DERIVED),
    case("2.3.3.2 (6.4.4.4) a subrange type's initial value", "p : Percent;", "", "p", 50, DERIVED),
    case("2.4.3 (6.5.1) an inline subrange starts at its lower limit", "s : INT (3..9);", "", "s",
        3),
    case("2.3.3.1 (6.4.4.5) array type", "v : Vec3; x : LREAL;", "v[3] := 2.5; x := v[3];", "x",
        2.5, DERIVED),
    case("2.3.3.2 (6.4.4.5) array type initial values", "g : Grid; x : INT;", "x := g[1, 1];", "x",
        3, DERIVED),
    case("2.3.3.2 (6.4.4.5) row-major order", "g : Grid; x : INT;", "x := g[0, 2];", "x", 2,
        DERIVED),
    case("2.3.3.1 (6.4.4.6) structure", "p : Point; x : INT;", "p.x := 4; x := p.x;", "x", 4,
        DERIVED),
    case("2.3.3.2 (6.4.4.6) a field's initial value", "p : Point; y : INT;", "y := p.y;", "y", 7,
        DERIVED),
    case("2.3.3.2 (6.4.4.6) a nested structure's initial value", "l : Line; y : INT;",
        "y := l.b.y;", "y", 2, DERIVED),
    case("2.3.3.2 (6.4.4.6) nested structure defaults", "l : Line; y : INT;", "y := l.a.y;", "y",
        7, DERIVED),
    case("2.3.3.1 (6.4.4.9) string type", "n : Name;", "n := 'abcdefghij';", "n", "abcdefgh",
        DERIVED),
    case("2.3.3.2 (6.4.4.9) string type initial value", "n : Name;", "", "n", "anon", DERIVED),
    case("2.3.3.2 (6.4.4.9) directly derived initial value", "n : Count;", "", "n", 3, DERIVED),
    case("2.3.3.2 (6.4.4.9) derived REAL initial value", "v : Speed;", "", "v", 1.5, DERIVED),
    case("2.3.3.2 (6.4.4.5) array of a derived type", "a : Counts; x : UINT;", "x := a[4];", "x",
        3, DERIVED),
    case("2.3.3.2 (6.4.4.6) field of a derived type", "t : Tagged; x : UINT;", "x := t.n;", "x", 3,
        DERIVED),
    case("2.3.3.2 (6.4.4.6) field of an enumeration", "t : Tagged; c : Color;", "c := t.c;", "c",
        2, DERIVED),
    case("2.4.3.2 (6.5.1) a declaration overrides the type's", "n : Count := 9;", "", "n", 9,
        DERIVED),
    case("2.3.3.2 (6.4.4.6) structure initial value", "p : Point := (x := 1); x : INT;",
        "x := p.x * 10 + p.y;", "x", 17, DERIVED),
]  # fmt: skip

VARIABLES = [
    case("2.4.1.2 (6.4.4.5) array element", "a : ARRAY[1..3] OF INT; x : INT;",
        "a[2] := 5; x := a[2];", "x", 5),
    case("2.4.1.2 (6.4.4.5) lower bound other than 0 and 1", "a : ARRAY[-2..2] OF INT; x : INT;",
        "a[-2] := 3; x := a[-2];", "x", 3),
    case("2.4.1.2 (6.4.4.5) two dimensions", "a : ARRAY[1..2, 1..3] OF INT; x : INT;",
        "a[2, 3] := 6; x := a[2, 3];", "x", 6),
    case("2.4.1.2 (6.4.4.5) an index expression", "a : ARRAY[1..5] OF INT; i : INT := 2; x : INT;",
        "a[i * 2 + 1] := 8; x := a[5];", "x", 8),
    case("2.4.1.2 (6.4.4.6) a field of a field", "l : Line; x : INT;", "l.a.x := 9; x := l.a.x;",
        "x", 9, DERIVED),
    case("2.4.1.2 (6.4.4.6) an array of structures", "ps : ARRAY[1..2] OF Point; x : INT;",
        "ps[2].x := 4; x := ps[2].x + ps[1].y;", "x", 11, DERIVED),
    case("2.4.1.2 (6.4.4.6) an array in a structure", "s : ST_A; x : INT;",
        "s.v[2] := 3; x := s.v[2];", "x", 3,
        "TYPE ST_A : STRUCT v : ARRAY[1..2] OF INT; END_STRUCT; END_TYPE"),
    case("2.4.3.2 (6.5.1) several names, one initial value", "a, b : INT := 4; x : INT;",
        "x := a + b;", "x", 8),
    case("2.4.3.2 (6.5.1) array initial value with repetition",
        "a : ARRAY[1..7] OF INT := [1, 2(7), 3(0), 9]; x : INT;", "x := a[3] * 10 + a[7];", "x",
        79),
    case("2.4.3.2 (6.5.1) too few array initial values",
        "a : ARRAY[1..4] OF INT := [5, 6]; x : INT;", "x := a[4];", "x", 0),
    case("2.4.3.2 (6.5.1) array of structures initial values",
        "ps : ARRAY[1..2] OF Point := [(x := 1), (x := 2, y := 3)]; x : INT;",
        "x := ps[1].y * 10 + ps[2].y;", "x", 73, DERIVED),
    case("2.4.3.2 (6.5.1) nested structure initial value", "l : Line := (a := (x := 5)); x : INT;",
        "x := l.a.x + l.a.y;", "x", 12, DERIVED),
    case("2.4.3.2 (6.5.1) a constant expression as initial value", "x : INT := 2 * 3 + 1;", "",
        "x", 7),
    case("2.4.3 (6.5.4) VAR CONSTANT", "y : INT;", "y := K * 2;", "y", 8,
        "VAR_GLOBAL CONSTANT K : INT := 4; END_VAR"),
    case("2.4.3 (6.5.4) an ARRAY CONSTANT", "y : INT;", "y := T[2];", "y", 5,
        "VAR_GLOBAL CONSTANT T : ARRAY[1..2] OF INT := [4, 5]; END_VAR"),
    case("2.4.3 (6.5.4) a constant in an array's bounds", "a : ARRAY[1..N] OF INT; y : INT;",
        "a[N] := 1; y := a[N];", "y", 1, "VAR_GLOBAL CONSTANT N : INT := 3; END_VAR"),
    case("2.4.3 (6.5.2) VAR_GLOBAL", "y : INT;", "g := g + 1; y := g;", "y", 2,
        "VAR_GLOBAL g : INT := 1; END_VAR"),
    case("2.4.3 (6.5.2) VAR_GLOBAL of a structure", "y : INT;", "y := gp.x + gp.y;", "y", 8,
        DERIVED + "VAR_GLOBAL gp : Point := (x := 1); END_VAR"),
]  # fmt: skip

REFERENCES = [
    case("3rd ed. 6.4.4.10.1 REF_TO starts at NULL", "r : REF_TO INT; b : BOOL;", "b := r = NULL;",
        "b", True),
    case("3rd ed. 6.4.4.10.2 REF() and ^", "r : REF_TO INT; y : INT; x : INT;",
        "r := REF(y); y := 4; x := r^;", "x", 4),
    case("3rd ed. 6.4.4.10.3 a write through ^", "r : REF_TO INT; y : INT;",
        "r := REF(y); r^ := 6;", "y", 6),
    case("3rd ed. 6.4.4.10.3 references compared", "r, q : REF_TO INT; y : INT; b : BOOL;",
        "r := REF(y); q := REF(y); b := r = q;", "b", True),
    case("3rd ed. 6.4.4.10.3 reference to an array element",
        "r : REF_TO INT; a : ARRAY[1..3] OF INT;", "r := REF(a[3]); r^ := 2;", "a", [0, 0, 2]),
    case("3rd ed. 6.4.4.10.3 a field through ^", "r : REF_TO Point; p : Point; x : INT;",
        "r := REF(p); r^.x := 5; x := p.x;", "x", 5, DERIVED),
    case("3rd ed. 6.4.4.10.3 reference to a global", "r : REF_TO INT; x : INT;",
        "r := REF(g); r^ := 3; x := g;", "x", 3, "VAR_GLOBAL g : INT; END_VAR"),
    case("3rd ed. 6.4.4.10.3 reset to NULL", "r : REF_TO INT; y : INT; b : BOOL;",
        "r := REF(y); r := NULL; b := r <> NULL;", "b", False),
]  # fmt: skip

PARTIAL = [
    case("3rd ed. 6.6.1.3 Table 17 bit read .%X", "w : WORD := 16#0010; b : BOOL;", "b := w.%X4;",
        "b", True),
    case("3rd ed. 6.6.1.3 Table 17 bit read .n", "w : WORD := 16#0010; b : BOOL := TRUE;",
        "b := w.3;", "b", False),
    case("3rd ed. 6.6.1.3 Table 17 bit write", "w : WORD;", "w.%X15 := TRUE;", "w", 0x8000),
    case("3rd ed. 6.6.1.3 Table 17 bit clear", "w : BYTE := 16#FF;", "w.0 := FALSE;", "w", 0xFE),
    case("3rd ed. 6.6.1.3 Table 17 byte read", "d : DWORD := 16#11223344; b : BYTE;",
        "b := d.%B2;", "b", 0x22),
    case("3rd ed. 6.6.1.3 Table 17 byte write", "d : DWORD := 16#11223344;", "d.%B0 := 16#FF;",
        "d", 0x112233FF),
    case("3rd ed. 6.6.1.3 Table 17 word read", "d : LWORD := 16#1122334455667788; w : WORD;",
        "w := d.%W3;", "w", 0x1122),
    case("3rd ed. 6.6.1.3 Table 17 dword write", "d : LWORD;", "d.%D1 := 16#FFFFFFFF;", "d",
        0xFFFFFFFF00000000),
    case("3rd ed. 6.6.1.3 Table 17 bit of an array element", "a : ARRAY[1..2] OF BYTE; b : BOOL;",
        "a[2].%X7 := TRUE; b := a[2] = 16#80;", "b", True),
]  # fmt: skip


@pytest.mark.parametrize(
    ("decls", "body", "name", "expected", "before"),
    [*COMMON, *LITERALS, *ELEMENTARY, *DERIVED_TYPES, *VARIABLES, *REFERENCES, *PARTIAL],
)
def test_iec_data(decls, body, name, expected, before):
    prog = run(program(decls, body, before))
    assert same(getattr(prog, name), expected), getattr(prog, name)


def test_reals_are_ieee_754():
    """2.3.1 (6.4.2) Table 10: REAL and LREAL are IEC 60559 (IEEE 754) single and double."""
    prog = run(
        program(
            "a : REAL := 1.0E38; b : LREAL := 1.0E308; c : REAL;",
            "a := a * 10.0; b := b * 10.0; c := 0.1;",
        )
    )
    assert prog.a == math.inf and prog.b == math.inf and prog.c == R01


SECTIONS = """
VAR_GLOBAL g : INT := 3; END_VAR
PROGRAM t
VAR_EXTERNAL g : INT; END_VAR
VAR RETAIN r : INT; END_VAR
VAR_TEMP k : INT; END_VAR
VAR n : INT; y : INT; END_VAR
k := k + 1; r := r + 1; n := n + k; y := g;
END_PROGRAM
"""


def test_variable_sections():
    """2.4.3 (6.5.2): VAR_EXTERNAL is the global; a RETAIN variable keeps its value from scan
    to scan as any VAR; a VAR_TEMP starts afresh at every scan."""
    prog = run(SECTIONS, scans=3)
    assert (prog.y, prog.r, prog.n) == (3, 3, 3)
