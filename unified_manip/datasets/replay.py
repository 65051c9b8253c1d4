"""``unified-manip replay``: replay a dataset in the env that recorded it and report where
it departs.

From states (the default), every step starts from the recorded simulator state: the env
is reset with the episode's seed (which restores the goal and the controller's memory),
then before each step the recorded state is restored
(:meth:`~unified_manip.envs.backend.Backend.set_state`) and the recorded action applied;
the observation it returns is compared with the recorded one, so an error never carries
over to the next step. From actions, the recorded actions are played from the reset
alone, as a user's copy of the env would. Either way a step *departs* when any float
observation entry differs from the recording at all; images (stored as JPEG) are not
compared.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from unified_manip.datasets import store, versions
from unified_manip.envs.video import write_video


@dataclass(frozen=True)
class EpisodeReplay:
    """One episode's replay: its steps, the largest absolute observation difference, the
    first step that departed (``None``: exact), and success as recorded and replayed."""

    episode: int
    steps: int
    max_deviation: float
    first_departure: int | None
    success_recorded: bool
    success_replayed: bool


@dataclass(frozen=True)
class ReplayReport:
    """Every episode's replay, and the version differences from the recording."""

    dataset: str
    from_actions: bool
    episodes: list[EpisodeReplay]
    version_mismatches: list[str] = field(default_factory=list)

    @property
    def exact(self) -> bool:
        return all(e.first_departure is None for e in self.episodes)

    def departure(self) -> str | None:
        """``"episode 3 departed at step 17 (max deviation 2.1e-05)"`` for the first
        episode that did not replay exactly, else ``None``."""
        for e in self.episodes:
            if e.first_departure is not None:
                return f"episode {e.episode} departed at step {e.first_departure} (max deviation {e.max_deviation:.3g})"
        return None

    def as_dict(self) -> dict[str, Any]:
        return {**asdict(self), "exact": self.exact}


def deviation(a: dict[str, np.ndarray], b: dict[str, np.ndarray]) -> float:
    """The largest absolute difference between the float entries of two observations."""
    return max(
        float(np.max(np.abs(np.asarray(a[k], dtype=np.float64) - np.asarray(b[k], dtype=np.float64)), initial=0.0))
        for k in a
        if np.asarray(a[k]).dtype.kind == "f"
    )


def replay(path: Path, from_actions: bool = False, video: Path | None = None, progress: bool = True) -> ReplayReport:
    """Replay every episode of the dataset at ``path``; ``video`` (``.mp4`` or ``.gif``)
    gets every replayed frame."""
    from tqdm import tqdm

    dataset = store.open_dataset(path)
    meta = store.metadata(dataset)
    render = {"render_mode": "rgb_array", "render_width": 320, "render_height": 320} if video else {}
    env = dataset.recover_environment(**render)
    frames: list[np.ndarray] = []
    rows = []
    try:
        seeds = [m["seed"] for m in dataset.storage.get_episode_metadata(dataset.episode_indices)]
        episodes = tqdm(dataset.iterate_episodes(), total=len(seeds), desc="replay", disable=not progress)
        for seed, ep in zip(seeds, episodes):
            rows.append(_replay_episode(env, ep, int(seed), from_actions, frames if video else None))
    finally:
        env.close()
    if video:
        write_video(Path(video), frames, fps=env.metadata.get("render_fps", 25))
    return ReplayReport(str(path), from_actions, rows, versions.mismatches(meta.get("versions", {})))


def _replay_episode(env, ep, seed: int, from_actions: bool, frames: list | None) -> EpisodeReplay:
    backend = env.unwrapped.backend
    recorded = ep.observations
    obs, info = env.reset(seed=seed)
    worst = deviation(obs, {k: v[0] for k, v in recorded.items()})
    first = 0 if worst > 0 else None
    if frames is not None:
        frames.append(env.render())
    for t, action in enumerate(ep.actions):
        if not from_actions:
            backend.set_state(ep.infos["state"][t])
        obs, _, _, _, info = env.step(action)
        d = deviation(obs, {k: v[t + 1] for k, v in recorded.items()})
        if d > 0 and first is None:
            first = t + 1
        worst = max(worst, d)
        if frames is not None:
            frames.append(env.render())
    return EpisodeReplay(
        episode=int(ep.id),
        steps=len(ep.actions),
        max_deviation=worst,
        first_departure=first,
        success_recorded=bool(ep.infos["is_success"][-1] > 0.5),
        success_replayed=bool(info.get("is_success", 0.0) > 0.5),
    )
