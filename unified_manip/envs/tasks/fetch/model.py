"""Fetch's model with arm actuators instead of the mocap weld (see the package docs)."""

from __future__ import annotations

import math

import mujoco
import numpy as np

from unified_manip.envs.mujoco_version import delete_element, set_to_position
from unified_manip.envs.tasks.fetch.scene import (
    ARM_ACTUATORS,
    ARM_JOINTS,
    ARM_KP,
    ARM_KV,
    ARM_TORQUE,
    FINGER_CTRL_MAX,
    FINGER_JOINTS,
    FINGER_KP,
    FROZEN_JOINTS,
    UNLIMITED_ROLL_JOINTS,
)


def actuated_model(path: str, initial_qpos: np.ndarray, width: int, height: int) -> mujoco.MjModel:
    """The Fetch model at ``path`` with the arm on position servos (see the package docs)."""
    spec = mujoco.MjSpec.from_file(path)
    for eq in list(spec.equalities):
        if eq.type == mujoco.mjtEq.mjEQ_WELD:
            delete_element(spec, eq)
    stack = [spec.body("robot0:shoulder_pan_link")]
    while stack:  # gravity compensation on the whole arm, gripper included
        body = stack.pop()
        body.gravcomp = 1.0
        stack.extend(body.bodies)
    for name in UNLIMITED_ROLL_JOINTS:
        spec.joint(name).range = [-math.pi, math.pi]  # command range; the joint stays unlimited
    for name in ARM_JOINTS:
        if spec.joint(name).limited == mujoco.mjtLimited.mjLIMITED_AUTO:
            spec.joint(name).limited = mujoco.mjtLimited.mjLIMITED_TRUE
    existing = {a.name for a in spec.actuators}
    for name in FINGER_JOINTS:
        if name not in existing:
            a = spec.add_actuator(name=name, target=name, trntype=mujoco.mjtTrn.mjTRN_JOINT)
            set_to_position(a, kp=FINGER_KP)
            a.ctrllimited = mujoco.mjtLimited.mjLIMITED_TRUE
            a.ctrlrange = [0.0, FINGER_CTRL_MAX]
    for joint, actuator, kp, kv, tau in zip(ARM_JOINTS, ARM_ACTUATORS, ARM_KP, ARM_KV, ARM_TORQUE):
        a = spec.add_actuator(name=actuator, target=joint, trntype=mujoco.mjtTrn.mjTRN_JOINT)
        set_to_position(a, kp=kp, kv=kv)
        a.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
        a.forcerange = [-tau, tau]
    spec.joint("robot0:torso_lift_joint").limited = mujoco.mjtLimited.mjLIMITED_FALSE
    model = spec.compile()
    for name in FROZEN_JOINTS:
        q0 = float(initial_qpos[model.jnt_qposadr[model.joint(name).id]])
        spec.add_equality(
            type=mujoco.mjtEq.mjEQ_JOINT,
            objtype=mujoco.mjtObj.mjOBJ_JOINT,
            name1=name,
            data=[q0] + [0.0] * 10,
        )
    model = spec.compile()
    model.vis.global_.offwidth = width
    model.vis.global_.offheight = height
    return model


_modified_model = actuated_model  # its old name
