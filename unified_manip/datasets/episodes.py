"""One episode as it is played and stored: observations, actions, rewards, flags, infos
and the simulator state of every step, turned into a Minari ``EpisodeBuffer``.

The infos hold every numeric entry the env returns (``is_success``, the task's reward inputs,
the action mode's diagnostics, ``reward_terms`` as a nested group) plus ``state``, the
simulator's full physics state (:meth:`~unified_manip.envs.backend.Backend.get_state`).
Like the observations they have one row per step plus one for the reset; an entry that
only steps return (``reward_terms``, ``ik_residual``) is NaN in the reset's row.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

#: A policy as the dataset tools play it: ``obs dict -> action``.
Policy = Callable[[dict[str, np.ndarray]], np.ndarray]


@dataclass
class Episode:
    """The steps of one episode, appended as it is played.

    Attributes:
        seed: The reset seed.
        observations: One dict per step, the reset's first.
        actions: One per step.
        rewards, terminations, truncations: One per step.
        infos: One dict per step, the reset's first, each with ``state`` added.
    """

    seed: int
    observations: list[dict[str, np.ndarray]] = field(default_factory=list)
    actions: list[np.ndarray] = field(default_factory=list)
    rewards: list[float] = field(default_factory=list)
    terminations: list[bool] = field(default_factory=list)
    truncations: list[bool] = field(default_factory=list)
    infos: list[dict[str, Any]] = field(default_factory=list)

    def start(self, env, obs: dict[str, np.ndarray], info: dict[str, Any]) -> None:
        """Record the reset of ``env`` (a gymnasium env of this project)."""
        self.observations.append({k: np.array(v) for k, v in obs.items()})
        self.infos.append({**info, "state": env.unwrapped.backend.get_state()})

    def add(self, env, action, obs, reward, terminated, truncated, info) -> None:
        """Record one ``env.step(action)`` and the state it left."""
        self.actions.append(np.asarray(action, dtype=np.float32))
        self.observations.append({k: np.array(v) for k, v in obs.items()})
        self.rewards.append(float(reward))
        self.terminations.append(bool(terminated))
        self.truncations.append(bool(truncated))
        self.infos.append({**info, "state": env.unwrapped.backend.get_state()})

    @property
    def steps(self) -> int:
        return len(self.actions)

    @property
    def done(self) -> bool:
        return bool(self.actions) and (self.terminations[-1] or self.truncations[-1])

    @property
    def success(self) -> bool:
        """Whether the last step was a success (the project's episode success)."""
        return bool(self.infos[-1].get("is_success", 0.0) > 0.5)

    def buffer(self, episode_id: int):
        """This episode as a Minari ``EpisodeBuffer`` with id ``episode_id``."""
        from minari.data_collector.episode_buffer import EpisodeBuffer

        return EpisodeBuffer(
            id=episode_id,
            seed=self.seed,
            observations={k: np.stack([o[k] for o in self.observations]) for k in self.observations[0]},
            actions=np.stack(self.actions),
            rewards=list(self.rewards),
            terminations=list(self.terminations),
            truncations=list(self.truncations),
            infos=info_columns(self.infos),
        )


def play(env, policy: Policy, seed: int) -> Episode:
    """One episode of ``policy`` in ``env`` from ``env.reset(seed=seed)``, recorded."""
    episode = Episode(seed)
    obs, info = env.reset(seed=seed)
    episode.start(env, obs, info)
    while not episode.done:
        action = policy(obs)
        obs, reward, terminated, truncated, info = env.step(action)
        episode.add(env, action, obs, reward, terminated, truncated, info)
    return episode


def info_columns(infos: list[dict[str, Any]]) -> dict[str, Any]:
    """Per-step info dicts as columns: a key's values stacked (nested dicts recursively),
    NaN where a step lacks it; strings and other non-numeric entries are left out."""
    keys: dict[str, None] = {}
    for info in infos:
        keys.update(dict.fromkeys(info))
    columns: dict[str, Any] = {}
    for key in keys:
        values = [info.get(key) for info in infos]
        sample = next(v for v in values if v is not None)
        if isinstance(sample, dict):
            columns[key] = info_columns([v if isinstance(v, dict) else {} for v in values])
            continue
        sample = np.asarray(sample)
        if sample.dtype.kind not in "biuf":
            continue
        blank = np.full(sample.shape, np.nan)
        columns[key] = np.stack([blank if v is None else np.asarray(v, dtype=np.float64) for v in values])
    return columns
