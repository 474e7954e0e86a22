"""The Faults panel: force an axis' inputs and inject faults through ``scene.faults``, clear
them again (for the page in control)."""

from __future__ import annotations

__all__ = ["FAULTS", "applies", "build_faults"]

import viser

import mcl.faults
from viewer.pages.widgets import SceneGui
from viewer.sim.session import Session
from viewer.sim.snapshot import AxisView, Snapshot

FAULTS: dict[str, mcl.faults.Fault] = {
    "force LIM+ on": mcl.faults.SwitchStuck("lim_pos", True),
    "force LIM− on": mcl.faults.SwitchStuck("lim_neg", True),
    "force REF on": mcl.faults.SwitchStuck("ref", True),
    "force REF off": mcl.faults.SwitchStuck("ref", False),
    "encoder freeze": mcl.faults.EncoderFreeze(),
    "encoder wire break": mcl.faults.EncoderWireBreak(),
    "drive not ready": mcl.faults.DriveNotReady(),
    "amplifier fault": mcl.faults.AmplifierFault(),
    "brake does not hold": mcl.faults.BrakeFailure(),
    "analog offset 0.1 V": mcl.faults.AnalogOffset(0.1),
}
"""Inputs the panel can force and faults it can inject (``scene.faults``), by label; the panel
offers each for the axes it applies to."""


def applies(fault: mcl.faults.Fault, view: AxisView) -> bool:
    """Whether an axis can have ``fault``: a switch it has, a drive and brake if it has one."""
    if isinstance(fault, mcl.faults.SwitchStuck):
        return fault.switch in view.switches
    if fault.key() in ("drive", "brake", "analog_out"):
        return view.has_drive
    return True


def build_faults(gui: SceneGui, session: Session, snapshot: Snapshot) -> None:
    """The Faults folder of a scene: one choice per axis and fault it can have (switch faults
    only for its switches, drive faults only with a drive), Inject, Clear faults of an axis."""
    generation = snapshot.generation
    choices_ = {
        f"{name}: {label}": (name, fault)
        for name, view in snapshot.axes.items()
        for label, fault in FAULTS.items()
        if applies(fault, view)
    }
    labels = list(choices_)
    names = list(snapshot.axes)
    with gui.folder("Faults", order=7, expand_by_default=False):
        kind = gui.dropdown("Fault", labels, labels[0])
        inject = gui.button("Inject", color="orange", icon=viser.Icon.BOLT)
        axis = gui.dropdown("Clear axis", names, names[0])
        clear = gui.button("Clear faults", icon=viser.Icon.ERASER)

    @inject.on_click
    def _(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
        if session.snapshot.generation == generation:
            session.inject(*choices_[kind.value])

    @clear.on_click
    def _(event: viser.GuiEvent[viser.GuiButtonHandle]) -> None:
        if session.snapshot.generation == generation:
            session.clear_faults(axis.value)
