"""Our envs against the upstream envs they wrap, stepped and trained side by side (the
upstream tables of ``python -m benchmarks.speed``)."""

from __future__ import annotations

import statistics
import time
from dataclasses import asdict, dataclass

import gymnasium as gym
import numpy as np

from unified_manip.envs.registry import TASKS


@dataclass(frozen=True)
class UpstreamResult:
    task_id: str
    upstream: str
    ours_steps_per_s: float
    upstream_steps_per_s: float
    ours_resets_per_s: float = float("nan")
    upstream_resets_per_s: float = float("nan")

    @property
    def ratio(self) -> float:
        return self.ours_steps_per_s / self.upstream_steps_per_s

    def as_dict(self) -> dict:
        return {**asdict(self), "ratio": self.ratio}


def _interleaved(ours, theirs, actions, horizon: int) -> tuple[float, float]:
    """Steps per second of ``ours`` and ``theirs`` over the same ``actions``, stepped in
    turn (which one goes first alternates), so both see the same machine load. Resets
    (every ``horizon`` steps) are not timed."""
    clock = time.perf_counter
    spent = [0.0, 0.0]
    envs = (ours, theirs)
    for i, a in enumerate(actions):
        for k in (0, 1) if i % 2 == 0 else (1, 0):
            start = clock()
            envs[k].step(a)
            spent[k] += clock() - start
        if (i + 1) % horizon == 0:
            ours.reset()
            theirs.reset()
    return len(actions) / spent[0], len(actions) / spent[1]


def compare_upstream(
    task_id: str, steps: int = 2000, rounds: int = 5, seed: int = 0, resets: int = 10
) -> UpstreamResult:
    """``native`` mode against the env it wraps (``TaskSpec.upstream_id``) on the same
    actions, one step of each in turn; the figure is the median of the per-round ratios
    (``rounds`` rounds of ``steps / rounds`` steps). Resets are timed the same way,
    ``resets`` of each in turn, each env with its default reset."""
    spec = TASKS[task_id]
    ours = gym.make(task_id, action_mode="native", reward_type="sparse", disable_env_checker=True)
    theirs = spec.build_upstream()
    ours.reset(seed=seed)
    theirs.reset()
    rng = np.random.default_rng(seed)
    per_round = max(steps // rounds, 1)
    horizon = spec.max_episode_steps
    warm = rng.uniform(-1, 1, size=(50,) + ours.action_space.shape).astype(np.float32)
    _interleaved(ours, theirs, warm, horizon)
    ours.reset(seed=seed)
    theirs.reset()
    ours_rates, ratios = [], []
    for _ in range(rounds):
        actions = rng.uniform(-1, 1, size=(per_round,) + ours.action_space.shape).astype(np.float32)
        a, b = _interleaved(ours, theirs, actions, horizon)
        ours_rates.append(a)
        ratios.append(a / b)
    clock = time.perf_counter
    reset_time = [0.0, 0.0]
    for _ in range(resets):
        for k, env in enumerate((ours, theirs)):
            start = clock()
            env.reset()
            reset_time[k] += clock() - start
    ours.close()
    theirs.close()
    mid = statistics.median(ratios)
    return UpstreamResult(
        task_id,
        spec.upstream_id,
        statistics.median(ours_rates),
        statistics.median(ours_rates) / mid,
        resets / reset_time[0] if resets else float("nan"),
        resets / reset_time[1] if resets else float("nan"),
    )


def train_speed(task_id: str, steps: int = 1500, rounds: int = 2, seed: int = 0) -> UpstreamResult:
    """SAC+HER training steps/s on ``task_id`` (native, sparse) against the same script
    on its upstream env (which must be a Gymnasium goal env, as Fetch's are),
    alternating, with the task's ``sac_her`` hyperparameters."""
    import torch
    from stable_baselines3 import SAC, HerReplayBuffer

    from unified_manip.training.hyperparams import resolve_run

    spec = TASKS[task_id]
    if not spec.upstream_id:
        raise ValueError(f"{task_id} wraps no Gymnasium env (TaskSpec.upstream_id is None)")
    params = resolve_run("sac_her", task_id).algo_kwargs
    params["learning_starts"] = min(params.get("learning_starts", 100), steps // 3)
    torch.set_num_threads(1)

    def rate(make) -> float:
        model = SAC(env=make(), replay_buffer_class=HerReplayBuffer, seed=seed, device="cpu", **params)
        model.learn(total_timesteps=params["learning_starts"] + 100)  # warm-up: buffers, first updates
        start = time.perf_counter()
        model.learn(total_timesteps=steps, reset_num_timesteps=False)
        return steps / (time.perf_counter() - start)

    ours_rates, theirs_rates = [], []
    for _ in range(rounds):
        ours_rates.append(rate(lambda: gym.make(task_id, action_mode="native", reward_type="sparse")))
        theirs_rates.append(rate(spec.build_upstream))
    ratios = [a / b for a, b in zip(ours_rates, theirs_rates)]
    mid = statistics.median(ratios)
    return UpstreamResult(task_id, spec.upstream_id, statistics.median(ours_rates), statistics.median(ours_rates) / mid)
