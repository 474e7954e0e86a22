"""The 3-D view: the MuJoCo model as viser scene nodes (:mod:`~viewer.view3d.model_scene`), the
overlays drawn over it, the axis marks, the legend of its colours and the cameras."""

__all__: list[str] = []
