"""Scripted ``ee_delta`` policies of the 4-DOF arm's tasks, on the documented
observation layout (:mod:`.scene`). They are memoryless, so they work from any state."""

from __future__ import annotations

import numpy as np

from unified_manip.envs.tasks.arm4.scene import (
    FINGER_ON_CUBE,
    OBS_CUBE,
    OBS_CUBE_REL,
    OBS_FINGERS,
    OBS_GOAL_REL,
    OBS_GRIP,
)
from unified_manip.envs.tasks.scripted import pick_and_place, toward


def reach_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    """Move the grip site straight to the goal."""
    move = toward(obs["desired_goal"] - obs["achieved_goal"])
    return np.append(move, 1.0).astype(np.float32)


def pick_and_place_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    """Hover over the cube, descend open, close, then carry it to the goal."""
    o = obs["observation"]
    closed_on_cube = bool(np.all(o[OBS_FINGERS] < FINGER_ON_CUBE + 0.006))
    return pick_and_place(o[OBS_CUBE_REL], o[OBS_GOAL_REL], closed_on_cube, align=0.012, hover=0.06, near=0.008)


PUSH_SPEED, PUSH_STEER, PUSH_LATERAL_TOL, PUSH_SLOWDOWN = 0.5, 20.0, 0.03, 10.0


def push_policy(obs: dict[str, np.ndarray], gain: float = 1.0) -> np.ndarray:
    """Go behind the cube (seen from the goal), lower the closed gripper, push.

    ``gain`` scales every action magnitude (the feedback gains in action units per metre
    and the pushing speed): 0.5 for the v1 task, whose ``ee_delta`` step is twice v0's, keeps
    v0's moves in metres per step. At 1 there, each step would try to cancel a whole error and
    push twice as far, and the stiff servos' overshoot made half of the pushes miss."""
    o = obs["observation"]
    grip = o[OBS_GRIP]
    obj = o[OBS_CUBE]
    to_goal = o[OBS_GOAL_REL]
    direction = to_goal[:2] / max(np.linalg.norm(to_goal[:2]), 1e-6)
    rel = grip[:2] - obj[:2]
    along = float(rel @ direction)  # negative: the gripper is behind the cube
    lateral = float(abs(rel[0] * direction[1] - rel[1] * direction[0]))
    push_z = obj[2] + 0.01
    remaining = float(np.linalg.norm(to_goal[:2]))
    if remaining < 0.015:  # close enough: stop, so the cube does not slide past
        return np.array([0.0, 0.0, 0.0, -1.0], dtype=np.float32)
    if along < -0.03 and lateral < PUSH_LATERAL_TOL and grip[2] < obj[2] + 0.03:
        # Steer back onto the line through the cube and the goal while pushing, and
        # slow down near the goal.
        correction = (obj[:2] - along * direction) - grip[:2]
        speed = gain * min(PUSH_SPEED, PUSH_SLOWDOWN * remaining)
        steer = np.clip(correction * PUSH_STEER * gain, -0.3, 0.3)
        move = np.append(direction * speed + steer, (push_z - grip[2]) * 20.0 * gain)
        return np.append(np.clip(move, -1, 1), -1.0).astype(np.float32)
    behind = np.append(obj[:2] - direction * 0.07, push_z)
    if np.linalg.norm(grip[:2] - behind[:2]) > 0.015:
        if grip[2] < obj[2] + 0.05 and np.linalg.norm(rel) < 0.1:  # rise clear of the cube first
            return np.array([0.0, 0.0, 1.0, -1.0], dtype=np.float32)
        above = behind.copy()
        above[2] = obj[2] + 0.07
        return np.append(toward(above - grip, 20.0 * gain), -1.0).astype(np.float32)
    return np.append(toward(behind - grip, 20.0 * gain), -1.0).astype(np.float32)


def push_policy_25hz(obs: dict[str, np.ndarray]) -> np.ndarray:
    """:func:`push_policy` for the v1 push task's doubled ``ee_delta`` step."""
    return push_policy(obs, gain=0.5)
