"""Benchmark: the cost of one PLC scan of each machine's demo in Structured Text
(examples/st/<machine>_demo.st, translated by plc.st) against its Python version.

Each demo runs from its demo start to its end; only the program's calls are timed (not the
servo cycles or the physics between them), so the figure is what the program itself costs per
scan. The ST and the Python demo run side by side, a PLC cycle of one then a PLC cycle of the
other, so that a burst of another process on a shared machine falls on both alike. Each pair
runs :data:`REPEATS` times; printed per machine: the median over the runs of µs per scan of the
ST demo, of the Python demo and of their ratio (target ≤ 1.2), every run's ratio, and the
ratio of the least cost of each scan over the runs (the demos are deterministic: scan n does
the same work in every run, so its least time is its cost without interruptions). As JSON per
mode (compiled where built, then pure Python, each in a fresh process).

The load times of a generated project of about 3000 lines (:func:`project`: stations of
a plant, each a FUNCTION_BLOCK with its enumeration and structure, and the PROGRAM that runs
them): its first load (an empty parse cache) with one parsing process and with one per CPU,
then a load with every POU in the cache (targets: ≤ 10 s on one core, ≤ 1 s cached); wall
and CPU time of this process (a shared machine's load inflates the wall time; the CPU time of
the parallel load leaves out its workers), and the load average. Then the same for a TwinCAT
project of 48 function blocks (:mod:`tests.benchmarks.st_twincat`: a motion station each, with
its DUTs, a GVL and the PROGRAM that runs them on the single axis): its first load and a
cached one, each in a fresh process (what a user's ``python -m scenes run`` pays).

Run: ``python -m tests.benchmarks.st`` (``--load``: the load times alone).
"""

from __future__ import annotations

import os
import statistics
import sys
import tempfile
import time
from typing import Any

from tests.benchmarks import report_in_both_modes

MACHINES = ("gantry", "flying_shear", "press")
"""The machines whose demos exist in ST."""
REPEATS = 5
"""Runs of each pair of demos."""


def side_by_side(machine: str) -> tuple[list[float], list[float]]:
    """Seconds of each PLC scan of the machine's ST demo and of its Python demo, run
    alternately one PLC cycle each, each to its end."""
    import scenes
    from tests.plc.st.test_demos import st_demo

    clock = time.perf_counter
    runs = []
    for st in (True, False):
        scene = scenes.load(machine, start=scenes.definition(machine).demo_start, trace_every=0)
        program: Any = st_demo(scene) if st else scenes.demo(scene)
        spent: list[float] = []

        def scan(program: Any = program, spent: list[float] = spent) -> None:
            start = clock()
            program()
            spent.append(clock() - start)

        runs.append((scene, program, scan, spent))
    period = runs[0][0].runtime.plc_period
    while not all(program.done or program.error for _, program, _, _ in runs):
        for scene, program, scan, _ in runs:
            if not (program.done or program.error):
                scene.run(scan, timeout=period)
    return runs[0][3], runs[1][3]


def report() -> dict[str, Any]:
    """Per machine: µs per scan of the ST and the Python demo (medians over the runs), their
    ratio, every run's ratio, and the ratio of the scans' least costs."""
    import mcl

    figures: dict[str, Any] = {"mode": "compiled" if mcl.COMPILED else "pure Python"}
    for machine in MACHINES:
        pairs = [side_by_side(machine) for _ in range(REPEATS)]
        st = [sum(s) / len(s) * 1e6 for s, _ in pairs]
        python = [sum(p) / len(p) * 1e6 for _, p in pairs]
        ratios = [s / p for s, p in zip(st, python, strict=True)]
        least_st = sum(min(scan) for scan in zip(*(s for s, _ in pairs), strict=True))
        least_python = sum(min(scan) for scan in zip(*(p for _, p in pairs), strict=True))
        figures[machine] = {
            "st_us_per_scan": round(statistics.median(st), 2),
            "python_us_per_scan": round(statistics.median(python), 2),
            "ratio": round(statistics.median(ratios), 3),
            "ratios": [round(r, 3) for r in ratios],
            "least_cost_ratio": round(least_st / least_python, 3),
        }
    return figures


STATION = """TYPE E_State{i} : (S{i}_Idle, S{i}_Starting, S{i}_Running, S{i}_Stopping,
                 S{i}_Faulted);
END_TYPE

TYPE ST_Data{i} :
STRUCT
  setpoint : LREAL;                 (* [mm] *)
  actual : LREAL;                   (* [mm] *)
  count : DINT;
  ok : BOOL;
END_STRUCT
END_TYPE

(* station {i}: starts on a rising Enable, runs until the filtered value settles *)
FUNCTION_BLOCK FB_Station{i}
VAR_INPUT
  Enable : BOOL;
  Setpoint : LREAL;
  Limit : LREAL := 100.0;
END_VAR
VAR_OUTPUT
  Done : BOOL;
  Error : BOOL;
  ErrorID : DINT;
END_VAR
VAR
  state : E_State{i};
  data : ST_Data{i};
  timer : TON;
  trigger : R_TRIG;
  history : ARRAY[1..10] OF LREAL;
  k : INT;
  sum : LREAL;
  filtered : LREAL;
END_VAR
trigger(CLK := Enable);
timer(IN := state = S{i}_Running, PT := T#200ms);
CASE state OF
  S{i}_Idle:
    Done := FALSE;
    IF trigger.Q THEN
      data.setpoint := LIMIT(0.0, Setpoint, Limit);
      data.count := 0;
      state := S{i}_Starting;
    END_IF
  S{i}_Starting:
    IF Setpoint > Limit THEN
      Error := TRUE;
      ErrorID := 16#100 + {i};
      state := S{i}_Faulted;
    ELSE
      state := S{i}_Running;
    END_IF
  S{i}_Running:
    data.actual := data.actual + (data.setpoint - data.actual) * 0.1;
    data.count := data.count + 1;
    IF ABS(data.setpoint - data.actual) < 0.01 OR timer.Q THEN
      state := S{i}_Stopping;
    END_IF
  S{i}_Stopping:
    data.ok := ABS(data.setpoint - data.actual) < 0.01;
    Done := TRUE;
    state := S{i}_Idle;
  S{i}_Faulted:
    IF NOT Enable THEN
      Error := FALSE;
      ErrorID := 0;
      state := S{i}_Idle;
    END_IF
END_CASE
FOR k := 1 TO 9 DO
  history[k] := history[k + 1];
END_FOR
history[10] := data.actual;
sum := 0.0;
FOR k := 1 TO 10 DO
  sum := sum + history[k];
END_FOR
filtered := sum / 10.0;
IF filtered > Limit THEN
  Error := TRUE;
  ErrorID := 16#200 + {i};
END_IF
END_FUNCTION_BLOCK

"""


def project(lines: int = 3000) -> str:
    """An ST project of about ``lines`` lines: stations (each a FUNCTION_BLOCK with its
    enumeration and structure) and the PROGRAM that enables them one after the other."""
    count = max(1, lines // (STATION.count("\n") + 4))
    stations = "".join(STATION.format(i=i) for i in range(count))
    instances = "".join(f"  station{i} : FB_Station{i};\n" for i in range(count))
    calls = "".join(
        f"station{i}(Enable := active = {i}, Setpoint := 10.0 + {i});\n"
        f"IF station{i}.Done THEN active := {i + 1}; END_IF\n"
        for i in range(count)
    )
    program = (
        f"PROGRAM Plant\nVAR\n{instances}  active : INT;\n  done : BOOL;\nEND_VAR\n"
        f"{calls}done := active >= {count};\nEND_PROGRAM\n"
    )
    return stations + program


def load_times() -> dict[str, Any]:
    """Seconds to load :func:`project` (parse and translate): its first load with one parsing
    process and with one per CPU, and a load from the parse cache."""
    import plc.st
    from plc.st.frontend import parse

    source = project()
    figures: dict[str, Any] = {"lines": source.count("\n"), "cpus": parse.jobs()}
    with tempfile.TemporaryDirectory() as folder:
        for label, jobs in (("first_load_1_process_s", 1), ("first_load_parallel_s", 0)):
            os.environ["MCL_ST_CACHE"] = os.path.join(folder, label)
            os.environ["MCL_ST_JOBS"] = str(jobs) if jobs else ""
            start, cpu = time.perf_counter(), time.process_time()
            plc.st.from_source(source, filename="plant.st", period=0.01)
            figures[label] = round(time.perf_counter() - start, 2)
            figures[label.replace("_s", "_cpu_s")] = round(time.process_time() - cpu, 2)
        start, cpu = time.perf_counter(), time.process_time()
        prog = plc.st.from_source(source, filename="plant.st", period=0.01)
        figures["cached_load_s"] = round(time.perf_counter() - start, 2)
        figures["cached_load_cpu_s"] = round(time.process_time() - cpu, 2)
    figures["load_average"] = round(os.getloadavg()[0], 1)
    for _ in range(100):
        prog()
    figures["runs"] = not prog.fault
    figures["twincat_48_blocks"] = twincat_load_times()
    return figures


TIMED_LOAD = """
import json, sys, time
from pathlib import Path
import plc.st, scenes
scene = scenes.load("single_axis", trace_every=0)
start, cpu = time.perf_counter(), time.process_time()
prog = plc.st.load(Path(sys.argv[1]), scene)
wall, cpu = time.perf_counter() - start, time.process_time() - cpu
for _ in range(10):
    prog()
print(json.dumps([wall, cpu, not prog.fault]))
"""
"""A load of the project in the folder ``argv[1]`` in a fresh process: wall and CPU seconds,
and whether it then runs."""


def twincat_load_times() -> dict[str, Any]:
    """Seconds to load the TwinCAT project of :mod:`tests.benchmarks.st_twincat` in a fresh
    process (parse, translate, compile, with the scene made first): its first load (one
    parsing process, an empty parse cache) and a cached load, wall and CPU."""
    import json
    import subprocess
    from pathlib import Path

    from tests.benchmarks.st_twincat import write_project

    root = str(Path(__file__).resolve().parents[2])
    figures: dict[str, Any] = {}
    with tempfile.TemporaryDirectory() as folder:
        project = Path(folder) / "Plant"
        figures["lines"] = write_project(project)
        env = {**os.environ, "MCL_ST_CACHE": os.path.join(folder, "cache"), "MCL_ST_JOBS": "1"}
        env["PYTHONPATH"] = os.pathsep.join([root, os.environ.get("PYTHONPATH", "")])
        for label in ("first_load", "cached_load"):
            command = [sys.executable, "-c", TIMED_LOAD, str(project)]
            out = subprocess.run(command, env=env, capture_output=True, text=True, check=True)
            wall, cpu, runs = json.loads(out.stdout.strip().splitlines()[-1])
            figures[f"{label}_s"], figures[f"{label}_cpu_s"] = round(wall, 2), round(cpu, 2)
            figures["runs"] = runs
    figures["load_average"] = round(os.getloadavg()[0], 1)
    return figures


if __name__ == "__main__":
    if "--load" in sys.argv:
        import json

        print(json.dumps(load_times(), indent=2))
    else:
        report_in_both_modes("tests.benchmarks.st", report)
