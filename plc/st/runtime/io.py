"""Located variables (``AT %IX0.2``) and named I/O: the machine's digital inputs, digital
outputs and analog inputs as ST variables (:class:`Address`).

The address scheme, per axis of the machine (its index in the machine definition's order,
``scene.axes``, from 0):

- ``%IX<axis>.<bit>``: digital input ``bit`` (0 LIM+, 1 LIM−, 2 REF, 3 TP, 4… further inputs;
  ``mcl.Axis.DI``), a BOOL;
- ``%QX<axis>.<bit>``: digital output ``bit`` (``mcl.Axis.DO``, e.g. the flying shear's knife),
  a BOOL;
- ``%IW<axis>.<channel>`` (or ``%ID``, ``%IL``): analog input ``channel`` in volts
  (``mcl.Axis.AI``), a REAL or LREAL.

A mapping names I/O by the same addresses or by axis name: ``{"Knife": "%QX2.0"}`` or
``{"Knife": "S.DO0"}`` (also ``S.DI2``, ``S.AI0``) binds the variable ``Knife``. Inputs are read
when the program's scan begins, outputs written when it ends (the process image); a variable on
an output owns it (an MC_WriteDigitalOutput on the same output is overwritten every scan).
"""

from __future__ import annotations

__all__ = ["Address", "Channels", "address", "channels", "location_text"]

import re
from dataclasses import dataclass
from typing import Any

from plc.st.semantics import types as T  # noqa: N812
from plc.st.semantics.types import Type

_ADDRESS = re.compile(r"%([IQ])([XBWDL]?)(\d+)\.(\d+)$", re.IGNORECASE)
_NAMED = re.compile(r"(.+)\.(DI|DO|AI)(\d+)$", re.IGNORECASE)
_DI = ("lim_pos", "lim_neg", "ref", "tp")
"""The channel attributes of digital inputs 0…3 (further inputs: ``io.inputs[k - 4]``)."""


@dataclass(frozen=True)
class Address:
    """One I/O point of the machine.

    Attributes:
        kind: ``"DI"``, ``"DO"`` or ``"AI"``.
        axis: the axis' name.
        number: the input's, output's or channel's number on the axis.
    """

    kind: str
    axis: str
    number: int

    @property
    def output(self) -> bool:
        """Written at the end of the scan."""
        return self.kind == "DO"

    def code(self, axis: str) -> str:
        """The Python expression of the point on the axis object ``axis`` (assignable for an
        output)."""
        if self.kind == "DO":
            return f"{axis}.io.outputs[{self.number}]"
        if self.kind == "AI":
            return f"{axis}.io.analog[{self.number}]"
        if self.number < len(_DI):
            return f"{axis}.io.{_DI[self.number]}"
        return f"{axis}.io.inputs[{self.number - len(_DI)}]"

    def check_type(self, t: Type) -> str:
        """Empty if a variable of type ``t`` fits the point, else what would."""
        if self.kind == "AI":
            return "" if t in (T.REAL, T.LREAL) else "a REAL or LREAL (volts)"
        return "" if t is T.BOOL else "a BOOL"


Channels = dict[str, tuple[int, int, int]]
"""Per axis name: how many digital inputs, digital outputs and analog inputs it has."""


def channels(axes: dict[str, Any]) -> Channels:
    """The I/O counts of a machine's axes (``mcl.Axis``; anything else has none)."""
    found: Channels = {}
    for name, axis in axes.items():
        io = getattr(axis, "io", None)
        inputs = len(getattr(io, "inputs", ())) + len(_DI) if io is not None else 0
        found[name] = (
            inputs,
            len(getattr(io, "outputs", ())),
            len(getattr(io, "analog", ())),
        )
    return found


def address(text: str, axes: Channels) -> tuple[Address | None, str]:
    """The point ``text`` names (``%QX2.0`` or ``S.DO0``), or None and why not."""
    names = list(axes)
    located = _ADDRESS.match(text.strip())
    if located:
        prefix, size, index, number = located.groups()
        if int(index) >= len(names):
            return None, f"axis index {index}: the machine has {len(names)} axes (0…)"
        if prefix.upper() == "Q" and size.upper() not in ("", "X"):
            return None, "the machine has no analog outputs (%QX only)"
        kind = "DO" if prefix.upper() == "Q" else "DI" if size.upper() in ("", "X") else "AI"
        return _checked(Address(kind, names[int(index)], int(number)), axes)
    named = _NAMED.match(text.strip())
    if named:
        axis = next((a for a in names if a.lower() == named.group(1).lower()), None)
        if axis is None:
            return None, f"no axis {named.group(1)!r} (axes: {', '.join(names) or 'none'})"
        return _checked(Address(named.group(2).upper(), axis, int(named.group(3))), axes)
    return None, "an address %IX<axis>.<bit>, %QX<axis>.<bit>, %IW<axis>.<channel> or AXIS.DO0"


def _checked(point: Address, axes: Channels) -> tuple[Address | None, str]:
    """The point if its axis has it, else None and what it has."""
    count = axes[point.axis][["DI", "DO", "AI"].index(point.kind)]
    if point.number >= count:
        what = {"DI": "digital inputs", "DO": "digital outputs", "AI": "analog inputs"}
        return None, f"axis {point.axis} has {count} {what[point.kind]} (0…)"
    return point, ""


def location_text(location: Any) -> str:
    """The text of a blark location node (``%IX0.2``)."""
    bits = "".join(f".{b}" for b in (getattr(location, "bits", None) or []))
    size = getattr(location, "size_prefix", None)
    size_text = getattr(size, "value", "") if size is not None else ""
    prefix = getattr(location.location_prefix, "value", "")
    return f"%{prefix}{size_text}{location.location}{bits}"
