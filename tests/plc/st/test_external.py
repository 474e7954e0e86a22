"""A machine's own block types (plc.st.External) in an ST program: declared, called with
inputs, their outputs read; a malformed one refused with what it needs."""

import pytest

import plc.st


class Doubler:
    def __init__(self) -> None:
        self.IN = 0.0
        self.OUT = 0.0
        self.calls = 0

    def __call__(self) -> None:
        self.OUT = 2.0 * self.IN
        self.calls += 1


MEMBERS = {"IN": ("LREAL", "input"), "OUT": ("LREAL", "output")}


def test_an_external_block_is_called_with_its_inputs_and_its_outputs_read():
    source = (
        "PROGRAM p\nVAR d : Doubler; x : LREAL; END_VAR\nd(IN := 21.0, OUT => x);\nEND_PROGRAM\n"
    )
    prog = plc.st.from_source(source, blocks={"Doubler": plc.st.External(Doubler, MEMBERS)})
    prog()
    prog()
    assert prog.x == 42.0 and prog.d.calls == 2


def test_an_unknown_block_type_names_the_external_one():
    source = "PROGRAM p\nVAR d : Dubler; END_VAR\nEND_PROGRAM\n"
    with pytest.raises(plc.st.STError, match="did you mean Doubler"):
        plc.st.from_source(source, blocks={"Doubler": plc.st.External(Doubler, MEMBERS)})


def test_a_member_of_no_elementary_type_is_refused():
    bad = plc.st.External(Doubler, {"IN": ("MATRIX", "input")})
    with pytest.raises(ValueError, match="member IN is \\('MATRIX', 'input'\\)"):
        plc.st.from_source("PROGRAM p\nEND_PROGRAM\n", blocks={"Doubler": bad})
