"""The front end of the ST compiler: sources parsed with blark into typed trees, kept on disk so
that a file parses once (:mod:`~plc.st.frontend.parse`, :mod:`~plc.st.frontend.tree_cache`)."""

__all__: list[str] = []
