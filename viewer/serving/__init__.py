"""Serving the viewer: the server on a checked port (:mod:`~viewer.serving.server`), who may open
it and what a page may send (:mod:`~viewer.serving.security`), who operates
(:mod:`~viewer.serving.control`) and the lifesign of every page."""

__all__: list[str] = []
