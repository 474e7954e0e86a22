"""The register map of a machine as an integrator reads it (``python -m scenes bridge map NAME``):
the unit id and the ones refused, each axis' block with its travel limits, limit switches and
homing, every register, and what the ErrorIDs mean."""

from __future__ import annotations

__all__ = ["NEGATIVE", "SWITCHES", "csv", "markdown"]

import mujoco

import mcl
from mcl.errors import error_text
from plc.procedures import BlockHoming, Recipe
from scenes.bridge.table import AXIS_BASE, AXIS_BLOCK, AXIS_STRIDE, SignalTable
from scenes.definition import AxisDef, MachineDef, unit_and_scale
from scenes.scene import model_path

SWITCHES = {"lim_neg": "LIM−", "lim_pos": "LIM+", "ref": "REF"}
"""The limit and reference switches by their names in a definition."""

NEGATIVE = (mcl.MC_Direction.MC_Negative, mcl.MC_Direction.MC_SwitchNegative)
"""The directions towards negative positions."""


def markdown(table: SignalTable) -> str:
    """The register map of ``table`` as Markdown."""
    others = [str(u) for u in table.units if u != table.unit_id]
    served = (
        f"Unit id {' and '.join(others)} serves the cell's other part; any other"
        if others
        else "Every other unit id"
    )
    lines = [
        f"# Register map of {table.machine}",
        "",
        f"Modbus TCP holding registers of unit id {table.unit_id} (function codes 3 and 4 read, "
        "6, 16, 22 and 23 write; any other: exception 1, ILLEGAL_FUNCTION). "
        f"{served} is refused with exception 10 (GATEWAY_PATH_UNAVAILABLE), also 0 and 255, "
        "which some masters send by default. PDU addresses from 0; u32 and f32 in two "
        "registers, high word first; u: the axis' user unit (mm on a slide, deg on a hinge).",
        "",
        f"Every axis has a block of {AXIS_BLOCK} registers of the same shape, from its base "
        "address: the registers of a block that are no field of its axis are reserved — they "
        "read 0 and take 0 (another value: exception 3, ILLEGAL_VALUE) — so that one write "
        "block fits every axis.",
        "",
        "## Axes",
        "",
        "| axis | block | unit | travel | switches | velocity | homing (the home bit, MC_Home) |",
        "|---|---|---|---|---|---|---|",
    ]
    axes = zip(table.axes, table.definition.axes.values(), _units(table.definition), strict=True)
    for i, (name, axis, unit) in enumerate(axes):
        base = AXIS_BASE + AXIS_STRIDE * i
        switches = ", ".join(SWITCHES[s] for s in axis.switches if s in SWITCHES) or "none"
        lines.append(
            f"| {name} | {base} … {base + AXIS_BLOCK - 1} | {unit} | {_travel(axis, unit)} "
            f"| {switches} | {_velocity(axis, unit)} | {_homing(axis.homing, name, unit)} |"
        )
    lines += [
        "",
        "## Registers",
        "",
        "| address | name | type | access | unit | description |",
        "|---:|---|---|---|---|---|",
    ]
    lines += [
        f"| {f.address} | {f.name} | {f.kind} | {f.access} | {f.unit} | {f.description} |"
        for f in table.fields
    ]
    lines += [
        "",
        "## ErrorID",
        "",
        "`error_id` (of the current command) and `axis_error_id` (of the axis):",
        "",
        "| ErrorID | name | meaning |",
        "|---:|---|---|",
    ]
    lines += [f"| {int(e)} | {e.name} | {error_text(e)} |" for e in mcl.ErrorID]
    return "\n".join(lines)


def csv(table: SignalTable) -> str:
    """The registers of ``table`` as CSV."""
    rows = ["address,name,type,access,unit,description"]
    rows += [
        f'{f.address},{f.name},{f.kind},{f.access},{f.unit},"{f.description}"' for f in table.fields
    ]
    return "\n".join(rows)


def _units(machine: MachineDef) -> list[str]:
    """The user units of a machine's axes in order: mm on a slide, deg on a hinge joint of
    its model, unless the definition names one."""
    if not machine.model:
        return [unit_and_scale(a, rotary=False)[0] for a in machine.axes.values()]
    model = mujoco.MjModel.from_xml_path(str(model_path(machine.model)))
    hinge = mujoco.mjtJoint.mjJNT_HINGE
    return [
        unit_and_scale(a, int(model.joint(a.joint or name).type[0]) == hinge)[0]
        for name, a in machine.axes.items()
    ]


def _number(value: float) -> str:
    return f"{value:g}".replace("-", "−")


def _travel(axis: AxisDef, unit: str) -> str:
    """The software limits of an axis (a target beyond them: ErrorID 8), or that it has none."""
    if axis.drive == "encoder":
        return "encoder only (no drive)"
    constants = axis.constants
    if constants is None or not constants.LimPos > constants.LimNeg:
        return "no software limits"
    return f"{_number(constants.LimNeg)} … {_number(constants.LimPos)} {unit} (software limits)"


def _velocity(axis: AxisDef, unit: str) -> str:
    """The velocities the moves and jogs of an axis take: from 1 % of Vmax (below: ErrorID 5)
    up to Vmax (beyond: clamped)."""
    constants = axis.constants
    if axis.drive == "encoder" or constants is None:
        return "—"
    vmax = constants.Vmax
    return (
        f"{_number(0.01 * vmax)} … {_number(vmax)} {unit}/s (below 1 % of Vmax: ErrorID 5; "
        "beyond Vmax: Vmax)"
    )


def _homing(recipe: Recipe | None, axis: str, unit: str) -> str:
    """How the home bit homes an axis, and the position it sets."""
    if recipe is None:
        return "none (the home bit gives Error, ErrorID 5)"
    if isinstance(recipe, BlockHoming):
        way = "negative" if recipe.direction in NEGATIVE else "positive"
        return (
            f"to the mechanical block ({way}), backs off: {axis} = "
            f"{_number(recipe.set_position)} {unit} there"
        )
    way = "negative" if recipe.direction in NEGATIVE else "positive"
    index = "negative" if recipe.index_direction in NEGATIVE else "positive"
    return (
        f"REF switch ({way}), then the index pulse ({index}): {axis} = "
        f"{_number(recipe.set_position)} {unit} at the index pulse"
    )
