"""Every registered machine keeps the contract: its MJCF model has the names and numerics
models/README.md lists for it and follows the README's conventions for each axis (drive,
encoder, switches, end stops), it compiles and steps, its demo runs and moves the machine, and a
state saved at power-up repeats the demo bit for bit in a fresh scene.

The tests iterate the registry (:data:`scenes.MACHINES`): a machine registered later is checked
without an edit here. Judged on the physics (MuJoCo joint coordinates, site positions).
"""

from __future__ import annotations

import fnmatch
import functools
import math
import re
from collections.abc import Iterator
from pathlib import Path

import mujoco
import numpy as np
import pytest

import scenes
from scenes.definition import AxisDef, MachineDef
from scenes.scene import MODELS, model_path

README = MODELS / "README.md"
SWITCHES = ("lim_neg", "lim_pos", "ref")
SLIDE, HINGE = int(mujoco.mjtJoint.mjJNT_SLIDE), int(mujoco.mjtJoint.mjJNT_HINGE)
NAMES = sorted(scenes.MACHINES)
"""Every registered machine."""
DEMO_SECONDS = 3.0
"""How long each demo runs in the demo test [s of simulated time]."""
MOVED = 1e-3
"""Least travel of some axis joint that counts as "the demo moved the machine" [m or rad]."""
KINDS = {
    "keyframe": mujoco.mjtObj.mjOBJ_KEY,
    "body": mujoco.mjtObj.mjOBJ_BODY,
    "joint": mujoco.mjtObj.mjOBJ_JOINT,
    "actuator": mujoco.mjtObj.mjOBJ_ACTUATOR,
    "sensor": mujoco.mjtObj.mjOBJ_SENSOR,
    "site": mujoco.mjtObj.mjOBJ_SITE,
    "geom": mujoco.mjtObj.mjOBJ_GEOM,
    "tendon": mujoco.mjtObj.mjOBJ_TENDON,
    "equality": mujoco.mjtObj.mjOBJ_EQUALITY,
}
"""The kinds of the README's "Names the code relies on" tables and their MuJoCo object types."""


# ------------------------------------------------------------------------ model helpers
def num(model: mujoco.MjModel, name: str) -> np.ndarray:
    """A custom numeric's values."""
    return np.asarray(model.numeric(name).data, dtype=float)


def switch_on(model: mujoco.MjModel, data: mujoco.MjData, axis: str, kind: str) -> bool:
    """The switch formula of models/README.md, from site positions only."""
    e = data.xaxis[model.joint(axis).id]
    cam = data.site_xpos[model.site(f"{axis}_{kind}_cam").id]
    sw = data.site_xpos[model.site(f"{axis}_{kind}").id]
    lo, hi = num(model, f"{axis}_{kind}_window")
    d = float((cam - sw) @ e)
    return lo <= d <= hi


def trip(model: mujoco.MjModel, axis: str, kind: str) -> float:
    """The joint coordinate where switch ``kind`` of ``axis`` trips [m]."""
    name = f"{axis}_ref_edge" if kind == "ref" else f"{axis}_{kind}_trip"
    return float(num(model, name)[0])


def place(model: mujoco.MjModel, data: mujoco.MjData, axis: str, q: float) -> None:
    """Put joint ``axis`` at ``q`` [m or rad] and update the positions."""
    data.qpos[model.jnt_qposadr[model.joint(axis).id]] = q
    mujoco.mj_forward(model, data)


def run(model: mujoco.MjModel, data: mujoco.MjData, seconds: float) -> None:
    """Step the bare model for ``seconds`` [s]."""
    mujoco.mj_step(model, data, nstep=round(seconds / model.opt.timestep))


def modelled(name: str) -> list[MachineDef]:
    """The machines whose models the registered machine ``name`` brings: itself, or the parts
    of a cell that are not registered under their own names (skips when there are none)."""
    machine = scenes.MACHINES[name]
    if machine.model:
        return [machine]
    parts = [part.machine for part in getattr(machine, "parts", ())]
    own = [m for m in parts if m.model and scenes.MACHINES.get(m.name) is not m]
    if not own:
        why = "its parts are checked under their own names" if parts else "simulated axes"
        pytest.skip(f"{name}: no MJCF model of its own ({why})")
    return own


@functools.cache
def _compiled(file: str) -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_path(str(model_path(file)))


def compiled(machine: MachineDef) -> mujoco.MjModel:
    """The machine's MJCF file compiled on its own (unprefixed names; do not modify)."""
    return _compiled(machine.model)


def at_home(model: mujoco.MjModel) -> mujoco.MjData:
    """Fresh data at the keyframe ``home``, positions current."""
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key("home").id)
    mujoco.mj_forward(model, data)
    return data


def axes(machine: MachineDef) -> Iterator[tuple[str, AxisDef]]:
    """The machine's axes as (joint name in its model, definition)."""
    for axis, spec in machine.axes.items():
        yield spec.joint or axis, spec


def slides_with_switches(machine: MachineDef) -> list[tuple[str, tuple[str, ...]]]:
    """The machine's slide axes that have switches, with their switch kinds."""
    model = compiled(machine)
    return [
        (joint, spec.switches)
        for joint, spec in axes(machine)
        if spec.switches and model.jnt_type[model.joint(joint).id] == SLIDE
    ]


# ------------------------------------------------------------------------ README contract
def cells(line: str) -> list[str]:
    """The cells of one Markdown table row (``\\|`` is a literal bar)."""
    return [c.strip() for c in re.split(r"(?<!\\)\|", line.strip().strip("|"))]


def section(machine: MachineDef) -> str | None:
    """The README section of the machine's model file (None: the README has none)."""
    text = README.read_text(encoding="utf-8")
    file = Path(machine.model).name
    head = re.search(rf"^## \S+ \(`{re.escape(file)}`\)$", text, re.MULTILINE)
    if head is None:
        return None
    end = text.find("\n## ", head.end())
    return text[head.end() : end if end >= 0 else len(text)]


def tables(text: str, heading: str) -> list[list[str]]:
    """The data rows of the table under each ``### `` heading that matches ``heading``."""
    rows: list[list[str]] = []
    for head in re.finditer(rf"^### {heading}.*$", text, re.MULTILINE):
        lines = text[head.end() :].lstrip("\n").splitlines()
        body = [line for line in _table(lines)]
        rows += [cells(line) for line in body[2:]]  # header and --- row
    return rows


def _table(lines: list[str]) -> Iterator[str]:
    """The lines of the first table in ``lines`` (text before it skipped, stops after it)."""
    started = False
    for line in lines:
        if line.startswith("|"):
            started = True
            yield line
        elif started or line.startswith("### "):
            return


def expand(cell: str, axes: list[str]) -> list[str]:
    """The names in a README cell: each backticked name; ``A_…`` once per axis (``(A = X, Y)``
    in the cell, else the machine's axes); a name starting with ``_`` is a suffix of every
    name before it ("and their `_cam` sites")."""
    letters = re.search(r"\(A = ([^)]*)\)", cell)
    values = [v.strip() for v in letters.group(1).split(",")] if letters else axes
    names: list[str] = []
    for token in re.findall(r"`([^`]+)`", cell):
        if token.startswith("_"):
            names += [n + token for n in names]
        elif token.startswith("A_"):
            names += [v + token[1:] for v in values]
        else:
            names.append(token)
    return names


def contract(machine: MachineDef) -> str:
    """The machine's README section (skips a machine whose model lives outside ``models/``)."""
    name = machine.name
    text = section(machine)
    if text is None:
        assert not (MODELS / Path(machine.model).name).is_file(), (
            f"models/README.md has no section '## … (`{Path(machine.model).name}`)' for {name}"
        )
        pytest.skip(f"{name}: its model {machine.model} is not one of models/")
    return text


NUMBER = re.compile(
    r"(?P<pi>\d*)π(?:/(?P<div>\d+))?"
    r"|(?P<n>[-−]?(?:\d{1,3}(?: \d{3})+|\d+)(?:\.(?P<dec>\d+))?(?:e(?P<exp>[-−+]?\d+))?)"
)
"""A number as the README writes it: ``−0.070``, ``5.0e-4``, ``12 000``, ``2π/5``."""


def numbers(cell: str) -> list[tuple[float, float]]:
    """The numbers of a README value cell, each with its tolerance (half its last digit)."""
    found = []
    for m in NUMBER.finditer(cell):
        if m.group("n") is None:
            value = float(m.group("pi") or 1) * math.pi / float(m.group("div") or 1)
            found.append((value, 1e-12))
            continue
        text = m.group("n").replace("−", "-").replace(" ", "")
        exp = int((m.group("exp") or "0").replace("−", "-"))
        found.append((float(text), 0.5 * 10.0 ** (exp - len(m.group("dec") or ""))))
    return found


@pytest.mark.parametrize("name", NAMES)
def test_every_name_the_readme_lists_for_the_machine_is_in_its_model(name: str) -> None:
    for machine in modelled(name):
        text = contract(machine)
        model = compiled(machine)
        joints = [joint for joint, _ in axes(machine)]
        rows = tables(text, "Names the code relies on")
        assert rows, f"{name}: no table under '### Names the code relies on'"
        missing = []
        for row in rows:
            kind = KINDS[row[0]]  # KeyError: a kind this test does not know yet
            for pattern in expand(row[1], joints):
                if "*" in pattern:
                    count = {"geom": model.ngeom, "site": model.nsite, "sensor": model.nsensor}[
                        row[0]
                    ]
                    have = [mujoco.mj_id2name(model, kind, i) or "" for i in range(count)]
                    if not fnmatch.filter(have, pattern):
                        missing.append(f"{row[0]} {pattern}")
                elif mujoco.mj_name2id(model, kind, pattern) < 0:
                    missing.append(f"{row[0]} {pattern}")
        assert not missing, f"{name}: the README lists names its model lacks: {missing}"


@pytest.mark.parametrize("name", NAMES)
def test_every_numeric_the_readme_lists_has_its_size_and_value(name: str) -> None:
    """Each numeric of the README's numerics tables exists with the listed size; where the
    value cell gives one number per element, the model's values are those numbers (to the
    README's last digit)."""
    for machine in modelled(name):
        text = contract(machine)
        model = compiled(machine)
        joints = [joint for joint, _ in axes(machine)]
        rows = tables(text, r".*[Nn]umerics")
        assert rows, f"{name}: no numerics table in its README section"
        for row in rows:
            names, size, values = expand(row[0], joints), int(row[1]), numbers(row[3])
            assert names, row
            for numeric in names:
                assert mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_NUMERIC, numeric) >= 0, numeric
                assert num(model, numeric).shape == (size,), numeric
            have = np.concatenate([num(model, n) for n in names])
            if len(values) == have.size:
                for (want, tol), got, where in zip(
                    values, have, np.repeat(names, size), strict=True
                ):
                    assert got == pytest.approx(want, abs=tol, rel=1e-9), (where, row[3])


def axes_table(text: str) -> dict[str, list[str]]:
    """The README's table of the machine's joints (the one with a ``joint, type`` row): row
    label → one cell per joint column."""
    lines = text.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("| joint, type"))
    while lines[start - 1].startswith("|"):
        start -= 1
    return {row[0]: row[1:] for row in map(cells, _table(lines[start:])) if row[0] != "---"}


@pytest.mark.parametrize("name", NAMES)
def test_each_joint_has_the_type_direction_and_range_the_readme_gives(name: str) -> None:
    for machine in modelled(name):
        model = compiled(machine)
        data = at_home(model)
        table = axes_table(contract(machine))
        ranges = next(v for k, v in table.items() if "range" in k)
        for kind, limits in zip(table["joint, type"], ranges, strict=True):
            joint = re.search(r"`([^`]+)`", kind)
            assert joint is not None, kind
            j = model.joint(joint.group(1)).id
            slide = re.search(r"\b(slide|hinge)\b", kind)
            assert slide is not None, kind
            want = SLIDE if slide.group(1) == "slide" else HINGE
            assert model.jnt_type[j] == want, kind
            vector = re.search(r"axis \(([^)]*)\)", kind)  # a direction off the world's axes
            if vector is not None:
                given = numbers(vector.group(1))
                e, tol = np.array([v for v, _ in given]), max(t for _, t in given)
            else:
                sign, axis = re.search(r"([+−-])([xyz])\b", kind).groups()  # type: ignore[union-attr]
                e, tol = np.zeros(3), 1e-12
                e["xyz".index(axis)] = -1.0 if sign != "+" else 1.0
            np.testing.assert_allclose(data.xaxis[j], e, atol=tol, err_msg=kind)
            if limits.startswith("none"):
                assert not model.jnt_limited[j], kind
            else:
                assert model.jnt_limited[j], kind
                lo, hi = (v for v, _ in numbers(limits)[:2])
                np.testing.assert_allclose(model.jnt_range[j], [lo, hi], atol=1e-12, err_msg=kind)


# ------------------------------------------------------------------------ axis conventions
@pytest.mark.parametrize("name", NAMES)
def test_each_axis_has_what_the_plant_needs(name: str) -> None:
    """Per axis, the conventions of models/README.md: a slide or hinge joint, its sensors,
    its encoder's numerics, its amplifier (electric drive), each switch's sites, geoms and
    window, and with LIM switches the hard stops, trip points and working travel."""
    for machine in modelled(name):
        model = compiled(machine)
        assert model.opt.timestep == pytest.approx(0.0005)
        model.key("home")
        for ax, spec in axes(machine):
            assert model.jnt_type[model.joint(ax).id] in (SLIDE, HINGE)
            for suffix in ("pos", "vel", *(("force",) if spec.drive == "electric" else ())):
                model.sensor(f"{ax}_{suffix}")
            for numeric in ("lead", "counts_per_rev", "index_width"):
                assert num(model, f"{ax}_{numeric}").shape == (1,)
            if spec.drive == "electric":
                model.actuator(f"{ax}_amp")
                for numeric in ("vmax", "kamp"):
                    assert num(model, f"{ax}_{numeric}").shape == (1,)
            for kind in spec.switches:
                model.site(f"{ax}_{kind}")
                model.site(f"{ax}_{kind}_cam")
                model.geom(f"{ax}_{kind}_geom")
                model.geom(f"{ax}_{kind}_cam_geom")
                assert num(model, f"{ax}_{kind}_window").shape == (2,)
                assert num(
                    model, f"{ax}_ref_edge" if kind == "ref" else f"{ax}_{kind}_trip"
                ).shape == (1,)
            if {"lim_neg", "lim_pos"} <= set(spec.switches):
                assert model.jnt_limited[model.joint(ax).id]
                assert num(model, f"{ax}_travel").shape == (2,)


@pytest.mark.parametrize("name", NAMES)
def test_the_home_keyframe_puts_every_joint_at_0_and_the_switches_as_their_trips_say(
    name: str,
) -> None:
    for machine in modelled(name):
        model = compiled(machine)
        data = at_home(model)
        for j in range(model.njnt):
            if model.jnt_type[j] in (SLIDE, HINGE):
                assert data.qpos[model.jnt_qposadr[j]] == 0.0, model.joint(j).name
        np.testing.assert_array_equal(data.act, 0.0)
        for ax, kinds in slides_with_switches(machine):
            for kind in kinds:
                at = trip(model, ax, kind)
                want = at <= 0.0 if kind == "lim_pos" else at >= 0.0
                assert switch_on(model, data, ax, kind) == want, (ax, kind)


@pytest.mark.parametrize("name", NAMES)
def test_drive_parameters_are_consistent(name: str) -> None:
    for machine in modelled(name):
        model = compiled(machine)
        for ax, spec in axes(machine):
            j = model.joint(ax).id
            if spec.drive == "electric":
                a = model.actuator(f"{ax}_amp").id
                lead = num(model, f"{ax}_lead")[0]
                vmax, kamp = num(model, f"{ax}_vmax")[0], num(model, f"{ax}_kamp")[0]
                if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_NUMERIC, f"{ax}_J") >= 0:
                    J = num(model, f"{ax}_J")[0]
                    armature = model.dof_armature[model.jnt_dofadr[j]]
                    assert armature == pytest.approx(J * (2 * math.pi / lead) ** 2)
                if model.jnt_type[j] == SLIDE:  # 1 count = 1 µm of travel
                    assert num(model, f"{ax}_counts_per_rev")[0] * 1e-6 == pytest.approx(lead)
                np.testing.assert_array_equal(model.actuator_ctrlrange[a], [-10.0, 10.0])
                assert model.actuator_gainprm[a, 0] == pytest.approx(kamp * vmax / 10.0)
                assert model.actuator_biasprm[a, 2] == pytest.approx(-kamp)
                assert model.actuator_dyntype[a] == mujoco.mjtDyn.mjDYN_FILTEREXACT
                assert model.actuator_actearly[a]
                assert model.actuator_forcelimited[a]
                # the drive holds the weight its joint carries, ten times over
                weight = 0.0  # a hinge's weight torque is not a force of its amplifier
                if model.jnt_type[j] == SLIDE:
                    mass = model.body_subtreemass[model.jnt_bodyid[j]]
                    weight = abs(float(model.jnt_axis[j] @ model.opt.gravity)) * mass
                assert model.actuator_forcerange[a, 1] > 10 * weight, ax
            if {"lim_neg", "lim_pos"} <= set(spec.switches):
                # the hard stops lie beyond the LIM trip points, which lie beyond the travel
                lo, hi = model.jnt_range[j]
                tlo, thi = num(model, f"{ax}_travel")
                assert (
                    lo < trip(model, ax, "lim_neg") < tlo and thi < trip(model, ax, "lim_pos") < hi
                )


def reach(model: mujoco.MjModel, ax: str) -> tuple[float, float]:
    """The joint's range, or ±1 m around its switches on an unlimited joint [m]."""
    j = model.joint(ax).id
    if model.jnt_limited[j]:
        lo, hi = model.jnt_range[j]
        return float(lo), float(hi)
    return -1.0, 1.0


Placed = tuple[mujoco.MjModel, mujoco.MjData, str, tuple[str, ...], float]
"""A model, its data with one axis placed, the axis, its switch kinds, its coordinate [m]."""


def swept(name: str, count: int = 0) -> Iterator[Placed]:
    """Each slide axis with switches of the machine's models placed in turn (the rest at home):
    at ``count`` coordinates across its reach, or (``count`` 0) at both ends of its reach and
    1 mm either side of each trip point."""
    for machine in modelled(name):
        model = compiled(machine)
        data = at_home(model)
        for ax, kinds in slides_with_switches(machine):
            lo, hi = reach(model, ax)
            points = [lo, hi, *(trip(model, ax, k) + dq for k in kinds for dq in (-1e-3, 1e-3))]
            for q in np.linspace(lo, hi, count) if count else points:
                place(model, data, ax, q)
                yield model, data, ax, kinds, float(q)


@pytest.mark.parametrize("name", NAMES)
def test_switch_formula_at_joint_positions(name: str) -> None:
    """The geometric formula equals the joint-coordinate form d = q - trip, and each switch is
    on where the README's table says: LIM− at and below its trip, LIM+ at and above its trip,
    REF below its edge."""
    for model, data, ax, kinds, q in swept(name, 61):
        for kind in kinds:
            e = data.xaxis[model.joint(ax).id]
            cam = data.site_xpos[model.site(f"{ax}_{kind}_cam").id]
            sw = data.site_xpos[model.site(f"{ax}_{kind}").id]
            assert (cam - sw) @ e == pytest.approx(q - trip(model, ax, kind), abs=1e-9)
    for model, data, ax, kinds, q in swept(name):
        got = tuple(switch_on(model, data, ax, k) for k in kinds)
        at = {k: trip(model, ax, k) for k in kinds}
        want = tuple(q >= at[k] if k == "lim_pos" else q <= at[k] for k in kinds)
        assert got == want, (ax, q)


@pytest.mark.parametrize("name", NAMES)
def test_dog_geoms_match_switch_windows(name: str) -> None:
    """What a viewer shows agrees with the formula: a switch is on iff its site is over its dog."""
    for model, data, ax, kinds, q in swept(name, 97):
        e = data.xaxis[model.joint(ax).id]
        for kind in kinds:
            g = model.geom(f"{ax}_{kind}_cam_geom").id
            half = np.abs(data.geom_xmat[g].reshape(3, 3).T @ e) @ model.geom_size[g]
            s = (data.site_xpos[model.site(f"{ax}_{kind}").id] - data.geom_xpos[g]) @ e
            if abs(abs(s) - half) > 1e-6:  # skip the edges themselves
                assert (abs(s) < half) == switch_on(model, data, ax, kind), (ax, kind, q)


def test_the_readme_parser_finds_the_gantry_contract() -> None:
    """The README tables the contract reads give the gantry's names as the README writes them
    (so an unreadable table cannot pass by finding nothing)."""
    text = section(scenes.MACHINES["gantry"])
    assert text is not None
    axes_ = ["X", "Y", "Z"]
    names = {n for row in tables(text, "Names the code relies on") for n in expand(row[1], axes_)}
    assert {"home", "bridge", "X_obstacle", "tool", "tool_pos", "Z_amp", "Y_force"} <= names
    assert {"X_stop_neg", "Z_stop_pos", "X_stop_neg_2", "Y_ref_cam", "Z_lim_pos_cam_geom"} <= names
    assert {"X_bumper", "X_obstacle_geom", "floor", "tool_geom"} <= names
    numerics = {n for row in tables(text, r".*[Nn]umerics") for n in expand(row[0], axes_)}
    assert {
        "X_J",
        "Z_counts_per_rev",
        "Y_travel",
        "Z_brake_force",
        "X_obstacle_blockneg",
    } <= numerics
    assert numbers("[0, 1.0] / [0, 0.6] / [−0.25, 0]")[-2] == (-0.25, 0.005)
    assert numbers("12 000, 2π/5")[0] == (12000.0, 0.5)
    assert numbers("2π/5")[0][0] == pytest.approx(2 * math.pi / 5)


# ------------------------------------------------------------------------ running
@pytest.mark.parametrize("name", NAMES)
def test_the_model_compiles_and_steps(name: str) -> None:
    """The file compiles alone and rests finite for a second from home."""
    for machine in modelled(name):
        model = compiled(machine)
        data = at_home(model)
        run(model, data, 1.0)
        assert np.isfinite(data.qpos).all() and np.isfinite(data.qvel).all()
        assert data.time == pytest.approx(1.0)


@pytest.mark.parametrize("name", NAMES)
def test_the_machines_scene_builds_and_steps(name: str) -> None:
    """The scene of the machine (its model attached under its prefix, a cell's models side by
    side, or its simulated axes) runs 0.2 s with its drives off and stays finite."""
    scene = scenes.load(name, trace_every=0)
    scene.run(timeout=0.2)
    assert scene.time == pytest.approx(0.2)
    if scene.has_model:
        assert np.isfinite(scene.data.qpos).all() and np.isfinite(scene.data.qvel).all()
    assert all(math.isfinite(scene.joint_position(axis)) for axis in scene.axes)


@pytest.mark.parametrize("name", NAMES)
def test_the_demo_runs_without_error_and_moves_the_machine(name: str) -> None:
    machine = scenes.MACHINES[name]
    if machine.demo is None:
        pytest.skip(f"{name} has no demo")
    scene = scenes.load(name, start=machine.demo_start, trace_every=0)
    program = scenes.demo(scene)
    before = {axis: scene.joint_position(axis) for axis in scene.axes}
    scene.run(program, timeout=DEMO_SECONDS)
    assert not program.error, f"{name}: {program.error}"
    moved = {axis: abs(scene.joint_position(axis) - q) for axis, q in before.items()}
    assert all(math.isfinite(d) for d in moved.values()), moved
    assert max(moved.values()) > MOVED, f"{name}: nothing moved in {DEMO_SECONDS} s: {moved}"


@pytest.mark.parametrize("name", NAMES)
def test_a_state_saved_at_power_up_repeats_the_demo_bit_for_bit_in_a_fresh_scene(
    name: str,
) -> None:
    """Trace rows, signals and, on a model, every joint's position and velocity are equal."""
    machine = scenes.MACHINES[name]
    if machine.demo is None:
        pytest.skip(f"{name} has no demo")
    first = scenes.load(name, start=machine.demo_start)
    state = first.save_state()

    def demo(scene: scenes.Scene) -> tuple[object, ...]:
        scene.run(scenes.demo(scene), timeout=1.0)
        physics = (scene.data.qpos.tolist(), scene.data.qvel.tolist()) if scene.has_model else ()
        signals = [scene.signal(s) for s in scene.signals]
        return scene.trace.rows, physics, np.array(signals, dtype=float).tobytes()

    after_save = demo(first)
    fresh = scenes.load(name, start=machine.demo_start)
    fresh.restore_state(state)
    assert len(next(iter(first.trace.rows.values()))) > 100, "the demo ran"
    assert demo(fresh) == after_save
