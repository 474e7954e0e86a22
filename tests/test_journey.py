"""The parts of the journey (``make journey``, :mod:`tests.journey`) without a browser: what it
does on each machine, how it reads charts and the console, and the viewer process it starts
(served and stopped, its port freed). The whole journey takes minutes: ``make journey``."""

from __future__ import annotations

import http.client
import io
import subprocess
import urllib.parse
from pathlib import Path

import pytest
from PIL import Image

import scenes
from tests.journey import (
    DOCS_LIMIT,
    ROOT,
    Chart,
    Console,
    JourneyError,
    blank,
    charts_drawing_nothing,
    plan,
    publish,
    viewer_process,
    viewer_url,
)
from viewer.serving.server import port_available

BASE_PICTURE = "aa8a491"
"""A commit whose docs/images/viewer.png is a screenshot stored as it was taken (229 kB)."""


@pytest.mark.parametrize("name", sorted(scenes.MACHINES))
def test_each_machine_has_a_driven_axis_and_an_error_to_provoke(name: str) -> None:
    journey = plan(name)
    definition = scenes.definition(name)
    machines = {p.machine.name: p.machine for p in definition.parts} or {"": definition}
    prefix, _, axis = journey.axis.rpartition("/")
    spec = machines[prefix].axes[axis]
    assert spec.drive != "encoder" and spec.constants is not None
    if journey.target is not None:
        assert journey.target > spec.constants.LimPos > spec.constants.LimNeg
    else:
        assert spec.constants.LimPos <= spec.constants.LimNeg  # no software limits


def test_the_gantry_is_driven_into_its_x_limit() -> None:
    journey = plan("gantry")
    assert journey.axis == "X" and journey.target == pytest.approx(1002.0 + 100.4)
    assert plan("cell").axis == "gantry/X"
    assert plan("flying_shear").axis == "S"  # the wheel W has no drive, the line L no recipe


def test_a_chart_without_two_finite_points_in_any_series_draws_nothing() -> None:
    drawn = Chart(["X position [mm]", "X command [V]"], 50, [50, 0], visible=True)
    empty = Chart(["force [kN]"], 50, [1], visible=True)
    hidden = Chart(["force [kN]"], 0, [0], visible=False)
    assert drawn.drawn == ["X position [mm]"] and empty.drawn == []
    assert charts_drawing_nothing([drawn, empty, hidden]) == [empty]


def png(image: Image.Image) -> bytes:
    out = io.BytesIO()
    image.save(out, format="PNG")
    return out.getvalue()


def test_a_3d_view_of_the_background_alone_is_blank() -> None:
    """A camera that looks away from the machine: white but for a sliver of the floor's edge
    (half a percent); a view of the machine: a fifth of it drawn."""
    view = Image.new("RGB", (640, 500), "white")
    view.paste((220, 218, 210), (300, 0, 304, 400))  # 1600 px: 0.5 %
    assert blank(png(view))
    view.paste((60, 60, 70), (100, 100, 420, 300))  # a machine: 64000 px
    assert not blank(png(view))


def test_console_errors_fail_with_their_text() -> None:
    console = Console()
    console.check("nothing yet")
    console.errors.append("Tried to update non-existent component 'abc'")
    with pytest.raises(JourneyError, match=r"1 console error.*by choosing press.*non-existent"):
        console.check("choosing press")


def test_the_address_is_read_from_the_viewer_start_line() -> None:
    line = "viewer: gantry at http://127.0.0.1:8123/?token=abc  (Ctrl-C to stop)\n"
    assert viewer_url(line) == "http://127.0.0.1:8123/?token=abc"
    assert viewer_url("viewer: stopping\n") is None


def test_the_viewer_process_serves_its_page_and_stops() -> None:
    with viewer_process("single_axis") as url:
        address = urllib.parse.urlsplit(url)
        assert address.hostname == "127.0.0.1" and address.port is not None
        connection = http.client.HTTPConnection("127.0.0.1", address.port, timeout=30)
        connection.request("GET", f"/?{address.query}")
        response = connection.getresponse()
        connection.close()
        assert response.status == 303  # the token traded for a cookie: the viewer answers
    assert port_available("127.0.0.1", address.port)


def test_the_documentation_pictures_are_each_machine_s_running_demo_and_small(
    tmp_path: Path,
) -> None:
    screenshot = tmp_path / "screenshot.png"  # a screenshot of the viewer, losslessly stored
    subprocess.run(
        ["git", "show", f"{BASE_PICTURE}:docs/images/viewer.png"],
        cwd=ROOT,
        check=True,
        stdout=screenshot.open("wb"),
    )
    assert screenshot.stat().st_size > DOCS_LIMIT
    shots = []
    for name in ("01-gantry-chosen.png", "02-gantry-demo-running.png", "09-press-demo-running.png"):
        shots.append(tmp_path / name)
        shots[-1].write_bytes(screenshot.read_bytes())
    written = publish(shots, tmp_path / "docs")
    assert sorted(p.relative_to(tmp_path / "docs").as_posix() for p in written) == [
        "machines/gantry.png",
        "machines/press.png",
        "viewer.png",
    ]
    for picture in written:
        with Image.open(picture) as image:
            assert image.size == (1280, 800)
        assert picture.stat().st_size <= DOCS_LIMIT
