"""The Shadow Hand backend: upstream's env object under its action modes."""

from __future__ import annotations

import math
from typing import Any, Mapping

import numpy as np
from gymnasium_robotics.envs.shadow_dexterous_hand.hand_env import DEFAULT_CAMERA_CONFIG

from unified_manip.envs.config import EnvConfig
from unified_manip.envs.controllers import ControllerConfig
from unified_manip.envs.observations import ObservationGroup
from unified_manip.envs.rendering import SceneOptions
from unified_manip.envs.tasks import upstream_private as private
from unified_manip.envs.tasks.gripper_terms import GRASPED, GRIP_TO_OBJECT
from unified_manip.envs.tasks.shadow_hand import observations as obs_groups
from unified_manip.envs.tasks.shadow_hand.rig import HandRig
from unified_manip.envs.tasks.upstream import UpstreamBackend

#: The block is still on the hand while its centre is above this height, m (upstream's reset check).
BLOCK_ON_HAND_Z = 0.04

#: How the scene is drawn: upstream's free camera, every geom group.
SCENE = SceneOptions(free_camera=DEFAULT_CAMERA_CONFIG)


class HandBackend(UpstreamBackend):
    """One Shadow Hand task under one of its action modes.

    Args:
        config: The validated env config.
        controller: The action mode's controller config (resolved by ``env_setup``).
        upstream_cls: The upstream env class, or its ``"module:Class"`` name.
        has_object: Whether the task has an object (the block).
    """

    def __init__(
        self, config: EnvConfig, controller: ControllerConfig, upstream_cls: type | str, has_object: bool
    ) -> None:
        super().__init__(config, upstream_cls, "Shadow Hand", SCENE)
        self.has_object = has_object
        self._native = config.action_mode == "native"
        self.rig = HandRig(self._up.model, self._up.data, self.dt)
        if not self._native:
            self.control = controller.build(self.rig)
        self.action_dim = self.rig.n
        m = self._up.model
        if has_object:
            self._palm = m.body("robot0:palm").id
            self._obj_q = int(m.jnt_qposadr[m.joint("object:joint").id])

    def apply(self, action: np.ndarray) -> dict[str, Any]:
        up = self._up
        a = action.astype(np.float32)  # upstream's action-space dtype
        if self._native:
            private.set_action(up, a)
        else:
            self.control(action)
        private.mujoco_step(up, a)
        private.step_callback(up)
        return {}

    def after_reset(self) -> None:
        if not self._native:
            self.control.reset()

    def after_unpickle(self) -> None:
        self.rig.model, self.rig.data = self._up.model, self._up.data

    def observation_groups(self) -> Mapping[str, ObservationGroup]:
        return obs_groups.BLOCK_GROUPS if self.has_object else obs_groups.REACH_GROUPS

    def default_observation(self) -> tuple[str, ...]:
        return obs_groups.BLOCK_DEFAULT if self.has_object else obs_groups.REACH_DEFAULT

    def quantities(self) -> dict[str, float]:
        """Block: ``grip_to_object``, the palm-to-block distance (m), and ``grasped``, 1
        while the block is still on the hand, i.e. its centre above z = 0.04 m (upstream's
        reset criterion); 0 and 0 on HandReach (:mod:`~unified_manip.envs.tasks.gripper_terms`)."""
        if not self.has_object:
            return {GRIP_TO_OBJECT: 0.0, GRASPED: 0.0}
        d = self._up.data
        obj = d.qpos[self._obj_q : self._obj_q + 3]
        return {GRIP_TO_OBJECT: math.dist(d.xpos[self._palm], obj), GRASPED: float(obj[2] > BLOCK_ON_HAND_Z)}
