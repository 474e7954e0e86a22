"""The pytest plugin of the testbench: the fixtures and helpers of :mod:`scenes.tools.testing`
where the ``[physics]`` extra is installed; nothing otherwise, so that pytest keeps working in an
environment with the core alone."""

from mcl.extras import installed

if installed("physics"):
    from scenes.tools.testing import *  # noqa: F403
