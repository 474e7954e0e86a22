"""The commissioning routines of one axis as PLC code: the reversing sequence
(:mod:`~plc.commissioning.reversing`), the step test of the position loop
(:mod:`~plc.commissioning.step_test`) and both run from an operator's requests
(:mod:`~plc.commissioning.axis`)."""

__all__: list[str] = []
