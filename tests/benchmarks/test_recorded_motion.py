"""The recorded-motion tool: how far a recording's grip site moves a step, before and after
the episode first succeeds (why a slower mode loses a recording that sweeps on)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from benchmarks.recorded_motion import main
from unified_manip.datasets.policies import scripted
from unified_manip.datasets.recording import collect
from unified_manip.datasets.store import open_dataset


def test_the_grip_site_read_from_the_states_moves_as_the_recorded_reach_goal(tmp_path):
    """On Arm4Reach the achieved goal is the grip site, so its recorded observations give
    the same moves as the restored states (float32 observations: within 1e-4 cm)."""
    path = tmp_path / "reach-v0"
    config = {"action_mode": "ee_delta", "reward_type": "sparse"}
    collect("UnifiedManip/Arm4Reach-v0", config, scripted, "scripted", "scripted", 2, path, seed=0)
    main([str(path), "--json", str(tmp_path / "m.json")])
    rows = json.loads((tmp_path / "m.json").read_text())["reach-v0"]["episodes"]
    for ep, row in zip(open_dataset(path).iterate_episodes(), rows, strict=True):
        goal = np.asarray(ep.observations["achieved_goal"], dtype=np.float64)
        moves = np.linalg.norm(np.diff(goal, axis=0), axis=1) * 100.0
        first = int(np.flatnonzero(np.asarray(ep.infos["is_success"]) > 0.5)[0])
        assert row["first_success"] == first < row["steps"] == len(moves)
        assert row["max_cm_before"] == pytest.approx(moves[:first].max(), abs=1e-4)
        assert row["max_cm_after"] == pytest.approx(moves[first:].max(), abs=1e-4)
        assert row["max_cm_before"] > 0


def test_a_missing_dataset_is_one_line_and_exit_2(tmp_path, capsys):
    with pytest.raises(SystemExit) as exit_:
        main([str(tmp_path / "none-v0"), "--json", str(tmp_path / "m.json")])
    assert exit_.value.code == 2
    assert (
        capsys.readouterr()
        .err.splitlines()[-1]
        .endswith(f"no dataset at {tmp_path / 'none-v0'}; expected a directory written by collect or convert")
    )
    assert not (tmp_path / "m.json").exists()
