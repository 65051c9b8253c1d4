"""A 600-step SAC + HerReplayBuffer run on one task of each family (in ee_delta, or native
where the task has no ee_delta): HER relabels with our reward. That compute_reward gives
the step's reward for relabelled goals is checked on every ID, mode and reward type in
tests/envs/test_envs.py."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
import torch
from conftest import HER_IDS, smoke_mode
from stable_baselines3 import SAC, HerReplayBuffer

import unified_manip


def test_every_family_has_a_task_in_the_her_tests():
    families = {spec.family for spec in unified_manip.TASKS.values()}
    assert {unified_manip.TASKS[t].family for t in HER_IDS} == families


@pytest.mark.slow
@pytest.mark.parametrize("task_id", HER_IDS)
def test_sac_her_smoke_run(task_id):
    torch.set_num_threads(1)
    spec = unified_manip.TASKS[task_id]
    # Episodes of at most 200 steps, so that 600 steps hold 3 or more of every ID's.
    episode = min(spec.max_episode_steps, 200)
    env = gym.make(task_id, action_mode=smoke_mode(task_id), reward_type="sparse", max_episode_steps=episode)
    model = SAC(
        "MultiInputPolicy",
        env,
        replay_buffer_class=HerReplayBuffer,
        replay_buffer_kwargs=dict(n_sampled_goal=4, goal_selection_strategy="future"),
        learning_starts=episode,
        batch_size=64,
        policy_kwargs=dict(net_arch=[32, 32]),
        seed=0,
        device="cpu",
    )
    model.learn(total_timesteps=600)  # 3 or more episodes of every ID, 400 updates
    assert model.num_timesteps == 600
    buffer = model.replay_buffer
    assert buffer.size() * buffer.n_envs == 600

    # Relabelled samples carry exactly the reward our compute_reward gives.
    batch = buffer.sample(512)
    next_ag = batch.next_observations["achieved_goal"].numpy()
    dg = batch.observations["desired_goal"].numpy()
    expected = -(
        spec.goal_distance(next_ag.astype(np.float64), dg.astype(np.float64)) >= spec.distance_threshold
    ).astype(np.float32)
    np.testing.assert_array_equal(batch.rewards.numpy().ravel(), expected)
    assert (expected == 0.0).mean() > 0.05  # some relabelled goals were reached
    action, _ = model.predict(env.reset(seed=0)[0], deterministic=True)
    assert env.action_space.contains(action)
