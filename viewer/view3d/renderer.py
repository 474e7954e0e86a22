"""What draws each page's 3-D view, and the frame rate that follows from it.

A browser without a GPU draws WebGL in software (SwiftShader, llvmpipe): every 3-D frame then
costs the page tens of milliseconds of its only thread, and at 30 frames a second a click waits
for the frames before it. Each page asks its browser for the WebGL renderer
(``WEBGL_debug_renderer_info``) once and reports it to the viewer (a same-origin request to
:data:`PATH`); while a page that draws in software is open, the 3-D view is updated at most
:data:`SOFTWARE_FPS` times a second, and that page says so in one line.

A page that draws in software also paces its own drawing (:data:`PACING`): it draws the 3-D
view only when the scene changed, at most :data:`SOFTWARE_FPS` times a second and so that
drawing takes at most :data:`DRAW_SHARE` of its time (a frame that took 100 ms waits 300 ms for
the next), and not at all for :data:`INPUT_PAUSE_MS` after a press on the panels (three frames'
time where frames are slow, at most :data:`MAX_INPUT_PAUSE_MS`), so that the command, and the
state that answers it, go through before the next frame.
"""

from __future__ import annotations

__all__ = [
    "DRAW_SHARE",
    "INPUT_PAUSE_MS",
    "MAX_INPUT_PAUSE_MS",
    "PACING",
    "PATH",
    "SOFTWARE",
    "SOFTWARE_FPS",
    "Renderers",
    "is_software",
    "note",
    "probe_html",
]

import html
import threading
from collections.abc import Mapping

import viser

PATH = "/_viewer/renderer"
"""Where a page reports its WebGL renderer (``?client=ID&renderer=TEXT``)."""

SOFTWARE = ("swiftshader", "llvmpipe", "softpipe", "software")
"""Words of the renderer strings of software WebGL (lower case)."""

SOFTWARE_FPS = 10.0
"""3-D updates per second while a page draws in software [Hz]."""

MAX_RENDERER = 200
"""Characters of a reported renderer string kept."""

DRAW_SHARE = 0.25
"""Share of a software-drawing page's time its 3-D frames may take (the rest: input, panels)."""

INPUT_PAUSE_MS = 300.0
"""3-D frames a software-drawing page skips after a press on its panels [ms], at least; a page
whose frames are slow skips three frames' time, at most :data:`MAX_INPUT_PAUSE_MS` (the answer
to the press is as slow as the frames: they share the CPU)."""
MAX_INPUT_PAUSE_MS = 1500.0
"""The longest pause of 3-D frames after a press [ms]."""

PACING = (
    "(function(period,share,pause,most){"
    "var hold=0,last=-1e9,cost=0,timer=null,tries=0;"
    "function input(e){var t=e.target;if(!(t&&t.tagName==='CANVAS'))"
    "hold=performance.now()+Math.min(Math.max(pause,3*cost),most);}"
    "window.addEventListener('pointerdown',input,true);"
    "window.addEventListener('keydown',input,true);"
    "function install(){"
    "var m=window.__viserMutable,s=m&&m.scene,r=s&&s.__r3f&&s.__r3f.root;"
    "if(!r){if(++tries<300)setTimeout(install,200);return;}"
    "var gl=r.getState().gl;if(gl.__paced)return;"
    "var draw=gl.render.bind(gl);"
    "gl.render=function(scene,camera){"
    "if(gl.getRenderTarget()!==null)return draw(scene,camera);"
    "var now=performance.now(),wait=Math.max(hold,last+Math.max(period,cost/share))-now;"
    "if(wait>0){if(timer===null)timer=setTimeout(function(){timer=null;"
    "r.getState().invalidate();},wait);return;}"
    "last=now;draw(scene,camera);cost=performance.now()-now;};"
    "gl.__paced=true;}"
    "install();})(PERIOD,SHARE,PAUSE,MOST);"
)
"""The script a page that draws in software runs: it wraps the 3-D renderer's ``render`` (the
frame loop of viser's page draws only on demand, so a frame is only asked for when the scene
changed) so that a frame waits for the period of :data:`SOFTWARE_FPS`, for :data:`DRAW_SHARE`
of the page's time and for the pause after a press outside the 3-D view
(:data:`INPUT_PAUSE_MS`); a skipped frame is asked for again when it may be drawn (the canvas
keeps the last one meanwhile; the presses are heard on ``window``: a bare name in an image's
``onerror`` is looked up on the image first). The renderer is reached through
``window.__viserMutable`` (viser's page); without it the page draws as before."""

_PROBE = (
    "try{{var c=document.createElement('canvas'),g=c.getContext('webgl2')||c.getContext('webgl'),"
    "r='none';if(g){{var e=g.getExtension('WEBGL_debug_renderer_info');"
    "r=String(e?g.getParameter(e.UNMASKED_RENDERER_WEBGL):g.getParameter(g.RENDERER));"
    "var l=g.getExtension('WEBGL_lose_context');if(l)l.loseContext();}}"
    "fetch('{path}?client={client}&renderer='+encodeURIComponent(r.slice(0,{limit})),"
    "{{credentials:'same-origin'}});"
    "if(/{software}/i.test(r)){{{pacing}}}}}catch(x){{}}this.remove();"
)


def is_software(renderer: str) -> bool:
    """Whether a WebGL renderer string names a software renderer."""
    text = renderer.lower()
    return any(word in text for word in SOFTWARE)


def probe_html(client_id: int) -> str:
    """An invisible image whose error handler reports the page's WebGL renderer and, where it
    is a software one, paces the page's 3-D drawing (:data:`PACING`; HTML set as the content of
    a page's element runs no ``<script>``, an image's ``onerror`` runs)."""
    pacing = (
        PACING.replace("PERIOD", f"{1000.0 / SOFTWARE_FPS:g}")
        .replace("SHARE", f"{DRAW_SHARE:g}")
        .replace("PAUSE", f"{INPUT_PAUSE_MS:g}")
        .replace("MOST", f"{MAX_INPUT_PAUSE_MS:g}")
    )
    script = _PROBE.format(
        path=PATH,
        client=client_id,
        limit=MAX_RENDERER,
        software="|".join(SOFTWARE),
        pacing=pacing,
    )
    return f'<img alt="" src="data:," style="display:none" onerror="{html.escape(script)}">'


def note(fps: float) -> str:
    """The page's line while it draws in software."""
    return (
        '<div style="font-size:0.8em;padding:0.2em 1em;color:#546e7a">'
        f"No GPU (software WebGL): 3-D view at most {fps:g} frames/s, "
        "paused for a moment after each click</div>"
    )


class Renderers:
    """The WebGL renderer of each open page and the 3-D frame rate they allow (thread-safe).

    Args:
        fps: The frame rate asked for (``--fps``) [Hz].
    """

    def __init__(self, fps: float) -> None:
        self.requested = fps
        self._renderers: dict[int, str] = {}
        self._lines: dict[int, viser.GuiHtmlHandle] = {}
        self._shown: dict[int, str] = {}
        self._lock = threading.Lock()

    @property
    def fps(self) -> float:
        """3-D updates per second: the asked rate, at most :data:`SOFTWARE_FPS` while a page
        that draws in software is open [Hz]."""
        with self._lock:
            software = any(is_software(r) for r in self._renderers.values())
        return min(self.requested, SOFTWARE_FPS) if software else self.requested

    def renderer(self, client_id: int) -> str | None:
        """What page ``client_id`` reported (None: nothing yet)."""
        with self._lock:
            return self._renderers.get(client_id)

    def connect(self, client: viser.ClientHandle) -> None:
        """A page opened: its line, asking its browser for the renderer."""
        line = client.gui.add_html(probe_html(client.client_id), order=-2)
        with self._lock:
            self._lines[client.client_id] = line
            self._shown[client.client_id] = line.content

    def disconnect(self, client: viser.ClientHandle) -> None:
        """A page closed: forget it."""
        with self._lock:
            self._renderers.pop(client.client_id, None)
            self._lines.pop(client.client_id, None)
            self._shown.pop(client.client_id, None)

    def report(self, query: Mapping[str, str]) -> None:
        """A page's report (``client``, ``renderer``); a malformed one is ignored."""
        try:
            client_id = int(query.get("client", ""))
        except ValueError:
            return
        renderer = query.get("renderer", "")[:MAX_RENDERER]
        with self._lock:
            if client_id in self._lines:
                self._renderers[client_id] = renderer

    def refresh(self, view3d: bool = True) -> None:
        """Each page's line: the note while it draws in software and the machine has a 3-D
        view (``view3d``: a model, not simulated axes alone), hidden otherwise (the update
        thread calls it)."""
        fps = self.fps
        with self._lock:
            pages = [(c, r, self._lines[c]) for c, r in self._renderers.items() if c in self._lines]
            for client_id, renderer, line in pages:
                content = note(fps) if view3d and is_software(renderer) else ""
                if self._shown.get(client_id) != content:
                    self._shown[client_id] = content
                    line.content = content
                    line.visible = bool(content)
