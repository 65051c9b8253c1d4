"""Fetch's observation groups, one line each (slices of upstream's vector, whose velocities
are upstream's: multiplied by the step's dt), and its default vectors (no simulator)."""

from __future__ import annotations

from unified_manip.envs.observations import ObservationGroup as G
from unified_manip.envs.observations import goal_rel_group


def _up(s: slice):
    return lambda b: b._obs["observation"][s]


_ROBOT: dict[str, G] = {
    "joint_pos": G("rad (7 arm joints)", lambda b: b.data.qpos[b._arm_q]),
    "joint_vel": G("rad/s (7 arm joints)", lambda b: b.data.qvel[b._arm_v], "velocity"),
}
#: FetchReach's groups: upstream's ``[grip_pos, gripper_state, grip_velp, gripper_vel]``.
REACH_GROUPS: dict[str, G] = {
    "ee_pos": G("m (grip site, world)", _up(slice(0, 3))),
    "gripper": G("m (finger joint positions)", _up(slice(3, 5))),
    "ee_vel": G("m per step (grip site velocity x dt)", _up(slice(5, 8)), "velocity"),
    "gripper_vel": G("m per step (finger velocities x dt)", _up(slice(8, 10)), "velocity"),
    **_ROBOT,
    "goal_rel": goal_rel_group("m (goal - grip site)"),
}
#: The object tasks' groups: upstream's ``[grip_pos, object_pos, object_rel_pos,
#: gripper_state, object_rot, object_velp, object_velr, grip_velp, gripper_vel]``.
OBJECT_GROUPS: dict[str, G] = {
    "ee_pos": G("m (grip site, world)", _up(slice(0, 3))),
    "object_pos": G("m (object centre, world)", _up(slice(3, 6))),
    "object_rel": G("m (object - grip site)", _up(slice(6, 9)), "relative"),
    "gripper": G("m (finger joint positions)", _up(slice(9, 11))),
    "object_rot": G("rad (Euler angles)", _up(slice(11, 14))),
    "object_vel": G("m, rad per step (x dt; linear part relative to the grip site)", _up(slice(14, 20)), "velocity"),
    "ee_vel": G("m per step (grip site velocity x dt)", _up(slice(20, 23)), "velocity"),
    "gripper_vel": G("m per step (finger velocities x dt)", _up(slice(23, 25)), "velocity"),
    **_ROBOT,
    "goal_rel": goal_rel_group("m (goal - object)"),
}

#: Upstream's vectors, group by group; the joint modes append the arm's joints.
REACH_DEFAULT = ("ee_pos", "gripper", "ee_vel", "gripper_vel")
OBJECT_DEFAULT = ("ee_pos", "object_pos", "object_rel", "gripper", "object_rot", "object_vel", "ee_vel", "gripper_vel")
JOINT_MODE_EXTRA = ("joint_pos", "joint_vel")
