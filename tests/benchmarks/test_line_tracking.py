"""``benchmarks.line_tracking``: a held end-effector action moves the hand along its axis,
and a mode the task lacks is refused in one line."""

from __future__ import annotations

import json

import pytest

from benchmarks.line_tracking import main


def test_a_held_action_moves_the_hand_along_its_axis(tmp_path, capsys):
    """On Arm4Reach-v0, five full ee_target_delta steps on each axis then five zero steps:
    the hand moves over 5 cm along the axis and under a tenth of that off it, and the table
    and JSON give every axis."""
    out = tmp_path / "lines.json"
    main(["--env", "UnifiedManip/Arm4Reach-v0", "--modes", "ee_target_delta", "--steps", "5", "--settle", "5",
          "--json", str(out)])  # fmt: skip
    rows = json.loads(out.read_text())["rows"]
    assert [r["axis"] for r in rows] == ["+x", "+y", "-z"]
    assert all(r["held_along_m"] > 0.05 and r["held_off_m"] < 0.1 * r["held_along_m"] for r in rows), rows
    assert capsys.readouterr().out.count("| Arm4Reach-v0 | `ee_target_delta` |") == 3


def test_a_mode_the_task_lacks_is_one_line(capsys):
    with pytest.raises(SystemExit) as done:
        main(["--env", "UnifiedManip/FetchReach-v0", "--modes", "joint_wobble"])
    assert done.value.code == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("python -m benchmarks.line_tracking: error: UnifiedManip/FetchReach-v0 has no action_mode ")
