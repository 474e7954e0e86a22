"""The tools around the scenes: the command line (:mod:`.cli`), commissioning, contour error,
plots, console reports, sweeps and their example scenarios, and the pytest plugin
(:mod:`.testing`)."""
