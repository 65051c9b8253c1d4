"""``unified-manip collect``: play a policy and publish the episodes as a Minari dataset.

Episode ``k`` is reset with seed ``seed + k``. Each step holds the Dict observation the
env returns (whatever observation design it was made with), the action, the reward,
``terminated``, ``truncated`` and the infos of :mod:`.episodes`, with the simulator's full
state. The dataset's env spec holds the ID and every ``gym.make`` keyword argument, so
``dataset.recover_environment()`` rebuilds this exact env; the metadata under
``unified_manip`` (:data:`~.store.KEY`) adds the policy and its source, the package
versions, the success rate, the episodes dropped by ``only_successful``, and the
domain randomisation the env applied (``randomization``: its terms and the preset terms
the task left out). Its drawn values are each episode's ``infos/randomization`` (the
reset's row); the reset seeds redraw them, so ``replay`` stays exact.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any, Callable

from unified_manip.datasets import store
from unified_manip.datasets.episodes import Episode, Policy, play
from unified_manip.datasets.errors import DatasetError

#: With ``only_successful``, give up after this many episodes per one asked for.
MAX_TRIES_PER_EPISODE = 10


@dataclass(frozen=True)
class CollectResult:
    """What ``collect`` wrote: episodes kept, episodes played, their success rate, and
    the failed episodes left out."""

    out: str
    episodes: int
    played: int
    success_rate: float
    dropped: int

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


def collect(
    env_id: str,
    env_kwargs: dict[str, Any],
    make_policy: Callable[[Any], Policy],
    policy: str,
    source: str,
    episodes: int,
    out: Path,
    seed: int = 0,
    only_successful: bool = False,
    overwrite: bool = False,
    progress: bool = True,
) -> CollectResult:
    """Record ``episodes`` episodes of ``make_policy(env)`` in ``gym.make(env_id, **env_kwargs)``
    and publish them as the dataset ``out``.

    Args:
        env_id: A registered ``UnifiedManip`` ID.
        env_kwargs: Every ``gym.make`` keyword argument (action mode, reward type,
            observation design, ...), JSON-serialisable.
        make_policy: ``env -> policy``; a policy with a ``seed`` method is seeded with
            each episode's reset seed.
        policy: The policy's name (``"scripted"``, ``"random"``, ``"run"``).
        source: Where it came from (the task's scripted policy, a model path).
        episodes: Episodes in the dataset.
        out: The dataset directory, ``ROOT/NAME-vN``.
        seed: Episode ``k`` (counting every one played) is reset with ``seed + k``.
        only_successful: Keep only successful episodes, playing on until ``episodes`` of
            them (at most ``MAX_TRIES_PER_EPISODE`` times as many in all).
        overwrite: Replace a dataset at ``out``.
        progress: Show a progress bar (on stderr).
    """
    import gymnasium as gym
    from tqdm import tqdm

    from unified_manip.envs.randomization.randomizer import randomization_info

    if episodes <= 0:
        raise DatasetError(f"--episodes must be a positive number of episodes; got {episodes}")
    out = store.check_out(Path(out), overwrite)
    env = gym.make(env_id, **env_kwargs)
    try:
        act = make_policy(env)
        kept: list[Episode] = []
        played = successes = 0
        limit = episodes * MAX_TRIES_PER_EPISODE if only_successful else episodes
        with tqdm(total=episodes, desc=f"collect {env_id}", unit="episode", disable=not progress) as bar:
            while len(kept) < episodes:
                if played == limit:
                    raise DatasetError(
                        f"the {policy} policy succeeded in {successes} of {played} episodes of {env_id}; "
                        f"{episodes} successful ones cannot be collected"
                    )
                if hasattr(act, "seed"):
                    act.seed(seed + played)
                episode = play(env, act, seed + played)
                played += 1
                successes += episode.success
                if episode.success or not only_successful:
                    kept.append(episode)
                    bar.update()
        meta = {
            "env_id": env_id,
            "env_kwargs": dict(env_kwargs),
            "policy": policy,
            "source": source,
            "seed": seed,
            "episodes_played": played,
            "success_rate": successes / played,
            "dropped_episodes": played - len(kept),
            "only_successful": only_successful,
            "randomization": randomization_info(env.unwrapped.randomizer),
        }
        description = f"{len(kept)} episodes of the {policy} policy ({source}) in {env_id} {env_kwargs}"
        store.publish(out, kept, env, meta, description)
    finally:
        env.close()
    return CollectResult(str(out), len(kept), played, successes / played, played - len(kept))
