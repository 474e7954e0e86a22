"""The checks of the ST compiler: types (:mod:`~plc.st.semantics.types`), names and scopes
(:mod:`~plc.st.semantics.scope`), what a program may name besides its own declarations
(:mod:`~plc.st.semantics.catalog`) and declarations with their initial values
(:mod:`~plc.st.semantics.declarations`)."""

__all__: list[str] = []
