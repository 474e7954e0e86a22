"""Constant block inputs are set once (mcl.st.hoist) only where that changes nothing a program
sees: two calls with different constants, or an input the program assigns, are set per call."""

import mcl.st


def scanned(source: str, scans: int = 3) -> mcl.st.STProgram:
    prog = mcl.st.from_source(f"PROGRAM p\n{source}\nEND_PROGRAM\n")
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
