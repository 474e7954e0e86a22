"""A machine's MJCF file in the words of its author: its parse and compile errors, and names the
machine definition expects but the file lacks, as :class:`ModelError` with the file and line.

MuJoCo reports errors with line numbers of the combined scene model (every machine attached to
one world) and dm_control without the file's name; these functions translate both.
"""

from __future__ import annotations

__all__ = ["check_names", "compiled", "elements", "in_files", "parse", "start_line"]

import re
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

from scenes.errors import ModelError, located, suggest

_NAMED = re.compile(r"Element name '([^']*)', id \d+, line (\d+)")
_LINE = re.compile(r"^Line (\d+): ")
_KEY_SIZE = re.compile(
    r"^keyframe (?:'([^']*)'|\d+): invalid (\w+) size, expected (?:length )?(\d+)(?:, got (\d+))?"
)
_KEY_NAME = re.compile(r"Element name '([^']*)', id \d+")
KEY_VALUES = {
    "qpos": "joint coordinates",
    "qvel": "joint velocities",
    "act": "actuator activations (one per actuator with dynamics, dyntype)",
    "ctrl": "actuator controls (one per actuator)",
}
"""What each value list of a ``<key>`` holds, one value per ..."""


def start_line(path: Path, tag: str, line: int) -> int:
    """The line where the element ``<tag`` that ends its start tag on ``line`` begins (libxml2
    and dm_control count the line of the start tag's ``>``)."""
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError):
        return line
    opening = re.compile(rf"<{re.escape(tag)}(\s|/|>|$)")
    for number in range(min(line, len(lines)), 0, -1):
        if opening.search(lines[number - 1]):
            return number
    return line


def elements(path: Path, tag: str) -> dict[str, int]:
    """The named ``<tag>`` elements of an MJCF file: name → line where each begins."""
    from lxml import etree  # type: ignore[import-untyped]

    try:
        tree = etree.parse(str(path))
    except (OSError, etree.XMLSyntaxError):
        return {}
    return {
        str(e.get("name")): start_line(path, tag, e.sourceline or 1)
        for e in tree.iter(tag)
        if e.get("name")
    }


def parse(path: Path, load: Callable[[str], Any]) -> Any:
    """``load(path)`` (dm_control's ``mjcf.from_path``), its errors located in the file.

    Raises:
        ModelError: the file is not well-formed XML, or not valid MJCF (an unknown element or
            attribute, an unreadable value); one line with the file and line.
    """
    from lxml import etree

    expected = "well-formed MJCF (https://mujoco.readthedocs.io/en/stable/XMLreference.html)"
    try:
        return load(str(path))
    except etree.XMLSyntaxError as error:
        what = re.sub(r", line \d+, column \d+$", "", str(error.msg))
        column = f", column {error.position[1]}" if error.position else ""
        raise ModelError.at(
            f"{path}:{error.lineno}", "", f"XML syntax: {what}{column}", expected
        ) from None
    except (ValueError, KeyError, AttributeError) as error:
        message = str(error.args[0] if isinstance(error, KeyError) and error.args else error)
        found = _LINE.match(message)
        if found is None:
            raise ModelError.at(str(path), "", message.splitlines()[0], expected) from None
        what = message[found.end() :].splitlines()[0]
        tag = re.search(r"element <(\w+)>", what)
        line = int(found.group(1))
        line = start_line(path, tag.group(1), line) if tag else line
        raise ModelError.at(f"{path}:{line}", "", what, expected) from None


def compiled(
    compile_model: Callable[[], Any],
    files: Mapping[str, Path],
    combined: str,
    lacking: Mapping[str, Sequence[str]] | None = None,
) -> Any:
    """``compile_model()`` (MuJoCo's compiler on the combined scene), an error located in the
    machine's own file.

    Args:
        compile_model: compiles the combined scene model.
        files: each machine's MJCF file by machine name (the prefix of its names).
        combined: the combined model's XML (where MuJoCo's line numbers point).
        lacking: per machine, the elements its definition needs that its file lacks (as
            :func:`absent` words them): what a keyframe of the wrong size may have lost.

    Raises:
        ModelError: MuJoCo refused the model; the line names the machine's file and the line
            of the element, or the element and the combined model's line when that file does
            not name it.
    """
    try:
        return compile_model()
    except ValueError as error:
        message = str(error)
        what = message.splitlines()[0].removeprefix("Error: ")
        expected = (
            "a model MuJoCo compiles (https://mujoco.readthedocs.io/en/stable/XMLreference.html)"
        )
        keyframe = _keyframe(message, files, lacking or {})
        if keyframe is not None:
            raise keyframe from None
        found = _NAMED.search(message)
        if found is None:
            where = ", ".join(str(p) for p in files.values())
            raise ModelError.at(where, "", what, expected) from None
        name, line = found.group(1), int(found.group(2))
        tag = _tag_at(combined, line)
        machine, _, local = name.partition("/")
        path = files.get(machine)
        if path is not None and tag and local:
            own = elements(path, tag).get(local)
            if own is not None:
                raise ModelError.at(
                    f"{path}:{own}", f"<{tag} name={local!r}>", what, expected
                ) from None
        where = str(path) if path is not None else ", ".join(str(p) for p in files.values())
        element = f"<{tag or 'element'}{f' name={local!r}' if local else ''}>"
        raise ModelError.at(
            where, element, f"{what} (line {line} of the combined scene model)", expected
        ) from None


def _keyframe(
    message: str, files: Mapping[str, Path], lacking: Mapping[str, Sequence[str]]
) -> ModelError | None:
    """A keyframe whose value list has the wrong size, located at its ``<key>`` in the machine's
    file, with the elements the machine needs that the file lacks (None: another error, or a
    keyframe no machine's file names)."""
    found = _KEY_SIZE.match(message.splitlines()[0].removeprefix("Error: "))
    named = _KEY_NAME.search(message)
    if found is None or named is None:
        return None
    field, model_size = found.group(2), int(found.group(3))
    machine, _, local = named.group(1).partition("/")
    path = files.get(machine)
    line = elements(path, "key").get(local) if path is not None else None
    if path is None or line is None:
        return None
    meaning = KEY_VALUES.get(field, field)
    given = found.group(4)
    if given is None:
        problem = f"{field} has the wrong number of values for the model's {meaning}"
        right = f"one value per {meaning.split(' (')[0].removesuffix('s')}"
    else:
        # the model and the key may hold other machines' values too: count in the file's terms
        own = len(_key_values(path, local, field))
        needed = own - (int(given) - model_size)
        problem = f"{field} has {own} values, the model has {needed} {meaning}"
        right = f"{field} with {needed} values"
    missing = lacking.get(machine, ())
    if missing:
        right = f"the file to have {' and '.join(missing)}, or {right}"
    return ModelError(located(f"{path}:{line}", f"<key name={local!r}>", problem, right))


def _key_values(path: Path, name: str, field: str) -> list[str]:
    """The values of the attribute ``field`` of the ``<key name=name>`` of an MJCF file."""
    from lxml import etree

    for key in etree.parse(str(path)).iter("key"):
        if key.get("name") == name:
            return str(key.get(field) or "").split()
    return []


def absent(machine: str, kind: str, expected: Mapping[str, str], have: Sequence[str]) -> list[str]:
    """The names the machine definition expects (name → what it is for) that the file lacks,
    each as ``"<kind> 'name' (machine 'm' needs it as what)"``."""
    return [
        f"{kind} {name!r} (machine {machine!r} needs it as {why})"
        for name, why in expected.items()
        if name not in have
    ]


def _tag_at(xml: str, line: int) -> str:
    """The tag of the element that starts on ``line`` of ``xml`` ("" if none)."""
    lines = xml.splitlines()
    if not 0 < line <= len(lines):
        return ""
    found = re.search(r"<(\w+)", lines[line - 1])
    return found.group(1) if found else ""


def check_names(
    path: Path, machine: str, kind: str, expected: Mapping[str, str], have: Sequence[str]
) -> None:
    """Every name the machine definition expects (name → what needs it) is in the file.

    Args:
        path: the machine's MJCF file.
        machine: the machine's name.
        kind: the MJCF element, e.g. ``"joint"``.
        expected: name → what of the definition needs it (e.g. ``"axis X (AxisDef.joint)"``).
        have: the names of that kind in the file.

    Raises:
        ModelError: one line per missing name: the file, the name, what expects it and the
            names the file has (with their lines).
    """
    missing = [(n, why) for n, why in expected.items() if n not in have]
    if not missing:
        return
    lines = elements(path, kind)
    listed = ", ".join(f"{n!r} (line {lines[n]})" if n in lines else repr(n) for n in have)
    raise ModelError.of(
        [
            f"{path}: <{kind} name={name!r}>: not in the file, but machine {machine!r} needs it "
            f"for {why}{suggest(name, have)}; expected one of the file's {kind}s: {listed}"
            for name, why in missing
        ]
    )


def in_files(error: Exception, files: Sequence[Path]) -> ModelError:
    """A wiring error found on the compiled model (a name the plant or a device looks for and
    does not find) with the machines' files in front (a :class:`ModelError` stays as it is)."""
    if isinstance(error, ModelError):
        return error
    return ModelError(f"{', '.join(str(f) for f in files)}: {error}")
