"""The conversion table (issue 39): recorded scripted episodes re-executed in each mode,
reported per task and mode, with the modes that cannot be converted into named and why."""

from __future__ import annotations

import json
import re

import pytest

from benchmarks.conversion_table import main, markdown, measure, overview
from unified_manip.datasets import DatasetError


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
        "grip-site trajectory | | | | — | |"
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


def test_a_recording_translated_live_into_another_mode_is_converted_from_that_mode(tmp_path):
    """``source``: Meta-World's servoed modes cannot follow its ``native`` recordings, so its
    rows are recorded in a servoed mode, the scripted actions translated live."""
    row = measure("UnifiedManip/Arm4Reach-v0", 2, tmp_path, modes=["joint_delta"], source="ee_target_delta")
    assert row["source"] == row["recorded"]["env_kwargs"]["action_mode"] == "ee_target_delta"
    assert (tmp_path / "Arm4Reach-v0-ee_target_delta-v0").is_dir()
    assert not (tmp_path / "Arm4Reach-v0-ee_delta-v0").exists()
    assert (row["modes"]["joint_delta"]["success"], row["modes"]["joint_delta"]["episodes"]) == (2, 2)
    assert overview({"UnifiedManip/Arm4Reach-v0": row}).splitlines()[-1] == (
        "| Arm4Reach-v0 (in `ee_target_delta`) | 2 of 2 | 1.00 (1.00) |"
    )


def test_each_mode_says_why_it_lost_the_episodes_it_did_not_keep(tmp_path):
    """Arm4Push's seed 6 in ``joint_torque``: the grip site stays on the recorded path, but
    the cube ends short of the goal (as ``convert --keep-failed``'s test shows)."""
    row = measure("UnifiedManip/Arm4Push-v0", 2, tmp_path, seed=5, modes=["joint_torque"], translated=False)
    cell = row["modes"]["joint_torque"]
    assert (cell["success"], cell["lost_on_path"], cell["lost_off_path_at"]) == (1, 1, [])


@pytest.mark.parametrize(
    "args, message",
    [
        (["--episodes", "0"], "--episodes: expected a positive integer, got 0"),
        (
            ["--env", "UnifiedManip/Nope-v0"],
            "unknown task 'UnifiedManip/Nope-v0'; expected one of UnifiedManip/Arm4Reach-v0",
        ),
        (
            ["--modes", "ee_pose"],
            "UnifiedManip/Arm4Reach-v0 has no action_mode 'ee_pose'; expected one of joint_torque",
        ),
        (["--env", "UnifiedManip/HandReach-v0"], "UnifiedManip/HandReach-v0 has no scripted policy"),
        (
            ["--source", "ee_pose"],
            "UnifiedManip/Arm4Reach-v0 has no action_mode 'ee_pose'; expected one of joint_torque",
        ),
    ],
)
def test_bad_input_is_one_line_and_exit_2(tmp_path, capsys, args, message):
    base = {"--env": "UnifiedManip/Arm4Reach-v0", "--episodes": "1", "--out": str(tmp_path / "rec")}
    base.update(dict(zip(args[::2], args[1::2])))
    with pytest.raises(SystemExit) as exit_:
        main([*(x for kv in base.items() for x in kv), "--json", str(tmp_path / "t.json"), "--no-progress"])
    assert exit_.value.code == 2
    assert message in capsys.readouterr().err.splitlines()[-1]
    assert not (tmp_path / "t.json").exists()


def test_the_command_reports_each_mode_and_writes_its_json_whole(tmp_path, capsys):
    out = tmp_path / "t.json"
    main(
        ["--env", "UnifiedManip/Arm4Reach-v0", "--episodes", "1", "--modes", "joint_delta,ee_delta"]
        + ["--out", str(tmp_path / "rec"), "--json", str(out), "--no-translated"]
    )
    captured = capsys.readouterr()
    assert "UnifiedManip/Arm4Reach-v0 joint_delta: 1/1 converted" in captured.err
    assert "UnifiedManip/Arm4Reach-v0 ee_delta: 1/1 converted" in captured.err
    assert captured.out.startswith("| task | recorded: successful of played | `joint_delta` | `ee_delta` |")
    written = json.loads(out.read_text())
    assert list(written["UnifiedManip/Arm4Reach-v0"]["modes"]) == ["joint_delta", "ee_delta"]
    assert [p.name for p in tmp_path.iterdir() if p.suffix == ".tmp"] == []


def test_what_kept_the_episodes_is_listed_in_the_order_the_tries_run():
    """The search, its lockstep, its lead-weighted retries (the larger weight first, as
    they run), then the open-loop guesses, whatever order the episodes came in."""
    row = {
        "success": 7,
        "episodes": 10,
        "kept_by": {"translated": 1, "search, lead 0.00015": 2, "search": 3, "search, lead 0.0005": 1},
        "tracking_error_mean_cm": 0.5,
        "tracking_error_max_cm": 4.0,
        "translated_success": 9,
        "seconds": 12.0,
    }
    line = markdown({"UnifiedManip/MetaWorldPush-v1": {"modes": {"joint_target_delta": row}}}).splitlines()[-1]
    assert line == (
        "| UnifiedManip/MetaWorldPush-v1 | joint_target_delta | 7/10 (0.70) | search 3; search, lead 0.0005 1; "
        "search, lead 0.00015 2; translated 1 | 0.50 | 4.00 | 9/10 | 12 s |"
    )
