"""The Stable-Baselines3 adapter of the native vector env: DummyVecEnv's output bit for
bit, HER through env_method("compute_reward"), VecNormalize, short SAC+HER and PPO runs."""

from __future__ import annotations

import csv
import json
import subprocess
import sys

import gymnasium as gym
import numpy as np
import pytest
import torch
from gymnasium.vector import AutoresetMode
from stable_baselines3 import PPO, SAC, HerReplayBuffer
from stable_baselines3.common.vec_env import DummyVecEnv, VecMonitor, VecNormalize

import unified_manip
from unified_manip.envs.vector import make_vector_env
from unified_manip.training.sb3_vec_env import NativeSB3VecEnv


def native(task_id: str, n: int, **kwargs) -> NativeSB3VecEnv:
    spec = gym.spec(task_id)
    return NativeSB3VecEnv(
        make_vector_env(n, task_id, spec.max_episode_steps, autoreset_mode=AutoresetMode.SAME_STEP, **kwargs)
    )


def assert_equal(a, b, path=""):
    """Equal values of equal types (Python floats stay floats), arrays bit for bit."""
    if isinstance(a, (list, tuple)):
        assert len(a) == len(b), path
        for j, (x, y) in enumerate(zip(a, b)):
            assert_equal(x, y, f"{path}[{j}]")
    elif isinstance(a, dict):
        assert a.keys() == b.keys(), f"{path}: {sorted(a)} != {sorted(b)}"
        for k in a:
            assert_equal(a[k], b[k], f"{path}/{k}")
    elif isinstance(a, np.ndarray):
        assert a.dtype == b.dtype and np.array_equal(a, b), f"{path}: {a} != {b}"
    else:
        assert type(a) is type(b) and a == b, f"{path}: {a!r} != {b!r}"


def test_adapter_matches_dummy_vec_env():
    kwargs = dict(action_mode="ee_delta", reward_type="dense_penalized")
    ours = native("UnifiedManip/Arm4Reach-v0", 3, **kwargs)
    theirs = DummyVecEnv([lambda: gym.make("UnifiedManip/Arm4Reach-v0", **kwargs)] * 3)
    ours.seed(7)
    theirs.seed(7)
    assert_equal(ours.reset(), theirs.reset())
    assert_equal(ours.reset_infos, theirs.reset_infos)
    rng = np.random.default_rng(0)
    dones = 0
    for k in range(105):  # two episode ends per env
        actions = rng.uniform(-1, 1, (3, 4)).astype(np.float32)
        out = ours.step(actions)
        assert_equal(out, theirs.step(actions), f"step {k}")
        assert_equal(ours.reset_infos, theirs.reset_infos, f"reset_infos {k}")
        dones += out[2].sum()
    assert dones == 6
    # HerReplayBuffer's call: env 0's compute_reward over a batch of stored info dicts.
    goals, desired = out[0]["achieved_goal"], out[0]["desired_goal"][::-1]
    infos = np.array(out[3], dtype=object)
    (batched,) = ours.env_method("compute_reward", goals, desired, infos, indices=[0])
    (single,) = theirs.env_method("compute_reward", goals, desired, infos, indices=[0])
    np.testing.assert_array_equal(batched, single)
    assert ours.get_attr("render_mode") == [None] * 3 and ours.env_is_wrapped(gym.Wrapper) == [False] * 3
    ours.close()
    theirs.close()


def test_vec_normalize_round_trip(tmp_path):
    env = VecNormalize(native("UnifiedManip/Arm4Push-v0", 2, action_mode="joint_delta"), norm_reward=False)
    env.seed(0)
    env.reset()
    for _ in range(30):
        env.step(np.random.default_rng(1).uniform(-1, 1, (2, 5)))
    env.save(tmp_path / "stats.pkl")
    loaded = VecNormalize.load(tmp_path / "stats.pkl", native("UnifiedManip/Arm4Push-v0", 2, action_mode="joint_delta"))
    raw = env.get_original_obs()
    for key in raw:
        np.testing.assert_array_equal(loaded.obs_rms[key].mean, env.obs_rms[key].mean)
        np.testing.assert_array_equal(loaded.obs_rms[key].var, env.obs_rms[key].var)
    assert_equal(loaded.normalize_obs(raw), env.normalize_obs(raw))
    env.close()
    loaded.close()


def test_sac_her_smoke():
    torch.set_num_threads(1)
    env = VecMonitor(native("UnifiedManip/Arm4Reach-v0", 2, action_mode="ee_delta"), info_keywords=("is_success",))
    model = SAC(
        "MultiInputPolicy",
        env,
        replay_buffer_class=HerReplayBuffer,
        learning_starts=200,
        batch_size=64,
        policy_kwargs=dict(net_arch=[32, 32]),
        seed=0,
        device="cpu",
    )
    model.learn(1_000)
    assert model.num_timesteps == 1_000
    assert len(model.ep_success_buffer) == 20  # 2 envs x 500 steps / 50-step episodes
    # Relabelled samples carry the reward of the batched compute_reward (via env_method).
    batch = model.replay_buffer.sample(512)
    next_ag, goal = batch.next_observations["achieved_goal"].numpy(), batch.observations["desired_goal"].numpy()
    spec = unified_manip.TASKS["UnifiedManip/Arm4Reach-v0"]
    distance = spec.goal_distance(next_ag.astype(np.float64), goal.astype(np.float64))
    expected = -(distance >= spec.distance_threshold).astype(np.float32)
    np.testing.assert_array_equal(batch.rewards.numpy().ravel(), expected)
    assert (expected == 0.0).mean() > 0.05  # some relabelled goals were reached
    env.close()


def test_ppo_smoke():
    torch.set_num_threads(1)
    env = VecMonitor(native("UnifiedManip/Arm4Push-v0", 2, action_mode="joint_position", reward_type="dense"))
    model = PPO(
        "MultiInputPolicy",
        env,
        n_steps=64,
        batch_size=64,
        n_epochs=1,
        policy_kwargs=dict(net_arch=[32]),
        seed=0,
        device="cpu",
    )
    model.learn(256)
    assert model.num_timesteps == 256
    env.close()


@pytest.mark.slow
def test_train_picks_and_runs_the_native_vector_env(tmp_path):
    from unified_manip.envs.vector.factory import resolve_vec

    assert resolve_vec("auto", "UnifiedManip/Arm4Reach-v0", 2) == "native"  # --n-envs N alone
    assert resolve_vec("auto", "UnifiedManip/Arm4Reach-v0", 1) == "dummy"
    assert resolve_vec("auto", "UnifiedManip/Lift-v0", 4) == "subproc"
    run = tmp_path / "run"
    sets = ["n_steps=64", "batch_size=64", "n_epochs=1", "eval_freq=128", "n_eval_episodes=1", "checkpoint_freq=128"]
    args = [
        "train",
        "--env",
        "UnifiedManip/Arm4Reach-v0",
        "--action-mode",
        "joint_delta",
        "--algo",
        "ppo",
        "--steps",
        "256",
        "--n-envs",
        "2",
        "--vec",
        "native",
        "--run-dir",
        str(run),
        "--no-progress",
        *[a for s in sets for a in ("--set", s)],
    ]
    proc = subprocess.run(
        [sys.executable, "-m", "unified_manip.cli", *args], capture_output=True, text=True, timeout=600
    )
    assert proc.returncode == 0, proc.stderr
    # The evaluation env has the training env's layers (one VecMonitor) and no Monitor under it.
    assert "already wrapped with a `Monitor`" not in proc.stderr, proc.stderr
    assert json.loads((run / "status.json").read_text())["state"] == "finished"
    with open(run / "monitor" / "seg0" / "native.monitor.csv") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    assert len(rows) >= 4 and {row["l"] for row in rows} == {"50"} and "is_success" in rows[0]
