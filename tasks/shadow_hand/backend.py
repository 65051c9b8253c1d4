"""The Shadow Hand backend: upstream's env object under ``native`` or ``joint_delta``."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from gymnasium_robotics.envs.shadow_dexterous_hand.hand_env import DEFAULT_CAMERA_CONFIG

from unified_manip.config import EnvConfig
from unified_manip.rendering import SceneOptions

from ..upstream import UpstreamBackend

#: The block is still on the hand while its centre is above this height, m (upstream's reset check).
BLOCK_ON_HAND_Z = 0.04
#: The finger actuators (J1) that also drive the distal joint J0.
COUPLED_FINGERS = ("FF", "MF", "RF", "LF")


#: How the scene is drawn: upstream's free camera, every geom group.
SCENE = SceneOptions(free_camera=DEFAULT_CAMERA_CONFIG)

class HandBackend(UpstreamBackend):
    """One Shadow Hand task under ``native`` or ``joint_delta``.

    Args:
        config: The validated env config.
        upstream_cls: The upstream env class, or its ``"module:Class"`` name.
        kind: ``"reach"`` or ``"push"`` (the block).
    """

    def __init__(self, config: EnvConfig, upstream_cls: type | str, kind: str) -> None:
        super().__init__(config, upstream_cls, "Shadow Hand", SCENE)
        self.kind = kind
        self.action_dim = 20
        self._relative = config.action_mode == "joint_delta"
        m = self._up.model
        self._ctrl_low = m.actuator_ctrlrange[:, 0].copy()
        self._ctrl_high = m.actuator_ctrlrange[:, 1].copy()
        self._half_range = (self._ctrl_high - self._ctrl_low) / 2.0
        # joint_delta: the qpos address of each actuator's joint (upstream: the actuator
        # name with ":A_" replaced by ":"), and of the coupled J0 for the J1 actuators.
        names = [m.actuator(i).name for i in range(m.nu)]
        self._act_qadr = np.array([m.jnt_qposadr[m.joint(n.replace(":A_", ":")).id] for n in names])
        self._coupled_act = np.array([names.index(f"robot0:A_{f}J1") for f in COUPLED_FINGERS])
        self._coupled_qadr = np.array([m.jnt_qposadr[m.joint(f"robot0:{f}J0").id] for f in COUPLED_FINGERS])
        if kind != "reach":
            self._palm = m.body("robot0:palm").id
            self._obj_q = int(m.jnt_qposadr[m.joint("object:joint").id])

    def apply(self, action: np.ndarray) -> dict[str, Any]:
        up = self._up
        a = action.astype(np.float32)  # upstream's action-space dtype
        if self._relative:
            q = up.data.qpos
            centre = q[self._act_qadr]
            centre[self._coupled_act] += q[self._coupled_qadr]
            up.data.ctrl[:] = np.clip(centre + a * self._half_range, self._ctrl_low, self._ctrl_high)
        else:
            up._set_action(a)
        up._mujoco_step(a)
        up._step_callback()
        return {}

    def reward_state(self) -> tuple[float, float]:
        """Block: (palm-to-block distance, 1 while the block is still on the hand, i.e.
        its centre above z = 0.04 m, upstream's reset criterion)."""
        if self.kind == "reach":
            return 0.0, 0.0
        d = self._up.data
        obj = d.qpos[self._obj_q : self._obj_q + 3]
        return math.dist(d.xpos[self._palm], obj), float(obj[2] > BLOCK_ON_HAND_Z)
