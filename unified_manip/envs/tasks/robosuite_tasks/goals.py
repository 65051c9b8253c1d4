"""How each robosuite env becomes a goal task: achieved goal, goal sampling, object."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable

import mujoco
import numpy as np


@dataclass(frozen=True)
class RobosuiteTask:
    """How one robosuite env becomes a goal task.

    Attributes:
        env_name: robosuite's env name.
        achieved: The achieved goal from the upstream env.
        sample_goal: ``(upstream env, np_random) -> desired goal``, called after reset.
        object_pos: The object the gripper must reach (for ``grip_to_object``); with
            several ``reachers``, one row per reacher, ``(k, 3)``.
        grasp_object: The robosuite object whose grasp ``grasped`` reports, or None; with
            several ``reachers``, one per reacher (``grasped``: every one holds its own).
        ee_turn: The gripper orientation ``ee_delta`` holds: the grip site's orientation
            at reset turned by this rotation (a rotation vector in the world frame, rad).
            Zero holds the reset orientation (gripper pointing down).
        goal_is_success: robosuite's ``_check_success()`` is "the achieved goal equals the
            desired goal": ``native_success`` is read off the achieved goal of the step
            instead of running the checks again.
        robots: How many robots robosuite's env takes (2 for the two-arm tasks).
        reachers: The robots whose grip sites ``grip_to_object`` measures (the largest of
            their distances to their rows of ``object_pos``) and whose grasps ``grasped``
            checks.
        ee_yaw: If set, a further turn about world z of the held orientation, read from
            the env at each reset (rad): TwoArmLift turns the grippers with the pot.
    """

    env_name: str
    achieved: Callable[[Any], np.ndarray]
    sample_goal: Callable[[Any, np.random.Generator], np.ndarray]
    object_pos: Callable[[Any], np.ndarray]
    grasp_object: Callable[[Any], Any] | None
    ee_turn: tuple[float, float, float] = (0.0, 0.0, 0.0)
    goal_is_success: bool = False
    robots: int = 1
    reachers: tuple[int, ...] = (0,)
    ee_yaw: Callable[[Any], float] | None = None

    def grasp_objects(self, up) -> tuple[Any, ...] | None:
        """One grasp object per reacher, or None."""
        if self.grasp_object is None:
            return None
        held = self.grasp_object(up)
        return tuple(held) if len(self.reachers) > 1 else (held,)

    def held_rotation(self, reset_rotation: np.ndarray, up: Any = None) -> np.ndarray:
        """The grip-site rotation matrix ``ee_delta`` holds, given the one at reset (and,
        where the task turns it by ``ee_yaw``, the env just reset)."""
        held = _turned(reset_rotation, np.asarray(self.ee_turn, dtype=np.float64))
        if self.ee_yaw is not None:
            held = _turned(held, np.array([0.0, 0.0, self.ee_yaw(up)]))
        return held


def _turned(rotation: np.ndarray, turn: np.ndarray) -> np.ndarray:
    """``rotation`` turned by the rotation vector ``turn`` (world frame, rad)."""
    angle = float(np.linalg.norm(turn))
    if angle == 0.0:
        return rotation.copy()
    quat, mat = np.zeros(4), np.zeros(9)
    mujoco.mju_axisAngle2Quat(quat, turn / angle, angle)
    mujoco.mju_quat2Mat(mat, quat)
    return mat.reshape(3, 3) @ rotation


def _body_pos(attr: str):
    def get(up) -> np.ndarray:
        return up.sim.data._data.xpos[getattr(up, attr)]

    return get


def obj_body_pos(name: str):
    def get(up) -> np.ndarray:
        return up.sim.data._data.xpos[up.obj_body_id[name]]

    return get


#: Lift: table top height and the desired-goal box above it.
LIFT_XY, LIFT_Z = 0.1, (0.10, 0.20)


def _lift_goal(up, rng: np.random.Generator) -> np.ndarray:
    top = up.model.mujoco_arena.table_offset[2]
    return np.array([rng.uniform(-LIFT_XY, LIFT_XY), rng.uniform(-LIFT_XY, LIFT_XY), top + rng.uniform(*LIFT_Z)])


#: PickPlaceCan: margin kept from the quadrant's walls, and the goal height above the bin floor.
CAN_MARGIN, CAN_Z = 0.05, 0.05


def bin_quadrant(up, key: str) -> tuple[float, float, float, float]:
    """x/y bounds of object ``key``'s quadrant of bin 2 (``"can"``, ``"milk"``, ...), as
    robosuite's ``not_in_bin``."""
    bin_id = up.object_to_id[key]
    x_low, y_low = up.bin2_pos[0], up.bin2_pos[1]
    if bin_id in (0, 2):
        x_low -= up.bin_size[0] / 2
    if bin_id < 2:
        y_low -= up.bin_size[1] / 2
    return x_low, x_low + up.bin_size[0] / 2, y_low, y_low + up.bin_size[1] / 2


@dataclass(frozen=True)
class BinGoal:
    """A PickPlace goal: a point of object ``key``'s quadrant of bin 2, ``margin`` m from
    its walls, ``z`` m above the bin's origin (picklable, unlike a closure)."""

    key: str
    z: float
    margin: float = CAN_MARGIN

    def __call__(self, up, rng: np.random.Generator) -> np.ndarray:
        x0, x1, y0, y1 = bin_quadrant(up, self.key)
        m = self.margin
        return np.array([rng.uniform(x0 + m, x1 - m), rng.uniform(y0 + m, y1 - m), up.bin2_pos[2] + self.z])


_can_goal = BinGoal("can", CAN_Z)


#: Stack: cube half-sizes (robosuite: A 2 cm, B 2.5 cm).
STACK_HEIGHT = 0.02 + 0.025


def _stack_goal(up, rng: np.random.Generator) -> np.ndarray:
    return up.sim.data._data.xpos[up.cubeB_body_id] + np.array([0.0, 0.0, STACK_HEIGHT])


#: NutAssemblyRound: the nut body's height above the table when it rests around the
#: peg, and the sampled extra height along the peg.
NUT_REST_Z, NUT_Z_RANGE = 0.0, (0.005, 0.02)


@dataclass(frozen=True)
class NutGoal:
    """A NutAssembly goal: the axis of the peg whose body id is ``up.<peg>``, at a height
    ``NUT_REST_Z`` + U(``NUT_Z_RANGE``) above the table top."""

    peg: str

    def __call__(self, up, rng: np.random.Generator) -> np.ndarray:
        peg = up.sim.data._data.xpos[getattr(up, self.peg)]
        return np.array([peg[0], peg[1], up.table_offset[2] + NUT_REST_Z + rng.uniform(*NUT_Z_RANGE)])


_nut_goal = NutGoal("peg2_body_id")


#: Door: the target hinge angle range, rad (the hinge's range is [0, 0.4]).
DOOR_GOAL = (0.35, 0.40)


def _door_goal(up, rng: np.random.Generator) -> np.ndarray:
    return np.array([rng.uniform(*DOOR_GOAL)])


def _door_angle(up) -> np.ndarray:
    return up.sim.data._data.qpos[up.hinge_qpos_addr : up.hinge_qpos_addr + 1]


def _door_handle(up) -> np.ndarray:
    return up.sim.data._data.site_xpos[up.door_handle_site_id]


TASK_DEFS: dict[str, RobosuiteTask] = {
    "Lift": RobosuiteTask("Lift", _body_pos("cube_body_id"), _lift_goal, _body_pos("cube_body_id"), lambda up: up.cube),
    "Stack": RobosuiteTask(
        "Stack", _body_pos("cubeA_body_id"), _stack_goal, _body_pos("cubeA_body_id"), lambda up: up.cubeA
    ),
    "PickPlaceCan": RobosuiteTask(
        "PickPlaceCan", obj_body_pos("Can"), _can_goal, obj_body_pos("Can"), lambda up: up.objects[up.object_id]
    ),
    "NutAssemblyRound": RobosuiteTask(
        "NutAssemblyRound", obj_body_pos("RoundNut"), _nut_goal, obj_body_pos("RoundNut"), lambda up: up.nuts[1]
    ),
    # The gripper points at the door (a quarter turn about world x), its fingers one above
    # the other: pointing down, the hand hits the door panel and the handle's base.
    "Door": RobosuiteTask("Door", _door_angle, _door_goal, _door_handle, None, ee_turn=(-math.pi / 2, 0.0, 0.0)),
}
