"""The Fetch backend: upstream's env object, with our action modes on an actuated copy
of its model (see the package docs)."""

from __future__ import annotations

import math
from typing import Any, Mapping

import mujoco
import numpy as np
from gymnasium_robotics.envs.fetch.fetch_env import DEFAULT_CAMERA_CONFIG

from unified_manip.envs.config import EnvConfig
from unified_manip.envs.controllers import ControllerConfig
from unified_manip.envs.controllers.rig import FixedRotation, MujocoRig
from unified_manip.envs.observations import ObservationGroup
from unified_manip.envs.rendering import SceneOptions
from unified_manip.envs.tasks import upstream_private as private
from unified_manip.envs.tasks.contacts import touches_both
from unified_manip.envs.tasks.fetch import observations as obs_groups
from unified_manip.envs.tasks.fetch.model import actuated_model
from unified_manip.envs.tasks.fetch.scene import (
    ARM_ACTUATORS,
    ARM_JOINTS,
    FINGER_GEOMS,
    FINGER_JOINTS,
    FINGER_OPEN,
    GRASP_RADIUS,
    GRIP_SITE,
    OBJECT_GEOM,
    OBS_REL,
)
from unified_manip.envs.tasks.gripper_terms import GRASPED, GRIP_TO_OBJECT
from unified_manip.envs.tasks.upstream import UpstreamBackend

#: How the scene is drawn: upstream's free camera, every geom group.
SCENE = SceneOptions(free_camera=DEFAULT_CAMERA_CONFIG)


class FetchBackend(UpstreamBackend):
    """One Fetch task under one action mode (see the package docs).

    Args:
        config: The validated env config.
        controller: The action mode's controller config (resolved by ``env_setup``).
        upstream_cls: The upstream env class, or its ``"module:Class"`` name.
        has_object: Whether the task has an object (all but Reach).
    """

    def __init__(
        self, config: EnvConfig, controller: ControllerConfig, upstream_cls: type | str, has_object: bool
    ) -> None:
        super().__init__(config, upstream_cls, "Fetch", SCENE)
        self.has_object = has_object
        self.mode = config.action_mode
        up = self._up
        self._native = self.mode == "native"
        # The joint-space modes observe the arm's joints too (14 entries).
        self._joint_obs = controller.space == "joint"
        if not self._native:
            model = actuated_model(up.fullpath, up.initial_qpos, config.render_width, config.render_height)
            private.replace_model(up, model, mujoco.MjData(model))
            mujoco.mj_resetData(up.model, up.data)
            up.data.qpos[:] = up.initial_qpos
            up.data.qvel[:] = up.initial_qvel
            mujoco.mj_forward(up.model, up.data)
            blocked = up.block_gripper  # Reach, Push, Slide: fingers held closed
            self.rig = MujocoRig(
                up.model,
                up.data,
                joints=ARM_JOINTS,
                actuators=ARM_ACTUATORS,
                gripper_actuators=FINGER_JOINTS,
                gripper_closed=0.0,
                gripper_open=0.0 if blocked else FINGER_OPEN,
                site=GRIP_SITE,
                dt=up.dt,
            )
            rotation = up.data.site_xmat[self.rig.site_id].reshape(3, 3).copy()  # pointing down
            self.rig.ee_rotation = FixedRotation(rotation)
            self.control = controller.build(self.rig)
            self.action_dim = self.control.action_dim
        else:
            self.action_dim = 4
        m = up.model
        self._arm_q = m.jnt_qposadr[[m.joint(j).id for j in ARM_JOINTS]]
        self._arm_v = m.jnt_dofadr[[m.joint(j).id for j in ARM_JOINTS]]
        if has_object:
            self._obj_geom = m.geom(OBJECT_GEOM).id
            self._finger_geoms = tuple(m.geom(g).id for g in FINGER_GEOMS)

    # -------------------------------------------------------------- episode
    def after_reset(self) -> None:
        if not self._native:
            self.control.reset()
            self.rig.set_gripper(-1.0)  # ctrl 0, as upstream's reset leaves it

    def apply(self, action: np.ndarray) -> dict[str, Any]:
        up = self._up
        if self._native:
            # Upstream clips in the action space's dtype (float32) and scales in it.
            a = action.astype(np.float32)
            private.set_action(up, a)
            private.mujoco_step(up, a)
            private.step_callback(up)
            return {}
        diagnostics = self.control(action)
        private.mujoco_step(up, action)
        return diagnostics

    # -------------------------------------------------------------- observation
    def observation(self) -> np.ndarray:
        obs = self._obs["observation"]
        if not self._joint_obs:
            return obs
        d = self._up.data
        return np.concatenate((obs, d.qpos[self._arm_q], d.qvel[self._arm_v]))

    def observation_groups(self) -> Mapping[str, ObservationGroup]:
        return obs_groups.OBJECT_GROUPS if self.has_object else obs_groups.REACH_GROUPS

    def default_observation(self) -> tuple[str, ...]:
        default = obs_groups.OBJECT_DEFAULT if self.has_object else obs_groups.REACH_DEFAULT
        return default + obs_groups.JOINT_MODE_EXTRA if self._joint_obs else default

    def quantities(self) -> dict[str, float]:
        """``grip_to_object`` (grip site to cube, m) and ``grasped`` (both fingers touch the
        cube); 0 and 0 without an object (:mod:`~unified_manip.envs.tasks.gripper_terms`)."""
        if not self.has_object:
            return {GRIP_TO_OBJECT: 0.0, GRASPED: 0.0}
        rel = self._obs["observation"][OBS_REL]  # object - grip, m
        dist = math.sqrt(float(rel @ rel))
        # Only a cube between the fingers can be held: skip the contact scan otherwise.
        held = float(dist < GRASP_RADIUS and touches_both(self._up.data, self._obj_geom, *self._finger_geoms))
        return {GRIP_TO_OBJECT: dist, GRASPED: held}

    # -------------------------------------------------------------- pickling
    def after_unpickle(self) -> None:
        if not self._native:  # the rig and its controller point at the same model/data
            self.rig.model, self.rig.data = self._up.model, self._up.data
