"""The kitchen's observation groups, one line each, and its default vector.

The default vector is upstream's ``observation`` exactly (59 entries), noise included:
upstream adds uniform noise to every entry, ``robot_noise_ratio`` (0.01) times each joint's
amplitude on the robot's and ``object_noise_ratio`` (0.0005) times it on the kitchen's,
drawn from the env's generator. The goals are exact.
"""

from __future__ import annotations

from unified_manip.envs.observations import ObservationGroup as G
from unified_manip.envs.observations import goal_rel_group


def _up(start: int, stop: int):
    return lambda b: b._obs["observation"][start:stop]


def _ee(b):
    return b.data.site_xpos[b.ee_site]


GROUPS: dict[str, G] = {
    "joint_pos": G("rad, m (7 arm joints, 2 fingers; upstream's noise)", _up(0, 9)),
    "joint_vel": G("rad/s, m/s (7 arm joints, 2 fingers; upstream's noise)", _up(9, 18), "velocity"),
    "fixture_pos": G("rad, m (the kitchen's 21 qpos: fixtures, kettle pose; upstream's noise)", _up(18, 39)),
    "fixture_vel": G("rad/s, m/s (the kitchen's 20 qvel; upstream's noise)", _up(39, 59), "velocity"),
    "ee_pos": G("m (end-effector site, world; exact)", _ee),
    "goal_rel": goal_rel_group("rad, m, quaternion difference (targets - subtask joints)"),
}
DEFAULT = ("joint_pos", "joint_vel", "fixture_pos", "fixture_vel")
