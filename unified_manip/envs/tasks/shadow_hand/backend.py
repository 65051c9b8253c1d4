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

#: The object is still on the hand while its centre is above this height, m (upstream's reset check).
OBJECT_ON_HAND_Z = 0.04

#: How the scene is drawn: upstream's free camera, every geom group.
SCENE = SceneOptions(free_camera=DEFAULT_CAMERA_CONFIG)


class HandBackend(UpstreamBackend):
    """One Shadow Hand task under one of its action modes.

    Args:
        config: The validated env config.
        controller: The action mode's controller config (resolved by ``env_setup``).
        upstream_cls: The upstream env class, or its ``"module:Class"`` name.
        held: The object on the palm (``"block"``, ``"egg"``, ``"pen"``), or ``None``
            (HandReach).
        quantities: The names the task's term set reads the two object quantities by:
            the palm-to-object distance and the on-the-hand flag (:meth:`quantities`).
        upstream_kwargs: More constructor arguments of the upstream env (the ``Rotate``
            variants' ``target_position="ignore"``).
    """

    def __init__(
        self,
        config: EnvConfig,
        controller: ControllerConfig,
        upstream_cls: type | str,
        held: str | None = None,
        quantities: tuple[str, str] = (GRIP_TO_OBJECT, GRASPED),
        upstream_kwargs: Mapping[str, Any] | None = None,
    ) -> None:
        super().__init__(config, upstream_cls, "Shadow Hand", SCENE, upstream_kwargs)
        self.held = held
        self._names = quantities
        self._native = config.action_mode == "native"
        self.rig = HandRig(self._up.model, self._up.data, self.dt)
        if not self._native:
            self.control = controller.build(self.rig)
        self.action_dim = self.rig.n
        m = self._up.model
        if held is not None:
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
        return obs_groups.REACH_GROUPS if self.held is None else obs_groups.OBJECT_GROUPS[self.held]

    def default_observation(self) -> tuple[str, ...]:
        return obs_groups.REACH_DEFAULT if self.held is None else obs_groups.OBJECT_DEFAULT

    def quantities(self) -> dict[str, float]:
        """With an object, under the term set's two names (``grip_to_object`` and
        ``grasped`` for the block, :mod:`~unified_manip.envs.tasks.gripper_terms`;
        ``palm_to_object`` and ``on_palm`` for the egg and pen,
        :mod:`~unified_manip.envs.tasks.shadow_hand.terms`): the palm-to-object distance
        (m), and 1 while the object is still on the hand, i.e. its centre above z =
        0.04 m (upstream's reset criterion). HandReach: ``grip_to_object`` and
        ``grasped``, 0 and 0."""
        distance, on_hand = self._names
        if self.held is None:
            return {distance: 0.0, on_hand: 0.0}
        d = self._up.data
        obj = d.qpos[self._obj_q : self._obj_q + 3]
        return {distance: math.dist(d.xpos[self._palm], obj), on_hand: float(obj[2] > OBJECT_ON_HAND_Z)}
