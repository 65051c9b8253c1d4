"""The two-arm robosuite tasks' documentation pages: TwoArmLift and TwoArmHandover."""

from __future__ import annotations

from unified_manip.envs.controllers.docs import modes_section
from unified_manip.envs.tasks.robosuite_tasks.controllers import CONTROLLERS
from unified_manip.envs.tasks.robosuite_tasks.doc_parts import INFO

TWO_ARMS = """Two Pandas face each other across the table (robosuite's default "opposed"
configuration): robot 0 on the -y side, robot 1 on the +y side. The table top is at
z = 0.8 m (world frame)."""

TWO_ARM_MODES = f"""Action modes (action in [-1, 1]; every mode acts on both arms: the action is arm 0's
part then arm 1's, each as the one-arm tasks' action, so ee_delta is 2 × (dx, dy, dz,
gripper) = 8 entries, the joint modes 2 × (7 joints + gripper) = 16 and native 2 × (6 + 1)
= 14; the gripper entries are -1 closed, +1 open, except in native):
{modes_section(CONTROLLERS)}
Each arm has its own controller of the mode: joint targets go to its robosuite
JOINT_POSITION controller (kp 150), torques to its JOINT_TORQUE controller, each plus
gravity compensation. ``ik_residual`` (m) is the larger of the two arms' and
``ik_limit_active`` is set when either arm's is. An action of the wrong shape raises
ValueError naming the shape and its layout, e.g. "action must have shape (8,) (2 × (3 + 1))".
native, with the same seed and actions, gives robosuite.make's observations and reward
(``info["native_reward"]``)."""

TWO_ARM_OBS = """Observation (float32): robosuite's ``robot0_proprio-state``, ``robot1_proprio-state``
(50 each on the Panda: joint pos, cos, sin, vel and acc of the 7 joints, eef position
(3, m, world), eef quaternion xyzw (4), grip-site quaternion (4), finger qpos (2, m) and
qvel (2, m/s)), then ``object-state``. Robot 1's observation groups carry its prefix
(``robot1_joint_pos``); robot 0's are named as on the one-arm tasks."""

TWO_ARM_OPTIONS = """Options: ``robot`` (default "Panda"), the robot of both arms. Camera images are the
``rgb`` and ``depth`` observation groups of every family (``camera=``: agentview (default),
frontview, birdview, sideview, robot0_robotview, robot0_eye_in_hand, robot1_robotview,
robot1_eye_in_hand, and each as ``<name>_collision``)."""

TWO_ARM_HISTORY = """Version history: v0 initial (robosuite {env} 1.5.2, two Pandas, control_freq 20 Hz)."""

TWO_ARM_START = """Starting state: both robots at robosuite's initial posture plus its default joint noise
(Gaussian, magnitude 0.02), at rest"""

TWO_ARM_LIFT_DOC = f"""TwoArmLift: two arms grasp the handles of a pot and lift it to a goal point (robosuite
TwoArmLift).

{TWO_ARMS} The pot (14 cm cube, a handle on either side) stands between them;
handle 0 faces robot 0, handle 1 robot 1.

{TWO_ARM_START}; the pot within 3 cm of the table centre and turned about z by
pi ± pi/3 (robosuite's placement); the goal is the pot's centre at reset raised by
U(0.16, 0.22) m.

Success: the goal distance is the Euclidean distance between the pot's centre (robosuite's
pot_center site) and the goal point, in metres, below 0.05.

Native success (robosuite): the pot's bottom more than 10 cm above the table. Every goal
is at least 16 cm up, so is_success implies native success.

{INFO}

{TWO_ARM_OBS}
Object state (19): pot position (3, m), pot quaternion (4), handle 0 and handle 1
positions (3 each, m), gripper 0 to handle 0 and gripper 1 to handle 1 (3 each, m).
Goal (3,): achieved = the pot's centre, desired = the goal point, world frame, m.

{TWO_ARM_MODES}
The ee modes hold each gripper pointing down, turned about z with the pot at reset so its
fingers close across its handle's bar.

Rewards: the template is "push": grip_to_object is the farther of the two grippers'
distances to their own handles (m), and the place term reads the pot's distance to the
goal. grasped (1 while each gripper holds its own handle, robosuite's grasp check) is
reported, but does not gate the place term: robosuite's check, which wants both finger
pads on the handle geoms, seldom holds while the scripted policy carries the pot.

Scripted policy (ee_delta): each gripper lines up 6 cm above its handle, comes down
open and closes; once both are closed on their handles, both carry the pot to the goal
together. Measured: 29 of 30 seeded episodes (seeds 0-29, each played to its 150 steps,
one ``unified-manip collect``) end in success, and 10 of 10 at seeds 1000-1009 end with
is_success and native success. In the other shared modes its actions are translated arm by
arm (live, as ``demonstrations`` plays it, and by ``unified-manip convert``); in
joint_position it succeeded in 1 of 2 episodes (seeds 0-1).

{TWO_ARM_OPTIONS}

{TWO_ARM_HISTORY.format(env="TwoArmLift")}
"""

TWO_ARM_HANDOVER_DOC = f"""TwoArmHandover: one arm picks up a hammer and hands it to the other (robosuite
TwoArmHandover).

{TWO_ARMS} The hammer lies on the table by robot 0, out of robot 1's reach.

{TWO_ARM_START}; the hammer at robosuite's placement near robot 0 (x within 10 cm, y
within 5 cm of its point), turned about its own y axis at random.

Success: the goal is three flags, 1.0 or 0.0 each, as robosuite's own checks
(``_get_task_info``) make them: (arm 0 holds any part of the hammer, arm 1 holds its
handle, the hammer is more than 10 cm above the table); desired (0, 1, 1), and the goal
distance their Euclidean distance, below 0.5: every flag must match, so is_success is
exactly robosuite's success (arm 1 alone holds the lifted hammer by its handle).

{INFO}

{TWO_ARM_OBS}
Object state (16): hammer position (3, m), hammer quaternion (4), handle position (3, m),
gripper 0 to handle and gripper 1 to handle (3 each, m).
Goal (3,): achieved = (arm 0 holds, arm 1 holds the handle, hammer lifted), desired =
(0, 1, 1).

{TWO_ARM_MODES}
The ee modes hold each gripper pointing down, turned about z with the hammer's handle at
reset so its fingers close across the handle.

Rewards: the template is "push": grip_to_object is the distance from arm 1's grip site
to the hammer's handle (m), and the place term reads the flags' distance (0 to 1.73). A
coarse shaping: it has no term for arm 0's pick-up.

Scripted policy (ee_delta): arm 0 grasps the handle 4 cm from its middle on its own
side and carries the hammer to the middle of the table, 20 cm above it; arm 1 grasps the
handle 4 cm from the middle on the other side; once it holds, arm 0 opens, rises and backs
away. Measured: 29 of 30 seeded episodes (seeds 0-29, each played to its 300 steps, one
``unified-manip collect``) end in success, and 8 of 10 at seeds 1000-1009. Like the lift's,
its actions are translated arm by arm into the other shared modes. Of the two failures at seeds 1000-1009, one ends with the hammer
back on the table, held by neither arm, the other with arm 0 holding it up and arm 1
never closed on the handle.

{TWO_ARM_OPTIONS}

{TWO_ARM_HISTORY.format(env="TwoArmHandover")}
"""
