"""Fetch's names, servo gains and observation layout (no simulator)."""

from __future__ import annotations

import numpy as np

ARM_JOINTS: tuple[str, ...] = tuple(
    f"robot0:{name}_joint"
    for name in (
        "shoulder_pan",
        "shoulder_lift",
        "upperarm_roll",
        "elbow_flex",
        "forearm_roll",
        "wrist_flex",
        "wrist_roll",
    )
)
ARM_ACTUATORS: tuple[str, ...] = tuple(j.replace("_joint", "_servo") for j in ARM_JOINTS)
FINGER_JOINTS = ("robot0:l_gripper_finger_joint", "robot0:r_gripper_finger_joint")
FINGER_GEOMS = ("robot0:l_gripper_finger_link", "robot0:r_gripper_finger_link")
FROZEN_JOINTS = ("robot0:slide0", "robot0:slide1", "robot0:slide2", "robot0:torso_lift_joint")
UNLIMITED_ROLL_JOINTS = ("robot0:upperarm_roll_joint", "robot0:forearm_roll_joint", "robot0:wrist_roll_joint")
GRIP_SITE = "robot0:grip"
OBJECT_GEOM = "object0"

#: Arm servo gains and torque limits. The model's arm joints carry damping 50 N m s/rad
#: and armature 1 kg m^2 (far more than the real Fetch), so the limits are above the
#: real robot's efforts (33.8, 131.8, 76.9, 66.2, 29.4, 25.7, 7.4 N m) to let the
#: arm move at about 1 rad/s against that damping.
ARM_KP = np.array([3000.0, 3000.0, 3000.0, 3000.0, 1500.0, 1500.0, 1000.0])
ARM_KV = np.array([50.0, 50.0, 50.0, 50.0, 25.0, 25.0, 20.0])
ARM_TORQUE = np.array([150.0, 250.0, 150.0, 150.0, 80.0, 80.0, 60.0])
#: Upstream's PickAndPlace finger actuators (position servos, kp 30000, ctrl 0-0.2 m).
FINGER_KP, FINGER_CTRL_MAX, FINGER_OPEN = 30000.0, 0.2, 0.05

#: Observation entries appended in the joint modes: 7 arm angles and 7 arm velocities.
N_JOINT_OBS = 14

#: Slices of the object tasks' observation (upstream's layout).
OBS_GRIP, OBS_OBJ, OBS_REL, OBS_FINGERS = slice(0, 3), slice(3, 6), slice(6, 9), slice(9, 11)

#: A grasp: both fingers touch the object and the grip site is within this of its centre, m.
GRASP_RADIUS = 0.05
