"""The benchmark table: targets from the grid, steps and wall time to them, met or missed."""

from __future__ import annotations

import pytest

from unified_manip.experiments.targets import Target, TargetError, benchmark_table, parse_targets, steps_to


def _row(seed: int, curve, wall: float = 3600.0, steps: int = 1000, mode: str = "ee_delta") -> dict:
    return {
        "task": "UnifiedManip/Arm4Push-v0",
        "action_mode": mode,
        "algo": "sac_her",
        "reward_type": "sparse",
        "seed": seed,
        "steps": steps,
        "final_success_rate": curve[-1][1],
        "curve": curve,
        "wall_time_s": wall,
        "steps_per_s": steps / wall,
    }


def test_steps_to_is_the_first_evaluation_reaching_the_threshold():
    curve = [[100, 0.2], [200, 0.95], [300, 0.85], [400, 1.0]]
    assert steps_to(curve, 0.9) == 200
    assert steps_to(curve, 0.99) == 400
    assert steps_to(curve, 1.01) is None


def test_table_marks_targets_and_scales_wall_time_by_the_steps_fraction():
    rows = [_row(0, [[500, 0.5], [1000, 0.9]]), _row(1, [[500, 0.92], [1000, 0.96]], wall=7200.0)]
    targets = (Target("UnifiedManip/Arm4Push-v0", "ee_delta", 0.9), Target("UnifiedManip/Lift-v0", "ee_delta", 0.9))
    lines = benchmark_table(rows, targets)
    row = next(line for line in lines if line.startswith("| Arm4Push"))
    cells = [c.strip() for c in row.strip("|").split("|")]
    assert cells[:6] == ["Arm4Push-v0", "ee_delta", "sac_her", "sparse", "1,000", "2"]
    assert cells[6] == "0.93 [0.90, 0.96] (range of 2 seeds)" and cells[7] == "0.90" and cells[8] == "**yes**"
    assert cells[9] == "1,000, 500"  # seed 0 reaches 0.9 at its last point, seed 1 at 500
    assert cells[10] == "1.00 h, 1.00 h"  # 3600 s x 1000/1000 and 7200 s x 500/1000
    lift = next(line for line in lines if line.startswith("| Lift"))
    assert "not run yet" in lift  # a target with no finished run is listed, never dropped


def test_a_missed_target_is_marked_no():
    lines = benchmark_table([_row(0, [[1000, 0.4]])], (Target("UnifiedManip/Arm4Push-v0", "ee_delta", 0.9),))
    cells = [c.strip() for c in lines[2].strip("|").split("|")]
    assert cells[6] == "0.40" and cells[8] == "no" and cells[9] == "—"


def test_a_mean_equal_to_the_target_is_met_despite_float_rounding():
    # 0.96, 0.90 and 0.84 average to 0.8999999999999999 in floats: shown as 0.90, and met.
    target = (Target("UnifiedManip/Arm4Push-v0", "ee_delta", 0.9),)
    rows = [_row(seed, [[1000, final]]) for seed, final in enumerate([0.96, 0.90, 0.84])]
    lines = benchmark_table(rows, target)
    cells = [c.strip() for c in lines[2].strip("|").split("|")]
    assert cells[6] == "0.90 [0.84, 0.96] (range of 3 seeds)" and cells[8] == "**yes**"
    just_below = benchmark_table([_row(0, [[1000, 0.88]])], target)
    assert [c.strip() for c in just_below[2].strip("|").split("|")][8] == "no"


@pytest.mark.parametrize(
    "value,message",
    [
        ({"task": "x"}, "targets must be a list of mappings with keys task, action_mode, success"),
        ([{"task": "x", "action_mode": "ee_delta"}], "targets must be a list of mappings"),
        (
            [{"task": "x", "action_mode": "ee_delta", "success": 1.5}],
            r"target success must be a number in \(0, 1\], got 1.5",
        ),
    ],
)
def test_malformed_targets_are_refused(value, message):
    with pytest.raises(TargetError, match=message):
        parse_targets(value, "grid.yaml")
