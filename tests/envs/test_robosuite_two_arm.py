"""robosuite's two-arm tasks: both arms under one action, TwoArmHandover's success as
robosuite's along its scripted handover, TwoArmLift's scripted lift.

Real robosuite 1.5.2, no mocks. (The contract suites, the golden rollouts and the parity
with robosuite.make, tests/envs/test_robosuite.py, cover both IDs through the registry.)
Each test builds one env: a two-arm env takes ~0.3 s.
"""

from __future__ import annotations

import itertools

import gymnasium as gym
import numpy as np
import pytest

import unified_manip

pytestmark = pytest.mark.robosuite  # every test here needs the robosuite extra

LIFT, HANDOVER = "UnifiedManip/TwoArmLift-v0", "UnifiedManip/TwoArmHandover-v0"


def test_every_mode_acts_on_both_arms_and_a_wrong_shape_names_it():
    """ee_delta is 2 × (3 + 1); a one-arm action is refused in one line naming the shape."""
    env = gym.make(LIFT, action_mode="ee_delta")
    env.reset(seed=0)
    assert env.action_space.shape == (8,)
    with pytest.raises(ValueError, match=r"^action must have shape \(8,\) \(2 × \(3 \+ 1\)\) for .*got shape \(4,\)$"):
        env.step(np.zeros(4, dtype=np.float32))
    # Arm 1's part raises arm 1's grip site only (arm 0, under a zero command, turns its
    # gripper to the pot's handle about z and stays at its height).
    b = env.unwrapped._backend
    sites = [b.data.site_xpos[s].copy() for s in b._grip_sites]
    for _ in range(4):
        env.step(np.array([0, 0, 0, 1, 0, 0, 1, 1], dtype=np.float32))
    moved = [b.data.site_xpos[s] - p for s, p in zip(b._grip_sites, sites)]
    assert abs(moved[0][2]) < 0.01 and moved[1][2] > 0.03
    env.close()


def test_handover_success_is_robosuites_check():
    """Along the scripted handover (seed 1000), the achieved goal is robosuite's three checks
    and is_success is robosuite's success at every step, before and after the handover; of
    the eight flag combinations exactly robosuite's success condition is within the threshold."""
    env = gym.make(HANDOVER, action_mode="ee_delta")
    spec = unified_manip.TASKS[HANDOVER]
    policy = spec.scripted_policy("ee_delta")
    obs, info = env.reset(seed=1000)
    up = env.unwrapped._backend._up
    seen = []
    for _ in range(spec.max_episode_steps):
        obs, _, _, _, info = env.step(policy(obs))
        arm0, arm1, hammer_z, table_z = up._get_task_info()
        np.testing.assert_array_equal(obs["achieved_goal"], [arm0, arm1, hammer_z - table_z > 0.1])
        assert info["is_success"] == info["native_success"] == float(up._check_success())
        seen.append(tuple(obs["achieved_goal"]))
        if seen[-5:] == [(0.0, 1.0, 1.0)] * 5:  # handed over, and held
            break
    assert (1.0, 0.0, 1.0) in seen and seen[-1] == (0.0, 1.0, 1.0)  # arm 0 lifted it, arm 1 took it
    for arm0, arm1, lifted in itertools.product((0.0, 1.0), repeat=3):
        d = spec.goal_distance(np.array([arm0, arm1, lifted]), obs["desired_goal"])
        assert (d < spec.distance_threshold) == (arm1 and not arm0 and lifted)
    env.close()


def test_two_arm_lift_scripted_policy_lifts_the_pot():
    """Seed 1000: both grippers close on their handles, and the pot reaches its goal, which
    robosuite counts as lifted too."""
    env = gym.make(LIFT, action_mode="ee_delta", reward_type="dense")
    policy = unified_manip.TASKS[LIFT].scripted_policy("ee_delta")
    obs, info = env.reset(seed=1000)
    start = obs["achieved_goal"].copy()
    for _ in range(100):
        obs, _, _, _, info = env.step(policy(obs))
        if info["is_success"]:
            break
    assert info["is_success"] == info["native_success"] == 1.0
    assert obs["achieved_goal"][2] - start[2] > 0.1
    env.close()
