"""What a translated ST program runs on: the loaded program scanned by a scene
(:mod:`~plc.st.runtime.program`), its TASK, the run-time helpers and standard function blocks,
located I/O, blocks a machine offers (:mod:`~plc.st.runtime.external`) and the watch table of a
running program (:mod:`~plc.st.runtime.watch`)."""

__all__: list[str] = []
