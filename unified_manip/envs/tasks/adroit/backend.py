"""The Adroit backend: upstream's env object (model, reset distribution) under its
action modes, with the goals and readings of :mod:`.tasks`."""

from __future__ import annotations

from typing import Any, Mapping

import mujoco
import numpy as np

from unified_manip.envs.backend import Backend
from unified_manip.envs.config import EnvConfig
from unified_manip.envs.controllers import ControllerConfig
from unified_manip.envs.lazy import resolve
from unified_manip.envs.observations import ObservationGroup
from unified_manip.envs.physics import bad_state_warnings
from unified_manip.envs.rendering import Renderer
from unified_manip.envs.tasks.adroit.cameras import SCENE
from unified_manip.envs.tasks.adroit.rig import AdroitRig
from unified_manip.envs.tasks.adroit.tasks import TASKS, AdroitTask
from unified_manip.envs.tasks.upstream import pickle_upstream, unpickle_upstream


class AdroitBackend(Backend):
    """One Adroit task under one of its action modes.

    Args:
        config: The validated env config (``options`` must be empty).
        controller: The action mode's controller config (resolved by ``env_setup``).
        task: The task's name in :data:`~.tasks.TASKS` (``"Relocate"``, ``"Door"``).
        upstream_cls: The upstream env class's ``"module:Class"`` name.

    Attributes:
        site, body, qadr: The ids of the task's sites and bodies, and the ``qpos``
            addresses of its joints, by name (what :mod:`.tasks` reads).
    """

    def __init__(self, config: EnvConfig, controller: ControllerConfig, task: str, upstream_cls: str) -> None:
        if config.options:
            raise TypeError(f"Adroit tasks take no extra options, got {sorted(config.options)}")
        up = resolve(upstream_cls)(reward_type="sparse", width=config.render_width, height=config.render_height)
        up.mujoco_renderer = None  # we render with our own renderer (see render())
        self._up = up
        self.task_name = task
        self.task: AdroitTask = TASKS[task]
        self.model, self.data = up.model, up.data
        m = up.model
        self.site = {name: m.site(name).id for name in self.task.sites}
        self.body = {name: m.body(name).id for name in self.task.bodies}
        self.qadr = {name: int(m.jnt_qposadr[m.joint(name).id]) for name in self.task.joints}
        self.dt = up.dt
        self._frames = up.frame_skip
        self._native = config.action_mode == "native"
        self._act_mean, self._act_rng = up.act_mean, up.act_rng
        self.rig = AdroitRig(m, up.data, self.dt)
        if not self._native:
            self.control = controller.build(self.rig)
        self.action_dim = m.nu
        self._readers = [self.task.groups[name].read for name in self.task.default]
        self._unstable = False
        self._renderer = Renderer(config.render_mode, config.render_width, config.render_height, SCENE)

    # -------------------------------------------------------------- episode
    def reset(self, np_random: np.random.Generator) -> None:
        """Upstream's reset (``mj_resetData``, then its ``reset_model``: the object's or
        door's and the target's placement) drawn from ``np_random``."""
        up = self._up
        up._np_random = np_random
        mujoco.mj_resetData(up.model, up.data)
        up.reset_model()
        if not self._native:
            self.control.reset()
        self._unstable = False

    def step(self, action: np.ndarray) -> dict[str, Any]:
        before = bad_state_warnings(self.data)
        if self._native:  # upstream's step: clip, then centre and scale onto the control range
            self.data.ctrl[:] = self._act_mean + action * self._act_rng
        else:
            self.control(action)
        self.physics_step()
        self._unstable = bad_state_warnings(self.data) > before
        return {}

    def physics_step(self) -> None:
        """Upstream's ``do_simulation``: ``frame_skip`` substeps, then ``mj_rnePostConstraint``."""
        m, d = self.model, self.data
        mujoco.mj_step(m, d, nstep=self._frames)
        mujoco.mj_rnePostConstraint(m, d)

    def unstable(self) -> bool:
        return self._unstable

    # -------------------------------------------------------------- observation
    def observation_groups(self) -> Mapping[str, ObservationGroup]:
        return self.task.groups

    def default_observation(self) -> tuple[str, ...]:
        return self.task.default

    def observation(self) -> np.ndarray:
        return np.concatenate([read(self) for read in self._readers])

    def achieved_goal(self) -> np.ndarray:
        return self.task.achieved(self)

    def desired_goal(self) -> np.ndarray:
        return self.task.desired(self)

    def quantities(self) -> dict[str, float]:
        return self.task.quantities(self)

    # -------------------------------------------------------------- rendering
    def render(self) -> np.ndarray | None:
        return self._renderer.render(self.model, self.data)

    def close(self) -> None:
        self._renderer.close()

    # -------------------------------------------------------------- pickling
    def __getstate__(self) -> dict[str, Any]:
        state = self.__dict__.copy()
        for key in ("task", "_readers", "model", "data"):  # the task's readers are lambdas
            del state[key]
        state["_up"] = pickle_upstream(self._up)
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        up = state["_up"] = unpickle_upstream(state["_up"])
        self.__dict__.update(state)
        self.task = TASKS[self.task_name]
        self._readers = [self.task.groups[name].read for name in self.task.default]
        self.model, self.data = up.model, up.data
        self.rig.model, self.rig.data = up.model, up.data
