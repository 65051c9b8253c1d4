"""The joint-space controllers: one implementation per joint mode, over any rig.

The action is ``n`` joint entries plus, where the rig has a gripper, one gripper entry
(-1 closed, +1 open). The stateless ones are affine, ``a * scale + offset`` or
``q + a * scale`` (``offset`` None; clipped to the range if the config says so), and
say so through ``scale``/``offset`` (the native vector env batches them).

Each also answers :meth:`action_toward`: the (unclipped) arm action that, this step,
commands the joints toward a joint position target ``q_target``: what lets a policy that
thinks in position targets (e.g. the scripted ``ee_delta`` policies through IK,
:mod:`.translate`) act in every joint mode.
"""

from __future__ import annotations

from typing import Any

import numpy as np


class _JointController:
    """What the joint controllers share: the action layout, reset and the command."""

    #: What it carries between steps (:mod:`.memory`).
    memory: tuple[str, ...] = ()

    def __init__(self, config, rig) -> None:
        self.config, self.rig = config, rig
        self.n = rig.n
        self.action_dim = rig.n + int(rig.has_gripper)

    def reset(self) -> None:
        self.rig.reset(self.config.command)

    def _send(self, arm: np.ndarray, action: np.ndarray) -> dict[str, Any]:
        self.rig.command(arm, action[self.n] if self.rig.has_gripper else None)
        return {}


class JointTorqueController(_JointController):
    """Torque ``a * max_torque`` (the rig's limits)."""

    def __init__(self, config, rig) -> None:
        super().__init__(config, rig)
        rig.actuate("torque")
        self.offset = np.zeros(rig.n)

    @property
    def scale(self) -> np.ndarray:
        return self.rig.max_torque

    def __call__(self, action: np.ndarray) -> dict[str, Any]:
        return self._send(action[: self.n] * self.rig.max_torque, action)

    def action_toward(self, q_target: np.ndarray) -> np.ndarray:
        """The rig's own position servo as torques: ``kp (q* - q) - kv q'`` (gravity is
        compensated by the model); ``ValueError`` on a rig without servo gains (robosuite's
        arms, whose position control is robosuite's own controller)."""
        rig = self.rig
        if not hasattr(rig, "kp"):
            raise ValueError("joint_torque here has no servo gains (kp, kv) to turn joint targets into torques")
        torque = rig.kp * (q_target - rig.joint_positions()) - rig.kv * rig.data.qvel[rig.dof_adr]
        return torque / rig.max_torque


class JointPositionController(_JointController):
    """Absolute target ``a * half_range + mid`` over each joint's command range."""

    def __init__(self, config, rig) -> None:
        super().__init__(config, rig)
        rig.actuate("position")
        self.scale = 0.5 * (rig.upper - rig.lower)
        self.offset = 0.5 * (rig.upper + rig.lower)

    def __call__(self, action: np.ndarray) -> dict[str, Any]:
        return self._send(action[: self.n] * self.scale + self.offset, action)

    def action_toward(self, q_target: np.ndarray) -> np.ndarray:
        return (q_target - self.offset) / self.scale


class JointPositionBandController(_JointController):
    """Absolute target ``q_reset + a * band``, clipped to the range: ``joint_position``
    over a band around the posture the episode started in."""

    memory = ("center",)

    def __init__(self, config, rig) -> None:
        super().__init__(config, rig)
        rig.actuate("position")
        band = np.atleast_1d(np.asarray(config.band, float))
        if band.shape not in ((1,), (rig.n,)):
            raise ValueError(f"JointPosition.band has {band.size} entries; expected 1 or one per arm joint ({rig.n})")
        self.scale = np.broadcast_to(band, (rig.n,)).copy()
        self.center = np.zeros(rig.n)

    def reset(self) -> None:
        super().reset()
        self.center = np.array(self.rig.joint_positions(), dtype=np.float64)

    def __call__(self, action: np.ndarray) -> dict[str, Any]:
        rig = self.rig
        target = self.center + action[: self.n] * self.scale
        return self._send(np.minimum(np.maximum(target, rig.lower), rig.upper), action)

    def action_toward(self, q_target: np.ndarray) -> np.ndarray:
        return (q_target - self.center) / self.scale


class JointDeltaController(_JointController):
    """Target ``q + a * max_delta`` from the measured ``q`` (clipped if configured)."""

    offset = None

    def __init__(self, config, rig) -> None:
        super().__init__(config, rig)
        rig.actuate("position")
        if config.max_delta == "half_range":
            self.scale = (rig.upper - rig.lower) / 2.0
        else:
            self.scale = np.full(rig.n, config.max_delta)

    def __call__(self, action: np.ndarray) -> dict[str, Any]:
        rig = self.rig
        target = rig.joint_positions() + action[: self.n] * self.scale
        if self.config.clip:
            target = np.minimum(np.maximum(target, rig.lower), rig.upper)
        return self._send(target, action)

    def action_toward(self, q_target: np.ndarray) -> np.ndarray:
        return (q_target - self.rig.joint_positions()) / self.scale


class JointTargetDeltaController(_JointController):
    """Target ``previous target + a * max_delta``, clipped to the range; the measured
    ``q`` at reset."""

    memory = ("target",)

    def __init__(self, config, rig) -> None:
        super().__init__(config, rig)
        rig.actuate("position")
        self.scale = np.full(rig.n, config.max_delta)
        self.target = np.zeros(rig.n)

    def reset(self) -> None:
        super().reset()
        self.target = np.array(self.rig.joint_positions(), dtype=np.float64)

    def __call__(self, action: np.ndarray) -> dict[str, Any]:
        rig = self.rig
        target = self.target + action[: self.n] * self.scale
        self.target = np.minimum(np.maximum(target, rig.lower), rig.upper)
        return self._send(self.target.copy(), action)

    def action_toward(self, q_target: np.ndarray) -> np.ndarray:
        return (q_target - self.target) / self.scale

    def lead(self) -> np.ndarray:
        """How far the carried target leads the measured joints, in full action steps."""
        return (self.target - self.rig.joint_positions()) / self.scale


class JointVelocityController(_JointController):
    """Velocity servos tracking ``a * max_velocity``."""

    def __init__(self, config, rig) -> None:
        super().__init__(config, rig)
        n = rig.n
        self.offset = np.zeros(n)
        self.kv = np.broadcast_to(np.asarray(config.kv, float), (n,)).copy()
        self.scale = np.broadcast_to(np.asarray(config.max_velocity, float), (n,)).copy()
        rig.actuate("velocity", kv=self.kv, max_velocity=self.scale)

    def __call__(self, action: np.ndarray) -> dict[str, Any]:
        return self._send(action[: self.n] * self.scale, action)

    def action_toward(self, q_target: np.ndarray) -> np.ndarray:
        """The speed that covers the distance in one env step."""
        return (q_target - self.rig.joint_positions()) / (self.rig.dt * self.scale)


class IntegratedJointVelocityController(_JointController):
    """``a * max_velocity`` integrated into a position target, within ``max_lead`` of
    the measured position and within the range."""

    memory = ("target",)

    def __init__(self, config, rig) -> None:
        super().__init__(config, rig)
        rig.actuate("position")
        self.target = np.zeros(rig.n)

    def reset(self) -> None:
        super().reset()
        self.target = np.array(self.rig.joint_positions(), dtype=np.float64)

    def __call__(self, action: np.ndarray) -> dict[str, Any]:
        rig, c = self.rig, self.config
        q = rig.joint_positions()
        target = self.target + action[: self.n] * (c.max_velocity * rig.dt)
        target = np.minimum(np.maximum(target, q - c.max_lead), q + c.max_lead)
        self.target = np.minimum(np.maximum(target, rig.lower), rig.upper)
        return self._send(self.target.copy(), action)

    def action_toward(self, q_target: np.ndarray) -> np.ndarray:
        return (q_target - self.target) / (self.config.max_velocity * self.rig.dt)

    def lead(self) -> np.ndarray:
        """How far the carried target leads the measured joints, in full action steps."""
        return (self.target - self.rig.joint_positions()) / (self.config.max_velocity * self.rig.dt)
