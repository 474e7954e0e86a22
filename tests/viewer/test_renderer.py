"""A page that draws its 3-D view in software lowers the viewer's frame rate and says so; an
element taken away is hidden at once and removed later (without a browser: the page's report
is sent as its probe sends it, over HTTP with the token cookie)."""

from __future__ import annotations

import html
import http.client
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any, cast

import pytest
import viser

from viewer.serving.retire import retire
from viewer.serving.server import Viewer
from viewer.view3d import renderer
from viewer.view3d.renderer import SOFTWARE_FPS, Renderers, is_software, note, probe_html

SWIFTSHADER = (
    "ANGLE (Google, Vulkan 1.3.0 (SwiftShader Device (Subzero) (0x0000C0DE)), SwiftShader driver)"
)
GPU = "ANGLE (NVIDIA, NVIDIA GeForce RTX 3060 Direct3D11 vs_5_0 ps_5_0, D3D11)"


class Line:
    """What a page's HTML element holds, and how often its content was sent."""

    def __init__(self, content: str, order: float = 0.0) -> None:
        self._content, self.order, self.sent = content, order, 0
        self.visible: bool | None = True
        self.removed = False

    @property
    def content(self) -> str:
        return self._content

    @content.setter
    def content(self, value: str) -> None:
        self._content, self.sent = value, self.sent + 1

    def remove(self) -> None:
        self.removed = True


@dataclass
class Gui:
    lines: list[Line] = field(default_factory=list)

    def add_html(self, content: str, order: float = 0.0) -> Line:
        self.lines.append(Line(content, order))
        return self.lines[-1]


@dataclass
class Client:
    client_id: int
    gui: Gui = field(default_factory=Gui)


def page(renderers: Renderers, client_id: int) -> Client:
    client = Client(client_id)
    renderers.connect(cast(viser.ClientHandle, client))
    return client


@pytest.mark.parametrize(
    ("text", "software"),
    [
        (SWIFTSHADER, True),
        ("llvmpipe (LLVM 15.0.6, 256 bits)", True),
        ("Mesa softpipe", True),
        ("Google SwiftShader", True),
        (GPU, False),
        ("Apple M2", False),
        ("none", False),
    ],
)
def test_software_renderers_are_told_from_gpus(text: str, software: bool) -> None:
    assert is_software(text) is software


def test_a_software_page_lowers_the_frame_rate_while_it_is_open_and_says_so() -> None:
    renderers = Renderers(30.0)
    gpu, software = page(renderers, 1), page(renderers, 2)
    probe = gpu.gui.lines[0]
    assert probe.order < 0  # above the Simulation folder: the top of the control panel
    assert "WEBGL_debug_renderer_info" in html.unescape(probe.content)
    assert f"{renderer.PATH}?client=1&" in html.unescape(probe.content)
    assert renderers.fps == 30.0  # nothing reported yet

    renderers.report({"client": "1", "renderer": GPU})
    renderers.refresh()
    assert renderers.fps == 30.0
    assert not probe.visible and probe.content == ""  # the probe ran, nothing to say

    renderers.report({"client": "2", "renderer": SWIFTSHADER})
    renderers.refresh()
    assert renderers.fps == SOFTWARE_FPS
    line = software.gui.lines[0]
    assert (
        line.visible and "No GPU" in line.content and f"{SOFTWARE_FPS:g} frames/s" in line.content
    )
    assert not probe.visible  # the GPU page says nothing
    sent = line.sent
    renderers.refresh()
    assert line.sent == sent == 1  # only a change is sent

    renderers.disconnect(cast(viser.ClientHandle, software))
    assert renderers.fps == 30.0  # back once the software page is gone
    assert renderers.renderer(2) is None
    renderers.report({"client": "2", "renderer": SWIFTSHADER})  # a late report of a closed page
    assert renderers.renderer(2) is None and renderers.fps == 30.0


def test_a_lower_asked_rate_is_kept_and_a_bad_report_is_ignored() -> None:
    renderers = Renderers(5.0)
    client = page(renderers, 7)
    renderers.report({"client": "7", "renderer": SWIFTSHADER})
    assert renderers.fps == 5.0
    renderers.refresh()
    assert "5 frames/s" in client.gui.lines[0].content
    for query in ({"client": "x", "renderer": GPU}, {"renderer": GPU}, {"client": "99"}):
        renderers.report(query)  # malformed, or a page that is not open
    assert renderers.renderer(99) is None and renderers.renderer(7) == SWIFTSHADER
    renderers.report({"client": "7", "renderer": "x" * 10_000})
    assert len(renderers.renderer(7) or "") == renderer.MAX_RENDERER


def test_the_probe_is_an_image_whose_error_handler_reports() -> None:
    text = probe_html(3)
    assert text.startswith("<img") and 'onerror="' in text
    assert f"r.slice(0,{renderer.MAX_RENDERER})" in html.unescape(text)  # bounded on the page
    assert '"' not in html.unescape(text).split('onerror="', 1)[1].rsplit('"', 1)[0]
    assert "No GPU" in note(10.0)


@pytest.fixture
def viewer() -> Iterator[Viewer]:
    with Viewer("single_axis", port=0, demo=False) as v:
        yield v


def test_the_viewer_hears_a_page_report_behind_its_access_checks(viewer: Viewer) -> None:
    heard: list[dict[str, str]] = []
    viewer.policy.beacons[renderer.PATH] = heard.append
    path = f"{renderer.PATH}?client=0&renderer=SwiftShader%20driver"

    def get(**headers: str) -> int:
        connection = http.client.HTTPConnection("127.0.0.1", viewer.port, timeout=10)
        connection.request("GET", path, headers=headers)
        status = connection.getresponse().status
        connection.close()
        return status

    assert get() == 403 and not heard  # without the token: refused, not heard
    cookie = f"{viewer.policy.cookie_name}={viewer.token}"
    assert get(Cookie=cookie) == 204
    assert heard == [{"client": "0", "renderer": "SwiftShader driver"}]


def test_a_retired_element_is_hidden_at_once_and_removed_later() -> None:
    elements = [Line("a"), Line("b")]
    timer = retire(cast(Any, elements), delay=0.2)
    assert all(e.visible is False and not e.removed for e in elements)
    assert timer.daemon  # never holds up the viewer's exit
    timer.join(5.0)
    assert all(e.removed for e in elements)


def test_a_machine_without_a_3d_view_gets_no_note_about_it() -> None:
    renderers = Renderers(30.0)
    client = page(renderers, 3)
    renderers.report({"client": "3", "renderer": SWIFTSHADER})
    renderers.refresh(view3d=False)  # single_axis: simulated axes, no 3-D model
    line = client.gui.lines[0]
    assert not line.visible and "3-D view" not in line.content
    renderers.refresh(view3d=True)  # back on a machine with a model: said again
    assert line.visible and "3-D view at most" in line.content
