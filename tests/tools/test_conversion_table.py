"""The conversion table (issue 39): recorded scripted episodes re-executed in each mode,
reported per task and mode, with the modes that cannot be converted into named and why."""

from __future__ import annotations

import re

import pytest

from unified_manip.datasets import DatasetError
from unified_manip.tools.conversion_table import markdown, measure, overview


def test_the_arm_converts_every_episode_and_fetch_refuses_its_own_controller(tmp_path):
    arm = measure("UnifiedManip/Arm4Reach-v0", 2, tmp_path, modes=["joint_delta", "ee_target_delta"])
    fetch = measure("UnifiedManip/FetchReach-v0", 2, tmp_path, modes=["native"], translated=False)
    results = {"UnifiedManip/Arm4Reach-v0": arm, "UnifiedManip/FetchReach-v0": fetch}

    assert arm["recorded"]["episodes_played"] == 2 and arm["recorded"]["dropped_episodes"] == 0
    for mode in ("joint_delta", "ee_target_delta"):
        row = arm["modes"][mode]
        assert (row["success"], row["episodes"], row["translated_success"]) == (2, 2, 2)
        assert 0 <= row["tracking_error_mean_cm"] <= row["tracking_error_max_cm"]
    assert overview(results).splitlines() == [
        "| task | recorded: successful of played | `joint_delta` | `ee_target_delta` | `native` |",
        "|---|---:|---:|---:|---:|",
        "| Arm4Reach-v0 | 2 of 2 | 1.00 (1.00) | 1.00 (1.00) |  |",
        "| FetchReach-v0 | 2 of 2 |  |  | — |",
    ]
    refused = markdown(results).splitlines()[-1]
    assert refused == (
        "| UnifiedManip/FetchReach-v0 | native | — the source's own controller, which cannot track a "
        "grip-site trajectory | | | — |"
    )


def test_each_version_of_a_task_is_recorded_on_its_own(tmp_path):
    """Arm4Push-v0 and -v1 share a spec name; the second must not reuse the first's episodes."""
    v0 = measure("UnifiedManip/Arm4Push-v0", 1, tmp_path, modes=["ee_target_delta"], translated=False)
    v1 = measure("UnifiedManip/Arm4Push-v1", 1, tmp_path, modes=["ee_target_delta"], translated=False)
    assert (v0["recorded"]["env_id"], v1["recorded"]["env_id"]) == (
        "UnifiedManip/Arm4Push-v0",
        "UnifiedManip/Arm4Push-v1",
    )
    # Without the live translation a cell is the converted share alone.
    assert re.fullmatch(
        r"\| Arm4Push-v0 \| 1 of \d+ \| [01]\.\d\d \|", overview({"UnifiedManip/Arm4Push-v0": v0}).splitlines()[-1]
    )
    (tmp_path / "Arm4Push-v0-ee_delta-v0").rename(tmp_path / "Arm4Reach-v0-ee_delta-v0")
    with pytest.raises(
        DatasetError, match=r"Arm4Reach-v0-ee_delta-v0 holds episodes of UnifiedManip/Arm4Push-v0, not of "
    ):
        measure("UnifiedManip/Arm4Reach-v0", 1, tmp_path, modes=["ee_target_delta"], translated=False)
