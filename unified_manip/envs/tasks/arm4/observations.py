"""The 4-DOF arm's observation groups, one line each, and its default vectors (no simulator)."""

from __future__ import annotations

import mujoco
import numpy as np

from unified_manip.envs.observations import ObservationGroup as G
from unified_manip.envs.observations import goal_rel_group
from unified_manip.envs.tasks.arm4.scene import QPOS_ARM, QPOS_CUBE_POS, QPOS_FINGERS

QPOS_CUBE_QUAT, QVEL_CUBE = slice(9, 13), slice(6, 12)


def _grip(b) -> np.ndarray:
    return b.data.site_xpos[b.rig.site_id]


def _grip_vel(b) -> np.ndarray:
    res = np.zeros(6)
    mujoco.mj_objectVelocity(b.model, b.data, mujoco.mjtObj.mjOBJ_SITE, b.rig.site_id, res, 0)
    return res[3:]  # world-frame linear velocity


#: Groups of every arm task.
ROBOT_GROUPS: dict[str, G] = {
    "joint_pos": G("rad", lambda b: b.data.qpos[QPOS_ARM]),
    "gripper": G("m (finger joint positions)", lambda b: b.data.qpos[QPOS_FINGERS]),
    "joint_vel": G("rad/s", lambda b: b.data.qvel[QPOS_ARM], "velocity"),
    "gripper_vel": G("m/s (finger joint velocities)", lambda b: b.data.qvel[QPOS_FINGERS], "velocity"),
    "ee_pos": G("m (grip site, world)", _grip),
    "ee_vel": G("m/s (grip site, world)", _grip_vel, "velocity"),
}
#: Groups of the tasks with the cube.
OBJECT_GROUPS: dict[str, G] = {
    **ROBOT_GROUPS,
    "object_pos": G("m (cube centre, world)", lambda b: b.data.qpos[QPOS_CUBE_POS]),
    "object_rot": G("quaternion (w, x, y, z)", lambda b: b.data.qpos[QPOS_CUBE_QUAT]),
    "object_vel": G("m/s, rad/s (cube free joint)", lambda b: b.data.qvel[QVEL_CUBE], "velocity"),
    "object_rel": G("m (cube - grip site)", lambda b: b.data.qpos[QPOS_CUBE_POS] - _grip(b), "relative"),
    "goal_rel": goal_rel_group("m (goal - cube)"),
}
REACH_GROUPS: dict[str, G] = {**ROBOT_GROUPS, "goal_rel": goal_rel_group("m (goal - grip site)")}

#: Today's vectors (``Arm4Backend.observation``), group by group.
REACH_DEFAULT = ("joint_pos", "gripper", "joint_vel", "gripper_vel", "ee_pos", "goal_rel")
OBJECT_DEFAULT = (
    "joint_pos",
    "gripper",
    "object_pos",
    "object_rot",
    "joint_vel",
    "gripper_vel",
    "object_vel",
    "ee_pos",
    "object_rel",
    "goal_rel",
)
