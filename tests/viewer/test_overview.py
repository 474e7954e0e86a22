"""The all-axes overview and the axis panel's texts, without a browser: what the table shows is
read back from its HTML and compared with the simulation (stepped scan by scan here)."""

from __future__ import annotations

import dataclasses
import re
from types import MappingProxyType, SimpleNamespace
from typing import cast

import pytest
import viser

import mcl.faults
from plc.operator.hmi import Move
from viewer.pages.overview import LAMPS, VALUE_COLUMNS, Overview, overview_html
from viewer.pages.panels import axis_panel_html, signals_html
from viewer.sim.session import Session

LAMP_OFF = "#cfd8dc"


def row(session: Session, axis: str) -> dict[str, str]:
    """The cells of ``axis``' row in the overview as plain texts; lamps as "on" or "off"."""
    page = overview_html(session.snapshot)
    lines = re.findall(rf'<tr data-axis="{axis}" data-line="(?:values|set|lamps)">(.*?)</tr>', page)
    assert len(lines) == 3, f"no values, set points and lamps of {axis}"
    cells: dict[str, str] = {}
    found = re.findall(r'<(td|div) data-field="(\w+)"[^>]*>(.*?)</\1>', "".join(lines))
    for _, field, content in found:
        colour = re.search(r"background:(#\w+)", content)
        if colour is not None:
            cells[field] = "off" if colour[1] == LAMP_OFF else "on"
        else:
            cells[field] = re.sub(r"<[^>]+>", "", content).strip()
    error = re.search(
        rf'<tr data-axis="{axis}" data-line="error">.*?title="([^"]*)"', page, re.DOTALL
    )
    assert error is not None
    cells["error_text"] = error[1]
    return cells


def lit(cells: dict[str, str]) -> set[str]:
    """The lamps of a row that are on."""
    return {field for field, _, _ in LAMPS if cells[field] == "on"}


def micrometres(text: str) -> float:
    """A following-error cell of an axis in mm (``"1.7"``, the header says µm) as a number [µm]."""
    assert "µm" not in text and text.strip() == text  # the unit is the header's
    return float(text)


def powered(session: Session, axis: str = "X") -> None:
    session.requests(axis).set_power(True)
    session.advance(100)


def test_the_peak_following_error_is_the_largest_of_every_scan() -> None:
    session = Session("gantry")
    x = session.scene.axes["X"]

    def scans(n: int) -> float:
        """Run ``n`` PLC scans one by one; the largest |following error| among them [mm]."""
        peak = 0.0
        for _ in range(n):
            session.advance(1)
            peak = max(peak, abs(x.following_error))
        return peak

    session.requests("X").set_power(True)
    largest = scans(100)
    session.requests("X").move(Move("relative", 200.0, 400.0, 4000.0))
    largest = max(largest, scans(150))
    assert session.snapshot.axes["X"].velocity == pytest.approx(400.0, rel=0.01)
    largest = max(largest, scans(700))
    cells = row(session, "X")
    assert session.snapshot.axes["X"].position == pytest.approx(200.0, abs=0.01)
    assert largest > 1e-3  # a following error of more than a micrometre to catch
    assert micrometres(cells["peak_following_error"]) == pytest.approx(largest * 1e3, abs=0.051)
    assert abs(micrometres(cells["following_error"])) < micrometres(cells["peak_following_error"])

    session.reset_peaks()
    since_reset = scans(20)
    cells = row(session, "X")
    assert micrometres(cells["peak_following_error"]) == pytest.approx(since_reset * 1e3, abs=0.051)
    assert since_reset < 0.2 * largest  # at standstill: the move's peak is gone


def test_the_row_shows_set_point_and_actual_values_in_the_axis_units() -> None:
    session = Session("gantry")
    powered(session)
    session.requests("X").move(Move("relative", 200.0, 400.0, 4000.0))
    session.advance(150)
    view, cells = session.snapshot.axes["X"], row(session, "X")
    axis = session.scene.axes["X"]
    assert cells["name"] == "X mm"  # the axis and its unit
    assert float(cells["set_position"]) == pytest.approx(axis.sp_pos, abs=0.0005)
    assert float(cells["position"]) == pytest.approx(axis.POS, abs=0.0005)
    assert float(cells["set_velocity"]) == pytest.approx(400.0, abs=0.005)
    assert float(cells["velocity"]) == pytest.approx(view.velocity, abs=0.005)
    assert float(cells["output"]) == pytest.approx(10.0 * axis.volts, abs=0.05)  # % of 10 V
    assert 30.0 < float(cells["output"]) < 50.0  # 400 of Vmax 1000 mm/s
    assert {"enabled", "moving"} <= lit(cells) and not {"ready", "in_position"} & lit(cells)
    session.advance(800)
    assert lit(row(session, "X")) == {"ready", "enabled", "in_position"}


def test_an_encoder_only_axis_shows_dashes_where_it_has_no_drive() -> None:
    session = Session("flying_shear")
    session.advance(5)
    wheel, carriage = row(session, "W"), row(session, "S")
    for field in ("set_position", "set_velocity", "following_error", "output"):
        assert wheel[field] == "—", field
        assert carriage[field] != "—", field
    assert wheel["position"] != "—" and wheel["velocity"] != "—"
    assert not {"enabled", "in_position"} & lit(wheel)


def test_the_status_word_shows_switches_limits_and_the_error_with_its_number() -> None:
    session = Session("gantry")
    powered(session)
    session.requests("X").home("set position (no motion)", 990.0)
    session.advance(20)
    assert "homed" in lit(row(session, "X")) and "sw_limit" not in lit(row(session, "X"))
    limit = session.scene.axes["X"].constants
    assert limit is not None and limit.LimPos == 1002.0
    session.requests("X").move(Move("absolute", limit.LimPos, 100.0, 1000.0))
    session.advance(300)
    assert "sw_limit" in lit(row(session, "X"))  # the set point stands at the software limit
    session.requests("X").move(Move("relative", 5.0, 100.0, 1000.0))
    session.advance(10)
    assert "refused: Move by: error 8" in row(session, "X")["error_text"]

    session.inject("X", mcl.faults.SwitchStuck("lim_pos", True))
    session.advance(5)
    cells = row(session, "X")
    assert {"lim_pos", "error"} <= lit(cells) and "ready" not in lit(cells)
    assert cells["error_text"].startswith(f"2004 {mcl.error_text(2004)}")


def test_an_encoder_wire_break_keeps_every_value_of_the_row() -> None:
    session = Session("gantry")
    powered(session)
    before = row(session, "X")
    session.inject("X", mcl.faults.EncoderWireBreak())
    session.advance(5)
    after = row(session, "X")
    assert after["error_text"] == f"2001 {mcl.error_text(2001)}"
    assert after.keys() == before.keys()
    assert all(after[f] not in ("", "—") for f, *_ in VALUE_COLUMNS)
    assert "error" in lit(after) and "in_position" not in lit(after)


def test_texts_from_the_simulation_are_escaped() -> None:
    session = Session("gantry")
    hostile = dataclasses.replace(
        session.snapshot.axes["X"], error="<img src=x onerror=alert(1)>", error_id=2001
    )
    snapshot = dataclasses.replace(session.snapshot, axes={"X": hostile})
    assert "<img" not in overview_html(snapshot) and "<img" not in axis_panel_html(hostile)


def test_the_overview_sends_only_a_changed_table() -> None:
    server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    try:
        session = Session("gantry")
        overview = Overview(server.gui)
        overview.update(session.snapshot)
        shown = overview._html.content
        assert 'data-axis="X"' in shown
        overview.update(session.snapshot)
        assert overview._html.content is shown
        powered(session)
        overview.update(session.snapshot)
        assert overview._html.content != shown
        overview.remove()
    finally:
        server.stop()


def test_the_axis_panel_puts_long_texts_under_the_values() -> None:
    session = Session("gantry")
    powered(session)
    session.inject("X", mcl.faults.EncoderWireBreak())
    session.requests("X").move(Move("relative", 5.0, 100.0, 1000.0))
    session.advance(10)
    page = axis_panel_html(session.snapshot.axes["X"])
    table, texts = page.split("</table>", 1)
    for value in ("Position", "Velocity", "Following error", "State"):
        assert f'data-value="{value}"' in table
    assert "table-layout:fixed" in table
    assert f"2001 {mcl.error_text(2001)}" in texts and "Move by: error" in texts
    assert mcl.error_text(2001) not in table


def test_signals_carry_labels_with_units() -> None:
    page = signals_html(Session("flying_shear").snapshot)
    assert "carriage − strip [mm/s]" in page and "knife valve command [−1…1]" in page
    assert "carriage_minus_strip" not in page and "[-]" not in page


def test_a_signal_that_rounds_to_zero_reads_0_not_minus_0() -> None:
    """The delta picker's standing belt read "-0.000 mm/s" (a −0.0002 of noise)."""
    snapshot = Session("flying_shear").snapshot
    small = [dataclasses.replace(s, value=-0.0002) for s in snapshot.signals]
    page = signals_html(dataclasses.replace(snapshot, signals=tuple(small)))
    assert "-0.000" not in page and "0.000" in page


def headers(session: Session) -> list[str]:
    """The value columns' headers of the overview (plain text, without what their lines are)."""
    page = overview_html(session.snapshot)
    found = re.findall(r'<th title="[^"]*" style="text-align:right[^"]*">(.*?)<div', page)
    return [str(h).strip() for h in found]


def test_the_headers_carry_the_unit_the_axes_share() -> None:
    assert headers(Session("gantry")) == ["Pos [mm]", "Vel [mm/s]", "FE [µm]", "Out [%]"]
    mixed = headers(Session("rotary_cutter"))  # mm and deg: each row names its unit
    assert mixed == ["Pos", "Vel", "FE", "Out [%]"]
    cells = row(Session("rotary_cutter"), "D")  # each following error then carries its own
    assert cells["following_error"].endswith(" mdeg")
    assert row(Session("gantry"), "X")["following_error"] == "0.0"  # the header's µm


def test_the_name_column_is_as_wide_as_the_longest_name_with_its_unit() -> None:
    from viewer.pages import overview

    cell = list(Session("cell").snapshot.axes.values())
    width = overview.name_width(cell)  # "gantry/X" over "mm": 8 characters
    assert width == pytest.approx(overview.CHAR_WIDTH * 8 + 0.4)
    assert f'<col style="width:{width:.2f}em">' in overview_html(Session("cell").snapshot)
    gantry = list(Session("gantry").snapshot.axes.values())
    assert overview.name_width(gantry) == overview.NAME_WIDTH  # "X mm": the narrowest column


def shown(**changes: object) -> tuple[str, dict[str, str]]:
    """The overview of the gantry with its X axis' view changed as given: the table and X's
    cells."""
    session = Session("gantry")
    snapshot = session.snapshot
    axes = dict(snapshot.axes)
    axes["X"] = dataclasses.replace(axes["X"], **changes)  # type: ignore[arg-type]
    changed = dataclasses.replace(snapshot, axes=MappingProxyType(axes))
    return overview_html(changed), row(cast(Session, SimpleNamespace(snapshot=changed)), "X")


def test_each_value_has_its_digits_its_tooltip_and_set_points_read_grey() -> None:
    page, cells = shown(
        position=12.34567,
        set_position=-0.0001,
        velocity=0.25,
        set_velocity=-3.14159,
        volts=1.2345,
        following_error=0.0012345,
        peak_following_error=-0.0025,
    )
    assert (cells["position"], cells["set_position"]) == ("12.346", "0.000")  # no −0.000
    assert (cells["velocity"], cells["set_velocity"]) == ("0.25", "-3.14")
    assert cells["output"] == "12.3"  # % of ±10 V
    assert (cells["following_error"], cells["peak_following_error"]) == ("1.2", "-2.5")  # µm
    values = re.search(r'<tr data-axis="X" data-line="values">(.*?)</tr>', page)
    set_points = re.search(r'<tr data-axis="X" data-line="set">(.*?)</tr>', page)
    assert values is not None and set_points is not None
    for field, _, line, tip in VALUE_COLUMNS:
        own = (values, set_points)[line][1]
        assert re.search(rf'data-field="{field}" title="{re.escape(tip)}"', own), field
    for field, _, line, _ in VALUE_COLUMNS:  # set points and peak grey, actual values not
        style = re.search(rf'data-field="{field}"[^>]*style="([^"]*)"', page)
        assert style is not None and ("color:#78909c" in style[1]) == (line == 1), field
    assert "XX" not in page  # nothing between the cells


def test_an_axis_in_another_unit_shows_its_following_error_with_four_decimals() -> None:
    """Axes in mm and in another unit: each following error carries its own unit."""
    _, cells = shown(unit="rev", following_error=0.0012345, peak_following_error=0.5)
    assert (cells["following_error"], cells["peak_following_error"]) == ("0.0012 rev", "0.5000 rev")


def test_without_a_drive_both_following_errors_read_a_dash() -> None:
    _, cells = shown(has_drive=False, following_error=0.5, peak_following_error=0.5)
    assert cells["following_error"] == cells["peak_following_error"] == cells["output"] == "—"


def test_the_error_text_names_the_error_and_the_last_refused_command() -> None:
    _, cells = shown(error_id=0, last_error="not powered", last_error_kind="Refused")
    assert cells["error_text"] == "refused: not powered"
    _, cells = shown(error_id=17, error="following error", last_error="", last_error_kind="")
    assert cells["error_text"] == "17 following error"
    _, cells = shown(
        error_id=17, error="following error", last_error="x", last_error_kind="Aborted"
    )
    assert cells["error_text"] == "17 following error · aborted: x"


def test_only_the_in_position_lamp_names_the_window() -> None:
    page, _ = shown(in_position_window=0.005)
    lamps = dict(re.findall(r'<div data-field="(\w+)" title="([^"]*)"', page))
    assert lamps["in_position"].endswith(" (±5.0 µm)")
    assert all("±" not in tip for field, tip in lamps.items() if field != "in_position")
