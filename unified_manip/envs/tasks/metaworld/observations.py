"""The Meta-World tasks' observation groups and reward quantities (numpy only; ``b`` is
the task's :class:`~unified_manip.envs.tasks.metaworld.backend.MetaWorldBackend`).

The default vector is Meta-World's own observation without its last three entries, the
goal (which comes as ``desired_goal``; Meta-World's multi-task benchmarks show it, its
meta-learning ones zero it): ``[hand, gripper, objects]`` of this step and of the last,
36 numbers, so that ``concat(observation, desired_goal)`` is Meta-World's 39. From
version 2 on, the joint modes' vector also holds the robot's joints and their velocities
(:data:`JOINT_MODE_EXTRA`), as Fetch's does: a policy that commands joints sees them.
"""

from __future__ import annotations

import math

import numpy as np

from unified_manip.envs.observations import ObservationGroup as G
from unified_manip.envs.observations import goal_rel_group
from unified_manip.envs.tasks.gripper_terms import GRASPED, GRIP_TO_OBJECT

#: The arm's 7 joints and the 2 fingers' slides: the first 9 entries of qpos and qvel.
ROBOT_JOINTS = 9

#: Meta-World's observation: hand, gripper, objects (14: two objects' position and
#: quaternion, zero-padded), then the same of the last step, then the goal.
HAND, GRIPPER, OBJECTS, PREVIOUS = slice(0, 3), slice(3, 4), slice(4, 18), slice(18, 36)
OBSERVATION_SIZE = 36


def _part(s: slice):
    return lambda b: b.upstream_obs[s]


GROUPS: dict[str, G] = {
    "ee_pos": G("m (the hand body, world)", _part(HAND)),
    "gripper": G("- (fingers' distance / 0.1 m, clipped to [0, 1])", _part(GRIPPER)),
    "object_pose": G(
        "m, - (each object's position and quaternion (w, x, y, z or scipy's x, y, z, w, as "
        "Meta-World's task returns it), zero-padded to two objects)",
        _part(OBJECTS),
    ),
    "previous": G("the last step's ee_pos, gripper, object_pose (Meta-World's frame stack)", _part(PREVIOUS)),
    "joint_pos": G("rad, m (the arm's 7 joints, then the 2 finger slides)", lambda b: b.data.qpos[:ROBOT_JOINTS]),
    "joint_vel": G("rad/s, m/s (the same joints)", lambda b: b.data.qvel[:ROBOT_JOINTS], "velocity"),
    "object_rel": G(
        "m (the first object - the fingertips' midpoint)", lambda b: b.upstream_obs[4:7] - b.tcp(), "relative"
    ),
    "goal_rel": goal_rel_group("m (target - achieved goal)"),
}

#: The groups of the default vector: Meta-World's observation without the goal.
DEFAULT = ("ee_pos", "gripper", "object_pose", "previous")

#: What the joint modes' default vector appends from version 2 on: the 7 arm joints and the
#: 2 finger slides, then their velocities (18).
JOINT_MODE_EXTRA = ("joint_pos", "joint_vel")


def quantities(b) -> dict[str, float]:
    """``grip_to_object``: the fingertips' midpoint to the first object, m (0 on the
    reach tasks, which have none); ``grasped``: 1.0 while both finger pads touch one
    body other than the robot's."""
    if b.task.terms == "reach":
        return {GRIP_TO_OBJECT: 0.0, GRASPED: 0.0}
    return {GRIP_TO_OBJECT: math.dist(b.tcp(), b.upstream_obs[4:7]), GRASPED: float(b.pads_on_one_body())}


def pads_touch_one_body(model, data, pads: tuple[int, int], robot: np.ndarray) -> bool:
    """Whether both pad geoms touch a geom of one body that is not the robot's (``robot``:
    a flag per body)."""
    n = data.ncon
    if n == 0:
        return False
    g1, g2 = data.contact.geom1[:n], data.contact.geom2[:n]
    b1, b2 = model.geom_bodyid[g1], model.geom_bodyid[g2]
    touched = []
    for pad in pads:
        other = np.where(g1 == pad, b2, np.where(g2 == pad, b1, -1))
        other = other[other >= 0]
        touched.append(set(other[~robot[other]].tolist()))
    return bool(touched[0] & touched[1])
