"""The parts several machines are built of (scenes/parts): the web line's line drive and
measuring wheel, one for the flying shear and the rotary cutter, and no machine package that
imports another."""

from __future__ import annotations

import ast
import math

import pytest

import mcl
import scenes
from scenes import parts
from scenes.machines import flying_shear as fs
from scenes.machines import rotary_cutter as rc
from tests.helpers import ROOT

MACHINES = ROOT / "scenes" / "machines"


def imported_modules(package: str) -> set[str]:
    """Every module the package ``scenes.machines.<package>`` imports, by its full name."""
    found = set()
    for path in (MACHINES / package).rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                found |= {alias.name for alias in node.names}
            elif isinstance(node, ast.ImportFrom) and node.module:
                found |= {node.module, *(f"{node.module}.{a.name}" for a in node.names)}
    return found


@pytest.mark.parametrize("package", sorted(p.parent.name for p in MACHINES.glob("*/__init__.py")))
def test_no_machine_package_imports_another(package: str) -> None:
    """A machine is one package: what it shares with others comes from scenes/parts (a cell
    takes its machines from the registry)."""
    own = f"scenes.machines.{package}"
    others = {
        m
        for m in imported_modules(package)
        if m.startswith("scenes.machines.") and m.split(".")[2] != package
    }
    assert others == set(), f"{own} imports {sorted(others)}"


def test_the_import_check_sees_an_import_of_another_machine(tmp_path, monkeypatch) -> None:
    """The check above can fail: a package that imports another machine is seen."""
    (tmp_path / "a").mkdir()
    (tmp_path / "a" / "demo.py").write_text(
        "from scenes.machines import gantry\nimport scenes.machines.press.axes\n"
    )
    monkeypatch.setattr(f"{__name__}.MACHINES", tmp_path)
    assert {"scenes.machines.gantry", "scenes.machines.press.axes"} <= imported_modules("a")


@pytest.mark.parametrize("machine", [fs, rc], ids=["flying_shear", "rotary_cutter"])
def test_both_web_machines_have_the_web_lines_drive_and_wheel(machine) -> None:
    line, wheel = machine.AXES["L"], machine.AXES["W"]
    assert (line.joint, line.unit, line.switches, line.drive) == ("L", "mm", (), "electric")
    assert line.scale == 1000.0 * machine.ROLL_RADIUS
    config = line.config
    assert (config.dev_max, config.in_position) == (20.0, 0.1)
    assert config.deceleration == config.acceleration
    assert config.max_deceleration == config.max_acceleration == 4.0 * config.acceleration
    assert (wheel.joint, wheel.unit, wheel.switches, wheel.drive) == ("W", "mm", (), "encoder")
    assert wheel.config == mcl.AxisConfig(resolution=0.025, dev_max=20.0, in_position=0.1)
    assert wheel.scale == 1000.0 * parts.WHEEL_RADIUS == 250.0 / (2.0 * math.pi)
    assert wheel.probe is not None
    assert (wheel.probe.marks, wheel.probe.joint) == (machine.MARKS, "M")
    assert wheel.probe.delay == machine.SENSOR_DELAY
    assert machine.DEVICES["wheel"] is parts.MeasuringWheel is machine.MeasuringWheel


def test_the_line_drives_are_each_machines_own() -> None:
    shear, cutter = fs.AXES["L"], rc.AXES["L"]
    assert (shear.config.resolution, shear.config.acceleration) == (0.0096, 500.0)
    assert (cutter.config.resolution, cutter.config.acceleration) == (0.008, 1000.0)
    assert (shear.constants, cutter.constants) == (
        mcl.ServoConstants(Kp=0.125, Ki=1.25, Ff=1.0, Kc=50.0, Vmax=2400.0, Filter=2.0, Ka=0.012),
        mcl.ServoConstants(Kp=0.075, Ki=0.75, Ff=1.0, Kc=50.0, Vmax=4000.0, Filter=2.0, Ka=0.0113),
    )


@pytest.mark.parametrize("name", ["flying_shear", "rotary_cutter"])
def test_each_web_machines_wheel_reads_its_own_models_numerics(name: str) -> None:
    scene = scenes.load(name, trace_every=0)
    wheel = scene.device("wheel", parts.MeasuringWheel)

    def numeric(local: str) -> list[float]:
        return [float(v) for v in scene.model.numeric(scene.model_name(local)).data]

    assert [wheel.radius] == numeric("W_radius") and [wheel.slip] == numeric("W_slip")
    assert [wheel.liftoff_rate, wheel.liftoff_time, wheel.drag_torque] == numeric("W_liftoff")
    assert [wheel.tension, wheel.stiffness] == numeric("M_stretch")
