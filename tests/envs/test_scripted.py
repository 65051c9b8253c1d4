"""Scripted policies: the demo and the oracle that every task is solvable as built."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import make

import unified_manip

# Seeds distinct from the ones used while writing the policies: 1000, 1001, ...
FIRST_SEED = 1000

SCRIPTED = [tid for tid, spec in unified_manip.TASKS.items() if spec.scripted_min_success is not None]


def success_rate(task_id: str, seeds) -> float:
    spec = unified_manip.TASKS[task_id]
    env = make(task_id, "ee_delta")
    policy = spec.scripted_policy("ee_delta")
    successes = 0
    for seed in seeds:
        obs, info = env.reset(seed=seed)
        for _ in range(spec.max_episode_steps):
            obs, _, _, _, info = env.step(policy(obs))
        successes += info["is_success"]
    env.close()
    return successes / len(seeds)


@pytest.mark.parametrize("task_id", SCRIPTED)
def test_scripted_ee_delta_policy_reaches_its_success_rate(task_id):
    spec = unified_manip.TASKS[task_id]
    seeds = range(FIRST_SEED, FIRST_SEED + spec.scripted_episodes)
    rate = success_rate(task_id, seeds)
    assert rate >= spec.scripted_min_success, f"{task_id}: scripted success {rate:.2f} over {len(seeds)} episodes"


def test_scripted_policy_rejects_other_modes():
    spec = unified_manip.TASKS["UnifiedManip/Arm4Reach-v0"]
    with pytest.raises(ValueError, match="emit ee_delta actions; got action_mode='joint_torque'"):
        spec.scripted_policy("joint_torque")


def test_pick_and_place_really_lifts_and_reports_grasp():
    """The success is a carried cube: it leaves the table while grasped, no drop on the way."""
    task_id = "UnifiedManip/Arm4PickAndPlace-v0"
    env = make(task_id, "ee_delta", "dense_penalized")
    policy = unified_manip.TASKS[task_id].scripted_policy("ee_delta")
    obs, _ = env.reset(seed=5)
    heights, grasped, drops = [], [], 0.0
    for _ in range(100):
        obs, _, _, _, info = env.step(policy(obs))
        heights.append(obs["achieved_goal"][2])
        grasped.append(info["grasped"])
        drops += info["dropped"]
    assert info["is_success"] == 1.0
    assert max(heights) > 0.445 + 0.05
    assert np.mean(grasped[-20:]) == 1.0
    assert drops == 0.0
    assert info["reward_terms"]["place"] > 4.0  # 5 * (1 - tanh(5 d)) with d < 5 cm


def test_terminate_on_success_ends_episode():
    task_id = "UnifiedManip/Arm4Reach-v0"
    env = make(task_id, "ee_delta", terminate_on_success=True)
    policy = unified_manip.TASKS[task_id].scripted_policy("ee_delta")
    obs, _ = env.reset(seed=1)
    for t in range(50):
        obs, r, terminated, truncated, info = env.step(policy(obs))
        if terminated:
            break
    assert terminated and not truncated and info["is_success"] == 1.0 and r == 0.0
