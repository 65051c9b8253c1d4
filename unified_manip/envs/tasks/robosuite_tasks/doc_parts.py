"""The paragraphs the robosuite tasks' documentation pages share (:mod:`.docs`,
:mod:`.more_docs`)."""

from __future__ import annotations

from unified_manip.envs.controllers.docs import modes_section
from unified_manip.envs.tasks.robosuite_tasks.controllers import CONTROLLERS

OPTIONS = """Options: ``robot`` (default "Panda"; also "Sawyer", "UR5e", "IIWA", "Kinova3",
"Jaco"). Unknown options raise TypeError, unknown robots ValueError. Camera images are
the ``rgb`` and ``depth`` observation groups of every family (``camera=``: agentview
(default), frontview, birdview, sideview, robot0_robotview, robot0_eye_in_hand, and each
as ``<name>_collision``, drawing the collision geoms instead of the visual meshes, about
20x faster on software rendering); the old ``camera_obs``, ``camera_width`` and ``camera_height`` options raise TypeError
naming them."""

MODES = f"""Action modes (action in [-1, 1]; n = the robot's arm joints, 7 on Panda; in every
mode but native the last entry commands the gripper, -1 closed, +1 open, and the ee
modes take (dx, dy, dz, gripper)):
{modes_section(CONTROLLERS)}
Joint targets (+-pi on continuous joints) go as absolute targets to robosuite's
JOINT_POSITION controller (kp 150, critically damped, mass-matrix and gravity
compensated); torques (limits 87/12 N m on Panda) to its JOINT_TORQUE controller, plus
its gravity compensation. The ee modes hold the gripper orientation at reset (on Door
turned to point at the door, see the task doc) and put ``ik_residual`` (m) and
``ik_limit_active`` in ``info``. native, with the same seed and actions, gives
robosuite.make's observations and reward (``info["native_reward"]``)."""

OBS = """Observation (float32): robosuite's ``robot0_proprio-state`` then ``object-state``.
Proprio (Panda: 50): joint pos (n, rad), cos, sin (n each), joint vel (n, rad/s), joint
acc (n, rad/s^2), eef position (3, m, world), eef quaternion xyzw (4), grip-site
quaternion (4), gripper finger qpos (2 on Panda, m) and qvel (2, m/s). Other robots:
Sawyer 50, UR5e 53, IIWA/Kinova3/Jaco 58 (grippers with more joints)."""

INFO = """Info adds ``native_success`` (1.0/0.0, robosuite's ``_check_success()``) and
``native_reward`` (robosuite's own sparse reward for the step)."""

HISTORY = """Version history: v0 initial (robosuite {env} 1.5.2, control_freq 20 Hz). Later,
without a version bump: rendered frames and camera images hide the collision geoms
(group 0), as robosuite's renderer does, with observations (low-dim), rewards and infos
unchanged; and the ``camera_obs=True`` option (an ``image`` key) became
``observation=['default', 'rgb']``, the image groups every family has."""

ROBOT_START = """Starting state: the robot at robosuite's initial posture plus robosuite's default
joint noise (Gaussian, magnitude 0.02), at rest"""

GRASP_REWARDS = """Rewards: grip_to_object is the distance from the grip site to the {what} (m);
grasped is robosuite's check that the gripper holds the {what}."""
