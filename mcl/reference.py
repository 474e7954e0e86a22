"""The Markdown reference of the library, generated from the code so that it cannot drift.

For every function block exported by :mod:`mcl` (grouped by the module that defines it) the
reference lists its purpose (the first paragraph of its docstring), its inputs with type and
default and its outputs; then the state enums, the other enums and the error codes with their
English and Czech texts. A short hand-written introduction explains the conventions.

``python -m mcl.reference`` prints the reference; ``--write`` writes ``docs/reference.md``;
``--check`` exits with 1 when ``docs/reference.md`` is not up to date.
"""

from __future__ import annotations

__all__ = [
    "AXIS_TRANSITIONS",
    "CHAPTER_ORDER",
    "DOC_PATH",
    "ENUM_MEANING",
    "FB_KIND",
    "INTRO",
    "STATE_MEANING",
    "chapters",
    "declared_inputs",
    "function_blocks",
    "generate",
    "inputs",
    "kind",
    "main",
    "outputs",
    "paragraphs",
    "public_text",
    "render_block",
    "render_enum",
    "render_errors",
    "render_table",
    "summary",
]

import argparse
import ast
import enum
import functools
import inspect
import io
import os
import re
import subprocess
import sys
import textwrap
from collections.abc import Iterable, Sequence
from pathlib import Path
from types import ModuleType
from typing import Any

import mcl
from mcl.errors import ErrorID, error_text
from mcl.fb import EnableFB, ExecuteFB, FunctionBlock, MotionFB, input_spec
from mcl.reference_intro import INTRO

DOC_PATH = Path(__file__).resolve().parent.parent / "docs" / "reference.md"
"""Where ``--write`` puts the reference (``docs/reference.md`` of the repository)."""

CHAPTER_ORDER = (
    "administrative",
    "parameters",
    "motion",
    "profiles",
    "override",
    "homing",
    "flying_reference",
    "gearing",
    "cam",
    "force",
    "touch_probe",
    "inputs_outputs",
    "group_fb",
    "group_control",
    "kin_fb",
    "tracking",
    "group_sync",
    "path_table",
    "gcode",
)
"""Preferred order of the function-block modules; modules not named here follow alphabetically."""

FB_KIND = (
    (MotionFB, "motion block, inputs sampled on the rising edge of `Execute`"),
    (ExecuteFB, "inputs sampled on the rising edge of `Execute`"),
    (EnableFB, "level-sensitive, evaluated every call while `Enable` is TRUE"),
)
"""How a block is triggered, by base class (the first match wins)."""


AXIS_TRANSITIONS: tuple[tuple[str, str, str], ...] = (
    (
        "Disabled",
        "MC_Power `Enable` TRUE (constants written by GT_SetConstant, else `Econst`)",
        "StandStill, the `Ref` flag cleared; ErrorStop when an axis error is pending",
    ),
    (
        "any",
        "MC_Power `Enable` FALSE",
        "Disabled; a moving axis first stops on its maximum ramp (Stopping); "
        "running commands report `CommandAborted`",
    ),
    (
        "any",
        "GT_EStop (every axis of the module)",
        "Disabled at once, loops open, brakes on, errors cleared",
    ),
    (
        "any",
        "axis error: following error (2001), limit switch (2004/2005), SW limit (2006/2007), "
        "homing supervision (1/2/3)",
        "ErrorStop; the axis stops on its maximum ramp (2001 opens the loop and the drive "
        "stays enabled at 0 V for `quick_stop_time`, MC_Power's `Status` TRUE until the enable "
        "drops; a homing TorqueLimit error 3 stops pushing at once); in ErrorStop only 2001 is "
        "taken, it replaces the error (Supervision, below)",
    ),
    (
        "ErrorStop",
        "MC_Reset",
        "StandStill, or Disabled when the error opened the loop; "
        "`Done` once the stop ramp has ended",
    ),
    (
        "StandStill, motion states, Homing",
        "MC_StepAbsSwitch, MC_StepLimitSwitch, MC_StepBlock",
        "Homing, and stays there",
    ),
    (
        "StandStill, motion states, Homing",
        "MC_StepRefPulse",
        "Homing while searching, then StandStill with `Ref` set",
    ),
    (
        "StandStill, Homing (at rest)",
        "MC_StepDirect, MC_FinishHoming",
        "StandStill with `Ref` set",
    ),
    (
        "StandStill, motion states",
        "MC_MoveAbsolute and GT_MoveAbsBlock (need `Ref`), MC_MoveRelative, MC_MoveAdditive",
        "DiscreteMotion; StandStill when done and nothing is queued",
    ),
    (
        "StandStill, motion states, Homing",
        "MC_Halt",
        "DiscreteMotion; StandStill once stopped",
    ),
    (
        "StandStill, motion states",
        "MC_PositionProfile",
        "DiscreteMotion; StandStill at the table's last point when nothing is queued",
    ),
    (
        "StandStill, motion states",
        "MC_MoveVelocity, GT_Jog, MC_MoveContinuousAbsolute, MC_MoveContinuousRelative, "
        "MC_VelocityProfile, MC_AccelerationProfile",
        "ContinuousMotion, until another command takes over",
    ),
    (
        "StandStill, motion states",
        "MC_GearIn, MC_GearInPos (the slave)",
        "SynchronizedMotion until another command takes over; MC_GearOut: ContinuousMotion",
    ),
    (
        "StandStill (group members)",
        "group motion (MC_MoveLinear*, MC_MoveCircular*, MC_MoveDirect*, MC_MovePath)",
        "SynchronizedMotion; StandStill when the group stands",
    ),
    (
        "StandStill, motion states, Homing",
        "MC_Stop",
        "Stopping; held while its `Execute` is TRUE; StandStill once `Done` AND NOT `Execute`",
    ),
)
"""The axis state machine: (from, by, to), hand-written from the behaviour of `mcl.Axis`."""

STATE_MEANING: dict[str, str] = {
    "Disabled": "position loop open, drive off",
    "StandStill": "powered, at rest, no motion command",
    "Homing": "a homing step is running, or a coarse step has ended",
    "DiscreteMotion": "a move to a target, a position profile, or MC_Halt",
    "ContinuousMotion": "MC_MoveVelocity, GT_Jog, a continuous move, a velocity or "
    "acceleration profile",
    "SynchronizedMotion": "geared to a master (MC_GearIn, MC_GearInPos), or a group command",
    "Stopping": "MC_Stop, or the ramp before the loop opens at power-off",
    "ErrorStop": "an axis error; stopped; left with MC_Reset",
    "GroupDisabled": "not enabled; refuses motion commands (`Epower` 10)",
    "GroupStandby": "enabled, all members at rest (or the path held by MC_GroupInterrupt)",
    "GroupMoving": "a group command runs or a member moves",
    "GroupHoming": "a member is homing",
    "GroupStopping": "MC_GroupStop, until its `Done` AND NOT `Execute`",
    "GroupErrorStop": "a member in ErrorStop or a group error; left with MC_GroupReset",
}
"""Meaning of the states (hand-written; a state without an entry is listed without one)."""

ENUM_MEANING: dict[str, str] = {
    "Aborting": "start at once, abort the active command",
    "Buffered": "start after the active command, from standstill",
    "BlendingLow": "no stop between; hand over at the lower velocity",
    "BlendingPrevious": "no stop between; hand over at the first command's velocity",
    "BlendingNext": "no stop between; hand over at the second command's velocity",
    "BlendingHigh": "no stop between; hand over at the higher velocity",
    "MC_Positive": "positive direction",
    "MC_Shortest": "shortest way (modulo axes)",
    "MC_Negative": "negative direction",
    "MC_Current": "the current direction of motion",
    "MC_SwitchPositive": "homing: positive when the REF switch is off at the edge, else negative",
    "MC_SwitchNegative": "homing: the opposite of MC_SwitchPositive",
    "MC_On": "the switch is on",
    "MC_Off": "the switch is off",
    "MC_EdgeOn": "rising edge of the switch (a falling edge reverses the search)",
    "MC_EdgeOff": "falling edge of the switch (a rising edge reverses the search)",
    "MC_EdgeSwitchPositive": "MC_EdgeOn when searching positive, MC_EdgeOff when negative",
    "MC_EdgeSwitchNegative": "MC_EdgeOff when searching positive, MC_EdgeOn when negative",
    "mcImmediately": "takes effect at once",
    "mcDelayed": "at the end of the running motion (not accepted by this library's blocks)",
    "mcQueued": "queued behind the motion commands given before it, as if Buffered",
    "BORDER": "AuxPoint lies on the arc (no full circle)",
    "CENTER": "AuxPoint is the centre (full circles, Turns)",
    "RADIUS": "AuxPoint's first value is the radius (> 0: at most 180°, < 0: longer)",
    "CLOCKWISE": "clockwise, seen from the positive normal of the plane",
    "COUNTERCLOCKWISE": "counter-clockwise, seen from the positive normal of the plane",
    "TMNone": "round the corner within the group's corner tolerance",
    "TMStartVelocity": "not offered (EParam)",
    "TMConstantVelocity": "not offered (EParam)",
    "TMCornerDistance": "leave the path at most TransitionParameter[0] from the corner",
    "TMMaxCornerDeviation": "deviate at most TransitionParameter[0] from the path",
    "ACS": "the axes' coordinates (without a kinematic transformation the same as MCS)",
    "MCS": "the machine's Cartesian coordinates (through MC_SetKinTransform's kinematics)",
    "PCS": (
        "the product's coordinates: the MCS until MC_SetCoordinateTransform, "
        "MC_SetCartesianTransform, MC_TrackConveyorBelt or MC_TrackRotaryTable sets a product "
        "coordinate system"
    ),
}
"""Meaning of the BufferMode, Direction, SwitchMode and ExecutionMode values (hand-written,
optional)."""

ENUMERATIONS: tuple[type[enum.IntEnum], ...] = (
    mcl.MC_BufferMode,
    mcl.MC_Direction,
    mcl.MC_SwitchMode,
    mcl.MC_ExecutionMode,
    mcl.MC_CIRC_MODE,
    mcl.MC_CIRC_PATHCHOICE,
    mcl.MC_TRANSITION_MODE,
    mcl.MC_COORD_SYSTEM,
)
"""The enumerations the reference lists, in order."""

ANNOUNCED: tuple[tuple[str, str, tuple[str, ...]], ...] = (
    (
        "administrative",
        "Part 1 v2.0",
        (
            "MC_SetPosition",
            "MC_ReadParameter",
            "MC_ReadBoolParameter",
            "MC_WriteParameter",
            "MC_WriteBoolParameter",
            "MC_TouchProbe",
            "GT_SWLim",
        ),
    ),
    (
        "motion",
        "Part 1 v2.0",
        (
            "MC_PositionProfile",
            "MC_VelocityProfile",
            "MC_AccelerationProfile",
            "MC_MoveContinuousAbsolute",
            "MC_MoveContinuousRelative",
        ),
    ),
    ("cams", "Part 1 v2.0", ("MC_CamTableSelect", "MC_CamIn", "MC_CamOut", "MC_Phasing")),
    (
        "homing",
        "Part 5 v2.0",
        ("MC_StepAbsolute", "MC_StepRefFlyingSwitch", "MC_StepRefFlyingRefPulse"),
    ),
    (
        "groups",
        "Part 4 v2.0",
        (
            "MC_MoveCircularAbsolute",
            "MC_MoveCircularRelative",
            "MC_MoveDirectAbsolute",
            "MC_MoveDirectRelative",
            "MC_MovePath",
            "MC_PathSelect",
            "MC_GroupHome",
            "MC_GroupHalt",
            "MC_GroupInterrupt",
            "MC_GroupContinue",
            "MC_GroupSetOverride",
            "MC_GroupSetPosition",
            "MC_GroupReadActualVelocity",
            "MC_GroupReadActualAcceleration",
            "MC_GroupReadConfiguration",
            "MC_SetKinTransform",
            "MC_ReadKinTransform",
            "MC_SetCartesianTransform",
            "MC_SetCoordinateTransform",
            "MC_SyncAxisToGroup",
            "MC_MovePathSynchronized",
            "MC_TrackConveyorBelt",
            "MC_TrackRotaryTable",
        ),
    ),
)
"""The blocks the Teco manual announced (its Tab. 2.2) with PLCopen's newer group blocks, by
family: (family, PLCopen source, block names)."""


# ------------------------------------------------------------------------ docstring cleaning

_CITATION = re.compile(r"MotionControlLib|REXYGEN|Beckhoff|docs/reference\.md")
"""A citation of the source a docstring follows (the Teco manual, another vendor's block) or of
this page itself: in the code it tells where a rule comes from, the reference leaves it out."""
_PAREN = re.compile(r"\s*\(([^()]*)\)")
_FIGURE = re.compile(r"(?:Fig|Tab|note|chapter|section)\b", re.IGNORECASE)
_PART = re.compile(r'(?<!reference\.md)[,;] (?=(?:[^"]*"[^"]*")*[^"]*$)')
"""Separator of the parts of a parenthesis (a comma or semicolon outside quotes; the section name
after docs/reference.md belongs to it)."""


def _markdown(text: str) -> str:
    """reST inline markup to Markdown: ``x`` and :role:`x` become `x`."""
    text = re.sub(r":[a-z]+:`~?([^`]+)`", r"`\1`", text)
    return text.replace("``", "`")


def public_text(text: str) -> str:
    """A docstring passage as the reference shows it: citations go, Markdown comes in.

    The parts of a parenthesis that cite a source (a MotionControlLib section, figure or note,
    another vendor's block, this page) are removed, and the parenthesis with them when nothing
    else is left. Lines are joined and reST markup becomes Markdown.
    """
    text = " ".join(text.split())

    def strip(match: re.Match[str]) -> str:
        if not _CITATION.search(match.group(1)):
            return match.group(0)
        kept = [
            part
            for part in _PART.split(match.group(1))
            if not _CITATION.search(part) and not _FIGURE.match(part)
        ]
        return f" ({', '.join(kept)})" if kept else ""

    return _markdown(_PAREN.sub(strip, text)).strip()


def paragraphs(obj: object) -> list[str]:
    """The paragraphs of the object's own docstring (none inherited)."""
    doc = getattr(obj, "__doc__", None)
    if not isinstance(doc, str):
        return []
    return [p for p in inspect.cleandoc(doc).split("\n\n") if p.strip()]


def summary(obj: object) -> str:
    """The first docstring paragraph, cleaned by :func:`public_text`."""
    found = paragraphs(obj)
    return public_text(found[0]) if found else ""


def _cell(text: str) -> str:
    """Text fit for a Markdown table cell."""
    return text.replace("|", "\\|").replace("\n", " ")


def _wrap(text: str) -> list[str]:
    """A prose paragraph as lines of at most 100 characters."""
    return textwrap.wrap(text, width=100, break_long_words=False, break_on_hyphens=False)


def _anchor(title: str) -> str:
    """The anchor GitHub gives a heading."""
    slug = re.sub(r"[^\w\- ]", "", title.strip().lower())
    return slug.replace(" ", "-")


# ------------------------------------------------------------------------ discovery


def function_blocks() -> list[type[FunctionBlock]]:
    """The public function blocks exported by :mod:`mcl` (``mcl.__all__``; not the base
    classes they share, such as :class:`mcl.MotionFB`)."""
    found: list[type[FunctionBlock]] = []
    for name in mcl.__all__:
        obj = getattr(mcl, name)
        if inspect.isclass(obj) and issubclass(obj, FunctionBlock) and obj.__module__ != "mcl.fb":
            found.append(obj)
    return found


def chapters() -> list[tuple[ModuleType, list[type[FunctionBlock]]]]:
    """The function blocks grouped by the module that defines them, in definition order."""
    by_module: dict[str, list[type[FunctionBlock]]] = {}
    for cls in function_blocks():
        by_module.setdefault(cls.__module__, []).append(cls)

    def module_key(name: str) -> tuple[int, str]:
        short = name.rsplit(".", 1)[-1]
        rank = CHAPTER_ORDER.index(short) if short in CHAPTER_ORDER else len(CHAPTER_ORDER)
        return rank, short

    result: list[tuple[ModuleType, list[type[FunctionBlock]]]] = []
    for name in sorted(by_module, key=module_key):
        module = sys.modules[name]
        order = list(vars(module))
        blocks = sorted(
            by_module[name],
            key=lambda c: order.index(c.__name__) if c.__name__ in order else len(order),
        )
        result.append((module, blocks))
    return result


def _annotation(cls: type, name: str) -> str:
    """The declared type of input ``name`` (the most derived declaration)."""
    for klass in cls.__mro__:
        hints = inspect.get_annotations(klass) or _source_annotations(klass)
        if name in hints:
            hint = hints[name]
            return hint if isinstance(hint, str) else getattr(hint, "__name__", repr(hint))
    return ""


@functools.cache
def _source_annotations(klass: type) -> dict[str, str]:
    """The annotations of ``klass``'s body read from its source: a compiled class keeps none
    (its module is an extension beside the ``.py`` file); empty where there is no source."""
    # from the top package's directory: a compiled module's __file__ is not where it lies
    package = sys.modules.get(klass.__module__.partition(".")[0])
    file = getattr(package, "__file__", None)
    if not file or klass.__module__ == "builtins":
        return {}
    source = Path(file).parent.parent.joinpath(*klass.__module__.split(".")).with_suffix(".py")
    if not source.is_file():
        return {}
    for node in ast.walk(ast.parse(source.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ClassDef) and node.name == klass.__name__:
            return {
                item.target.id: ast.unparse(item.annotation)
                for item in node.body
                if isinstance(item, ast.AnnAssign) and isinstance(item.target, ast.Name)
            }
    return {}


def _in_out_type(name: str) -> str:
    """Type of an in-out reference: the mcl class of that name (``AxesGroup``), else ``Axis``."""
    obj = getattr(mcl, name, None)
    return obj.__name__ if inspect.isclass(obj) else mcl.Axis.__name__


def _value(value: Any) -> str:
    """An input default or output initial value as Markdown."""
    if isinstance(value, enum.IntEnum):
        return f"`{type(value).__name__}.{value.name}` ({int(value)})"
    if isinstance(value, enum.Enum):
        return f"`{type(value).__name__}.{value.name}`"
    return f"`{value!r}`"


def declared_inputs(cls: type[FunctionBlock]) -> dict[str, Any]:
    """The inputs of ``cls`` (not the in-outs) with their declared initial values."""
    instance = cls()
    spec = input_spec(instance)
    defaults: dict[str, Any] = {}
    for name in spec.kinds:
        if name in cls.REFS:
            continue
        for klass in cls.__mro__:
            if name in vars(klass):
                default = vars(klass)[name]
                # a compiled class holds its attributes in descriptors: the instance's value
                compiled = inspect.isdatadescriptor(default) and not isinstance(default, property)
                defaults[name] = getattr(instance, name) if compiled else default
                break
    return defaults


def inputs(cls: type[FunctionBlock]) -> list[tuple[str, str, str]]:
    """(name, type, default) of the in-outs and inputs of ``cls``."""
    rows = [(name, _in_out_type(name), "in-out") for name in cls.REFS]
    for name, default in declared_inputs(cls).items():
        rows.append((name, _annotation(cls, name), _value(default)))
    return rows


def _attributes(instance: object) -> list[tuple[str, object]]:
    """(name, value) of the attributes of ``instance``, base classes' first: its ``__dict__``
    (pure Python) or, for a compiled class (no ``__dict__``), the attributes mypyc declares
    per class."""
    if hasattr(instance, "__dict__"):
        return list(vars(instance).items())
    names: dict[str, None] = {}
    for klass in reversed(type(instance).__mro__):
        names.update(dict.fromkeys(getattr(klass, "__mypyc_attrs__", ())))
    return [(name, getattr(instance, name)) for name in names if hasattr(instance, name)]


def outputs(cls: type[FunctionBlock]) -> list[tuple[str, str, str]]:
    """(name, type, note) of the outputs of ``cls``: the public (capitalised) attributes of a
    fresh instance that are not inputs, then its public properties."""
    names = set(cls.REFS) | set(declared_inputs(cls))
    instance = cls()
    rows: list[tuple[str, str, str]] = []
    attributes = _attributes(instance)
    for name, value in attributes:
        if name[:1].isupper() and name not in names:
            rows.append((name, type(value).__name__, ""))
    names |= {name for name, _ in attributes}
    compiled = not hasattr(instance, "__dict__")
    for name in dir(cls):
        attr = inspect.getattr_static(cls, name, None)
        if not name[:1].isupper() or name in names:
            continue
        if isinstance(attr, property):
            hint = inspect.get_annotations(attr.fget).get("return", "") if attr.fget else ""
            rows.append((name, str(hint), summary(attr.fget)))
        elif compiled and inspect.isdatadescriptor(attr):  # a compiled class' property
            rows.append((name, type(getattr(instance, name)).__name__, ""))
    return rows


def kind(cls: type[FunctionBlock]) -> str:
    """How the block is triggered; empty for blocks with their own rules (see their purpose)."""
    for base, text in FB_KIND:
        if issubclass(cls, base):
            return text
    return ""


# ------------------------------------------------------------------------ rendering


def _chapter_title(module: ModuleType) -> str:
    first = summary(module)
    return first.rstrip(".") if first else module.__name__


def render_block(cls: type[FunctionBlock]) -> list[str]:
    """The section of one function block."""
    lines = [f"### {cls.__name__}", "", *_wrap(summary(cls) or "(no description)"), ""]
    for text in (public_text(p) for p in paragraphs(cls)[1:]):
        if text:
            lines += [*_wrap(text), ""]
    how = kind(cls)
    if how:
        lines += [f"Call: {how}.", ""]
    lines += ["| input | type | default |", "| --- | --- | --- |"]
    rows = [(n, t.replace("|", "\\|"), d) for n, t, d in inputs(cls)]  # a "|" would end a cell
    lines += [f"| `{n}` | `{t}` | {d} |" for n, t, d in rows]
    out = []
    for name, typ, note in outputs(cls):
        extra = f"; {note.rstrip('.')}" if note else ""
        out.append(f"`{name}` ({typ}{extra})")
    lines += ["", *_wrap("Outputs: " + (", ".join(out) if out else "none") + "."), ""]
    return lines


def render_enum(
    title: str, enum_cls: type[enum.IntEnum], meanings: dict[str, str], level: str = "###"
) -> list[str]:
    """A table of the values of an enumeration."""
    lines = [f"{level} {title}", ""]
    text = summary(enum_cls)
    if text:
        lines += [*_wrap(text), ""]
    lines += ["| name | value | meaning |", "| --- | --- | --- |"]
    for member in enum_cls:
        meaning = _cell(meanings.get(member.name, ""))
        lines.append(f"| `{member.name}` | {int(member)} | {meaning} |")
    return [*lines, ""]


def render_table(table: Any) -> list[str]:
    """A module's ``REFERENCE_TABLE`` (header, rows of texts) as a Markdown table; none: no
    lines. It follows the module's text (e.g. the parameter numbers of :mod:`mcl.parameters`)."""
    if table is None:
        return []
    header, rows = table
    lines = ["| " + " | ".join(header) + " |", "|" + " --- |" * len(header)]
    lines += ["| " + " | ".join(_cell(_markdown(cell)) for cell in row) + " |" for row in rows]
    return [*lines, ""]


def render_errors() -> list[str]:
    """The error-code table."""
    lines = [
        "## Error codes",
        "",
        *_wrap(summary(ErrorID)),
        "",
        "| code | name | English | Czech |",
        "| --- | --- | --- | --- |",
    ]
    for code in ErrorID:
        en, cz = _cell(error_text(code, "en")), _cell(error_text(code, "cz"))
        lines.append(f"| {int(code)} | `{code.name}` | {en} | {cz} |")
    return [*lines, ""]


def render_announced() -> list[str]:
    """The table of announced blocks: which the library has and which remain."""
    complete = all(hasattr(mcl, n) for _, _, names in ANNOUNCED for n in names)
    state = (
        "every one of them is available and listed above"
        if complete
        else "available ones are listed above, the others remain"
    )
    lines = [
        "## Announced blocks",
        "",
        *_wrap(
            "The blocks the MotionControlLib announced as being prepared, and PLCopen Part 4's "
            f"group blocks, built to PLCopen's definitions: {state}. GT_Touch, GT_Pulse and "
            "GT_Show have no description in the manual and are not implemented."
        ),
        "",
        "| family | PLCopen | available | remaining |",
        "| --- | --- | --- | --- |",
    ]
    for family, source, names in ANNOUNCED:
        have = [n for n in names if hasattr(mcl, n)]
        missing = [n for n in names if not hasattr(mcl, n)]
        lines.append(
            f"| {family} | {source} | {', '.join(have) or '—'} | {', '.join(missing) or '—'} |"
        )
    return [*lines, ""]


def _contents(groups: Iterable[tuple[ModuleType, Sequence[type[FunctionBlock]]]]) -> list[str]:
    lines = ["## Function blocks", ""]
    for module, blocks in groups:
        title = _chapter_title(module)
        links = ", ".join(f"[{c.__name__}](#{_anchor(c.__name__)})" for c in blocks)
        lines.append(f"- [{title}](#{_anchor(title)}): {links}")
    return [*lines, ""]


def generate() -> str:
    """The whole reference as Markdown, from the interpreted classes (their annotations and
    declared values) in either mode: compiled, it asks a pure-Python interpreter for it."""
    if mcl.COMPILED:
        return subprocess.run(
            [sys.executable, "-m", "mcl.reference"],
            env={**os.environ, "MCL_PURE_PYTHON": "1", "PYTHONIOENCODING": "utf-8"},
            capture_output=True,
            check=True,
            encoding="utf-8",
        ).stdout
    groups = chapters()
    table = ["| from | by | to |", "| --- | --- | --- |"]
    table += [f"| {a} | {b} | {c} |" for a, b, c in AXIS_TRANSITIONS]
    lines = [*INTRO.format(transitions="\n".join(table)).splitlines(), ""]
    lines += _contents(groups)
    for module, blocks in groups:
        lines += [f"## {_chapter_title(module)}", "", f"Module `{module.__name__}`.", ""]
        for text in (public_text(p) for p in paragraphs(module)[1:]):
            if text:
                lines += [*_wrap(text), ""]
        lines += render_table(getattr(module, "REFERENCE_TABLE", None))
        for cls in blocks:
            lines += render_block(cls)
    lines += ["## States", ""]
    lines += render_enum("AxisState", mcl.AxisState, STATE_MEANING)
    lines += render_enum("GroupState", mcl.GroupState, STATE_MEANING)
    lines += ["## Enumerations", ""]
    for enum_cls in ENUMERATIONS:
        lines += render_enum(enum_cls.__name__, enum_cls, ENUM_MEANING)
    lines += render_errors()
    lines += render_announced()
    while lines and not lines[-1]:
        lines.pop()
    return "\n".join(lines) + "\n"


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: print the reference, write it (``--write``) or check it (``--check``)."""
    parser = argparse.ArgumentParser(
        prog="python -m mcl.reference", description="The Markdown reference of mcl."
    )
    action = parser.add_mutually_exclusive_group()
    action.add_argument("--write", action="store_true", help=f"write {DOC_PATH}")
    action.add_argument(
        "--check", action="store_true", help=f"exit 1 when {DOC_PATH} is not up to date"
    )
    args = parser.parse_args(argv)
    text = generate()
    if args.write:
        DOC_PATH.parent.mkdir(parents=True, exist_ok=True)
        DOC_PATH.write_text(text, encoding="utf-8", newline="\n")
        print(f"wrote {DOC_PATH}")
        return 0
    if args.check:
        current = DOC_PATH.read_text(encoding="utf-8") if DOC_PATH.exists() else ""
        if current != text:
            print(f"{DOC_PATH} is out of date: run python -m mcl.reference --write")
            return 1
        return 0
    if isinstance(sys.stdout, io.TextIOWrapper):
        sys.stdout.reconfigure(encoding="utf-8")
    sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
