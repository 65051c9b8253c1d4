"""Helpers for families that wrap a gymnasium-robotics env object (Fetch, Shadow Hand).

These backends keep the upstream env (its model, reset, goal sampling, observation
and ``native`` control code) and drive its methods directly, so the task is exactly
upstream's. Two things need care:

* **Seeding.** ``UnifiedManipEnv.reset(seed=s)`` seeds its own ``np_random`` exactly
  as ``gymnasium.Env.reset(seed=s)`` does; :func:`upstream_reset` hands that generator
  to the upstream env before running upstream's ``_reset_sim``/``_sample_goal``, so a
  seed gives the same episode as ``gym.make(<upstream id>).reset(seed=s)``.
* **Pickling.** Upstream envs are ``EzPickle``: unpickling rebuilds them from their
  constructor arguments and loses the simulator state. :func:`pickle_upstream` stores
  the object's ``__dict__`` instead (model and data pickle with their full state),
  minus module references and the renderer, which :func:`unpickle_upstream` restores.
"""

from __future__ import annotations

import importlib
import types
from typing import Any

import numpy as np


def upstream_reset(env: Any, np_random: np.random.Generator) -> None:
    """Run the upstream env's reset (without its re-seeding) from ``np_random``."""
    env._np_random = np_random
    while not env._reset_sim():  # upstream retries failed resets the same way
        pass
    env.goal = env._sample_goal().copy()


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
