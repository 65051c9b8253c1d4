"""The private members of a gymnasium-robotics env object that this package uses, each
named once, here.

gymnasium-robotics (1.4.2) offers ``reset(seed=...)`` and ``step(action)`` only. Those re-seed
the env's generator, apply upstream's own controller and compute upstream's reward; the
Fetch and Shadow Hand backends need the steps in between, so they call upstream's private
members through these functions and nowhere else. A gymnasium-robotics release that renames
one breaks here alone. Each function is the part of ``BaseRobotEnv.reset`` or ``step`` it
replays, in upstream's order:

========================  ==================================================================
``_np_random`` (set)      the env's generator: set to ours, so that ``reset(seed=s)`` here
                          draws what upstream's ``reset(seed=s)`` draws (:func:`reset`)
``_reset_sim()``          restore the initial state and sample the object's pose; False
                          means an invalid start, retried as upstream does (:func:`reset`)
``_sample_goal()``        the episode's goal, drawn after the state (:func:`reset`)
``_get_obs()``            upstream's observation dict (:func:`observation`)
``_set_action(a)``        upstream's own controller: clip, scale, write the controls or the
                          mocap target (:func:`set_action`; the ``native`` mode)
``_mujoco_step(a)``       ``n_substeps`` MuJoCo steps, one env step (:func:`mujoco_step`)
``_step_callback()``      after the physics step: Fetch holds a blocked gripper shut
                          (:func:`step_callback`)
``_render_callback()``    before drawing: move the goal's marker sites (:func:`render_callback`)
``_model_names`` (set)    upstream's name-to-id tables, rebuilt when Fetch's joint modes swap
                          in a model with joint actuators (:func:`replace_model`)
========================  ==================================================================
"""

from __future__ import annotations

from typing import Any

import numpy as np


def reset(env: Any, np_random: np.random.Generator) -> None:
    """Upstream's reset, drawing from ``np_random`` instead of re-seeding: ``_reset_sim()``
    until it succeeds, then ``goal = _sample_goal()``."""
    env._np_random = np_random
    while not env._reset_sim():  # upstream retries failed resets the same way
        pass
    env.goal = env._sample_goal().copy()


def observation(env: Any) -> dict[str, np.ndarray]:
    """Upstream's observation dict now (``_get_obs()``)."""
    return env._get_obs()


def set_action(env: Any, action: np.ndarray) -> None:
    """Upstream's own controller applies ``action`` (``_set_action``), without stepping."""
    env._set_action(action)


def mujoco_step(env: Any, action: np.ndarray | None) -> None:
    """One env step of physics (``_mujoco_step``: ``n_substeps`` of ``mj_step``)."""
    env._mujoco_step(action)


def step_callback(env: Any) -> None:
    """What upstream does after the physics step (``_step_callback``)."""
    env._step_callback()


def render_callback(env: Any) -> None:
    """What upstream does before drawing (``_render_callback``: the goal's markers)."""
    env._render_callback()


def replace_model(env: Any, model: Any, data: Any) -> None:
    """Give ``env`` another model and data, and upstream's name tables of it
    (``_model_names``, which upstream's utilities look joints and sites up in)."""
    from gymnasium_robotics.utils.mujoco_utils import MujocoModelNames

    env.model, env.data = model, data
    env._model_names = MujocoModelNames(model)
