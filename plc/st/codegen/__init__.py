"""Code generation of the ST compiler: a checked tree translated to one Python module
(:mod:`~plc.st.codegen.translate`): expressions, statements, calls, the standard functions and
the inputs set once (:mod:`~plc.st.codegen.hoist`)."""

__all__: list[str] = []
