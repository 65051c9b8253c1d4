"""The headline table of a cross-task study against a hand-made experiment, and the
README's copy of the committed one."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml
from test_aggregates import _row as _curve_row  # this folder is on sys.path

from unified_manip.experiments.headline import headline_table, readme_block
from unified_manip.experiments.results import write_results

ROOT = Path(__file__).resolve().parents[2]
ARM, FETCH = "UnifiedManip/Arm4Reach-v0", "UnifiedManip/FetchReach-v0"


def _row(task: str, mode: str, seed: int, final: float, demos: int = 100) -> dict:
    row = _curve_row(task, mode, seed, [[500, 0.0], [1000, final]])
    return {**row, "wall_time_s": 360.0, "demonstrations": json.dumps({"episodes": demos})}


def _experiment(
    tmp_path: Path, rows: list[dict], tasks=(ARM, FETCH), modes=("joint_torque", "joint_delta", "ee_delta")
) -> Path:
    grid = {
        "name": "tiny",
        "tasks": list(tasks),
        "action_modes": list(modes),
        "reward_types": ["sparse"],
        "algos": ["tqc_her"],
        "seeds": [0, 1, 2],
        "steps": 1000,
    }
    (tmp_path / "grid.yaml").write_text(yaml.safe_dump(grid))
    write_results(tmp_path, rows)
    return tmp_path


def _cells(table: str) -> dict[str, list[str]]:
    lines = [line for line in table.splitlines() if line.startswith("| `")]
    return {line.split("|")[1].strip(" `"): [c.strip() for c in line.split("|")[2:-1]] for line in lines}


def test_the_headline_of_an_unfinished_grid_says_what_finished_and_marks_missing_cells(tmp_path):
    rows = [_row(ARM, "ee_delta", s, f) for s, f in enumerate([0.9, 0.95, 1.0])]
    rows += [_row(FETCH, "ee_delta", 0, 1.0)]
    rows += [_row(ARM, "joint_delta", s, f) for s, f in enumerate([0.0, 0.4])]
    rows += [_row(FETCH, "joint_delta", s, 0.5, demos=0) for s in range(2)]
    rows += [_row(ARM, "joint_torque", 0, 0.1)]
    table = headline_table(_experiment(tmp_path, rows))
    assert table.startswith("9 of 18 runs, 0.9 core-hours so far")
    assert "| action mode | Arm4Reach-v0 | FetchReach-v0 | IQM, all 2 tasks |" in table
    # Rows in the registry's order of modes; IQM over the same runs per task (the fewest):
    # ee_delta (0.9, 1.0) -> 0.95; joint_delta (0.0, 0.4, 0.5, 0.5) trimmed to 0.4, 0.5 -> 0.45.
    assert _cells(table) == {
        "joint_torque": ["0.10 (1 seed)", "–", "–"],
        "joint_delta": ["0.20 [0.00, 0.40] (2 seeds)", "0.50 [0.50, 0.50] (2 seeds)†", "0.45 [—]"],
        "ee_delta": ["0.95 [0.90, 1.00]", "1.00 (1 seed)", "0.95 [—]"],
    }
    assert list(_cells(table)) == ["joint_torque", "joint_delta", "ee_delta"]


def test_with_two_runs_of_every_mode_on_every_task_the_aggregate_gets_its_interval(tmp_path):
    rows = [
        _row(t, m, s, f) for t in (ARM, FETCH) for m in ("joint_delta", "ee_delta") for s, f in enumerate([0.2, 0.8])
    ]
    cells = _cells(headline_table(_experiment(tmp_path, rows)))
    point, interval = cells["ee_delta"][-1].split(" ", 1)
    low, high = (float(v) for v in interval.strip("[]").split(", "))
    assert float(point) == pytest.approx(0.5) and 0.2 <= low < 0.5 < high <= 0.8
    assert cells["joint_torque"] == ["–", "–", "–"]


def test_with_more_tasks_than_modes_the_table_has_a_row_per_task_and_the_iqm_last(tmp_path):
    tasks = (ARM, FETCH, "UnifiedManip/Arm4Push-v0")
    rows = [_row(ARM, "ee_delta", 0, 0.9), _row(FETCH, "joint_delta", 1, 0.3, demos=0)]
    table = headline_table(_experiment(tmp_path, rows, tasks=tasks, modes=("joint_delta", "ee_delta")))
    lines = table.splitlines()
    assert lines[2:4] == ["| task | `joint_delta` | `ee_delta` |", "|---|---|---|"]
    assert lines[4:8] == [
        "| Arm4Reach-v0 | – | 0.90 (1 seed) |",
        "| FetchReach-v0 | 0.30 (1 seed)† | – |",
        "| Arm4Push-v0 | – | – |",
        "| IQM, all 3 tasks | – | – |",
    ]


def test_a_headline_needs_one_algorithm_and_reward(tmp_path):
    rows = [_row(ARM, "ee_delta", 0, 0.5), {**_row(ARM, "ee_delta", 1, 0.5), "reward_type": "dense"}]
    with pytest.raises(ValueError, match="one algorithm and reward"):
        headline_table(_experiment(tmp_path, rows))


@pytest.mark.robosuite  # loading the grid builds a Lift backend per observation design (check_design)
def test_the_readme_holds_the_families_headline_of_the_committed_results(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # as in a clean clone: no demonstration datasets under data/
    assert readme_block(ROOT / "results" / "action_spaces_families") in (ROOT / "README.md").read_text()
