"""The Shadow Hand tasks' documentation pages (``unified-manip list --doc``), in the
labelled paragraphs the site's task pages put under their headings (see the arm's docs)."""

from __future__ import annotations

from unified_manip.envs.controllers.docs import modes_section
from unified_manip.envs.tasks.shadow_hand.controllers import CONTROLLERS

_MODES = f"""Action modes (20 entries in [-1, 1], one per actuator, upstream's order: WRJ1, WRJ0,
FFJ3-1, MFJ3-1, RFJ3-1, LFJ4-1, THJ4-0; q is the actuated joint's angle, J1 + J0 for
the coupled finger joints, and the range is the actuator's control range):
{modes_section(CONTROLLERS)}
joint_delta is upstream's relative_control (whose own code calls mujoco-py APIs and
fails under the mujoco bindings). Other modes raise ValueError: the hand has no end
effector or torque interface."""

REACH_DOC = f"""HandReach: move the Shadow Hand's five fingertips to goal positions
(gymnasium-robotics HandReach-v3).

Starting state: the hand at upstream's initial posture, at rest; the goal: with
probability 0.1 the initial fingertip layout, otherwise one finger's tip must meet the
thumb's tip over the palm while the others keep their initial positions.

Success: the goal distance is the Euclidean distance over the 15 goal coordinates, in
metres; threshold and criterion are upstream's, so the sparse reward, success - 1,
equals upstream's.

Observation (63,), upstream's vector exactly:
    0-23   joint angles (24 joints, upstream's order)             rad
    24-47  joint velocities                                       rad/s
    48-62  fingertip positions (ff, mf, rf, lf, th; x, y, z)      m
Goal (15,): achieved = fingertip positions, desired = their targets, m.

{_MODES}

Rewards: with no object, the reach term reads the goal distance d_goal.

Version history: v0 initial (over HandReach-v3, gymnasium-robotics 1.4.2).
"""

BLOCK_DOC = f"""HandManipulateBlock: move and rotate a block held on the Shadow Hand's palm
to a goal pose (gymnasium-robotics HandManipulateBlock-v1: random target position
and full xyz target rotation).

Starting state: the hand at upstream's initial posture; the block on the palm with a
uniformly random rotation and a 5 mm position jitter; the goal position the block's
position plus an offset in x [-0.04, 0.04], y [-0.06, 0.02], z [0, 0.06] m, the goal
rotation uniformly random.

Success: the goal distance is max(position error, 0.1 m/rad x rotation error), so with
the threshold of 0.01 a success is exactly upstream's criterion (position error < 0.01 m
and rotation error < 0.1 rad); the sparse reward, success - 1, equals upstream's.

Observation (61,), upstream's vector exactly:
    0-23   joint angles                                           rad
    24-47  joint velocities                                       rad/s
    48-53  block linear and angular velocity                      m/s, rad/s
    54-60  block pose: position, quaternion (w, x, y, z)          m, -
Goal (7,): achieved = block pose, desired = goal pose (position m, unit quaternion).

{_MODES}

Rewards: the template is "push" (an object, no grasp gate): grip_to_object is the
distance from the palm to the block (m), so the reach term keeps the block near the
palm; grasped is 1 while the block is on the hand (its centre above z = 0.04 m,
upstream's reset check), so dense_penalized's drop term fires when it falls off.

Version history: v0 initial (over HandManipulateBlock-v1, gymnasium-robotics 1.4.2).
"""

#: What each in-hand object is, and how it starts.
_OBJECTS = {
    "egg": (
        "an egg (an ellipsoid of semi-axes 3 x 3 x 4 cm)",
        "a random rotation (an angle in [-pi, pi] about a random axis)",
    ),
    "pen": (
        "a pen (a capsule of radius 8 mm and length 20 cm)",
        "upstream's fixed orientation (no random rotation)",
    ),
}


def in_hand_doc(obj: str, distance) -> str:
    """The page of the egg or pen task, full pose or ``Rotate`` (``distance``: its
    :class:`~unified_manip.envs.tasks.shadow_hand.goals.PoseDistance`)."""
    what, start = _OBJECTS[obj]
    cap = obj.capitalize()
    rotate = not distance.position
    name = f"HandManipulate{cap}{'Rotate' if rotate else ''}"
    z = (
        " The pen's spin about its own axis does not count (upstream's "
        "ignore_z_target_rotation: the achieved orientation's z Euler angle is replaced by "
        "the goal's before the two are compared)."
        if distance.ignore_z
        else ""
    )
    scales = f"{distance.rotation_scale:g} m/rad x rotation error"
    if rotate:
        goal = (
            "The goal position is the object's own position when the goal is drawn, and it is\n"
            "ignored (upstream's target_position='ignore'); the goal rotation is uniformly random.\n\n"
            f"Success (upstream's): rotation error < {distance.rotation_threshold:g} rad.{z}\n"
            f"Goal distance = {scales}, threshold {distance.threshold:g}, so success is\n"
            "upstream's criterion."
        )
    else:
        position = "position error" if distance.position_scale == 1 else f"{distance.position_scale:g} x position error"
        goal = (
            "The goal position is the object's position plus an offset in x [-0.04, 0.04],\n"
            "y [-0.06, 0.02], z [0, 0.06] m; the goal rotation is uniformly random.\n\n"
            "Success (upstream's):"
            f" position error < {distance.position_threshold:g} m and rotation error <\n"
            f"{distance.rotation_threshold:g} rad.{z}\n"
            f"Goal distance = max({position}, {scales}): each error as a fraction of\n"
            f"its threshold, times {distance.threshold:g}. Threshold {distance.threshold:g}, so success is upstream's\n"
            "position-and-rotation criterion."
        )
    return f"""{name}: rotate {what} held on the Shadow Hand's palm to a goal
{"orientation" if rotate else "pose"} (gymnasium-robotics {name}-v1).

Starting state: the {obj} on the palm with {start} and a 5 mm position jitter.
{goal}

Sparse reward = success - 1 = upstream's sparse reward. 100 steps of 40 ms.

Observation (61,), upstream's vector exactly:
    0-23   joint angles                                           rad
    24-47  joint velocities                                       rad/s
    48-53  {obj} linear and angular velocity                        m/s, rad/s
    54-60  {obj} pose: position, quaternion (w, x, y, z)            m, -
Goal (7,): achieved = {obj} pose, desired = goal pose (position m, unit quaternion).

{_MODES}

Rewards: term set "in_hand": hold = 1 - tanh(5 |palm - {obj}|) keeps the {obj}
near the palm, pose = 5 on_palm (1 - tanh(5 d)) with on_palm 1 while the {obj} is on the
hand (centre above z = 0.04 m, upstream's reset check), success bonus 10;
dense_penalized adds -0.01 sum(a^2) and a drop penalty (-10) on the step the {obj}
falls off. (Upstream's dense reward, -(10 d_pos + d_rot), is not offered: a reward term
reads the goal only through the one goal distance.)

Version history: v0 initial (over {name}-v1, gymnasium-robotics 1.4.2).
"""
