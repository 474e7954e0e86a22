"""The circle test of ISO 230-4 (scenes.tools.circle) on the gantry's physics: the figures an
engineer reads from a ballbar report, the evaluation on known shapes, the command line."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from scenes.errors import UserError
from scenes.machines import gantry
from scenes.tools import cli
from scenes.tools.circle import CircleResult, evaluate, plot

START = {"X": 0.5, "Y": 0.3, "Z": -0.1}
"""Joint coordinates [m] of the circle's centre: the middle of X's and Y's travel."""
G_LIMIT = 5e-3
"""Largest circular deviation G of R 50 mm at F3000 [mm] (measured 1.5–1.6 µm at the joints,
2.8–2.9 µm at the encoders with their 1 µm counts; without the friction band 8.8–10.0 µm, the Y
axis' reversal spikes of ±5 µm at 90° and 270°)."""


@pytest.fixture(scope="module")
def result() -> CircleResult:
    """The circle test R 50 mm at F3000 in XY, both directions, on one gantry."""
    from scenes.tools.circle import circle_test

    return circle_test(gantry.build(start=START, trace_every=0), "XY", 50.0, 3000.0, "both")


def test_each_direction_runs_one_whole_lap(result: CircleResult) -> None:
    """Both directions are measured over exactly one turn, each servo cycle (1 ms): the run-in
    and run-out are left out, and CCW turns the other way than CW."""
    for source in ("encoders", "joints"):
        for lap, sign in (("CCW", 1.0), ("CW", -1.0)):
            p = result.laps[source][lap]
            turn = np.unwrap(np.arctan2(p[:, 1], p[:, 0]))
            assert sign * (turn[-1] - turn[0]) == pytest.approx(2 * math.pi, abs=0.01)
            assert len(p) == pytest.approx(2 * math.pi * 50.0 / 50.0 * 1000, rel=0.01)


def test_the_circle_stays_within_its_circular_deviation(result: CircleResult) -> None:
    """G (max − min radius about the least-squares centre) from the joints and the encoders,
    per direction and bi-directional, is within 5 µm; the mean radius of either direction is
    within 1 µm of the nominal 50 mm (the feed-forward leaves no radius loss), and the two
    directions' mean radii agree within 1 µm."""
    for source in ("encoders", "joints"):
        figures = result.figures[source]
        for f in figures.values():
            assert 1e-3 < f.G < G_LIMIT  # a real measurement: never exactly round
            assert abs(f.mean_radial) < 1e-3
            assert f.radial < G_LIMIT
        assert abs(figures["CCW"].mean_radial - figures["CW"].mean_radial) < 1e-3
        assert result.bidirectional[source] < G_LIMIT
        assert result.bidirectional[source] >= max(f.G for f in figures.values()) - 1e-9


def test_the_reversal_spikes_are_found_at_the_quadrant_points(result: CircleResult) -> None:
    """The spikes are sought at 0°, 90°, 180° and 270°; the largest is where an axis reverses
    and it is within G, a few tenths of a degree to a degree wide."""
    for source in ("encoders", "joints"):
        for f in result.figures[source].values():
            assert [s.at for s in f.spikes] == [0.0, 90.0, 180.0, 270.0]
            assert 0.5e-3 < f.spike <= f.G
            widest = max(f.spikes, key=lambda s: abs(s.height))
            assert 0.0 < widest.width < 5.0


def test_the_polar_plot_is_written(result: CircleResult, tmp_path: Path) -> None:
    """plot() writes the ballbar polar plot as a PNG."""
    pytest.importorskip("matplotlib")
    out = plot(result, tmp_path / "circle.png")
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert out.stat().st_size > 20_000


def _circle(radius: float, x: Any, y: Any, n: int = 3600) -> np.ndarray:
    """Points of a shape given by functions of the angle [rad]."""
    theta = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    return np.column_stack([x(theta), y(theta)])


def test_evaluate_reads_a_scale_mismatch_and_a_centre_offset() -> None:
    """An X scale 20 µm/m larger than Y's on R 50 and a centre 3 µm off: G = 1 µm (the
    ellipse; the offset is no deviation of form), the scale mismatch 20 µm/m, the offset."""
    f = evaluate(
        _circle(50.0, lambda t: 50.0 * (1 + 20e-6) * np.cos(t) + 0.003, lambda t: 50 * np.sin(t)),
        50.0,
        50.0,
        ccw=True,
    )
    deviation = f.G
    assert deviation == pytest.approx(1e-3, rel=0.01)
    assert f.ellipse.scale == pytest.approx(20e-6, rel=0.01)
    assert f.ellipse.offset == pytest.approx((0.003, 0.0), abs=1e-6)
    assert f.mean_radial == pytest.approx(0.5e-3, abs=1e-5)
    assert f.spike < 1e-6


@pytest.mark.parametrize("ccw", [True, False])
def test_evaluate_reads_a_lag_mismatch_in_either_direction(ccw: bool) -> None:
    """X following 0.2 ms behind Y at 50 mm/s on R 50 tilts the circle into an ellipse at
    45°: its lag is read back as +0.2 ms whichever way the circle ran."""
    lag, speed, radius = 0.2e-3, 50.0, 50.0
    behind = (1.0 if ccw else -1.0) * speed / radius * lag  # the angle X trails by [rad]
    f = evaluate(
        _circle(radius, lambda t: radius * np.cos(t - behind), lambda t: radius * np.sin(t)),
        radius,
        speed,
        ccw=ccw,
    )
    assert f.ellipse.lag == pytest.approx(lag, rel=0.02)
    deviation = f.G
    assert deviation == pytest.approx(radius * abs(behind), rel=0.02)


def test_a_spike_is_measured_in_height_and_width() -> None:
    """A bump of 4 µm, 2° wide at half height, at 90° on an otherwise round circle."""

    def bump(t: np.ndarray) -> np.ndarray:
        return 50.0 + 0.004 * np.exp(-0.5 * ((np.degrees(t) - 90.0) / (2.0 / 2.3548)) ** 2)

    f = evaluate(
        _circle(50.0, lambda t: bump(t) * np.cos(t), lambda t: bump(t) * np.sin(t)),
        50.0,
        50.0,
        ccw=True,
    )
    assert f.spikes[1].height == pytest.approx(0.004, rel=0.05)
    assert f.spikes[1].width == pytest.approx(2.0, abs=0.2)
    assert max(abs(f.spikes[k].height) for k in (0, 2, 3)) < 2e-4


def test_a_bad_argument_is_one_clear_error() -> None:
    """A plane, a direction or a radius that is not valid, or a circle beyond the software
    limits, raise a UserError naming what is wrong and what is right."""
    from scenes.tools.circle import circle_test

    scene = gantry.build(start=START, trace_every=0)
    with pytest.raises(UserError, match=r"plane.*'XX'.*one of"):
        circle_test(scene, plane="XX")
    with pytest.raises(UserError, match="direction"):
        circle_test(scene, direction="up")
    with pytest.raises(UserError, match=r"radius.*positive"):
        circle_test(scene, radius=-1.0)
    with pytest.raises(UserError, match="software limits"):
        circle_test(scene, radius=400.0)


def test_the_command_line_prints_the_figures_and_writes_the_plot(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """``python -m scenes circle gantry --radius 20 --feed 5000 --direction ccw --plot F``."""
    pytest.importorskip("matplotlib")
    out = tmp_path / "c.png"
    argv = ["circle", "gantry", "--radius", "20", "--feed", "5000", "--direction", "ccw"]
    assert cli.main([*argv, "--plot", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "circle XY R20 mm F5000 mm/min" in printed
    assert "joints   CCW  G" in printed and " CW " not in printed
    assert out.is_file()


def test_the_plugin_offers_the_circle_test(circle: Any) -> None:
    """The pytest plugin's ``circle`` fixture is the circle test."""
    from scenes.tools.circle import circle_test

    assert circle is circle_test


def test_the_friction_band_keeps_f1000_within_5_um() -> None:
    """R 50 mm at F1000, both directions, as commissioned (the friction feed-forward switching
    within its band Vf where an axis reverses): G within 5 µm at the joints and the encoders,
    no reversal spike above 2 µm at the joints; the same circle with Vf = 0 (Kf's own ramp
    through 0 V) has the spikes of the axis standing in its friction, above 5 µm on Y."""
    from scenes.tools.circle import circle_test

    result = circle_test(gantry.build(start=START, trace_every=0), "XY", 50.0, 1000.0, "both")
    for source in ("encoders", "joints"):
        assert result.bidirectional[source] < 5e-3
    assert max(f.spike for f in result.figures["joints"].values()) < 2e-3
    scene = gantry.build(start=START, trace_every=0)
    axis = scene.axes["Y"]
    assert axis.constants is not None and axis.constants.Vf > 0.0
    axis.set_constants(replace(axis.constants, Vf=0.0))
    without = circle_test(scene, "XY", 50.0, 1000.0, "ccw").figures["joints"]["CCW"]
    assert max(abs(s.height) for s in without.spikes if s.at in (90.0, 270.0)) > 5e-3
