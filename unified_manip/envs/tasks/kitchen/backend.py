"""The kitchen backend: upstream's ``KitchenEnv`` (model, initial state, configuration)
under its action modes, with its noisy observation read as upstream's (:mod:`.readout`)
and the subtasks' goals of :mod:`.subtasks`. It calls no private member of upstream's env:
upstream's generator is not used (the noise is drawn from the env's own)."""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Mapping

import mujoco
import numpy as np

from unified_manip.envs.backend import Backend, Checkpoint
from unified_manip.envs.config import EnvConfig
from unified_manip.envs.controllers import ControllerConfig
from unified_manip.envs.lazy import resolve
from unified_manip.envs.observations import ObservationGroup
from unified_manip.envs.physics import bad_state_warnings
from unified_manip.envs.rendering import Renderer
from unified_manip.envs.tasks.kitchen import observations as obs_groups
from unified_manip.envs.tasks.kitchen.cameras import SCENE
from unified_manip.envs.tasks.kitchen.readout import KitchenReadout
from unified_manip.envs.tasks.kitchen.rig import EE_SITE, actuated_model, franka_rig
from unified_manip.envs.tasks.kitchen.subtasks import SubtaskDistance
from unified_manip.envs.tasks.upstream import pickle_upstream, unpickle_upstream

UPSTREAM = "gymnasium_robotics.envs.franka_kitchen.kitchen_env:KitchenEnv"


class KitchenBackend(Backend):
    """One kitchen task (a set of subtasks) under one of its action modes.

    Args:
        config: The validated env config (``options`` must be empty).
        controller: The action mode's controller config (resolved by ``env_setup``).
        distance: The task's goal distance, which names its subtasks in the goal's order.

    Attributes:
        ee_site: The end-effector site's id (the ``ee_pos`` group).
    """

    def __init__(self, config: EnvConfig, controller: ControllerConfig, distance: SubtaskDistance) -> None:
        if config.options:
            raise TypeError(f"kitchen tasks take no extra options, got {sorted(config.options)}")
        width, height = config.render_width, config.render_height
        up = resolve(UPSTREAM)(tasks_to_complete=list(distance.subtasks), width=width, height=height)
        up.robot_env.mujoco_renderer = None  # we render with our own renderer (see render())
        self._up = up
        self._goal_q = distance.qpos_indices
        self._target = distance.target
        self._native = config.action_mode == "native"
        robot = up.robot_env
        self.dt = robot.dt
        self._frames = robot.frame_skip
        self._readout = KitchenReadout(up)
        self._rng: np.random.Generator | None = None
        if self._native:
            self.action_dim = robot.model.nu
        else:  # the shared controllers run on the copy with gravity compensation (.rig)
            model = actuated_model(robot.fullpath, width, height)
            self._swap(model, mujoco.MjData(model))
            self._place_initial_state()
            self.rig = franka_rig(model, up.data, self.dt)
            self.control = controller.build(self.rig)
            self.action_dim = self.control.action_dim
        self.ee_site = up.model.site(EE_SITE).id
        self._obs: dict[str, np.ndarray] | None = None
        self._unstable = False
        self._renderer = Renderer(config.render_mode, width, height, SCENE)

    @property
    def model(self):
        return self._up.model

    @property
    def data(self):
        return self._up.data

    def _swap(self, model, data) -> None:
        """Give upstream's kitchen and robot envs (which hold one pair) ``model`` and ``data``."""
        up = self._up
        up.model = up.robot_env.model = model
        up.data = up.robot_env.data = data

    def _place_initial_state(self) -> None:
        """Upstream's ``reset_model``: ``mj_resetData``, then its initial ``qpos`` at rest."""
        robot = self._up.robot_env
        mujoco.mj_resetData(robot.model, robot.data)
        robot.set_state(robot.init_qpos, np.zeros(robot.model.nv))

    # -------------------------------------------------------------- episode
    def reset(self, np_random: np.random.Generator) -> None:
        """Upstream's reset: the fixed initial state, then the noisy observation drawn from
        ``np_random`` (the episode's only randomness)."""
        self._rng = np_random
        self._place_initial_state()
        if not self._native:
            self.control.reset()
        self._read()
        self._unstable = False

    def step(self, action: np.ndarray) -> dict[str, Any]:
        before = bad_state_warnings(self.data)
        if self._native:  # upstream's FrankaRobot.step
            self.data.ctrl[:] = self._readout.controls(action)
            diagnostics: dict[str, Any] = {}
        else:
            diagnostics = self.control(action)
        self.physics_step()
        self._unstable = bad_state_warnings(self.data) > before
        self._read()
        return diagnostics

    def physics_step(self) -> None:
        """Upstream's ``do_simulation``: ``frame_skip`` substeps, then ``mj_rnePostConstraint``."""
        m, d = self.model, self.data
        mujoco.mj_step(m, d, nstep=self._frames)
        mujoco.mj_rnePostConstraint(m, d)

    def _read(self) -> None:
        self._obs = {"observation": self._readout.observation(self.data, self._rng)}

    def unstable(self) -> bool:
        return self._unstable

    def checkpoint(self) -> Checkpoint:
        """Also the last observation's noisy joint positions, which ``native``'s servo
        targets start from (upstream's ``FrankaRobot.step``)."""
        return replace(super().checkpoint(), family=self._readout.last_q.copy())

    def restore(self, checkpoint: Checkpoint) -> None:
        super().restore(checkpoint)
        self._readout.last_q = checkpoint.family.copy()

    # -------------------------------------------------------------- observation
    def observation_groups(self) -> Mapping[str, ObservationGroup]:
        return obs_groups.GROUPS

    def default_observation(self) -> tuple[str, ...]:
        return obs_groups.DEFAULT

    def observation(self) -> np.ndarray:
        return self._obs["observation"]

    def achieved_goal(self) -> np.ndarray:
        return self.data.qpos[self._goal_q]

    def desired_goal(self) -> np.ndarray:
        return self._target.copy()

    def quantities(self) -> dict[str, float]:
        """None: the kitchen's terms read the goal distance alone (:mod:`.terms`)."""
        return {}

    # -------------------------------------------------------------- rendering
    def render(self) -> np.ndarray | None:
        return self._renderer.render(self.model, self.data)

    def close(self) -> None:
        self._renderer.close()

    # -------------------------------------------------------------- pickling
    def __getstate__(self) -> dict[str, Any]:
        state = self.__dict__.copy()
        state["_up"] = pickle_upstream(self._up)
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        state["_up"] = unpickle_upstream(state["_up"])
        self.__dict__.update(state)
        if not self._native:  # the rig and its controller point at upstream's model and data
            self.rig.model, self.rig.data = self.model, self.data
