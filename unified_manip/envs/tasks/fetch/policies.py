"""Scripted ``ee_delta`` policies of the Fetch tasks, on upstream's observation layout
(see the task docs). They are memoryless."""

from __future__ import annotations

import math

import numpy as np

from unified_manip.envs.tasks.fetch.scene import OBS_FINGERS, OBS_GRIP, OBS_OBJ, OBS_REL
from unified_manip.envs.tasks.scripted import pick_and_place, toward


def reach_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    """Move the grip site straight to the goal."""
    return np.append(toward(obs["desired_goal"] - obs["achieved_goal"]), -1.0).astype(np.float32)


def pick_and_place_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    """Hover over the cube, descend open, close, then carry it to the goal."""
    o = obs["observation"]
    closed_on_cube = bool(np.all(o[OBS_FINGERS] < 0.03))
    to_goal = obs["desired_goal"] - obs["achieved_goal"]
    return pick_and_place(o[OBS_REL], to_goal, closed_on_cube, align=0.01, hover=0.05, near=0.01)


#: Grip-site height above the object's centre while pushing, m. Lower, the fingertips
#: drag on the table and the servos stall.
PUSH_HEIGHT = 0.008
#: Grip site to the object's centre when a finger touches the cube's face, m.
PUSH_CONTACT = 0.04
#: While going around the object the grip site keeps this far from its centre, m (the
#: fingers clear the cube's corners).
PUSH_CLEARANCE = 0.065
#: Extra grip-site height while moving low around the object, m: a fast move near the
#: reach limit makes the arm dip, and fingertips on the table stall it.
APPROACH_LIFT = 0.02
#: Grip-site height above the object's centre from which the fingers clear its top, m.
CLEAR_HEIGHT = 0.05
#: Position gain of the approach and of height keeping: action per metre of error (20
#: asks for the whole error in one step of 5 cm per unit).
PUSH_GAIN = 20.0


def _around(rel: np.ndarray, spot: np.ndarray, radius: float, speed: float) -> np.ndarray:
    """xy action that takes the grip site, at ``rel`` from the object's centre, around the
    circle of ``radius`` towards ``spot`` (also from the centre), the shorter way round:
    towards the circle's tangent point from outside, along the circle and back out to it
    from inside."""
    dist = max(float(np.linalg.norm(rel)), 1e-6)
    radial = rel / dist
    side = 1.0 if radial[0] * spot[1] - radial[1] * spot[0] >= 0.0 else -1.0
    if dist > radius:  # the direction to the centre, turned by the tangent angle
        beta = side * math.asin(radius / dist)
        c, s = math.cos(beta), math.sin(beta)
        return -np.array([c * radial[0] + s * radial[1], c * radial[1] - s * radial[0]]) * speed
    xy = side * np.array([-radial[1], radial[0]]) * speed + radial * (radius - dist) * PUSH_GAIN
    return xy * min(1.0, speed / float(np.linalg.norm(xy)))


def _push(
    obs: dict[str, np.ndarray],
    speed: float,
    stop: float,
    slowdown: float,
    behind_by: float = 0.05,
    lateral_tol: float = 0.02,
    approach_speed: float = 0.8,
) -> np.ndarray:
    """Push the object along the line from it to the goal, re-deciding the contact point
    from the object-goal direction at every step (memoryless).

    * Pushing: the gripper is low, behind the object (seen from the goal) and within
      ``lateral_tol`` of that line: move along it at ``speed`` (``slowdown`` x the
      remaining distance near the goal, only as fast as the gripper is down at the
      object's height) and steer sideways back onto it, so the contact point follows
      the object as it turns or drifts.
    * Behind the object and on the line but high: come down onto it.
    * Otherwise go to the spot ``behind_by`` behind the object: straight if the way is
      clear of the object, straight over it if the fingers already clear its top, else
      around it, low, along the tangents of a circle of radius :data:`PUSH_CLEARANCE`
      (faster than over it: the arm is slow to rise and come down).

    Most of the remaining misses are cubes near the arm's reach with the goal towards
    the robot: the contact point is where the elbow is straight and the IK is slow.
    """
    o = obs["observation"]
    grip, obj = o[OBS_GRIP], o[OBS_OBJ]
    to_goal = (obs["desired_goal"] - obj)[:2]
    remaining = float(np.linalg.norm(to_goal))
    if remaining < stop:
        return np.zeros(4, dtype=np.float32)
    direction = to_goal / max(remaining, 1e-6)
    normal = np.array([-direction[1], direction[0]])
    rel = grip[:2] - obj[:2]
    along = float(rel @ direction)  # negative: the gripper is behind the object
    lateral = float(rel @ normal)
    height = float(grip[2] - obj[2])
    push_z = obj[2] + PUSH_HEIGHT  # grip site above the object's centre: fingertips clear the table
    touching = along > -PUSH_CONTACT - 0.01  # close enough to touch: a wider band keeps the push going
    if along < -0.02 and abs(lateral) < lateral_tol + 0.01 * touching and height < 0.03:
        low = float(np.clip(1.0 - (grip[2] - push_z - 0.01) / 0.02, 0.0, 1.0))
        v = min(speed, slowdown * remaining) * low
        steer = float(np.clip(-lateral * PUSH_GAIN, -0.3, 0.3))
        move = np.append(direction * v + normal * steer, (push_z - grip[2]) * PUSH_GAIN)
        return np.append(np.clip(move, -1.0, 1.0), -1.0).astype(np.float32)
    if along < -PUSH_CONTACT - 0.005 and abs(lateral) < lateral_tol + 0.005:  # on the line, high: come down
        spot = obj[:2] - direction * min(-along, behind_by)
        move = np.append((spot - grip[:2]) * PUSH_GAIN, (push_z - grip[2]) * PUSH_GAIN)
        return np.append(np.clip(move, -1.0, 1.0), -1.0).astype(np.float32)
    spot = -direction * behind_by  # from the object's centre
    to_spot = spot - rel
    dist = float(np.linalg.norm(to_spot))
    # How close the straight way to the spot passes by the object's centre.
    t = float(np.clip(-(rel @ to_spot) / max(dist * dist, 1e-9), 0.0, 1.0))
    clearance = float(np.linalg.norm(rel + t * to_spot))
    if clearance >= PUSH_CLEARANCE:  # the straight way is clear: low, or at the height it has
        xy = to_spot * PUSH_GAIN
        if dist < 0.03:
            z = push_z
        else:
            z = grip[2] if height > CLEAR_HEIGHT - 0.01 else push_z + APPROACH_LIFT
    elif height > CLEAR_HEIGHT - 0.01:  # above the object already: straight over it
        xy = to_spot * PUSH_GAIN
        if float(np.linalg.norm(rel)) < PUSH_CLEARANCE + 0.01:  # over it: slower while still rising
            xy *= min(1.0, (height - 0.02) / (CLEAR_HEIGHT - 0.02))
        z = obj[2] + CLEAR_HEIGHT + 0.01
    else:
        xy = _around(rel, spot, PUSH_CLEARANCE, approach_speed)
        z = push_z + APPROACH_LIFT
    norm = float(np.linalg.norm(xy))
    if norm > approach_speed:  # not faster than the arm follows without dipping
        xy *= approach_speed / norm
    move = np.append(xy, (z - grip[2]) * PUSH_GAIN)
    return np.append(np.clip(move, -1.0, 1.0), -1.0).astype(np.float32)


def push_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    """Push the cube to the goal, slowing down near it."""
    return _push(obs, speed=0.5, stop=0.01, slowdown=10.0)


def slide_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    """Line up behind the puck and push it towards the goal, letting it slide the rest."""
    return _push(obs, speed=1.0, stop=0.0, slowdown=4.0, lateral_tol=0.015)
