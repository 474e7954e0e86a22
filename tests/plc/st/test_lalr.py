"""The parser's fast path: the LALR parser reads the programs engineers write (the demos, their
TwinCAT and PLCopen projects, the load benchmark's plant) into the same typed tree as the Earley
parser, and what it cannot read the Earley parser still reads, with the same messages."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import blark.transform as tf
import lark
import pytest
from blark import util

from plc.st.errors import STError
from plc.st.frontend import chunks, lalr
from plc.st.frontend import parse as st_parse
from plc.st.frontend.project import read_project
from tests.benchmarks.st import project
from tests.helpers import ROOT

EXAMPLES = ROOT / "examples" / "st"


def _sources() -> list[tuple[str, str]]:
    """(name, ST text) of every example program, project and the benchmark's plant."""
    found = [(p.name, p.read_text(encoding="utf-8")) for p in sorted(EXAMPLES.glob("*.st"))]
    projects = [*sorted(EXAMPLES.glob("*_twincat")), *sorted((EXAMPLES / "plcopen").glob("*"))]
    found += [(p.name, read_project(p).source) for p in projects]
    return [*found, ("plant", project(600))]


def _both(text: str) -> tuple[Any, Any]:
    """``text`` (one item) as the LALR parser reads it (None if it cannot) and as the Earley
    parser reads it, each through the whole of :func:`plc.st.frontend.parse._parse`."""
    earley, fast = st_parse.parser, lalr.parse
    try:
        st_parse.parser = _refused  # type: ignore[assignment]
        read: Any = _same_values(st_parse._parse(text, "x.st"))
    except _Refused:
        read = None
    finally:
        st_parse.parser = earley
    try:
        lalr.parse = _unread
        return read, _same_values(st_parse._parse(text, "x.st"))
    finally:
        lalr.parse = fast


def _unread(text: str) -> None:
    """The LALR parser reading nothing: the Earley parser reads every text."""


class _Refused(Exception):
    """The Earley parser was asked: the LALR parser could not read the text."""


def _refused() -> Any:
    raise _Refused


def _same_values(node: Any) -> Any:
    """``node`` with each negative literal as the unary minus of its value (in a structure's
    initial value, the Earley parser reads ``-20.0`` as one literal: the same value)."""
    if isinstance(node, list):
        return [_same_values(n) for n in node]
    if isinstance(node, tf.Integer | tf.Real) and str(node.value).startswith("-"):
        positive = lark.Token(node.value.type, str(node.value)[1:])
        return tf.UnaryOperation(lark.Token("UNARY_OPERATOR", "-"), type(node)(positive))
    if dataclasses.is_dataclass(node) and not isinstance(node, type):
        for field in dataclasses.fields(node):
            if field.name != "meta":
                setattr(node, field.name, _same_values(getattr(node, field.name)))
    return node


@pytest.mark.parametrize(("name", "source"), _sources(), ids=[n for n, _ in _sources()])
def test_each_item_of_the_examples_reads_as_the_earley_parser_reads_it(name: str, source: str):
    for piece in chunks.chunks(source):
        fast, slow = _both(piece.text)
        assert fast is not None or name in FALLBACKS, f"{name}:{piece.line}: not read by LALR"
        assert fast is None or fast == slow, f"{name}:{piece.line}"


FALLBACKS = {"axis_cycle.st", "axis_cycle.xml"}
"""Examples with items the Earley parser reads (an array of structures' initial value, initial
values in a CONFIGURATION's VAR_GLOBAL)."""


CONSTRUCTS = {
    "case labels after statements": """PROGRAM p
VAR s : E; x : INT; END_VAR
CASE s OF
  Idle, Ready: x := 1; x := x + 1;
  Busy: IF x > 0 THEN x := 0; END_IF
  3..5, 7: x := -1;
ELSE
  x := 2;
END_CASE
END_PROGRAM
""",
    "literals": """PROGRAM p
VAR a : DINT := -7; b : LREAL := -2.5E3; t : TIME := T#1h2m3s; w : WORD := 16#FF_FF;
  c : BOOL := TRUE; d : DATE := D#2024-01-02; s : STRING(20) := 'a$'b'; timer : TON; END_VAR
a := 2#1010 + 8#17 - DINT#5 + INT#-3;
timer(IN := c AND NOT FALSE, PT := TIME#250ms);
b := -a * -2.0 ** 2;
END_PROGRAM
""",
    "names that begin like keywords and units": """PROGRAM p
VAR timer_ok : BOOL; dwell : LREAL; truey : BOOL; date_x : INT; msg : INT; d : INT; END_VAR
timer_ok := truey OR dwell > 0.0;
d := date_x + msg;
END_PROGRAM
""",
    "types": """TYPE E : (Idle := 0, Busy := 2); END_TYPE
TYPE P : STRUCT x : LREAL; y : LREAL := 1.0; END_STRUCT END_TYPE
TYPE A : ARRAY[1..3] OF INT; END_TYPE
TYPE S : STRING(25) := 'abc'; END_TYPE
""",
    "a function block and its calls": """FUNCTION_BLOCK FB
VAR_INPUT i : INT; END_VAR
VAR_OUTPUT o : INT; END_VAR
VAR_IN_OUT io : ARRAY[1..2] OF INT; END_VAR
o := i + io[1];
END_FUNCTION_BLOCK
""",
    "initial values and calls": """PROGRAM p
VAR fb : FB; arr : ARRAY[1..3] OF INT := [1, 2, 3]; v : INT; e : E := Busy; END_VAR
fb(i := 1, io := arr, o => v);
v := fb.o + LIMIT(0, v, 10) + arr[v MOD 3 + 1];
FOR v := 1 TO 10 BY 2 DO arr[1] := v; END_FOR
WHILE v > 0 DO v := v - 1; END_WHILE
REPEAT v := v + 1; UNTIL v >= 3 END_REPEAT
RETURN;
END_PROGRAM
""",
}


@pytest.mark.parametrize("name", CONSTRUCTS)
def test_common_constructs_read_as_the_earley_parser_reads_them(name: str):
    fast, slow = _both(CONSTRUCTS[name])
    assert fast is not None, "the LALR parser cannot read it"
    assert fast == slow


def test_what_the_lalr_parser_cannot_read_the_earley_parser_reads():
    source = """TYPE P : STRUCT x : LREAL; y : LREAL; END_STRUCT END_TYPE
PROGRAM p
VAR a : ARRAY[1..2] OF P := [(x := 1.0, y := 2.0), (x := 3.0, y := 4.0)]; END_VAR
a[1].x := 3.0;
END_PROGRAM
"""
    pieces = chunks.chunks(source)
    assert lalr.parse(util.find_and_clean_comments(pieces[1].text)[1]) is None
    fast, slow = _both(pieces[1].text)
    assert fast is None and isinstance(slow.items[0], tf.Program)
    init = st_parse.parse(source, "p.st").items[1].declarations[0].items[0].init
    assert len(init.value.elements) == 2


def test_a_syntax_error_names_its_line_and_column_as_before():
    source = "PROGRAM p\nVAR x : INT; END_VAR\nx := 1\nx := 2;\nEND_PROGRAM\n"
    with pytest.raises(STError, match=r"^p\.st:3:7: missing ';' at the end of line 3$"):
        st_parse.parse(source, "p.st")


def test_the_tables_are_kept_and_loaded(tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    monkeypatch.setenv("MCL_ST_CACHE", str(tmp_path))
    lalr.parser.cache_clear()
    try:
        text = CONSTRUCTS["case labels after statements"]
        built = lalr.parse(text)
        assert built is not None
        (kept,) = tmp_path.glob("lalr-*.parser")
        lalr.parser.cache_clear()
        assert lalr.parse(text) == built  # from the kept tables
        kept.write_bytes(b"damaged")
        lalr.parser.cache_clear()
        assert lalr.parse(text) == built  # built again
        assert kept.read_bytes() != b"damaged"
    finally:
        lalr.parser.cache_clear()
