"""Commissioning the delta picker's arm A1 end to end: the drive identified on its amplifier, the
constants derived, and the verification moves run on the physics with the other arms moving
the same way (one arm alone would tear the closed chains) — out from the start pose and back."""

from __future__ import annotations

import math

import pytest

import scenes
from scenes.tools import commissioning


def test_the_commissioning_of_a_delta_arm_verifies_with_the_chain_closed(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert commissioning.main(["delta_picker", "A1"]) == 0
    out = capsys.readouterr().out
    assert "A1 moves with A2, A3 (closed chains), out and back" in out
    assert "move +20 at 400" in out and "move -20 at 400" in out
    machine = scenes.definition("delta_picker")
    assert commissioning.robot_joints(machine, "A1") == ("A2", "A3")
    assert commissioning.robot_joints(scenes.definition("gantry"), "X") == ()
    spec = machine.axes["A1"]
    assert spec.constants is not None
    tuning = commissioning.derive(spec, commissioning.identify(machine, "A1"))
    assert tuning.constants.Kp == pytest.approx(spec.constants.Kp, rel=0.01)  # the shipped ones
    out_fig, back_fig = commissioning.verify(machine, "A1", tuning.constants, 400.0, 20.0)
    for fig in (out_fig, back_fig):
        assert abs(fig.final) < 0.005  # deg: settled at the target within 5 mdeg
        assert fig.overshoot < 0.02 and fig.peak_error < 0.5
        assert math.isfinite(fig.settling) and fig.settling < 0.3
