"""The tools for users' scenario tests and studies: the pytest plugin, trace plots, sweeps."""

from __future__ import annotations

import pytest

import mcl
import mcl.extras
import scenes
import scenes.tools.plot  # loaded here: an in-process pytester run unloads what it loads
from scenes.errors import UserError
from scenes.tools.cli import main
from scenes.tools.sweep import Sweep, from_toml

pytest_plugins = ["pytester"]


def test_a_failing_scenario_test_writes_the_plot_of_its_trace(pytester: pytest.Pytester):
    pytester.makepyfile(
        """
        import mcl
        from scenes.tools.testing import run_until

        def test_move(scene):
            machine = scene("single_axis")
            X = machine.axes["X"]
            power = mcl.MC_Power(Axis=X)
            move = mcl.MC_MoveRelative(Axis=X, Distance=50.0, Velocity=100.0)

            def program():
                power(Enable=True)
                move(Execute=power.Status)

            run_until(machine, program, lambda: move.Done, timeout=2.0)
            assert X.POS == 51.0  # wrong on purpose

        def test_passing(scene):
            scene("single_axis").run(timeout=0.01)
        """
    )
    result = pytester.runpytest_inprocess("--scene-plots", "plots")
    result.assert_outcomes(passed=1, failed=1)
    plots = sorted(p.name for p in (pytester.path / "plots").iterdir())
    assert plots == ["test_move.html", "test_move.png"]
    assert (pytester.path / "plots" / "test_move.png").stat().st_size > 10_000
    result.stdout.fnmatch_lines(["*test_move: plots plots/test_move.png and plots/test_move.html"])


def test_without_the_plot_extra_a_failing_scenario_test_fails_alone(
    pytester: pytest.Pytester, monkeypatch: pytest.MonkeyPatch
):
    """Its own assertion, no error from the plots it cannot draw."""
    monkeypatch.setitem(mcl.extras.PACKAGES, "plot", ("matplotlib", "not_installed_plotter"))
    pytester.makepyfile(
        """
        def test_move(scene):
            scene("single_axis").run(timeout=0.01)
            assert False, "wrong on purpose"
        """
    )
    result = pytester.runpytest_inprocess("--scene-plots", "plots")
    result.assert_outcomes(failed=1)  # and no error at teardown
    result.stdout.fnmatch_lines(["*AssertionError: wrong on purpose*"])
    assert not (pytester.path / "plots").exists()


def test_run_until_says_why_a_condition_was_not_met():
    from scenes.tools.testing import run_until

    machine = scenes.load("single_axis")
    with pytest.raises(AssertionError, match=r"within 0.1 s .*X: Disabled"):
        run_until(machine, None, lambda: False, timeout=0.1)


def test_a_pulse_of_two_scans_is_not_one(scans):
    from scenes.tools.testing import assert_pulsed_once

    assert assert_pulsed_once([False, True, False]) == 1
    with pytest.raises(AssertionError, match="2 scans"):
        assert_pulsed_once([False, True, True, False], "Done")


def test_plot_command_draws_a_trace_file(tmp_path, capsys):
    machine = scenes.load("single_axis")
    X = machine.axes["X"]
    power = mcl.MC_Power(Axis=X)
    machine.run(lambda: power(Enable=True), timeout=0.2)
    trace = machine.trace.to_csv(tmp_path / "run.csv")
    assert main(["plot", str(trace)]) == 0
    png, page = tmp_path / "run.png", tmp_path / "run.html"
    assert png.stat().st_size > 10_000
    assert "<svg" in page.read_text()
    assert str(png) in capsys.readouterr().out


@pytest.mark.once  # the workers are processes of their own: see the marker
def test_a_sweep_on_two_dask_workers_equals_the_serial_run_row_for_row():
    sweep = Sweep(
        "scenes.tools.examples:payload_following_error",
        grid={"friction_n": [5.0, 15.0, 30.0, 60.0]},
        random={"payload_kg": (0.0, 40.0)},
        samples=50,
        seed=7,
    )
    serial = sweep.run(workers=0)
    assert len(serial) == 200
    assert list(serial["run"]) == list(range(200))
    assert {"friction_n", "payload_kg", "seed", "version"} <= set(serial.columns)
    assert serial["peak_following_error_mm"].between(0.0, 1.0).all()
    # more payload, more following error: the sweep shows the physics
    heavy = serial[serial["payload_kg"] > 30]["peak_following_error_mm"].mean()
    light = serial[serial["payload_kg"] < 10]["peak_following_error_mm"].mean()
    assert heavy > light
    seen: list[tuple[int, int]] = []
    parallel = sweep.run(workers=2, progress=lambda done, failed: seen.append((done, failed)))
    assert parallel.equals(serial)
    assert seen == [(n, 0) for n in range(201)]  # each scenario as it came back


def test_sweep_files_are_checked_and_written(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('scenario = "scenes.tools.examples:payload_following_error"\nsampels = 3\n')
    with pytest.raises(UserError, match=r"bad.toml:2: sampels: unknown key; .*'samples'\?"):
        from_toml(bad)
    with pytest.raises(ValueError, match="module:function"):
        Sweep("payload_following_error")
    good = tmp_path / "good.toml"
    good.write_text(
        'scenario = "scenes.tools.examples:payload_following_error"\nseed = 3\nout = "r.parquet"\n'
        "workers = 0\n[grid]\npayload_kg = [0.0, 20.0]\n"
    )
    assert main(["sweep", str(good)]) == 0
    import pandas as pd

    table = pd.read_parquet(tmp_path / "r.parquet")
    assert list(table["payload_kg"]) == [0.0, 20.0]
    assert (tmp_path / "r_payload_kg.png").exists()


def test_home_homes_x_on_its_index_and_the_window_leaves_the_homing_out(scene):
    from scenes.tools.testing import home, max_following_error, run_until, window

    gantry = scene("gantry", start={"X": 0.3})
    took = home(gantry, "X")
    X = gantry.axes["X"]
    recipe = scenes.homing(gantry)["X"]
    # the physical origin of the homed coordinate is the index pulse above the REF edge
    lead = float(gantry.model.numeric("gantry/X_lead").data[0])
    edge = float(gantry.model.numeric("gantry/X_ref_edge").data[0])
    index = -(-edge // lead) * lead
    origin = gantry.joint_position("X") - (X.POS - recipe.set_position) / 1000.0
    assert 1.0 < took < 30.0
    assert X.state == mcl.AxisState.StandStill
    assert abs(origin - index) < 20e-6
    # a slow move after homing: its following error is smaller than the homing's
    power = mcl.MC_Power(Axis=X)
    move = mcl.MC_MoveAbsolute(Axis=X, Position=150.0, Velocity=20.0, Acceleration=500.0)
    moving = window(gantry, move)

    def program():
        power(Enable=True)
        move(Execute=power.Status)

    run_until(gantry, program, lambda: move.Done, timeout=5.0)
    gantry.run(program, timeout=0.2)
    assert moving.start is not None and moving.end is not None
    assert took <= moving.start < moving.end < gantry.time
    whole = max_following_error(gantry, "X")
    during = max_following_error(gantry, "X", during=moving)
    assert during == max_following_error(gantry, "X", during=(moving.start, moving.end))
    assert during < whole  # the homing's larger error is left out
    # the joint itself followed the set point that closely (ground truth of the trace)
    t, model = gantry.trace.column("X", "t"), gantry.trace.column("X", "model")
    truth = gantry.trace.column("X", "truth")
    physical = [
        abs(m - ((q - origin) * 1000.0 + recipe.set_position))
        for s, m, q in zip(t, model, truth, strict=True)
        if moving.start <= s <= moving.end
    ]
    assert max(physical) < during + 0.01
    with pytest.raises(AssertionError, match="no homing recipe for \\['Q'\\]"):
        home(gantry, "Q")


def test_sweep_plots_name_the_sweep_and_show_numbers_in_full():
    import pandas as pd

    from scenes.tools.plot import sweep_figure

    table = pd.DataFrame(
        {
            "speed": [1.0, 2.0, 3.0, 1.0, 2.0, 3.0],
            "slip": [0.0, 0.0, 0.0, -0.5, -0.5, -0.5],
            "length_mm": [110.001, 110.002, 110.003, 110.004, 110.005, 110.006],
        }
    )
    fig = sweep_figure(
        table, "speed", ["length_mm"], title="s:f (seed 3, 6 scenarios)", colour=["slip"]
    )
    (panel,) = fig.axes
    assert fig.get_suptitle() == "s:f (seed 3, 6 scenarios)"
    assert panel.yaxis.get_offset_text().get_text() == ""  # no "+1.1e2"
    assert all("110.00" in t.get_text() for t in panel.get_yticklabels() if t.get_text())
    legend = panel.get_legend()
    assert legend is not None and legend.get_title().get_text() == "slip"
