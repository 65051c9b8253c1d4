"""Demonstrations from the task's scripted policy in an off-policy run's replay buffer.

The hyperparameter ``demonstrations: N`` plays N episodes of the task's scripted policy
(:attr:`~unified_manip.envs.registry.TaskSpec.scripted_policy`, in ``ee_delta``; in another mode
through :mod:`unified_manip.envs.controllers.translate`) before training starts and
stores every transition in the replay buffer, as the HER paper's follow-up did with
expert episodes (Nair et al. 2018, "Overcoming Exploration in Reinforcement Learning with
Demonstrations"), without its behaviour-cloning loss. HER relabels them like any other
episode. They are played in envs of their own, so the run's monitor files, step count and
observation statistics hold the agent's own episodes only; the buffer keeps them for the
whole run (and checkpoints carry them), so a resumed run does not play them again.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

#: Offset of the demonstration envs' seed from the run's (the eval env uses +10,000).
SEED_OFFSET = 20_000


class DemonstrationError(ValueError):
    """Demonstrations were asked of a run that cannot take them."""


def check(task_id: str, action_mode: str, off_policy: bool, episodes: int | str) -> None:
    """Raise :class:`DemonstrationError` unless a run can take ``episodes`` demonstrations
    (0: none): an off-policy algorithm (a replay buffer), a task with a scripted policy,
    and an action mode of the shared controllers (which the policy's ``ee_delta`` actions
    can be translated into). A dataset path needs the off-policy algorithm only here."""
    from unified_manip.envs.registry import get_task
    from unified_manip.training.algorithms import ALGOS

    if isinstance(episodes, str):  # a dataset: :mod:`unified_manip.training.dataset_demonstrations` checks it
        if not off_policy:
            choices = ", ".join(name for name, algo in ALGOS.items() if algo.off_policy)
            raise DemonstrationError(f"demonstrations go into a replay buffer; use an off-policy algorithm ({choices})")
        return
    if episodes < 0:
        raise DemonstrationError(f"demonstrations must be a number of episodes, 0 or more; got {episodes}")
    if episodes == 0:
        return
    if not off_policy:
        choices = ", ".join(name for name, algo in ALGOS.items() if algo.off_policy)
        raise DemonstrationError(f"demonstrations go into a replay buffer; use an off-policy algorithm ({choices})")
    spec = get_task(task_id)
    if spec.scripted_policy is None:
        raise DemonstrationError(f"{task_id} has no scripted policy to demonstrate with")
    modes = demonstrable_modes(task_id)
    if action_mode not in modes:
        raise DemonstrationError(
            f"demonstrations: {task_id}'s action_mode {action_mode!r} is the source's own controller, which the "
            f"scripted {spec.scripted_mode} policy cannot drive; use one of {', '.join(modes)}"
        )


def demonstrable_modes(task_id: str) -> list[str]:
    """The action modes of ``task_id`` that its scripted policy can play: those of the
    shared controllers, and the one it emits (Meta-World's ``native``), not another of a
    source's own."""
    from unified_manip.envs.registry import get_task

    spec = get_task(task_id)
    own = spec.scripted_mode
    return [mode for mode, config in spec.controllers.items() if config.controller is not None or mode == own]


def policy(task_id: str, action_mode: str, env):
    """``obs -> action`` for ``env`` (a gymnasium env of ``task_id`` in ``action_mode``): the
    task's scripted policy as :func:`unified_manip.datasets.policies.scripted` plays it,
    reading the env's state, so demonstrations are the same episodes whatever the agent's
    observation design; the buffer records them as the agent sees them."""
    from unified_manip.datasets.policies import scripted

    return scripted(env)


def policies(task_id: str, action_mode: str, venv) -> list:
    """One :func:`policy` per env of ``venv``: in a ``DummyVecEnv`` each reads its own env's
    state. Another kind of vector env (the native one) has no per-env state to read, so its
    policies read the observations, which only ``ee_delta`` with the default design allows."""
    envs = getattr(venv, "envs", None)
    if envs is not None:
        return [policy(task_id, action_mode, env) for env in envs]
    from unified_manip.envs.design_names import DESIGN_KEYWORDS, design_label
    from unified_manip.envs.registry import get_task

    config = venv.get_attr("config")[0]
    design = design_label({k: getattr(config, k) for k in DESIGN_KEYWORDS})
    if action_mode != "ee_delta" or design != "default":
        raise DemonstrationError(
            f"demonstrations in action_mode {action_mode!r} with observation design {design!r} are played in a "
            "DummyVecEnv (the scripted policy reads each env's state); this vector env can play ee_delta with the "
            "default design only"
        )
    return [get_task(task_id).scripted_policy("ee_delta")] * venv.num_envs


def episodes_per_env(episodes: int, n_envs: int) -> int:
    """Each env plays this many: ``episodes`` rounded up to a multiple of ``n_envs``, so
    that every env ends its last episode on the same step and the buffer holds no
    partial episode (HER samples goals from whole episodes)."""
    return math.ceil(episodes / n_envs)


def prefill(model, venv, task_id: str, action_mode: str, episodes: int) -> dict[str, Any]:
    """Play ``episodes`` (rounded up, see :func:`episodes_per_env`) of the scripted policy
    in ``venv`` (an SB3 ``DummyVecEnv`` with the model's env count, seeded, unnormalised)
    and add every transition to ``model.replay_buffer``.

    Returns ``{"episodes", "transitions", "success"}``: what was stored and the fraction
    of the demonstrated episodes that ended in success.
    """
    acting = policies(task_id, action_mode, venv)
    per_env = episodes_per_env(episodes, venv.num_envs)
    buffer = model.replay_buffer
    if buffer.n_envs != venv.num_envs:
        raise DemonstrationError(f"the replay buffer has {buffer.n_envs} envs, the demonstration env {venv.num_envs}")
    obs = venv.reset()
    finished = np.zeros(venv.num_envs, dtype=int)
    successes = transitions = 0
    while finished.min() < per_env:
        actions = np.stack([act({k: v[i] for k, v in obs.items()}) for i, act in enumerate(acting)])
        actions = np.clip(actions, venv.action_space.low, venv.action_space.high)
        new_obs, rewards, dones, infos = venv.step(actions)
        next_obs = {k: v.copy() for k, v in new_obs.items()}
        for i, done in enumerate(dones):  # the vector env has already reset a finished env
            if done:
                for k in next_obs:
                    next_obs[k][i] = infos[i]["terminal_observation"][k]
        buffer.add(obs, next_obs, model.policy.scale_action(actions), rewards, dones, infos)
        transitions += venv.num_envs
        obs = new_obs
        if dones.any():
            if not dones.all():
                raise DemonstrationError(
                    f"{task_id}: demonstrations need episodes of one fixed length (env episodes ended on different steps)"
                )
            finished += 1
            successes += sum(bool(info.get("is_success", False)) for info in infos)
    played = int(finished.sum())
    return {"episodes": played, "transitions": transitions, "success": successes / played}
