"""Constant block inputs are set once (plc.st.codegen.hoist) only where that changes nothing a
program
sees: two calls with different constants, or an input the program assigns, are set per call."""

import plc.st


def scanned(source: str, scans: int = 3) -> plc.st.STProgram:
    prog = plc.st.from_source(f"PROGRAM p\n{source}\nEND_PROGRAM\n")
    for _ in range(scans):
        prog()
    return prog


def test_two_calls_with_different_constants_each_set_their_own():
    prog = scanned(
        "VAR t : TON; first, second, before : TIME; END_VAR\n"
        "before := t.PT;\nt(PT := T#100ms);\nfirst := t.PT;\nt(PT := T#200ms);\nsecond := t.PT;"
    )
    assert (prog.before, prog.first, prog.second) == (200, 100, 200)


def test_an_input_the_program_assigns_is_set_again_by_each_call():
    prog = scanned(
        "VAR t : TON; before, after : TIME; END_VAR\n"
        "before := t.PT;\nt(PT := T#100ms);\nafter := t.PT;\nt.PT := T#50ms;"
    )
    assert (prog.before, prog.after) == (50, 100)


def test_a_constant_input_set_once_holds_from_the_first_scan():
    prog = scanned("VAR t : TON; q : BOOL; END_VAR\nt(IN := TRUE, PT := T#20ms, Q => q);", 4)
    assert prog.t.PT == 20 and prog.q  # 10 ms per scan without a machine: 30 ms >= 20 ms


DELAY = (
    "FUNCTION_BLOCK Delay\nVAR_INPUT IN : BOOL; PT : TIME; END_VAR\nVAR_OUTPUT Q : BOOL; END_VAR\n"
    "VAR t : TON; END_VAR\n{body}t(IN := IN, PT := PT, Q => Q);\nEND_FUNCTION_BLOCK\n"
)


def block_scanned(body: str, program: str, scans: int = 3) -> plc.st.STProgram:
    """A program using the block Delay (a TON inside; ``body`` before the TON's call)."""
    prog = plc.st.from_source(DELAY.format(body=body) + f"PROGRAM p\n{program}\nEND_PROGRAM\n")
    for _ in range(scans):
        prog()
    return prog


def scan_code(prog: plc.st.STProgram, cls: str) -> str:
    """The generated Python of class ``cls``'s scan (its ``__call__``)."""
    source = prog.module.source
    return source[source.index(f"class {cls}:") :].split("def __call__", 1)[1].split("\nclass")[0]


def test_a_block_input_every_instance_holds_constant_reaches_the_inner_block_once():
    prog = block_scanned(
        "",
        "VAR a : Delay; b : Delay := (PT := T#40ms); qa, qb : BOOL; END_VAR\n"
        "a(IN := TRUE, PT := T#20ms, Q => qa);\nb(IN := TRUE, Q => qb);",
        4,
    )
    assert (prog.a.t.PT, prog.b.t.PT) == (20, 40)
    assert prog.qa and not prog.qb  # 30 ms after the first scan: past 20 ms, not 40 ms
    assert "self.t.PT" not in scan_code(prog, "Delay")  # set once, not per scan


def test_an_instance_passing_a_variable_makes_the_inner_input_follow_each_call():
    prog = block_scanned(
        "",
        "VAR a, b : Delay; pt : TIME := T#20ms; END_VAR\n"
        "a(IN := TRUE, PT := T#30ms);\nb(IN := TRUE, PT := pt);\npt := T#50ms;",
    )
    assert (prog.a.t.PT, prog.b.t.PT) == (30, 50)
    assert "PT = self.PT" in scan_code(prog, "Delay")


def test_a_block_that_writes_its_own_input_passes_it_on_per_call():
    prog = block_scanned("PT := PT + T#10ms;\n", "VAR a : Delay; END_VAR\na(PT := T#20ms);")
    assert prog.a.t.PT == 30  # the call sets 20, the block adds 10 before its TON's call


def test_instances_in_an_array_pass_their_inputs_on_per_call():
    prog = block_scanned(
        "",
        "VAR d : ARRAY[1..2] OF Delay; i : INT; END_VAR\n"
        "FOR i := 1 TO 2 DO d[i](IN := TRUE, PT := T#20ms); END_FOR",
    )
    assert [d.t.PT for d in prog.d] == [20, 20]


GROUP = (
    "PROGRAM p\nVAR g : AXES_GROUP_REF; m, m2 : MC_MoveLinearAbsolute; go : BOOL;\n"
    "target : ARRAY[1..3] OF LREAL; y : LREAL; END_VAR\n{calls}\nEND_PROGRAM\n"
)


def test_an_array_input_every_call_sets_is_passed_without_a_copy():
    calls = "m(AxesGroup := g, Execute := go, Position := target);"
    source = plc.st.compile_source(GROUP.format(calls=calls)).source
    assert "Position = self.target" in source and "tuple(" not in source


def test_an_array_input_a_call_omits_or_the_program_reads_is_copied():
    omitted = "m(AxesGroup := g, Execute := go, Position := target);\nm(Execute := go);"
    read = (
        "m(AxesGroup := g, Execute := go, Position := target);\n"
        "m2(AxesGroup := g, Position := m.Position);"
    )
    for calls in (omitted, read):
        source = plc.st.compile_source(GROUP.format(calls=calls)).source
        assert "Position = tuple(self.target)" in source


def test_and_evaluates_an_operand_that_may_fault_even_when_the_first_is_false():
    prog = scanned("VAR z : INT; q : BOOL; END_VAR\nq := FALSE AND (10 / z > 1);", 1)
    assert "division by zero" in prog.error


def test_and_or_skip_a_plain_operand_with_the_value_iec_gives():
    prog = scanned(
        "VAR t : TON; a, b, c, d : BOOL; END_VAR\nt(IN := TRUE, PT := T#15ms);\n"
        "a := FALSE AND t.Q;\nb := TRUE AND t.Q;\nc := TRUE OR t.Q;\nd := FALSE OR t.Q;"
    )
    assert (prog.a, prog.b, prog.c, prog.d) == (False, True, True, True)
    assert "(False and self.t.Q)" in prog.module.source
