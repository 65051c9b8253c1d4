"""Demonstrations from a dataset in an off-policy run's replay buffer (``demonstrations: PATH``).

The run setting ``demonstrations`` takes, in place of a number of scripted episodes
(:mod:`unified_manip.training.demonstrations`), the path of a dataset written by
``unified-manip collect`` or ``convert`` (:mod:`unified_manip.datasets`). Its episodes go
into the replay buffer before training, transition by transition as the live prefill
stores them, so a HER buffer relabels their goals like any other episode's. Episode ``k``
goes to env ``k mod n_envs`` of the buffer: a dataset collected with ``--seed S`` holds,
in its first ``n_envs`` episodes, the episodes the live prefill of a run of seed
``S - SEED_OFFSET`` plays first, and fills the buffer with the same arrays.

The dataset must have been recorded on the run's task, in its action mode, observation
design, reward type and other env keyword arguments; a difference is a one-line
:class:`DemonstrationError` naming it and the command that fixes it (``convert`` for the
action mode and the observation design).
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np

from unified_manip.training.demonstrations import DemonstrationError


def dataset_path(path: str, task_id: str, env_config: dict[str, Any]) -> str:
    """``path`` with ``{task}`` replaced by the run's task (its ID without the namespace,
    e.g. ``Lift-v0``) and ``{action_mode}`` by its action mode: one grid entry
    (``overrides: {bc: [demonstrations=data/{task}/{action_mode}-v0]}``) then names each
    task's and mode's own dataset."""
    return path.replace("{task}", task_id.split("/")[-1]).replace("{action_mode}", str(env_config.get("action_mode")))


def _dataset(path: str):
    from unified_manip.datasets import DatasetError
    from unified_manip.datasets.store import metadata, open_dataset

    try:
        dataset = open_dataset(Path(path))
    except DatasetError as err:
        raise DemonstrationError(f"demonstrations: {err}") from None
    return dataset, metadata(dataset)


def _converted_name(path: str, mode: str) -> str:
    """Where ``convert`` could write ``path`` in ``mode``: a sibling named after both."""
    p = Path(path)
    stem = re.sub(r"-v\d+$", "", p.name)
    return str(p.with_name(f"{stem}-{mode}-v0"))


def _whole_rounds(total: int, n_envs: int, path: str) -> int:
    """The episodes a prefill with ``n_envs`` envs takes from ``total``: whole rounds, one
    episode per env; none is an error."""
    used = total - total % n_envs
    if used == 0:
        raise DemonstrationError(
            f"demonstrations: {path} holds {total} episodes, fewer than the run's {n_envs} envs (a prefill gives "
            f"each env one at least); train with n_envs of at most {total}, or without them (demonstrations=0)"
        )
    return used


def check(path: str, task_id: str, env_config: dict[str, Any], n_envs: int = 1) -> dict[str, Any]:
    """Raise :class:`DemonstrationError` unless the dataset at ``path`` was recorded on
    ``task_id`` with the env keyword arguments ``env_config`` (the run's ``action_mode``,
    ``reward_type`` and extras) and holds an episode for each of the run's ``n_envs``
    envs; return its metadata (``unified_manip``'s). ``path`` may hold ``{task}`` and
    ``{action_mode}`` (:func:`dataset_path`)."""
    from unified_manip.envs.design_names import observation_label
    from unified_manip.envs.randomization import randomization_label

    path = dataset_path(path, task_id, env_config)
    dataset, meta = _dataset(path)
    if meta["env_id"] != task_id:
        raise DemonstrationError(
            f"demonstrations: {path} holds episodes of {meta['env_id']}, not of {task_id}; record them with "
            f"unified-manip collect --env {task_id} --out DIR/NAME-v0"
        )
    recorded = dict(meta["env_kwargs"])
    wanted = dict(env_config)
    mode, recorded_mode = wanted.get("action_mode"), recorded.get("action_mode")
    design = observation_label(wanted.get("observation", "default"))
    recorded_design = observation_label(recorded.get("observation", "default"))
    if mode != recorded_mode or design != recorded_design:
        what = []
        if mode != recorded_mode:
            what.append(f"action_mode {recorded_mode!r}, the run's is {mode!r}")
        if design != recorded_design:
            what.append(f"observation design {recorded_design!r}, the run's is {design!r}")
        observation = f" --observation {design.replace('+', ',')}" if design != recorded_design else ""
        raise DemonstrationError(
            f"demonstrations: {path} was recorded with {' and '.join(what)}; convert it: unified-manip convert "
            f"{path} --action-mode {mode}{observation} --out {_converted_name(path, mode)}"
        )
    if wanted.get("reward_type") != recorded.get("reward_type"):
        raise DemonstrationError(
            f"demonstrations: {path} was recorded with reward_type {recorded.get('reward_type')!r}, the run's is "
            f"{wanted.get('reward_type')!r} (its stored rewards are that design's); record it with unified-manip "
            f"collect --env {task_id} --action-mode {mode} --reward-type {wanted.get('reward_type')} --out DIR/NAME-v0"
        )
    ignored = ("action_mode", "reward_type", "observation", "render_mode")
    if randomization_label(recorded.get("randomization")) == "none" and isinstance(wanted.get("randomization"), str):
        # Nominal episodes suit a run under a preset: every preset's ranges hold the nominal
        # values, so the nominal world is one the run trains in.
        ignored += ("randomization",)
    differ = sorted(k for k in set(recorded) | set(wanted) if k not in ignored and recorded.get(k) != wanted.get(k))
    if differ:
        shown = ", ".join(f"{k} {recorded.get(k)!r} (recorded) vs {wanted.get(k)!r} (run)" for k in differ)
        raise DemonstrationError(f"demonstrations: {path} was recorded with other env keyword arguments: {shown}")
    _whole_rounds(dataset.total_episodes, n_envs, path)
    return meta


def prefill(model, path: str, task_id: str, env_config: dict[str, Any]) -> dict[str, Any]:
    """Add the episodes of the dataset at ``path`` to ``model.replay_buffer``, episode ``k``
    in env ``k mod n_envs``; a last round of fewer than ``n_envs`` episodes is left out
    (every env of a round must end its episode on the same step, as in the live prefill).

    Returns ``{"episodes", "transitions", "success", "dataset", "dataset_episodes"}``.
    """
    meta = check(path, task_id, env_config)
    path = dataset_path(path, task_id, env_config)
    dataset, _ = _dataset(path)
    buffer = model.replay_buffer
    n_envs = buffer.n_envs
    total = dataset.total_episodes
    used = _whole_rounds(total, n_envs, path)
    episodes = list(dataset.iterate_episodes(dataset.episode_indices[:used]))
    rows = sum(len(ep.actions) for ep in episodes[::n_envs])
    if rows > buffer.buffer_size:
        raise DemonstrationError(
            f"demonstrations: {path} needs {rows} rows of the replay buffer ({rows * n_envs} transitions); "
            f"buffer_size is {buffer.buffer_size}"
        )
    successes = transitions = 0
    for start in range(0, used, n_envs):
        group = episodes[start : start + n_envs]
        lengths = {len(ep.actions) for ep in group}
        if len(lengths) != 1:
            raise DemonstrationError(
                f"demonstrations: episodes {start}-{start + n_envs - 1} of {path} have lengths {sorted(lengths)}; "
                f"with {n_envs} envs each round of episodes must have one length"
            )
        transitions += _add_round(model, buffer, group)
        successes += sum(bool(ep.infos["is_success"][-1] > 0.5) for ep in group)
    return {
        "episodes": used,
        "transitions": transitions,
        "success": successes / used,
        "dataset": str(path),
        "dataset_episodes": total,
        "dataset_policy": meta.get("policy"),
    }


def _add_round(model, buffer, group: list) -> int:
    """Add one episode per env (``group``, one length) to ``buffer``, step by step."""
    keys = list(group[0].observations)
    space = model.action_space
    for t in range(len(group[0].actions)):
        obs = {k: np.stack([ep.observations[k][t] for ep in group]) for k in keys}
        next_obs = {k: np.stack([ep.observations[k][t + 1] for ep in group]) for k in keys}
        actions = np.clip(np.stack([ep.actions[t] for ep in group]), space.low, space.high)
        rewards = np.array([ep.rewards[t] for ep in group])
        terminated = np.array([bool(ep.terminations[t]) for ep in group])
        truncated = np.array([bool(ep.truncations[t]) for ep in group])
        dones = terminated | truncated
        infos = [
            {"is_success": float(ep.infos["is_success"][t + 1]), "TimeLimit.truncated": bool(tr and not te)}
            for ep, te, tr in zip(group, terminated, truncated)
        ]
        buffer.add(obs, next_obs, model.policy.scale_action(actions), rewards, dones, infos)
    return len(group[0].actions) * len(group)
