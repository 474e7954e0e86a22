"""The machine layer: one registry, hinge axes in degrees, device hooks, drive kinds."""

from __future__ import annotations

import math
from pathlib import Path

import mujoco
import numpy as np
import pytest

import mcl
import scenes
import scenes.machines.gantry
from plc.procedures import HomeAxis, HomingRecipe
from scenes.definition import AxisDef, MachineDef
from scenes.plant.drives import SpringDamper
from scenes.plant.mujoco import MujocoPlant, WiringError
from scenes.scene import Scene
from scenes.tools.cli import main
from tests.helpers import ROOT

ROTARY = str(ROOT / "tests" / "models" / "rotary_table.xml")


# ------------------------------------------------------------------------------ registry
def test_one_registry_for_the_cli_and_load(capsys):
    assert {"gantry", "single_axis"} <= set(scenes.MACHINES)
    assert main(["list"]) == 0
    listed = [line.split()[0] for line in capsys.readouterr().out.splitlines()]
    assert listed == sorted(scenes.MACHINES)
    for name, definition in scenes.MACHINES.items():
        assert isinstance(definition, MachineDef) and definition.name == name


def test_the_simulated_single_axis_loads_through_the_registry_and_runs_its_demo():
    scene = scenes.load("single_axis", trace_every=0)
    assert not scene.has_model
    with pytest.raises(TypeError, match="simulated axes"):
        _ = scene.model
    program = scenes.demo(scene)
    scene.run(program, until=lambda: program.done, timeout=10.0)
    assert not program.error
    assert scene.axes["X"].state == mcl.AxisState.StandStill


def test_a_machine_definition_checks_its_drives():
    config = mcl.AxisConfig()
    with pytest.raises(ValueError, match="devices"):
        MachineDef("m", "test", {"X": AxisDef(config, drive="device", device="valve")}, "a.xml")
    with pytest.raises(ValueError, match="drive must be"):
        MachineDef("m", "test", {"X": AxisDef(config, drive="hydraulic")}, "a.xml")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"AxisDef\.sim"):
        MachineDef("m", "test", {"X": AxisDef(config)})


# ------------------------------------------------------------------------------ hinge axis
def rotary_table(**axis: object) -> MachineDef:
    spec = AxisDef(
        config=mcl.AxisConfig(
            resolution=0.01,
            dev_max=5.0,
            in_position=0.02,
            acceleration=1440.0,
            deceleration=1440.0,
            max_acceleration=3600.0,
            max_deceleration=3600.0,
            modulo=360.0,
        ),
        # Vmax 360 °/s at 10 V; Kv = Kp·Vmax/10 = 54 1/s; Ka = J/Kamp + lag + half a cycle
        constants=mcl.ServoConstants(
            Kp=1.5, Ki=30.0, Ff=1.0, Kc=50.0, Vmax=360.0, Filter=2.0, Ka=0.0073
        ),
        switches=("ref",),
        homing=HomingRecipe(search_velocity=30.0, index_velocity=10.0, set_position=90.0),
        **axis,  # type: ignore[arg-type]
    )
    return MachineDef("table", "rotary table", {"T": spec}, model=ROTARY)


def test_a_hinge_axis_reports_degrees_and_its_encoder_follows_the_angle():
    scene = Scene([rotary_table()], trace_every=0)
    T = scene.axes["T"]
    assert T.config.unit == "deg" and scene.scales["T"] == pytest.approx(180.0 / math.pi)
    io = scene.io("T")
    assert io.rotary
    power, move = mcl.MC_Power(), mcl.MC_MoveRelative()

    def program() -> None:
        power(Axis=T, Enable=True)
        move(Axis=T, Execute=power.Status, Distance=100.0, Velocity=180.0)

    scene.run(program, until=lambda: move.Done, timeout=5.0)
    scene.run(program, timeout=0.2)
    angle = math.degrees(scene.joint_position("T"))
    assert angle == pytest.approx(100.0, abs=0.02)
    assert pytest.approx(angle, abs=0.011) == T.POS  # one count is 0.01°


def test_a_hinge_axis_homes_on_its_ref_cam_and_index():
    scene = Scene([rotary_table()], start={"T": math.radians(25.0)}, trace_every=0)
    T = scene.axes["T"]
    power = mcl.MC_Power()
    home = HomeAxis(T, scenes.MACHINES.get("table", rotary_table()).homing["T"])

    def program() -> None:
        power(Axis=T, Enable=True)
        home(Execute=power.Status)

    scene.run(program, until=lambda: home.Done or home.Error, timeout=20.0)
    assert home.Done and T.Ref
    # REF goes off at −18°; the next index in the positive direction is at 0° of the joint: 90°
    q = math.degrees(scene.joint_position("T"))
    assert pytest.approx(q % 360.0, abs=0.011) == (T.POS - 90.0) % 360.0


def test_hinge_switch_states_match_the_geometry_at_360_angles():
    scene = Scene([rotary_table()], trace_every=0)
    io = scene.io("T")
    model, data = scene.model, scene.data
    switch, cam = model.site("table/T_ref").id, model.site("table/T_ref_cam").id
    lo, hi = model.numeric("table/T_ref_window").data
    joint = model.joint("table/T").id
    ons = 0
    for k in range(360):
        q = math.radians(k - 179.5)
        data.qpos[io.qpos_adr] = q
        mujoco.mj_forward(model, data)
        # the README's switch formula, measured from the sites: angle from switch to cam
        e = data.xaxis[joint]
        s = data.site_xpos[switch] - data.xanchor[joint]
        c = data.site_xpos[cam] - data.xanchor[joint]
        s, c = s - (s @ e) * e, c - (c @ e) * e
        d = math.atan2(float(np.cross(s, c) @ e), float(s @ c))
        io.sense(float(k))
        assert io.ref == (lo <= d <= hi), f"at {math.degrees(q):.1f}°"
        ons += io.ref
    assert ons == 20  # the dog spans 20°


def test_a_unit_that_does_not_fit_the_joint_is_refused():
    with pytest.raises(WiringError, match="does not fit"):
        Scene([rotary_table(unit="mm")], trace_every=0)


# ------------------------------------------------------------------------------ device hook
SPRINGS = """<mujoco>
  <option timestep="0.0005" integrator="Euler"/>
  <worldbody>
    <body name="a"><joint name="qa" type="slide" axis="1 0 0"/><geom size=".05" mass="2"/></body>
    <body name="b" pos="0 1 0"><joint name="qb" type="slide" axis="1 0 0"/>
      <geom size=".05" mass="2"/></body>
  </worldbody>
  <actuator>
    <general name="spring" joint="qa" gainprm="0" biastype="affine" biasprm="0 -800 -3"/>
  </actuator>
</mujoco>"""
"""Two equal masses: ``qa`` on a spring-damper written as MJCF, ``qb`` free for a Python one."""


def spring_plant() -> tuple[MujocoPlant, SpringDamper]:
    model = mujoco.MjModel.from_xml_string(SPRINGS)
    data = mujoco.MjData(model)
    data.qpos[:] = 0.05
    device = SpringDamper(model, data, "qb", stiffness=800.0, damping=3.0)
    return MujocoPlant(model, data, [], {"spring": device}), device


def test_a_python_device_on_the_hook_matches_the_same_spring_in_mjcf():
    plant, device = spring_plant()
    worst = 0.0
    for _ in range(1000):  # 1 s
        plant.step(2)
        qa, qb = plant.data.qpos
        worst = max(worst, abs(qa - qb))
    assert worst < 1e-9
    assert abs(plant.data.qpos[1]) < 0.05  # it really oscillated and decayed
    assert device.dissipated > 0.0


def test_the_device_state_belongs_to_the_plant_state_and_replays_bit_identically():
    plant, device = spring_plant()
    start = plant.get_state()

    def run() -> tuple[np.ndarray, float]:
        rows = []
        for _ in range(400):
            plant.step(2)
            rows.append(plant.data.qpos.copy())
        return np.array(rows), device.dissipated

    first, energy = run()
    plant.set_state(start)
    assert device.dissipated == 0.0
    second, energy2 = run()
    assert np.array_equal(first, second) and energy == energy2


def test_without_devices_a_servo_period_is_one_mj_step_call_with_the_same_result():
    a, b = scenes.load("gantry", trace_every=0), scenes.load("gantry", trace_every=0)
    for scene in (a, b):
        scene.data.ctrl[:] = 3.0
        scene.model.opt.disableactuator = 0
    for _ in range(200):
        a.plant.step(2)
        b.plant.step(1)
        b.plant.step(1)
    assert np.array_equal(a.data.qpos, b.data.qpos)


def test_the_electric_drive_state_is_restored_with_the_plant_state():
    scene = scenes.load("gantry", trace_every=0)
    plant = scene.plant
    assert isinstance(plant, MujocoPlant)
    start = plant.get_state()
    z = scene.io("Z")
    brake = float(scene.model.dof_frictionloss[z.dof])
    z.write(0.0, True)  # enable: brake released, friction back to the joint's own
    plant.sense()  # the module's outputs reach the drive at its next sample
    assert scene.model.dof_frictionloss[z.dof] < brake
    plant.set_state(start)
    assert scene.model.dof_frictionloss[z.dof] == brake
    assert scene.model.opt.disableactuator & (1 << int(scene.model.actuator_group[z.actuator]))


# ------------------------------------------------------------------------------ drive kinds
def test_an_encoder_only_axis_on_a_model_has_no_drive_and_refuses_motion():
    scene = Scene([rotary_table(drive="encoder")], trace_every=0)
    T = scene.axes["T"]
    assert not T.has_drive
    power, move = mcl.MC_Power(), mcl.MC_MoveRelative()
    power(Axis=T, Enable=True)
    move(Axis=T, Execute=True, Distance=10.0, Velocity=10.0)
    assert power.Error and power.ErrorID == mcl.ErrorID.ENoDrive
    assert move.Error and move.ErrorID == mcl.ErrorID.ENoDrive
    scene.model.opt.disableactuator = ~0  # the test model's amplifier is not connected
    scene.data.qvel[scene.io("T").dof] = math.radians(90.0)  # somebody turns the table
    scene.run(timeout=0.1)
    speed = math.degrees(scene.data.qvel[scene.io("T").dof])
    assert speed > 40.0
    # POS was sampled one servo period (1 ms) before the physics' present
    assert pytest.approx(math.degrees(scene.joint_position("T")) - speed * 1e-3, abs=0.02) == T.POS
    assert pytest.approx(speed, rel=0.05) == T.VEL


@pytest.mark.parametrize(
    ("numeric", "value", "message"),
    [
        ("X_lead", "nan", r"X_lead.*nan.*\(0, inf\]"),
        ("X_lead", "0", r"X_lead.*0\.0"),
        ("X_counts_per_rev", "nan", r"X_counts_per_rev.*nan"),
        ("X_ref_window", "nan 0", r"X_ref_window.*nan"),
        ("Z_brake_force", "-5", r"Z_brake_force.*-5"),
    ],
)
def test_a_bad_numeric_names_the_axis_the_value_and_the_valid_range(
    tmp_path: Path, numeric: str, value: str, message: str
):
    source = (Path(scenes.scene.MODELS) / "gantry.xml").read_text()
    start = source.index(f'<numeric name="{numeric}" data="')
    end = source.index('"/>', start)
    broken = tmp_path / "gantry.xml"
    broken.write_text(f'{source[:start]}<numeric name="{numeric}" data="{value}{source[end:]}')
    machine = MachineDef("gantry", "broken", scenes.machines.gantry.AXES, model=str(broken))
    with pytest.raises(WiringError, match=message):
        Scene([machine], trace_every=0)
