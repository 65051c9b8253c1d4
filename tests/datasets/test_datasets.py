"""collect -> minari.load_dataset -> recover_environment, exact replay, and convert, on
real envs of every family (a few short episodes each)."""

from __future__ import annotations

import os
import warnings

import h5py
import minari
import numpy as np
import pytest
from conftest import extra_marks

from unified_manip.datasets import store, versions
from unified_manip.datasets.convert import convert
from unified_manip.datasets.policies import RandomPolicy, scripted
from unified_manip.datasets.recording import collect
from unified_manip.datasets.replay import replay

#: One ID per family: (ID, action mode, policy). The Shadow Hand has no scripted policy.
FAMILIES = {
    "arm4": ("UnifiedManip/Arm4PickAndPlace-v0", "ee_delta", "scripted"),
    "fetch": ("UnifiedManip/FetchPickAndPlace-v0", "ee_delta", "scripted"),
    "shadow_hand": ("UnifiedManip/HandReach-v0", "joint_delta", "random"),
    "robosuite": ("UnifiedManip/Lift-v0", "ee_delta", "scripted"),
}
#: The families as parameters, robosuite's with its extra's marker.
FAMILY_PARAMS = [pytest.param(f, marks=extra_marks(task_id)) for f, (task_id, _, _) in FAMILIES.items()]
POLICIES = {"scripted": scripted, "random": RandomPolicy}
EPISODES = 2


class _Recorded(dict):
    """``family -> dataset path``: two episodes of a family, recorded on first use."""

    def __init__(self, root):
        super().__init__()
        self.root = root

    def __missing__(self, family: str):
        task_id, mode, policy = FAMILIES[family]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            collect(
                task_id,
                {"action_mode": mode, "reward_type": "dense"},
                POLICIES[policy],
                policy,
                f"{policy} policy of {task_id}",
                EPISODES,
                self.root / f"{family}-v0",
                seed=7,
                progress=False,
            )
        self[family] = self.root / f"{family}-v0"
        return self[family]


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    return _Recorded(tmp_path_factory.mktemp("datasets"))


@pytest.mark.parametrize("family", FAMILY_PARAMS)
def test_collect_loads_with_minari_and_recovers_the_exact_env(recorded, family, monkeypatch):
    task_id, mode, policy = FAMILIES[family]
    monkeypatch.setenv("MINARI_DATASETS_PATH", str(recorded[family].parent))
    dataset = minari.load_dataset(f"{family}-v0")
    assert dataset.total_episodes == EPISODES
    meta = dataset.storage.metadata[store.KEY]
    assert meta["env_id"] == task_id
    assert meta["env_kwargs"] == {"action_mode": mode, "reward_type": "dense"}
    assert meta["policy"] == policy
    assert meta["versions"] == versions.installed()
    assert meta["dropped_episodes"] == 0
    seeds = [m["seed"] for m in dataset.storage.get_episode_metadata(dataset.episode_indices)]
    assert seeds == [7, 8]

    env = dataset.recover_environment()
    try:
        assert env.spec.id == task_id
        assert env.spec.kwargs == {"task_id": task_id, "action_mode": mode, "reward_type": "dense"}
        successes = []
        for seed, episode in zip(seeds, dataset.iterate_episodes()):
            steps = len(episode.actions)
            assert steps == env.spec.max_episode_steps
            assert set(episode.observations) == set(env.observation_space.spaces)
            for key, space in env.observation_space.spaces.items():
                assert episode.observations[key].shape == (steps + 1, *space.shape)
            assert episode.actions.shape == (steps, *env.action_space.shape)
            state = env.unwrapped.backend.get_state()
            assert episode.infos["state"].shape == (steps + 1, state.size)
            # the reset's row of a step-only entry is NaN; the steps' rows add up to the reward
            terms = episode.infos["reward_terms"]
            assert all(np.isnan(v[0]) for v in terms.values())
            np.testing.assert_allclose(sum(v[1:] for v in terms.values()), episode.rewards)
            obs, _ = env.reset(seed=int(seed))  # the recorded reset seed gives the recorded start
            for key in obs:
                np.testing.assert_array_equal(obs[key], episode.observations[key][0])
            np.testing.assert_array_equal(env.unwrapped.backend.get_state(), episode.infos["state"][0])
            successes.append(episode.infos["is_success"][-1] > 0.5)
        assert meta["success_rate"] == np.mean(successes)
    finally:
        env.close()


@pytest.mark.parametrize("family", FAMILY_PARAMS)
def test_replay_from_states_is_exact(recorded, family):
    report = replay(recorded[family], progress=False)
    assert report.version_mismatches == []
    assert [(e.episode, e.first_departure, e.max_deviation) for e in report.episodes] == [
        (0, None, 0.0),
        (1, None, 0.0),
    ]
    assert all(e.success_replayed == e.success_recorded for e in report.episodes)


def test_replay_from_actions_is_exact(recorded):
    report = replay(recorded["fetch"], from_actions=True, progress=False)
    assert report.exact


def test_replay_names_the_episode_and_step_that_departs(recorded, tmp_path):
    import shutil

    copy = tmp_path / "arm4-v0"
    shutil.copytree(recorded["arm4"], copy)
    with h5py.File(copy / "data" / "main_data.hdf5", "r+") as file:
        file["episode_1/observations/observation"][17, 0] += 1e-3
    report = replay(copy, progress=False)
    assert not report.exact
    assert report.departure() == "episode 1 departed at step 17 (max deviation 0.001)"
    assert report.episodes[0].first_departure is None


def test_replay_names_version_mismatches(recorded, tmp_path):
    import json
    import shutil

    copy = tmp_path / "arm4-v0"
    shutil.copytree(recorded["arm4"], copy)
    path = copy / "data" / "metadata.json"
    meta = json.loads(path.read_text())
    meta[store.KEY]["versions"]["mujoco"] = "3.8.0"
    path.write_text(json.dumps(meta))
    report = replay(copy, progress=False)
    assert report.version_mismatches == [f"mujoco 3.8.0 (recorded) vs {versions.installed()['mujoco']} (here)"]


def test_convert_to_joint_delta_keeps_the_successes(tmp_path):
    source = tmp_path / "arm-ee-v0"
    collect(
        "UnifiedManip/Arm4PickAndPlace-v0",
        {"action_mode": "ee_delta", "reward_type": "sparse"},
        scripted,
        "scripted",
        "scripted",
        3,
        source,
        only_successful=True,
        progress=False,
    )
    report = convert(source, "joint_delta", tmp_path / "arm-joint-v0", progress=False)
    assert [(e.success_recorded, e.success_converted) for e in report.episodes] == [(True, True)] * 3
    assert all(e.tracking_error_mean_cm < 2.0 for e in report.episodes)
    assert report.kept == 3
    converted = store.open_dataset(tmp_path / "arm-joint-v0")
    assert converted.recover_environment().spec.kwargs["action_mode"] == "joint_delta"
    meta = store.metadata(converted)
    assert meta["env_kwargs"] == {"action_mode": "joint_delta", "reward_type": "sparse"}
    assert meta["converted_from"]["env_kwargs"]["action_mode"] == "ee_delta"
    assert replay(tmp_path / "arm-joint-v0", progress=False).exact  # its own states replay it


def test_a_failed_collect_leaves_nothing(tmp_path):
    """An error while recording leaves no dataset and no temporary directory."""

    def failing(env):
        def act(obs):
            raise RuntimeError("policy crashed")

        return act

    with pytest.raises(RuntimeError, match="policy crashed"):
        collect("UnifiedManip/Arm4Reach-v0", {"action_mode": "ee_delta"}, failing, "x", "x", 2, tmp_path / "d-v0")
    assert os.listdir(tmp_path) == []
