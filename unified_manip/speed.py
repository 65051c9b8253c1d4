"""``unified-manip speed``: env steps per second against the raw physics limit.

For every ID x action mode, the env's ``step`` rate is measured side by side with the
backend's :meth:`~unified_manip.backend.Backend.physics_step` (the same model, the
same substeps, nothing else), in alternating blocks so that both see the same machine
load. Report ratios, not absolute rates: these machines are shared and noisy.
"""

from __future__ import annotations

import statistics
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

    def as_dict(self) -> dict:
        return {**asdict(self), "ratio_to_raw": self.ratio_to_raw}


def _time_block(fn, n: int) -> float:
    start = time.perf_counter()
    for _ in range(n):
        fn()
    return n / (time.perf_counter() - start)


def measure(task_id: str, action_mode: str, steps: int = 2000, blocks: int = 5, seed: int = 0) -> SpeedResult:
    """Median rates over ``blocks`` alternating blocks of ``steps // blocks`` steps."""
    env = gym.make(task_id, action_mode=action_mode, disable_env_checker=True)
    env.reset(seed=seed)
    backend = env.unwrapped._backend
    rng = np.random.default_rng(seed)
    actions = rng.uniform(-1, 1, size=(steps,) + env.action_space.shape).astype(np.float32)
    it = iter(actions)

    def env_step():
        _, _, terminated, truncated, _ = env.step(next(it))
        if terminated or truncated:
            env.reset()

    per_block = max(steps // blocks, 1)
    for _ in range(20):  # warm-up (lazy allocations, caches)
        env.step(actions[0])
        backend.physics_step()
    env_rates, raw_rates = [], []
    for _ in range(blocks):
        it = iter(rng.uniform(-1, 1, size=(per_block,) + env.action_space.shape).astype(np.float32))
        env_rates.append(_time_block(env_step, per_block))
        raw_rates.append(_time_block(backend.physics_step, per_block))
    env.close()
    return SpeedResult(task_id, action_mode, statistics.median(env_rates), statistics.median(raw_rates))


def run(task_ids=None, modes=None, steps: int = 2000, progress: bool = True) -> list[SpeedResult]:
    """Measure every requested ID x supported mode."""
    from tqdm import tqdm

    jobs = [
        (tid, mode)
        for tid in (task_ids or list(TASKS))
        for mode in TASKS[tid].action_modes
        if modes is None or mode in modes
    ]
    results = []
    for tid, mode in tqdm(jobs, desc="speed", disable=not progress, unit="env"):
        results.append(measure(tid, mode, steps=steps))
    return results
