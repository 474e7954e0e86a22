"""The simulation side of the viewer: the scene run in its own thread and paced to the wall clock
(:mod:`~viewer.sim.session`, with the testbench's pacing loop, :mod:`scenes.pacing`), the
immutable snapshots it hands to the pages (:mod:`~viewer.sim.snapshot`), the scope recorder, the
demo run, the programs offered, the cam view's data and an external PLC."""

__all__: list[str] = []
