"""``unified-manip speed``: env steps per second per ID x action mode, through the public API.

Every ID x action mode is made with ``gym.make`` (wrappers included, env checker off) and
plays seeded random actions in [-1, 1]; a figure is the median over rounds of the env steps
per second, the resets that end episodes not timed. The rounds go over every ID x mode in
turn, so that a change of machine load reaches them alike: compare rates within one run.
(The physics alone, the upstream envs and training are timed by ``python -m
benchmarks.speed`` in a checkout.)
"""

from __future__ import annotations

import statistics
import time
from dataclasses import asdict, dataclass

import gymnasium as gym
import numpy as np

from unified_manip.envs.registry import TASKS

#: Untimed steps before a measurement: lazy allocations, caches.
WARMUP = 50


@dataclass(frozen=True)
class StepRate:
    """One ID x action mode's env steps per second."""

    task_id: str
    action_mode: str
    env_steps_per_s: float

    def as_dict(self) -> dict:
        return asdict(self)


def step_rate(env: gym.Env, steps: int, seed: int = 0) -> float:
    """Env steps per second of ``env`` over ``steps`` seeded random actions from a
    ``reset(seed=seed)``; the resets of episodes that end on the way are not timed."""
    if steps < 1:
        raise ValueError(f"steps must be a positive integer, got {steps}")
    rng = np.random.default_rng(seed)
    actions = rng.uniform(-1, 1, size=(steps,) + env.action_space.shape).astype(np.float32)
    clock = time.perf_counter
    env.reset(seed=seed)
    resets = 0.0
    start = clock()
    for a in actions:
        _, _, terminated, truncated, _ = env.step(a)
        if terminated or truncated:
            t = clock()
            env.reset()
            resets += clock() - t
    return steps / (clock() - start - resets)


def measure(task_id: str, action_mode: str, steps: int = 2000, seed: int = 0) -> float:
    """Env steps per second of ``task_id`` under ``action_mode`` (:func:`step_rate`, after
    :data:`WARMUP` untimed steps)."""
    env = gym.make(task_id, action_mode=action_mode, disable_env_checker=True)
    try:
        step_rate(env, WARMUP, seed)
        return step_rate(env, steps, seed)
    finally:
        env.close()


def rounds(task_ids=None, modes=None, steps: int = 2000, repeats: int = 3, progress: bool = True, measure=measure):
    """``measure(task_id, action_mode, steps=steps)`` of every requested ID x action mode it
    supports (all IDs, all modes by default), ``repeats`` times in rounds: the samples of
    each ``(task_id, action_mode)``, in order."""
    from tqdm import tqdm

    todo = [
        (tid, mode)
        for tid in (task_ids or list(TASKS))
        for mode in TASKS[tid].action_modes
        if modes is None or mode in modes
    ]
    samples: dict[tuple[str, str], list] = {job: [] for job in todo}
    with tqdm(total=len(todo) * repeats, desc="speed", disable=not progress, unit="run") as bar:
        for _ in range(repeats):
            for tid, mode in todo:
                samples[(tid, mode)].append(measure(tid, mode, steps=steps))
                bar.update()
    return samples


def run(task_ids=None, modes=None, steps: int = 2000, repeats: int = 3, progress: bool = True) -> list[StepRate]:
    """:func:`measure` every requested ID x action mode (:func:`rounds`); each figure is
    the median of its ``repeats``."""
    samples = rounds(task_ids, modes, steps, repeats, progress)
    return [StepRate(tid, mode, statistics.median(rates)) for (tid, mode), rates in samples.items()]
