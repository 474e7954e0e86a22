"""The data types of ST programs as the translator sees them: the elementary types with their
IEC widths, and the derived ones (ARRAY, STRUCT, enumeration, function block, AXIS_REF).

Values at run time: BOOL is ``bool``; every integer and bit string is ``int`` (wrapped to its
width on every store); REAL and LREAL are ``float`` (REAL rounded to 32 bits); TIME is ``int``
milliseconds, LTIME ``int`` nanoseconds; DATE, TIME_OF_DAY and DATE_AND_TIME ``int``
milliseconds (since 1970-01-01, since midnight, since 1970-01-01 00:00); STRING is ``str``; an
enumeration value is ``int``; an ARRAY is a ``list`` per dimension; a STRUCT and a function block
are objects; a REF_TO is a :class:`plc.st.runtime.functions.Ref` (NULL: ``_f.NULL``).
"""

from __future__ import annotations

__all__ = [
    "ANY_INT",
    "ANY_REAL",
    "ANY_STRUCT",
    "AXIS",
    "AXIS_FIELDS",
    "BOOL",
    "DINT",
    "ELEMENTARY",
    "GROUP",
    "LINT",
    "LREAL",
    "LTIME",
    "REAL",
    "SEQUENCE",
    "STRING",
    "TIME",
    "ArrayType",
    "BlockType",
    "Elementary",
    "EnumType",
    "Member",
    "RefType",
    "StructType",
    "Type",
    "mask",
    "real_of",
    "string_of",
    "wider",
    "wrap_code",
    "wrap_value",
]

import functools
from dataclasses import dataclass, field


@dataclass(frozen=True)
class Type:
    """A data type; ``name`` as the source spells it in messages."""

    name: str

    @property
    def kind(self) -> str:
        """``bool``, ``int``, ``bits``, ``real``, ``time``, ``date``, ``tod``, ``dt``, ``string``,
        ``enum``, ``array``, ``struct``, ``block``, ``axis``, ``group``, ``ref``."""
        return "?"


@dataclass(frozen=True)
class Elementary(Type):
    """An elementary type: its kind and, for integers and bit strings, its width."""

    base: str = "int"
    bits: int = 0
    signed: bool = False

    @property
    def kind(self) -> str:
        return self.base

    @property
    def numeric(self) -> bool:
        """Takes part in arithmetic (integers, bit strings, reals)."""
        return self.base in ("int", "bits", "real")

    @property
    def integral(self) -> bool:
        """An integer or a bit string."""
        return self.base in ("int", "bits")


def _ints() -> dict[str, Elementary]:
    types: dict[str, Elementary] = {}
    for bits, signed, unsigned, bitstring in (
        (8, "SINT", "USINT", "BYTE"),
        (16, "INT", "UINT", "WORD"),
        (32, "DINT", "UDINT", "DWORD"),
        (64, "LINT", "ULINT", "LWORD"),
    ):
        types[signed] = Elementary(signed, "int", bits, True)
        types[unsigned] = Elementary(unsigned, "int", bits, False)
        types[bitstring] = Elementary(bitstring, "bits", bits, False)
    return types


ELEMENTARY: dict[str, Elementary] = {
    "BOOL": Elementary("BOOL", "bool", 1),
    **_ints(),
    "REAL": Elementary("REAL", "real", 32, True),
    "LREAL": Elementary("LREAL", "real", 64, True),
    "TIME": Elementary("TIME", "time", 32, False),
    "LTIME": Elementary("LTIME", "time", 64, False),
    "STRING": Elementary("STRING", "string", 80),
    "DATE": Elementary("DATE", "date", 64),
    "TOD": Elementary("TOD", "tod", 32),
    "DT": Elementary("DT", "dt", 64),
}
"""The elementary types by name; STRING's ``bits`` is its default length [characters]."""
ELEMENTARY["TIME_OF_DAY"] = ELEMENTARY["TOD"]
ELEMENTARY["DATE_AND_TIME"] = ELEMENTARY["DT"]

BOOL = ELEMENTARY["BOOL"]
DINT = ELEMENTARY["DINT"]
LINT = ELEMENTARY["LINT"]
REAL = ELEMENTARY["REAL"]
LREAL = ELEMENTARY["LREAL"]
TIME = ELEMENTARY["TIME"]
LTIME = ELEMENTARY["LTIME"]
STRING = ELEMENTARY["STRING"]
DATE = ELEMENTARY["DATE"]
TOD = ELEMENTARY["TOD"]
DT = ELEMENTARY["DT"]
ANY_INT = Elementary("ANY_INT", "int", 0, True)
"""An integer literal without a type: it takes the type of the other operand."""
ANY_REAL = Elementary("ANY_REAL", "real", 0, True)
"""A real literal without a type: REAL next to a REAL, else LREAL."""


@dataclass(frozen=True)
class Subrange(Elementary):
    """An integer subrange ``INT (low..high)`` (IEC 61131-3 2.3.3.1, 3rd ed. 6.4.4.4): values
    of its integer type ``of`` within ``low``..``high``."""

    low: int = 0
    high: int = 0
    of: str = "INT"

    @property
    def parent(self) -> Elementary:
        """The integer type it is a subrange of."""
        return ELEMENTARY[self.of]


def plain(t: Type) -> Type:
    """``t``, or the integer type of a subrange (the type of arithmetic on its values)."""
    return t.parent if isinstance(t, Subrange) else t


def string_of(length: int) -> Elementary:
    """STRING(length)."""
    return STRING if length == STRING.bits else Elementary(f"STRING({length})", "string", length)


@dataclass(frozen=True)
class ArrayType(Type):
    """ARRAY[lo..hi, ...] OF element: ``dims`` the bounds of each dimension."""

    element: Type = BOOL
    dims: tuple[tuple[int, int], ...] = ()

    @property
    def kind(self) -> str:
        return "array"


@dataclass(frozen=True)
class StructType(Type):
    """A STRUCT: its fields in order, ``python`` the class generated for it."""

    fields: dict[str, Type] = field(default_factory=dict, hash=False, compare=False)
    python: str = ""

    @property
    def kind(self) -> str:
        return "struct"


@dataclass(frozen=True)
class EnumType(Type):
    """An enumeration: value name → integer; ``base`` the integer type (default INT)."""

    values: dict[str, int] = field(default_factory=dict, hash=False, compare=False)
    base: Elementary = ELEMENTARY["INT"]

    @property
    def kind(self) -> str:
        return "enum"

    @functools.cached_property
    def by_lower_name(self) -> dict[str, int]:
        """The values by lower-case name (IEC names are case-insensitive; the first of
        two names differing only in case wins)."""
        found: dict[str, int] = {}
        for name, value in self.values.items():
            found.setdefault(name.lower(), value)
        return found


@dataclass(frozen=True)
class Member:
    """An input, output or in-out of a block or function: its type and direction."""

    type: Type
    direction: str
    """``input``, ``output``, ``in_out`` or ``local``."""
    python: str
    """Its attribute name in the generated code."""


@dataclass(frozen=True)
class BlockType(Type):
    """A function block type: mcl's (``origin`` ``mcl``), a standard one (``std``) or the
    user's (``user``); ``members`` by their ST names, ``python`` the class to instantiate."""

    origin: str = "user"
    members: dict[str, Member] = field(default_factory=dict, hash=False, compare=False)
    python: str = ""

    @property
    def kind(self) -> str:
        return "block"


@dataclass(frozen=True)
class RefType(Type):
    """AXIS_REF (``axis``) or AXES_GROUP_REF (``group``)."""

    ref: str = "axis"

    @property
    def kind(self) -> str:
        return self.ref


@dataclass(frozen=True)
class ReferenceType(Type):
    """REF_TO target (IEC 61131-3 ed. 3, 6.4.4.10): a reference to a variable of ``target``."""

    target: Type = BOOL

    @property
    def kind(self) -> str:
        return "ref"


NULL = ReferenceType("NULL", Type("ANY"))
"""The type of the literal NULL: a reference to nothing, assignable to every REF_TO."""

AXIS = RefType("AXIS_REF", "axis")
GROUP = RefType("AXES_GROUP_REF", "group")
AXIS_FIELDS: dict[str, tuple[str, Type]] = {
    "POS": ("POS", LREAL),
    "VEL": ("VEL", LREAL),
    "AXERRORID": ("AxErrorID", DINT),
}
"""The fields of an AXIS_REF a program reads (read-only), by upper-case name: (the axis'
attribute, type): the actual position POS [u], velocity VEL [u/s], the error AxErrorID."""
SEQUENCE = ArrayType("ARRAY OF LREAL", LREAL, ((0, -1),))
"""A group block's per-member values (any length)."""
ANY_STRUCT = StructType("ANY STRUCT")
"""A profile block's table: any STRUCT, passed as it is (the block reads its fields by name)."""


def mask(t: Elementary) -> int:
    """All bits of an integer type set."""
    return (1 << t.bits) - 1


def wrap_value(value: int, t: Elementary) -> int:
    """``value`` wrapped to the width of integer type ``t``."""
    if not t.bits:
        return value
    if t.signed:
        half = 1 << (t.bits - 1)
        return ((value + half) & mask(t)) - half
    return value & mask(t)


def wrap_code(code: str, t: Elementary) -> str:
    """Python code wrapping the integer ``code`` to the width of ``t`` (inline arithmetic)."""
    if not t.bits:
        return code
    if t.signed:
        half = 1 << (t.bits - 1)
        return f"(((({code}) + {half}) & {mask(t)}) - {half})"
    return f"(({code}) & {mask(t)})"


def wider(a: Elementary, b: Elementary) -> Elementary:
    """The type of an integer operation on ``a`` and ``b``: the wider one (a literal takes
    the other's)."""
    if a is ANY_INT or not a.bits:
        return b
    if b is ANY_INT or not b.bits:
        return a
    return b if b.bits > a.bits else a


def real_of(a: Elementary, b: Elementary) -> Elementary:
    """The type of a real operation: LREAL unless no operand is LREAL and one is REAL."""
    names = {a.name, b.name}
    if "LREAL" in names:
        return LREAL
    return REAL if "REAL" in names else LREAL
