"""The example family from outside the package (``examples/valve_family``): installed in
the test environment, so that every registry-parametrised contract test runs on its IDs,
and its own behaviour: an angle goal with a wrapped distance, and a scripted policy."""

from __future__ import annotations

import math
import subprocess
import sys
from importlib.metadata import PackageNotFoundError, distribution

import gymnasium as gym
import numpy as np

import unified_manip
from unified_manip.envs import tasks

VALVE = "UnifiedManip/ValveTurn-v0"
INSTALL = "install it: pip install -e examples/valve_family (.ci/run does)"


def test_the_example_family_is_installed_and_registered_through_its_entry_point():
    try:
        dist = distribution("unified-manip-valve")
    except PackageNotFoundError:
        raise AssertionError(f"the example family unified-manip-valve is not installed; {INSTALL}") from None
    assert [ep.value for ep in dist.entry_points if ep.group == "unified_manip.families"] == [
        "unified_manip_valve.specs"
    ]
    assert tasks.PLUGIN_IDS == (VALVE,), f"{tasks.PLUGIN_IDS}; {INSTALL}"
    spec = unified_manip.TASKS[VALVE]
    assert spec.family == "valve" and spec.goal_dim == 1
    assert spec.action_modes == ("joint_torque", "joint_position", "joint_delta", "joint_target_delta",
                                 "joint_velocity", "native")  # fmt: skip


def test_the_family_registers_whichever_module_is_imported_first():
    """Registering the family imports its specs: a module of it imported before
    ``unified_manip`` must not leave the specs a half-built package to read."""
    for module in ("unified_manip_valve.policy", "unified_manip_valve.backend", "unified_manip"):
        code = f"import {module}, unified_manip; print(list(unified_manip.TASKS)[-1])"
        out = subprocess.run([sys.executable, "-W", "error", "-c", code], capture_output=True, text=True, timeout=120)
        assert (out.returncode, out.stdout) == (0, f"{VALVE}\n"), out.stderr[-2000:]


def test_the_goal_is_an_angle_and_its_distance_wraps_round():
    env = gym.make(VALVE, action_mode="joint_delta", reward_type="sparse").unwrapped
    obs, info = env.reset(seed=0)
    assert -math.pi <= obs["achieved_goal"][0] < math.pi and -math.pi <= obs["desired_goal"][0] < math.pi
    # 0.02 rad apart across +-pi: a success; 0.2 rad apart either side of 0: not.
    achieved = np.array([[math.pi - 0.01], [0.1], [-3.0]])
    desired = np.array([[-math.pi + 0.01], [-0.1], [3.0]])
    np.testing.assert_allclose(env.task.goal_distance(achieved, desired), [0.02, 0.2, 2 * math.pi - 6.0], atol=1e-12)
    infos = np.array([info] * 3, dtype=object)
    np.testing.assert_array_equal(env.compute_reward(achieved, desired, infos), [0.0, -1.0, -1.0])
    env.close()


def test_the_quantities_are_the_fingertip_handle_gap_in_metres_and_the_valve_speed():
    """Read beside the observation while the scripted policy pushes the handle round."""
    from unified_manip_valve.policy import turn_policy

    env = gym.make(VALVE, action_mode="joint_delta", reward_type="dense_penalized")
    obs, info = env.reset(seed=2)
    layout = env.unwrapped.observation_layout
    gaps, speeds = [], []
    for _ in range(60):
        obs, _, _, _, info = env.step(turn_policy(obs))
        o = obs["observation"]
        assert math.isclose(info["fingertip_to_handle"], np.linalg.norm(o[layout["object_rel"]]), rel_tol=1e-6)
        assert math.isclose(info["valve_speed"], abs(o[layout["valve_vel"]][0]), rel_tol=1e-6, abs_tol=1e-9)
        gaps.append(info["fingertip_to_handle"])
        speeds.append(info["valve_speed"])
    # The tip (12 mm) touched the handle (10 mm) and turned the valve.
    assert min(gaps) < 0.023 and max(speeds) > 0.5
    assert tuple(info["reward_terms"]) == ("approach", "turn", "success", "action", "spin")
    env.close()


def test_the_scripted_policy_turns_the_valve_in_joint_delta():
    """Success at the episode's end over 20 seeded episodes (measured: 20 of 20 on these
    seeds, 199 of 200 on seeds 0-199)."""
    from unified_manip_valve.policy import success_rate

    assert success_rate(range(1000, 1020)) >= 0.9
