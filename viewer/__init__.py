"""Browser viewer (viser) for any testbench scene: watch it live in 3-D and operate its axes.

Modules:
    model_scene: a MuJoCo model as viser scene nodes that follow the bodies.
    operator: the operator's request flags (HMI variables) and the PLC program that passes them
        to the library's function blocks.
    session: the scene simulated in its own thread, paced to the wall clock; snapshots.
    app: the GUI and its 30 Hz update loop; ``Viewer`` = session + server + app.
    __main__: the command line, ``python -m viewer``.
"""
