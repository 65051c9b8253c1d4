"""The scripted ``ee_delta`` policies of the two-arm tasks; each action is
``2 × (dx, dy, dz, gripper)``. They are memoryless: the stage is read off the state.

* **TwoArmLift:** each Panda grasps its own pot handle from above, and once both hold,
  both lift together.
* **TwoArmHandover:** arm 0 grasps the hammer's handle on its side of the handle's middle
  and carries it to the middle of the table; arm 1 grasps the handle's other half; once
  it holds, arm 0 opens, rises and backs away, and arm 1 keeps the hammer up.
"""

from __future__ import annotations

import numpy as np

from unified_manip.envs.tasks.scripted import toward

#: Panda proprio (50 entries per robot): eef position (m, world), finger qpos and qvel.
PROPRIO = 50
EEF, FINGER_QPOS, FINGER_QVEL = slice(35, 38), slice(46, 48), slice(48, 50)
#: The object state after the two proprio vectors. TwoArmLift: pot pos (3), pot quat (4),
#: handle 0 (3), handle 1 (3), ...; TwoArmHandover: hammer handle pos (3), quat (4), ...
OBJECT = 2 * PROPRIO
HANDLES = (slice(OBJECT + 7, OBJECT + 10), slice(OBJECT + 10, OBJECT + 13))
HAMMER, HAMMER_QUAT = slice(OBJECT, OBJECT + 3), slice(OBJECT + 3, OBJECT + 7)
#: How high above its grasp point a gripper lines up before coming down, m.
HOVER = 0.06
#: TwoArmHandover: each arm's grasp point, this far from the handle's middle along it, m;
#: where the hammer is handed over (world, m); where arm 0 backs away to (x, y), m.
HANDOVER_OFFSET, HANDOVER_POINT, ARM0_REST = 0.04, np.array([0.0, 0.0, 1.0]), np.array([0.0, -0.45])
CLOSE, OPEN = np.array([0.0, 0.0, 0.0, -1.0]), np.array([0.0, 0.0, 0.0, 1.0])


def _arm(o: np.ndarray, i: int) -> tuple[np.ndarray, float, float]:
    """Arm ``i``'s eef position, finger opening (m) and closing speed (m/s)."""
    p = o[i * PROPRIO : (i + 1) * PROPRIO]
    return p[EEF], p[FINGER_QPOS][0] - p[FINGER_QPOS][1], abs(p[FINGER_QVEL][0] - p[FINGER_QVEL][1])


def _holds(to_grasp: np.ndarray, opening: float, speed: float, xy: float = 0.02) -> bool:
    """The fingers are closed, and still, at the grasp point."""
    near = np.linalg.norm(to_grasp[:2]) < xy and abs(to_grasp[2]) < 0.03
    return bool(near and opening < 0.07 and speed < 0.02)


def _reach(to_grasp: np.ndarray, hover: float = HOVER) -> np.ndarray:
    """Line up above the grasp point, open; come down; close once on it."""
    if np.linalg.norm(to_grasp[:2]) > 0.01 and to_grasp[2] > -hover + 0.01:
        return np.append(toward(to_grasp + np.array([0.0, 0.0, hover])), 1.0)
    if np.linalg.norm(to_grasp[:2]) < 0.015 and abs(to_grasp[2]) < 0.015:
        return CLOSE
    return np.append(toward(to_grasp), 1.0)


def two_arm_lift_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    o = obs["observation"]
    arms = [_arm(o, i) for i in range(2)]
    to_handles = [o[h] - eef for h, (eef, _, _) in zip(HANDLES, arms)]
    held = [_holds(d, opening, speed) for d, (_, opening, speed) in zip(to_handles, arms)]
    if all(held):  # both hold their handles: carry the pot to the goal, together
        move = toward(obs["desired_goal"] - obs["achieved_goal"], 5.0)
        return np.concatenate([np.append(move, -1.0)] * 2)
    return np.concatenate([CLOSE if h else _reach(d) for d, h in zip(to_handles, held)])


def _handle_axis(quat: np.ndarray) -> np.ndarray:
    """The handle's long axis (its z axis, from its quaternion x, y, z, w) in the table's
    plane, pointing toward arm 1 (+y)."""
    x, y, z, w = quat
    axis = np.array([2 * (x * z + w * y), 2 * (y * z - w * x), 0.0])
    axis /= np.linalg.norm(axis) + 1e-9
    return axis if axis[1] >= 0 else -axis


def two_arm_handover_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    o = obs["observation"]
    handle, axis = o[HAMMER], _handle_axis(o[HAMMER_QUAT])
    (eef0, opening0, speed0), (eef1, opening1, speed1) = _arm(o, 0), _arm(o, 1)
    to0 = handle - HANDOVER_OFFSET * axis - eef0
    to1 = handle + HANDOVER_OFFSET * axis - eef1
    if _holds(to1, opening1, speed1, xy=0.025):  # arm 1 has it: arm 0 lets go and backs away
        if opening0 < 0.07:
            arm0 = OPEN
        elif eef0[2] < handle[2] + 0.08:  # straight up first, clear of the handle
            arm0 = np.array([0.0, 0.0, 1.0, 1.0])
        else:
            arm0 = np.append(toward(np.append(ARM0_REST, handle[2] + 0.1) - eef0), 1.0)
        return np.concatenate([arm0, CLOSE])
    if not _holds(to0, opening0, speed0, xy=0.025):  # arm 0 picks it up; arm 1 waits, open
        return np.concatenate([_reach(to0, 0.08), OPEN])
    carry = np.append(toward(HANDOVER_POINT - handle, 5.0), -1.0)
    if np.linalg.norm(HANDOVER_POINT - handle) > 0.03:
        return np.concatenate([carry, OPEN])
    return np.concatenate([carry, _reach(to1, 0.08)])
