"""Browser viewer (viser) for any testbench scene: watch it live in 3-D and operate its axes.

Modules:
    model_scene: a MuJoCo model as viser scene nodes that follow the bodies.
    overlays: the set-point ghost and the force arrows drawn over the model.
    axis_marks: each axis' name and positive direction drawn on the part it moves.
    legend: what every colour of the 3-D view means (bodies, lamps, overlays).
    operator: the operator's request flags (HMI variables) and the PLC program that passes them
        to the library's function blocks.
    session: the scene simulated in its own thread, paced to the wall clock; its commands and
        the error history.
    snapshot: the immutable copies of what the viewer shows, taken from the scene.
    recorder: the scope channels of a scene in a ring buffer.
    security: who may open the viewer (same origin, expected Host, token, headers), the check of
        every GUI value a page sends, and the requests viser's server refuses.
    panels: the HTML of the read-out panels.
    control: who operates (one page in control) and the dead-man of its held jogs.
    widgets: the GUI elements of one scene, each with its gate rule.
    axis_panel: the panel of one axis and the step and jog hotkeys.
    scope: several recorder channels on one time base, trigger, CSV export.
    faults_panel: forcing inputs and injecting faults.
    views: camera presets, follow cameras and the 3-D overlays' choices.
    app: the GUI skeleton and its 30 Hz update loop.
    server: ``Viewer`` = session + server + app, on a checked port.
    __main__: the command line, ``python -m viewer``.
"""
