"""Benchmark: the force on the block after homing to block and after GT_MoveAbsBlock's
TorqueLimit on the MuJoCo gantry (goal: below 5 % of the amplifier's force limit from 0.5 s
after running into the block on).

Prints JSON: per case how long after running into the block the force on it was last at or
above 5 % of the force limit [ms], the force limit, the peak force while pushing (the impact
included) and the force on the block 0.5 s, 10 s and 20 s after the axis ran into it [N], and
the largest force from 0.5 s on.
Run: ``python -m tests.benchmarks.block_homing``.
"""

from __future__ import annotations

import json

from tests.mcl.test_block_homing import (
    RELEASED_AFTER,
    SHARE,
    BlockRun,
    home_to_block,
    move_to_obstacle,
)


def figures(run: BlockRun) -> dict[str, float]:
    """The forces of one run [N]."""
    hit, log = run.hit(), run.log
    level = SHARE * run.fmax
    last = max(t for t, f in zip(log.times, log.forces, strict=True) if f >= level)
    return {
        "below_5_percent_after_ms": round((last - hit) * 1e3, 1),
        "force_limit_N": round(run.fmax, 1),
        "pushing_peak_N": round(log.peak(until=hit + RELEASED_AFTER), 1),
        "at_0.5s_N": round(log.at(hit + 0.5), 1),
        "at_10s_N": round(log.at(hit + 10.0), 1),
        "at_20s_N": round(log.at(hit + 20.0), 1),
        "max_from_0.5s_N": round(log.peak(since=hit + RELEASED_AFTER), 1),
    }


def block_forces() -> dict[str, dict[str, float]]:
    """Every case of tests/mcl/test_block_homing.py."""
    return {
        "StepBlock+StepDirect X-": figures(home_to_block("X", -1)),
        "StepBlock, then StepDirect X-": figures(home_to_block("X", -1, buffered=False)),
        "StepBlock+StepDirect X+": figures(home_to_block("X", +1)),
        "StepBlock+StepDirect Z- (down)": figures(home_to_block("Z", -1)),
        "StepBlock+StepDirect Z+ (up)": figures(home_to_block("Z", +1)),
        "GT_MoveAbsBlock X+ obstacle": figures(move_to_obstacle(+1)),
        "GT_MoveAbsBlock X- obstacle": figures(move_to_obstacle(-1)),
    }


def main() -> None:
    print(json.dumps(block_forces(), indent=1))


if __name__ == "__main__":
    main()
