"""What the flying shear offers an ST program beyond mcl's blocks (:func:`blocks`): the
run-out table's length gauge as the block ``FS_CutGauge`` (examples/st/flying_shear_demo.st
reads the pieces with it for the cut-length correction)."""

from __future__ import annotations

__all__ = ["CutGauge", "blocks"]

from typing import ClassVar

import plc.st
from scenes.machines.flying_shear.devices import CutRecorder
from scenes.scene import Scene


class CutGauge:
    """FS_CutGauge: the cuts the machine made since the program started, measured from the
    physics (a program run again counts its own cuts).

    Inputs: Index (the cut, from 0). Outputs: Count (cuts so far), Valid (cut Index has a
    piece length), Length (that length [mm]: from the previous cut; 0 when not Valid).
    """

    MEMBERS: ClassVar[dict[str, tuple[str, str]]] = {
        "Index": ("DINT", "input"),
        "Count": ("DINT", "output"),
        "Valid": ("BOOL", "output"),
        "Length": ("LREAL", "output"),
    }

    def __init__(self, recorder: CutRecorder) -> None:
        self.recorder = recorder
        self.first = len(recorder.cuts)
        """Cuts made before the program started."""
        self.Index = 0
        self.Count = 0
        self.Valid = False
        self.Length = 0.0

    def __call__(self) -> None:
        """One scan: the outputs of cut ``Index`` now."""
        cuts = self.recorder.cuts
        self.Count = len(cuts) - self.first
        index = self.first + self.Index
        length = cuts[index].length if 0 <= self.Index < self.Count else None
        self.Valid = length is not None
        self.Length = length if length is not None else 0.0


def blocks(scene: Scene) -> dict[str, plc.st.External]:
    """The flying shear's own ST block types for ``scene`` (``plc.st.load(..., blocks=...)``)."""
    recorder = scene.device("cuts", CutRecorder)
    return {"FS_CutGauge": plc.st.External(lambda: CutGauge(recorder), CutGauge.MEMBERS)}
