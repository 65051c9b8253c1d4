"""The Fetch tasks' documentation pages (``unified-manip list --doc``), in the labelled
paragraphs the site's task pages put under their headings (see the arm's docs)."""

from __future__ import annotations

from unified_manip.envs.controllers.docs import modes_section
from unified_manip.envs.tasks.fetch.controllers import CONTROLLERS

_MODES = f"""Action modes (action in [-1, 1]; the last entry commands the fingers, -1 closed,
+1 open, except on tasks whose gripper upstream blocks, where the fingers stay closed;
the joint modes command the 7 arm joints, the ee modes (dx, dy, dz), with mink IK on
the 7 arm joints only, base and torso frozen, gripper kept pointing down):
{modes_section(CONTROLLERS)}
Torque limits: 150, 250, 150, 150, 80, 80, 60 N m; the three unlimited roll joints
command +-pi. The non-native modes run on a copy of the model without the mocap weld,
with position servos (kp 3000, 3000, 3000, 3000, 1500, 1500, 1000 N m/rad), gravity
compensation on the arm and the base slides and torso frozen by joint equality
constraints (see ``unified_manip/envs/tasks/fetch/``). In the joint modes the observation gains 14
entries: the 7 arm angles (rad, shoulder pan, shoulder lift, upper-arm roll, elbow
flex, forearm roll, wrist flex, wrist roll) and their velocities (rad/s). native and
the ee modes keep upstream's vector exactly."""

_OBJECT_OBS = """Observation (25,) in native and the ee modes (upstream's vector exactly; +14 in the joint
modes, see below). Velocities are upstream's: displacement per env step (m or rad
per 0.04 s).
    0-2    grip-site position (world)                         m
    3-5    object position (world)                            m
    6-8    object - grip site                                 m
    9-10   finger openings (right, left)                      m
    11-13  object rotation, Euler xyz                         rad
    14-16  object linear velocity relative to the grip site   m/step
    17-19  object angular velocity                            rad/step
    20-22  grip-site linear velocity                          m/step
    23-24  finger velocities                                  m/step
Goal (3,): achieved = object position, desired = goal point, m."""

_SUCCESS = """Success: the goal distance is the Euclidean distance between the {what} and the goal
point, in metres; the threshold is upstream's, so the sparse reward, success - 1, equals
upstream's -(d > threshold)."""

_ROBOT_START = """Starting state: the robot at upstream's initial posture (no noise), the gripper
{gripper}, at rest"""

_HISTORY = """Version history: v0 initial (over {upstream}, gymnasium-robotics 1.4.2)."""

REACH_DOC = f"""FetchReach: bring the Fetch gripper to a goal point (gymnasium-robotics FetchReach-v4).

No object; the gripper is blocked closed.

{_ROBOT_START.format(gripper="at (1.342, 0.749, 0.535) m")}; the goal at that point plus a
uniform offset in [-0.15, 0.15] m on each axis.

{_SUCCESS.format(what="grip site")}

Observation (10,) in native and the ee modes (upstream's vector exactly; +14 in the joint
modes). Velocities are displacement per env step.
    0-2    grip-site position (world)                         m
    3-4    finger openings (right, left)                      m
    5-7    grip-site linear velocity                          m/step
    8-9    finger velocities                                  m/step
Goal (3,): achieved = grip-site position, desired = goal point, m.

{_MODES}

Rewards: with no object, the reach term reads the goal distance d_goal.

{_HISTORY.format(upstream="FetchReach-v4")}
"""

_CUBE_START = """the cube's xy within 15 cm (per axis, uniform) of the gripper's initial xy, drawn
again until at least 10 cm from it, on the table, at rest"""

_PUSH_REWARDS = """Rewards: grip_to_object is the distance from the grip site to the {what}'s centre (m);
the place term has no grasp gate."""

PUSH_DOC = f"""FetchPush: push a 5 cm cube (2 kg) across the table to a goal on the table
(gymnasium-robotics FetchPush-v4).

The gripper is blocked closed.

{_ROBOT_START.format(gripper="above the table")}; {_CUBE_START}; the goal within 15 cm
(per axis, uniform) of the gripper's initial xy, at the cube's resting height (z = 0.425 m).

{_SUCCESS.format(what="cube's centre")}

{_OBJECT_OBS}

{_MODES}

{_PUSH_REWARDS.format(what="cube")}

{_HISTORY.format(upstream="FetchPush-v4")}
"""

SLIDE_DOC = f"""FetchSlide: hit a puck so that it slides along a low-friction table to a goal
out of the arm's reach (gymnasium-robotics FetchSlide-v4).

The gripper is blocked closed.

{_ROBOT_START.format(gripper="above the table")}; the puck within 10 cm (per axis,
uniform) of the gripper's initial xy, drawn again until at least 10 cm from it; the goal
0.4 m further in x plus a uniform offset within 30 cm (per axis), on the table
(z = 0.42 m).

{_SUCCESS.format(what="puck's centre")}

{_OBJECT_OBS}

{_MODES}

{_PUSH_REWARDS.format(what="puck")}

{_HISTORY.format(upstream="FetchSlide-v4")}
"""

PICK_AND_PLACE_DOC = f"""FetchPickAndPlace: grasp a 5 cm cube (2 kg) and carry it to a goal, in the air
half of the time (gymnasium-robotics FetchPickAndPlace-v4).

The gripper is free.

{_ROBOT_START.format(gripper="above the table, open")}; {_CUBE_START}; the goal within
15 cm (per axis, uniform) of the gripper's initial xy at the cube's resting height,
raised by U(0, 0.45) m with probability 1/2.

{_SUCCESS.format(what="cube's centre")}

{_OBJECT_OBS}

{_MODES}

Rewards: grip_to_object is the distance from the grip site to the cube's centre (m);
grasped is 1 while both fingers touch the cube (MuJoCo contacts) with the grip site within
5 cm of its centre.

{_HISTORY.format(upstream="FetchPickAndPlace-v4")}
"""
