"""Browser viewer (viser) for any testbench scene: watch it live in 3-D and operate its axes.

Modules:
    model_scene: a MuJoCo model as viser scene nodes that follow the bodies.
    operator: the operator's request flags (HMI variables) and the PLC program that passes them
        to the library's function blocks.
    session: the scene simulated in its own thread, paced to the wall clock; snapshots, the
        scope recorder and the error history.
    security: who may open the viewer (same origin, expected Host, token, headers) and the
        check of every GUI value a page sends.
    app: the GUI (axis panels, STOP all, control, scope, faults, results) and its 30 Hz update
        loop; ``Viewer`` = session + server + app.
    __main__: the command line, ``python -m viewer``.
"""
