"""The tools around the scenes: the command line (:mod:`.cli`), commissioning, contour error,
plots, console reports, sweeps and their example scenarios, and the pytest plugin
(:mod:`.testing`). Plots need the ``[plot]`` extra, sweeps the ``[sweep]`` extra."""

__all__: list[str] = []
