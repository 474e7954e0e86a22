"""Blocks a machine offers an ST program beyond mcl's (:class:`External`): a Python object
with IEC-style inputs and outputs, e.g. a measuring device of the machine read as a function
block. ``plc.st.load(path, scene, blocks={"FS_CutGauge": External(make, members)})`` lets the
program declare ``gauge : FS_CutGauge;``; a call sets its inputs and calls it, as any block.
"""

from __future__ import annotations

__all__ = ["External"]

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from plc.st.semantics.types import ELEMENTARY, BlockType, Member


@dataclass(frozen=True)
class External:
    """A block type made in Python.

    Attributes:
        make: makes one instance (called once per declared instance).
        members: each input and output by name: (elementary type name, ``"input"`` or
            ``"output"``), e.g. ``{"Index": ("DINT", "input"), "Length": ("LREAL", "output")}``.
    """

    make: Callable[[], Any]
    members: Mapping[str, tuple[str, str]]

    def block_type(self, name: str) -> BlockType:
        """The ST type of the block, named ``name``.

        Raises:
            ValueError: a member of no elementary type or of another direction.
        """
        members = {}
        for member, (type_name, direction) in self.members.items():
            if type_name.upper() not in ELEMENTARY or direction not in ("input", "output"):
                raise ValueError(
                    f"block {name}: member {member} is ({type_name!r}, {direction!r}); "
                    "expected an elementary type and 'input' or 'output'"
                )
            members[member.upper()] = Member(ELEMENTARY[type_name.upper()], direction, member)
        return BlockType(name, "ext", members, name)
