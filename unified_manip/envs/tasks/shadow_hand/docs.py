"""The Shadow Hand tasks' documentation pages (``unified-manip list --doc``)."""

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

With probability 0.1 the goal is the initial fingertip layout; otherwise one finger's
tip must meet the thumb's tip over the palm, the others keep their initial positions.
Success: Euclidean distance over the 15 goal coordinates < 0.01 m (upstream's
criterion); sparse reward = success - 1 = upstream's. 50 steps of 40 ms.

Observation (63,), upstream's vector exactly:
    0-23   joint angles (24 joints, upstream's order)             rad
    24-47  joint velocities                                       rad/s
    48-62  fingertip positions (ff, mf, rf, lf, th; x, y, z)      m
Goal (15,): achieved = fingertip positions, desired = their targets, m.

{_MODES}
Dense reward: shaping "reach": reach = 1 - tanh(5 d), success bonus 10.
Version history: v0 initial (over HandReach-v3, gymnasium-robotics 1.4.2).
"""

BLOCK_DOC = f"""HandManipulateBlock: move and rotate a block held on the Shadow Hand's palm
to a goal pose (gymnasium-robotics HandManipulateBlock-v1: random target position
and full xyz target rotation).

The block starts on the palm with a random rotation and a 5 mm position jitter; the
goal position is the block's position plus an offset in x [-0.04, 0.04], y [-0.06,
0.02], z [0, 0.06] m; the goal rotation is uniformly random. Success (upstream's):
position error < 0.01 m and rotation error < 0.1 rad. 100 steps of 40 ms.

Observation (61,), upstream's vector exactly:
    0-23   joint angles                                           rad
    24-47  joint velocities                                       rad/s
    48-53  block linear and angular velocity                      m/s, rad/s
    54-60  block pose: position, quaternion (w, x, y, z)          m, -
Goal (7,): achieved = block pose, desired = goal pose (position m, unit quaternion).
Goal distance = max(position error, 0.1 m/rad x rotation error), threshold 0.01, so
success is exactly upstream's position-and-rotation criterion; sparse reward =
success - 1 = upstream's sparse reward.

{_MODES}
Dense reward: shaping "push" (an object, no grasp gate): reach = 1 - tanh(5 |palm -
block|) keeps the block near the palm, place = 5 (1 - tanh(5 d)), success bonus 10;
``grasped`` is 1 while the block is on the hand (centre above z = 0.04 m, upstream's
reset check), so dense_penalized's drop penalty (-10) fires when it falls off.
Version history: v0 initial (over HandManipulateBlock-v1, gymnasium-robotics 1.4.2).
"""
