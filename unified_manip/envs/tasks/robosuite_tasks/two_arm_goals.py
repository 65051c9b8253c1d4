"""The goal tasks of robosuite's two-arm envs, TwoArmLift and TwoArmHandover: two Pandas
facing each other across the table (robosuite's default ``opposed`` configuration).

* **TwoArmLift:** the achieved goal is the position of the pot's centre (robosuite's
  ``pot_center`` site, m, world frame); the desired goal is that point at reset raised by
  U(0.16, 0.22) m. Within the 5 cm threshold the pot's bottom is then more than 10 cm above
  the table, which is robosuite's own success (``native_success``), so success here implies
  robosuite's. The ee modes turn both grippers with the pot at reset (``ee_yaw``), so their
  fingers close across the handles' bars. Both arms reach: ``grip_to_object`` is the farther of each gripper's distance
  to its own handle (arm 0 to handle 0, arm 1 to handle 1), and ``grasped`` is 1 while each
  gripper holds its own handle (robosuite's grasp check).
* **TwoArmHandover:** the hammer starts on the table by arm 0; robosuite's success is "arm 1
  holds the handle, arm 0 holds no part of the hammer, and the hammer is more than 10 cm
  above the table". The goal is those three checks, as robosuite's ``_get_task_info`` makes
  them: achieved ``(arm 0 holds the hammer, arm 1 holds its handle, hammer lifted)`` as 0/1,
  desired ``(0, 1, 1)``, within 0.5: every flag must match, so ``is_success`` is exactly
  robosuite's ``_check_success()`` (``goal_is_success``). The reach term draws arm 1 to the
  handle and ``grasped`` is arm 1's grasp of it. The ee modes turn both grippers with the
  handle at reset (``ee_yaw``), so their fingers close across it.
"""

from __future__ import annotations

import numpy as np

from unified_manip.envs.tasks.robosuite_tasks.goals import RobosuiteTask

#: TwoArmLift: how far above its place at reset the pot's centre must go, m.
POT_RISE = (0.16, 0.22)


def _pot_center(up) -> np.ndarray:
    return up.sim.data._data.site_xpos[up.pot_center_id]


def _pot_goal(up, rng: np.random.Generator) -> np.ndarray:
    return _pot_center(up) + np.array([0.0, 0.0, rng.uniform(*POT_RISE)])


def _pot_handles(up) -> np.ndarray:
    sites = up.sim.data._data.site_xpos
    return np.stack((sites[up.handle0_site_id], sites[up.handle1_site_id]))


def _pot_yaw(up) -> float:
    """How far the pot is turned about z from robosuite's nominal placement (yaw pi, the
    handles on the line between the robots), rad: the grippers turn as much, so their
    fingers close across the handles' bars."""
    v = _pot_handles(up)[0] - _pot_handles(up)[1]  # nominally along -y
    return float(np.arctan2(v[0], -v[1])) + np.pi / 2


def _handle_geoms(up) -> tuple:
    return (up.pot.handle0_geoms, up.pot.handle1_geoms)


def _handover_flags(up) -> np.ndarray:
    arm0_holds, arm1_holds_handle, hammer_z, table_z = up._get_task_info()
    return np.array([float(arm0_holds), float(arm1_holds_handle), float(hammer_z - table_z > up.height_threshold)])


def _handover_goal(up, rng: np.random.Generator) -> np.ndarray:
    return np.array([0.0, 1.0, 1.0])


def _hammer_handle(up) -> np.ndarray:
    return up.sim.data._data.geom_xpos[up.hammer_handle_geom_id]


def _handle_yaw(up) -> float:
    """The hammer handle's heading about z at reset, turned a quarter (rad): the grippers
    turn as much, so their fingers close across the handle."""
    axis = up.sim.data._data.geom_xmat[up.hammer_handle_geom_id].reshape(3, 3)[:, 2]
    return float(np.arctan2(-axis[1], -axis[0])) + np.pi / 2


def _handle_of_hammer(up):
    return up.hammer.handle_geoms


TWO_ARM_TASK_DEFS: dict[str, RobosuiteTask] = {
    "TwoArmLift": RobosuiteTask(
        "TwoArmLift", _pot_center, _pot_goal, _pot_handles, _handle_geoms, robots=2, reachers=(0, 1), ee_yaw=_pot_yaw
    ),
    "TwoArmHandover": RobosuiteTask(
        "TwoArmHandover",
        _handover_flags,
        _handover_goal,
        _hammer_handle,
        _handle_of_hammer,
        goal_is_success=True,
        robots=2,
        reachers=(1,),
        ee_yaw=_handle_yaw,
    ),
}
