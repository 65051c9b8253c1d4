"""The base of the families that wrap a gymnasium-robotics env object (Fetch, Shadow Hand).

These backends keep the upstream env (its model, reset, goal sampling, observation
and ``native`` control code) and drive its methods directly, so the task is exactly
upstream's. :class:`UpstreamBackend` holds what they share; a family adds how an action
is applied (:meth:`UpstreamBackend.apply`) and what its reward terms read. Every private
member of the upstream env they call is called through
:mod:`unified_manip.envs.tasks.upstream_private`, which names each and why. Two things
need care:

* **Seeding.** ``UnifiedManipEnv.reset(seed=s)`` seeds its own ``np_random`` exactly
  as ``gymnasium.Env.reset(seed=s)`` does; :func:`upstream_private.reset
  <unified_manip.envs.tasks.upstream_private.reset>` hands that generator to the upstream
  env before running upstream's reset steps, so a seed gives the same episode as
  ``gym.make(<upstream id>).reset(seed=s)``.
* **Pickling.** Upstream envs are ``EzPickle``: unpickling rebuilds them from their
  constructor arguments and loses the simulator state. :func:`pickle_upstream` stores
  the object's ``__dict__`` instead (model and data pickle with their full state),
  minus module references and the renderer, which :func:`unpickle_upstream` restores.
"""

from __future__ import annotations

import abc
import importlib
import types
from typing import Any, Mapping

import numpy as np

from unified_manip.envs.backend import Backend
from unified_manip.envs.config import EnvConfig
from unified_manip.envs.lazy import resolve
from unified_manip.envs.physics import bad_state_warnings
from unified_manip.envs.rendering import Renderer, SceneOptions
from unified_manip.envs.tasks import upstream_private as private


def pickle_upstream(env: Any) -> tuple[type, dict[str, Any], dict[str, str]]:
    """A picklable snapshot of an upstream env object, state included."""
    state, modules = {}, {}
    for key, value in env.__dict__.items():
        if isinstance(value, types.ModuleType):
            modules[key] = value.__name__
        elif key != "mujoco_renderer":
            state[key] = value
    return type(env), state, modules


def unpickle_upstream(snapshot: tuple[type, dict[str, Any], dict[str, str]]) -> Any:
    cls, state, modules = snapshot
    env = cls.__new__(cls)
    env.__dict__.update(state)
    for key, name in modules.items():
        setattr(env, key, importlib.import_module(name))
    env.mujoco_renderer = None  # the backends render with their own renderer
    return env


class UpstreamBackend(Backend):
    """One task over a gymnasium-robotics env object.

    Args:
        config: The validated env config (``options`` must be empty).
        upstream: The upstream env class, or its ``"module:Class"`` name.
        family: The family's name, for error messages.
        scene: How the family's scene is drawn.
        upstream_kwargs: More constructor arguments of the upstream env (a task variant's).
    """

    def __init__(
        self,
        config: EnvConfig,
        upstream: type | str,
        family: str,
        scene: SceneOptions,
        upstream_kwargs: Mapping[str, Any] | None = None,
    ) -> None:
        if config.options:
            raise TypeError(f"{family} tasks take no extra options, got {sorted(config.options)}")
        cls = resolve(upstream) if isinstance(upstream, str) else upstream
        kwargs = dict(upstream_kwargs or {})
        up = cls(reward_type="sparse", width=config.render_width, height=config.render_height, **kwargs)
        up.mujoco_renderer = None  # we render with our own renderer (see render())
        self._up = up
        self.dt = up.dt
        self._obs: dict[str, np.ndarray] | None = None
        self._unstable = False
        self._renderer = Renderer(config.render_mode, config.render_width, config.render_height, scene)

    @property
    def model(self):
        return self._up.model

    @property
    def data(self):
        return self._up.data

    # -------------------------------------------------------------- what a family adds
    @abc.abstractmethod
    def apply(self, action: np.ndarray) -> dict[str, Any]:
        """Apply ``action`` and advance upstream's simulation one env step; return
        diagnostics for ``info``."""

    def after_reset(self) -> None:
        """Called after upstream's reset, before the first observation is read."""

    # -------------------------------------------------------------- episode
    def reset(self, np_random: np.random.Generator) -> None:
        private.reset(self._up, np_random)
        self.after_reset()
        self._obs = private.observation(self._up)
        self._unstable = False

    def step(self, action: np.ndarray) -> dict[str, Any]:
        before = bad_state_warnings(self._up.data)
        diagnostics = self.apply(action)
        self._unstable = bad_state_warnings(self._up.data) > before
        self._obs = private.observation(self._up)
        return diagnostics

    def unstable(self) -> bool:
        return self._unstable

    # -------------------------------------------------------------- observation
    def observation(self) -> np.ndarray:
        return self._obs["observation"]

    def achieved_goal(self) -> np.ndarray:
        return self._obs["achieved_goal"]

    def desired_goal(self) -> np.ndarray:
        return self._obs["desired_goal"]

    # -------------------------------------------------------------- rendering
    def render(self) -> np.ndarray | None:
        up = self._up
        private.render_callback(up)  # upstream: show the goal
        return self._renderer.render(up.model, up.data)

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
        self.after_unpickle()

    def after_unpickle(self) -> None:
        """Re-point anything that holds upstream's model or data after unpickling."""
