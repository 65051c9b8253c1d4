"""``unified-manip speed``: env steps per second against the raw physics limit.

For every ID x action mode, random actions are played through ``gym.make``'s env
(wrappers included, env checker off) and two clocks run over the same steps: the wall
time of the whole ``step`` calls, and the time spent inside the backend's
:meth:`~unified_manip.backend.Backend.physics_step` (the substeps of ``mj_step``,
nothing else). Their ratio is the fraction of the raw physics limit the env reaches on
exactly the states it visited. Compare ratios, not absolute rates: these machines are
shared and noisy.
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass

import gymnasium as gym
import numpy as np

from .registry import TASKS


@dataclass(frozen=True)
class SpeedResult:
    task_id: str
    action_mode: str
    env_steps_per_s: float
    raw_steps_per_s: float

    @property
    def ratio_to_raw(self) -> float:
        return self.env_steps_per_s / self.raw_steps_per_s

    @property
    def overhead_us(self) -> float:
        """Time per step spent outside the physics (control, observation, reward), µs."""
        return 1e6 * (1.0 / self.env_steps_per_s - 1.0 / self.raw_steps_per_s)

    def as_dict(self) -> dict:
        return {**asdict(self), "ratio_to_raw": self.ratio_to_raw, "overhead_us": self.overhead_us}


def measure(task_id: str, action_mode: str, steps: int = 2000, seed: int = 0) -> SpeedResult:
    """Step rate of the env and of its physics alone, over the same ``steps`` steps."""
    env = gym.make(task_id, action_mode=action_mode, disable_env_checker=True)
    env.reset(seed=seed)
    backend = env.unwrapped._backend
    rng = np.random.default_rng(seed)
    actions = rng.uniform(-1, 1, size=(steps + 50,) + env.action_space.shape).astype(np.float32)

    physics = backend.physics_step
    clock = time.perf_counter
    spent = [0.0]

    def timed_physics() -> None:
        start = clock()
        physics()
        spent[0] += clock() - start

    backend.physics_step = timed_physics  # instance attribute shadows the method
    try:
        for a in actions[:50]:  # warm-up: lazy allocations, caches
            env.step(a)
        env.reset(seed=seed)
        spent[0] = 0.0
        resets = 0.0
        start = clock()
        for a in actions[50:]:
            _, _, terminated, truncated, _ = env.step(a)
            if terminated or truncated:
                t = clock()
                env.reset()
                resets += clock() - t
        total = clock() - start - resets
    finally:
        del backend.physics_step
        env.close()
    return SpeedResult(task_id, action_mode, steps / total, steps / spent[0])


def run(task_ids=None, modes=None, steps: int = 2000, repeats: int = 3, progress: bool = True) -> list[SpeedResult]:
    """Measure every requested ID x supported mode; each figure is the median of
    ``repeats`` measurements, taken in rounds so that load spikes spread over modes."""
    import statistics
    from tqdm import tqdm

    jobs = [
        (tid, mode)
        for tid in (task_ids or list(TASKS))
        for mode in TASKS[tid].action_modes
        if modes is None or mode in modes
    ]
    samples: dict[tuple[str, str], list[SpeedResult]] = {job: [] for job in jobs}
    with tqdm(total=len(jobs) * repeats, desc="speed", disable=not progress, unit="run") as bar:
        for _ in range(repeats):
            for tid, mode in jobs:
                samples[(tid, mode)].append(measure(tid, mode, steps=steps))
                bar.update()
    return [
        SpeedResult(
            tid,
            mode,
            statistics.median(r.env_steps_per_s for r in rs),
            statistics.median(r.raw_steps_per_s for r in rs),
        )
        for (tid, mode), rs in samples.items()
    ]
