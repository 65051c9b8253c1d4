"""The Shadow Hand's observation groups, one line each (slices of upstream's vector
``[robot_qpos, robot_qvel, (object_qvel,) achieved_goal]``), and its default vectors."""

from __future__ import annotations

from unified_manip.envs.observations import ObservationGroup as G
from unified_manip.envs.observations import goal_rel_group


def _up(start: int, stop: int):
    return lambda b: b._obs["observation"][start:stop]


_JOINTS: dict[str, G] = {
    "joint_pos": G("rad (24 hand joints)", _up(0, 24)),
    "joint_vel": G("rad/s (24 hand joints)", _up(24, 48), "velocity"),
}
REACH_GROUPS: dict[str, G] = {
    **_JOINTS,
    "fingertip_pos": G("m (5 fingertips, world)", _up(48, 63)),
    "goal_rel": goal_rel_group("m (goal - fingertips)"),
}


def object_groups(name: str) -> dict[str, G]:
    """The groups of a task with an object on the palm (``name``: the block, egg or pen)."""
    return {
        **_JOINTS,
        "object_vel": G(f"m/s, rad/s ({name} free joint)", _up(48, 54), "velocity"),
        "object_pos": G(f"m ({name} centre, world)", _up(54, 57)),
        "object_rot": G("quaternion (w, x, y, z)", _up(57, 61)),
        "goal_rel": goal_rel_group(f"m, quaternion difference (goal - {name} pose)"),
    }


#: The groups of each object's tasks, by the object's name.
OBJECT_GROUPS: dict[str, dict[str, G]] = {name: object_groups(name) for name in ("block", "egg", "pen")}
REACH_DEFAULT = ("joint_pos", "joint_vel", "fingertip_pos")
OBJECT_DEFAULT = ("joint_pos", "joint_vel", "object_vel", "object_pos", "object_rot")
