"""The scripted ``ee_delta`` policy of TwoArmLift: each Panda grasps its own pot handle
from above, and once both hold, both lift together. Its action is
``2 × (dx, dy, dz, gripper)``. It is memoryless."""

from __future__ import annotations

import numpy as np

from unified_manip.envs.tasks.scripted import toward

#: Panda proprio (50 entries per robot): eef position (m, world), finger qpos and qvel.
PROPRIO = 50
EEF, FINGER_QPOS, FINGER_QVEL = slice(35, 38), slice(46, 48), slice(48, 50)
#: TwoArmLift's object state after the two proprio vectors: pot pos (3), pot quat (4),
#: handle 0 (3), handle 1 (3), ...
HANDLES = (slice(2 * PROPRIO + 7, 2 * PROPRIO + 10), slice(2 * PROPRIO + 10, 2 * PROPRIO + 13))
#: How high above its handle a gripper lines up before coming down, m.
HOVER = 0.06


def _arm(o: np.ndarray, i: int) -> tuple[np.ndarray, float, float]:
    """Arm ``i``'s eef position, finger opening (m) and closing speed (m/s)."""
    p = o[i * PROPRIO : (i + 1) * PROPRIO]
    return p[EEF], p[FINGER_QPOS][0] - p[FINGER_QPOS][1], abs(p[FINGER_QVEL][0] - p[FINGER_QVEL][1])


def _holds(to_handle: np.ndarray, opening: float, speed: float) -> bool:
    return np.linalg.norm(to_handle[:2]) < 0.02 and abs(to_handle[2]) < 0.03 and opening < 0.07 and speed < 0.02


def _reach(to_handle: np.ndarray) -> np.ndarray:
    """Line up above the handle, open; come down; close once on it."""
    if np.linalg.norm(to_handle[:2]) > 0.01 and to_handle[2] > -HOVER + 0.01:
        return np.append(toward(to_handle + np.array([0.0, 0.0, HOVER])), 1.0)
    if np.linalg.norm(to_handle[:2]) < 0.015 and abs(to_handle[2]) < 0.015:
        return np.array([0.0, 0.0, 0.0, -1.0])
    return np.append(toward(to_handle), 1.0)


def two_arm_lift_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    o = obs["observation"]
    arms = [_arm(o, i) for i in range(2)]
    to_handles = [o[h] - eef for h, (eef, _, _) in zip(HANDLES, arms)]
    held = [_holds(d, opening, speed) for d, (_, opening, speed) in zip(to_handles, arms)]
    if all(held):  # both hold their handles: carry the pot to the goal, together
        move = toward(obs["desired_goal"] - obs["achieved_goal"], 5.0)
        return np.concatenate([np.append(move, -1.0)] * 2)
    actions = []
    for d, h in zip(to_handles, held):
        actions.append(np.array([0.0, 0.0, 0.0, -1.0]) if h else _reach(d))
    return np.concatenate(actions)
