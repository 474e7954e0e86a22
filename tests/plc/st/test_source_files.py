"""A user's source file read one way (:func:`plc.st.frontend.project.read_source`) by every
entry point: an .st file as UTF-8, a TwinCAT file in the encoding its XML declaration names; a
byte that is not of it gives one message at its line and column, never a traceback."""

from __future__ import annotations

import pytest

import plc.st
from plc.st.check import check
from scenes.tools import cli
from tests.plc.st.test_projects import _pou

PROGRAM = "PROGRAM Main\nVAR n : INT; END_VAR\n(* Zähler *) n := n + 1;\nEND_PROGRAM\n"
"""An ST program with a non-ASCII letter (ä) on line 3, column 5."""


@pytest.mark.parametrize(
    "entry",
    ["check", "load", "task_of_file", "scenes check", "scenes run"],
)
def test_a_file_not_in_utf8_gives_one_message_at_its_first_foreign_byte(entry, tmp_path, capsys):
    """Saved as Latin-1 (ä is the byte 0xE4): ``file:3:5``, what is wrong, what is right, from
    :func:`plc.st.check`, :func:`plc.st.load`, :func:`plc.st.task_of_file` and the ``check``
    and ``run`` commands (on standard error, exit status 1 and 2)."""
    path = tmp_path / "latin1.st"
    path.write_bytes(PROGRAM.encode("latin-1"))
    expected = f"{path}:3:5: cannot read it (byte 0xE4 is not UTF-8); expected a UTF-8 ST file"

    if entry == "check":
        assert check(path).errors == [expected]
    elif entry == "load":
        with pytest.raises(plc.st.STError) as raised:
            plc.st.load(path)
        assert str(raised.value) == expected
    elif entry == "task_of_file":
        with pytest.raises(plc.st.STError) as raised:
            plc.st.task_of_file(path)
        assert str(raised.value) == expected
    else:
        command, status = ("check", 1) if entry == "scenes check" else ("run", 2)
        where = [str(path)] if command == "check" else ["--program", str(path)]
        assert cli.main([command, "single_axis", *where]) == status
        assert capsys.readouterr().err.splitlines() == [expected]


def test_the_same_file_in_utf8_with_or_without_a_byte_order_mark_or_in_utf16_runs(tmp_path):
    """UTF-8 as most editors save it, and as Windows editors do (a byte order mark first, or
    UTF-16 after its byte order mark)."""
    for name, data in [
        ("plain.st", PROGRAM.encode()),
        ("bom.st", b"\xef\xbb\xbf" + PROGRAM.encode()),
        ("utf16.st", PROGRAM.encode("utf-16")),
    ]:
        path = tmp_path / name
        path.write_bytes(data)
        assert check(path).errors == []
        program = plc.st.load(path)
        program()
        assert program.n == 1


POU = _pou(
    "Main",
    "PROGRAM Main\nVAR\n  n : INT; (* Zähler *)\nEND_VAR\n",
    "(* zählt *) n := n + ;\n",
)
"""A TwinCAT POU with an ä on lines 6 and 10 and a syntax error after the second."""


def test_a_twincat_file_is_read_in_the_encoding_its_xml_declaration_names(tmp_path):
    """Declared ISO-8859-1 and saved so (or UTF-16 with its byte order mark), the POU reads as
    in UTF-8: the same message at the same column (the ä one character, not a byte the UTF-8
    reading could not place)."""
    utf8, latin1, utf16 = (tmp_path / name / "Main.TcPOU" for name in ("utf8", "latin1", "utf16"))
    for path, data in [
        (utf8, POU.encode()),
        (latin1, POU.replace('encoding="utf-8"', 'encoding="ISO-8859-1"').encode("latin-1")),
        (utf16, POU.replace('encoding="utf-8"', 'encoding="utf-16"').encode("utf-16")),
    ]:
        path.parent.mkdir()
        path.write_bytes(data)
    problem = ":10:41: unexpected ';'; expected an expression"
    assert check(utf8).errors == [f"{utf8}{problem}"]
    assert check(latin1).errors == [f"{latin1}{problem}"]
    assert check(utf16).errors == [f"{utf16}{problem}"]


def test_a_twincat_file_not_in_its_declared_encoding_gives_one_message(tmp_path):
    """Declared UTF-8 but saved as Latin-1: the first foreign byte's line and column, and
    what would be right, from :func:`plc.st.check` and :func:`plc.st.load`."""
    path = tmp_path / "Main.TcPOU"
    path.write_bytes(POU.replace("n + ;", "n + 1;").encode("latin-1"))
    expected = (
        f"{path}:6:16: cannot read it (byte 0xE4 is not UTF-8); expected UTF-8, or the "
        'encoding it is written in named by <?xml ... encoding="..."?>'
    )
    assert check(path).errors == [expected]
    with pytest.raises(plc.st.STError) as raised:
        plc.st.load(path)
    assert str(raised.value) == expected


@pytest.mark.parametrize(
    ("encoding", "data", "problem"),
    [
        ("windows-1252", b"\x81", "6:16: cannot read it (byte 0x81 is not WINDOWS-1252)"),
        ("x-unknown", b"a", "1:1: cannot read it (an encoding unknown here: x-unknown)"),
        ("UTF8", b"\xe4", "6:16: cannot read it (byte 0xE4 is not UTF-8)"),
        ("utf_8", b"\xe4", "6:16: cannot read it (byte 0xE4 is not UTF-8)"),
    ],
)
def test_a_twincat_file_in_an_encoding_that_cannot_read_it_gives_one_message(
    encoding, data, problem, tmp_path
):
    """A byte its declared encoding has no character for (0x81 in windows-1252; a Latin-1 ä in
    UTF-8, however the declaration spells it), or an encoding Python does not know: one
    message, naming the encoding."""
    path = tmp_path / "Main.TcPOU"
    text = POU.replace('encoding="utf-8"', f'encoding="{encoding}"').replace("zählt", "counts")
    path.write_bytes(text.replace("Zähler", "Z#hler").encode().replace(b"#", data))
    expected = (
        f"{path}:{problem}; expected UTF-8, or the encoding it is written in named by "
        '<?xml ... encoding="..."?>'
    )
    assert check(path).errors == [expected]
