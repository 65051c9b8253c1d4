"""``convert`` into the mode a dataset was recorded in: the recorded actions are played
again, so the episodes stay the same, seen through another observation design or played
on another version of the task."""

from __future__ import annotations

import numpy as np
import pytest

from unified_manip.datasets import DatasetError
from unified_manip.datasets.convert import convert
from unified_manip.datasets.policies import scripted
from unified_manip.datasets.recording import collect
from unified_manip.datasets.store import metadata, open_dataset


def _collect(task_id: str, mode: str, episodes: int, path):
    kwargs = {"action_mode": mode, "reward_type": "sparse"}
    collect(task_id, kwargs, scripted, "scripted", "scripted", episodes, path, only_successful=True, progress=False)
    return path


def _same_episodes(a, b) -> list[tuple]:
    """Per episode pair: whether the actions, the simulator states and the rewards are
    equal, and both observation shapes."""
    return [
        (
            np.array_equal(ea.actions, eb.actions),
            np.array_equal(ea.infos["state"], eb.infos["state"]),
            np.array_equal(ea.rewards, eb.rewards),
            ea.observations["observation"].shape[1],
            eb.observations["observation"].shape[1],
        )
        for ea, eb in zip(a.iterate_episodes(), b.iterate_episodes(), strict=True)
    ]


def test_into_its_own_mode_a_dataset_replays_its_actions_in_another_observation_design(tmp_path):
    source = _collect("UnifiedManip/Arm4Reach-v0", "joint_delta", 2, tmp_path / "reach-joint-v0")
    report = convert(
        source, "joint_delta", tmp_path / "reach-full-v0", observation="full", method="track", progress=False
    )
    assert [(e.replayed_by, e.kept, e.tracking_error_max_cm) for e in report.episodes] == [("recorded", True, 0.0)] * 2
    a, b = open_dataset(source), open_dataset(tmp_path / "reach-full-v0")
    default, full = (d.observation_space["observation"].shape[0] for d in (a, b))
    assert default < full
    assert _same_episodes(a, b) == [(True, True, True, default, full)] * 2
    assert metadata(b)["env_kwargs"]["observation"] == "full"


def test_an_unknown_env_for_convert_names_the_close_ids(tmp_path):
    source = _collect("UnifiedManip/Arm4Reach-v0", "joint_delta", 1, tmp_path / "reach-joint-v0")
    with pytest.raises(DatasetError, match=r"^convert --env: unknown task 'UnifiedManip/Arm4Reach-v9'; did you mean"):
        convert(source, "joint_delta", None, env_id="UnifiedManip/Arm4Reach-v9", method="track", progress=False)


@pytest.mark.metaworld  # Meta-World on MuJoCo 3.3.0 (CI's second leg)
def test_a_metaworld_v1_dataset_plays_on_v2_as_the_same_episodes_with_the_joints_observed(tmp_path):
    """v2 changed only the joint modes' observation (the robot's joints appended): a v1
    recording converted into v2 in its own mode is the same episode, step for step, with
    v1's observation as the first 36 numbers of v2's."""
    source = _collect("UnifiedManip/MetaWorldReach-v1", "joint_delta", 1, tmp_path / "reach-v1-v0")
    out = tmp_path / "reach-v2-v0"
    report = convert(
        source, "joint_delta", out, env_id="UnifiedManip/MetaWorldReach-v2", method="track", progress=False
    )
    assert [(e.replayed_by, e.kept) for e in report.episodes] == [("recorded", True)]
    a, b = open_dataset(source), open_dataset(out)
    assert metadata(b)["env_id"] == "UnifiedManip/MetaWorldReach-v2"
    assert _same_episodes(a, b) == [(True, True, True, 36, 54)]
    (ea,), (eb,) = a.iterate_episodes(), b.iterate_episodes()
    np.testing.assert_array_equal(ea.observations["observation"], eb.observations["observation"][:, :36])
