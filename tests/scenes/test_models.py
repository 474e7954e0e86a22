"""The gantry's model in motion (brake, amplifier, hard stop, obstacle), its README table, and
every machine's hard stops resolved at the model timestep.

The names, numerics and conventions every machine model keeps (models/README.md) are checked
for each registered machine by tests/scenes/test_machine_contract.py.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import mujoco
import numpy as np
import pytest

from tests.helpers import ROOT
from tests.scenes.test_machine_contract import num, place, run, switch_on, trip

MODELS = ROOT / "models"
GANTRY = MODELS / "gantry.xml"
AXES = ("X", "Y", "Z")


@pytest.fixture(scope="module")
def model() -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_path(str(GANTRY))


@pytest.fixture
def data(model: mujoco.MjModel) -> mujoco.MjData:
    d = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, d, model.key("home").id)
    mujoco.mj_forward(model, d)
    return d


@pytest.fixture
def fresh() -> mujoco.MjModel:
    """A private model for tests that modify model fields (brake, disabled amplifier)."""
    return mujoco.MjModel.from_xml_path(str(GANTRY))


def test_home_keyframe(model: mujoco.MjModel, data: mujoco.MjData) -> None:
    """The gantry's home (every joint at 0, filter states 0: the contract test) lies inside its
    working travel, with REF on for X and Y and off for Z, and no LIM actuated."""
    for ax in AXES:
        lo, hi = num(model, f"{ax}_travel")
        assert lo <= 0.0 <= hi
    # At home X and Y sit below their REF edge (REF on), Z sits above its edge (REF off).
    assert switch_on(model, data, "X", "ref") and switch_on(model, data, "Y", "ref")
    assert not switch_on(model, data, "Z", "ref")
    assert not any(switch_on(model, data, ax, k) for ax in AXES for k in ("lim_neg", "lim_pos"))


def test_brake_holds_z(fresh: mujoco.MjModel) -> None:
    m = fresh
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key("home").id)
    a, z = m.actuator("Z_amp").id, m.joint("Z").id
    m.opt.disableactuator |= 1 << int(m.actuator_group[a])  # drive off
    m.dof_frictionloss[m.jnt_dofadr[z]] = num(m, "Z_brake_force")[0]  # brake on
    d.qpos[z] = -0.1
    run(m, d, 2.0)
    assert d.actuator_force[a] == 0.0
    assert abs(d.qpos[z] + 0.1) < 1e-4
    # and without the brake the ram falls
    m.dof_frictionloss[m.jnt_dofadr[z]] = 40.0
    run(m, d, 0.2)
    assert d.qpos[z] < -0.1 - 1e-3


def test_x_velocity_at_full_command(model: mujoco.MjModel, data: mujoco.MjData) -> None:
    x = model.joint("X").id
    place(model, data, "X", 0.1)
    data.ctrl[model.actuator("X_amp").id] = 10.0
    run(model, data, 0.2)
    assert data.qvel[x] == pytest.approx(num(model, "X_vmax")[0], rel=0.05)


def test_x_into_positive_stop_is_stable(model: mujoco.MjModel, data: mujoco.MjData) -> None:
    x, a = model.joint("X").id, model.actuator("X_amp").id
    hi = model.jnt_range[x, 1]
    place(model, data, "X", hi - 0.05)
    data.ctrl[a] = 10.0
    worst = 0.0
    for _ in range(20):
        run(model, data, 0.1)
        assert np.isfinite(data.qpos).all() and np.isfinite(data.qvel).all()
        worst = max(worst, data.qpos[x] - hi)
    assert worst < 0.002
    assert abs(data.qvel[x]) < 1e-3
    assert data.actuator_force[a] == pytest.approx(model.actuator_forcerange[a, 1])
    assert switch_on(model, data, "X", "lim_pos")


@pytest.mark.parametrize(("which", "volts", "q_block"), [("pos", 10.0, 0.5), ("neg", -10.0, 0.3)])
def test_obstacle_blocks_x(fresh: mujoco.MjModel, which: str, volts: float, q_block: float) -> None:
    m = fresh
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key("home").id)
    shift = np.array([q_block, 0.0, 0.0])
    m.body_pos[m.body("X_obstacle").id] = num(m, f"X_obstacle_block{which}") + shift
    d.qpos[m.joint("X").id] = 0.4
    d.ctrl[m.actuator("X_amp").id] = volts
    run(m, d, 1.0)
    assert d.qpos[m.joint("X").id] == pytest.approx(q_block, abs=0.002)


def readme_axes_table() -> dict[str, list[list[float]]]:
    """The gantry's axes table of models/README.md: row label → numbers per axis column."""
    text = (MODELS / "README.md").read_text(encoding="utf-8")
    section = text[text.index("## gantry") :]
    table = section[section.index("### Axes") : section.index("\n\n", section.index("| |"))]
    rows: dict[str, list[list[float]]] = {}
    number = re.compile(r"[-−]?\d+(?:\.\d+)?(?:e[-−]?\d+)?")
    for line in table.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) != 4 or cells[0] in ("", "---"):
            continue
        rows[cells[0]] = [
            [float(n.replace("−", "-")) for n in number.findall(c.replace("×", " "))]
            for c in cells[1:]
        ]
    return rows


def test_readme_axes_table_matches_the_model(model: mujoco.MjModel) -> None:
    """Every model number in the README's gantry table is the model's (and the catalogue rows
    add up to the inertia and force the model uses)."""
    rows = readme_axes_table()

    def row(label: str) -> list[list[float]]:
        matches = [v for k, v in rows.items() if k.startswith(label)]
        assert len(matches) == 1, (label, list(rows))
        return matches[0]

    for i, ax in enumerate(AXES):
        j, a = model.joint(ax).id, model.actuator(f"{ax}_amp").id
        dof = model.jnt_dofadr[j]
        lo, hi = model.jnt_range[j]
        lead = num(model, f"{ax}_lead")[0]
        m = model.body_subtreemass[model.jnt_bodyid[j]]
        meff = m + model.dof_armature[dof]
        kamp = num(model, f"{ax}_kamp")[0]
        np.testing.assert_allclose(
            row("LIM− trip / LIM+ trip")[i],
            [trip(model, ax, "lim_neg"), trip(model, ax, "lim_pos")],
        )
        np.testing.assert_allclose(row("hard stop")[i], [lo, hi])
        np.testing.assert_allclose(row("working travel")[i][:2], num(model, f"{ax}_travel"))
        assert row("LIM trip to hard stop")[i] == pytest.approx(
            [(trip(model, ax, "lim_neg") - lo) * 1e3], abs=1e-9
        )
        assert row("LIM trip to hard stop")[i][0] == pytest.approx(
            (hi - trip(model, ax, "lim_pos")) * 1e3
        )
        assert row("REF edge")[i] == pytest.approx([trip(model, ax, "ref")])
        assert row("moving mass")[i][0] == pytest.approx(m)
        assert row("screw lead")[i] == pytest.approx([lead])
        J = num(model, f"{ax}_J")[0]
        assert row("J motor + coupling + screw")[i] == pytest.approx([J])
        parts = row("rotor inertia")[i][0] + row("coupling")[i][-1] + row("screw inertia")[i][-1]
        assert parts == pytest.approx(J, rel=0.005)
        assert row("armature")[i][0] == pytest.approx(model.dof_armature[dof], abs=5e-4)
        assert row("effective mass")[i][0] == pytest.approx(meff, abs=5e-3)
        assert row("damping")[i] == pytest.approx(
            [model.dof_damping[dof], model.dof_frictionloss[dof]]
        )
        assert row("vmax at 10 V")[i][-1] == pytest.approx(num(model, f"{ax}_vmax")[0])
        assert row("Kamp")[i] == pytest.approx([kamp])
        assert row("gainprm")[i] == pytest.approx([model.actuator_gainprm[a, 0]])
        assert row("velocity-loop pole")[i][0] == pytest.approx(kamp / meff, abs=0.5)
        assert row("current-loop lag")[i] == pytest.approx([model.actuator_dynprm[a, 0]])
        fmax = model.actuator_forcerange[a, 1]
        assert row("Fmax")[i] == pytest.approx([fmax])
        assert row("peak torque")[i][0] * 2 * math.pi / lead * 0.9 == pytest.approx(fmax, rel=0.005)
        assert row("counts_per_rev")[i] == pytest.approx(
            [num(model, f"{ax}_counts_per_rev")[0], num(model, f"{ax}_index_width")[0]]
        )


# ------------------------------------------------------------------------ hard stops


STEPS = (0.0005, 0.00025, 0.0001)
"""Physics timesteps [s]: the model's, and two finer ones the impact must agree with."""
CONVERGED = 0.25
"""Largest change of penetration and rebound from the finest step, as a share of its value."""


@dataclass(frozen=True)
class Impact:
    """A run of one joint into one of its stops with the drive as it is.

    ``end`` is +1 for the upper stop (joint range max or, with ``part``, the press's block) and
    −1 for the lower one; ``speed`` the impact speed [m/s] (an electric axis' amplifier at
    ±10 V has it as its steady state); ``force`` a constant force toward the stop [N] for a
    joint driven by a device (cylinder), which the bare model does not contain; ``part``: the
    press's part ``"none"`` (the ram reaches the cylinder's end) or ``"solid"`` (its block at
    the contact: the ram hits the block); empty: as loaded.
    """

    machine: str
    joint: str
    end: int
    speed: float
    force: float = 0.0
    part: str = ""

    def __str__(self) -> str:
        part = f"-{self.part}" if self.part else ""
        return f"{self.machine}-{self.joint}{'+' if self.end > 0 else '-'}{part}"


# Ram retracting at its free speed (0.207 m/s): weight 1962 N + viscous 2000·0.207 + seal 250 N.
_RAISE = 200 * 9.81 + 2000 * 0.207 + 250
IMPACTS = [
    *(
        Impact("gantry", ax, end, vmax)
        for ax, vmax in (("X", 1.0), ("Y", 1.0), ("Z", 0.5))
        for end in (1, -1)
    ),
    Impact("flying_shear", "S", 1, 4.0),
    Impact("flying_shear", "S", -1, 4.0),
    # the knife cylinder returns at its stroke speed (K_speed) with its force (K_force); its
    # lower stop is out of reach (the blade lands on the strip first)
    Impact("flying_shear", "K", 1, 0.6, force=12000.0),
    # the ram falls at its free extension speed with its weight (gravity is in the model) onto
    # the cylinder's end (no part) or onto a solid part, and retracts onto its top end
    Impact("hydraulic_press", "R", 1, 0.3, part="none"),
    Impact("hydraulic_press", "R", 1, 0.3, part="solid"),
    Impact("hydraulic_press", "R", -1, 0.207, force=_RAISE),
]


def run_into_stop(case: Impact, timestep: float) -> tuple[float, float, float]:
    """Drive ``case`` into its stop from 2 mm before it at the model's ``timestep`` [s].

    Returns the penetration beyond the stop [m] (joint qpos against the joint range, or the
    press's block), the rebound (largest speed away from the stop after touching it, as a share
    of the impact speed) and where the joint rests 0.1 s later [m beyond the stop].
    """
    m = mujoco.MjModel.from_xml_path(str(MODELS / f"{case.machine}.xml"))
    m.opt.timestep = timestep
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key("home").id)
    j = m.joint(case.joint).id
    qa, va = m.jnt_qposadr[j], m.jnt_dofadr[j]
    if case.part:  # models/README.md, hydraulic_press: exchange the part
        t = m.tendon("workpiece").id
        solid = case.part == "solid"
        m.tendon_range[t, 0] = m.tendon_lengthspring[t, 0] if solid else 0.0
        if not solid:
            m.tendon_lengthspring[t, 0] = 0.0
    if case.part == "solid":  # the ram's R at the block, from the tendon's length at R = 0
        mujoco.mj_forward(m, d)
        stop = float(d.ten_length[t] - m.tendon_range[t, 0])
    else:
        stop = float(m.jnt_range[j, 1 if case.end > 0 else 0])
    for a in np.flatnonzero(m.actuator_trnid[:, 0] == j):  # the amplifier at ±10 V, settled
        d.ctrl[a] = d.act[m.actuator_actadr[a]] = 10.0 * case.end
    d.qfrc_applied[va] = case.force * case.end
    d.qpos[qa] = stop - 0.002 * case.end
    d.qvel[va] = case.speed * case.end
    penetration = rebound = 0.0
    touched = False
    for _ in range(round(0.1 / timestep)):
        mujoco.mj_step(m, d)
        beyond = (d.qpos[qa] - stop) * case.end
        touched = touched or beyond > 0.0
        if touched:
            penetration = max(penetration, beyond)
            rebound = max(rebound, -d.qvel[va] * case.end / case.speed)
    assert touched, f"{case} never reached its stop"
    return penetration, rebound, float((d.qpos[qa] - stop) * case.end)


@pytest.mark.parametrize("case", IMPACTS, ids=str)
def test_hard_stop_impact_is_converged_at_the_model_timestep(case: Impact) -> None:
    """Penetration and rebound of a run into a hard stop are the same (within 25 %) at the
    model's 0.5 ms as at 0.25 and 0.1 ms, and the stop still holds a steady push stiffly."""
    runs = {dt: run_into_stop(case, dt) for dt in STEPS}
    pen_ref, reb_ref, _ = runs[STEPS[-1]]
    for dt in STEPS[:-1]:
        pen, reb, _ = runs[dt]
        assert abs(pen - pen_ref) <= CONVERGED * pen_ref, (
            f"{case}: penetrates {pen * 1e3:.3f} mm at {dt * 1e3:g} ms, "
            f"{pen_ref * 1e3:.3f} mm at {STEPS[-1] * 1e3:g} ms"
        )
        assert abs(reb - reb_ref) <= CONVERGED * reb_ref, (
            f"{case}: rebounds {reb:.1%} at {dt * 1e3:g} ms, {reb_ref:.1%} at "
            f"{STEPS[-1] * 1e3:g} ms"
        )
    pen, _, rest = runs[STEPS[0]]
    if not case.force:  # a stiff stop: at most 2.5 mm per m/s of impact speed
        assert pen < 2.5e-3 * case.speed, f"{case}: {pen * 1e3:.2f} mm is no stiff stop"
    assert abs(rest) < 50e-6, f"{case}: rests {rest * 1e6:.1f} µm beyond the stop under its push"
