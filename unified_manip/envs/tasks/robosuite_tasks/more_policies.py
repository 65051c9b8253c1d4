"""Scripted ``ee_delta`` policies of PickPlaceMilk, PickPlaceBread, PickPlaceCereal and
NutAssemblySquare (dx, dy, dz, gripper: -1 closed, +1 open), on the Panda observation
layout of :mod:`.policies`. They are memoryless."""

from __future__ import annotations

import math
from functools import partial

import numpy as np

from unified_manip.envs.tasks.robosuite_tasks.policies import EEF, PROPRIO, _closing_speed, _opening
from unified_manip.envs.tasks.scripted import toward


def _bin_policy(obs: dict[str, np.ndarray], held: tuple[float, float], carry: float, grip: float) -> np.ndarray:
    """PickPlaceCan's policy for another object: grasp it from above, lift it ``carry`` m
    above the goal, carry it across, lower it over the goal and let go, back up.

    Args:
        held: The finger openings, m, between which the fingers hold the object.
        carry: The object centre's height above the goal while carried, m.
        grip: The height above the object's centre the fingers close at, m (the hand
            must stay above a tall object's top).
    """
    o = obs["observation"]
    eef, obj, goal = o[EEF], obs["achieved_goal"], obs["desired_goal"]
    to_obj, to_goal = obj + np.array([0.0, 0.0, grip]) - eef, goal - obj
    opening = _opening(o)
    if np.linalg.norm(to_goal[:2]) < 0.045 and obj[2] < goal[2] + 0.07:  # low over the goal: let go
        return np.array([0.0, 0.0, 0.5 if opening > 0.07 else 0.0, 1.0])  # back up once open
    near = np.linalg.norm(to_obj[:2]) < 0.04 and abs(to_obj[2]) < 0.05
    if near and held[0] < opening < held[1]:  # closing on, or holding, the object
        if _closing_speed(o) > 0.02:  # still closing: wait
            return np.array([0.0, 0.0, 0.0, -1.0])
        carry_z = goal[2] + carry
        if np.linalg.norm(to_goal[:2]) > 0.02:
            if obj[2] < carry_z - 0.03:  # up first, then across
                move = np.array([0.3 * to_goal[0], 0.3 * to_goal[1], carry_z + 0.02 - obj[2]])
            else:
                move = np.array([to_goal[0], to_goal[1], carry_z - obj[2]])
            return np.append(toward(move) * 0.6, -1.0)
        return np.append(toward(to_goal) * 0.6, -1.0)
    xy = np.linalg.norm(to_obj[:2])
    if xy < 0.015 and abs(to_obj[2]) < 0.012 and opening >= 0.07:  # in place: close
        return np.array([0.0, 0.0, 0.0, -1.0])
    if xy > 0.01:  # line up above the object, open
        return np.append(toward(to_obj + np.array([0.0, 0.0, 0.1])), 1.0)
    return np.append(toward(to_obj, 30.0), 1.0)  # a higher gain: the arm sags short of a small step


#: Per object: the openings that hold it (m) and the carrying height above the goal (m),
#: which clears the bins' walls with the object's bottom.
milk_policy = partial(_bin_policy, held=(0.025, 0.07), carry=0.14, grip=0.045)
bread_policy = partial(_bin_policy, held=(0.025, 0.07), carry=0.13, grip=0.0)
cereal_policy = partial(_bin_policy, held=(0.015, 0.07), carry=0.15, grip=0.04)

#: Square nut layout (after the proprio): its position, then quaternion (x, y, z, w).
NUT_POS, NUT_QUAT = slice(PROPRIO + 7, PROPRIO + 10), slice(PROPRIO + 10, PROPRIO + 14)
#: The handle's centre in the nut's frame, m (robosuite's square-nut.xml ``handle_site``).
NUT_HANDLE = 0.054
#: Height of the nut's centre above the goal while carried: the nut clears the peg's top
#: (13 cm above the table), m.
NUT_CARRY = 0.15
#: The nut is let go once its centre is this far above the goal, over the peg: at the peg's
#: top. Held by the handle, the nut tilts and catches on the peg's top; let go, it levels
#: and drops down the peg.
NUT_DROP = 0.14


def _yaw(quat_xyzw: np.ndarray) -> float:
    x, y, z, w = quat_xyzw
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def nut_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    """Grasp the square nut by its handle from above, raise it over the peg, lower its
    centre onto the peg's axis, let go, back up."""
    o = obs["observation"]
    eef, nut, goal = o[EEF], o[NUT_POS], obs["desired_goal"]
    yaw = _yaw(o[NUT_QUAT])
    handle = nut + NUT_HANDLE * np.array([math.cos(yaw), math.sin(yaw), 0.0])
    to_handle, to_goal = handle - eef, goal - nut
    opening = _opening(o)
    if np.linalg.norm(to_goal[:2]) < 0.006 and nut[2] < goal[2] + NUT_DROP:  # on the peg: let go, back up
        return np.array([0.0, 0.0, 0.5 if opening > 0.07 else 0.0, 1.0])
    near = np.linalg.norm(to_handle[:2]) < 0.03 and abs(to_handle[2]) < 0.03
    if near and 0.005 < opening < 0.07:  # closing on, or holding, the handle
        if _closing_speed(o) > 0.02:
            return np.array([0.0, 0.0, 0.0, -1.0])
        carry_z = goal[2] + NUT_CARRY
        xy = np.linalg.norm(to_goal[:2])
        if xy > 0.003 and nut[2] < carry_z - 0.03:  # up first
            move = np.array([0.2 * to_goal[0], 0.2 * to_goal[1], carry_z + 0.02 - nut[2]])
        elif xy > 0.003:  # across, at the carrying height
            move = np.array([2.0 * to_goal[0], 2.0 * to_goal[1], carry_z - nut[2]])
        else:  # down the peg, centring
            move = np.array([3.0 * to_goal[0], 3.0 * to_goal[1], -0.05])
        return np.append(toward(move, 15.0) * 0.7, -1.0)
    xy = np.linalg.norm(to_handle[:2])
    if xy < 0.008 and to_handle[2] > -0.008 and opening >= 0.07:  # in place: close
        return np.array([0.0, 0.0, 0.0, -1.0])
    if xy > 0.006:  # line up above the handle, open
        return np.append(toward(to_handle + np.array([0.0, 0.0, 0.08])), 1.0)
    return np.append(
        toward(to_handle - np.array([0.0, 0.0, 0.006]), 30.0), 1.0
    )  # a higher gain: the arm sags short of a small step
