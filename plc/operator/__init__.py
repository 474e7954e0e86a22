"""The operator program: the requests of an HMI (the viewer's buttons) passed to the library's
function blocks once per PLC scan (:mod:`~plc.operator.hmi`)."""

__all__: list[str] = []
