"""``unified-manip convert``: the episodes of a dataset re-executed in another action mode.

Each episode starts from the recorded initial state (the env reset with the episode's
seed, the recorded state restored over it where the two modes share a model) and then
re-executes the recording step by step (:mod:`.steps`), by one of two methods:

* ``search`` (the default): each step's action is searched for in the new mode, so that
  the step lands the grip site where the recording had it after that step, and the
  achieved goal (the object) where the recording's was (:mod:`.search`). Where the
  converted object drifts from the recording, the search trades grip-site error for
  object error, so it steers back toward the recorded object trajectory. Where the new
  mode is slower than the recording's, the search spends up to
  :attr:`~.search.SearchConfig.catch_up` extra steps on a recorded step while the grip
  site lags it: the episode follows the recorded path at the mode's own pace. An episode
  the search loses is tried again by the search in lockstep with the recording; in a mode
  that carries a target, by the search with the target's lead over the arm weighted in
  (:attr:`~.search.SearchConfig.lead_weights`); then by each initial guess open loop. The
  first replay that is kept is kept (:func:`.steps.steppers`).
* ``track``: open loop, the recorded action translated into the mode (as the
  ``demonstrations`` run setting plays a scripted policy), or, for a dataset recorded in
  another mode, the grip site driven toward its next recorded position
  (:class:`~unified_manip.envs.controllers.translate.SiteTracker`).

The recorded gripper command passes through. The recorded grip-site positions are read by
restoring each recorded state in an env that has the task's rig. The new episode is
recorded with its own observations and states. A converted episode is kept when it ends
in success and no step left the grip site further than ``tolerance_cm`` from the
recording; the report names the first step that did.
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from unified_manip.datasets import store
from unified_manip.datasets.episodes import Episode
from unified_manip.datasets.errors import DatasetError
from unified_manip.datasets.policies import shared_modes
from unified_manip.datasets.search import METHODS, TOLERANCE_CM, SearchConfig, Target, sites
from unified_manip.datasets.steps import Way, recorded_targets, steppers


@dataclass(frozen=True)
class EpisodeConversion:
    """One converted episode: success as recorded and as converted; after each step, the
    grip site's distance from the recorded trajectory (mean and max, cm) and the achieved
    goal's (mean and max, in the goal's units: m for a position); the first step whose
    grip site landed beyond the tolerance (``None``: none); the wall time, s, of every try;
    and what replayed it: ``search``, or, where the search lost it, the search in lockstep
    (``search, lockstep``), the search with the target's lead weighted in (``search, lead
    W``) or an initial guess played open loop (``recorded``, ``translated``, ``tracker``:
    :func:`.steps.guessers`)."""

    episode: int
    steps: int
    success_recorded: bool
    success_converted: bool
    tracking_error_mean_cm: float
    tracking_error_max_cm: float
    goal_error_mean: float
    goal_error_max: float
    first_step_off: int | None
    seconds: float
    replayed_by: str

    @property
    def kept(self) -> bool:
        """Whether the converted episode is a demonstration: a success that stayed on the
        recorded trajectory."""
        return self.success_converted and self.first_step_off is None


@dataclass(frozen=True)
class ConvertReport:
    """Every episode's conversion, and what was written."""

    dataset: str
    action_mode: str
    method: str
    tolerance_cm: float
    episodes: list[EpisodeConversion]
    out: str | None
    kept: int

    @property
    def success_rate(self) -> float:
        """The share of episodes converted into demonstrations (:attr:`EpisodeConversion.kept`)."""
        return sum(e.kept for e in self.episodes) / len(self.episodes)

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
    method: str = METHODS[0],
    tolerance_cm: float = TOLERANCE_CM,
    search: SearchConfig = SearchConfig(),
    env_id: str | None = None,
) -> ConvertReport:
    """Convert the dataset at ``path`` (its ``first`` episodes; ``None``: all) to
    ``action_mode`` by ``method`` (:data:`METHODS`), and to the observation design
    ``observation`` (``None``: the recorded one), on the task ``env_id`` (``None``: the
    recorded one; another version of it, whose model the recorded states fit), and publish
    it as ``out`` (``None``: measure only), with its first ``keep`` kept episodes
    (``None``: all). No dataset is written when no episode is kept, nor when more than
    ``max_failed`` episodes fail to convert (the conversion stops there).

    Into the recorded mode, ``track`` plays the recorded actions themselves: the same
    episodes, seen through another observation design or played on another version."""
    import gymnasium as gym
    from tqdm import tqdm

    if method not in METHODS:
        raise DatasetError(f"convert's method must be one of {', '.join(METHODS)}; got {method!r}")
    if not tolerance_cm > 0:
        raise DatasetError(f"convert's tolerance must be a positive number of cm; got {tolerance_cm}")
    dataset = store.open_dataset(path)
    meta = store.metadata(dataset)
    if out is not None:
        out = store.check_out(Path(out), overwrite)
    try:
        task = _task(env_id or meta["env_id"])
    except ValueError as err:
        if env_id is None:
            raise
        raise DatasetError(f"convert --env: {err}") from None
    source_mode = meta["env_kwargs"].get("action_mode")
    try:
        task.check_choices(action_mode, meta["env_kwargs"].get("reward_type", "sparse"))
    except ValueError as err:
        raise DatasetError(str(err)) from None
    if action_mode not in shared_modes(task):
        raise DatasetError(
            f"{task.id}'s action_mode {action_mode!r} is the source's own controller, which cannot track a "
            f"grip-site trajectory; expected one of {', '.join(shared_modes(task))}"
        )
    source = dataset.recover_environment()
    kwargs = {**meta["env_kwargs"], "action_mode": action_mode}
    if observation is not None:
        kwargs.pop("observation", None)
        if observation != "default":
            kwargs["observation"] = observation
    target = gym.make(task.id, **kwargs)
    probe = gym.make(task.id, **kwargs) if method == "search" else None
    try:
        ways = steppers(task, target, probe, source_mode, method, search)
        indices = dataset.episode_indices[:first]
        seeds = [int(m["seed"]) for m in dataset.storage.get_episode_metadata(indices)]
        rows, kept = [], []
        bar = tqdm(
            dataset.iterate_episodes(indices),
            total=len(seeds),
            desc=f"convert to {action_mode} ({method})",
            disable=not progress,
        )
        reader = source if getattr(source.unwrapped.backend, "rig", None) is not None else target
        for seed, ep in zip(seeds, bar):
            targets = recorded_targets(reader, ep, task.id)
            try:
                episode, row = _convert_tries(target, ways, ep, seed, targets, tolerance_cm, search)
            except ValueError as err:  # a controller that cannot follow a target on this robot
                raise DatasetError(
                    f"{task.id}'s action_mode {action_mode!r} cannot track a trajectory: {err}"
                ) from None
            rows.append(row)
            if row.kept or keep_failed:
                kept.append(episode)
            if max_failed is not None and sum(not r.kept for r in rows) > max_failed:
                kept = []  # out of reach: nothing is written
                break
        kept = kept[:keep]
        if out is not None and kept:
            published = {
                "env_id": task.id,
                "env_kwargs": kwargs,
                "policy": "convert",
                "source": f"{path} ({source_mode}, policy {meta['policy']})",
                "converted_from": meta,
                "conversion": {"method": method, "tolerance_cm": tolerance_cm, "search": asdict(search)},
                "conversion_episodes": [asdict(r) for r in rows],
                "seed": meta.get("seed"),
                "episodes_played": len(rows),
                "success_rate": sum(r.kept for r in rows) / len(rows),
                "dropped_episodes": len(rows) - len(kept),
                "only_successful": not keep_failed,
            }
            how = "searching each step's action" if method == "search" else "playing its actions translated, open loop"
            description = f"{path} converted to action_mode {action_mode!r} by {how}"
            store.publish(out, kept, target, published, description)
    finally:
        for env in (source, target, probe):
            if env is not None:
                env.close()
    out_name = str(out) if out is not None and kept else None
    return ConvertReport(str(path), action_mode, method, tolerance_cm, rows, out_name, len(kept))


def _task(env_id: str):
    from unified_manip.envs.registry import get_task

    return get_task(env_id)


def _convert_tries(env, ways, ep, seed: int, targets: list[Target], tolerance_cm: float, config: SearchConfig):
    """The episode converted by the first of ``ways`` that keeps it (else by the first),
    its row naming that way and the seconds all the tries took."""
    started = time.perf_counter()
    first = None
    for way in ways:
        episode, row = _convert_episode(env, way, ep, seed, targets, tolerance_cm, config.catch_up_cm)
        first = first or (episode, row)
        if row.kept:
            break
    episode, row = (episode, row) if row.kept else first
    return episode, replace(row, seconds=time.perf_counter() - started)


def _convert_episode(env, way: Way, ep, seed: int, targets: list[Target], tolerance_cm: float, catch_up_cm: float):
    from unified_manip.envs.controllers.translate import arms

    started = time.perf_counter()
    backend = env.unwrapped.backend
    rigs = [arm.rig for arm in arms(backend)]
    obs, info = env.reset(seed=seed)
    initial = ep.infos["state"][0]
    if backend.get_state().shape == initial.shape:
        backend.set_state(initial)
    if not np.array_equal(obs["desired_goal"], ep.observations["desired_goal"][0]):
        raise DatasetError(f"episode {ep.id}: reset with seed {seed} gives another goal than the recording's")
    step = way.step
    step.start(seed)
    episode = Episode(seed)
    episode.start(env, obs, info)
    errors, goal_errors = [], []
    first_off = None
    for t, recorded in enumerate(ep.actions):
        if episode.done:
            break
        target = targets[t + 1]
        for _ in range(way.catch_up + 1):  # more steps toward the same target while it lags
            action = step(recorded, target)
            obs, reward, terminated, truncated, info = env.step(action)
            episode.add(env, action, obs, reward, terminated, truncated, info)
            lag = float(np.max(np.linalg.norm((sites(rigs) - target.site).reshape(-1, 3), axis=1)))
            if episode.done or lag <= catch_up_cm / 100:
                break
        errors.append(lag)
        goal_errors.append(float(np.linalg.norm(obs["achieved_goal"].astype(np.float64) - target.goal)))
        if first_off is None and errors[-1] > tolerance_cm / 100:
            first_off = t
    row = EpisodeConversion(
        episode=int(ep.id),
        steps=episode.steps,
        success_recorded=bool(ep.infos["is_success"][-1] > 0.5),
        success_converted=episode.success,
        tracking_error_mean_cm=100 * float(np.mean(errors)),
        tracking_error_max_cm=100 * float(np.max(errors)),
        goal_error_mean=float(np.mean(goal_errors)),
        goal_error_max=float(np.max(goal_errors)),
        first_step_off=first_off,
        seconds=time.perf_counter() - started,
        replayed_by=way.name,
    )
    return episode, row
