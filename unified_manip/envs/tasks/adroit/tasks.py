"""What each Adroit task reads from the simulator: goals, reward quantities and
observation groups (numpy only; ``b`` is the task's
:class:`~unified_manip.envs.tasks.adroit.backend.AdroitBackend`).

Upstream's Adroit envs are not goal-conditioned; here:

* **Relocate**: achieved = the ball's position, desired = the target site's position
  (sampled by upstream's reset), m; success = distance < 0.1 m, upstream's ``success``.
  Upstream's observation holds ``palm - target`` and ``ball - target``, which depend on
  the goal: hindsight relabelling would leave them stale, so the default vector holds
  the palm's and the ball's positions instead (the goal comes as ``desired_goal``).
* **Door**: achieved = the door hinge's angle, desired = fully open, 1.57 rad (the
  hinge's upper limit); success = ``|angle - 1.57| < 0.22``, i.e. angle > 1.35 rad while
  the hinge is within its range: upstream's ``success`` (angle >= 1.35).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping

import numpy as np

from unified_manip.envs.observations import ObservationGroup as G
from unified_manip.envs.observations import goal_rel_group
from unified_manip.envs.tasks.gripper_terms import GRASPED, GRIP_TO_OBJECT

#: Relocate: the ball is off the table above this height, m (upstream's dense reward's check).
BALL_LIFTED_Z = 0.04
#: Door: the hinge's fully open angle (its upper limit), and how close counts as open, rad.
DOOR_OPEN, DOOR_TOLERANCE = 1.57, 0.22
#: Door: upstream's ``door_open`` observation entry is +1 beyond this angle, else -1, rad.
DOOR_OPEN_FLAG = 1.0


@dataclass(frozen=True)
class AdroitTask:
    """One Adroit task's readings.

    Attributes:
        sites: Site names the readings use (looked up once: ``b.site[name]``).
        bodies: Body names (``b.body[name]``).
        joints: Joint names whose ``qpos`` address the readings use (``b.qadr[name]``).
        n_joints: How many of the model's joints are the arm's and hand's (the first ones).
        achieved: ``b -> achieved goal``.
        desired: ``b -> desired goal``.
        quantities: ``b -> {name: value}`` (the term set's inputs).
        groups: The observation groups, in the ``"full"`` preset's order.
        default: The groups of the default vector.
    """

    sites: tuple[str, ...]
    bodies: tuple[str, ...]
    joints: tuple[str, ...]
    n_joints: int
    achieved: Callable[[Any], np.ndarray]
    desired: Callable[[Any], np.ndarray]
    quantities: Callable[[Any], dict[str, float]]
    groups: Mapping[str, G] = field(default_factory=dict)
    default: tuple[str, ...] = ()


def _palm(b) -> np.ndarray:
    return b.data.site_xpos[b.site["S_grasp"]]


def _joints(b) -> np.ndarray:
    return b.data.qpos[: b.task.n_joints]


def _joint_vel(b) -> np.ndarray:
    return b.data.qvel[: b.task.n_joints]


# ------------------------------------------------------------------ Relocate
def _ball(b) -> np.ndarray:
    return b.data.xpos[b.body["Object"]]


def _target(b) -> np.ndarray:
    return b.data.site_xpos[b.site["target"]]


def _relocate_quantities(b) -> dict[str, float]:
    ball = _ball(b)
    return {GRIP_TO_OBJECT: math.dist(_palm(b), ball), GRASPED: float(ball[2] > BALL_LIFTED_Z)}


RELOCATE = AdroitTask(
    sites=("S_grasp", "target"),
    bodies=("Object",),
    joints=(),
    n_joints=30,
    achieved=lambda b: _ball(b).copy(),
    desired=lambda b: _target(b).copy(),
    quantities=_relocate_quantities,
    groups={
        "joint_pos": G("m, rad (30 arm and hand joints, upstream's order)", _joints),
        "joint_vel": G("m/s, rad/s (30 arm and hand joints)", _joint_vel, "velocity"),
        "object_rel": G("m (palm - ball, upstream's)", lambda b: _palm(b) - _ball(b), "relative"),
        "ee_pos": G("m (palm site S_grasp, world)", _palm),
        "object_pos": G("m (ball centre, world)", _ball),
        "object_vel": G("m/s, rad/s (ball's 6 joints)", lambda b: b.data.qvel[30:36], "velocity"),
        "goal_rel": goal_rel_group("m (target - ball)"),
    },
    default=("joint_pos", "object_rel", "ee_pos", "object_pos"),
)


# ------------------------------------------------------------------ Door
def _hinge(b) -> np.ndarray:
    a = b.qadr["door_hinge"]
    return b.data.qpos[a : a + 1]


def _handle(b) -> np.ndarray:
    return b.data.site_xpos[b.site["S_handle"]]


def _door_quantities(b) -> dict[str, float]:
    """``grip_to_object``: palm to handle, m; ``grasped``: 0, no grasp check (as
    robosuite's Door)."""
    return {GRIP_TO_OBJECT: math.dist(_palm(b), _handle(b)), GRASPED: 0.0}


DOOR = AdroitTask(
    sites=("S_grasp", "S_handle"),
    bodies=(),
    joints=("door_hinge", "latch"),
    n_joints=28,
    achieved=lambda b: _hinge(b).copy(),
    desired=lambda b: np.array([DOOR_OPEN]),
    quantities=_door_quantities,
    groups={
        "joint_pos": G("m, rad (28 arm and hand joints, upstream's order)", _joints),
        "joint_vel": G("m/s, rad/s (28 arm and hand joints)", _joint_vel, "velocity"),
        "latch": G("rad (latch angle)", lambda b: b.data.qpos[b.qadr["latch"] : b.qadr["latch"] + 1]),
        "hinge": G("rad (door hinge angle)", _hinge),
        "ee_pos": G("m (palm site S_grasp, world)", _palm),
        "handle_pos": G("m (handle site, world)", _handle),
        "object_rel": G("m (palm - handle, upstream's)", lambda b: _palm(b) - _handle(b), "relative"),
        "door_open": G(
            "+1 beyond 1 rad, else -1 (upstream's)", lambda b: np.where(_hinge(b) > DOOR_OPEN_FLAG, 1.0, -1.0)
        ),
        "goal_rel": goal_rel_group("rad (1.57 - hinge angle)"),
    },
    default=("joint_pos", "latch", "hinge", "ee_pos", "handle_pos", "object_rel", "door_open"),
)

TASKS = {"Relocate": RELOCATE, "Door": DOOR}
