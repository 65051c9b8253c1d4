"""Scripted ``ee_delta`` policies of the robosuite tasks (dx, dy, dz, gripper: -1 closed,
+1 open) on the Panda observation layout. They are memoryless."""

from __future__ import annotations

import math

import numpy as np

from unified_manip.envs.tasks.scripted import toward

#: Panda proprio layout: eef position (m, world).
EEF = slice(35, 38)
#: Panda's two finger joints in the proprio vector: positions (m), then velocities (m/s).
FINGER_QPOS, FINGER_QVEL = slice(46, 48), slice(48, 50)
PROPRIO = 50


def _opening(o: np.ndarray) -> float:
    """Panda finger opening, m (0.08 open)."""
    left, right = o[FINGER_QPOS]
    return left - right


def _closing_speed(o: np.ndarray) -> float:
    """How fast the fingers close or open, m/s."""
    left, right = o[FINGER_QVEL]
    return abs(left - right)


def _pick_and_carry(obs: dict[str, np.ndarray], lift_first: float = 0.0) -> np.ndarray:
    """Above the object, descend open, close, then carry it to the goal (raising it
    ``lift_first`` m above the goal height before moving sideways, if set)."""
    o = obs["observation"]
    eef = o[EEF]
    obj = obs["achieved_goal"]
    goal = obs["desired_goal"]
    to_obj = obj - eef
    opening = _opening(o)  # Panda finger opening, m (0.08 open)
    closing_speed = _closing_speed(o)  # m/s
    xy = np.linalg.norm(to_obj[:2])
    if xy < 0.02 and abs(to_obj[2]) < 0.04 and opening < 0.07:
        if closing_speed > 0.02:  # still closing: wait
            return np.array([0.0, 0.0, 0.0, -1.0])
        # closed on the object: carry it
        to_goal = goal - obj
        if lift_first and np.linalg.norm(to_goal[:2]) > 0.04 and obj[2] < goal[2] + lift_first:
            to_goal = np.array([to_goal[0], to_goal[1], 3.0 * (goal[2] + lift_first + 0.02 - obj[2])])
        return np.append(toward(to_goal), -1.0)
    if xy < 0.015 and abs(to_obj[2]) < 0.025:  # in place: close
        return np.array([0.0, 0.0, 0.0, -1.0])
    if np.linalg.norm(to_obj[:2]) > 0.01:  # line up above the object, open
        return np.append(toward(to_obj + np.array([0.0, 0.0, 0.08])), 1.0)
    return np.append(toward(to_obj), 1.0)


def lift_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    return _pick_and_carry(obs)


#: How far above the goal (cube B's top) cube A is raised before it moves across, m:
#: it clears B's side.
STACK_CLEARANCE = 0.04


def stack_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    """Grasp cube A, raise it over cube B and hold it on B's top. It does not let go:
    the task's success does not require it (see the task doc), and a cube dropped from
    the fingers lands off its 2 cm threshold."""
    return _pick_and_carry(obs, lift_first=STACK_CLEARANCE)


#: Height of the can's centre above the goal while carried, m (clears the bins' walls).
CAN_CARRY = 0.13


def can_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    """Grasp the can from above, lift it over the bins' walls, carry it at a moderate
    speed (it swings in the fingers), lower it to 3 cm above the goal, let go, back up."""
    o = obs["observation"]
    eef = o[EEF]
    can = obs["achieved_goal"]
    goal = obs["desired_goal"]
    to_can = can - eef
    to_goal = goal - can
    opening = _opening(o)  # Panda finger opening, m (0.08 open, ~0.05 on the can)
    if np.linalg.norm(to_goal[:2]) < 0.045 and can[2] < goal[2] + 0.07:  # low over the goal: let go
        return np.array([0.0, 0.0, 0.5 if opening > 0.07 else 0.0, 1.0])  # back up once open
    closing_speed = _closing_speed(o)  # m/s
    near = np.linalg.norm(to_can[:2]) < 0.04 and abs(to_can[2]) < 0.05
    if near and 0.03 < opening < 0.07:  # closing on, or holding, the can
        if closing_speed > 0.02:  # still closing: wait
            return np.array([0.0, 0.0, 0.0, -1.0])
        carry_z = goal[2] + CAN_CARRY
        if np.linalg.norm(to_goal[:2]) > 0.02:
            if can[2] < carry_z - 0.03:  # up first, then across
                move = np.array([0.3 * to_goal[0], 0.3 * to_goal[1], carry_z + 0.02 - can[2]])
            else:
                move = np.array([to_goal[0], to_goal[1], carry_z - can[2]])
            return np.append(toward(move, 10.0) * 0.6, -1.0)
        return np.append(toward(to_goal, 10.0) * 0.6, -1.0)
    xy = np.linalg.norm(to_can[:2])
    if xy < 0.015 and abs(to_can[2]) < 0.025 and opening >= 0.07:  # in place: close
        return np.array([0.0, 0.0, 0.0, -1.0])
    if xy > 0.01:  # line up above the can, open
        return np.append(toward(to_can + np.array([0.0, 0.0, 0.08])), 1.0)
    return np.append(toward(to_can), 1.0)


#: Door geometry (robosuite's door_lock.xml) in the door body's frame, m: the latch
#: joint's anchor (its axis is the door's y) and the hinge's (axis z); the handle site
#: in the latch's frame. The handle is a lever along the latch's x, 15 cm long, 3 cm
#: thick (y, centred 10 cm in front of the door) and 4 cm high; a positive latch angle
#: turns it down.
DOOR_LATCH = np.array([-0.175, 0.0, -0.025])
DOOR_HINGE = np.array([0.255, 0.0, 0.0])
DOOR_HANDLE_SITE = np.array([0.125, -0.10, 0.0])
#: Door object state (after the proprio): door body position, handle site, hinge angle, latch angle.
DOOR_POS, DOOR_HANDLE = slice(PROPRIO, PROPRIO + 3), slice(PROPRIO + 3, PROPRIO + 6)
DOOR_ANGLE, DOOR_LATCH_ANGLE = PROPRIO + 6, PROPRIO + 13
#: Where the grip site presses the lever, in the latch's frame, m: 12 cm out along the
#: lever, fingertips just past its back face (the hand clears the handle's base), the
#: closed fingers' lower edge on its top face.
DOOR_PRESS = np.array([0.12, -0.095, 0.05])
#: Latch angles, rad: how far ahead of the lever the press target leads, the angle it
#: presses towards, and the angle beyond which the latch clears the frame and the
#: policy pulls (the latch_joint's range ends at 1.57).
DOOR_LEAD, DOOR_HOLD, DOOR_PULL = 0.4, 1.6, 1.3
#: The pull aims this far past the goal angle (the door lags the gripper), rad.
DOOR_OVERSHOOT = 0.03


def _latch_turn(v: np.ndarray, angle: float) -> np.ndarray:
    """``v`` (latch frame) turned by the latch angle about the latch's y axis."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([c * v[0] + s * v[2], v[1], -s * v[0] + c * v[2]])


def _yaw(angle: float) -> np.ndarray:
    """The rotation matrix of ``angle`` about z."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def door_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    """Press the lever down with the closed fingertips, then pull the door open by it.

    Needs ``ee_delta``'s Door orientation (gripper pointing at the door, fingers one
    above the other). Everything is computed in the door's frame, whose yaw follows from
    the door, handle and latch angle of the observation: from the front, rise above
    the press point, descend onto the lever and follow it down along its arc (the target
    leads the lever by ``DOOR_LEAD``); once the latch is past ``DOOR_PULL``, keep
    pressing and swing the press point about the hinge towards the goal angle (friction
    on the lever drags the door)."""
    o = obs["observation"]
    door, eef = o[DOOR_POS], o[EEF]
    latch, angle, goal = float(o[DOOR_LATCH_ANGLE]), float(o[DOOR_ANGLE]), float(obs["desired_goal"][0])
    handle_local = DOOR_LATCH + _latch_turn(DOOR_HANDLE_SITE, latch)
    handle = o[DOOR_HANDLE] - door
    rot = _yaw(math.atan2(handle[1], handle[0]) - math.atan2(handle_local[1], handle_local[0]))
    grip = rot.T @ (eef - door)  # grip site in the door's frame

    def press(latch_angle: float) -> np.ndarray:
        return DOOR_LATCH + _latch_turn(DOOR_PRESS, latch_angle)

    if latch < 0.15:  # lever up: get above the press point, then descend onto it
        point = press(0.0)
        above = point + np.array([0.0, 0.0, 0.04])
        if np.linalg.norm(point[:2] - grip[:2]) > 0.015:
            target = above
            if grip[2] < above[2] - 0.02:  # rise first, staying 6 cm in front of the lever
                step = 0.3 * (above - grip)
                target = np.array([grip[0] + step[0], min(grip[1] + step[1], above[1] - 0.06), above[2]])
        else:
            target = press(latch + DOOR_LEAD)
    else:
        target = press(min(latch + DOOR_LEAD, DOOR_HOLD))
        if latch > DOOR_PULL:  # unlatched: swing the press point about the hinge
            swing = float(np.clip(goal + DOOR_OVERSHOOT - angle, -0.1, 0.1))
            target = DOOR_HINGE + _yaw(swing) @ (target - DOOR_HINGE)
    return np.append(toward(rot @ (target - grip)), -1.0)
