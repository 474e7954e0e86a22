"""The scope of a page: its channels, triggers and acquisition (:mod:`~viewer.scope.capture`), the
read-out and export (:mod:`~viewer.scope.readout`), the display units
(:mod:`~viewer.scope.units`) and its GUI (:mod:`~viewer.scope.panel`)."""

__all__: list[str] = []
