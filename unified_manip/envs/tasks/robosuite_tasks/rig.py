"""The robosuite rig: a robot's arm joints and grip site, commanded through robosuite's
own part controllers (which the env was built with, :func:`.suite.controller_config`)."""

from __future__ import annotations

import numpy as np

from unified_manip.envs.controllers.ik import IKJoints


class SuiteRig:
    """One robosuite robot's arm, for the shared controllers.

    A command becomes the robot's part of the action vector of robosuite's ``step``
    (:attr:`pending`, a view of the backend's action, which holds each robot's part in
    turn): the arm entries (absolute joint targets for JOINT_POSITION, torques for
    JOINT_TORQUE), then the gripper with robosuite's sign (+1 closed). A robot without a
    gripper that moves (Wipe's wiping tool) has no gripper entry: ``has_gripper`` is False.

    Args:
        up: The robosuite env.
        joints: The arm joints, their ranges and the grip site.
        held_rotation: Maps the grip site's rotation at reset (and the env) to the one the
            end-effector modes hold (the task's choice).
        robot: Which of ``up.robots``.
        pending: The robot's part of the step's action (written in place).
    """

    def __init__(self, up, joints: IKJoints, held_rotation, robot: int, pending: np.ndarray) -> None:
        self._up = up
        self._robot = up.robots[robot]
        self.has_gripper = self._robot.gripper["right"].dof > 0
        self.model, self.data = up.sim.model._model, up.sim.data._data
        self.joints = joints
        self.n = joints.n
        self.qpos_adr, self.dof_adr = joints.qpos_adr, joints.dof_adr
        self.lower, self.upper = joints.lower, joints.upper
        self.site_name = joints.site_name
        self.site_id = self.model.site(joints.site_name).id
        self.dt = float(up.control_timestep)
        self._held_rotation = held_rotation
        self.rotation = np.eye(3)
        self.kind = "position"
        self.pending = pending

    def joint_positions(self) -> np.ndarray:
        return self.data.qpos[self.qpos_adr]

    def site_position(self) -> np.ndarray:
        return self.data.site_xpos[self.site_id]

    def ee_rotation(self, target: np.ndarray) -> np.ndarray:
        return self.rotation

    @property
    def max_torque(self) -> np.ndarray:
        """The arm actuators' torque limits (robosuite's controller reads them)."""
        return self._robot.part_controllers["right"].actuator_max

    def actuate(self, kind: str, **_) -> None:
        """robosuite's part controller for ``kind`` was chosen when the env was built."""
        if kind not in ("position", "torque"):
            raise ValueError(f"robosuite tasks command joint positions or torques, not {kind!r}")
        self.kind = kind

    def reset(self, kind: str) -> None:
        """After robosuite's reset, which rebuilds its controllers."""
        if kind == "torque":
            # Torques pass through JOINT_TORQUE unscaled: its input and output ranges are
            # both the actuator limits (its default maps |a| = 1 to 0.1 N m).
            c = self._robot.part_controllers["right"]
            c.output_max, c.output_min = c.actuator_max.copy(), c.actuator_min.copy()
            c.input_max, c.input_min = c.actuator_max.copy(), c.actuator_min.copy()
            c.action_scale = None
        self.rotation = self._held_rotation(self.data.site_xmat[self.site_id].reshape(3, 3), self._up)

    def command(self, arm: np.ndarray, gripper: float | None) -> None:
        command = self.pending
        if self.has_gripper:
            command[-1] = -gripper  # robosuite's GRIP: -1 open, +1 closed
            command[:-1] = arm
        else:
            command[:] = arm
