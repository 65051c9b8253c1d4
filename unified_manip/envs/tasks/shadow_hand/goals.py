"""Goal distances of the Shadow Hand's manipulation tasks (numpy only).

Upstream (gymnasium-robotics' ``ManipulateEnv``) judges a pose goal by two numbers: the
position error ``d_pos`` (m) and the rotation error ``d_rot`` (rad), and calls it a
success when ``d_pos < position threshold`` and ``d_rot < rotation threshold``. The shared
env has one goal distance and one threshold, so :class:`PoseDistance` folds the two into
one normalised distance: each error as a fraction of its threshold, the larger of the
two, times :data:`DISTANCE_UNIT` (0.01)::

    d = 0.01 max(d_pos / position threshold, d_rot / rotation threshold)

It is below 0.01 exactly when both errors are below their thresholds (up to the last
bit of rounding at the threshold). With the block's and egg's thresholds (0.01 m, 0.1
rad) it is ``max(d_pos, 0.1 m/rad d_rot)`` in metres; the pen's (0.05 m, 0.1 rad) give
``max(0.2 d_pos, 0.1 m/rad d_rot)``. On the ``Rotate`` variants (upstream's
``target_position="ignore"``) the position does not count: ``d = 0.1 m/rad d_rot``. One
scale for every task keeps the dense reward's ``1 - tanh(g d)`` equally steep on all of
them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

#: Upstream's default success thresholds: position within 1 cm, rotation within 0.1 rad.
BLOCK_POSITION_THRESHOLD = 0.01
BLOCK_ROTATION_THRESHOLD = 0.1
#: The pen's position threshold (upstream's ``distance_threshold=0.05``).
PEN_POSITION_THRESHOLD = 0.05
#: The threshold of every pose distance: an error at its threshold is this far.
DISTANCE_UNIT = BLOCK_POSITION_THRESHOLD
#: The pose goal's layout: position (m), then unit quaternion (w, x, y, z).
GOAL_POSITION, GOAL_QUATERNION = slice(0, 3), slice(3, 7)


def _ignore_z_rotation(quat_a: np.ndarray, quat_b: np.ndarray) -> np.ndarray:
    """``quat_a`` with its z Euler angle (xyz convention) replaced by ``quat_b``'s:
    upstream's ``ignore_z_target_rotation`` (the pen's spin about its own axis does not
    count). Upstream writes ``euler_a[2] = euler_b[2]``, which on a batch of goals
    replaces the third goal instead of the third angle; this is its single-goal meaning,
    applied to every goal of a batch."""
    from gymnasium_robotics.utils import rotations  # numpy only; imported on first use

    euler_a = rotations.quat2euler(quat_a)
    euler_b = rotations.quat2euler(quat_b)
    euler_a[..., 2] = euler_b[..., 2]
    return rotations.euler2quat(euler_a)


@dataclass(frozen=True)
class PoseDistance:
    """The goal distance of a pose goal ``(..., 7)`` = (x, y, z, qw, qx, qy, qz): see the
    module docstring; ``distance < DISTANCE_UNIT`` is upstream's success.

    ``d_pos`` is the Euclidean position error (m) and ``d_rot = 2 arccos(clip(<qa, qd>))``
    upstream's rotation error (rad): the real part of ``qa * conj(qd)`` is the dot product
    of the two quaternions.

    Attributes:
        position_threshold: Upstream's position threshold, m.
        rotation_threshold: Upstream's rotation threshold, rad.
        position: Whether the position counts (upstream's ``target_position`` is not
            ``"ignore"``).
        ignore_z: Upstream's ``ignore_z_target_rotation`` (the pen).
    """

    position_threshold: float = BLOCK_POSITION_THRESHOLD
    rotation_threshold: float = BLOCK_ROTATION_THRESHOLD
    position: bool = True
    ignore_z: bool = False

    #: The task's ``distance_threshold``.
    threshold: ClassVar[float] = DISTANCE_UNIT

    @property
    def position_scale(self) -> float:
        """What ``d_pos`` is multiplied by (1 on the block and egg)."""
        return DISTANCE_UNIT / self.position_threshold

    @property
    def rotation_scale(self) -> float:
        """What ``d_rot`` is multiplied by, m per rad."""
        return DISTANCE_UNIT / self.rotation_threshold

    def __call__(self, achieved_goal: np.ndarray, desired_goal: np.ndarray) -> np.ndarray:
        a = np.asarray(achieved_goal)
        b = np.asarray(desired_goal)
        quat_a, quat_b = a[..., GOAL_QUATERNION], b[..., GOAL_QUATERNION]
        if self.ignore_z:
            quat_a = _ignore_z_rotation(quat_a, quat_b)
        w = (quat_a * quat_b).sum(axis=-1)
        rotation = self.rotation_scale * (2.0 * np.arccos(np.clip(w, -1.0, 1.0)))
        if not self.position:
            return rotation
        diff = a[..., GOAL_POSITION] - b[..., GOAL_POSITION]
        d_pos = np.sqrt((diff * diff).sum(axis=-1))
        return np.maximum(self.position_scale * d_pos, rotation)


#: The block's (and the egg's) distance: ``max(d_pos, 0.1 m/rad * d_rot)``, threshold 0.01.
block_goal_distance = PoseDistance()
