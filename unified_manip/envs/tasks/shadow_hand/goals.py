"""Goal distances of the Shadow Hand tasks (numpy only)."""

from __future__ import annotations

import numpy as np

#: Upstream's block success: position within 1 cm and rotation within 0.1 rad.
BLOCK_POSITION_THRESHOLD = 0.01
BLOCK_ROTATION_THRESHOLD = 0.1
#: Rotation error is folded into the goal distance at this many metres per radian, so
#: that ``distance < 0.01`` is exactly upstream's "position < 0.01 and rotation < 0.1".
ROTATION_WEIGHT = BLOCK_POSITION_THRESHOLD / BLOCK_ROTATION_THRESHOLD
#: The block goal's layout: position (m), then unit quaternion (w, x, y, z).
GOAL_POSITION, GOAL_QUATERNION = slice(0, 3), slice(3, 7)


def block_goal_distance(achieved_goal: np.ndarray, desired_goal: np.ndarray) -> np.ndarray:
    """``max(d_pos, 0.1 m/rad * d_rot)`` over goals ``(..., 7)`` = (x, y, z, qw, qx, qy, qz).

    ``d_pos`` is the Euclidean position error (m) and ``d_rot = 2 arccos(clip(<qa, qd>))``
    upstream's rotation error (rad): the real part of ``qa * conj(qd)`` is the dot
    product of the two quaternions.
    """
    a = np.asarray(achieved_goal)
    b = np.asarray(desired_goal)
    diff = a[..., GOAL_POSITION] - b[..., GOAL_POSITION]
    d_pos = np.sqrt((diff * diff).sum(axis=-1))
    w = (a[..., GOAL_QUATERNION] * b[..., GOAL_QUATERNION]).sum(axis=-1)
    d_rot = 2.0 * np.arccos(np.clip(w, -1.0, 1.0))
    return np.maximum(d_pos, ROTATION_WEIGHT * d_rot)
