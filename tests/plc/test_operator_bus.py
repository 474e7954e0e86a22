"""The bus front end of the operator program on simulated axes and a real signal table (the
gantry's): control-word commands, the result held until the master acknowledges it, the command
counter, commands the axis cannot take, method calls held until the next command (a held stop
released before it), the master out of control, and the status it publishes. Positions are
measured on the simulated carriage."""

from __future__ import annotations

from typing import Any

import pytest

import mcl
import scenes
from plc.operator.axis import AxisOperator
from plc.operator.bus import CONTROL_BITS, STATUS_BITS, CommandWords
from scenes.bridge.table import AxisRegisters, SignalTable
from tests.helpers import carriage_mm, make_machine

MOVE = {"velocity": 200.0, "acceleration": 2000.0, "deceleration": 2000.0}


def bits(*names: str) -> int:
    return sum(1 << CONTROL_BITS.index(name) for name in names)


class Bus:
    """The gantry's table over three simulated axes X, Y, Z (powered, referenced at 0 mm), X
    driven by its command words; published after every scan. A subclass drives another block
    of the table (``BLOCK``, its ``STATUS`` bits) by overriding :meth:`front_end`."""

    BLOCK = "X"
    STATUS: tuple[str, ...] = STATUS_BITS
    operator: Any
    """The block's operator (an axis', a group's)."""

    def __init__(self) -> None:
        self.machine = make_machine("XYZ")
        self.table = SignalTable(scenes.definition("gantry"))
        self.words = self.front_end([self.machine.axes[a] for a in "XYZ"])

    def front_end(self, axes: list[mcl.Axis]) -> Any:
        """The front end on the block's registers."""
        self.operator = AxisOperator(axes[0], None, axes, sim_time=lambda: self.machine.time)
        return CommandWords(self.operator, AxisRegisters(self.table, self.BLOCK))

    def scan(self) -> None:
        self.words()
        self.words.publish()

    def run(self, seconds: float) -> None:
        self.machine.run(self.scan, timeout=seconds)

    def powered(self, seconds: float) -> list[bool]:
        """Scans for ``seconds`` (:meth:`run`): the power bit each published."""
        seen: list[bool] = []

        def scan() -> None:
            self.scan()
            seen.append(self.status("power"))

        self.machine.run(scan, timeout=seconds)
        return seen

    def write(self, **values: float) -> None:
        for name, value in values.items():
            self.table.put(f"{self.BLOCK}.{name}", value)

    def status(self, name: str) -> bool:
        word = int(self.table.get(f"{self.BLOCK}.status"))
        return bool(word >> self.STATUS.index(name) & 1)

    def get(self, name: str) -> float:
        return self.table.get(f"{self.BLOCK}.{name}")


@pytest.fixture
def bus() -> Bus:
    bus = Bus()
    bus.write(control=bits("enable"), **MOVE)
    bus.run(0.01)
    return bus


def test_a_command_is_held_done_until_the_master_clears_its_bit(bus: Bus) -> None:
    assert bus.status("power") and bus.status("homed") and bus.get("command_count") == 0
    bus.write(position=50.0, control=bits("enable", "move_absolute"))
    bus.run(0.004)
    assert bus.status("busy") and bus.status("active") and bus.get("command_count") == 1
    assert bus.get("command") == 1 + CONTROL_BITS.index("move_absolute")
    bus.run(1.0)
    assert carriage_mm(bus.machine) == pytest.approx(50.0, abs=0.05)
    assert bus.status("done") and not bus.status("busy")
    assert bus.get("actual_position") == pytest.approx(50.0, abs=0.05)
    assert bus.get("state") == mcl.AxisState.StandStill
    bus.write(control=bits("enable"))  # the acknowledgement
    bus.run(0.004)
    assert not bus.status("done") and bus.get("command_count") == 1


def test_a_pulse_keeps_its_result_until_the_next_command(bus: Bus) -> None:
    bus.write(distance=20.0, control=bits("enable", "move_relative"))
    bus.write(control=bits("enable"))  # cleared before a scan saw the bit
    bus.run(1.0)
    assert carriage_mm(bus.machine) == pytest.approx(20.0, abs=0.05)
    assert bus.status("done")  # not acknowledged: never published while the bit was set
    bus.write(control=bits("enable", "move_relative"))
    bus.run(0.004)
    assert not bus.status("done") and bus.get("command_count") == 2


def test_an_error_is_held_with_its_id_and_a_command_it_cannot_take_is_eparam(bus: Bus) -> None:
    bus.write(position=1e9, velocity=0.0, control=bits("enable", "move_absolute"))
    bus.run(0.01)
    assert bus.status("error") and bus.get("error_id") == mcl.ErrorID.EParam
    bus.write(control=bits("enable"))
    bus.run(0.01)
    assert not bus.status("error") and bus.get("error_id") == 0
    assert "home" not in bus.words.commands  # no recipe
    bus.write(control=bits("enable", "home"))
    bus.run(0.01)
    assert bus.status("error") and bus.get("error_id") == mcl.ErrorID.EParam
    assert bus.words.current is None and bus.get("command_count") == 2
    assert carriage_mm(bus.machine) == pytest.approx(0.0, abs=0.01)


def test_a_slow_poller_sees_the_result_of_a_pulse_the_block_answered_at_once(bus: Bus) -> None:
    """A master that pulses a command bit between two scans and reads the status only after
    a run of scans (published once at its end, as the bridge's lockstep runs do) still sees
    the result: a refusal (home without a recipe: Error, EParam) and a reset's Done, each held
    until the next command; before any command the status names none."""
    assert bus.get("command") == 0 and bus.get("command_count") == 0
    for command, status, error_id in (("home", "error", mcl.ErrorID.EParam), ("reset", "done", 0)):
        bus.write(control=bits("enable", command))
        bus.write(control=bits("enable"))  # cleared before a scan saw the bit
        bus.machine.run(bus.words, timeout=0.01)  # five scans, nothing published
        bus.words.publish()
        assert bus.status(status) and bus.get("error_id") == error_id, command
        assert bus.get("command") == 1 + CONTROL_BITS.index(command)


def test_the_jog_bits_count_as_commands_and_jog_at_the_velocity(bus: Bus) -> None:
    bus.write(velocity=-50.0, control=bits("enable", "jog_pos"))
    bus.run(0.5)
    assert bus.words.current is bus.operator.jog and bus.get("command_count") == 1
    assert bus.get("actual_velocity") == pytest.approx(50.0, rel=0.05)  # |velocity|
    bus.write(control=bits("enable", "jog_neg"))
    bus.run(0.5)
    assert bus.get("command_count") == 2 and bus.get("actual_velocity") < -40.0


def test_gearing_is_offered_where_the_table_has_its_fields(bus: Bus) -> None:
    assert set(bus.words.commands) >= {"gear_in", "gear_in_pos", "gear_out", "halt", "stop"}
    assert "force_control" not in bus.words.commands
    bus.write(master=1.0, ratio_numerator=1.0, ratio_denominator=1.0)
    bus.write(control=bits("enable", "gear_in"))
    bus.run(0.01)
    assert bus.operator.gear_in.Master is bus.machine.axes["Y"] and not bus.status("error")


def test_a_call_holds_its_execute_until_the_next_command(bus: Bus) -> None:
    table = bus.table
    table.request("X", "move_relative", {"distance": 20.0})
    bus.run(0.002)  # one scan: a call whose bit is low starts at once
    assert bus.status("busy") and bus.get("command_count") == 1
    bus.run(1.0)
    assert bus.status("done") and bus.operator.move_relative.Execute
    table.request("X", "move_relative", {"distance": 20.0})  # again: one scan low first
    bus.run(0.002)  # one scan
    assert not bus.operator.move_relative.Execute
    bus.run(1.0)
    assert carriage_mm(bus.machine) == pytest.approx(40.0, abs=0.05)
    assert bus.get("command_count") == 2
    bus.write(distance=10.0, control=bits("enable", "move_relative"))  # the call's bit: waits
    bus.run(0.002)  # one scan
    assert not bus.operator.move_relative.Execute
    bus.run(1.0)
    assert carriage_mm(bus.machine) == pytest.approx(50.0, abs=0.05)
    assert bus.get("command_count") == 3  # the word's command alone
    table.request("X", "move_relative", {"distance": 20.0})
    bus.run(1.0)
    bus.write(position=0.0, control=bits("enable", "move_absolute"))  # another bit: at once
    bus.run(0.002)  # one scan
    assert bus.operator.move_absolute.Execute and bus.get("command_count") == 5


def test_a_called_stop_ends_one_scan_before_the_next_command(bus: Bus) -> None:
    table = bus.table

    def stopped() -> float:
        table.request("X", "move_velocity", {"velocity": 100.0})
        bus.run(0.3)
        table.request("X", "stop")
        bus.run(0.5)
        assert bus.status("done") and bus.get("state") == mcl.AxisState.Stopping
        return carriage_mm(bus.machine)

    start = stopped()
    table.request("X", "move_relative", {"distance": 20.0, "velocity": 200.0})
    bus.run(0.002)  # one scan
    assert not bus.operator.stop.Execute and not bus.operator.move_relative.Execute
    bus.run(1.0)
    assert bus.status("done") and bus.get("error_id") == 0
    assert carriage_mm(bus.machine) - start == pytest.approx(20.0, abs=0.05)
    start = stopped()
    bus.write(distance=30.0, control=bits("enable", "move_relative"))
    bus.run(0.002)  # one scan
    assert not bus.operator.stop.Execute and not bus.operator.move_relative.Execute
    bus.run(1.0)
    assert bus.status("done") and bus.get("error_id") == 0
    assert carriage_mm(bus.machine) - start == pytest.approx(30.0, abs=0.05)


def test_out_of_control_the_axis_is_left_alone_and_old_edges_are_dropped(bus: Bus) -> None:
    bus.write(distance=20.0, control=bits("enable", "move_relative"))
    bus.table.in_control = False
    bus.run(1.0)
    assert carriage_mm(bus.machine) == pytest.approx(0.0, abs=0.01)
    bus.table.in_control = True
    bus.run(0.5)  # the bit was set while out of control: no edge
    assert carriage_mm(bus.machine) == pytest.approx(0.0, abs=0.01)
    assert bus.get("command_count") == 0


def test_the_published_inputs_and_switches_are_the_axis(bus: Bus) -> None:
    axis = bus.machine.axes["X"]
    inputs = sum(1 << i for i, on in enumerate(axis.DI) if on)
    assert bus.get("inputs") == inputs
    assert bus.status("ref") == bool(axis.io.ref)
    assert bus.get("following_error") == pytest.approx(axis.following_error)
    assert bus.get("volts") == pytest.approx(axis.volts, abs=1e-6)
    assert "X.actual_force" not in bus.table.by_name  # no force fields on the gantry


def test_before_enable_the_drive_is_off_and_no_result_is_shown() -> None:
    """A fresh program: no result before the first command (no current command, ErrorID 0),
    the drive off until enable (not even for a scan)."""
    bus = Bus()  # the axes powered by a previous program; the control word 0
    bus.run(0.002)  # one scan
    assert not bus.status("power") and bus.get("command_count") == 0
    assert not any(bus.status(name) for name in ("done", "error", "command_aborted"))
    assert bus.words.current is None and bus.get("error_id") == 0 and bus.get("command") == 0
    powered = bus.powered(0.05)
    assert powered and not any(powered) and bus.get("command_count") == 0
    bus.write(control=bits("enable"))
    bus.run(0.01)
    assert bus.status("power")


def test_a_result_reached_between_two_publications_is_kept_past_an_early_clear(bus: Bus) -> None:
    """Published while the command was busy, the bit's fall is no acknowledgement of the Done
    that came after that publication: a slow poller clearing the bit still sees it."""
    bus.write(distance=20.0, control=bits("enable", "move_relative"))
    bus.run(0.1)
    assert bus.status("busy") and not bus.status("done")  # published while the bit is set
    bus.machine.run(bus.words, timeout=1.0)  # the move ends, nothing published
    bus.write(control=bits("enable"))
    bus.machine.run(bus.words, timeout=0.01)
    bus.words.publish()
    assert bus.status("done") and carriage_mm(bus.machine) == pytest.approx(20.0, abs=0.05)
    bus.write(control=bits("enable", "reset"))  # the next command releases it
    bus.write(control=bits("enable"))
    bus.run(0.01)
    assert bus.get("command") == 1 + CONTROL_BITS.index("reset")


def test_a_bit_cleared_while_out_of_control_acknowledges_nothing(bus: Bus) -> None:
    """The control word's edges the program sees out of control are dropped, the fall of the
    command's bit too: the result seen while the bit was set is held until the next command."""
    bus.write(control=bits("enable", "reset"))
    bus.run(0.01)
    assert bus.status("done")  # published while the bit is set
    bus.write(control=bits("enable"))  # cleared just before the operator of the viewer takes over
    bus.table.in_control = False
    bus.run(0.01)
    bus.table.in_control = True
    bus.run(0.01)
    assert bus.status("done") and bus.get("command") == 1 + CONTROL_BITS.index("reset")
    bus.write(control=bits("enable", "move_relative"), distance=10.0)
    bus.run(0.004)
    assert not bus.status("done") and bus.get("command_count") == 2


def test_the_masters_reset_after_a_called_reset_starts_after_one_scan_low(bus: Bus) -> None:
    bus.table.request("X", "reset")
    bus.run(0.002)  # one scan
    assert bus.status("done") and bus.get("command_count") == 1
    bus.write(control=bits("enable", "reset"))  # the call's bit: one scan low first
    bus.run(0.002)
    assert bus.get("command_count") == 1
    bus.run(0.002)
    assert bus.status("done") and bus.get("command_count") == 2


def test_enable_raised_while_a_call_is_held_keeps_the_call(bus: Bus) -> None:
    """The enable level is no command: raising it leaves a held call's bit set, so the same
    call again gets its scan low first."""
    bus.write(control=0)
    bus.run(0.01)
    assert not bus.status("power")
    bus.table.request("X", "reset")
    bus.run(0.01)
    assert bus.status("done") and bus.get("command_count") == 1
    bus.write(control=bits("enable"))
    bus.run(0.01)
    assert bus.status("power")
    bus.table.request("X", "reset")
    bus.run(0.002)  # one scan: low
    assert bus.get("command_count") == 1
    bus.run(0.002)
    assert bus.status("done") and bus.get("command_count") == 2


def test_a_result_not_published_while_the_bit_was_set_is_not_acknowledged(bus: Bus) -> None:
    """A pulse's result is published with its bit low; the bit set again is seen out of control
    (no edge) and cleared before the next publication: nothing acknowledged it, it is held."""
    bus.write(distance=20.0, control=bits("enable", "move_relative"))
    bus.write(control=bits("enable"))  # cleared before a scan saw the bit
    bus.run(1.0)
    assert bus.status("done") and bus.get("command_count") == 1
    bus.write(control=bits("enable", "move_relative"))
    bus.table.in_control = False
    bus.machine.run(bus.words, timeout=0.01)  # the edge dropped, nothing published
    bus.table.in_control = True
    bus.write(control=bits("enable"))
    bus.machine.run(bus.words, timeout=0.01)
    bus.words.publish()
    assert bus.status("done") and bus.get("command_count") == 1
    assert carriage_mm(bus.machine) == pytest.approx(20.0, abs=0.05)


def test_a_result_shows_only_the_outputs_its_command_has(bus: Bus) -> None:
    """MC_Reset has no CommandAborted and the jog no Done: the status shows neither for them."""
    bus.write(control=bits("enable", "reset"))
    bus.run(0.01)
    assert bus.status("done") and not bus.status("command_aborted")
    bus.write(velocity=50.0, control=bits("enable", "jog_pos"))
    bus.run(0.2)
    assert bus.words.current is bus.operator.jog and carriage_mm(bus.machine) > 2.0
    assert not any(bus.status(name) for name in ("done", "error", "command_aborted"))


def test_with_enable_clear_no_call_nor_command_of_the_master_powers_the_drive(bus: Bus) -> None:
    """The drive off (enable clear): a reset called, called again (one scan low first), then the
    master's own reset (it ends the call, after a scan low) each start a reset, and not one scan
    has the drive powered."""
    bus.write(control=0)
    bus.run(0.01)
    bus.table.request("X", "reset")
    powered = bus.powered(0.01)
    bus.table.request("X", "reset")  # its bit is held: one scan low first
    powered += bus.powered(0.01)
    bus.write(control=bits("reset"))  # the call's bit from the master: one scan low first
    powered += bus.powered(0.05)
    assert bus.get("command_count") == 3 and bus.status("done")
    assert powered and not any(powered)
