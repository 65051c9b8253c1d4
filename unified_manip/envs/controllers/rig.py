"""Rigs: what a family supplies so that the shared controllers can drive its robot.

A rig is any object with these members (the controllers use nothing else):

=========================  ===================================================================
``n``                      arm joints the controllers command
``lower``, ``upper``       each joint's command range (rad)
``has_gripper``            whether the action's last entry commands a gripper
``max_torque``             torque limits (``joint_torque``)
``dt``                     seconds per env step
``model``, ``data``        the MuJoCo model and data (the IK reads them)
``qpos_adr``, ``dof_adr``  the joints' ``qpos``/``qvel`` addresses, and ``site_name``, the
                           grip site: what :class:`~.ik.MinkIK` solves for
``joint_positions()``      the measured joint positions
``site_position()``        the grip site's world position
``ee_rotation(target)``    the grip-site rotation the end-effector modes hold
``actuate(kind, ...)``     configure the actuators for a command kind, once
``reset(kind)``            what the actuators do at the start of an episode
``command(arm, gripper)``  send one step's joint command and gripper command (-1 closed, 1 open)
=========================  ===================================================================

:class:`MujocoRig` is the rig of a MuJoCo model whose arm has general position-servo
actuators (the 4-DOF arm, Fetch's actuated copy). robosuite and the Shadow Hand have
rigs of their own in their packages.
"""

from __future__ import annotations

from typing import Callable

import mujoco
import numpy as np


class MujocoRig:
    """An arm and its gripper inside a MuJoCo model, on general-actuator servos.

    Args:
        model: The model; its arm actuators must be force-limited ``general``
            position servos on the arm joints, in the same order as ``joints``. Their
            gains and force limits are the servo gains and torque limits of every mode.
        data: The data the env steps.
        joints: Names of the arm joints.
        actuators: Names of the arm actuators, one per joint.
        gripper_actuators: Names of the gripper's position actuators.
        gripper_closed: Gripper ctrl at action -1.
        gripper_open: Gripper ctrl at action +1.
        site: Name of the end-effector site (IK frame, reach goal).
        dt: Seconds per env step.
        ee_rotation: Maps a grip-site target to the rotation the end-effector modes
            hold (e.g. "pointing down"); may be set after construction.
    """

    has_gripper = True

    def __init__(
        self,
        model: mujoco.MjModel,
        data: mujoco.MjData,
        joints: tuple[str, ...],
        actuators: tuple[str, ...],
        gripper_actuators: tuple[str, ...],
        gripper_closed: float,
        gripper_open: float,
        site: str,
        dt: float = 0.0,
        ee_rotation: Callable[[np.ndarray], np.ndarray] | None = None,
    ) -> None:
        self.model, self.data, self.dt = model, data, dt
        self.joint_names = joints
        jids = np.array([model.joint(j).id for j in joints])
        self.qpos_adr = model.jnt_qposadr[jids].copy()
        self.dof_adr = model.jnt_dofadr[jids].copy()
        self.lower = model.jnt_range[jids, 0].copy()
        self.upper = model.jnt_range[jids, 1].copy()
        self.actuator_ids = np.array([model.actuator(a).id for a in actuators])
        self.gripper_ids = np.array([model.actuator(a).id for a in gripper_actuators])
        self.gripper_closed = float(gripper_closed)
        self.gripper_span = float(gripper_open) - float(gripper_closed)
        self.site_name = site
        self.site_id = model.site(site).id
        self.ee_rotation = ee_rotation
        self.n = len(joints)
        ids = self.actuator_ids
        if not np.all(model.actuator_forcelimited[ids]) or np.any(model.actuator_gainprm[ids, 0] <= 0):
            raise ValueError("arm actuators must be force-limited position servos (gainprm[0] = kp > 0)")
        self.kp = model.actuator_gainprm[ids, 0].copy()
        self.kv = -model.actuator_biasprm[ids, 2].copy()
        self.max_torque = model.actuator_forcerange[ids, 1].copy()

    # ------------------------------------------------------------------ reading
    def joint_positions(self) -> np.ndarray:
        return self.data.qpos[self.qpos_adr]

    def site_position(self) -> np.ndarray:
        return self.data.site_xpos[self.site_id]

    # ------------------------------------------------------------------ actuation
    def actuate(self, kind: str, kv: np.ndarray | None = None, max_velocity: np.ndarray | None = None) -> None:
        """Set the arm actuators' gains, bias and ctrl range for a command ``kind``
        (``kv`` and ``max_velocity``, per joint, for ``"velocity"``)."""
        m, ids = self.model, self.actuator_ids
        m.actuator_gaintype[ids] = mujoco.mjtGain.mjGAIN_FIXED
        m.actuator_biastype[ids] = mujoco.mjtBias.mjBIAS_AFFINE
        m.actuator_gainprm[ids, :] = 0.0
        m.actuator_biasprm[ids, :] = 0.0
        m.actuator_forcelimited[ids] = 1
        m.actuator_forcerange[ids, 0] = -self.max_torque
        m.actuator_forcerange[ids, 1] = self.max_torque
        m.actuator_ctrllimited[ids] = 1
        if kind == "torque":
            m.actuator_gainprm[ids, 0] = 1.0
            m.actuator_ctrlrange[ids, 0] = -self.max_torque
            m.actuator_ctrlrange[ids, 1] = self.max_torque
        elif kind == "velocity":
            assert kv is not None and max_velocity is not None, "velocity actuation needs kv and max_velocity"
            # force = (kv + d) v_cmd - kv qdot: the feed-forward d v_cmd cancels the
            # joint's passive damping d, so the joint settles at exactly v_cmd.
            m.actuator_gainprm[ids, 0] = kv + m.dof_damping[self.dof_adr]
            m.actuator_biasprm[ids, 2] = -kv
            m.actuator_ctrlrange[ids, 0] = -max_velocity
            m.actuator_ctrlrange[ids, 1] = max_velocity
        elif kind == "position":
            m.actuator_gainprm[ids, 0] = self.kp
            m.actuator_biasprm[ids, 1] = -self.kp
            m.actuator_biasprm[ids, 2] = -self.kv
            m.actuator_ctrlrange[ids, 0] = self.lower
            m.actuator_ctrlrange[ids, 1] = self.upper
        else:
            raise ValueError(f"unknown command kind {kind!r}; expected 'position', 'torque' or 'velocity'")

    def reset(self, kind: str) -> None:
        """Servo targets at the current joint positions; zero torque or speed otherwise."""
        if kind == "position":
            self.data.ctrl[self.actuator_ids] = self.data.qpos[self.qpos_adr]
        else:
            self.data.ctrl[self.actuator_ids] = 0.0

    def command(self, arm: np.ndarray, gripper: float) -> None:
        self.data.ctrl[self.actuator_ids] = arm
        self.set_gripper(gripper)

    def set_gripper(self, command: float) -> None:
        self.data.ctrl[self.gripper_ids] = self.gripper_closed + (command + 1.0) * 0.5 * self.gripper_span

    def hold_current_pose(self) -> None:
        """Set servo targets to the current joint positions (after a reset)."""
        self.reset("position")


class FixedRotation:
    """A rig's ``ee_rotation`` that holds one rotation whatever the target (a picklable
    callable): e.g. the grip site's rotation at the start, "pointing down"."""

    def __init__(self, rotation: np.ndarray) -> None:
        self.rotation = rotation

    def __call__(self, target: np.ndarray) -> np.ndarray:
        return self.rotation
