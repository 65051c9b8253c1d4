"""The Sawyer of the joint and end-effector modes: Meta-World's model with the mocap weld
removed and the arm's 7 joints on position servos, and the rig the shared controllers
drive.

Meta-World moves the hand with a mocap body welded to it; the arm's joints have no
actuators. These modes run on an actuated copy of the model (MjSpec): the weld
deleted, gravity compensation on the arm, a force-limited position servo per joint (the
rig switches it to torque for ``joint_torque``), and an armature on the arm joints (the
model's are 0; measured: servos on them diverge within 0.15 s at Meta-World's 2.5 ms
step, with 0.1 kg m^2 they hold still to 1e-13 rad). The fingers keep Meta-World's two
position actuators.

Version 1 lowers the wrists' joint damping (:data:`.specs.WRIST_DAMPING`). Meta-World's model
damps every arm joint with 10 N m s/rad; a wrist's 9 N m limit then holds it to 0.9 rad/s,
so on fast moves the wrists lag the IK's joint plan and the hand leaves its commanded
line (measured: Reach, seed 0, ``ee_delta`` commanded +x -z for ~80 steps moved the hand
-x +z). Meta-World never meets the cap: its mocap moves the hand.
"""

from __future__ import annotations

import mujoco
import numpy as np

from unified_manip.envs.controllers.rig import FixedRotation, MujocoRig
from unified_manip.envs.mujoco_version import delete_element, set_to_position

ARM_JOINTS = tuple(f"right_j{i}" for i in range(7))
ARM_ACTUATORS = tuple(f"servo_j{i}" for i in range(7))
#: The fingers' actuators (unnamed in Meta-World's model; named after their joints here),
#: in Meta-World's control order: its gripper action ``a`` sets them to ``(a, -a)``.
FINGER_ACTUATORS = ("finger_r_close", "finger_l_close")
#: The grip site of the end-effector modes: Meta-World's ``endEffector``, on the hand
#: between the fingers, 5 mm above the fingertips' midpoint (the fingers' own sites move
#: as they open and close).
GRIP_SITE = "endEffector"
#: Servo gains, N m/rad, and torque limits, N m (the Sawyer's rated joint torques).
ARM_KP = (1000.0, 1000.0, 500.0, 500.0, 100.0, 100.0, 100.0)
ARM_TORQUE = (80.0, 80.0, 40.0, 40.0, 9.0, 9.0, 9.0)
#: The arm joints' armature, kg m^2 (see the module docstring).
ARM_ARMATURE = 0.1
#: The wrist joints, whose damping version 1 lowers (the module docstring).
WRIST_JOINTS = ARM_JOINTS[4:]
#: The first arm body: gravity compensation from here down.
ARM_ROOT = "right_l0"


def actuated_model(path: str, wrist_damping: float | None = None) -> mujoco.MjModel:
    """Meta-World's model at ``path``, with the arm on position servos (module docstring),
    and the wrists' joint damping set to ``wrist_damping`` N m s/rad (None keeps the
    model's: version 0)."""
    spec = mujoco.MjSpec.from_file(path)
    if wrist_damping is not None:
        for joint in WRIST_JOINTS:
            spec.joint(joint).damping = wrist_damping
    for eq in list(spec.equalities):
        if eq.type == mujoco.mjtEq.mjEQ_WELD:
            delete_element(spec, eq)
    stack = [spec.body(ARM_ROOT)]
    while stack:
        body = stack.pop()
        body.gravcomp = 1.0
        stack.extend(body.bodies)
    for a in spec.actuators:
        if a.target in ("r_close", "l_close"):
            a.name = f"finger_{a.target}"
    for joint, actuator, kp, tau in zip(ARM_JOINTS, ARM_ACTUATORS, ARM_KP, ARM_TORQUE):
        spec.joint(joint).armature = ARM_ARMATURE
        a = spec.add_actuator(name=actuator, target=joint, trntype=mujoco.mjtTrn.mjTRN_JOINT)
        set_to_position(a, kp=kp)
        a.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
        a.forcerange = [-tau, tau]
    model = spec.compile()
    # Critical damping at the model's rest pose: kv = 2 sqrt(kp M_jj), M_jj the joint's
    # diagonal of the joint-space inertia (armature included).
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    inertia = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, inertia, data.qM)
    ids = np.array([model.actuator(a).id for a in ARM_ACTUATORS])
    dofs = model.jnt_dofadr[model.actuator_trnid[ids, 0]]
    model.actuator_biasprm[ids, 2] = -2.0 * np.sqrt(np.array(ARM_KP) * inertia[dofs, dofs])
    return model


class MetaWorldRig(MujocoRig):
    """The actuated Sawyer for the shared controllers. Its gripper command is
    Meta-World's with the sign of this interface: -1 closes (Meta-World's +1: finger
    controls ``(1, -1)``), +1 opens. Its grip site is :data:`GRIP_SITE`; the end-effector
    modes hold the hand's rotation at the episode's start (:meth:`hold_rotation`), as
    Meta-World's mocap holds one rotation."""

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData, dt: float) -> None:
        super().__init__(
            model,
            data,
            joints=ARM_JOINTS,
            actuators=ARM_ACTUATORS,
            gripper_actuators=FINGER_ACTUATORS,
            gripper_closed=1.0,
            gripper_open=-1.0,
            site=GRIP_SITE,
            dt=dt,
            ee_rotation=FixedRotation(np.eye(3)),
        )

    def hold_rotation(self) -> None:
        """Make the grip site's present rotation the one the end-effector modes hold."""
        self.ee_rotation = FixedRotation(self.data.site_xmat[self.site_id].reshape(3, 3).copy())

    def set_gripper(self, command: float) -> None:
        self.data.ctrl[self.gripper_ids] = (-command, command)
