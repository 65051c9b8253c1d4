"""The goal tasks of robosuite's other one-arm envs: PickPlaceMilk, PickPlaceBread,
PickPlaceCereal, NutAssemblySquare, Wipe and ToolHang (:data:`TASKS` holds them with
:data:`.goals.TASK_DEFS`'s).

The pick, place and nut tasks are goal tasks as PickPlaceCan and NutAssemblyRound are.
Wipe and ToolHang have no point to carry an object to; their goals are the quantities
robosuite's own success reads, so ``is_success`` is robosuite's ``_check_success()``:

* **Wipe:** the fraction of the markers wiped (achieved) against 1 (desired), within half
  a marker. The object the reach term draws the gripper to is the centroid of the
  markers left.
* **ToolHang:** two flags, whether the frame stands in the stand and whether the tool hangs
  on the frame (robosuite's ``_check_frame_assembled`` and ``_check_tool_on_frame``),
  against (1, 1), within 0.5 (both must hold). The reach term's object follows the stage:
  the frame (its corner site) until it stands, then the tool.

The goals read the simulator's state as robosuite's success and reward do, at the end of
the step (robosuite's observables are sampled at its first substep). On both,
``native_success`` is read off the achieved goal (``goal_is_success``), which holds the
very checks ``_check_success()`` makes, so they are not made twice a step.
"""

from __future__ import annotations

import weakref
from typing import Any

import numpy as np

from unified_manip.envs.tasks.robosuite_tasks.goals import TASK_DEFS, BinGoal, NutGoal, RobosuiteTask, obj_body_pos
from unified_manip.envs.tasks.robosuite_tasks.two_arm_goals import TWO_ARM_TASK_DEFS

#: Each PickPlace object's goal height above bin 2's origin, m: its centre's height when it
#: stands on the bin floor (measured: milk 0.081, bread 0.043, cereal 0.095; the can's
#: 0.060 against its goal's 0.05), inside robosuite's band of success (up to 0.1).
BIN_Z = {"milk": 0.08, "bread": 0.045, "cereal": 0.095}


#: Each Wipe env's marker body ids, in robosuite's marker order, and each marker's index
#: by ``id``, looked up once (robosuite looks every marker up by name at every call).
_MARKERS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _markers(up) -> tuple[np.ndarray, dict[int, int]]:
    if up not in _MARKERS:
        markers = up.model.mujoco_arena.markers
        ids = np.array([up.sim.model.body_name2id(m.root_body) for m in markers])
        _MARKERS[up] = (ids, {id(m): i for i, m in enumerate(markers)})
    return _MARKERS[up]


def _wiped(up) -> np.ndarray:
    return np.array([len(up.wiped_markers) / up.num_markers])


def _wipe_goal(up, rng: np.random.Generator) -> np.ndarray:
    return np.ones(1)


def _wipe_target(up) -> np.ndarray:
    """The centroid of the markers left (robosuite's ``wipe_centroid``, from the current
    state); the grip site once every marker is wiped."""
    data = up.sim.data._data
    if len(up.wiped_markers) == up.num_markers:
        return data.site_xpos[up.robots[0].eef_site_id["right"]]
    ids, index = _markers(up)
    left = np.ones(len(ids), dtype=bool)
    left[[index[id(m)] for m in up.wiped_markers]] = False
    return data.xpos[ids[left]].mean(axis=0)


def _hang_stages(up) -> np.ndarray:
    return np.array([float(up._check_frame_assembled()), float(up._check_tool_on_frame())])


def _hang_goal(up, rng: np.random.Generator) -> np.ndarray:
    return np.ones(2)


def _hang_target(up) -> np.ndarray:
    """The frame's corner until the frame stands in the stand, then the tool. The stage is
    robosuite's ``frame_is_assembled`` observable of this step (sampled at its first
    substep): the check is not run a second time for the reach term."""
    data = up.sim.data._data
    if up._observables["frame_is_assembled"].obs:
        return data.xpos[up.obj_body_id["tool"]]
    return data.site_xpos[up.obj_site_id["frame_intersection_site"]]


def _pick_place(name: str) -> RobosuiteTask:
    key = name.lower()
    return RobosuiteTask(
        f"PickPlace{name}", obj_body_pos(name), BinGoal(key, BIN_Z[key]), obj_body_pos(name), _placed_object
    )


def _placed_object(up) -> Any:
    return up.objects[up.object_id]


MORE_TASK_DEFS: dict[str, RobosuiteTask] = {
    "PickPlaceMilk": _pick_place("Milk"),
    "PickPlaceBread": _pick_place("Bread"),
    "PickPlaceCereal": _pick_place("Cereal"),
    "NutAssemblySquare": RobosuiteTask(
        "NutAssemblySquare",
        obj_body_pos("SquareNut"),
        NutGoal("peg1_body_id"),
        obj_body_pos("SquareNut"),
        lambda up: up.nuts[0],
    ),
    "Wipe": RobosuiteTask("Wipe", _wiped, _wipe_goal, _wipe_target, None, goal_is_success=True),
    "ToolHang": RobosuiteTask("ToolHang", _hang_stages, _hang_goal, _hang_target, None, goal_is_success=True),
}

#: Every robosuite task, by name.
TASKS: dict[str, RobosuiteTask] = TASK_DEFS | MORE_TASK_DEFS | TWO_ARM_TASK_DEFS
