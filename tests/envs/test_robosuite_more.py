"""robosuite's Wipe and ToolHang: goals that are not positions, and a robot without a gripper.

Real robosuite 1.5.2, no mocks. (The contract suites, parity with robosuite.make and the
scripted policies cover these IDs with the others.)
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

from unified_manip.envs.tasks.scripted import toward

pytestmark = pytest.mark.robosuite  # every test here needs the robosuite extra


def test_wipe_has_no_gripper_entry_in_any_mode():
    """The sponge has no moving part: no gripper entry, whatever the mode."""
    shapes = {}
    for mode in ("joint_position", "joint_torque", "ee_delta", "ee_target_delta", "native"):
        env = gym.make("UnifiedManip/Wipe-v0", action_mode=mode)
        shapes[mode] = env.action_space.shape
        env.close()
    assert shapes == {
        "joint_position": (7,),
        "joint_torque": (7,),
        "ee_delta": (3,),
        "ee_target_delta": (3,),
        "native": (6,),  # robosuite's OSC_POSE
    }


def test_wipe_goal_is_the_fraction_robosuite_wiped():
    """Pressing the sponge onto the first marker and along the line wipes markers: the
    achieved goal counts them as robosuite does, the place term grows with it, and
    is_success stays robosuite's success (all wiped) throughout."""
    env = gym.make("UnifiedManip/Wipe-v0", action_mode="ee_delta", reward_type="dense")
    obs, _ = env.reset(seed=0)
    up = env.unwrapped._backend._up
    markers = [
        up.sim.data.body_xpos[up.sim.model.body_name2id(m.root_body)].copy() for m in up.model.mujoco_arena.markers
    ]
    place = []
    for k in range(80):
        target = markers[min(k // 6, len(markers) - 1)]
        obs, _, _, _, info = env.step(toward(target - obs["observation"][35:38] + [0.0, 0.0, -0.03], 5.0))
        assert obs["achieved_goal"][0] == np.float32(len(up.wiped_markers) / 100)
        assert info["is_success"] == info["native_success"] == float(len(up.wiped_markers) == 100)
        place.append(info["reward_terms"]["place"])
    assert obs["achieved_goal"][0] >= 0.05 and place[-1] > place[0]
    env.close()


def test_tool_hang_goal_is_robosuites_two_stages():
    """ToolHang's goal is the two checks robosuite's success is made of, and its desired
    goal asks for both; at reset neither holds and the reach term's object is the frame."""
    env = gym.make("UnifiedManip/ToolHang-v0", action_mode="ee_delta", reward_type="dense")
    obs, info = env.reset(seed=0)
    up = env.unwrapped._backend._up
    np.testing.assert_array_equal(obs["desired_goal"], [1.0, 1.0])
    np.testing.assert_array_equal(obs["achieved_goal"], [0.0, 0.0])
    obs, _, _, _, info = env.step(np.zeros(4, dtype=np.float32))
    frame = up.sim.data.site_xpos[up.obj_site_id["frame_intersection_site"]]
    grip = up.sim.data.site_xpos[up.robots[0].eef_site_id["right"]]
    assert info["grip_to_object"] == np.linalg.norm(frame - grip)
    assert info["is_success"] == info["native_success"] == 0.0
    env.close()
