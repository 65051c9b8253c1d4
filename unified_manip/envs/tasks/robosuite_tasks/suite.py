"""How the robosuite env is built: ``robosuite.make`` options and controller configs."""

from __future__ import annotations

import math
from typing import Any

import robosuite
from robosuite.controllers import load_composite_controller_config, load_part_controller_config

from unified_manip.envs.tasks.robosuite_tasks.controllers import CONTROLLERS

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
#: Command range of joints without limits (Kinova3's continuous joints), rad.
UNLIMITED_RANGE = (-math.pi, math.pi)


def controller_config(mode: str, robot: str) -> dict:
    """The robosuite composite-controller config for an action mode: robosuite's
    default BASIC for ``native``; otherwise the arm part controller that takes the
    mode's command (:mod:`.controllers`): JOINT_TORQUE for torques, JOINT_POSITION with
    absolute targets for joint positions; GRIP for the gripper."""
    cfg = load_composite_controller_config(controller="BASIC", robot=robot)
    if mode == "native":
        return cfg
    if CONTROLLERS[mode].command == "torque":
        arm = load_part_controller_config(default_controller="JOINT_TORQUE")
    else:
        arm = load_part_controller_config(default_controller="JOINT_POSITION")
        arm["kp"] = JOINT_KP
        arm["input_type"] = "absolute"
    arm["gripper"] = {"type": "GRIP"}
    cfg["body_parts"] = {"right": arm}
    return cfg


def make_upstream(env_name: str, robot: str, mode: str, robots: int = 1):
    """The robosuite env, built with ``robosuite.make`` as a robosuite user would:
    ``robots`` of ``robot`` (two for the two-arm tasks, in robosuite's default ``opposed``
    configuration), each with the mode's controller config."""
    config = controller_config(mode, robot)
    return robosuite.make(env_name, robots=[robot] * robots, controller_configs=config, **UPSTREAM_KWARGS)
