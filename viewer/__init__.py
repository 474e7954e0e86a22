"""Browser viewer (viser) for any testbench scene: watch it live in 3-D and operate its axes.

Sub-packages, by concept:
    sim: the scene run in its own thread and paced to the wall clock, its snapshots, the scope
        recorder, the demo run, the programs offered and an external PLC.
    serving: the server on a checked port, who may open it and what a page may send, who
        operates, the lifesign of every page.
    view3d: the MuJoCo model in 3-D, its overlays, axis marks, legend and cameras.
    scope: the scope of a page (channels, trigger, acquisition, read-out, export).
    pages: the GUI skeleton, each page's layout and panels.
The operator's buttons only set requests of the PLC layer's operator program
(:mod:`plc.operator`); ``python -m viewer`` is the command line (:mod:`viewer.__main__`).
``Viewer(scene="gantry", port=8080)`` (:class:`viewer.serving.server.Viewer`) serves it.
Needs the ``[viewer]`` extra.

The public API is :class:`Viewer` and the command line; the sub-packages are the viewer's
internals.
"""

from mcl.extras import require

require("viewer", "viewer")

from viewer.serving.server import Viewer

__all__ = ["Viewer"]
