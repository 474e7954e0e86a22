"""The operator program: one program that the viewer's buttons and a fieldbus master's command
words both drive, through the library's function blocks, once per PLC scan.

- :mod:`~plc.operator.axis`: :class:`~plc.operator.axis.AxisOperator`, the function blocks of one
  axis and their sequencing, and the one vocabulary of commands a front end gives it each scan
  (:class:`~plc.operator.axis.Orders`); the outcome of every command is reported from there.
- :mod:`~plc.operator.program`: :class:`~plc.operator.program.OperatorProgram`, one axis operator
  per axis of a scene, each driven by its front end, and the release of axes groups.
- :mod:`~plc.operator.hmi`: the viewer's front end: the buttons' request flags as orders (a press
  executes until the block is no longer busy, a jog lives on a dead-man deadline).
- :mod:`~plc.operator.bus`: the bridge's front end of an axis: control words and parameter
  registers as orders (levels, edges), and the status word back.
- :mod:`~plc.operator.handshake`: :class:`~plc.operator.handshake.Handshake`, the control word of
  a block of registers (method calls, the acknowledge handshake, the command counter), shared by
  the front ends of an axis and of a group.
- :mod:`~plc.operator.group`: :class:`~plc.operator.group.GroupOperator`, the function blocks of
  one axes group (grouping, lines, arcs, its path table and paths, stop).
- :mod:`~plc.operator.group_bus`: the bridge's front end of a group: its control word and
  registers as orders, and its status back.
"""

__all__: list[str] = []
