"""The Franka for the shared controllers (every mode but ``native``).

The kitchen's Franka has position servos on its 7 arm joints (kp 870 N m/rad on the first
four, 120 on the last three, force-limited to 87 and 12 N m) and on its 2 fingers (kp 500,
0 to 4 cm); the arm joints' damping (100 and 10 N m s/rad) is their only damping. Upstream
drives them with joint-velocity commands integrated into position targets (``native``).
The other modes run on a copy of upstream's model with gravity compensation on the robot's
bodies (:func:`actuated_model`: MuJoCo sizes gravity compensation when it compiles a
model, so it cannot be switched on in upstream's), through
:class:`~unified_manip.envs.controllers.rig.MujocoRig`: the servos' own gains and force
limits are those of every mode, and one gripper entry commands both fingers.
"""

from __future__ import annotations

import copy
import functools

import mujoco
import numpy as np

from unified_manip.envs.controllers.rig import MujocoRig

ARM_JOINTS = tuple(f"robot:panda0_joint{i}" for i in range(1, 8))
ARM_ACTUATORS = tuple(f"panda0_joint{i}" for i in range(1, 8))
FINGER_ACTUATORS = ("r_gripper_finger_joint", "l_gripper_finger_joint")
#: The fingers' servo targets closed and open, m.
FINGER_CLOSED, FINGER_OPEN = 0.0, 0.04
#: The end-effector site between the fingers (the IK's frame).
EE_SITE = "end_effector"
#: The robot's base body: gravity compensation from here down.
ROBOT_ROOT = "panda0_link0"


@functools.cache
def _compiled(path: str) -> mujoco.MjModel:
    spec = mujoco.MjSpec.from_file(path)
    stack = [spec.body(ROBOT_ROOT)]
    while stack:
        body = stack.pop()
        body.gravcomp = 1.0
        stack.extend(body.bodies)
    return spec.compile()


def actuated_model(path: str, width: int, height: int) -> mujoco.MjModel:
    """Upstream's model at ``path`` with gravity compensation on the robot (compiled once
    per process; each call returns a copy of its own)."""
    model = copy.deepcopy(_compiled(path))
    model.vis.global_.offwidth = width
    model.vis.global_.offheight = height
    return model


class HeldRotation:
    """The end-effector modes' target rotation: the site's at reset (a picklable callable)."""

    def __init__(self, rotation: np.ndarray) -> None:
        self.rotation = rotation

    def __call__(self, target: np.ndarray) -> np.ndarray:
        return self.rotation


def franka_rig(model: mujoco.MjModel, data: mujoco.MjData, dt: float) -> MujocoRig:
    """The rig of the Franka in ``model`` (its pose in ``data`` at reset: the held
    end-effector rotation is the site's there)."""
    rig = MujocoRig(
        model,
        data,
        joints=ARM_JOINTS,
        actuators=ARM_ACTUATORS,
        gripper_actuators=FINGER_ACTUATORS,
        gripper_closed=FINGER_CLOSED,
        gripper_open=FINGER_OPEN,
        site=EE_SITE,
        dt=dt,
    )
    rig.ee_rotation = HeldRotation(data.site_xmat[rig.site_id].reshape(3, 3).copy())
    return rig
