"""How the robosuite env is built: ``robosuite.make`` options and controller configs."""

from __future__ import annotations

import math
from typing import Any

import robosuite
from robosuite.controllers import load_composite_controller_config, load_part_controller_config

#: Keyword arguments of ``robosuite.make`` used for every task (besides the env name,
#: robot and controller config): low-dim observations only, no robosuite renderer,
#: robosuite never ends the episode itself (our TimeLimit does), fast resets, and a
#: fixed construction seed: robosuite samples some model properties when it builds
#: the model (e.g. Lift's cube half-size in [2.0, 2.2] cm), so every instance must
#: build the same model.
UPSTREAM_KWARGS: dict[str, Any] = dict(
    seed=0,
    has_renderer=False,
    has_offscreen_renderer=False,
    use_camera_obs=False,
    use_object_obs=True,
    ignore_done=True,
    hard_reset=False,
    control_freq=20,
)

#: JOINT_POSITION gains of the joint-position-based modes (robosuite's default kp is 50,
#: too soft for an IK-driven end effector at 20 Hz). Torques are kp * M(q) e + ... .
JOINT_KP = 150.0
#: Largest joint-target change per step in ``joint_delta``, rad.
MAX_DELTA = 0.05
#: Joint speed at |a| = 1 in ``joint_velocity``, rad/s, and how far the integrated
#: target may lead the measured position, rad.
MAX_VELOCITY = 1.0
MAX_LEAD = 0.1
#: Grip-site displacement at |a| = 1 in ``ee_delta``, m per step (as OSC_POSE's 5 cm).
EE_STEP = 0.05
#: ee_delta IK: weight of the held gripper orientation against position, and the
#: position residual, m, beyond which the orientation yields (a second solve with
#: ``EE_YIELD_ORIENTATION_COST``) so the arm can tilt the gripper to reach further.
EE_ORIENTATION_COST = 0.3
EE_YIELD_RESIDUAL = 0.005
EE_YIELD_ORIENTATION_COST = 0.01
#: Command range of joints without limits (Kinova3's continuous joints), rad.
UNLIMITED_RANGE = (-math.pi, math.pi)


def controller_config(mode: str, robot: str) -> dict:
    """The robosuite composite-controller config for an action mode."""
    cfg = load_composite_controller_config(controller="BASIC", robot=robot)
    if mode == "native":
        return cfg
    if mode == "joint_torque":
        arm = load_part_controller_config(default_controller="JOINT_TORQUE")
    else:
        arm = load_part_controller_config(default_controller="JOINT_POSITION")
        arm["kp"] = JOINT_KP
        if mode == "joint_delta":
            arm["input_type"] = "delta"
            arm["output_max"], arm["output_min"] = MAX_DELTA, -MAX_DELTA
        else:  # joint_position, joint_velocity, ee_delta: absolute targets in rad
            arm["input_type"] = "absolute"
    arm["gripper"] = {"type": "GRIP"}
    cfg["body_parts"] = {"right": arm}
    return cfg


def make_upstream(env_name: str, robot: str, mode: str):
    """The robosuite env, built with ``robosuite.make`` as a robosuite user would."""
    return robosuite.make(env_name, robots=robot, controller_configs=controller_config(mode, robot), **UPSTREAM_KWARGS)
