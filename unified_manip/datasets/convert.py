"""``unified-manip convert``: the episodes of a dataset re-executed in another action mode.

Each episode starts from the recorded initial state (the env reset with the episode's
seed, the recorded state restored over it where the two modes share a model) and then
tracks the recorded trajectory: at step ``t`` the grip site is driven toward where the
recording had it after step ``t``, through the task's ``ee_delta`` IK and the mode's own
controller (:class:`~unified_manip.envs.controllers.translate.SiteTracker`), with the
recorded gripper command passed through. The recorded grip-site positions are read by
restoring each recorded state in the recording's own env. The new episode is recorded
with its own observations and states; a converted episode that does not end in success
is left out unless ``keep_failed``.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from unified_manip.datasets import store
from unified_manip.datasets.episodes import Episode
from unified_manip.datasets.errors import DatasetError
from unified_manip.datasets.policies import shared_modes


@dataclass(frozen=True)
class EpisodeConversion:
    """One converted episode: success as recorded and as converted, and the grip site's
    distance from the recorded trajectory after each step (mean and max, cm)."""

    episode: int
    steps: int
    success_recorded: bool
    success_converted: bool
    tracking_error_mean_cm: float
    tracking_error_max_cm: float


@dataclass(frozen=True)
class ConvertReport:
    """Every episode's conversion, and what was written."""

    dataset: str
    action_mode: str
    episodes: list[EpisodeConversion]
    out: str | None
    kept: int

    @property
    def success_rate(self) -> float:
        return sum(e.success_converted for e in self.episodes) / len(self.episodes)

    def as_dict(self) -> dict[str, Any]:
        return {**asdict(self), "success_rate": self.success_rate}


def convert(
    path: Path,
    action_mode: str,
    out: Path | None,
    keep_failed: bool = False,
    overwrite: bool = False,
    progress: bool = True,
    first: int | None = None,
    observation: Any = None,
    keep: int | None = None,
    max_failed: int | None = None,
) -> ConvertReport:
    """Convert the dataset at ``path`` (its ``first`` episodes; ``None``: all) to
    ``action_mode`` (and to the observation design ``observation``; ``None``: the
    recorded one) and publish it as ``out`` (``None``: measure only), with its first
    ``keep`` kept episodes (``None``: all). No dataset is written when no episode is kept,
    nor when more than ``max_failed`` episodes fail to convert (the conversion stops there)."""
    import gymnasium as gym
    from tqdm import tqdm

    from unified_manip.envs.controllers.translate import SiteTracker

    dataset = store.open_dataset(path)
    meta = store.metadata(dataset)
    if out is not None:
        out = store.check_out(Path(out), overwrite)
    spec = gym.spec(meta["env_id"])
    task = _task(meta["env_id"])
    try:
        task.check_choices(action_mode, meta["env_kwargs"].get("reward_type", "sparse"))
    except ValueError as err:
        raise DatasetError(str(err)) from None
    source = dataset.recover_environment()
    kwargs = {**meta["env_kwargs"], "action_mode": action_mode}
    if observation is not None:
        kwargs.pop("observation", None)
        if observation != "default":
            kwargs["observation"] = observation
    target = gym.make(spec.id, **kwargs)
    try:
        rig = getattr(source.unwrapped.backend, "rig", None)
        if rig is None:
            raise DatasetError(
                f"{path} was recorded in {meta['env_kwargs'].get('action_mode')!r}, the source's own controller, "
                "which has no grip-site rig to read its trajectory from; convert a dataset of a shared-controller mode"
            )
        if action_mode not in shared_modes(task):
            raise DatasetError(
                f"{task.id}'s action_mode {action_mode!r} is the source's own controller, which cannot track a "
                f"grip-site trajectory; expected one of {', '.join(shared_modes(task))}"
            )
        try:
            tracker = SiteTracker(target.unwrapped.backend, task.controllers["ee_delta"])
        except ValueError as err:
            raise DatasetError(f"{task.id}'s action_mode {action_mode!r} cannot track a trajectory: {err}") from None
        indices = dataset.episode_indices[:first]
        seeds = [int(m["seed"]) for m in dataset.storage.get_episode_metadata(indices)]
        rows, kept = [], []
        bar = tqdm(
            dataset.iterate_episodes(indices), total=len(seeds), desc=f"convert to {action_mode}", disable=not progress
        )
        for seed, ep in zip(seeds, bar):
            sites = _recorded_sites(source, ep.infos["state"])
            try:
                episode, row = _convert_episode(target, tracker, ep, seed, sites)
            except ValueError as err:  # a controller that cannot follow a target on this robot
                raise DatasetError(
                    f"{task.id}'s action_mode {action_mode!r} cannot track a trajectory: {err}"
                ) from None
            rows.append(row)
            if row.success_converted or keep_failed:
                kept.append(episode)
            if max_failed is not None and sum(not r.success_converted for r in rows) > max_failed:
                kept = []  # out of reach: nothing is written
                break
        kept = kept[:keep]
        if out is not None and kept:
            published = {
                "env_id": spec.id,
                "env_kwargs": kwargs,
                "policy": "convert",
                "source": f"{path} ({meta['env_kwargs'].get('action_mode')}, policy {meta['policy']})",
                "converted_from": meta,
                "conversion": [asdict(r) for r in rows],
                "seed": meta.get("seed"),
                "episodes_played": len(rows),
                "success_rate": sum(r.success_converted for r in rows) / len(rows),
                "dropped_episodes": len(rows) - len(kept),
                "only_successful": not keep_failed,
            }
            description = f"{path} converted to action_mode {action_mode!r} by tracking its grip-site trajectory"
            store.publish(out, kept, target, published, description)
    finally:
        source.close()
        target.close()
    return ConvertReport(str(path), action_mode, rows, str(out) if out is not None and kept else None, len(kept))


def _task(env_id: str):
    from unified_manip.envs.registry import get_task

    return get_task(env_id)


def _recorded_sites(env, states: np.ndarray) -> np.ndarray:
    """The grip site's position in each recorded state, read in the recording's env."""
    backend = env.unwrapped.backend
    env.reset(seed=0)
    sites = []
    for state in states:
        backend.set_state(state)
        sites.append(np.array(backend.rig.site_position()))
    return np.stack(sites)


def _convert_episode(env, tracker, ep, seed: int, sites: np.ndarray) -> tuple[Episode, EpisodeConversion]:
    backend = env.unwrapped.backend
    rig = tracker.rig
    obs, info = env.reset(seed=seed)
    initial = ep.infos["state"][0]
    if backend.get_state().shape == initial.shape:
        backend.set_state(initial)
    if not np.array_equal(obs["desired_goal"], ep.observations["desired_goal"][0]):
        raise DatasetError(f"episode {ep.id}: reset with seed {seed} gives another goal than the recording's")
    episode = Episode(seed)
    episode.start(env, obs, info)
    errors = []
    for t, recorded in enumerate(ep.actions):
        if episode.done:
            break
        action = tracker(sites[t + 1], float(recorded[-1]) if rig.has_gripper else None)
        obs, reward, terminated, truncated, info = env.step(action)
        episode.add(env, action, obs, reward, terminated, truncated, info)
        errors.append(float(np.linalg.norm(rig.site_position() - sites[t + 1])))
    row = EpisodeConversion(
        episode=int(ep.id),
        steps=episode.steps,
        success_recorded=bool(ep.infos["is_success"][-1] > 0.5),
        success_converted=episode.success,
        tracking_error_mean_cm=100 * float(np.mean(errors)),
        tracking_error_max_cm=100 * float(np.max(errors)),
    )
    return episode, row
