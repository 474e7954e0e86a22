"""The tools for users' scenario tests and studies: the pytest plugin, trace plots, sweeps."""

from __future__ import annotations

import pytest

import mcl
import scenes
from scenes.__main__ import main
from scenes.errors import UserError
from scenes.sweep import Sweep, from_toml

pytest_plugins = ["pytester"]


def test_a_failing_scenario_test_writes_the_plot_of_its_trace(pytester: pytest.Pytester):
    pytester.makepyfile(
        """
        import mcl
        from scenes.testing import run_until

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


def test_run_until_says_why_a_condition_was_not_met():
    from scenes.testing import run_until

    machine = scenes.load("single_axis")
    with pytest.raises(AssertionError, match=r"within 0.1 s .*X: Disabled"):
        run_until(machine, None, lambda: False, timeout=0.1)


def test_a_pulse_of_two_scans_is_not_one(scans):
    from scenes.testing import assert_pulsed_once

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


def test_a_sweep_on_two_dask_workers_equals_the_serial_run_row_for_row():
    sweep = Sweep(
        "scenes.examples:payload_following_error",
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
    parallel = sweep.run(workers=2)
    assert parallel.equals(serial)


def test_sweep_files_are_checked_and_written(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('scenario = "scenes.examples:payload_following_error"\nsampels = 3\n')
    with pytest.raises(UserError, match=r"bad.toml:2: sampels: unknown key; .*'samples'\?"):
        from_toml(bad)
    with pytest.raises(ValueError, match="module:function"):
        Sweep("payload_following_error")
    good = tmp_path / "good.toml"
    good.write_text(
        'scenario = "scenes.examples:payload_following_error"\nseed = 3\nout = "r.parquet"\n'
        "workers = 0\n[grid]\npayload_kg = [0.0, 20.0]\n"
    )
    assert main(["sweep", str(good)]) == 0
    import pandas as pd

    table = pd.read_parquet(tmp_path / "r.parquet")
    assert list(table["payload_kg"]) == [0.0, 20.0]
    assert (tmp_path / "r_payload_kg.png").exists()
